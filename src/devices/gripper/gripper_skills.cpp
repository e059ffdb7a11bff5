#include "devices/gripper/gripper_skills.hpp"

#include "devices/common/frame.hpp"

namespace skillcell::devices {
namespace {

enum class Operation : std::uint8_t { Grasp, Release, Move };

class GripperBehaviour final : public skills::SkillBehaviour {
public:
    /// `parallel` is the same gripper when it is a ParallelGripper (MoveGripper needs it).
    GripperBehaviour(Operation operation, Gripper& gripper, ParallelGripper* parallel)
        : operation_(operation), gripper_(gripper), parallel_(parallel) {}

    void start(const skills::SkillParameters& parameters, skills::SkillRun run) override {
        ParallelGripper::Done done = [run](std::optional<std::string> failure) {
            if (failure) {
                run.failed(*failure);
            } else {
                run.finished();
            }
        };
        switch (operation_) {
            case Operation::Grasp:
                gripper_.grasp(std::move(done));
                break;
            case Operation::Release:
                gripper_.release(std::move(done));
                break;
            case Operation::Move:
                // Range-checked at Start against the parameters' EURange.
                parallel_->moveTo(parameters.get<double>("Width").value_or(0),
                                  parameters.get<double>("Force").value_or(0), std::move(done));
                break;
        }
    }
    void suspend() override { gripper_.suspend(); }
    void resume() override { gripper_.resume(); }
    void halt() override { gripper_.halt(); }

private:
    Operation operation_;
    Gripper& gripper_;
    ParallelGripper* parallel_;
};

ua::StatusCode addSkills(skills::SkillServer& skills, Gripper& gripper, ParallelGripper* parallel,
                         const KDL::Frame& offset, GripPointType type, std::string* error);

}  // namespace

ua::StatusCode addGripperSkills(skills::SkillServer& skills, Gripper& gripper,
                                const KDL::Frame& offset, GripPointType type, std::string* error) {
    return addSkills(skills, gripper, nullptr, offset, type, error);
}

ua::StatusCode addGripperSkills(skills::SkillServer& skills, ParallelGripper& gripper,
                                const KDL::Frame& offset, GripPointType type, std::string* error) {
    return addSkills(skills, gripper, &gripper, offset, type, error);
}

namespace {

ua::StatusCode addSkills(skills::SkillServer& skills, Gripper& gripper, ParallelGripper* parallel,
                         const KDL::Frame& offset, GripPointType type, std::string* error) {
    struct Spec {
        const char* type;
        const char* name;
        Operation operation;
    };
    const Spec specs[] = {{"GraspGripperSkillType", "Grasp", Operation::Grasp},
                          {"ReleaseGripperSkillType", "Release", Operation::Release},
                          {"MoveGripperSkillType", "MoveGripper", Operation::Move}};
    ua::AddressSpace& as = skills.server().addressSpace();
    const GripperRating rating = gripper.rating();
    for (const Spec& spec : specs) {
        if (spec.operation == Operation::Move && parallel == nullptr) continue;
        const auto skillType = skills.findSkillType(spec.type);
        if (!skillType) {
            if (error != nullptr) *error = std::string("no skill type ") + spec.type;
            return ua::status::BadTypeDefinitionInvalid;
        }
        auto skill =
            skills.add(*skillType, spec.name,
                       std::make_unique<GripperBehaviour>(spec.operation, gripper, parallel));
        if (!skill) {
            if (error != nullptr) *error = std::string("cannot add ") + spec.name;
            return skill.status();
        }
        for (const auto& p : (*skill)->parameters()) {
            if (p.name == "GripPointOffset") (void)as.setValue(p.nodeId, frameToVariant(offset));
            if (p.name == "GripPointType") {
                (void)as.setValue(p.nodeId, ua::Variant(static_cast<std::int32_t>(type)));
            }
            if (p.name == "MaxPayload") (void)as.setValue(p.nodeId, ua::Variant(rating.maxPayload));
            if (p.name == "MaxGripWidth") {
                (void)as.setValue(p.nodeId, ua::Variant(rating.maxGripWidth));
            }
            if (p.name == "Width") (void)as.setValue(p.nodeId, ua::Variant(0.0));
            if (p.name == "Force") (void)as.setValue(p.nodeId, ua::Variant(0.0));
        }
    }
    return ua::status::Good;
}

}  // namespace
}  // namespace skillcell::devices
