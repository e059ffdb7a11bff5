#include "ua/server/services/monitored_item_service.hpp"

#include "ua/server/services/operations.hpp"
#include "ua/server/session.hpp"

namespace skillcell::ua {
namespace {

bool validTimestamps(TimestampsToReturn t) {
    return t == TimestampsToReturn::Source || t == TimestampsToReturn::Server ||
           t == TimestampsToReturn::Both || t == TimestampsToReturn::Neither;
}

}  // namespace

void registerMonitoredItemServices(ServiceTable& table, ServerSubscriptionEngine& engine) {
    using A = ServiceTable::Access;
    table.add<CreateMonitoredItemsRequest, CreateMonitoredItemsResponse>(
        A::ActivatedSession, [&engine](ServiceContext& ctx, const auto& req, auto& resp) {
            ServerSubscription* sub = engine.find(ctx.session->sessionId(), req.subscriptionId);
            if (sub == nullptr) return status::BadSubscriptionIdInvalid;
            if (!validTimestamps(req.timestampsToReturn))
                return status::BadTimestampsToReturnInvalid;
            return forEachOperation(limitsOf(ctx), req.itemsToCreate, resp.results,
                                    [&](const MonitoredItemCreateRequest& item) {
                                        return engine.createMonitoredItem(
                                            *sub, req.timestampsToReturn, item, ctx.now);
                                    });
        });
    table.add<ModifyMonitoredItemsRequest, ModifyMonitoredItemsResponse>(
        A::ActivatedSession, [&engine](ServiceContext& ctx, const auto& req, auto& resp) {
            ServerSubscription* sub = engine.find(ctx.session->sessionId(), req.subscriptionId);
            if (sub == nullptr) return status::BadSubscriptionIdInvalid;
            if (!validTimestamps(req.timestampsToReturn))
                return status::BadTimestampsToReturnInvalid;
            return forEachOperation(limitsOf(ctx), req.itemsToModify, resp.results,
                                    [&](const MonitoredItemModifyRequest& item) {
                                        return engine.modifyMonitoredItem(
                                            *sub, req.timestampsToReturn, item, ctx.now);
                                    });
        });
    table.add<SetMonitoringModeRequest, SetMonitoringModeResponse>(
        A::ActivatedSession, [&engine](ServiceContext& ctx, const auto& req, auto& resp) {
            ServerSubscription* sub = engine.find(ctx.session->sessionId(), req.subscriptionId);
            if (sub == nullptr) return status::BadSubscriptionIdInvalid;
            const auto m = static_cast<std::int32_t>(req.monitoringMode);
            if (m < 0 || m > 2) return status::BadMonitoringModeInvalid;
            return forEachOperation(
                limitsOf(ctx), req.monitoredItemIds, resp.results, [&](std::uint32_t id) {
                    return engine.setMonitoringMode(*sub, id, req.monitoringMode, ctx.now);
                });
        });
    table.add<DeleteMonitoredItemsRequest, DeleteMonitoredItemsResponse>(
        A::ActivatedSession, [&engine](ServiceContext& ctx, const auto& req, auto& resp) {
            ServerSubscription* sub = engine.find(ctx.session->sessionId(), req.subscriptionId);
            if (sub == nullptr) return status::BadSubscriptionIdInvalid;
            return forEachOperation(
                limitsOf(ctx), req.monitoredItemIds, resp.results,
                [&](std::uint32_t id) { return engine.deleteMonitoredItem(*sub, id); });
        });
}

}  // namespace skillcell::ua
