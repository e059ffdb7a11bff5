#pragma once
// What a simulated parallel gripper's fingers meet and do, in terms the world model knows:
// shared by every simulated parallel-gripper model (Robotiq 2F-85, DH-Robotics AG-95).
#include <cstdint>
#include <string>

namespace skillcell::devices {

/// What lies between the fingers: an object and its width across the fingers (m).
struct ObjectBetweenFingers {
    std::string id;
    double width = 0;
};

/// Something the fingers did to an object (for the world model).
struct FingerEvent {
    enum class Kind : std::uint8_t { Grasped, Released };
    Kind kind;
    std::string objectId;
};

}  // namespace skillcell::devices
