#include "ua/server/services/subscription_service.hpp"

#include "ua/server/services/operations.hpp"
#include "ua/server/session.hpp"

namespace skillcell::ua {

void registerSubscriptionServices(ServiceTable& table, ServerSubscriptionEngine& engine) {
    using A = ServiceTable::Access;
    table.add<CreateSubscriptionRequest, CreateSubscriptionResponse>(
        A::ActivatedSession, [&engine](ServiceContext& ctx, const auto& req, auto& resp) {
            auto sub = engine.createSubscription(ctx.session->sessionId(), req, ctx.now);
            if (!sub) return sub.status();
            const auto& s = (*sub)->settings();
            resp.subscriptionId = (*sub)->id();
            resp.revisedPublishingInterval = s.publishingIntervalMs;
            resp.revisedLifetimeCount = s.lifetimeCount;
            resp.revisedMaxKeepAliveCount = s.maxKeepAliveCount;
            return status::Good;
        });
    table.add<ModifySubscriptionRequest, ModifySubscriptionResponse>(
        A::ActivatedSession, [&engine](ServiceContext& ctx, const auto& req, auto& resp) {
            ServerSubscription* sub = engine.find(ctx.session->sessionId(), req.subscriptionId);
            if (sub == nullptr) return status::BadSubscriptionIdInvalid;
            const auto s = reviseSettings(
                limitsOf(ctx), req.requestedPublishingInterval, req.requestedLifetimeCount,
                req.requestedMaxKeepAliveCount, req.maxNotificationsPerPublish, req.priority);
            engine.modifySubscription(*sub, s, ctx.now);
            resp.revisedPublishingInterval = s.publishingIntervalMs;
            resp.revisedLifetimeCount = s.lifetimeCount;
            resp.revisedMaxKeepAliveCount = s.maxKeepAliveCount;
            return status::Good;
        });
    table.add<SetPublishingModeRequest, SetPublishingModeResponse>(
        A::ActivatedSession, [&engine](ServiceContext& ctx, const auto& req, auto& resp) {
            return forEachOperation(
                limitsOf(ctx), req.subscriptionIds, resp.results,
                [&](std::uint32_t id) -> StatusCode {
                    ServerSubscription* sub = engine.find(ctx.session->sessionId(), id);
                    if (sub == nullptr) return status::BadSubscriptionIdInvalid;
                    engine.setPublishingEnabled(*sub, req.publishingEnabled, ctx.now);
                    return status::Good;
                });
        });
    table.add<DeleteSubscriptionsRequest, DeleteSubscriptionsResponse>(
        A::ActivatedSession, [&engine](ServiceContext& ctx, const auto& req, auto& resp) {
            return forEachOperation(
                limitsOf(ctx), req.subscriptionIds, resp.results, [&](std::uint32_t id) {
                    return engine.deleteSubscription(ctx.session->sessionId(), id);
                });
        });
    table.add<RepublishRequest, RepublishResponse>(
        A::ActivatedSession, [&engine](ServiceContext& ctx, const auto& req, auto& resp) {
            ServerSubscription* sub = engine.find(ctx.session->sessionId(), req.subscriptionId);
            if (sub == nullptr) return status::BadSubscriptionIdInvalid;
            auto message = sub->republish(req.retransmitSequenceNumber);
            if (!message) return message.status();
            resp.notificationMessage = std::move(*message);
            return status::Good;
        });
    table.addDeferred<PublishRequest, PublishResponse>(
        A::ActivatedSession,
        [&engine](ServiceContext& ctx, const PublishRequest& req, Deferred<PublishResponse> resp) {
            engine.publish(ctx.session->sessionId(), req, std::move(resp), ctx.now);
            return status::Good;  // answered (now or later) through `resp`
        });
}

}  // namespace skillcell::ua
