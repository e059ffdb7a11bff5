#pragma once
// The edge lengths of a box: what the world model knows of an object's shape.

namespace skillcell::devices {

/// Edge lengths of a box, metres.
struct BoxSize {
    double x = 0, y = 0, z = 0;
    friend bool operator==(const BoxSize&, const BoxSize&) = default;
};

}  // namespace skillcell::devices
