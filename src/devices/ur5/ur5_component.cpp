#include "devices/ur5/ur5_component.hpp"

#include "devices/common/frame.hpp"
#include "devices/common/motion_device_system.hpp"
#include "devices/ur5/move_behaviour.hpp"

namespace skillcell::devices {

Ur5Component::Ur5Component(Token, ua::Server& server, Ur5ComponentOptions options)
    : server_(server), options_(std::move(options)), planner_(kinematics_, options_.defaults) {}

Ur5Component::~Ur5Component() = default;

ua::Result<std::unique_ptr<Ur5Component>> Ur5Component::create(ua::Server& server,
                                                               Ur5ComponentOptions options,
                                                               std::string* error) {
    auto component = std::make_unique<Ur5Component>(Token{}, server, std::move(options));
    if (const auto s = component->build(error); s.isBad()) return s;
    return component;
}

ua::StatusCode Ur5Component::build(std::string* error) {
    ua::AddressSpace& as = server_.addressSpace();
    robot_ = ua::NodeId(1, ua::String("UR5"));
    auto id = [](const char* name) {
        return ua::NodeId(1, ua::String(std::string("UR5/") + name));
    };
    if (auto r = as.addObject(ua::NodeId(ua::ns0::ObjectsFolder), robot_, "UR5"); !r) {
        return r.status();
    }
    const ua::NodeId frame(ua::ns0::ThreeDFrame);
    const Joints q0 = options_.arm.initial;
    struct Var {
        const char* name;
        ua::NodeId type;
        ua::Variant value;
        std::int32_t rank;
    };
    const Var vars[] = {
        {"JointPositions", ua::NodeId(ua::ns0::Double),
         ua::Variant::array(std::vector<double>(q0.begin(), q0.end())),
         ua::value_rank::kOneDimension},
        {"FlangePose", frame, frameToVariant(kinematics_.forward(q0)), ua::value_rank::kScalar},
        {"TcpPose", frame, frameToVariant(kinematics_.forward(q0)), ua::value_rank::kScalar},
        {"ToolFrame", frame, frameToVariant(KDL::Frame::Identity()), ua::value_rank::kScalar},
    };
    for (const Var& v : vars) {
        auto r = as.addVariable(robot_, id(v.name), v.name, v.type, v.value,
                                ua::access_level::kCurrentRead, v.rank);
        if (!r) return r.status();
    }

    arm_ = std::make_unique<SimulatedUr5>(server_.executor(), options_.arm,
                                          [this](const Joints& q) { publish(q); });
    skills_ = skills::SkillServer::create(server_, server_.executor(), error);
    if (!skills_) return ua::status::BadConfigurationError;
    // The same arm as the Robotics model shows it, for clients that know that model (the
    // skill server has loaded the companion models).
    MotionDeviceDescription description;
    description.name = "UR5";
    description.manufacturer = "Universal Robots";
    description.model = "UR5";
    description.productCode = "UR5";
    description.axes = {"Base", "Shoulder", "Elbow", "Wrist1", "Wrist2", "Wrist3"};
    auto motionDevice = MotionDeviceSystem::create(as, description);
    if (!motionDevice) {
        if (error != nullptr) *error = "cannot add the UR5 to the Robotics model's DeviceSet";
        return motionDevice.status();
    }
    motionDevice_ = std::move(*motionDevice);

    struct SkillSpec {
        const char* type;
        const char* name;
        MoveKind kind;
    };
    const SkillSpec specs[] = {
        {"CartesianLinearMoveSkillType", "CartesianLinearMove", MoveKind::CartesianLinear},
        {"CartesianPtpMoveSkillType", "CartesianPtpMove", MoveKind::CartesianPtp},
        {"JointLinearMoveSkillType", "JointLinearMove", MoveKind::JointLinear},
        {"JointPtpMoveSkillType", "JointPtpMove", MoveKind::JointPtp},
    };
    for (const SkillSpec& spec : specs) {
        const auto type = skills_->findSkillType(spec.type);
        if (!type) {
            if (error != nullptr) *error = std::string("no skill type ") + spec.type;
            return ua::status::BadTypeDefinitionInvalid;
        }
        auto behaviour = std::make_unique<MoveBehaviour>(
            spec.kind, *arm_, planner_, [this](const KDL::Frame& tool) {
                toolFrame_ = tool;
                (void)server_.addressSpace().setValue(ua::NodeId(1, ua::String("UR5/ToolFrame")),
                                                      frameToVariant(tool));
            });
        auto skill = skills_->add(*type, spec.name, std::move(behaviour));
        if (!skill) {
            if (error != nullptr) *error = std::string("cannot add ") + spec.name;
            return skill.status();
        }
        // Values a client need not write: no tool offset, the default limits, no extra
        // axis bounds. Targets have none, so a Start without one is refused.
        for (const auto& p : (*skill)->parameters()) {
            ua::Variant value;
            if (p.name == "ToolFrame") value = frameToVariant(KDL::Frame::Identity());
            if (p.name == "MaxVelocity" || p.name == "MaxAcceleration") value = ua::Variant(0.0);
            if (p.name == "AxisBounds") {
                value = ua::Variant::array(ua::BuiltinType::ExtensionObject, {});
            }
            if (!value.isEmpty()) (void)as.setValue(p.nodeId, std::move(value));
        }
    }
    publish(q0);
    return ua::status::Good;
}

void Ur5Component::publish(const Joints& q) {
    ua::AddressSpace& as = server_.addressSpace();
    const KDL::Frame flange = kinematics_.forward(q);
    (void)as.setValue(ua::NodeId(1, ua::String("UR5/JointPositions")),
                      ua::Variant::array(std::vector<double>(q.begin(), q.end())));
    (void)as.setValue(ua::NodeId(1, ua::String("UR5/FlangePose")), frameToVariant(flange));
    if (motionDevice_) motionDevice_->update(as, std::span<const double>(q.data(), q.size()));
    (void)as.setValue(ua::NodeId(1, ua::String("UR5/TcpPose")),
                      frameToVariant(flange * toolFrame_));
    if (options_.onFlange) options_.onFlange(flange);
}

}  // namespace skillcell::devices
