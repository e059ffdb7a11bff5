#include "devices/arm/arm_component.hpp"

#include "devices/arm/move_behaviour.hpp"
#include "devices/common/frame.hpp"
#include "devices/common/motion_device_system.hpp"
#include "ua/nodeset/companion_models.hpp"

namespace skillcell::devices {

namespace {
// Its skills are of the RoboticSkills model's types; the arm is also shown as the Robotics
// model's MotionDeviceSystem.
constexpr std::array<std::string_view, 2> kArmSkillModels{ua::companion::kRoboticSkillsUri,
                                                          ua::companion::kRoboticsUri};
}  // namespace

std::span<const std::string_view> ArmComponent::skillModels() {
    return kArmSkillModels;
}

ArmComponent::ArmComponent(Token, ua::Server& server, ArmComponentOptions options)
    : server_(server),
      options_(std::move(options)),
      kinematics_(options_.model, options_.base),
      planner_(kinematics_, options_.model.defaults) {}

ArmComponent::~ArmComponent() = default;

ua::Result<std::unique_ptr<ArmComponent>> ArmComponent::create(ua::Server& server,
                                                               ArmComponentOptions options,
                                                               std::string* error) {
    auto component = std::make_unique<ArmComponent>(Token{}, server, std::move(options));
    if (const auto s = component->build(error); s.isBad()) return s;
    return component;
}

ua::StatusCode ArmComponent::build(std::string* error) {
    ua::AddressSpace& as = server_.addressSpace();
    const ArmModel& model = options_.model;
    robot_ = ua::NodeId(1, ua::String(model.name));
    if (auto r = as.addObject(ua::NodeId(ua::ns0::ObjectsFolder), robot_, model.name); !r) {
        return r.status();
    }
    // The models first (most of a start): a device that asks the world where it stands has
    // the answer meanwhile.
    skills_ = skills::SkillServer::create(server_, server_.executor(), kArmSkillModels, error);
    if (!skills_) return ua::status::BadConfigurationError;
    // The same arm as the Robotics model shows it, for clients that know that model (the
    // skill server has loaded the companion models).
    MotionDeviceDescription description;
    description.name = model.name;
    description.manufacturer = model.manufacturer;
    description.model = model.model;
    description.productCode = model.productCode;
    description.axes = model.axes;
    auto motionDevice = MotionDeviceSystem::create(as, description);
    if (!motionDevice) {
        if (error != nullptr) {
            *error = "cannot add the " + model.name + " to the Robotics model's DeviceSet";
        }
        return motionDevice.status();
    }
    motionDevice_ = std::move(*motionDevice);

    if (options_.startingJoints) {
        std::string why;
        auto q = options_.startingJoints(&why);
        if (!q) {
            if (error != nullptr) *error = "where the arm stands: " + why;
            return q.status();
        }
        if (!q->empty()) options_.arm.initial = std::move(*q);
    }
    if (options_.arm.initial.empty()) options_.arm.initial = model.home;
    if (options_.arm.initial.size() != model.joints()) {
        if (error != nullptr) {
            *error = "the " + model.name + " has " + std::to_string(model.joints()) +
                     " joints; the initial position gives " +
                     std::to_string(options_.arm.initial.size());
        }
        return ua::status::BadConfigurationError;
    }
    auto id = [&model](const char* name) {
        return ua::NodeId(1, ua::String(model.name + "/" + name));
    };
    const ua::NodeId frame(ua::ns0::ThreeDFrame);
    const Joints q0 = options_.arm.initial;
    struct Var {
        const char* name;
        ua::NodeId type;
        ua::Variant value;
        std::int32_t rank;
    };
    std::vector<Var> vars = {
        {"JointPositions", ua::NodeId(ua::ns0::Double),
         ua::Variant::array(std::vector<double>(q0.begin(), q0.end())),
         ua::value_rank::kOneDimension},
        {"FlangePose", frame, frameToVariant(kinematics_.forward(q0)), ua::value_rank::kScalar},
        {"TcpPose", frame, frameToVariant(kinematics_.forward(q0)), ua::value_rank::kScalar},
        {"ToolFrame", frame, frameToVariant(KDL::Frame::Identity()), ua::value_rank::kScalar},
    };
    if (sensesForce()) {
        vars.push_back({"ContactForce", ua::NodeId(ua::ns0::Double), ua::Variant(0.0),
                        ua::value_rank::kScalar});
    }
    for (const Var& v : vars) {
        auto r = as.addVariable(robot_, id(v.name), v.name, v.type, v.value,
                                ua::access_level::kCurrentRead, v.rank);
        if (!r) return r.status();
    }

    arm_ = std::make_unique<SimulatedArm>(server_.executor(), options_.arm,
                                          [this](const Joints& q) { publish(q); });

    struct SkillSpec {
        const char* type;
        const char* name;
        MoveKind kind;
    };
    std::vector<SkillSpec> specs = {
        {"CartesianLinearMoveSkillType", "CartesianLinearMove", MoveKind::CartesianLinear},
        {"CartesianPtpMoveSkillType", "CartesianPtpMove", MoveKind::CartesianPtp},
        {"JointLinearMoveSkillType", "JointLinearMove", MoveKind::JointLinear},
        {"JointPtpMoveSkillType", "JointPtpMove", MoveKind::JointPtp},
    };
    // An arm that measures force, fed what it measures, also stops a move on contact.
    if (sensesForce()) {
        specs.push_back({"CartesianForceLimitedLinearMoveSkillType",
                         "CartesianForceLimitedLinearMove", MoveKind::CartesianForceLimitedLinear});
    }
    for (const SkillSpec& spec : specs) {
        const auto type = skills_->findSkillType(spec.type);
        if (!type) {
            if (error != nullptr) *error = std::string("no skill type ") + spec.type;
            return ua::status::BadTypeDefinitionInvalid;
        }
        auto behaviour = std::make_unique<MoveBehaviour>(
            spec.kind, *arm_, planner_, [this](const KDL::Frame& tool) {
                toolFrame_ = tool;
                (void)server_.addressSpace().setValue(
                    ua::NodeId(1, ua::String(options_.model.name + "/ToolFrame")),
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
            if (p.name == "MaxVelocity" || p.name == "MaxAcceleration" || p.name == "ForceLimit") {
                value = ua::Variant(0.0);
            }
            if (p.name == "AxisBounds") {
                value = ua::Variant::array(ua::BuiltinType::ExtensionObject, {});
            }
            // Where it reaches, for an MES to choose a robot that reaches its targets before
            // any motion: the shoulder, where the base stands in the cell.
            if (p.name == "Reach") value = ua::Variant(options_.model.reach);
            if (p.name == "ReachCentre") {
                value = frameToVariant(KDL::Frame(kinematics_.shoulder()));
            }
            if (!value.isEmpty()) (void)as.setValue(p.nodeId, std::move(value));
        }
    }
    publish(q0);
    return ua::status::Good;
}

void ArmComponent::publish(const Joints& q) {
    ua::AddressSpace& as = server_.addressSpace();
    const KDL::Frame flange = kinematics_.forward(q);
    const std::string& name = options_.model.name;
    (void)as.setValue(ua::NodeId(1, ua::String(name + "/JointPositions")),
                      ua::Variant::array(std::vector<double>(q.begin(), q.end())));
    (void)as.setValue(ua::NodeId(1, ua::String(name + "/FlangePose")), frameToVariant(flange));
    if (motionDevice_) motionDevice_->update(as, std::span<const double>(q.data(), q.size()));
    if (sensesForce()) {
        (void)as.setValue(ua::NodeId(1, ua::String(name + "/ContactForce")),
                          ua::Variant(arm_ ? arm_->contactForce() : 0.0));
    }
    (void)as.setValue(ua::NodeId(1, ua::String(name + "/TcpPose")),
                      frameToVariant(flange * toolFrame_));
    if (options_.onFlange) options_.onFlange(flange);
}

}  // namespace skillcell::devices
