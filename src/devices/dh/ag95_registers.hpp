#pragma once
// The DH-Robotics AG-95 adaptive parallel gripper on Modbus RTU (slave 1, 115200 8N1):
// DH's basic control registers, all holding registers (function 3 reads, 6 and 16 write):
//
//   0x0100  initialise           write 1: the gripper opens fully to find its zero
//   0x0101  force                20..100 (% of the maximum grip force)
//   0x0103  position             0..1000 (per mille of the stroke, 1000 = fully open);
//                                writing it starts the motion
//   0x0104  speed                1..100 (% of the maximum finger speed)
//   0x0200  initialisation state 0 not initialised, 1 initialised, 2 initialising
//   0x0201  gripper state        0 moving, 1 at the requested position, 2 object caught,
//                                3 object dropped
//   0x0202  position now         0..1000
//
// Unlike the 2F-85 it has no "go" bit: a motion starts when the position is written and
// ends at the position or on an object; there is no stop command, so an adapter stops the
// fingers by asking for the position they are at.
#include <cstdint>

namespace skillcell::devices::dh {

inline constexpr int kSlaveId = 1;
inline constexpr int kBaudRate = 115200;

inline constexpr std::uint16_t kInitialise = 0x0100;
inline constexpr std::uint16_t kForce = 0x0101;
inline constexpr std::uint16_t kPosition = 0x0103;
inline constexpr std::uint16_t kSpeed = 0x0104;
inline constexpr std::uint16_t kInitialisationState = 0x0200;
inline constexpr std::uint16_t kGripperState = 0x0201;
inline constexpr std::uint16_t kPositionNow = 0x0202;
/// The holding registers the gripper answers: 0x0100 up to 0x0202.
inline constexpr std::uint16_t kFirstRegister = kInitialise;
inline constexpr std::uint16_t kRegisterCount = kPositionNow - kFirstRegister + 1;

enum class InitialisationState : std::uint16_t {
    NotInitialised = 0,
    Initialised = 1,
    Initialising = 2
};
enum class GripperState : std::uint16_t { Moving = 0, AtPosition = 1, Caught = 2, Dropped = 3 };

/// The AG-95's mechanics, as the simulation and the adapter both need them.
inline constexpr double kStroke = 0.095;            // m between the fingers, fully open
inline constexpr double kMaximumSpeed = 0.15;       // m/s at 100 %
inline constexpr double kMaximumForce = 160;        // N at 100 %
inline constexpr std::uint16_t kMinimumForce = 20;  // %

/// Per mille of the stroke for a width (m), clamped to 0..1000.
[[nodiscard]] std::uint16_t perMilleOf(double width);
[[nodiscard]] double widthOf(double perMille);
/// The force register for a force (N), clamped to 20..100 %.
[[nodiscard]] std::uint16_t forcePercentOf(double newtons);
/// The speed register for a finger speed (m/s), clamped to 1..100 %.
[[nodiscard]] std::uint16_t speedPercentOf(double metresPerSecond);

}  // namespace skillcell::devices::dh
