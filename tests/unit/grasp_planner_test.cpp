// The pick-and-place grasp planner: where the grip point ends up on the box for vacuum and
// parallel grip points (level, yawed, lying on a side, slightly tilted), the approach and
// retreat offsets, the object carried unchanged relative to the grip point to the place
// position, the flange poses through the grip point offset, and the refusals.
#include "devices/pickplace/grasp_planner.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <numbers>

namespace skillcell::devices::pickplace::grasp_planner_test {
namespace {

constexpr double kTol = 1e-9;
constexpr double kDeg = std::numbers::pi / 180;

KDL::Frame at(double x, double y, double z, double roll = 0, double pitch = 0, double yaw = 0) {
    return {KDL::Rotation::RPY(roll, pitch, yaw), KDL::Vector(x, y, z)};
}

::testing::AssertionResult sameVector(const KDL::Vector& actual, const KDL::Vector& expected,
                                      double tol = kTol) {
    for (int i = 0; i < 3; ++i) {
        if (!(std::abs(actual(i) - expected(i)) <= tol)) {
            return ::testing::AssertionFailure()
                   << "(" << actual.x() << ", " << actual.y() << ", " << actual.z() << ") != ("
                   << expected.x() << ", " << expected.y() << ", " << expected.z() << ")";
        }
    }
    return ::testing::AssertionSuccess();
}

::testing::AssertionResult sameFrame(const KDL::Frame& actual, const KDL::Frame& expected,
                                     double tol = kTol) {
    if (auto r = sameVector(actual.p, expected.p, tol); !r) return r << " (position)";
    for (int i = 0; i < 3; ++i) {
        for (int j = 0; j < 3; ++j) {
            if (!(std::abs(actual.M(i, j) - expected.M(i, j)) <= tol)) {
                return ::testing::AssertionFailure()
                       << "rotations differ at (" << i << ", " << j << "): " << actual.M(i, j)
                       << " vs " << expected.M(i, j);
            }
        }
    }
    return ::testing::AssertionSuccess();
}

// Parallel or antiparallel unit vectors.
::testing::AssertionResult parallel(const KDL::Vector& a, const KDL::Vector& b) {
    if (std::abs(std::abs(KDL::dot(a, b)) - a.Norm() * b.Norm()) <= kTol) {
        return ::testing::AssertionSuccess();
    }
    return ::testing::AssertionFailure() << "not parallel: |a.b| = " << std::abs(KDL::dot(a, b));
}

::testing::AssertionResult properRotation(const KDL::Rotation& r) {
    const KDL::Vector c[3] = {r.UnitX(), r.UnitY(), r.UnitZ()};
    for (int i = 0; i < 3; ++i) {
        for (int j = 0; j < 3; ++j) {
            const double expected = i == j ? 1 : 0;
            if (!(std::abs(KDL::dot(c[i], c[j]) - expected) <= 1e-12)) {
                return ::testing::AssertionFailure() << "not orthonormal at " << i << ", " << j;
            }
        }
    }
    const double det = KDL::dot(c[0] * c[1], c[2]);
    if (!(std::abs(det - 1) <= 1e-12)) return ::testing::AssertionFailure() << "det " << det;
    return ::testing::AssertionSuccess();
}

void expectProper(const GraspPlan& plan) {
    for (const auto& [name, flange] : steps(plan)) {
        EXPECT_TRUE(properRotation(flange.M)) << name;
    }
}

// The box's extent along `direction` (what fingers closing along it meet).
double extentAlong(const BoxSize& size, const KDL::Frame& pose, const KDL::Vector& direction) {
    const KDL::Vector local = pose.M.Inverse(direction / direction.Norm());
    return std::abs(local.x()) * size.x + std::abs(local.y()) * size.y +
           std::abs(local.z()) * size.z;
}

// A gripper whose grip point is 15 cm along the flange's z axis.
const KDL::Frame kOffset = at(0, 0, 0.15);

GraspRequest request(GripPointType type, BoxSize size, const KDL::Frame& object,
                     const KDL::Frame& place = at(0.2, -0.3, 0.02, 0, 0, 90 * kDeg)) {
    GraspRequest r;
    r.size = size;
    r.objectPose = object;
    r.gripPointOffset = kOffset;
    r.type = type;
    r.placePosition = place;
    return r;
}

TEST(GraspPlanner, VacuumGripsTheTopFaceCentrePointingDown) {
    const auto req = request(GripPointType::Vacuum, {0.04, 0.06, 0.04}, at(0.5, 0.1, 0.02));
    std::string why;
    const auto plan = planGrasp(req, &why);
    ASSERT_TRUE(plan) << why;
    expectProper(*plan);
    EXPECT_EQ(plan->width, 0);

    const KDL::Frame grip = plan->grasp * kOffset;
    EXPECT_TRUE(sameVector(grip.p, {0.5, 0.1, 0.04}));
    EXPECT_TRUE(sameVector(grip.M.UnitZ(), {0, 0, -1}));
    EXPECT_TRUE(sameVector(grip.M.UnitX(), {1, 0, 0}));  // the object's x axis
    // The grip point's z is the flange's z, so the flange is 15 cm straight above.
    EXPECT_TRUE(sameVector(plan->grasp.p, {0.5, 0.1, 0.19}));

    const KDL::Frame approach = plan->approach * kOffset;
    EXPECT_TRUE(sameFrame(approach, KDL::Frame(grip.M, {0.5, 0.1, 0.09})));
    EXPECT_TRUE(sameFrame(plan->retreat, plan->approach));
}

TEST(GraspPlanner, VacuumFollowsAYawedBox) {
    const KDL::Frame object = at(0.4, -0.2, 0.03, 0, 0, 30 * kDeg);
    const BoxSize size{0.08, 0.05, 0.06};
    const auto plan = planGrasp(request(GripPointType::Vacuum, size, object));
    ASSERT_TRUE(plan);
    expectProper(*plan);

    const KDL::Frame grip = plan->grasp * kOffset;
    EXPECT_TRUE(sameVector(object.Inverse(grip.p), {0, 0, size.z / 2}));  // top-face centre
    EXPECT_TRUE(sameVector(grip.p, {0.4, -0.2, 0.06}));
    EXPECT_TRUE(sameVector(grip.M.UnitZ(), {0, 0, -1}));
    EXPECT_TRUE(sameVector(grip.M.UnitX(), {std::cos(30 * kDeg), std::sin(30 * kDeg), 0}));
    EXPECT_TRUE(sameVector((plan->approach * kOffset).p, {0.4, -0.2, 0.11}));
}

TEST(GraspPlanner, VacuumUsesWhicheverFaceIsOnTop) {
    const BoxSize size{0.04, 0.10, 0.06};
    {  // lying on its side: the box's y axis points up, so its y face is on top
        const KDL::Frame object = at(0.5, 0, 0.05, 90 * kDeg);
        const auto plan = planGrasp(request(GripPointType::Vacuum, size, object));
        ASSERT_TRUE(plan);
        expectProper(*plan);
        const KDL::Frame grip = plan->grasp * kOffset;
        EXPECT_TRUE(sameVector(grip.p, {0.5, 0, 0.10}));
        EXPECT_TRUE(sameVector(grip.M.UnitZ(), {0, 0, -1}));
        EXPECT_TRUE(sameVector(grip.M.UnitX(), object.M.UnitX()));
    }
    {  // upside down: the box's -z face is on top
        const KDL::Frame object = at(0.5, 0, 0.03, 180 * kDeg);
        const auto plan = planGrasp(request(GripPointType::Vacuum, size, object));
        ASSERT_TRUE(plan);
        expectProper(*plan);
        const KDL::Frame grip = plan->grasp * kOffset;
        EXPECT_TRUE(sameVector(grip.p, {0.5, 0, 0.06}));
        EXPECT_TRUE(sameVector(grip.M.UnitZ(), {0, 0, -1}));
        EXPECT_TRUE(sameVector(grip.M.UnitX(), object.M.UnitX()));
    }
    {  // standing on its x face: x is the up axis, so the grip x follows the box's y
        const KDL::Frame object = at(0.5, 0, 0.02, 0, -90 * kDeg);
        ASSERT_TRUE(sameVector(object.M.UnitX(), {0, 0, 1}));
        const auto plan = planGrasp(request(GripPointType::Vacuum, size, object));
        ASSERT_TRUE(plan);
        expectProper(*plan);
        const KDL::Frame grip = plan->grasp * kOffset;
        EXPECT_TRUE(sameVector(grip.p, {0.5, 0, 0.04}));
        EXPECT_TRUE(sameVector(grip.M.UnitZ(), {0, 0, -1}));
        EXPECT_TRUE(sameVector(grip.M.UnitX(), object.M.UnitY()));
    }
}

TEST(GraspPlanner, VacuumOnASlightlyTiltedBoxFollowsItsTopFace) {
    const KDL::Frame object = at(0.5, 0.1, 0.03, 6 * kDeg, -4 * kDeg, 20 * kDeg);
    const BoxSize size{0.05, 0.07, 0.06};
    const auto plan = planGrasp(request(GripPointType::Vacuum, size, object));
    ASSERT_TRUE(plan);
    expectProper(*plan);
    const KDL::Frame grip = plan->grasp * kOffset;
    EXPECT_TRUE(sameVector(object.Inverse(grip.p), {0, 0, size.z / 2}));
    EXPECT_TRUE(sameVector(grip.M.UnitZ(), -object.M.UnitZ()));
    EXPECT_TRUE(sameVector(grip.M.UnitX(), object.M.UnitX()));
    // Approach backs off along the face normal.
    EXPECT_TRUE(
        sameFrame(plan->approach * kOffset, KDL::Frame(grip.M, grip.p + 0.05 * object.M.UnitZ())));
}

TEST(GraspPlanner, ParallelClosesAcrossTheNarrowerWidth) {
    const BoxSize size{0.04, 0.10, 0.05};
    const KDL::Frame object = at(0.5, 0.1, 0.025);
    std::string why;
    const auto plan = planGrasp(request(GripPointType::Parallel, size, object), &why);
    ASSERT_TRUE(plan) << why;
    expectProper(*plan);
    EXPECT_DOUBLE_EQ(plan->width, 0.04);

    const KDL::Frame grip = plan->grasp * kOffset;
    EXPECT_TRUE(sameVector(grip.p, object.p));                // the box's centre
    EXPECT_TRUE(parallel(grip.M.UnitY(), object.M.UnitX()));  // across the 0.04 axis
    EXPECT_NEAR(extentAlong(size, object, grip.M.UnitY()), 0.04, kTol);
    EXPECT_NEAR(grip.M.UnitZ().z(), 0, kTol);                 // horizontal approach
    EXPECT_TRUE(parallel(grip.M.UnitZ(), object.M.UnitY()));  // along the wide axis
    // The wide axis is perpendicular to base x: the approach comes from the -y side.
    EXPECT_TRUE(sameVector(grip.M.UnitZ(), {0, 1, 0}));
    EXPECT_TRUE(sameVector(grip.M.UnitX(), {0, 0, 1}));

    EXPECT_TRUE(sameFrame(plan->approach * kOffset, KDL::Frame(grip.M, {0.5, 0.05, 0.025})));
    // Retreat lifts the held box straight up.
    EXPECT_TRUE(sameFrame(plan->retreat * kOffset, KDL::Frame(grip.M, {0.5, 0.1, 0.075})));
}

TEST(GraspPlanner, ParallelOnAYawedBoxApproachesFromTheMinusXSide) {
    const BoxSize size{0.04, 0.10, 0.05};
    const KDL::Frame object = at(0.45, -0.1, 0.025, 0, 0, 30 * kDeg);
    const auto plan = planGrasp(request(GripPointType::Parallel, size, object));
    ASSERT_TRUE(plan);
    expectProper(*plan);

    const KDL::Frame grip = plan->grasp * kOffset;
    EXPECT_TRUE(sameVector(grip.p, object.p));
    EXPECT_TRUE(parallel(grip.M.UnitY(), object.M.UnitX()));
    EXPECT_NEAR(extentAlong(size, object, grip.M.UnitY()), 0.04, kTol);
    EXPECT_TRUE(parallel(grip.M.UnitZ(), object.M.UnitY()));
    EXPECT_NEAR(grip.M.UnitZ().z(), 0, kTol);
    EXPECT_GT(grip.M.UnitZ().x(), 0);  // pointing into the box from its -x side
    EXPECT_TRUE(sameVector(grip.M.UnitZ(), {std::sin(30 * kDeg), -std::cos(30 * kDeg), 0}));

    const KDL::Frame approach = plan->approach * kOffset;
    EXPECT_TRUE(sameFrame(approach, KDL::Frame(grip.M, grip.p - 0.05 * grip.M.UnitZ())));
    EXPECT_LT(approach.p.x(), grip.p.x());
    EXPECT_TRUE(
        sameFrame(plan->retreat * kOffset, KDL::Frame(grip.M, grip.p + KDL::Vector(0, 0, 0.05))));
}

TEST(GraspPlanner, ParallelPicksTheNarrowAxisWhicheverItIs) {
    const BoxSize size{0.10, 0.04, 0.05};  // narrow along the box's y this time
    const KDL::Frame object = at(0.5, 0, 0.025);
    const auto plan = planGrasp(request(GripPointType::Parallel, size, object));
    ASSERT_TRUE(plan);
    expectProper(*plan);
    EXPECT_DOUBLE_EQ(plan->width, 0.04);
    const KDL::Frame grip = plan->grasp * kOffset;
    EXPECT_TRUE(parallel(grip.M.UnitY(), {0, 1, 0}));
    EXPECT_TRUE(sameVector(grip.M.UnitZ(), {1, 0, 0}));  // from the -x side
    EXPECT_TRUE(sameVector((plan->approach * kOffset).p, {0.45, 0, 0.025}));

    // On its side (y up), the horizontal axes are x (0.10) and z (0.05).
    const KDL::Frame side = at(0.5, 0, 0.02, 90 * kDeg, 0, 10 * kDeg);
    const auto onSide = planGrasp(request(GripPointType::Parallel, size, side));
    ASSERT_TRUE(onSide);
    expectProper(*onSide);
    EXPECT_DOUBLE_EQ(onSide->width, 0.05);
    const KDL::Frame sideGrip = onSide->grasp * kOffset;
    EXPECT_TRUE(parallel(sideGrip.M.UnitY(), side.M.UnitZ()));
    EXPECT_TRUE(parallel(sideGrip.M.UnitZ(), side.M.UnitX()));
    EXPECT_GT(sideGrip.M.UnitZ().x(), 0);
    EXPECT_TRUE(sameVector(sideGrip.M.UnitX(), {0, 0, 1}));
}

// The object stays put relative to the grip point from grasp to place, and the place pose
// puts it exactly at the place position.
void expectPlacedAtPlacePosition(GripPointType type, const GraspRequest& req) {
    const auto plan = planGrasp(req);
    ASSERT_TRUE(plan);
    expectProper(*plan);
    const KDL::Frame offset = req.gripPointOffset;
    const KDL::Frame objectInGrip = (plan->grasp * offset).Inverse() * req.objectPose;
    EXPECT_TRUE(sameFrame(plan->place * offset * objectInGrip, req.placePosition));

    const KDL::Frame placeGrip = plan->place * offset;
    const KDL::Vector back =
        type == GripPointType::Vacuum ? -0.05 * placeGrip.M.UnitZ() : KDL::Vector(0, 0, 0.05);
    EXPECT_TRUE(
        sameFrame(plan->placeApproach * offset, KDL::Frame(placeGrip.M, placeGrip.p + back)));
    EXPECT_TRUE(sameFrame(plan->placeRetreat, plan->placeApproach));
}

TEST(GraspPlanner, PlaceCarriesTheObjectToThePlacePosition) {
    const KDL::Frame object = at(0.5, 0.1, 0.025, 0, 0, 30 * kDeg);
    const KDL::Frame place = at(0.1, -0.4, 0.125, 0, 0, -60 * kDeg);
    {
        SCOPED_TRACE("vacuum");
        const auto req = request(GripPointType::Vacuum, {0.04, 0.10, 0.05}, object, place);
        expectPlacedAtPlacePosition(GripPointType::Vacuum, req);
        // Level object, level place: the suction cup still points down at the place.
        const auto plan = planGrasp(req);
        ASSERT_TRUE(plan);
        const KDL::Frame grip = plan->place * kOffset;
        EXPECT_TRUE(sameVector(grip.M.UnitZ(), {0, 0, -1}));
        EXPECT_TRUE(sameVector(grip.p, {0.1, -0.4, 0.15}));  // the placed top-face centre
        EXPECT_TRUE(sameVector((plan->placeApproach * kOffset).p, {0.1, -0.4, 0.20}));
    }
    {
        SCOPED_TRACE("parallel");
        const auto req = request(GripPointType::Parallel, {0.04, 0.10, 0.05}, object, place);
        expectPlacedAtPlacePosition(GripPointType::Parallel, req);
        const auto plan = planGrasp(req);
        ASSERT_TRUE(plan);
        const KDL::Frame grip = plan->place * kOffset;
        EXPECT_TRUE(sameVector(grip.p, place.p));
        EXPECT_NEAR(grip.M.UnitZ().z(), 0, kTol);
    }
    {
        SCOPED_TRACE("tilted object, odd tool, arbitrary place orientation");
        auto req = request(GripPointType::Parallel, {0.03, 0.07, 0.09},
                           at(0.3, 0.2, 0.045, 4 * kDeg, -7 * kDeg, 123 * kDeg),
                           at(-0.2, 0.5, 0.3, 0.4, -0.2, 2.5));
        req.gripPointOffset = at(0.01, -0.02, 0.17, 0.1, 0.2, 45 * kDeg);
        expectPlacedAtPlacePosition(GripPointType::Parallel, req);
        req.type = GripPointType::Vacuum;
        expectPlacedAtPlacePosition(GripPointType::Vacuum, req);
    }
}

// A run cut short left the object held, a little askew and lifted (not as planGrasp would take
// it): the rest of the run keeps it as it is held, lifts it straight up and puts it at its place.
TEST(GraspPlanner, CarryingOnKeepsTheObjectAsItIsHeldAndPutsItAtItsPlace) {
    const KDL::Frame place = at(0.1, -0.4, 0.125, 0, 0, -60 * kDeg);
    for (const auto type : {GripPointType::Parallel, GripPointType::Vacuum}) {
        SCOPED_TRACE(type == GripPointType::Parallel ? "parallel" : "vacuum");
        // Taken from its start by the plan, held a little askew, and lifted a little askew.
        const KDL::Frame start = at(0.5, 0.1, 0.025, 0, 0, 30 * kDeg);
        const auto first = planGrasp(request(type, {0.04, 0.10, 0.05}, start, place));
        ASSERT_TRUE(first);
        const KDL::Frame inFlange =
            first->grasp.Inverse() * start * at(0.003, -0.002, 0.001, 0, 0, 0.05);
        const KDL::Frame flange = first->retreat * at(0.01, 0.02, 0.03, 0.01, -0.02, 0.03);
        const KDL::Frame held = flange * inFlange;
        auto req = request(type, {0.04, 0.10, 0.05}, held, place);
        const GraspPlan plan = planCarryOn(flange, req);
        expectProper(plan);
        EXPECT_TRUE(sameVector(plan.grasp.p, flange.p));
        EXPECT_TRUE(sameVector(plan.retreat.p, flange.p + KDL::Vector(0, 0, 0.05)));
        EXPECT_TRUE(sameVector(plan.retreat.M.UnitX(), flange.M.UnitX()));
        // The object, carried as it is held, ends at its place.
        const KDL::Frame placed = plan.place * (flange.Inverse() * held);
        EXPECT_TRUE(sameVector(placed.p, place.p));
        EXPECT_TRUE(sameVector(placed.M.UnitX(), place.M.UnitX()));
        EXPECT_TRUE(sameVector(placed.M.UnitZ(), place.M.UnitZ()));
        EXPECT_GT(plan.placeApproach.p.z(), plan.place.p.z() - kTol);
        EXPECT_EQ(plan.placeRetreat, plan.placeApproach);
    }
}

TEST(GraspPlanner, FlangePosesApplyTheGripPointOffset) {
    for (GripPointType type : {GripPointType::Vacuum, GripPointType::Parallel}) {
        auto req = request(type, {0.05, 0.08, 0.04}, at(0.4, 0.3, 0.02, 0, 0, -50 * kDeg));
        req.gripPointOffset = KDL::Frame::Identity();
        const auto atGrip = planGrasp(req);  // flange poses are the grip point poses
        const KDL::Frame offset = at(0.02, 0.01, 0.16, 0.3, -0.1, 1.0);
        req.gripPointOffset = offset;
        const auto withTool = planGrasp(req);
        ASSERT_TRUE(atGrip);
        ASSERT_TRUE(withTool);
        expectProper(*withTool);
        const auto grips = steps(*atGrip);
        const auto flanges = steps(*withTool);
        ASSERT_EQ(grips.size(), flanges.size());
        for (std::size_t i = 0; i < grips.size(); ++i) {
            EXPECT_TRUE(sameFrame(flanges[i].second * offset, grips[i].second)) << flanges[i].first;
        }
    }
}

TEST(GraspPlanner, ApproachDistanceIsAParameter) {
    auto req = request(GripPointType::Vacuum, {0.04, 0.04, 0.04}, at(0.5, 0, 0.02));
    req.approachDistance = 0.12;
    auto plan = planGrasp(req);
    ASSERT_TRUE(plan);
    EXPECT_TRUE(sameVector((plan->approach * kOffset).p, {0.5, 0, 0.16}));
    req.approachDistance = 0;
    plan = planGrasp(req);
    ASSERT_TRUE(plan);
    EXPECT_TRUE(sameFrame(plan->approach, plan->grasp));
    EXPECT_TRUE(sameFrame(plan->placeApproach, plan->place));
    EXPECT_EQ(GraspRequest{}.approachDistance, 0.05);
}

TEST(GraspPlanner, StepsNameThePosesInOrder) {
    const auto plan =
        planGrasp(request(GripPointType::Vacuum, {0.04, 0.04, 0.04}, at(0.5, 0, 0.02)));
    ASSERT_TRUE(plan);
    const auto s = steps(*plan);
    ASSERT_EQ(s.size(), 6u);
    const char* names[] = {"approach",       "grasp", "retreat",
                           "place-approach", "place", "place-retreat"};
    const KDL::Frame* poses[] = {&plan->approach,      &plan->grasp, &plan->retreat,
                                 &plan->placeApproach, &plan->place, &plan->placeRetreat};
    for (std::size_t i = 0; i < s.size(); ++i) {
        EXPECT_EQ(s[i].first, names[i]);
        EXPECT_TRUE(sameFrame(s[i].second, *poses[i], 0)) << names[i];
    }
}

TEST(GraspPlanner, RefusesABoxWiderThanTheFingersOpen) {
    auto req = request(GripPointType::Parallel, {0.09, 0.10, 0.05}, at(0.5, 0, 0.025));
    req.maxOpening = 0.085;
    std::string why;
    EXPECT_FALSE(planGrasp(req, &why));
    EXPECT_NE(why.find("wide"), std::string::npos) << why;

    req.maxOpening = 0.09;  // exactly as wide as the opening: still fits
    EXPECT_TRUE(planGrasp(req));
    req.maxOpening = 0;  // unlimited
    const auto plan = planGrasp(req);
    ASSERT_TRUE(plan);
    EXPECT_DOUBLE_EQ(plan->width, 0.09);
    // The opening does not matter to a suction cup.
    req.type = GripPointType::Vacuum;
    req.maxOpening = 0.01;
    EXPECT_TRUE(planGrasp(req));
}

TEST(GraspPlanner, RefusesATiltedBox) {
    const BoxSize size{0.04, 0.10, 0.05};
    for (const KDL::Frame& pose :
         {at(0.5, 0, 0.05, 15 * kDeg), at(0.5, 0, 0.05, 0, 45 * kDeg),
          at(0.5, 0, 0.05, 30 * kDeg, 30 * kDeg, 10 * kDeg), at(0.5, 0, 0.05, 0, 10.5 * kDeg)}) {
        for (GripPointType type : {GripPointType::Vacuum, GripPointType::Parallel}) {
            std::string why;
            EXPECT_FALSE(planGrasp(request(type, size, pose), &why));
            EXPECT_NE(why.find("tilted"), std::string::npos) << why;
        }
    }
    // Within 10 degrees of a face is fine, whichever face.
    for (const KDL::Frame& pose : {at(0.5, 0, 0.05, 9.9 * kDeg), at(0.5, 0, 0.05, 0, -9.9 * kDeg),
                                   at(0.5, 0, 0.05, 85 * kDeg, 0, 40 * kDeg)}) {
        for (GripPointType type : {GripPointType::Vacuum, GripPointType::Parallel}) {
            const auto plan = planGrasp(request(type, size, pose));
            ASSERT_TRUE(plan);
            expectProper(*plan);
        }
    }
}

TEST(GraspPlanner, RefusesBadEdges) {
    const double nan = std::numeric_limits<double>::quiet_NaN();
    const double inf = std::numeric_limits<double>::infinity();
    for (const BoxSize& size :
         {BoxSize{0, 0.1, 0.1}, BoxSize{0.1, -0.01, 0.1}, BoxSize{0.1, 0.1, 0},
          BoxSize{nan, 0.1, 0.1}, BoxSize{0.1, inf, 0.1}}) {
        for (GripPointType type : {GripPointType::Vacuum, GripPointType::Parallel}) {
            std::string why;
            EXPECT_FALSE(planGrasp(request(type, size, at(0.5, 0, 0.05)), &why));
            EXPECT_NE(why.find("positive"), std::string::npos) << why;
        }
    }
}

TEST(GraspPlanner, RefusesOtherBadInput) {
    const auto good = request(GripPointType::Parallel, {0.04, 0.10, 0.05}, at(0.5, 0, 0.025));
    ASSERT_TRUE(planGrasp(good));
    std::string why;

    auto req = good;
    req.type = GripPointType::MultiFinger;
    EXPECT_FALSE(planGrasp(req, &why));
    EXPECT_FALSE(why.empty());

    req = good;
    req.approachDistance = -0.01;
    why.clear();
    EXPECT_FALSE(planGrasp(req, &why));
    EXPECT_NE(why.find("approach"), std::string::npos) << why;

    req = good;
    req.maxOpening = -1;
    why.clear();
    EXPECT_FALSE(planGrasp(req, &why));
    EXPECT_NE(why.find("opening"), std::string::npos) << why;

    req = good;
    req.objectPose.p.x(std::numeric_limits<double>::quiet_NaN());
    why.clear();
    EXPECT_FALSE(planGrasp(req, &why));
    EXPECT_NE(why.find("object pose"), std::string::npos) << why;

    req = good;  // a mirror image, not a rotation
    req.placePosition.M =
        KDL::Rotation(KDL::Vector(1, 0, 0), KDL::Vector(0, -1, 0), KDL::Vector(0, 0, 1));
    why.clear();
    EXPECT_FALSE(planGrasp(req, &why));
    EXPECT_NE(why.find("place position"), std::string::npos) << why;

    req = good;  // scaled, not orthonormal
    req.gripPointOffset.M =
        KDL::Rotation(KDL::Vector(2, 0, 0), KDL::Vector(0, 1, 0), KDL::Vector(0, 0, 1));
    why.clear();
    EXPECT_FALSE(planGrasp(req, &why));
    EXPECT_NE(why.find("grip point offset"), std::string::npos) << why;

    EXPECT_FALSE(planGrasp(req));  // no reason wanted: still refused, nothing written
}

}  // namespace
}  // namespace skillcell::devices::pickplace::grasp_planner_test
