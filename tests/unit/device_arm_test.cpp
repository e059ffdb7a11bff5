// The simulated arms. The UR5: kinematics (IK against FK on random reachable poses,
// unreachable poses refused), trapezoidal profiles within their limits, planned motions, and
// the four move skills through a real server and SkillClient: success, an unreachable target
// (Halted with the reason), Suspend/Resume and Halt mid-motion on a test-driven clock. The
// KUKA LBR iiwa 7 R800 (7 axes) on the same stack: its kinematics from KUKA's dimensions,
// IK against FK within its axis limits, a linear move with its elbow kept, and its seven
// axes in the Robotics model.
#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <condition_variable>
#include <mutex>
#include <optional>
#include <random>
#include <thread>

#include "client_thread.hpp"
#include "devices/arm/arm_component.hpp"
#include "devices/arm/arm_kinematics.hpp"
#include "devices/arm/motion_planner.hpp"
#include "devices/arm/trapezoidal_profile.hpp"
#include "devices/common/frame.hpp"
#include "running_server.hpp"
#include "ua/encoding/codec.hpp"
#include "ua/messages/data_access.hpp"
#include "ua/nodeset/companion_models.hpp"

namespace skillcell::devices::device_arm_test {
namespace {

using namespace std::chrono_literals;
using Kind = skills::SkillOutcome::Kind;
using skills::SkillMethod;
using skills::SkillState;

KDL::Frame at(double x, double y, double z, double a = 0, double b = 0, double c = 0) {
    return toFrame(Pose6{x, y, z, a, b, c});
}

double maxDiff(const Joints& a, const Joints& b) {
    double d = 0;
    for (std::size_t i = 0; i < a.size() && i < b.size(); ++i) {
        d = std::max(d, std::abs(a[i] - b[i]));
    }
    return d;
}

TEST(DeviceArmKinematics, ForwardKinematicsMatchesThePublishedZeroPose) {
    ArmKinematics k(ArmModel::ur5());
    // All joints at zero: the arm stretched along -x (UR's own documentation).
    const KDL::Frame f = k.forward({0, 0, 0, 0, 0, 0});
    EXPECT_NEAR(f.p.x(), -0.81725, 1e-9);
    EXPECT_NEAR(f.p.y(), -0.19145, 1e-9);
    EXPECT_NEAR(f.p.z(), -0.005491, 1e-9);
}

// A robot whose base stands elsewhere in the cell (a cell with two robots): its poses are in
// the cell's frame, the same joints put its flange where the base carries it, and its reach is
// measured from its own shoulder.
TEST(DeviceArmKinematics, ABaseElsewhereInTheCellCarriesItsPosesAndItsReach) {
    const KDL::Frame base(KDL::Rotation::RotZ(M_PI / 2), KDL::Vector(0.2, -0.75, 0.1));
    ArmKinematics atOrigin(ArmModel::ur5());
    ArmKinematics placed(ArmModel::ur5(), base);
    const Joints q{0.3, -1.2, 1.4, -1.8, -1.57, 0.2};
    EXPECT_TRUE(near(placed.forward(q), base * atOrigin.forward(q), 1e-12, 1e-12));
    EXPECT_NEAR((placed.shoulder() - base * ArmModel::ur5().shoulder).Norm(), 0, 1e-12);
    // The pose it reaches with those joints, in the cell's frame, gives them back.
    const KDL::Frame target = placed.forward(q);
    std::string why;
    const auto solution = placed.inverse(target, q, ArmModel::ur5().bounds, &why);
    ASSERT_TRUE(solution) << why;
    EXPECT_TRUE(near(placed.forward(*solution), target, 1e-6, 1e-6));
    // A pose near the cell's origin but beyond its reach from where it stands: refused, as
    // out of reach, while the arm at the origin reaches it.
    const KDL::Frame nearOrigin(KDL::Rotation::RPY(M_PI, 0, 0), KDL::Vector(0.3, 0.6, 0.3));
    EXPECT_TRUE(atOrigin.inverse(nearOrigin, {}, ArmModel::ur5().bounds));
    EXPECT_FALSE(placed.inverse(nearOrigin, {}, ArmModel::ur5().bounds, &why));
    EXPECT_NE(why.find("out of the"), std::string::npos) << why;
}

TEST(DeviceArmKinematics, InverseMatchesForwardOnRandomReachablePoses) {
    ArmKinematics k(ArmModel::ur5());
    std::mt19937 random(20261122);
    std::uniform_real_distribution<double> angle(-M_PI, M_PI);
    const JointBounds bounds = ArmModel::ur5().bounds;
    int solved = 0;
    for (int n = 0; n < 100; ++n) {
        Joints q(6), seed(6);
        for (std::size_t i = 0; i < q.size(); ++i) {
            q[i] = angle(random);
            seed[i] = angle(random);  // an unrelated present position
        }
        const KDL::Frame target = k.forward(q);
        std::string why;
        const auto solution = k.inverse(target, seed, bounds, &why);
        ASSERT_TRUE(solution) << "pose " << n << " " << describe(target) << ": " << why;
        EXPECT_TRUE(bounds.contains(*solution));
        EXPECT_TRUE(near(k.forward(*solution), target, 1e-6, 1e-6)) << n;
        ++solved;
    }
    EXPECT_EQ(solved, 100);
}

TEST(DeviceArmKinematics, SolutionsHonourTheBoundsAndPreferTheSeed) {
    ArmKinematics k(ArmModel::ur5());
    const Joints q{0.3, -1.2, 1.4, -1.8, -1.57, 0.4};
    const KDL::Frame target = k.forward(q);
    // From a seed near q, the solution is q itself (not another configuration).
    Joints seed = q;
    for (double& v : seed) v += 0.05;
    const auto near = k.inverse(target, seed, ArmModel::ur5().bounds);
    ASSERT_TRUE(near);
    EXPECT_LT(maxDiff(*near, q), 1e-6);

    // Bounds around q admit q; bounds that exclude this configuration's wrist do not.
    JointBounds tight = ArmModel::ur5().bounds;
    tight.lower[5] = 0.3;
    tight.upper[5] = 0.5;
    const auto bounded = k.inverse(target, {0, -1.57, 0, -1.57, 0, 0}, tight);
    ASSERT_TRUE(bounded);
    EXPECT_TRUE(tight.contains(*bounded));
    EXPECT_TRUE(devices::near(k.forward(*bounded), target, 1e-6, 1e-6));
}

TEST(DeviceArmKinematics, UnreachablePosesAreRefusedWithAReason) {
    ArmKinematics k(ArmModel::ur5());
    std::string why;
    EXPECT_FALSE(k.inverse(at(1.5, 0, 0.3), {}, ArmModel::ur5().bounds, &why));
    EXPECT_NE(why.find("out of the UR5's reach"), std::string::npos) << why;
    // Inside the bounding sphere but not reachable with this orientation: the flange
    // pointing up right above the base, at the reach limit.
    EXPECT_FALSE(k.inverse(at(0, 0, 0.089159 + 0.99, 0, 0, 0), {}, ArmModel::ur5().bounds, &why));

    // Reachable, but only outside the bounds given: a shoulder pan limited to a range
    // where the target is behind the robot.
    const Joints q{2.5, -1.2, 1.4, -1.8, -1.57, 0.4};
    JointBounds narrow = ArmModel::ur5().bounds;
    narrow.lower[0] = -0.2;
    narrow.upper[0] = 0.2;
    why.clear();
    EXPECT_FALSE(k.inverse(k.forward(q), {}, narrow, &why));
    EXPECT_NE(why.find("joint bounds"), std::string::npos) << why;
}

TEST(DeviceUr5Profile, TrapezoidRespectsItsLimits) {
    for (const auto& [distance, v, a] : {std::tuple{1.0, 0.25, 1.2}, std::tuple{0.01, 0.25, 1.2},
                                         std::tuple{3.0, 1.05, 1.4}, std::tuple{0.0, 1.0, 1.0}}) {
        const TrapezoidalProfile p(distance, v, a);
        EXPECT_NEAR(p.position(p.duration()), distance, 1e-12);
        EXPECT_LE(p.peakVelocity(), v + 1e-12);
        if (distance == 0) {
            EXPECT_EQ(p.duration(), 0);
            continue;
        }
        const double dt = p.duration() / 2000;
        double previousVelocity = 0;
        for (int i = 1; i <= 2000; ++i) {
            const double t = dt * i;
            const double velocity = (p.position(t) - p.position(t - dt)) / dt;
            EXPECT_LE(velocity, v * (1 + 1e-9)) << distance << " at " << t;
            EXPECT_GE(velocity, -1e-12);
            if (i > 1) {
                EXPECT_LE(std::abs(velocity - previousVelocity) / dt, a * (1 + 1e-6) + 1e-6)
                    << distance << " at " << t;
            }
            previousVelocity = velocity;
        }
    }
    // Long enough to cruise: accelerate v/a, cruise, decelerate v/a.
    const TrapezoidalProfile cruise(1.0, 0.25, 1.2);
    EXPECT_NEAR(cruise.duration(), 1.0 / 0.25 + 0.25 / 1.2, 1e-12);
    EXPECT_DOUBLE_EQ(cruise.peakVelocity(), 0.25);
    // Too short to cruise: a triangle peaking below the limit.
    const TrapezoidalProfile triangle(0.01, 0.25, 1.2);
    EXPECT_LT(triangle.peakVelocity(), 0.25);
    EXPECT_NEAR(triangle.duration(), 2 * std::sqrt(0.01 / 1.2), 1e-12);
}

TEST(DeviceUr5Planner, PointToPointMovesEveryJointWithinTheLimits) {
    ArmKinematics k(ArmModel::ur5());
    MotionPlanner planner(k, k.model().defaults);
    const Joints from{0, -1.57, 1.57, -1.57, -1.57, 0};
    MoveRequest r;
    r.kind = MoveKind::JointPtp;
    r.targetJoints = {1.0, -1.2, 1.0, -1.57, -1.0, 0.5};
    r.maxVelocity = 0.5;
    r.maxAcceleration = 2.0;
    const auto planned = planner.plan(from, r);
    ASSERT_TRUE(std::holds_alternative<Trajectory>(planned)) << std::get<std::string>(planned);
    const Trajectory& t = std::get<Trajectory>(planned);
    EXPECT_NEAR(t.duration(), 1.0 / 0.5 + 0.5 / 2.0, 1e-9);  // the lead joint moves 1 rad
    const double dt = t.duration() / 500;
    for (int i = 1; i <= 500; ++i) {
        EXPECT_LE(maxDiff(t.at(dt * i), t.at(dt * (i - 1))) / dt, 0.5 * (1 + 1e-9));
    }
    EXPECT_LT(maxDiff(t.at(t.duration()), r.targetJoints), 1e-12);

    // All-zero limits mean the defaults (1.05 rad/s, 1.4 rad/s^2).
    r.maxVelocity = 0;
    r.maxAcceleration = 0;
    const auto byDefault = planner.plan(from, r);
    ASSERT_TRUE(std::holds_alternative<Trajectory>(byDefault));
    EXPECT_NEAR(std::get<Trajectory>(byDefault).duration(), 1.0 / 1.05 + 1.05 / 1.4, 1e-9);

    r.targetJoints[2] = 7.0;  // beyond +-2 pi
    const auto refused = planner.plan(from, r);
    ASSERT_TRUE(std::holds_alternative<std::string>(refused));
    EXPECT_NE(std::get<std::string>(refused).find("joint 3"), std::string::npos);
}

TEST(DeviceUr5Planner, LinearMovesKeepTheToolOnTheLine) {
    ArmKinematics k(ArmModel::ur5());
    MotionPlanner planner(k, k.model().defaults);
    const Joints from{0, -1.57, 1.57, -1.57, -1.57, 0};
    const KDL::Frame tool = at(0, 0, 0.1);  // TCP 10 cm beyond the flange
    const KDL::Frame start = k.forward(from) * tool;
    MoveRequest r;
    r.kind = MoveKind::CartesianLinear;
    r.toolFrame = tool;
    r.target = KDL::Frame(start.M, start.p + KDL::Vector(0.1, 0.15, -0.1));
    r.maxVelocity = 0.1;
    r.maxAcceleration = 0.5;
    const auto planned = planner.plan(from, r);
    ASSERT_TRUE(std::holds_alternative<Trajectory>(planned)) << std::get<std::string>(planned);
    const Trajectory& t = std::get<Trajectory>(planned);
    const KDL::Vector line = r.target.p - start.p;
    const double length = line.Norm();
    EXPECT_GT(t.duration(), length / 0.1);
    const double dt = t.duration() / 400;
    KDL::Vector previous = start.p;
    for (int i = 0; i <= 400; ++i) {
        const KDL::Frame tcp = k.forward(t.at(dt * i)) * tool;
        // Distance from the line, and the orientation held.
        const KDL::Vector offset = tcp.p - start.p;
        const double along = KDL::dot(offset, line) / length;
        EXPECT_LT((offset - line * (along / length)).Norm(), 2e-4) << i;
        EXPECT_TRUE(near(KDL::Frame(tcp.M), KDL::Frame(start.M), 1, 1e-3)) << i;
        if (i > 0) {
            EXPECT_LE((tcp.p - previous).Norm() / dt, 0.1 * 1.01) << i;
        }
        previous = tcp.p;
    }
    EXPECT_TRUE(near(k.forward(t.end()) * tool, r.target, 1e-6, 1e-6));

    r.target.p = KDL::Vector(1.2, 0.2, 0.3);  // out of reach
    const auto refused = planner.plan(from, r);
    ASSERT_TRUE(std::holds_alternative<std::string>(refused));
    EXPECT_NE(std::get<std::string>(refused).find("unreachable"), std::string::npos);
}

/// A clock the test moves by hand, and a count of the arm's ticks to wait on.
struct ManualClock {
    std::atomic<std::int64_t> ns{0};
    std::chrono::steady_clock::time_point now() const {
        return std::chrono::steady_clock::time_point(std::chrono::nanoseconds(ns.load()));
    }
    void advance(std::chrono::milliseconds d) {
        ns += std::chrono::duration_cast<std::chrono::nanoseconds>(d).count();
    }
};

class TickCounter {
public:
    void tick() {
        {
            std::lock_guard lock(mutex_);
            ++ticks_;
        }
        cv_.notify_all();
    }
    /// Waits for `n` more ticks (bounded).
    bool waitTicks(int n) {
        std::unique_lock lock(mutex_);
        const std::uint64_t target = ticks_ + static_cast<std::uint64_t>(n);
        return cv_.wait_for(lock, 5s, [&] { return ticks_ >= target; });
    }

private:
    std::mutex mutex_;
    std::condition_variable cv_;
    std::uint64_t ticks_ = 0;
};

/// An arm component (a UR5 unless told otherwise) on a real server.
class Ur5Cell {
public:
    /// `forceAt`: the force the tool meets at a flange pose (the arm senses it if its model
    /// does); empty: none.
    explicit Ur5Cell(ManualClock* clock = nullptr, double speed = 20,
                     const ArmModel& model = ArmModel::ur5(),
                     std::function<double(const KDL::Frame&)> forceAt = {},
                     const std::function<void(ArmComponentOptions&)>& adjust = {})
        : kinematics_(model), server_(test::RunningServer::defaultConfig(), [&](ua::Server& s) {
              ArmComponentOptions o;
              o.model = model;
              if (forceAt) {
                  o.arm.contactForce = [this, forceAt] { return forceAt(flange_); };
              }
              o.arm.speed = speed;
              o.arm.tick = 1ms;
              if (clock != nullptr) o.arm.clock = [clock] { return clock->now(); };
              o.onFlange = [this](const KDL::Frame& f) {
                  flange_ = f;  // on the server's thread, as the arm asks for the force
                  ticks_.tick();
              };
              if (adjust) adjust(o);
              auto c = ArmComponent::create(s, o);
              ASSERT_TRUE(c.ok());
              component_ = std::move(*c);
          }) {}
    ~Ur5Cell() {
        server_.inServer([this](ua::Server&) {
            component_.reset();
            return 0;
        });
    }
    Ur5Cell(const Ur5Cell&) = delete;
    Ur5Cell& operator=(const Ur5Cell&) = delete;

