#pragma once
// The Robotiq 2F-85's Modbus RTU register map (Robotiq 2F-85 & 2F-140 instruction
// manual, section 4: control): the robot writes three "output" registers from 0x03E8
// (function 16) and reads three "input" registers from 0x07D0 (function 4). Each 16-bit
// register carries two byte-sized fields, the first in its high byte. Default slave id 9,
// 115200 baud, 8N1.
//
//   0x03E8  ACTION REQUEST (rACT bit 0, rGTO bit 3, rATR bit 4, rARD bit 5) | reserved
//   0x03E9  reserved | POSITION REQUEST rPR (0 open .. 255 closed)
//   0x03EA  SPEED rSP (0 slowest .. 255 fastest) | FORCE rFR (0 lowest .. 255 highest)
//   0x07D0  GRIPPER STATUS (gACT bit 0, gGTO bit 3, gSTA bits 4-5, gOBJ bits 6-7) | reserved
//   0x07D1  FAULT STATUS gFLT (low nibble; kFLT high nibble) | POSITION REQUEST ECHO gPR
//   0x07D2  POSITION gPO | CURRENT gCU (x 10 mA)
#include <array>
#include <cstdint>

namespace skillcell::devices::robotiq {

inline constexpr int kSlaveId = 9;
inline constexpr int kBaudRate = 115200;
inline constexpr std::uint16_t kCommandAddress = 0x03E8;
inline constexpr std::uint16_t kStatusAddress = 0x07D0;
inline constexpr int kRegisterCount = 3;

/// gSTA: activation status.
enum class ActivationStatus : std::uint8_t { Reset = 0, Activating = 1, Active = 3 };
/// gOBJ: object detection status (valid while gGTO = 1).
enum class ObjectStatus : std::uint8_t {
    Moving = 0,              // fingers moving towards the requested position, no object
    ContactOpening = 1,      // fingers stopped by contact while opening
    ContactClosing = 2,      // fingers stopped by contact while closing: an object is held
    AtRequestedPosition = 3  // fingers at the requested position: no object met
};
/// gFLT values the simulation produces.
enum class Fault : std::uint8_t {
    None = 0x00,
    ActionDelayed = 0x05,       // activation must complete before the action
    ActivationBitNotSet = 0x07  // rGTO without rACT
};

/// What the robot writes.
struct Command {
    bool activate = false;         // rACT
    bool go = false;               // rGTO
    bool autoRelease = false;      // rATR
    bool autoReleaseOpen = false;  // rARD
    std::uint8_t position = 0;     // rPR
    std::uint8_t speed = 0;        // rSP
    std::uint8_t force = 0;        // rFR
    friend bool operator==(const Command&, const Command&) = default;
};

/// What the gripper reports.
struct Status {
    bool activated = false;  // gACT
    bool going = false;      // gGTO
    ActivationStatus activation = ActivationStatus::Reset;
    ObjectStatus object = ObjectStatus::Moving;
    Fault fault = Fault::None;
    std::uint8_t requestEcho = 0;  // gPR
    std::uint8_t position = 0;     // gPO
    std::uint8_t current = 0;      // gCU
    friend bool operator==(const Status&, const Status&) = default;
};

using Registers = std::array<std::uint16_t, kRegisterCount>;

[[nodiscard]] Registers encode(const Command& c);
[[nodiscard]] Command decodeCommand(const Registers& r);
[[nodiscard]] Registers encode(const Status& s);
/// gFLT values other than those above are kept as their number.
[[nodiscard]] Status decodeStatus(const Registers& r);

// The 2F-85's mechanics: stroke 85 mm; 20-150 mm/s; 20-235 N. Position 0 is fully open
// and 255 fully closed; the simulation maps positions linearly onto the stroke.
inline constexpr double kStroke = 0.085;  // m
inline constexpr double kMinSpeed = 0.020;
inline constexpr double kMaxSpeed = 0.150;  // m/s
inline constexpr double kMinForce = 20;
inline constexpr double kMaxForce = 235;  // N

[[nodiscard]] double widthOf(std::uint8_t position);
/// The position whose width is nearest `width` (clamped to the stroke).
[[nodiscard]] std::uint8_t positionFor(double width);
[[nodiscard]] double speedOf(std::uint8_t speed);
[[nodiscard]] std::uint8_t speedFor(double metresPerSecond);
[[nodiscard]] double forceOf(std::uint8_t force);
[[nodiscard]] std::uint8_t forceFor(double newtons);

}  // namespace skillcell::devices::robotiq
