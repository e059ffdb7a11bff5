// skillcell_bench_roundtrip: request/response latency of one Read and one Call, compared
// with the floor (raw TCP ping-pong with the same message sizes) and with node-opcua.
//
//   skillcell_bench_roundtrip [--count N] [--no-node]
//
// Sequentially, in one run:
//   1. raw TCP ping-pong on loopback, sized like the real ReadRequest/ReadResponse frames;
//   2. our Server in this process (its own io_context thread) with
//      a. the coroutine Client on an io_context driven by the main thread,
//      b. the BlockingClient (one thread hop per call);
//      N sequential Reads of Demo.Double, then N sequential Calls of Demo.Add(2, 3.5);
//   3. node-opcua's client against node-opcua's server (tests/interop/bench_client.js and
//      server.js), unless --no-node.
// Prints a table of medians and 99th percentiles in microseconds, the ratios, and whether
// the goals (ours <= 2x raw TCP, >= 10x faster than node-opcua) are met.
#include <algorithm>
#include <charconv>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <filesystem>
#include <iostream>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include <spdlog/spdlog.h>

#include <asio/co_spawn.hpp>
#include <asio/detached.hpp>
#include <asio/io_context.hpp>

#include "apps/demo_nodes.hpp"
#include "common/command_line.hpp"
#include "latency_stats.hpp"
#include "node_peer.hpp"
#include "process/child_process.hpp"
#include "running_server.hpp"
#include "tcp_ping_pong.hpp"
#include "ua/client/blocking_client.hpp"
#include "ua/client/client.hpp"

#ifndef SKILLCELL_INTEROP_DIR
#error "SKILLCELL_INTEROP_DIR must name tests/interop"
#endif

