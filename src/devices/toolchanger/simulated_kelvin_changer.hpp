#pragma once
// SimulatedKelvinChanger: a Kelvin tool changer's coupling in the simulated cell. Locking
// takes the tool of the dock the flange is at (the world model decides whether the flange
// is there and the dock holds a tool); opening leaves the tool in the dock the flange is
// at. The identification pin shows the mounted tool's coding voltage (from the tool
// table: each tool's resistor sits in the middle of its band), with converter noise.
#include <functional>
#include <mutex>
#include <random>

#include "devices/toolchanger/tool_changer_io.hpp"
#include "devices/toolchanger/tool_table.hpp"
#include "devices/world/world_link.hpp"

namespace skillcell::devices::toolchanger {

class SimulatedKelvinChanger final : public ToolChangerIo {
public:
    /// `world` and `tools` must outlive it.
    SimulatedKelvinChanger(WorldLink& world, const ToolTable& tools);

    ua::StatusCode setLockValve(bool lock) override;
    [[nodiscard]] ua::Result<bool> locked() override;
    [[nodiscard]] ua::Result<std::uint16_t> identificationCounts() override;

private:
    WorldLink& world_;
    const ToolTable& tools_;
    std::mutex mutex_;
    std::minstd_rand noise_{4711};
};

}  // namespace skillcell::devices::toolchanger
