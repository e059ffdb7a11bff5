#pragma once
// BlockingClient: the Client's operations as plain blocking calls, for code that is not a
// coroutine (command-line tools, tests, scripts).
//
// It owns an io_context and the thread that runs it; each call runs the Client coroutine on
// that thread and waits for its result. Calls may come from any thread other than the
// client's own (calling from inside a Client coroutine would deadlock); overlapping calls
// from several threads are allowed and travel as concurrent requests. The destructor
// disconnects (CloseSession, CloseSecureChannel) and joins the thread.
#include <condition_variable>
#include <exception>
#include <memory>
#include <mutex>
#include <optional>
#include <thread>
#include <type_traits>
#include <utility>

#include <asio/co_spawn.hpp>
#include <asio/detached.hpp>
#include <asio/executor_work_guard.hpp>
#include <asio/io_context.hpp>
#include <asio/post.hpp>

#include "ua/client/client.hpp"

namespace skillcell::ua {

namespace blocking_detail {

/// Wakes a thread blocked in a BlockingClient call. Each calling thread has one and reuses
/// it for every call (a thread waits for one call at a time), so that a call allocates no
/// shared state. Held by shared_ptr because the client's thread may still be inside
/// notify() when the caller has already returned.
class CallSignal {
public:
    void notify() {
        {
            std::lock_guard lock(mutex_);
            done_ = true;
        }
        // After unlocking: the woken caller does not then block on the mutex again.
        cv_.notify_one();
    }
    void wait() {
        std::unique_lock lock(mutex_);
        cv_.wait(lock, [this] { return done_; });
        done_ = false;  // ready for this thread's next call
    }

private:
    std::mutex mutex_;
    std::condition_variable cv_;
    bool done_ = false;
};

/// The calling thread's CallSignal.
[[nodiscard]] const std::shared_ptr<CallSignal>& callSignal();

}  // namespace blocking_detail

class BlockingClient {
public:
    BlockingClient();
    ~BlockingClient();
    BlockingClient(const BlockingClient&) = delete;
    BlockingClient& operator=(const BlockingClient&) = delete;

    StatusCode connect(std::string endpointUrl, ClientConfig config = {});
    StatusCode disconnect();
    [[nodiscard]] bool isConnected();
    /// The server's endpoints as returned by CreateSession (a copy).
    [[nodiscard]] std::vector<EndpointDescription> serverEndpoints();
    /// The channel's security policy URI and mode (the chosen ones, with kBestSecurity).
    [[nodiscard]] std::pair<std::string, MessageSecurityMode> security();

    template <EncodableStructure Req, EncodableStructure Resp>
    Result<Resp> request(Req req) {
        return run([&req](Client& c) { return c.request<Req, Resp>(std::move(req)); });
    }

    Result<std::vector<EndpointDescription>> getEndpoints(std::string endpointUrl = {});
    Result<std::vector<ApplicationDescription>> findServers(std::string endpointUrl = {});

    Result<BrowseResponse> browse(BrowseRequest req);
    Result<BrowseResult> browse(NodeId nodeId, BrowseDirection direction = BrowseDirection::Forward,
                                NodeId referenceTypeId = NodeId(33), bool includeSubtypes = true,
                                std::uint32_t nodeClassMask = 0);
    Result<BrowseNextResponse> browseNext(BrowseNextRequest req);
    Result<BrowseResult> browseNext(ByteString continuationPoint,
                                    bool releaseContinuationPoint = false);
    Result<TranslateBrowsePathsToNodeIdsResponse> translateBrowsePaths(
        TranslateBrowsePathsToNodeIdsRequest req);
    Result<NodeId> translateBrowsePath(NodeId start, std::vector<QualifiedName> path);
    Result<std::vector<NodeId>> registerNodes(std::vector<NodeId> nodes);
    StatusCode unregisterNodes(std::vector<NodeId> nodes);