namespace {

using namespace skillcell;
using namespace std::chrono_literals;
using Clock = std::chrono::steady_clock;

constexpr std::size_t kWarmup = 200;  // as bench_client.js
/// MSG frame overhead with SecurityPolicy None: message header (8), SecureChannelId (4),
/// TokenId (4), sequence header (8).
constexpr std::size_t kMsgFrameOverhead = 24;

struct Options {
    std::size_t count = 10'000;
    bool node = true;
};

using bench::Samples;
using bench::summarize;
using Stats = bench::LatencyStats;

struct Row {
    std::string name;
    Stats read;
    Stats call;
    std::string note;
};

/// The Read and Call every client measurement repeats.
struct DemoIds {
    ua::NodeId demo;
    ua::NodeId add;
    ua::NodeId dbl;
};

DemoIds demoIds(std::uint16_t ns) {
    return {ua::NodeId(ns, ua::String("Demo")), ua::NodeId(ns, ua::String("Demo.Add")),
            ua::NodeId(ns, ua::String("Demo.Double"))};
}

ua::ReadRequest demoRead(const DemoIds& ids) {
    ua::ReadRequest req;
    ua::ReadValueId rv;
    rv.nodeId = ids.dbl;
    req.nodesToRead.push_back(std::move(rv));
    return req;
}

void checkRead(const ua::Result<ua::ReadResponse>& r) {
    if (!r || r->results.size() != 1 || !r->results[0].value ||
        r->results[0].value->get<double>() == nullptr) {
        throw std::runtime_error("Read Demo.Double failed: " +
                                 std::string(ua::statusName(r.status())));
    }
}

void checkCall(const ua::Result<std::vector<ua::Variant>>& r) {
    if (!r || r->size() != 1 || (*r)[0].get<double>() == nullptr || *(*r)[0].get<double>() != 5.5) {
        throw std::runtime_error("Call Demo.Add(2, 3.5) failed: " +
                                 std::string(ua::statusName(r.status())));
    }
}

/// The wire sizes of a Read of Demo.Double as our client and server exchange it: the
/// request as Client::request fills it (the session's 32-byte opaque authentication token,
/// timestamp, handle, timeoutHint) and the response the server actually returned.
struct FrameSizes {
    std::size_t request = 0;
    std::size_t response = 0;
};

FrameSizes readFrameSizes(const DemoIds& ids, const ua::ReadResponse& realResponse) {
    ua::ReadRequest req = demoRead(ids);
    req.requestHeader.authenticationToken =
        ua::NodeId(0, ua::ByteString(std::vector<std::uint8_t>(32, 0xA5)));
    req.requestHeader.timestamp = ua::DateTime::now();
    req.requestHeader.requestHandle = 1;
    req.requestHeader.timeoutHint = 10'000;
    auto reqBody = ua::client_detail::encodeBody(req);
    auto respBody = ua::client_detail::encodeBody(realResponse);
    if (!reqBody || !respBody) throw std::runtime_error("cannot encode the Read frames");
    return {reqBody->size() + kMsgFrameOverhead, respBody->size() + kMsgFrameOverhead};
}

std::uint16_t demoNamespaceOf(test::RunningServer& server) {
    const auto ns = server.inServer(
        [](ua::Server& s) { return s.addressSpace().namespaceIndex(apps::kDemoNamespaceUri); });
    if (!ns) throw std::runtime_error("demo namespace missing");
    return *ns;
}

struct ClientRun {
    Samples reads;
    Samples calls;
    ua::ReadResponse sampleResponse;
};

/// The coroutine Client on an io_context run by this thread: no thread hop on our side.
ClientRun runCoroutineClient(const std::string& url, const DemoIds& ids, std::size_t count) {
    asio::io_context io{1};  // one thread runs it
    ua::Client client(io.get_executor());
    ClientRun run;
    std::exception_ptr failure;
    asio::co_spawn(
        io,
        [&]() -> asio::awaitable<void> {
            try {
                if (auto s = co_await client.connect(url); s.isBad()) {
                    throw std::runtime_error("connect: " + std::string(ua::statusName(s)));
                }
                run.reads.reserve(count);
                run.calls.reserve(count);
                for (std::size_t i = 0; i < kWarmup + count; ++i) {
                    // Named first: see the GCC 12 note in src/ua/client/README.md.
                    ua::ReadRequest req = demoRead(ids);
                    const auto t0 = Clock::now();
                    auto r = co_await client.read(std::move(req));
                    const auto dt = Clock::now() - t0;
                    checkRead(r);
                    if (i >= kWarmup) run.reads.push_back(dt);
                    if (i == 0) run.sampleResponse = *r;
                }
                for (std::size_t i = 0; i < kWarmup + count; ++i) {
                    std::vector<ua::Variant> in{ua::Variant(2.0), ua::Variant(3.5)};
                    const auto t0 = Clock::now();
                    auto r = co_await client.call(ids.demo, ids.add, std::move(in));
                    const auto dt = Clock::now() - t0;
                    checkCall(r);
                    if (i >= kWarmup) run.calls.push_back(dt);
                }
                co_await client.disconnect();
            } catch (...) {
                failure = std::current_exception();
                client.abort();
            }
        },
        asio::detached);
    io.run();
    if (failure) std::rethrow_exception(failure);
    return run;
}

ClientRun runBlockingClient(const std::string& url, const DemoIds& ids, std::size_t count) {
    ua::BlockingClient client;
    if (auto s = client.connect(url); s.isBad()) {
        throw std::runtime_error("connect: " + std::string(ua::statusName(s)));
    }
    ClientRun run;
    run.reads.reserve(count);
    run.calls.reserve(count);
    for (std::size_t i = 0; i < kWarmup + count; ++i) {
        const auto t0 = Clock::now();
        auto r = client.read(demoRead(ids));
        const auto dt = Clock::now() - t0;
        checkRead(r);
        if (i >= kWarmup) run.reads.push_back(dt);
    }
    for (std::size_t i = 0; i < kWarmup + count; ++i) {
        std::vector<ua::Variant> in{ua::Variant(2.0), ua::Variant(3.5)};
        const auto t0 = Clock::now();
        auto r = client.call(ids.demo, ids.add, std::move(in));
        const auto dt = Clock::now() - t0;
        checkCall(r);
        if (i >= kWarmup) run.calls.push_back(dt);
    }
    (void)client.disconnect();
    return run;
}

/// The number after "key": inside the object "section" of a one-line JSON document.
std::optional<double> jsonNumber(const std::string& json, const std::string& section,
                                 const std::string& key) {
    const auto sec = json.find("\"" + section + "\":{");
    if (sec == std::string::npos) return std::nullopt;
    const auto end = json.find('}', sec);
    const auto k = json.find("\"" + key + "\":", sec);
    if (k == std::string::npos || k > end) return std::nullopt;
    const char* first = json.data() + k + key.size() + 3;
    double v = 0;
    const auto [p, ec] = std::from_chars(first, json.data() + end, v);
    if (ec != std::errc()) return std::nullopt;
    return v;
}

/// node-opcua client against node-opcua server; std::nullopt and a reason when skipped.
std::optional<Row> runNode(std::size_t count, std::string& why) {
    const std::filesystem::path dir = SKILLCELL_INTEROP_DIR;
    const auto logDir = std::filesystem::temp_directory_path();
    const auto serverLog = (logDir / "skillcell-bench-node-server.log").string();
    const auto clientLog = (logDir / "skillcell-bench-node-client.log").string();
    std::filesystem::remove(serverLog);  // this run's log only
    std::filesystem::remove(clientLog);
    auto peer = test::startNodeServer(dir, {}, serverLog);
    if (!peer) {
        why = peer.error();
        return std::nullopt;
    }
    const std::string& url = peer->url;
    std::cerr << "node-opcua: server.js at " << url << ", running bench_client.js (" << count
              << " Reads + " << count << " Calls)...\n";
    auto client = process::ChildProcess::start(
        {"node", (dir / "bench_client.js").string(), url, std::to_string(count)},
        process::reportingChild(clientLog));
    if (!client) {
        why = client.error();
        return std::nullopt;
    }
    // bench_client.js bounds itself at 120 s; allow for its start-up on top.
    const auto line = client->readLine(150s);
    const auto exit = client->wait(10s);
    (void)peer->server.terminate(std::chrono::seconds(5));
    if (!line || !exit || !exit->success()) {
        why = "bench_client.js failed (" + (exit ? exit->describe() : exit.error()) +
              ", log: " + clientLog + ")";
        return std::nullopt;
    }
    Row row{"node-opcua client -> node-opcua server", {}, {}, "separate processes (node 20)"};
    const auto rm = jsonNumber(*line, "read", "median_us");
    const auto rp = jsonNumber(*line, "read", "p99_us");
    const auto cm = jsonNumber(*line, "call", "median_us");
    const auto cp = jsonNumber(*line, "call", "p99_us");
    const auto rn = jsonNumber(*line, "read", "n");
    if (!rm || !rp || !cm || !cp || !rn) {
        why = "cannot parse bench_client.js output: " + *line;
        return std::nullopt;
    }
    // bench_client.js runs as many Calls as Reads; it reports n once per kind.
    row.read = {.medianUs = *rm, .p99Us = *rp, .n = static_cast<std::size_t>(*rn)};
    row.call = {.medianUs = *cm, .p99Us = *cp, .n = static_cast<std::size_t>(*rn)};
    return row;
}

void printRow(const Row& r) {
    auto cell = [](double v) {
        char buf[32];
        if (std::isnan(v)) return std::string("-");
        std::snprintf(buf, sizeof buf, "%.1f", v);
        return std::string(buf);
    };
    std::printf("| %-40s | %10s | %10s | %10s | %10s |\n", r.name.c_str(),
                cell(r.read.medianUs).c_str(), cell(r.read.p99Us).c_str(),
                cell(r.call.medianUs).c_str(), cell(r.call.p99Us).c_str());
}

int run(const Options& options) {
    std::printf(
        "skillcell round-trip benchmark: %zu timed requests per measurement "
        "(+%zu warm-up), loopback\n",
        options.count, kWarmup);
    if (options.count < 10'000) {
        std::printf("NOTE: --count %zu is below 10000: a smoke run, not a measurement\n",
                    options.count);
    }

    spdlog::set_level(spdlog::level::warn);  // keep the server's info lines out of the table
    // Our server in this process on its own thread; clients on other threads.
    test::RunningServer server(test::RunningServer::defaultConfig(), [](ua::Server& s) {
        if (auto st = apps::addDemoNodes(s.addressSpace()); st.isBad()) {
            throw std::runtime_error("addDemoNodes: " + std::string(ua::statusName(st)));
        }
    });
    const DemoIds ids = demoIds(demoNamespaceOf(server));

    std::fprintf(stderr, "skillcell: coroutine client...\n");
    const ClientRun coro = runCoroutineClient(server.url(), ids, options.count);
    const FrameSizes sizes = readFrameSizes(ids, coro.sampleResponse);
    std::fprintf(stderr, "skillcell: blocking client...\n");
    const ClientRun blocking = runBlockingClient(server.url(), ids, options.count);

    std::fprintf(stderr, "raw TCP: %zu-byte request, %zu-byte response...\n", sizes.request,
                 sizes.response);
    // Both columns of the raw row use the Read sizes (a Call frame is ~40 bytes larger
    // each way, which loopback does not notice).
    const Stats raw =
        summarize(bench::tcpPingPong(options.count, kWarmup, sizes.request, sizes.response));

    std::vector<Row> rows;
    rows.push_back({"raw TCP ping-pong (Read frame sizes)", raw, raw,
                    std::to_string(sizes.request) + " B -> " + std::to_string(sizes.response) +
                        " B, blocking sockets, TCP_NODELAY"});
    rows.push_back({"skillcell coroutine Client", summarize(coro.reads), summarize(coro.calls),
                    "in-process server thread + client io_context on main thread"});
    rows.push_back({"skillcell BlockingClient", summarize(blocking.reads),
                    summarize(blocking.calls), "in-process server thread + client thread"});
    std::optional<Row> node;
    std::string nodeWhy = "skipped (--no-node)";
    if (options.node) node = runNode(options.count, nodeWhy);
    if (node) rows.push_back(*node);

    std::printf("\nRound-trip latency in microseconds (median / 99th percentile, nearest rank)\n");
    std::printf("| %-40s | %10s | %10s | %10s | %10s |\n", "", "Read med", "Read p99", "Call med",
                "Call p99");
    std::printf("|%s|%s|%s|%s|%s|\n", std::string(42, '-').c_str(), std::string(12, '-').c_str(),
                std::string(12, '-').c_str(), std::string(12, '-').c_str(),
                std::string(12, '-').c_str());
    for (const auto& r : rows) printRow(r);
    if (!node) std::printf("| %-40s | %s\n", "node-opcua", nodeWhy.c_str());
    std::printf("\nSetup:\n");
    for (const auto& r : rows) std::printf("  %-40s %s\n", r.name.c_str(), r.note.c_str());
    std::printf("  (skillcell server and client share this process, on separate threads)\n");

    const Row& ours = rows[1];
    const Row& oursBlocking = rows[2];
    std::printf("\nRatios (medians):\n");
    std::printf("  coroutine / raw TCP:   Read %.2fx  Call %.2fx\n",
                ours.read.medianUs / raw.medianUs, ours.call.medianUs / raw.medianUs);
    std::printf("  blocking  / raw TCP:   Read %.2fx  Call %.2fx\n",
                oursBlocking.read.medianUs / raw.medianUs,
                oursBlocking.call.medianUs / raw.medianUs);
    if (node) {
        std::printf("  node-opcua / coroutine: Read %.1fx  Call %.1fx\n",
                    node->read.medianUs / ours.read.medianUs,
                    node->call.medianUs / ours.call.medianUs);
        std::printf("  node-opcua / blocking:  Read %.1fx  Call %.1fx\n",
                    node->read.medianUs / oursBlocking.read.medianUs,
                    node->call.medianUs / oursBlocking.call.medianUs);
        // The loopback round trip is a floor no stack can go below; what a stack adds on
        // top of it is what it costs. When the floor is high on a machine, the plain ratio
        // above cannot reach 10x however little a stack adds.
        auto above = [&raw](double us) { return std::max(us - raw.medianUs, 0.1); };
        std::printf(
            "  time above raw TCP, node-opcua / coroutine: Read %.1fx  Call %.1fx "
            "(%.1f vs %.1f us, %.1f vs %.1f us)\n",
            above(node->read.medianUs) / above(ours.read.medianUs),
            above(node->call.medianUs) / above(ours.call.medianUs), above(node->read.medianUs),
            above(ours.read.medianUs), above(node->call.medianUs), above(ours.call.medianUs));
    }

    auto verdict = [](bool met) { return met ? "MET" : "NOT MET"; };
    const double worstRawRatio = std::max(ours.read.medianUs, ours.call.medianUs) / raw.medianUs;
    std::printf("\nGoals (skillcell coroutine Client, medians):\n");
    std::printf("  ours <= 2x raw TCP:              %s (worst of Read/Call: %.2fx)\n",
                verdict(worstRawRatio <= 2.0), worstRawRatio);
    if (node) {
        const double worstNodeRatio = std::min(node->read.medianUs / ours.read.medianUs,
                                               node->call.medianUs / ours.call.medianUs);
        std::printf("  >= 10x faster than node-opcua:   %s (worst of Read/Call: %.1fx)\n",
                    verdict(worstNodeRatio >= 10.0), worstNodeRatio);
    } else {
        std::printf("  >= 10x faster than node-opcua:   not measured (%s)\n", nodeWhy.c_str());
    }
    return 0;
}

}  // namespace

int main(int argc, char** argv) {
    Options o;
    CLI::App app{
        "Read and Call round trips: the raw TCP floor, our coroutine and blocking "
        "clients against our server, open62541 if built, and node-opcua"};
    app.add_option("--count", o.count,
                   "timed requests per measurement (10000 or more for real numbers, fewer for "
                   "smoke tests)")
        ->check(CLI::PositiveNumber)
        ->capture_default_str();
    app.add_flag("--no-node{false}", o.node, "skip the node-opcua measurement");
    if (const auto exit = skillcell::parseCommandLine(app, argc, argv)) return *exit;
    try {
        return run(o);
    } catch (const std::exception& e) {
        std::fprintf(stderr, "skillcell_bench_roundtrip: %s\n", e.what());
        return 1;
    }
}
