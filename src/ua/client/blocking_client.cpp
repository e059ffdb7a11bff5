#include "ua/client/blocking_client.hpp"

namespace skillcell::ua {

const std::shared_ptr<blocking_detail::CallSignal>& blocking_detail::callSignal() {
    thread_local const auto signal = std::make_shared<CallSignal>();
    return signal;
}

BlockingClient::BlockingClient()
    : client_(std::make_unique<Client>(ctx_.get_executor())),
      work_(asio::make_work_guard(ctx_)),
      thread_([this] {
          // Handlers do not throw (every coroutine catches); the loop only guards against
          // a stray exception ending the client's thread while callers still wait on it.
          for (;;) {
              try {
                  ctx_.run();
                  return;
              } catch (...) {
              }
          }
      }) {}

BlockingClient::~BlockingClient() {
    disconnect();
    // Nothing is left to wait for once the connection is gone: run() returns when the last
    // cancelled operation has completed.
    asio::post(ctx_, [&client = *client_] { client.abort(); });
    work_.reset();
    thread_.join();
}

StatusCode BlockingClient::connect(std::string endpointUrl, ClientConfig config) {
    return run([&](Client& c) { return c.connect(std::move(endpointUrl), std::move(config)); });
}

StatusCode BlockingClient::disconnect() {
    return run([](Client& c) { return c.disconnect(); });
}

bool BlockingClient::isConnected() {
    return runSync([](Client& c) { return c.isConnected(); });
}

std::pair<std::string, MessageSecurityMode> BlockingClient::security() {
    return runSync([](Client& c) { return std::pair{c.securityPolicyUri(), c.securityMode()}; });
}

std::vector<EndpointDescription> BlockingClient::serverEndpoints() {
    return runSync([](Client& c) { return c.serverEndpoints(); });
}

Result<std::vector<EndpointDescription>> BlockingClient::getEndpoints(std::string endpointUrl) {
    return run([&](Client& c) { return c.getEndpoints(std::move(endpointUrl)); });
}

Result<std::vector<ApplicationDescription>> BlockingClient::findServers(std::string endpointUrl) {
    return run([&](Client& c) { return c.findServers(std::move(endpointUrl)); });
}

Result<BrowseResponse> BlockingClient::browse(BrowseRequest req) {
    return run([&](Client& c) { return c.browse(std::move(req)); });
}

Result<BrowseResult> BlockingClient::browse(NodeId nodeId, BrowseDirection direction,
                                            NodeId referenceTypeId, bool includeSubtypes,
                                            std::uint32_t nodeClassMask) {
    return run([&](Client& c) {
        return c.browse(std::move(nodeId), direction, std::move(referenceTypeId), includeSubtypes,
                        nodeClassMask);
    });
}

Result<BrowseNextResponse> BlockingClient::browseNext(BrowseNextRequest req) {
    return run([&](Client& c) { return c.browseNext(std::move(req)); });
}

Result<BrowseResult> BlockingClient::browseNext(ByteString continuationPoint,
                                                bool releaseContinuationPoint) {
    return run([&](Client& c) {
        return c.browseNext(std::move(continuationPoint), releaseContinuationPoint);
    });
}

Result<TranslateBrowsePathsToNodeIdsResponse> BlockingClient::translateBrowsePaths(
    TranslateBrowsePathsToNodeIdsRequest req) {
    return run([&](Client& c) { return c.translateBrowsePaths(std::move(req)); });
}

Result<NodeId> BlockingClient::translateBrowsePath(NodeId start, std::vector<QualifiedName> path) {
    return run([&](Client& c) { return c.translateBrowsePath(std::move(start), std::move(path)); });
}

Result<std::vector<NodeId>> BlockingClient::registerNodes(std::vector<NodeId> nodes) {
    return run([&](Client& c) { return c.registerNodes(std::move(nodes)); });
}

StatusCode BlockingClient::unregisterNodes(std::vector<NodeId> nodes) {
    return run([&](Client& c) { return c.unregisterNodes(std::move(nodes)); });
}

Result<ReadResponse> BlockingClient::read(ReadRequest req) {
    return run([&](Client& c) { return c.read(std::move(req)); });
}

Result<DataValue> BlockingClient::readAttribute(NodeId nodeId, AttributeId attribute) {
    return run([&](Client& c) { return c.readAttribute(std::move(nodeId), attribute); });
}

Result<Variant> BlockingClient::readValue(NodeId nodeId) {
    return run([&](Client& c) { return c.readValue(std::move(nodeId)); });
}

Result<WriteResponse> BlockingClient::write(WriteRequest req) {
    return run([&](Client& c) { return c.write(std::move(req)); });
}

StatusCode BlockingClient::writeAttribute(NodeId nodeId, AttributeId attribute, DataValue value) {
    return run([&](Client& c) {
        return c.writeAttribute(std::move(nodeId), attribute, std::move(value));
    });
}

StatusCode BlockingClient::writeValue(NodeId nodeId, Variant value) {
    return run([&](Client& c) { return c.writeValue(std::move(nodeId), std::move(value)); });
}

Result<CallResponse> BlockingClient::call(CallRequest req) {
    return run([&](Client& c) { return c.call(std::move(req)); });
}

Result<std::vector<Variant>> BlockingClient::call(NodeId objectId, NodeId methodId,
                                                  std::vector<Variant> inputs) {
    return run([&](Client& c) {
        return c.call(std::move(objectId), std::move(methodId), std::move(inputs));
    });
}

Result<std::shared_ptr<Subscription>> BlockingClient::createSubscription(
    SubscriptionSettings settings, Subscription::StatusCallback onStatusChange) {
    return run(
        [&](Client& c) { return c.createSubscription(settings, std::move(onStatusChange)); });
}

Result<Subscription::MonitoredItem> BlockingClient::monitorDataChange(
    const std::shared_ptr<Subscription>& sub, NodeId nodeId, AttributeId attribute,
    double samplingInterval, std::uint32_t queueSize, std::optional<DataChangeFilter> filter,
    Subscription::DataChangeCallback callback) {
    return run([&](Client&) {
        return sub->monitorDataChange(std::move(nodeId), attribute, samplingInterval, queueSize,
                                      filter, std::move(callback));
    });
}

Result<Subscription::MonitoredItem> BlockingClient::monitorEvents(
    const std::shared_ptr<Subscription>& sub, NodeId notifier, EventFilter filter,
    Subscription::EventCallback callback, std::uint32_t queueSize) {
    return run([&](Client&) {
        return sub->monitorEvents(std::move(notifier), std::move(filter), std::move(callback),
                                  queueSize);
    });
}

Result<Subscription::MonitoredItem> BlockingClient::modifyMonitoredItem(
    const std::shared_ptr<Subscription>& sub, std::uint32_t monitoredItemId,
    double samplingInterval, std::uint32_t queueSize) {
    return run([&](Client&) {
        return sub->modifyMonitoredItem(monitoredItemId, samplingInterval, queueSize);
    });
}

Result<std::vector<StatusCode>> BlockingClient::setMonitoringMode(
    const std::shared_ptr<Subscription>& sub, std::vector<std::uint32_t> monitoredItemIds,
    MonitoringMode mode) {
    return run([&](Client&) { return sub->setMonitoringMode(std::move(monitoredItemIds), mode); });
}

Result<std::vector<StatusCode>> BlockingClient::deleteMonitoredItems(
    const std::shared_ptr<Subscription>& sub, std::vector<std::uint32_t> monitoredItemIds) {
    return run([&](Client&) { return sub->deleteMonitoredItems(std::move(monitoredItemIds)); });
}

StatusCode BlockingClient::modifySubscription(const std::shared_ptr<Subscription>& sub,
                                              SubscriptionSettings settings) {
    return run([&](Client&) { return sub->modify(settings); });
}

StatusCode BlockingClient::setPublishingMode(const std::shared_ptr<Subscription>& sub,
                                             bool enabled) {
    return run([&](Client&) { return sub->setPublishingMode(enabled); });
}

StatusCode BlockingClient::deleteSubscription(const std::shared_ptr<Subscription>& sub) {
    return run([&](Client&) { return sub->remove(); });
}

}  // namespace skillcell::ua
