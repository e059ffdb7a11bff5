#pragma once
// MonitoredItem service set (OPC 10000-4, 5.12): CreateMonitoredItems,
// ModifyMonitoredItems, SetMonitoringMode, DeleteMonitoredItems.
#include "ua/server/service_table.hpp"
#include "ua/server/subscriptions/subscription_engine.hpp"

namespace skillcell::ua {

void registerMonitoredItemServices(ServiceTable& table, ServerSubscriptionEngine& engine);

}  // namespace skillcell::ua
