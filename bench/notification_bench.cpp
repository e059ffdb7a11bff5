// skillcell_bench_notifications: how many data change notifications one server delivers to
// one client per second, and how long a value change takes to reach the client's callback.
//
//   skillcell_bench_notifications [--count N] [--seconds S] [--no-node]
//
// Sequentially, in one run, with our Server in this process (its own io_context thread) and
// our coroutine Client on an io_context driven by the main thread:
//   1. throughput: kItems Int64 variables, one monitored item each (queue kQueueSize,
//      discardOldest), one subscription with publishing interval 0 (revised to the server's
//      fastest). A producer on the server's thread calls AddressSpace::setValue on every
//      variable in turn, one pass per posted handler (so that the server's own work runs in
//      between), for S seconds, in two modes:
//        free-running:  as fast as the server thread goes; what the item queues cannot hold
//                       is discarded (oldest first) and counted as dropped;
//        paced:         a variable changes only while its item queue has room (the producer
//                       looks at the server's queue; when all are full it waits for the
//                       subscription's next publishing cycle): nothing is dropped, so the
//                       rate is what the pipeline sustains without loss.
//      The values count up per variable, so the client finds every dropped value as a gap.
//   2. latency: one Int64 variable set every kLatencyPeriod by a timer on the server thread
//      to steady_clock::now() (same process, same clock); the client's callback takes
//      now - value. N samples after a warm-up, with the server's default limits (fastest
//      publishing interval 20 ms) and with ServerLimits::minPublishingIntervalMs lowered to
//      1 ms, to show that the publishing interval is what bounds the latency.
//   3. write -> notification round trip (a different quantity): the client writes
//      Demo.Double and waits for the data change notification carrying the written value;
//      against our server and, unless --no-node, against node-opcua's server
//      (tests/interop/server.js, our client).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <filesystem>
#include <functional>
#include <future>
#include <iostream>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <system_error>
#include <thread>
#include <vector>

#include <spdlog/spdlog.h>

#include <asio/co_spawn.hpp>
#include <asio/detached.hpp>
#include <asio/io_context.hpp>
#include <asio/post.hpp>
#include <asio/redirect_error.hpp>
#include <asio/steady_timer.hpp>
#include <asio/use_awaitable.hpp>

#include "apps/demo_nodes.hpp"
#include "common/command_line.hpp"
#include "latency_stats.hpp"
#include "node_peer.hpp"
#include "running_server.hpp"
#include "ua/client/client.hpp"
#include "ua/client/subscription.hpp"
#include "ua/server/server.hpp"

#ifndef SKILLCELL_INTEROP_DIR
#error "SKILLCELL_INTEROP_DIR must name tests/interop"
#endif

