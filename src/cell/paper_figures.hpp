#pragma once
// The paper's detection times (section VIII-C: from a component's start until the others
// have its skills, averaged over 5 runs), by the component that plays each part here: said
// once, for the demo's table and the dashboard's.
#include <string_view>

namespace skillcell::cell {

struct PaperDetection {
    std::string_view label;  // as the tables name it: "UR5", "Robotiq adapter"
    double ms = 0;           // 0: the paper measured none (a gripper it did not have)
};

/// The part of the component announcing `applicationUri` (its kind's URI, or that with
/// ":<name>" for a second one of a kind); nothing for a component the paper does not have.
[[nodiscard]] const PaperDetection* paperDetection(std::string_view applicationUri);

}  // namespace skillcell::cell
