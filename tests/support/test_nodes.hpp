#pragma once
// Nodes the security tests call and write, added to a test server's address space.
#include "ua/address_space/address_space.hpp"

namespace skillcell::test {

/// A method of Objects (i=85) that returns twice its Double argument: a call that needs the
/// Operator role and proves the round trip.
[[nodiscard]] ua::StatusCode addDoublingMethod(ua::AddressSpace& as, const ua::NodeId& id);

}  // namespace skillcell::test