namespace {

using namespace skillcell;
using namespace std::chrono_literals;
using Clock = std::chrono::steady_clock;

constexpr std::size_t kItems = 100;           // throughput: variables / monitored items
constexpr std::uint32_t kQueueSize = 100;     // throughput: item queue size
constexpr std::uint32_t kLatencyQueue = 100;  // latency: holds > one interval of changes
constexpr auto kLatencyPeriod = 1037us;       // latency: one change per period, not a divisor
                                              // of publishing intervals (no phase lock)
constexpr std::size_t kLatencyWarmup = 50;
constexpr std::size_t kMaxWriteSamples = 300;  // write round trips: one interval each
/// The Int64 data type (i=8); namespace 0 has no named constant for it here.
constexpr std::uint32_t kInt64DataType = 8;
/// DataValue status info bits: InfoType DataValue + Overflow (OPC 10000-4, 7.39.1).
constexpr std::uint32_t kOverflowBits = 0x0480;

struct Options {
    std::size_t count = 5'000;  // latency samples
    double seconds = 2.0;       // per throughput mode
    bool node = true;
};

using bench::Samples;
using bench::summarize;
using Stats = bench::LatencyStats;

double seconds(Clock::duration d) {
    return std::chrono::duration<double>(d).count();
}

/// Our Server on loopback, port 0, on its own io_context thread; the producers post work to
/// its io_context.
using ServerThread = test::RunningServer;

ua::ServerConfig serverConfig(double minPublishingIntervalMs) {
    ua::ServerConfig config = test::RunningServer::defaultConfig();
    config.limits.minPublishingIntervalMs = minPublishingIntervalMs;
    return config;
}

std::string benchName(std::size_t i) {
    return "Bench.V" + std::to_string(i);
}
constexpr const char* kStampName = "Bench.Stamp";

ua::NodeId benchVariable(std::uint16_t ns, std::size_t i) {
    return {ns, ua::String(benchName(i))};
}

ua::NodeId stampVariable(std::uint16_t ns) {
    return {ns, ua::String(kStampName)};
}

/// Adds the demo nodes (Demo.Double for the write round trip), kItems counters and the
/// latency stamp, all Int64 starting at 0, in the demo namespace; returns that namespace.
std::uint16_t addBenchNodes(ua::Server& s) {
    auto& as = s.addressSpace();
    if (auto st = apps::addDemoNodes(as); st.isBad()) {
        throw std::runtime_error("addDemoNodes: " + statusText(st));
    }
    const std::uint16_t ns = as.registerNamespace(apps::kDemoNamespaceUri);
    auto add = [&](const ua::NodeId& id, const std::string& name) {
        auto r = as.addVariable(ua::NodeId(ua::ns0::ObjectsFolder), id, name,
                                ua::NodeId(kInt64DataType), ua::Variant(std::int64_t{0}));
        if (!r) throw std::runtime_error("addVariable " + name + ": " + statusText(r.status()));
    };
    for (std::size_t i = 0; i < kItems; ++i) add(benchVariable(ns, i), benchName(i));
    add(stampVariable(ns), kStampName);
    return ns;
}

/// A condition a coroutine on the client's executor waits for, with a bound. Whoever makes
/// the condition true (on that executor) calls notify().
class Signal {
public:
    explicit Signal(const asio::any_io_executor& ex) : timer_(ex) {}
    void notify() { timer_.cancel(); }
    /// True once pred() holds; false if `bound` passed first.
    template <class Pred>
    asio::awaitable<bool> waitFor(Pred pred, Clock::duration bound) {
        const auto deadline = Clock::now() + bound;
        while (!pred()) {
            if (Clock::now() >= deadline) co_return false;
            timer_.expires_at(deadline);
            std::error_code ec;
            co_await timer_.async_wait(asio::redirect_error(asio::use_awaitable, ec));
        }
        co_return true;
    }

private:
    asio::steady_timer timer_;
};

/// Runs `body` as a coroutine on an io_context driven by this thread, rethrowing what it
/// throws. The Client lives in here so that it is destroyed on this thread.
template <class Body>
void runClient(Body&& body) {
    asio::io_context io{1};
    ua::Client client(io.get_executor());
    std::exception_ptr failure;
    asio::co_spawn(
        io,
        [&]() -> asio::awaitable<void> {
            try {
                co_await body(client);
                co_await client.disconnect();
            } catch (...) {
                failure = std::current_exception();
                client.abort();
            }
        },
        asio::detached);
    io.run();
    if (failure) std::rethrow_exception(failure);
}

asio::awaitable<void> connect(ua::Client& client, const std::string& url) {
    ua::ClientConfig config;
    config.requestTimeout = 10s;
    if (auto s = co_await client.connect(url, config); s.isBad()) {
        throw std::runtime_error("connect " + url + ": " + statusText(s));
    }
}

asio::awaitable<std::shared_ptr<ua::Subscription>> subscribe(ua::Client& client,
                                                             double publishingIntervalMs) {
    // Keep-alive every 10 intervals; lifetime 1000 intervals (the producer never stalls
    // the Publish requests for that long).
    ua::SubscriptionSettings settings(publishingIntervalMs, 1000, 10);
    auto sub = co_await client.createSubscription(settings);
    if (!sub) throw std::runtime_error("CreateSubscription: " + statusText(sub.status()));
    co_return *sub;
}

// --- 1. Throughput ----------------------------------------------------------------------

struct ThroughputResult {
    double publishingMs = 0;
    double samplingMs = 0;
    std::uint32_t queueSize = 0;
    std::uint64_t changed = 0;         // setValue calls
    std::uint64_t received = 0;        // notifications after the initial values
    std::uint64_t dropped = 0;         // gaps in the per-variable counters
    std::uint64_t overflowMarked = 0;  // notifications carrying the Overflow info bit
    std::uint64_t messages = 0;        // NotificationMessages with data the server sent
    Clock::duration producing{};       // first to last setValue
    Clock::duration delivering{};      // first setValue to the last notification's callback
    bool complete = false;             // every variable's last value arrived
};

/// The producer on the server's thread. Owned by the handlers it posts.
struct Producer : std::enable_shared_from_this<Producer> {
    ServerThread* server = nullptr;
    std::vector<ua::NodeId> ids;
    std::vector<ua::MonitoredItem*> items;  // paced mode: the server's items, else empty
    ua::ServerSubscription* subscription = nullptr;
    std::uint32_t queueSize = 0;
    Clock::duration duration{};
    std::function<void(std::vector<std::int64_t> finals, std::uint64_t changed, Clock::time_point,
                       Clock::time_point)>
        onDone;  // posted to the client's executor by the caller's wrapper

