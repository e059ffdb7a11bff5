#include "devices/arm/move_behaviour.hpp"

#include "devices/common/frame.hpp"
#include "ua/encoding/codec.hpp"
#include "ua/messages/data_access.hpp"

namespace skillcell::devices {
namespace {

std::variant<KDL::Frame, std::string> frameParameter(const skills::SkillParameters& p,
                                                     const char* name) {
    const auto frame = frameFromVariant(p.value(name));
    if (!frame) {
        return std::string(name) + " is not a valid 3DFrame (" +
               std::string(ua::statusName(frame.status())) + ")";
    }
    return *frame;
}

}  // namespace

std::variant<MoveRequest, std::string> MoveBehaviour::request(MoveKind kind,
                                                              const skills::SkillParameters& p) {
    MoveRequest r;
    r.kind = kind;
    auto tool = frameParameter(p, "ToolFrame");
    if (auto* why = std::get_if<std::string>(&tool)) return *why;
    r.toolFrame = std::get<KDL::Frame>(tool);
    // Range checks (EURange, NaN) happened at Start; absent means zero, the default.
    r.maxVelocity = p.get<double>("MaxVelocity").value_or(0);
    r.maxAcceleration = p.get<double>("MaxAcceleration").value_or(0);

    if (kind == MoveKind::JointLinear || kind == MoveKind::JointPtp) {
        // The planner checks the count against the arm's joints.
        const auto joints = p.doubles("TargetJointPosition");
        if (!joints) return std::string("TargetJointPosition must hold the joint positions");
        r.targetJoints.assign(joints->begin(), joints->end());
        return r;
    }
    auto target = frameParameter(p, "TargetPosition");
    if (auto* why = std::get_if<std::string>(&target)) return *why;
    r.target = std::get<KDL::Frame>(target);
    if (kind == MoveKind::CartesianForceLimitedLinear) {
        r.forceLimit = p.get<double>("ForceLimit").value_or(0);
    }

    const ua::Variant& bounds = p.value("AxisBounds");
    if (bounds.isArray() && !bounds.elements().empty()) {
        JointBounds b;
        for (std::size_t i = 0; i < bounds.elements().size(); ++i) {
            const auto* eo = std::get_if<ua::ExtensionObject>(&bounds.elements()[i]);
            ua::Range range;
            if (eo == nullptr || ua::fromExtensionObject(*eo, range).isBad() ||
                !(range.low <= range.high)) {
                return "AxisBounds[" + std::to_string(i) + "] is not a Range with low <= high";
            }
            b.lower.push_back(range.low);
            b.upper.push_back(range.high);
        }
        r.axisBounds = b;
    }
    return r;
}

void MoveBehaviour::start(const skills::SkillParameters& parameters, skills::SkillRun run) {
    const auto parsed = request(kind_, parameters);
    if (const auto* why = std::get_if<std::string>(&parsed)) {
        run.failed(*why);
        return;
    }
    const MoveRequest& r = std::get<MoveRequest>(parsed);
    if (arm_.busy()) {
        run.failed("the arm is executing another move");
        return;
    }
    auto planned = planner_.plan(arm_.joints(), r);
    if (const auto* why = std::get_if<std::string>(&planned)) {
        run.failed(*why);
        return;
    }
    if (onToolFrame_) onToolFrame_(r.toolFrame);
    *moving_ = arm_.execute(std::move(std::get<Trajectory>(planned)),
                            [moving = moving_, run](std::optional<std::string> fault) {
                                *moving = false;
                                if (fault) {
                                    run.failed(*fault);
                                } else {
                                    run.finished();
                                }
                            });
    if (!*moving_) run.failed("the arm is executing another move");
}

void MoveBehaviour::suspend() {
    if (*moving_) arm_.pause();
}

void MoveBehaviour::resume() {
    if (*moving_) arm_.resume();
}

void MoveBehaviour::halt() {
    if (*moving_) arm_.stop();
    *moving_ = false;
}

}  // namespace skillcell::devices
