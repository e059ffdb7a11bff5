#include "devices/robotiq/robotiq_registers.hpp"

#include <algorithm>
#include <cmath>

namespace skillcell::devices::robotiq {
namespace {

std::uint16_t pack(std::uint8_t high, std::uint8_t low) {
    return static_cast<std::uint16_t>((high << 8) | low);
}
std::uint8_t high(std::uint16_t r) {
    return static_cast<std::uint8_t>(r >> 8);
}
std::uint8_t low(std::uint16_t r) {
    return static_cast<std::uint8_t>(r & 0xFF);
}
bool bit(std::uint8_t byte, int n) {
    return ((byte >> n) & 1U) != 0;
}

std::uint8_t scale(double value, double lo, double hi) {
    const double f = std::clamp((value - lo) / (hi - lo), 0.0, 1.0);
    return static_cast<std::uint8_t>(std::lround(f * 255));
}

}  // namespace

Registers encode(const Command& c) {
    const auto action = static_cast<std::uint8_t>((c.activate ? 1U : 0U) | (c.go ? 1U << 3 : 0U) |
                                                  (c.autoRelease ? 1U << 4 : 0U) |
                                                  (c.autoReleaseOpen ? 1U << 5 : 0U));
    return {pack(action, 0), pack(0, c.position), pack(c.speed, c.force)};
}

Command decodeCommand(const Registers& r) {
    const std::uint8_t action = high(r[0]);
    Command c;
    c.activate = bit(action, 0);
    c.go = bit(action, 3);
    c.autoRelease = bit(action, 4);
    c.autoReleaseOpen = bit(action, 5);
    c.position = low(r[1]);
    c.speed = high(r[2]);
    c.force = low(r[2]);
    return c;
}

Registers encode(const Status& s) {
    const auto status = static_cast<std::uint8_t>(
        (s.activated ? 1U : 0U) | (s.going ? 1U << 3 : 0U) |
        (static_cast<unsigned>(s.activation) << 4) | (static_cast<unsigned>(s.object) << 6));
    return {pack(status, 0), pack(static_cast<std::uint8_t>(s.fault), s.requestEcho),
            pack(s.position, s.current)};
}

Status decodeStatus(const Registers& r) {
    const std::uint8_t status = high(r[0]);
    Status s;
    s.activated = bit(status, 0);
    s.going = bit(status, 3);
    s.activation = static_cast<ActivationStatus>((status >> 4) & 0x3U);
    s.object = static_cast<ObjectStatus>((status >> 6) & 0x3U);
    s.fault = static_cast<Fault>(high(r[1]) & 0x0FU);
    s.requestEcho = low(r[1]);
    s.position = high(r[2]);
    s.current = low(r[2]);
    return s;
}

double widthOf(std::uint8_t position) {
    return kStroke * (1.0 - position / 255.0);
}
std::uint8_t positionFor(double width) {
    return static_cast<std::uint8_t>(255 - scale(width, 0, kStroke));
}
double speedOf(std::uint8_t speed) {
    return kMinSpeed + (kMaxSpeed - kMinSpeed) * speed / 255.0;
}
std::uint8_t speedFor(double metresPerSecond) {
    return scale(metresPerSecond, kMinSpeed, kMaxSpeed);
}
double forceOf(std::uint8_t force) {
    return kMinForce + (kMaxForce - kMinForce) * force / 255.0;
}
std::uint8_t forceFor(double newtons) {
    return scale(newtons, kMinForce, kMaxForce);
}

}  // namespace skillcell::devices::robotiq