    std::vector<std::int64_t> values;
    std::uint64_t changed = 0;
    Clock::time_point start;
    Clock::time_point deadline;
    std::optional<asio::steady_timer> cycleTimer;

    /// `values` holds each variable's current value.
    void begin() {
        start = Clock::now();
        deadline = start + duration;
        step();
    }

    void step() {
        auto& as = server->server().addressSpace();
        bool any = false;
        for (std::size_t i = 0; i < ids.size(); ++i) {
            if (!items.empty() && items[i]->queued() >= queueSize) continue;
            if (as.setValue(ids[i], ua::Variant(++values[i])).isBad()) {
                throw std::logic_error("setValue failed");
            }
            ++changed;
            any = true;
        }
        const auto now = Clock::now();
        if (now >= deadline) {
            onDone(values, changed, start, now);
            return;
        }
        if (any || items.empty()) {
            asio::post(server->io(), [self = shared_from_this()] { self->step(); });
            return;
        }
        // Paced and every queue full: they empty at the next publishing cycle.
        if (!cycleTimer) cycleTimer.emplace(server->io());
        cycleTimer->expires_at(std::min(subscription->nextCycle(), deadline));
        cycleTimer->async_wait([self = shared_from_this()](std::error_code) { self->step(); });
    }
};

ThroughputResult runThroughput(ServerThread& server, std::uint16_t ns, bool paced,
                               double durationSeconds) {
    ThroughputResult res;
    runClient([&](ua::Client& client) -> asio::awaitable<void> {
        co_await connect(client, server.url());
        auto executor = client.executor();
        Signal signal(executor);
        auto sub = co_await subscribe(client, 0);
        res.publishingMs = sub->revisedPublishingInterval();

        std::vector<std::int64_t> last(kItems, -1);  // -1: initial value not seen yet
        std::size_t initials = 0;
        std::optional<std::vector<std::int64_t>> finals;
        Clock::time_point firstChange;
        Clock::time_point lastArrival;
        std::vector<std::uint32_t> itemIds;
        for (std::size_t i = 0; i < kItems; ++i) {
            auto onValue = [&, i](const ua::DataValue& dv) {
                const auto* v = dv.value ? dv.value->get<std::int64_t>() : nullptr;
                if (v == nullptr) return;
                if (last[i] < 0) {  // the initial value, reported when the item is created
                    last[i] = *v;
                    ++initials;
                    signal.notify();
                    return;
                }
                lastArrival = Clock::now();
                ++res.received;
                if (*v > last[i] + 1) res.dropped += static_cast<std::uint64_t>(*v - last[i] - 1);
                last[i] = *v;
                if ((dv.statusOrGood().code & kOverflowBits) == kOverflowBits) ++res.overflowMarked;
                if (finals && (*finals)[i] == *v) signal.notify();
            };
            ua::NodeId id = benchVariable(ns, i);
            auto item = co_await sub->monitorDataChange(std::move(id), ua::AttributeId::Value, 0,
                                                        kQueueSize, std::nullopt, onValue);
            if (!item)
                throw std::runtime_error("CreateMonitoredItems: " + statusText(item.status()));
            res.samplingMs = item->revisedSamplingInterval;
            res.queueSize = item->revisedQueueSize;
            itemIds.push_back(item->monitoredItemId);
        }
        if (!co_await signal.waitFor([&] { return initials == kItems; }, 10s)) {
            throw std::runtime_error("initial values did not arrive within 10 s");
        }

        // The server's next sequence number before and after: the NotificationMessages
        // with data it sent (keep-alives do not use one).
        const auto sessionId = client.sessionId();
        const auto subId = sub->id();
        auto nextSequence = [&] {
            return server.inServer([&](ua::Server& s) -> std::uint32_t {
                auto* ss = s.subscriptions().find(sessionId, subId);
                if (ss == nullptr) throw std::runtime_error("subscription not found on the server");
                return ss->nextSequenceNumber();
            });
        };
        const std::uint32_t seqBefore = nextSequence();

        auto producer = std::make_shared<Producer>();
        producer->server = &server;
        producer->queueSize = res.queueSize;
        producer->duration = std::chrono::duration_cast<Clock::duration>(
            std::chrono::duration<double>(durationSeconds));
        for (std::size_t i = 0; i < kItems; ++i) producer->ids.push_back(benchVariable(ns, i));
        producer->values = last;  // the initial values: where the counters go on from
        producer->onDone = [&, executor](std::vector<std::int64_t> values, std::uint64_t changed,
                                         Clock::time_point t0, Clock::time_point t1) {
            asio::post(executor, [&, values = std::move(values), changed, t0, t1]() mutable {
                finals = std::move(values);
                res.changed = changed;
                firstChange = t0;
                res.producing = t1 - t0;
                signal.notify();
            });
        };
        asio::post(server.io(), [&, producer, paced] {
            if (paced) {
                producer->subscription = server.server().subscriptions().find(sessionId, subId);
                for (const auto id : itemIds) {
                    producer->items.push_back(producer->subscription->item(id));
                }
            }
            producer->begin();
        });

        auto allArrived = [&] {
            if (!finals) return false;
            for (std::size_t i = 0; i < kItems; ++i) {
                if (last[i] != (*finals)[i]) return false;
            }
            return true;
        };
        res.complete = co_await signal.waitFor(
            allArrived, producer->duration + std::chrono::duration_cast<Clock::duration>(30s));
        if (finals) res.delivering = lastArrival - firstChange;
        // The Publish responses still in flight were answered before the server gets here.
        const std::uint32_t seqAfter = nextSequence();
        res.messages = seqAfter - seqBefore;
        (void)co_await sub->remove();
    });
    return res;
}

// --- 2. Latency from setValue on the server to the client's callback ----------------------

struct LatencyResult {
    double publishingMs = 0;
    double minPublishingLimitMs = 0;
    std::uint32_t queueSize = 0;
    std::size_t produced = 0;
    std::size_t lost = 0;  // produced - received after the warm-up
    Samples samples;
};

/// Sets Bench.Stamp to steady_clock::now() every kLatencyPeriod on the server's thread.
struct StampProducer : std::enable_shared_from_this<StampProducer> {
    ServerThread* server = nullptr;
    ua::NodeId id;
    std::size_t remaining = 0;
    std::size_t produced = 0;
    std::function<void(std::size_t)> onDone;
    std::optional<asio::steady_timer> timer;

