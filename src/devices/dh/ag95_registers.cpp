#include "devices/dh/ag95_registers.hpp"

#include <algorithm>
#include <cmath>

namespace skillcell::devices::dh {

std::uint16_t perMilleOf(double width) {
    return static_cast<std::uint16_t>(std::clamp(std::lround(width / kStroke * 1000), 0L, 1000L));
}

double widthOf(double perMille) {
    return perMille / 1000 * kStroke;
}

std::uint16_t forcePercentOf(double newtons) {
    return static_cast<std::uint16_t>(std::clamp(std::lround(newtons / kMaximumForce * 100),
                                                 static_cast<long>(kMinimumForce), 100L));
}

std::uint16_t speedPercentOf(double metresPerSecond) {
    return static_cast<std::uint16_t>(
        std::clamp(std::lround(metresPerSecond / kMaximumSpeed * 100), 1L, 100L));
}

}  // namespace skillcell::devices::dh
