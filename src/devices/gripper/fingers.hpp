#pragma once
// What a simulated parallel gripper's fingers meet and do, in terms the world model knows:
// shared by every simulated parallel-gripper model (Robotiq 2F-85, DH-Robotics AG-95).
#include <cstdint>
#include <optional>
#include <string>
#include <utility>

namespace skillcell::devices {

/// What lies between the fingers: an object and its width across the fingers (m).
struct ObjectBetweenFingers {
    std::string id;
    double width = 0;
};

/// What a probe of the world finds between the fingers as they start to close: an object or
/// nothing; or, while the world cannot say (it restarts), not known yet. The fingers then
/// wait, as everything does while the simulation's physics is down, and the probe is asked
/// again on the next status read.
struct Probed {
    Probed() = default;
    // Implicit: a probe that always knows returns what it found.
    Probed(std::optional<ObjectBetweenFingers> found)  // NOLINT(google-explicit-constructor)
        : object(std::move(found)) {}
    [[nodiscard]] static Probed unknown() {
        Probed p;
        p.known = false;
        return p;
    }
    std::optional<ObjectBetweenFingers> object;
    bool known = true;
};

/// Something the fingers did to an object (for the world model).
struct FingerEvent {
    enum class Kind : std::uint8_t { Grasped, Released };
    Kind kind;
    std::string objectId;
};

}  // namespace skillcell::devices