    [[nodiscard]] std::string url() const { return server_.url(); }
    Joints joints() {
        return server_.inServer([this](ua::Server&) { return component_->arm().joints(); });
    }
    double elapsed() {
        return server_.inServer([this](ua::Server&) { return component_->arm().elapsed(); });
    }
    SkillState state(const std::string& name) {
        return server_.inServer([&](ua::Server&) {
            for (const auto& s : component_->skills().skills()) {
                if (s->name() == name) return s->state();
            }
            return SkillState::Halted;
        });
    }
    bool has(const std::string& path) {
        return server_.inServer([&](ua::Server& s) {
            return s.addressSpace().find(ua::NodeId(1, ua::String(path))) != nullptr;
        });
    }
    ua::Variant read(const std::string& path) {
        return server_.inServer([&](ua::Server& s) {
            const ua::Node* node = s.addressSpace().find(ua::NodeId(1, ua::String(path)));
            return node == nullptr ? ua::Variant() : *s.addressSpace().readValue(*node).value;
        });
    }
    /// The value at a browse path (namespace URI, name pairs) from Objects.
    ua::Variant readPath(const std::vector<std::pair<std::string_view, std::string>>& path) {
        return server_.inServer([&](ua::Server& s) {
            const ua::AddressSpace& as = s.addressSpace();
            ua::NodeId at(ua::ns0::ObjectsFolder);
            for (const auto& [uri, name] : path) {
                const auto ns =
                    uri.empty() ? std::optional<std::uint16_t>(1) : as.namespaceIndex(uri);
                const ua::Node* n = ns ? as.findChild(at, ua::QualifiedName{*ns, name}) : nullptr;
                if (n == nullptr) return ua::Variant();
                at = n->nodeId;
            }
            return *as.readValue(*as.find(at)).value;
        });
    }
    KDL::Frame forward(const Joints& q) { return kinematics_.forward(q); }
    TickCounter& ticks() { return ticks_; }
    static ua::NodeId skill(const std::string& name) {
        return ua::NodeId(1, ua::String("Skills/" + name));
    }

private:
    ArmKinematics kinematics_;
    KDL::Frame flange_;
    TickCounter ticks_;
    std::unique_ptr<ArmComponent> component_;
    test::RunningServer server_;
};

ua::Variant joints(const Joints& q) {
    return ua::Variant::array(std::vector<double>(q.begin(), q.end()));
}

TEST(DeviceUr5Skills, JointAndCartesianMovesReachTheirTargets) {
    Ur5Cell cell;
    test::ClientThread t;
    auto ptp = t.attach(cell.url(), Ur5Cell::skill("JointPtpMove"));
    ASSERT_TRUE(ptp);
    const Joints target{0.5, -1.3, 1.2, -1.5, -1.57, 0.2};
    auto outcome = t.invoke(ptp, {{"TargetJointPosition", joints(target)}}, 10s);
    ASSERT_EQ(outcome.kind, Kind::Finished) << outcome.reason;
    EXPECT_LT(maxDiff(cell.joints(), target), 1e-9);
    // The published joints and TCP follow the arm.
    const ua::Variant published = cell.read("UR5/JointPositions");
    ASSERT_EQ(published.elements().size(), 6u);
    EXPECT_NEAR(std::get<double>(published.elements()[0]), 0.5, 1e-9);

    // A linear move of the TCP (10 cm tool) 5 cm down and 5 cm sideways.
    auto linear = t.attach(cell.url(), Ur5Cell::skill("CartesianLinearMove"));
    ASSERT_TRUE(linear);
    const KDL::Frame tool = at(0, 0, 0.1);
    const KDL::Frame tcp = cell.forward(target) * tool;
    const KDL::Frame goal(tcp.M, tcp.p + KDL::Vector(0, 0.05, -0.05));
    outcome = t.invoke(linear,
                       {{"TargetPosition", frameToVariant(goal)},
                        {"ToolFrame", frameToVariant(tool)},
                        {"MaxVelocity", ua::Variant(0.5)}},
                       10s);
    ASSERT_EQ(outcome.kind, Kind::Finished) << outcome.reason;
    EXPECT_TRUE(near(cell.forward(cell.joints()) * tool, goal, 1e-6, 1e-6));
    const auto tcpPublished = frameFromVariant(cell.read("UR5/TcpPose"));
    ASSERT_TRUE(tcpPublished.ok());
    EXPECT_TRUE(near(*tcpPublished, goal, 1e-6, 1e-6)) << describe(*tcpPublished);

    // Point to point to a Cartesian pose, within AxisBounds.
    auto cptp = t.attach(cell.url(), Ur5Cell::skill("CartesianPtpMove"));
    ASSERT_TRUE(cptp);
    const KDL::Frame goal2 = at(-0.3, -0.4, 0.3, M_PI, 0, 0);
    std::vector<ua::Scalar> bounds;
    for (std::size_t i = 0; i < 6; ++i) {
        bounds.emplace_back(ua::toExtensionObject(ua::Range{-M_PI, M_PI}));
    }
    outcome = t.invoke(
        cptp,
        {{"TargetPosition", frameToVariant(goal2)},
         {"AxisBounds", ua::Variant::array(ua::BuiltinType::ExtensionObject, std::move(bounds))}},
        10s);
    ASSERT_EQ(outcome.kind, Kind::Finished) << outcome.reason;
    const Joints q = cell.joints();
    EXPECT_TRUE(near(cell.forward(q), goal2, 1e-6, 1e-6));
    for (double v : q) EXPECT_LE(std::abs(v), M_PI + 1e-9);

    // Joint-linear: the TCP on a straight line, ending in the joints asked for.
    auto jlin = t.attach(cell.url(), Ur5Cell::skill("JointLinearMove"));
    ASSERT_TRUE(jlin);
    Joints nearby = q;
    nearby[0] += 0.1;
    nearby[1] += 0.05;
    outcome = t.invoke(jlin, {{"TargetJointPosition", joints(nearby)}}, 10s);
    ASSERT_EQ(outcome.kind, Kind::Finished) << outcome.reason;
    EXPECT_LT(maxDiff(cell.joints(), nearby), 1e-6);
}

// A client that knows the OPC Foundation's Robotics model and nothing of skillcell finds the
// arm in DI's DeviceSet: its nameplate, its category, and each axis's ActualPosition.
TEST(DeviceUr5Skills, TheArmIsInTheRoboticsModelWithEachAxisPosition) {
    namespace cm = ua::companion;
    Ur5Cell cell;
    test::ClientThread t;
    auto ptp = t.attach(cell.url(), Ur5Cell::skill("JointPtpMove"));
    ASSERT_TRUE(ptp);
    const Joints target{0.5, -1.3, 1.2, -1.5, -1.57, 0.2};
    auto outcome = t.invoke(ptp, {{"TargetJointPosition", joints(target)}}, 10s);
    ASSERT_EQ(outcome.kind, Kind::Finished) << outcome.reason;

    using Path = std::vector<std::pair<std::string_view, std::string>>;
    const Path device{{cm::kDiUri, "DeviceSet"},
                      {"", "UR5System"},
                      {cm::kRoboticsUri, "MotionDevices"},
                      {"", "UR5"}};
    auto at = [&](Path tail) {
        Path p = device;
        p.insert(p.end(), tail.begin(), tail.end());
        return cell.readPath(p);
    };
    const ua::Variant manufacturerValue = at({{cm::kDiUri, "Manufacturer"}});
    const auto* manufacturer = manufacturerValue.get<ua::LocalizedText>();
    ASSERT_NE(manufacturer, nullptr);
    EXPECT_EQ(manufacturer->text, "Universal Robots");
    const ua::Variant categoryValue = at({{cm::kRoboticsUri, "MotionDeviceCategory"}});
    const auto* category = categoryValue.get<std::int32_t>();
    ASSERT_NE(category, nullptr);
    EXPECT_EQ(*category, 1);  // ARTICULATED_ROBOT
    const char* axes[] = {"Base", "Shoulder", "Elbow", "Wrist1", "Wrist2", "Wrist3"};
    for (std::size_t i = 0; i < std::size(axes); ++i) {
        const auto value = at({{cm::kRoboticsUri, "Axes"},
                               {"", axes[i]},
                               {cm::kDiUri, "ParameterSet"},
                               {cm::kRoboticsUri, "ActualPosition"}});
        const auto* position = value.get<double>();
        ASSERT_NE(position, nullptr) << axes[i];
        EXPECT_NEAR(*position, target[i], 1e-9) << axes[i];
    }
}

TEST(DeviceUr5Skills, StartsWhereItIsToldOnceItsModelsAreLoadedOrFailsSayingWhyItWasNot) {
    // A device that learns where its arm stands from the world model learns it while the arm
    // loads its models: the arm asks once they are loaded.
    const Joints q{0.3, -1.2, 1.1, -0.4, 1.2, 0.1};
    bool modelsLoaded = false;
    Joints started;
    ua::Variant published;
    {
        std::unique_ptr<ArmComponent> arm;
        test::RunningServer server(test::RunningServer::defaultConfig(), [&](ua::Server& s) {
            ArmComponentOptions o;
            o.startingJoints = [&](std::string*) -> ua::Result<Joints> {
                modelsLoaded = s.addressSpace().namespaceIndex(ua::companion::kRoboticsUri) &&
                               s.addressSpace().find(ua::NodeId(1, ua::String("UR5"))) != nullptr;
                return q;
            };
            auto c = ArmComponent::create(s, o);
            ASSERT_TRUE(c.ok());
            arm = std::move(*c);
        });
        server.inServer([&](ua::Server& s) {
            started = arm->arm().joints();
            const ua::Node* node =
                s.addressSpace().find(ua::NodeId(1, ua::String("UR5/JointPositions")));
            if (node != nullptr) published = *s.addressSpace().readValue(*node).value;
            arm.reset();
            return 0;
        });
    }
    EXPECT_TRUE(modelsLoaded);
    EXPECT_EQ(started, q);
    EXPECT_EQ(published, joints(q));

    ua::StatusCode refused;
    std::string error;
    test::RunningServer server(test::RunningServer::defaultConfig(), [&](ua::Server& s) {
        ArmComponentOptions o;
        o.startingJoints = [](std::string* why) -> ua::Result<Joints> {
            *why = "the world model is out of reach";
            return ua::status::BadServerNotConnected;
        };
        refused = ArmComponent::create(s, o, &error).status();
    });
    EXPECT_EQ(refused, ua::status::BadServerNotConnected);
    EXPECT_NE(error.find("the world model is out of reach"), std::string::npos) << error;
}

TEST(DeviceUr5Skills, AnUnreachableTargetHaltsTheSkillWithTheReason) {
    Ur5Cell cell;
    test::ClientThread t;
    auto linear = t.attach(cell.url(), Ur5Cell::skill("CartesianLinearMove"));
    ASSERT_TRUE(linear);
    const Joints before = cell.joints();
    auto outcome = t.invoke(linear, {{"TargetPosition", frameToVariant(at(2.0, 0, 0.5))}}, 10s);
    EXPECT_EQ(outcome.kind, Kind::Failed);
    EXPECT_NE(outcome.reason.find("unreachable"), std::string::npos) << outcome.reason;
    EXPECT_EQ(cell.state("CartesianLinearMove"), SkillState::Halted);
    EXPECT_EQ(cell.joints(), before);  // nothing moved

    // Wrong inputs are refused before the run: a joint vector of the wrong length fails
    // with its reason; a velocity beyond the EURange is refused at the write.
    auto ptp = t.attach(cell.url(), Ur5Cell::skill("JointPtpMove"));
    ASSERT_TRUE(ptp);
    outcome = t.invoke(
        ptp,
        {{"TargetJointPosition", joints({0, 0, 0, 0, 0, 0})}, {"MaxVelocity", ua::Variant(5.0)}},
        10s);
    EXPECT_EQ(outcome.kind, Kind::Refused);
    EXPECT_EQ(outcome.status, ua::status::BadOutOfRange);
    outcome = t.invoke(ptp,
                       {{"TargetJointPosition", ua::Variant::array(std::vector<double>{0, 0, 0})},
                        {"MaxVelocity", ua::Variant(0.0)}},
                       10s);
    EXPECT_EQ(outcome.kind, Kind::Failed);
    EXPECT_NE(outcome.reason.find("6 joint positions"), std::string::npos) << outcome.reason;
    // No target written: the model's default TargetPosition (the base frame's origin,
    // inside the robot's own base) is not reachable.
    auto cptp = t.attach(cell.url(), Ur5Cell::skill("CartesianPtpMove"));
    ASSERT_TRUE(cptp);
    outcome = t.invoke(cptp, {}, 10s);
    EXPECT_EQ(outcome.kind, Kind::Failed);
    EXPECT_NE(outcome.reason.find("unreachable"), std::string::npos) << outcome.reason;
}

TEST(DeviceUr5Skills, SuspendResumeAndHaltWorkMidMotion) {
    ManualClock clock;
    Ur5Cell cell(&clock, 1.0);
    test::ClientThread t;
    auto ptp = t.attach(cell.url(), Ur5Cell::skill("JointPtpMove"));
    ASSERT_TRUE(ptp);
    const Joints start = cell.joints();
    Joints target = start;
    target[0] += 1.0;  // 1 rad at 0.5 rad/s, 1 rad/s^2: 2.5 s
    auto started = t.run([&]() -> asio::awaitable<ua::StatusCode> {
        co_await ptp->setParameter("TargetJointPosition", joints(target));
        co_await ptp->setParameter("MaxVelocity", ua::Variant(0.5));
        co_await ptp->setParameter("MaxAcceleration", ua::Variant(1.0));
        co_return co_await ptp->start();
    });
    ASSERT_EQ(started, ua::status::Good);
    EXPECT_EQ(cell.state("JointPtpMove"), SkillState::Running);

    clock.advance(1000ms);
    ASSERT_TRUE(cell.ticks().waitTicks(2));
    EXPECT_NEAR(cell.elapsed(), 1.0, 1e-9);
    const double at1s = cell.joints()[0] - start[0];
    EXPECT_NEAR(at1s, 0.5 * 1.0 * 0.25 + 0.5 * 0.5, 1e-9);  // 0.5 s accelerating, 0.5 s cruising

    auto call = [&](SkillMethod m) {
        return t.run([&]() -> asio::awaitable<ua::StatusCode> { co_return co_await ptp->call(m); });
    };
    ASSERT_EQ(call(SkillMethod::Suspend), ua::status::Good);
    EXPECT_EQ(cell.state("JointPtpMove"), SkillState::Suspended);
    const Joints held = cell.joints();
    clock.advance(10'000ms);  // long past the motion's end: a suspended arm does not move
    ASSERT_TRUE(cell.ticks().waitTicks(3));
    EXPECT_EQ(cell.joints(), held);
    EXPECT_EQ(cell.state("JointPtpMove"), SkillState::Suspended);

    ASSERT_EQ(call(SkillMethod::Resume), ua::status::Good);
    EXPECT_EQ(cell.state("JointPtpMove"), SkillState::Running);
    clock.advance(500ms);
    ASSERT_TRUE(cell.ticks().waitTicks(2));
    EXPECT_NEAR(cell.elapsed(), 1.5, 1e-9);  // the pause did not count
    clock.advance(2000ms);
    const auto end = t.run(
        [&]() -> asio::awaitable<skills::SkillOutcome> { co_return co_await ptp->waitForEnd(5s); });
    EXPECT_EQ(end.kind, Kind::Finished) << end.reason;
    EXPECT_LT(maxDiff(cell.joints(), target), 1e-12);

    // Halt in the middle of the way back: the arm stays where it was.
    started = t.run([&]() -> asio::awaitable<ua::StatusCode> {
        co_await ptp->setParameter("TargetJointPosition", joints(start));
        co_return co_await ptp->start();
    });
    ASSERT_EQ(started, ua::status::Good);
    clock.advance(1000ms);
    ASSERT_TRUE(cell.ticks().waitTicks(2));
    ASSERT_EQ(call(SkillMethod::Halt), ua::status::Good);
    EXPECT_EQ(cell.state("JointPtpMove"), SkillState::Halted);
    const Joints stopped = cell.joints();
    EXPECT_LT(stopped[0], target[0] - 0.1);
    EXPECT_GT(stopped[0], start[0] + 0.1);
    clock.advance(5000ms);  // a halted arm has no motion left to take up the time
    EXPECT_EQ(cell.joints(), stopped);
    ASSERT_EQ(call(SkillMethod::Reset), ua::status::Good);
    EXPECT_EQ(cell.state("JointPtpMove"), SkillState::Ready);
}

TEST(DeviceIiwaKinematics, StretchedUpTheFlangeIsAboveTheBaseAtTheSumOfTheLinks) {
    ArmKinematics k(ArmModel::lbrIiwa7());
    ASSERT_EQ(k.joints(), 7u);
    const KDL::Frame up = k.forward(Joints(7, 0.0));
    EXPECT_NEAR(up.p.x(), 0, 1e-9);
    EXPECT_NEAR(up.p.y(), 0, 1e-9);
    EXPECT_NEAR(up.p.z(), 0.34 + 0.4 + 0.4 + 0.126, 1e-9);
    // Axis 4 bent by 90 degrees: the forearm horizontal, 0.4 m out from the elbow.
    const KDL::Frame bent = k.forward({0, 0, 0, -M_PI / 2, 0, 0, 0});
    EXPECT_NEAR(bent.p.z(), 0.34 + 0.4, 1e-9);
    EXPECT_NEAR(std::hypot(bent.p.x(), bent.p.y()), 0.4 + 0.126, 1e-9);
    // At home the flange points down, in front of the robot, within reach.
    const KDL::Frame home = k.forward(ArmModel::lbrIiwa7().home);
    EXPECT_LT(home.M.UnitZ().z(), -0.99) << describe(home);
    EXPECT_GT(home.p.x(), 0.3);
    EXPECT_TRUE(ArmModel::lbrIiwa7().bounds.contains(ArmModel::lbrIiwa7().home));
    // The wrong number of joints gives no pose, not a crash.
    EXPECT_TRUE(near(k.forward({0, 0, 0}), KDL::Frame::Identity(), 0, 0));
}

TEST(DeviceIiwaKinematics, InverseMatchesForwardWithinTheAxisLimits) {
    const ArmModel model = ArmModel::lbrIiwa7();
    ArmKinematics k(model);
    std::mt19937 random(20261129);
    int solved = 0;
    for (int n = 0; n < 50; ++n) {
        Joints q(7);
        for (std::size_t i = 0; i < 7; ++i) {
            // Away from the limits, where the arm works.
            std::uniform_real_distribution<double> angle(model.bounds.lower[i] * 0.8,
                                                         model.bounds.upper[i] * 0.8);
            q[i] = angle(random);
        }
        const KDL::Frame target = k.forward(q);
        std::string why;
        const auto solution = k.inverse(target, model.home, model.bounds, &why);
        ASSERT_TRUE(solution) << "pose " << n << " " << describe(target) << ": " << why;
        EXPECT_TRUE(model.bounds.contains(*solution)) << n;
        EXPECT_TRUE(near(k.forward(*solution), target, 1e-6, 1e-6)) << n;
        ++solved;
    }
    EXPECT_EQ(solved, 50);
    std::string why;
    EXPECT_FALSE(k.inverse(at(1.2, 0, 0.3), {}, model.bounds, &why));
    EXPECT_NE(why.find("out of the LBRiiwa7's reach"), std::string::npos) << why;
    // The UR5's six joints are no seed for seven axes.
    EXPECT_FALSE(k.inverse(k.forward(model.home), Joints(6, 0.0), model.bounds, &why));
    EXPECT_NE(why.find("6 joints"), std::string::npos) << why;
}

TEST(DeviceIiwaPlanner, ALinearMoveKeepsTheToolOnTheLineAndTheElbowWhereItWas) {
    const ArmModel model = ArmModel::lbrIiwa7();
    ArmKinematics k(model);
    MotionPlanner planner(k, model.defaults);
    MoveRequest r;
    r.kind = MoveKind::CartesianLinear;
    const KDL::Frame start = k.forward(model.home);
    r.target = KDL::Frame(start.M, start.p + KDL::Vector(0.05, 0.1, -0.15));
    const auto planned = planner.plan(model.home, r);
    ASSERT_TRUE(std::holds_alternative<Trajectory>(planned)) << std::get<std::string>(planned);
    const Trajectory& t = std::get<Trajectory>(planned);
    const KDL::Vector line = r.target.p - start.p;
    for (int i = 0; i <= 100; ++i) {
        const KDL::Frame f = k.forward(t.at(t.duration() * i / 100));
        const KDL::Vector off = f.p - start.p;
        const KDL::Vector across = off - line * (KDL::dot(off, line) / KDL::dot(line, line));
        EXPECT_LT(across.Norm(), 1e-3) << i;
        EXPECT_TRUE(near(KDL::Frame(f.M), KDL::Frame(start.M), 0, 1e-3)) << i;
    }
    EXPECT_TRUE(near(k.forward(t.end()), r.target, 1e-6, 1e-6));
    // A redundant arm could reach the end with its elbow elsewhere; the line keeps it near.
    EXPECT_LT(maxDiff(t.end(), model.home), 0.6);

    // Joint moves need seven positions.
    MoveRequest six;
    six.kind = MoveKind::JointPtp;
    six.targetJoints = Joints(6, 0.0);
    const auto refused = planner.plan(model.home, six);
    ASSERT_TRUE(std::holds_alternative<std::string>(refused));
    EXPECT_NE(std::get<std::string>(refused).find("must hold 7 joint positions, not 6"),
              std::string::npos)
        << std::get<std::string>(refused);
}

TEST(DeviceIiwaSkills, MovesThroughItsSkillsAndShowsItsSevenAxesInTheRoboticsModel) {
    namespace cm = ua::companion;
    const ArmModel model = ArmModel::lbrIiwa7();
    Ur5Cell cell(nullptr, 20, model);
    test::ClientThread t;
    auto ptp = t.attach(cell.url(), Ur5Cell::skill("JointPtpMove"));
    ASSERT_TRUE(ptp);
    const Joints target{0.3, 0.6, -0.2, -1.4, 0.1, 0.9, 0.5};
    auto outcome = t.invoke(ptp, {{"TargetJointPosition", joints(target)}}, 10s);
    ASSERT_EQ(outcome.kind, Kind::Finished) << outcome.reason;
    EXPECT_LT(maxDiff(cell.joints(), target), 1e-12);
    const ua::Variant published = cell.read("LBRiiwa7/JointPositions");
    ASSERT_TRUE(published.isArray());
    EXPECT_EQ(published.elements().size(), 7u);

    auto lin = t.attach(cell.url(), Ur5Cell::skill("CartesianLinearMove"));
    ASSERT_TRUE(lin);
    const KDL::Frame here = cell.forward(cell.joints());
    const KDL::Frame goal(here.M, here.p + KDL::Vector(0, 0, -0.05));
    outcome = t.invoke(lin, {{"TargetPosition", frameToVariant(goal)}}, 10s);
    ASSERT_EQ(outcome.kind, Kind::Finished) << outcome.reason;
    EXPECT_TRUE(near(cell.forward(cell.joints()), goal, 1e-6, 1e-6));

    // Six positions for seven axes: Halted with the reason.
    outcome = t.invoke(ptp, {{"TargetJointPosition", joints(Joints(6, 0.0))}}, 10s);
    EXPECT_EQ(outcome.kind, Kind::Failed);
    EXPECT_NE(outcome.reason.find("must hold 7 joint positions"), std::string::npos)
        << outcome.reason;

    using Path = std::vector<std::pair<std::string_view, std::string>>;
    const Path device{{cm::kDiUri, "DeviceSet"},
                      {"", "LBRiiwa7System"},
                      {cm::kRoboticsUri, "MotionDevices"},
                      {"", "LBRiiwa7"}};
    const auto manufacturer =
        cell.readPath({device[0], device[1], device[2], device[3], {cm::kDiUri, "Manufacturer"}});
    ASSERT_NE(manufacturer.get<ua::LocalizedText>(), nullptr);
    EXPECT_EQ(manufacturer.get<ua::LocalizedText>()->text, "KUKA");
    const Joints q = cell.joints();
    for (std::size_t i = 0; i < 7; ++i) {
        const std::string axis = "A" + std::to_string(i + 1);
        const auto value = cell.readPath({device[0],
                                          device[1],
                                          device[2],
                                          device[3],
                                          {cm::kRoboticsUri, "Axes"},
                                          {"", axis},
                                          {cm::kDiUri, "ParameterSet"},
                                          {cm::kRoboticsUri, "ActualPosition"}});
        ASSERT_NE(value.get<double>(), nullptr) << axis;
        EXPECT_NEAR(*value.get<double>(), q[i], 1e-9) << axis;
    }
}

// An arm that senses force stops a force-limited move where its tool meets a surface, Halted
// with the force in the reason; the same move in free space ends; an arm that senses no force
// offers no such move.
TEST(DeviceIiwaSkills, AForceLimitedMoveStopsOnContactWithTheForceInItsReason) {
    const ArmModel model = ArmModel::lbrIiwa7();
    ArmKinematics k(model);
    const double surface = k.forward(model.home).p.z() - 0.01;  // 1 cm below the flange
    constexpr double kStiffness = 30'000;                       // N/m
    Ur5Cell cell(nullptr, 20, model, [surface](const KDL::Frame& f) {
        return kStiffness * std::max(0.0, surface - f.p.z());
    });
    test::ClientThread t;
    auto press = t.attach(cell.url(), Ur5Cell::skill("CartesianForceLimitedLinearMove"));
    ASSERT_TRUE(press);
    const KDL::Frame start = cell.forward(cell.joints());
    const KDL::Frame down(start.M, start.p - KDL::Vector(0, 0, 0.03));
    auto outcome = t.invoke(press,
                            {{"TargetPosition", frameToVariant(down)},
                             {"ForceLimit", ua::Variant(20.0)},
                             {"MaxVelocity", ua::Variant(0.02)}},
                            10s);
    ASSERT_EQ(outcome.kind, Kind::Failed) << outcome.reason;
    EXPECT_NE(outcome.reason.find("exceeded the limit of 20.0 N"), std::string::npos)
        << outcome.reason;
    // Stopped past the surface by at least the limit's 0.7 mm (plus what the ticks' lag
    // adds, which a loaded machine makes longer), short of the target.
    const double z = cell.forward(cell.joints()).p.z();
    EXPECT_LT(z, surface - 20 / kStiffness + 1e-9);
    EXPECT_GT(z, down.p.z() + 1e-4);
    const ua::Variant force = cell.read("LBRiiwa7/ContactForce");
    ASSERT_NE(force.get<double>(), nullptr);
    EXPECT_GT(*force.get<double>(), 20.0);

    // A plain linear move backs off; in free space the force-limited move ends.
    ASSERT_EQ(t.run([&]() -> asio::awaitable<ua::StatusCode> {
        co_return co_await press->call(SkillMethod::Reset);
    }),
              ua::status::Good);
    auto lin = t.attach(cell.url(), Ur5Cell::skill("CartesianLinearMove"));
    ASSERT_TRUE(lin);
    outcome = t.invoke(lin, {{"TargetPosition", frameToVariant(start)}}, 10s);
    ASSERT_EQ(outcome.kind, Kind::Finished) << outcome.reason;
    const KDL::Frame above(start.M, start.p + KDL::Vector(0, 0, 0.01));
    outcome = t.invoke(
        press, {{"TargetPosition", frameToVariant(above)}, {"ForceLimit", ua::Variant(20.0)}}, 10s);
    ASSERT_EQ(outcome.kind, Kind::Finished) << outcome.reason;
    EXPECT_TRUE(near(cell.forward(cell.joints()), above, 1e-6, 1e-6));
    // No limit, no move.
    outcome = t.invoke(
        press, {{"TargetPosition", frameToVariant(down)}, {"ForceLimit", ua::Variant(0.0)}}, 10s);
    EXPECT_EQ(outcome.kind, Kind::Failed);
    EXPECT_NE(outcome.reason.find("ForceLimit must be above 0 N"), std::string::npos)
        << outcome.reason;

    // The UR5 measures no force: it offers no force-limited move.
    Ur5Cell ur5;
    EXPECT_FALSE(ur5.has("Skills/CartesianForceLimitedLinearMove"));
    EXPECT_TRUE(ur5.has("Skills/CartesianLinearMove"));
}

/// A force sensor whose measurements come late, as the world model's answers do on a loaded
/// machine: a thread of its own measures the newest reported pose every `period`.
class SlowForceSensor {
public:
    SlowForceSensor(std::function<double(const KDL::Frame&)> forceAt,
                    std::chrono::milliseconds period)
        : forceAt_(std::move(forceAt)), thread_([this, period] { run(period); }) {}
    ~SlowForceSensor() {
        {
            std::lock_guard lock(mutex_);
            stopping_ = true;
        }
        cv_.notify_all();
        thread_.join();
    }
    SlowForceSensor(const SlowForceSensor&) = delete;
    SlowForceSensor& operator=(const SlowForceSensor&) = delete;

    void report(const KDL::Frame& f) {
        std::lock_guard lock(mutex_);
        pending_ = f;
        ++reported_;
    }
    double force() {
        std::lock_guard lock(mutex_);
        return force_;
    }
    std::uint64_t unmeasured() {
        std::lock_guard lock(mutex_);
        return reported_ - measured_;
    }

private:
    void run(std::chrono::milliseconds period) {
        std::unique_lock lock(mutex_);
        while (!cv_.wait_for(lock, period, [this] { return stopping_; })) {
            if (!pending_) continue;
            force_ = forceAt_(*pending_);
            measured_ = reported_;
            pending_.reset();
        }
    }

    std::function<double(const KDL::Frame&)> forceAt_;
    std::mutex mutex_;
    std::condition_variable cv_;
    std::optional<KDL::Frame> pending_;
    std::uint64_t reported_ = 0;
    std::uint64_t measured_ = 0;
    double force_ = 0;
    bool stopping_ = false;
    std::thread thread_;  // last: it starts with the members above in place
};

// The simulated sensing's latency is a round trip, which a loaded machine stretches; the arm
// waits for it instead of running deeper into the contact: with a measurement every 10 ms
// (ten of the arm's ticks), it stops within a few samples of where the force passes the limit.
TEST(DeviceIiwaSkills, ASlowForceMeasurementDoesNotLetTheMotionRunDeeperIntoContact) {
    const ArmModel model = ArmModel::lbrIiwa7();
    ArmKinematics k(model);
    const double surface = k.forward(model.home).p.z() - 0.002;  // 2 mm below the flange
    constexpr double kStiffness = 30'000;                        // N/m: 20 N at 0.67 mm
    SlowForceSensor sensor(
        [surface](const KDL::Frame& f) { return kStiffness * std::max(0.0, surface - f.p.z()); },
        10ms);
    Ur5Cell cell(nullptr, 20, model, {}, [&sensor](ArmComponentOptions& o) {
        o.onFlange = [&sensor, forward = o.onFlange](const KDL::Frame& f) {
            forward(f);
            sensor.report(f);
        };
        o.arm.contactForce = [&sensor] { return sensor.force(); };
        o.arm.unmeasuredSamples = [&sensor] { return sensor.unmeasured(); };
    });
    test::ClientThread t;
    auto press = t.attach(cell.url(), Ur5Cell::skill("CartesianForceLimitedLinearMove"));
    ASSERT_TRUE(press);
    const KDL::Frame start = cell.forward(cell.joints());
    const KDL::Frame down(start.M, start.p - KDL::Vector(0, 0, 0.01));
    const auto outcome = t.invoke(press,
                                  {{"TargetPosition", frameToVariant(down)},
                                   {"ForceLimit", ua::Variant(20.0)},
                                   {"MaxVelocity", ua::Variant(0.02)}},
                                  20s);
    ASSERT_EQ(outcome.kind, Kind::Failed) << outcome.reason;
    EXPECT_NE(outcome.reason.find("exceeded the limit of 20.0 N"), std::string::npos)
        << outcome.reason;
    // A sample is at most 0.04 mm of motion at 20 mm/s; one may await its measurement while
    // the next is taken. Unbounded, ten samples pass per measurement: 0.4 mm too deep.
    const double depth = surface - cell.forward(cell.joints()).p.z();
    EXPECT_GT(depth, 20 / kStiffness);
    EXPECT_LT(depth, 20 / kStiffness + 0.00015) << "stopped " << depth * 1000 << " mm deep";
}

TEST(DeviceIiwaSkills, AForceLimitedMoveThatEndsPressedHarderThanItsLimitFails) {
    // A face exactly at the target: the move gets there, and the force there is what counts.
    const ArmModel model = ArmModel::lbrIiwa7();
    ArmKinematics k(model);
    const KDL::Frame start = k.forward(model.home);
    const double face = start.p.z() - 0.005;
    Ur5Cell cell(nullptr, 20, model,
                 [face](const KDL::Frame& f) { return f.p.z() < face + 1e-6 ? 50.0 : 0.0; });
    test::ClientThread t;
    auto press = t.attach(cell.url(), Ur5Cell::skill("CartesianForceLimitedLinearMove"));
    ASSERT_TRUE(press);
    const KDL::Frame onTheFace(start.M, KDL::Vector(start.p.x(), start.p.y(), face));
    const auto outcome = t.invoke(
        press, {{"TargetPosition", frameToVariant(onTheFace)}, {"ForceLimit", ua::Variant(20.0)}},
        10s);
    ASSERT_EQ(outcome.kind, Kind::Failed) << outcome.reason;
    EXPECT_NE(outcome.reason.find("the contact force 50.0 N exceeded the limit of 20.0 N"),
              std::string::npos)
        << outcome.reason;
}

}  // namespace
}  // namespace skillcell::devices::device_arm_test
