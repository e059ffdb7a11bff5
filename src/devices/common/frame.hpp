#pragma once
// Poses of the devices layer: KDL frames (small copyable values with tolerance-based
// comparison) and their OPC UA form, the 3DFrame structure (namespace 0, i=18814) that the
// skill models use for TargetPosition, ToolFrame, GripPointOffset and PlacePosition.
//
// Orientation convention: A, B, C are rotations about the fixed X, Y and Z axes applied in
// that order, i.e. R = Rz(C) * Ry(B) * Rx(A) (KDL's RPY(roll=A, pitch=B, yaw=C)), as in
// OPC 40010 (Robotics) 3DOrientation. Positions are metres, angles radians.
#include <kdl/frames.hpp>
#include <optional>
#include <string>
#include <string_view>

#include "ua/types/result.hpp"
#include "ua/types/variant.hpp"

namespace skillcell::devices {

/// The six numbers of a 3DFrame.
struct Pose6 {
    double x = 0, y = 0, z = 0, a = 0, b = 0, c = 0;
    friend bool operator==(const Pose6&, const Pose6&) = default;
};

[[nodiscard]] KDL::Frame toFrame(const Pose6& pose);
[[nodiscard]] Pose6 toPose6(const KDL::Frame& frame);

/// A 3DFrame value: an ExtensionObject with the structure's Default Binary encoding
/// (CartesianCoordinates X, Y, Z then Orientation A, B, C, six Doubles).
[[nodiscard]] ua::Variant frameToVariant(const KDL::Frame& frame);
/// The frame in a 3DFrame value: BadTypeMismatch for anything else (another structure, a
/// body of the wrong size), BadOutOfRange for a NaN or infinite number.
[[nodiscard]] ua::Result<KDL::Frame> frameFromVariant(const ua::Variant& value);

/// "x,y,z" or "x,y,z,a,b,c" (command lines, scene descriptions); nullopt if malformed.
[[nodiscard]] std::optional<Pose6> parsePose6(std::string_view text);
/// "(x, y, z | a, b, c)" with millimetre precision, for messages and logs.
[[nodiscard]] std::string describe(const Pose6& pose);
[[nodiscard]] std::string describe(const KDL::Frame& frame);

/// True when both frames agree within `positionTolerance` metres and `angleTolerance`
/// radians (the angle of the relative rotation).
[[nodiscard]] bool near(const KDL::Frame& a, const KDL::Frame& b, double positionTolerance,
                        double angleTolerance);

/// True when every element of the position and the rotation matrix is finite.
[[nodiscard]] bool isFinite(const KDL::Frame& frame);

}  // namespace skillcell::devices