    Result<ReadResponse> read(ReadRequest req);
    Result<DataValue> readAttribute(NodeId nodeId, AttributeId attribute);
    Result<Variant> readValue(NodeId nodeId);
    Result<WriteResponse> write(WriteRequest req);
    StatusCode writeAttribute(NodeId nodeId, AttributeId attribute, DataValue value);
    StatusCode writeValue(NodeId nodeId, Variant value);

    Result<CallResponse> call(CallRequest req);
    Result<std::vector<Variant>> call(NodeId objectId, NodeId methodId,
                                      std::vector<Variant> inputs);

    // Subscriptions (see Subscription). The callbacks given here run on the client's own
    // thread, not the caller's: they must not block and must not call this BlockingClient
    // (that would deadlock); hand what they receive to another thread instead. Use a
    // Subscription only through these calls, and read its accessors only between them.
    Result<std::shared_ptr<Subscription>> createSubscription(
        SubscriptionSettings settings, Subscription::StatusCallback onStatusChange = {});
    Result<Subscription::MonitoredItem> monitorDataChange(
        const std::shared_ptr<Subscription>& sub, NodeId nodeId, AttributeId attribute,
        double samplingInterval, std::uint32_t queueSize, std::optional<DataChangeFilter> filter,
        Subscription::DataChangeCallback callback);
    Result<Subscription::MonitoredItem> monitorEvents(const std::shared_ptr<Subscription>& sub,
                                                      NodeId notifier, EventFilter filter,
                                                      Subscription::EventCallback callback,
                                                      std::uint32_t queueSize = 100);
    Result<Subscription::MonitoredItem> modifyMonitoredItem(
        const std::shared_ptr<Subscription>& sub, std::uint32_t monitoredItemId,
        double samplingInterval, std::uint32_t queueSize);
    Result<std::vector<StatusCode>> setMonitoringMode(const std::shared_ptr<Subscription>& sub,
                                                      std::vector<std::uint32_t> monitoredItemIds,
                                                      MonitoringMode mode);
    Result<std::vector<StatusCode>> deleteMonitoredItems(
        const std::shared_ptr<Subscription>& sub, std::vector<std::uint32_t> monitoredItemIds);
    StatusCode modifySubscription(const std::shared_ptr<Subscription>& sub,
                                  SubscriptionSettings settings);
    StatusCode setPublishingMode(const std::shared_ptr<Subscription>& sub, bool enabled);
    StatusCode deleteSubscription(const std::shared_ptr<Subscription>& sub);

    /// Runs `start(client)` (which returns an awaitable) on the client's thread and waits for
    /// its result; the building block of every call above, and open for custom sequences.
    template <class Start>
    auto run(Start&& start) {
        using Awaitable = std::invoke_result_t<Start&, Client&>;
        using T = typename Awaitable::value_type;
        static_assert(std::is_constructible_v<T, StatusCode>, "a Result<...> or a StatusCode");
        // Written by the client's thread before it signals, read here after the wait.
        std::optional<T> result;
        const auto& signal = blocking_detail::callSignal();
        asio::co_spawn(
            ctx_,
            [&start, &result, &client = *client_, signal = signal]() -> asio::awaitable<void> {
                try {
                    result.emplace(co_await start(client));
                } catch (...) {
                    // Client coroutines do not throw; this covers a throwing `start`.
                    result.emplace(T(status::BadInternalError));
                }
                signal->notify();
            },
            asio::detached);
        signal->wait();
        return std::move(*result);
    }

private:
    /// Runs a plain (non-coroutine) function of the client on its thread.
    template <class F>
    auto runSync(F&& f) {
        using T = std::invoke_result_t<F&, Client&>;
        std::optional<T> result;
        const auto& signal = blocking_detail::callSignal();
        asio::post(ctx_, [&f, &result, &client = *client_, signal = signal] {
            result.emplace(f(client));
            signal->notify();
        });
        signal->wait();
        return std::move(*result);
    }

    // Concurrency hint 1: only the client's own thread runs it.
    asio::io_context ctx_{1};
    std::unique_ptr<Client> client_;
    asio::executor_work_guard<asio::io_context::executor_type> work_;
    std::jthread thread_;
};

}  // namespace skillcell::ua
