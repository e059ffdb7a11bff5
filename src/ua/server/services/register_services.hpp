#pragma once
// Registration of the service sets that work on the address space. Each registers typed
// handlers with Access::ActivatedSession; the address space must outlive the table.
#include "ua/address_space/address_space.hpp"
#include "ua/server/service_table.hpp"

namespace skillcell::ua {

/// Browse, BrowseNext, TranslateBrowsePathsToNodeIds, RegisterNodes, UnregisterNodes.
void registerViewServices(ServiceTable& table, AddressSpace& as);
/// Read, Write.
void registerAttributeServices(ServiceTable& table, AddressSpace& as);
/// Call.
void registerMethodServices(ServiceTable& table, AddressSpace& as);

}  // namespace skillcell::ua
