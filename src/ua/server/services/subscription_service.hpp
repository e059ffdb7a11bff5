#pragma once
// Subscription service set (OPC 10000-4, 5.13): CreateSubscription, ModifySubscription,
// SetPublishingMode, Publish (deferred), Republish, DeleteSubscriptions.
#include "ua/server/service_table.hpp"
#include "ua/server/subscriptions/subscription_engine.hpp"

namespace skillcell::ua {

void registerSubscriptionServices(ServiceTable& table, ServerSubscriptionEngine& engine);

}  // namespace skillcell::ua