    void begin() {
        timer.emplace(server->io());
        timer->expires_at(Clock::now());
        tick();
    }
    void tick() {
        if (remaining == 0) {
            onDone(produced);
            return;
        }
        --remaining;
        ++produced;
        const std::int64_t stamp = Clock::now().time_since_epoch().count();
        if (server->server().addressSpace().setValue(id, ua::Variant(stamp)).isBad()) {
            throw std::logic_error("setValue failed");
        }
        timer->expires_at(timer->expiry() + kLatencyPeriod);
        timer->async_wait([self = shared_from_this()](std::error_code) { self->tick(); });
    }
};

LatencyResult runLatency(ServerThread& server, std::uint16_t ns, std::size_t count,
                         double minPublishingLimitMs) {
    LatencyResult res;
    res.minPublishingLimitMs = minPublishingLimitMs;
    runClient([&](ua::Client& client) -> asio::awaitable<void> {
        co_await connect(client, server.url());
        auto executor = client.executor();
        Signal signal(executor);
        auto sub = co_await subscribe(client, 0);
        res.publishingMs = sub->revisedPublishingInterval();

        bool initial = true;
        std::size_t arrived = 0;  // stamps after the initial value
        std::optional<std::size_t> produced;
        res.samples.reserve(count);
        auto onValue = [&](const ua::DataValue& dv) {
            const auto now = Clock::now();
            const auto* v = dv.value ? dv.value->get<std::int64_t>() : nullptr;
            if (v == nullptr) return;
            if (std::exchange(initial, false)) {
                signal.notify();
                return;
            }
            if (++arrived > kLatencyWarmup) {
                res.samples.push_back(now - Clock::time_point(Clock::duration(*v)));
            }
            if (produced && arrived == *produced) signal.notify();
        };
        ua::NodeId id = stampVariable(ns);
        auto item = co_await sub->monitorDataChange(id, ua::AttributeId::Value, 0, kLatencyQueue,
                                                    std::nullopt, onValue);
        if (!item) throw std::runtime_error("CreateMonitoredItems: " + statusText(item.status()));
        res.queueSize = item->revisedQueueSize;
        if (!co_await signal.waitFor([&] { return !initial; }, 10s)) {
            throw std::runtime_error("initial value did not arrive within 10 s");
        }

        auto producer = std::make_shared<StampProducer>();
        producer->server = &server;
        producer->id = id;
        producer->remaining = count + kLatencyWarmup;
        producer->onDone = [&, executor](std::size_t n) {
            asio::post(executor, [&, n] {
                produced = n;
                signal.notify();
            });
        };
        asio::post(server.io(), [producer] { producer->begin(); });
        const auto bound = kLatencyPeriod * (count + kLatencyWarmup) + 30s;
        (void)co_await signal.waitFor([&] { return produced && arrived >= *produced; }, bound);
        res.produced = produced.value_or(0);
        res.lost = res.produced > arrived ? res.produced - arrived : 0;
        (void)co_await sub->remove();
    });
    return res;
}

// --- 3. Write -> notification round trip -------------------------------------------------

struct WriteRoundTrip {
    double publishingMs = 0;
    double samplingMs = 0;
    std::size_t timeouts = 0;
    Samples samples;
};

/// Connects to `url`, subscribes to Demo.Double and, `n` times, writes a new value and waits
/// for the notification carrying it; the time from before the Write to that callback.
WriteRoundTrip runWriteRoundTrip(const std::string& url, std::size_t n,
                                 double publishingIntervalMs) {
    WriteRoundTrip res;
    runClient([&](ua::Client& client) -> asio::awaitable<void> {
        co_await connect(client, url);
        auto nsArray = co_await client.readValue(ua::NodeId(ua::ns0::Server_NamespaceArray));
        if (!nsArray || !nsArray->isArray()) throw std::runtime_error("cannot read NamespaceArray");
        std::uint16_t ns = 0;
        const auto& uris = nsArray->elements();
        for (std::size_t i = 0; i < uris.size(); ++i) {
            const auto* uri = std::get_if<ua::String>(&uris[i]);
            if (uri != nullptr && *uri == apps::kDemoNamespaceUri) {
                ns = static_cast<std::uint16_t>(i);
            }
        }
        if (ns == 0) throw std::runtime_error("urn:skillcell:demo not in the NamespaceArray");
        const ua::NodeId dbl(ns, ua::String("Demo.Double"));

        Signal signal(client.executor());
        auto sub = co_await subscribe(client, publishingIntervalMs);
        res.publishingMs = sub->revisedPublishingInterval();
        double lastSeen = NAN;
        Clock::time_point lastArrival;
        auto onValue = [&](const ua::DataValue& dv) {
            const auto* v = dv.value ? dv.value->get<double>() : nullptr;
            if (v == nullptr) return;
            lastSeen = *v;
            lastArrival = Clock::now();
            signal.notify();
        };
        ua::NodeId id = dbl;
        auto item = co_await sub->monitorDataChange(std::move(id), ua::AttributeId::Value, 0, 10,
                                                    std::nullopt, onValue);
        if (!item) throw std::runtime_error("CreateMonitoredItems: " + statusText(item.status()));
        res.samplingMs = item->revisedSamplingInterval;
        if (!co_await signal.waitFor([&] { return !std::isnan(lastSeen); }, 10s)) {
            throw std::runtime_error("initial value of Demo.Double did not arrive within 10 s");
        }
        // Values the variable did not hold before: above the current one.
        const double base = std::floor(lastSeen) + 1000;
        res.samples.reserve(n);
        for (std::size_t k = 1; k <= n; ++k) {
            const double value = base + double(k);
            const auto t0 = Clock::now();
            if (auto s = co_await client.writeValue(dbl, ua::Variant(value)); s.isBad()) {
                throw std::runtime_error("Write Demo.Double: " + statusText(s));
            }
            if (co_await signal.waitFor([&] { return lastSeen == value; }, 5s)) {
                res.samples.push_back(lastArrival - t0);
            } else {
                ++res.timeouts;
            }
        }
        (void)co_await sub->remove();
    });
    return res;
}

/// node-opcua's server.js; nullopt and a reason when it cannot run.
std::optional<WriteRoundTrip> runNodeWriteRoundTrip(std::size_t n, std::string& why) {
    const auto serverLog =
        std::filesystem::temp_directory_path() / "skillcell-bench-notify-node-server.log";
    std::filesystem::remove(serverLog);  // this run's log only
    auto peer = test::startNodeServer(SKILLCELL_INTEROP_DIR, {}, serverLog);
    if (!peer) {
        why = peer.error();
        return std::nullopt;
    }
    const std::string& url = peer->url;
    std::fprintf(stderr, "node-opcua: server.js at %s, %zu write round trips...\n", url.c_str(), n);
    auto r = runWriteRoundTrip(url, n, 0);
    (void)peer->server.terminate(std::chrono::seconds(5));
    return r;
}

// --- Output ------------------------------------------------------------------------------

std::string ms(double us) {
    if (std::isnan(us)) return "-";
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.2f", us / 1000.0);
    return buf;
}

void printThroughput(const char* mode, const ThroughputResult& r) {
    const double prodS = seconds(r.producing);
    const double delS = seconds(r.delivering);
    std::printf(
        "| %-12s | %11llu | %10.0f | %11llu | %9llu | %10llu | %11.0f | %9.1f | %s\n", mode,
        static_cast<unsigned long long>(r.changed), prodS > 0 ? double(r.changed) / prodS : 0.0,
        static_cast<unsigned long long>(r.received), static_cast<unsigned long long>(r.dropped),
        static_cast<unsigned long long>(r.overflowMarked),
        delS > 0 ? double(r.received) / delS : 0.0, delS > 0 ? double(r.messages) / delS : 0.0,
        r.complete ? "all final values arrived" : "INCOMPLETE: final values missing");
}

void printLatency(const char* name, const Stats& s, const std::string& setup) {
    std::printf("| %-44s | %6zu | %9s | %9s | %9s | %s\n", name, s.n, ms(s.medianUs).c_str(),
                ms(s.p99Us).c_str(), ms(s.maxUs).c_str(), setup.c_str());
}

std::string num(double v, int decimals) {
    char buf[64];
    std::snprintf(buf, sizeof buf, "%.*f", decimals, v);
    return buf;
}

int run(const Options& options) {
    spdlog::set_level(spdlog::level::warn);
    const std::size_t writeSamples =
        std::clamp<std::size_t>(options.count / 10, 10, kMaxWriteSamples);
    std::printf(
        "skillcell notification benchmark: our server and client in one process "
        "(separate threads), loopback\n");
    if (options.count < 2'000) {
        std::printf("NOTE: --count %zu is below 2000: a smoke run, not a measurement\n",
                    options.count);
    }

    std::optional<ThroughputResult> freeRun;
    std::optional<ThroughputResult> pacedRun;
    std::optional<LatencyResult> latDefault;
    std::uint16_t ns = 0;
    std::optional<WriteRoundTrip> writeOurs;
    std::optional<WriteRoundTrip> writeOurs50;
    {
        ServerThread server(serverConfig(ua::ServerLimits{}.minPublishingIntervalMs),
                            [&ns](ua::Server& s) { ns = addBenchNodes(s); });
        std::fprintf(stderr, "throughput, free-running producer (%.1f s)...\n", options.seconds);
        freeRun = runThroughput(server, ns, false, options.seconds);
        std::fprintf(stderr, "throughput, paced producer (%.1f s)...\n", options.seconds);
        pacedRun = runThroughput(server, ns, true, options.seconds);
        std::fprintf(stderr, "latency, default limits (%zu samples)...\n", options.count);
        latDefault =
            runLatency(server, ns, options.count, ua::ServerLimits{}.minPublishingIntervalMs);
        std::fprintf(stderr, "write round trips (%zu)...\n", writeSamples);
        writeOurs = runWriteRoundTrip(server.url(), writeSamples, 0);
        writeOurs50 = runWriteRoundTrip(server.url(), writeSamples, 50);
    }
    std::optional<LatencyResult> latFast;
    {
        ServerThread server(serverConfig(1), [&ns](ua::Server& s) { ns = addBenchNodes(s); });
        std::fprintf(stderr, "latency, minPublishingIntervalMs = 1 (%zu samples)...\n",
                     options.count);
        latFast = runLatency(server, ns, options.count, 1);
    }
    std::optional<WriteRoundTrip> writeNode;
    std::string nodeWhy = "skipped (--no-node)";
    if (options.node) writeNode = runNodeWriteRoundTrip(writeSamples, nodeWhy);

    // 1.
    std::printf(
        "\n1. Throughput: %zu Int64 variables, one monitored item each; requested "
        "publishing interval 0 -> revised %.1f ms,\n   sampling interval 0 -> revised "
        "%.1f ms (setValue is reported at once regardless), queue size %u "
        "(discardOldest),\n   maxNotificationsPerPublish 0 (server limit %u), "
        "%.1f s per mode\n",
        kItems, freeRun->publishingMs, freeRun->samplingMs, freeRun->queueSize,
        ua::ServerLimits{}.maxNotificationsPerPublish, options.seconds);
    std::printf("| %-12s | %11s | %10s | %11s | %9s | %10s | %11s | %9s |\n", "producer", "changed",
                "changes/s", "received", "dropped", "overflow-b", "notif/s", "Publish/s");
    std::printf(
        "|%s|%s|%s|%s|%s|%s|%s|%s|\n", std::string(14, '-').c_str(), std::string(13, '-').c_str(),
        std::string(12, '-').c_str(), std::string(13, '-').c_str(), std::string(11, '-').c_str(),
        std::string(12, '-').c_str(), std::string(13, '-').c_str(), std::string(11, '-').c_str());
    printThroughput("free-running", *freeRun);
    printThroughput("paced", *pacedRun);
    std::printf(
        "   changed: setValue calls; received: notifications at the client's callbacks;\n"
        "   dropped: values the client never saw (gaps in the per-variable counters), i.e.\n"
        "   discarded by the server's full item queues; overflow-b: notifications carrying\n"
        "   the Overflow info bit (one per discard burst, not per discarded value);\n"
        "   notif/s: received / (first setValue -> last callback); Publish/s: Publish\n"
        "   responses with data over the same span (the server's sequence numbers used).\n"
        "   paced: a variable changes only while its item queue has room, so the rate is\n"
        "   what the pipeline sustains without loss; its capacity is %zu items x %u queued\n"
        "   per publishing cycle. The paced producer refills the queues only when its\n"
        "   timer at the subscription's next cycle fires, so a Publish answered between\n"
        "   cycles (a late subscription) leaves the queues empty until then: a lower bound.\n"
        "   free-running shows the ceiling: items x queue size per cycle (and at most\n"
        "   maxNotificationsPerPublish per message), the rest is discarded.\n",
        kItems, pacedRun->queueSize);

    // 2. and 3.
    std::printf("\n2./3. Latency in milliseconds (nearest rank)\n");
    std::printf("| %-44s | %6s | %9s | %9s | %9s | %s\n", "", "n", "median", "p99", "max", "setup");
    std::printf("|%s|%s|%s|%s|%s|%s\n", std::string(46, '-').c_str(), std::string(8, '-').c_str(),
                std::string(11, '-').c_str(), std::string(11, '-').c_str(),
                std::string(11, '-').c_str(), std::string(30, '-').c_str());
    auto latSetup = [](const LatencyResult& r) {
        return "publishing " + num(r.publishingMs, 1) + " ms (revised from 0; server minimum " +
               num(r.minPublishingLimitMs, 0) + " ms)" + ", queue " + std::to_string(r.queueSize) +
               ", lost " + std::to_string(r.lost);
    };
    printLatency("setValue -> callback (default limits)", summarize(latDefault->samples),
                 latSetup(*latDefault));
    printLatency("setValue -> callback (server min 1 ms)", summarize(latFast->samples),
                 latSetup(*latFast));
    auto writeSetup = [](const WriteRoundTrip& r) {
        return "publishing " + num(r.publishingMs, 1) + " ms, sampling " + num(r.samplingMs, 1) +
               " ms (revised)" +
               (r.timeouts ? ", " + std::to_string(r.timeouts) + " TIMED OUT (5 s)" : "");
    };
    printLatency("write -> notification round trip, skillcell", summarize(writeOurs->samples),
                 "requested 0: " + writeSetup(*writeOurs));
    printLatency("write -> notification round trip, skillcell", summarize(writeOurs50->samples),
                 "requested 50: " + writeSetup(*writeOurs50));
    if (writeNode) {
        printLatency("write -> notification round trip, node-opcua", summarize(writeNode->samples),
                     "requested 0: " + writeSetup(*writeNode) + "; our client, node server.js");
    } else {
        std::printf("| %-44s | %s\n", "write -> notification round trip, node-opcua",
                    nodeWhy.c_str());
    }
    std::printf(
        "\n   setValue -> callback: the server sets an Int64 variable to steady_clock::now()\n"
        "   every %lld us on its thread; the client's callback (main thread, same process)\n"
        "   takes now - value. After %zu warm-up samples.\n"
        "   What bounds it: a change is queued in the monitored item at once but leaves only\n"
        "   with the subscription's next publishing cycle, so it waits between 0 and one\n"
        "   publishing interval (uniform for changes at random times: median ~ interval/2,\n"
        "   p99 ~ interval), plus encoding, loopback and decoding. The server revises a\n"
        "   requested 0 to ServerLimits::minPublishingIntervalMs (default %.0f ms); the\n"
        "   second row lowers that limit to 1 ms to show the bound moving with it.\n"
        "   write -> notification round trip: a different quantity, measured by the client\n"
        "   alone: Write request and response, then the wait for the next publishing cycle,\n"
        "   then the Publish response. Each write follows the notification of the previous\n"
        "   one, i.e. comes just after a publishing cycle, so it waits nearly a whole\n"
        "   interval: expect ~ one publishing interval, not half. node-opcua revises\n"
        "   publishing intervals to >= 50 ms (its minimum), so compare it with the\n"
        "   'requested 50' row of ours; the node-opcua server is another process (node),\n"
        "   ours shares this one.\n",
        static_cast<long long>(std::chrono::microseconds(kLatencyPeriod).count()), kLatencyWarmup,
        ua::ServerLimits{}.minPublishingIntervalMs);

    const bool ok = freeRun->complete && pacedRun->complete && pacedRun->dropped == 0 &&
                    latDefault->samples.size() == options.count &&
                    latFast->samples.size() == options.count && writeOurs->timeouts == 0 &&
                    writeOurs50->timeouts == 0;
    if (!ok) {
        std::printf("\nFAILED: notifications went missing where none may (see the tables)\n");
        return 1;
    }
    return 0;
}

}  // namespace

int main(int argc, char** argv) {
    Options o;
    CLI::App app{
        "Data change notifications: throughput from one server to one client, the "
        "latency from a change to the client's callback, and write -> notification "
        "round trips (also against node-opcua's server)"};
    app.add_option("--count", o.count,
                   "latency samples per latency measurement (2000 or more for real numbers); "
                   "write round trips: N/10, at most 300")
        ->check(CLI::PositiveNumber)
        ->capture_default_str();
    app.add_option("--seconds", o.seconds, "duration of each throughput measurement")
        ->check(CLI::Range(0.001, 3600.0))
        ->capture_default_str();
    app.add_flag("--no-node{false}", o.node, "skip the write round trip against node-opcua");
    if (const auto exit = skillcell::parseCommandLine(app, argc, argv)) return *exit;
    try {
        return run(o);
    } catch (const std::exception& e) {
        std::fprintf(stderr, "skillcell_bench_notifications: %s\n", e.what());
        return 1;
    }
}
