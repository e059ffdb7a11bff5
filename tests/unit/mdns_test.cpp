// mDNS on real multicast, in a private network namespace (see discovery.cmake): responders
// see each other, goodbyes and expiry remove servers, malformed datagrams are dropped, the
// watcher describes what it sees, and servers register with the LDS they discover.
#include <gtest/gtest.h>

#include <asio.hpp>
#include <condition_variable>
#include <future>
#include <mutex>
#include <thread>

#include "running_server.hpp"
#include "skills/skill_detector.hpp"
#include "ua/client/blocking_client.hpp"
#include "ua/discovery/local_discovery_server.hpp"
#include "ua/discovery/mdns_responder.hpp"
#include "ua/discovery/server_registrar.hpp"
#include "ua/discovery/server_watcher.hpp"

namespace skillcell::ua::mdns::mdns_test {
namespace {

using namespace std::chrono_literals;

/// An io_context on its own thread; run() executes a function there and returns its result.
class Loop {
public:
    Loop() : thread_([this] { io_.run(); }) {}
    ~Loop() {
        work_.reset();
        io_.stop();
        thread_.join();
    }
    template <class F>
    auto run(F f) -> decltype(f()) {
        std::packaged_task<decltype(f())()> task(std::move(f));
        auto result = task.get_future();
        asio::post(io_, [&task] { task(); });
        return result.get();
    }
    asio::io_context& io() { return io_; }

private:
    asio::io_context io_{1};
    asio::executor_work_guard<asio::io_context::executor_type> work_{io_.get_executor()};
    std::thread thread_;
};

/// Events as they arrive, for a test thread to wait on.
class EventLog {
public:
    void add(std::string line) {
        std::lock_guard lock(mutex_);
        lines_.push_back(std::move(line));
        changed_.notify_all();
    }
    /// Waits (bounded) until a line equal to `line` arrived.
    bool waitFor(const std::string& line, std::chrono::milliseconds timeout = 5s) {
        std::unique_lock lock(mutex_);
        return changed_.wait_for(lock, timeout, [&] {
            return std::find(lines_.begin(), lines_.end(), line) != lines_.end();
        });
    }
    bool has(const std::string& line) {
        std::lock_guard lock(mutex_);
        return std::find(lines_.begin(), lines_.end(), line) != lines_.end();
    }

private:
    std::mutex mutex_;
    std::condition_variable changed_;
    std::vector<std::string> lines_;
};

std::string eventLine(const ServiceEvent& e) {
    return e.kind == ServiceEvent::Kind::Announced
               ? "announced " + e.instance.name + " " + e.instance.discoveryUrl()
               : "gone " + e.instance.name + " " + std::string(toString(e.reason));
}

MdnsConfig fastConfig(int ttlSeconds = 120) {
    MdnsConfig c;
    c.recordTtl = std::chrono::seconds(ttlSeconds);
    c.queryPeriod = 1s;
    return c;
}

std::shared_ptr<MdnsResponder> makeResponder(asio::io_context& io, EventLog* log = nullptr,
                                             MdnsConfig config = fastConfig()) {
    std::string error;
    auto r = MdnsResponder::create(io.get_executor(), std::move(config), &error);
    if (!r) {
        ADD_FAILURE() << "responder: " << error;
        return nullptr;
    }
    if (log != nullptr) (*r)->subscribe([log](const ServiceEvent& e) { log->add(eventLine(e)); });
    (*r)->start();
    return *r;
}

ServiceAnnouncement pump(std::uint16_t port = 4840) {
    ServiceAnnouncement a;
    a.name = "pump";
    a.port = port;
    a.path = "/ua";
    a.capabilities = {"DA"};
    return a;
}

/// A socket on the mDNS port that plays a foreign peer.
class RawPeer {
public:
    explicit RawPeer(asio::io_context& io) : socket_(io) {
        socket_.open(asio::ip::udp::v4());
        socket_.set_option(asio::ip::udp::socket::reuse_address(true));
        const int one = 1;
        ::setsockopt(socket_.native_handle(), SOL_SOCKET, SO_REUSEPORT, &one, sizeof one);
        socket_.bind({asio::ip::address_v4::any(), 5353});
        socket_.set_option(asio::ip::multicast::enable_loopback(true));
    }
    void send(const std::vector<std::uint8_t>& bytes) {
        socket_.send_to(asio::buffer(bytes), {asio::ip::make_address_v4("224.0.0.251"), 5353});
    }

private:
    asio::ip::udp::socket socket_;
};

std::vector<std::uint8_t> foreignAnnouncement(const std::string& name, std::uint32_t ttl,
                                              std::uint16_t port = 4999,
                                              const std::string& host = "foreign.local") {
    DnsMessage m;
    m.isResponse = true;
    const std::string instance = name + "._opcua-tcp._tcp.local";
    DnsRecord ptr;
    ptr.name = "_opcua-tcp._tcp.local";
    ptr.type = static_cast<std::uint16_t>(DnsType::Ptr);
    ptr.ttl = ttl;
    ptr.target = instance;
    DnsRecord srv;
    srv.name = instance;
    srv.type = static_cast<std::uint16_t>(DnsType::Srv);
    srv.ttl = ttl;
    srv.port = port;
    srv.target = host;
    DnsRecord txt;
    txt.name = instance;
    txt.type = static_cast<std::uint16_t>(DnsType::Txt);
    txt.ttl = ttl;
    txt.txt = {"path=", "caps=NA"};
    DnsRecord a;
    a.name = host;
    a.type = static_cast<std::uint16_t>(DnsType::A);
    a.ttl = ttl;
    a.ipv4 = {127, 0, 0, 1};
    m.records = {ptr, srv, txt, a};
    return *encodeDnsMessage(m);
}

TEST(Mdns, AResponderSeesAnotherAnnounceAndSayGoodbye) {
    Loop loop;
    EventLog log;
    auto announcer = loop.run([&] { return makeResponder(loop.io()); });
    auto listener = loop.run([&] { return makeResponder(loop.io(), &log); });
    ASSERT_TRUE(announcer && listener);
    ASSERT_EQ(loop.run([&] { return announcer->announce(pump()); }), status::Good);
    EXPECT_TRUE(log.waitFor("announced pump opc.tcp://127.0.0.1:4840/ua"));
    loop.run([&] {
        announcer->withdraw("pump");
        return 0;
    });
    EXPECT_TRUE(log.waitFor("gone pump goodbye"));
    loop.run([&] {
        announcer->shutdown();
        listener->shutdown();
        return 0;
    });
}

TEST(Mdns, AListenerStartedLaterFindsEarlierServersByItsFirstQuery) {
    Loop loop;
    EventLog own;
    auto announcer = loop.run([&] { return makeResponder(loop.io(), &own); });
    ASSERT_TRUE(announcer);
    loop.run([&] { return announcer->announce(pump()); });
    // The announcer hears its own announcement over the loopback: it has been sent.
    ASSERT_TRUE(own.waitFor("announced pump opc.tcp://127.0.0.1:4840/ua"));
    EventLog log;
    auto listener = loop.run([&] { return makeResponder(loop.io(), &log); });
    // libmdnsd repeats an announcement 2 s after the first one; finding it well before that
    // means the listener's own query was answered.
    EXPECT_TRUE(log.waitFor("announced pump opc.tcp://127.0.0.1:4840/ua", 1500ms));
    loop.run([&] {
        announcer->shutdown();
        listener->shutdown();
        return 0;
    });
}

TEST(Mdns, AServerThatVanishesWithoutGoodbyeExpiresAfterItsTtl) {
    Loop loop;
    EventLog log;
    auto listener = loop.run([&] { return makeResponder(loop.io(), &log); });
    ASSERT_TRUE(listener);
    RawPeer peer(loop.io());
    peer.send(foreignAnnouncement("ghost", 2));  // and never answers a refresh query
    ASSERT_TRUE(log.waitFor("announced ghost opc.tcp://127.0.0.1:4999"));
    const auto seen = std::chrono::steady_clock::now();
    ASSERT_TRUE(log.waitFor("gone ghost expired", 5s));
    EXPECT_GE(std::chrono::steady_clock::now() - seen, 1500ms);  // not before its TTL
    loop.run([&] {
        listener->shutdown();
        return 0;
    });
}

TEST(Mdns, MalformedAndOversizedDatagramsAreDroppedAndCountedWithoutHarm) {
    Loop loop;
    EventLog log;
    auto listener = loop.run([&] { return makeResponder(loop.io(), &log); });
    auto announcer = loop.run([&] { return makeResponder(loop.io()); });
    ASSERT_TRUE(listener && announcer);
    loop.run([&] { return announcer->announce(pump()); });  // so that queries reach libmdnsd
    ASSERT_TRUE(log.waitFor("announced pump opc.tcp://127.0.0.1:4840/ua"));
    RawPeer peer(loop.io());
    auto good = foreignAnnouncement("evil", 120);
    std::vector<std::vector<std::uint8_t>> bad;
    bad.push_back({1, 2, 3});
    bad.push_back(std::vector<std::uint8_t>(good.begin(), good.begin() + 40));  // truncated
    auto loopy = good;
    loopy[12] = 0xC0;  // the first name points at itself
    loopy[13] = 12;
    bad.push_back(loopy);
    std::vector<std::uint8_t> huge(9100, 0);  // over the 9000-byte mDNS limit
    huge[7] = 1;
    bad.push_back(huge);
    // A query with 65535 questions in 12 bytes.
    bad.push_back({0, 0, 0, 0, 0xFF, 0xFF, 0, 0, 0, 0, 0, 0});
    for (const auto& b : bad) peer.send(b);
    // A valid datagram after them proves the listener kept going, and that none of the bad
    // ones left an entry.
    peer.send(foreignAnnouncement("fine", 120));
    ASSERT_TRUE(log.waitFor("announced fine opc.tcp://127.0.0.1:4999"));
    EXPECT_FALSE(log.has("announced evil opc.tcp://127.0.0.1:4999"));
    EXPECT_GE(loop.run([&] { return listener->stats().malformed; }), bad.size());
    EXPECT_GE(loop.run([&] { return announcer->stats().malformed; }), bad.size());
    loop.run([&] {
        announcer->shutdown();
        listener->shutdown();
        return 0;
    });
}

/// Polls `done` on the loop every 10 ms until it holds, at most `timeout`.
template <class F>
bool waitUntil(Loop& loop, F done, std::chrono::milliseconds timeout = 5s) {
    const auto end = std::chrono::steady_clock::now() + timeout;
    while (!loop.run(done)) {
        if (std::chrono::steady_clock::now() > end) return false;
        std::this_thread::sleep_for(10ms);
    }
    return true;
}

std::vector<std::uint8_t> browseQuery(std::vector<std::pair<std::string, std::uint32_t>> known) {
    DnsMessage q;
    q.questions = {{"_opcua-tcp._tcp.local", static_cast<std::uint16_t>(DnsType::Ptr), kClassIn}};
    for (const auto& [name, ttl] : known) {
        DnsRecord ptr;
        ptr.name = "_opcua-tcp._tcp.local";
        ptr.type = static_cast<std::uint16_t>(DnsType::Ptr);
        ptr.ttl = ttl;
        ptr.target = name + "._opcua-tcp._tcp.local";
        q.records.push_back(ptr);
    }
    return *encodeDnsMessage(q);
}

TEST(Mdns, AServerThatOnlyAnnouncesNeverQueries) {
    Loop loop;
    EventLog log;
    auto announcer = loop.run([&] { return makeResponder(loop.io()); });  // no subscriber
    auto listener = loop.run([&] { return makeResponder(loop.io(), &log); });
    ASSERT_TRUE(announcer && listener);
    loop.run([&] { return announcer->announce(pump()); });
    ASSERT_TRUE(log.waitFor("announced pump opc.tcp://127.0.0.1:4840/ua"));
    // The listener's first query waits 20-120 ms (RFC 6762, 5.2); the announcer's never comes.
    EXPECT_TRUE(waitUntil(loop, [&] { return listener->stats().queriesSent >= 1; }));
    EXPECT_EQ(loop.run([&] { return announcer->stats().queriesSent; }), 0u);
    EXPECT_TRUE(loop.run([&] { return announcer->services().empty(); }));  // keeps no cache
    loop.run([&] {
        announcer->shutdown();
        listener->shutdown();
        return 0;
    });
}

// RFC 6762, 5.2 and 7.3: servers that start together each look for their LDS, and each one's
// first query waits 20-120 ms; the first that asks stands for the others, which hear its
// question and its answers instead of asking the same.
TEST(Mdns, ServersStartingTogetherLetOneQuestionForTheirLdsStandForTheOthers) {
    Loop loop;
    constexpr std::size_t kServers = 8;
    std::vector<std::shared_ptr<MdnsResponder>> servers;
    for (std::size_t i = 0; i < kServers; ++i) {
        servers.push_back(loop.run([&] { return makeResponder(loop.io()); }));
        ASSERT_TRUE(servers.back());
    }
    loop.run([&] {
        for (auto& s : servers)
            s->subscribe([](const ServiceEvent&) {}, BrowseScope::DiscoveryServers);
        return 0;
    });
    // Each either asked or had its question asked for it.
    ASSERT_TRUE(waitUntil(loop, [&] {
        return std::all_of(servers.begin(), servers.end(), [](const auto& s) {
            return s->stats().queriesSent + s->stats().queriesSpared >= 1;
        });
    }));
    const std::size_t asked = loop.run([&] {
        std::size_t n = 0;
        for (const auto& s : servers) n += s->stats().queriesSent;
        return n;
    });
    EXPECT_GE(asked, 1u);
    EXPECT_LT(asked, kServers);  // all 8 asking would need 8 delays within a delivery time
    loop.run([&] {
        for (auto& s : servers) s->shutdown();
        return 0;
    });
}

TEST(Mdns, ABrowseThatKnowsOurServerGetsNoAnswerAndOneThatForgetsItDoes) {
    Loop loop;
    auto announcer = loop.run([&] { return makeResponder(loop.io()); });
    ASSERT_TRUE(announcer);
    loop.run([&] { return announcer->announce(pump()); });
    RawPeer peer(loop.io());
    // It knows pump with the full TTL (120 s): RFC 6762 7.1 says nothing to send.
    peer.send(browseQuery({{"pump", 120}}));
    ASSERT_TRUE(waitUntil(loop, [&] { return announcer->stats().queriesHeard >= 1; }));
    EXPECT_EQ(loop.run([&] { return announcer->pendingAnswers(); }), 0u);
    EXPECT_EQ(loop.run([&] { return announcer->stats().answersSent; }), 0u);
    // Less than half the TTL left: pump answers, after its random delay.
    peer.send(browseQuery({{"pump", 59}}));
    ASSERT_TRUE(waitUntil(loop, [&] { return announcer->stats().queriesHeard >= 2; }));
    EXPECT_TRUE(waitUntil(
        loop, [&] { return announcer->stats().answersSent >= 1; }, 3s));
    loop.run([&] {
        announcer->shutdown();
        return 0;
    });
}

TEST(Mdns, BadAnnouncementsAreRefused) {
    Loop loop;
    auto r = loop.run([&] { return makeResponder(loop.io()); });
    ASSERT_TRUE(r);
    auto bad = pump();
    bad.name = "a.b";
    EXPECT_EQ(loop.run([&] { return r->announce(bad); }), status::BadInvalidArgument);
    bad.name = std::string(64, 'x');
    EXPECT_EQ(loop.run([&] { return r->announce(bad); }), status::BadInvalidArgument);
    bad = pump(0);
    EXPECT_EQ(loop.run([&] { return r->announce(bad); }), status::BadInvalidArgument);
    bad = pump();
    bad.capabilities = {"A,B"};
    EXPECT_EQ(loop.run([&] { return r->announce(bad); }), status::BadInvalidArgument);
    loop.run([&] {
        r->shutdown();
        return 0;
    });
}

TEST(Mdns, TheWatcherDescribesAnnouncedServersAndReportsThemGone) {
    auto config = test::RunningServer::defaultConfig();
    config.description.applicationUri = "urn:test:watched";
    test::RunningServer server(config);
    Loop loop;
    auto announcer = loop.run([&] { return makeResponder(loop.io()); });
    auto listener = loop.run([&] { return makeResponder(loop.io()); });
    ASSERT_TRUE(announcer && listener);
    EventLog log;
    lds::ServerWatcher::Callbacks callbacks;
    callbacks.announced = [&](const lds::AnnouncedServer& s) {
        log.add("announced " + s.instance.name + " " + s.application.applicationUri);
    };
    callbacks.gone = [&](const lds::AnnouncedServer& s, RemovalReason why) {
        log.add("gone " + s.application.applicationUri + " " + std::string(toString(why)));
    };
    auto watcher = loop.run([&] {
        auto w = lds::ServerWatcher::create(loop.io().get_executor(), listener, callbacks);
        w->start();
        return w;
    });
    ServiceAnnouncement a;
    a.name = "watched";
    a.port = server.port();
    loop.run([&] { return announcer->announce(a); });
    EXPECT_TRUE(log.waitFor("announced watched urn:test:watched"));
    loop.run([&] {
        announcer->withdraw("watched");
        return 0;
    });
    EXPECT_TRUE(log.waitFor("gone urn:test:watched goodbye"));
    loop.run([&] {
        watcher->stop();
        announcer->shutdown();
        listener->shutdown();
        return 0;
    });
}

TEST(Mdns, ADetectorLeavesOutTheComponentThatRunsItWhenToldItsName) {
    // A composite: its server, announced on its own responder, which also feeds its detector.
    auto selfConfig = test::RunningServer::defaultConfig();
    selfConfig.description.applicationUri = "urn:test:composite";
    test::RunningServer self(selfConfig);
    auto otherConfig = test::RunningServer::defaultConfig();
    otherConfig.description.applicationUri = "urn:test:robot";
    test::RunningServer other(otherConfig);
    Loop loop;
    auto own = loop.run([&] { return makeResponder(loop.io()); });
    auto elsewhere = loop.run([&] { return makeResponder(loop.io()); });
    ASSERT_TRUE(own && elsewhere);
    auto detector = skills::SkillDetector::create(loop.io().get_executor());
    EventLog log;
    loop.run([&] {
        detector->subscribeComponents([&log](const skills::ComponentEvent& e) {
            log.add(e.status.id + " " +
                    (e.status.state == skills::ComponentStatus::State::Connected ? "connected"
                                                                                 : "other"));
        });
        return 0;
    });
    ServiceAnnouncement a;
    a.name = "Composite";
    a.port = self.port();
    loop.run([&] { return own->announce(a); });
    auto watcher = loop.run([&] { return skills::attachMdns(detector, own, "composite"); });
    ServiceAnnouncement b;
    b.name = "robot";
    b.port = other.port();
    loop.run([&] { return elsewhere->announce(b); });
    // The watcher heard both (its own announcement first); the detector connects to the other.
    EXPECT_TRUE(log.waitFor("urn:test:robot connected"));
    const auto components = loop.run([&] { return detector->components(); });
    ASSERT_EQ(components.size(), 1U);
    EXPECT_EQ(components.front().id, "urn:test:robot");
    EXPECT_EQ(self.inServer([](ua::Server& s) { return s.sessionCount(); }), 0U);
    EXPECT_EQ(other.inServer([](ua::Server& s) { return s.sessionCount(); }), 1U);
    loop.run([&] {
        watcher->stop();
        return 0;
    });
    // Its session ends politely before the loop stops: a Publish in flight would otherwise
    // keep the connection, and the coroutine awaiting the reply, alive in a cycle.
    asio::co_spawn(loop.io(), detector->shutdown(2s), asio::use_future).get();
    loop.run([&] {
        own->shutdown();
        elsewhere->shutdown();
        return 0;
    });
}

TEST(Mdns, TheWatcherReportsAServerOnceWhenOnlyItsSrvTargetChanges) {
    // Two responders naming one instance with different SRV targets for the same address
    // (a server and an LDS speaking for it, say) change the cache's records, not the server.
    auto config = test::RunningServer::defaultConfig();
    config.description.applicationUri = "urn:test:twice";
    test::RunningServer server(config);
    Loop loop;
    auto listener = loop.run([&] { return makeResponder(loop.io()); });
    ASSERT_TRUE(listener);
    EventLog log;
    lds::ServerWatcher::Callbacks callbacks;
    callbacks.announced = [&](const lds::AnnouncedServer& s) {
        log.add("announced " + s.discoveryUrl + " " + s.application.applicationUri);
    };
    auto watcher = loop.run([&] {
        auto w = lds::ServerWatcher::create(loop.io().get_executor(), listener, callbacks);
        w->start();
        return w;
    });
    const Ipv4 source{127, 0, 0, 1};
    auto feed = [&](const std::vector<std::uint8_t>& bytes) {
        return loop.run([&] {
            listener->handleDatagram(bytes, source, 5353);
            return watcher->describesStarted();
        });
    };
    const std::string url = "opc.tcp://127.0.0.1:" + std::to_string(server.port());
    EXPECT_EQ(feed(foreignAnnouncement("twice", 120, server.port(), "one.local")), 1U);
    ASSERT_TRUE(log.waitFor("announced " + url + " urn:test:twice"));
    // Another SRV target, the same address: no second GetEndpoints, no second report.
    EXPECT_EQ(feed(foreignAnnouncement("twice", 120, server.port(), "two.local")), 1U);
    EXPECT_EQ(feed(foreignAnnouncement("twice", 120, server.port(), "one.local")), 1U);
    // Another port is another URL: described again.
    EXPECT_EQ(feed(foreignAnnouncement("twice", 120, 1, "one.local")), 2U);
    loop.run([&] {
        watcher->stop();
        listener->shutdown();
        return 0;
    });
}

/// An LDS with mDNS, on its RunningServer's thread.
struct LdsUnderTest {
    LdsUnderTest() : server(test::RunningServer::defaultConfig()) {
        server.inServer([this](Server& s) {
            responder = makeResponder(server.io());
            lds = lds::LocalDiscoveryServer::create(s, responder);
            lds->start(server.io().get_executor());
            ServiceAnnouncement self;
            self.name = "the-lds";
            self.port = server.port();
            self.capabilities = {"LDS"};
            return responder->announce(self);
        });
    }
    ~LdsUnderTest() {
        server.inServer([this](Server&) {
            lds->stop();
            responder->shutdown();
            return 0;
        });
    }
    bool registered(const std::string& uri) {
        return server.inServer([&](Server&) { return lds->registrations().find(uri) != nullptr; });
    }
    /// Polls (bounded) until registered(uri) == expected.
    bool waitRegistered(const std::string& uri, bool expected) {
        for (int i = 0; i < 100; ++i) {
            if (registered(uri) == expected) return true;
            std::this_thread::sleep_for(50ms);
        }
        return false;
    }

    test::RunningServer server;
    std::shared_ptr<MdnsResponder> responder;
    std::shared_ptr<lds::LocalDiscoveryServer> lds;
};

TEST(Mdns, AServerRegistersWithTheLdsItDiscoversAndUnregistersOnStop) {
    LdsUnderTest lds;
    Loop loop;
    auto responder = loop.run([&] { return makeResponder(loop.io()); });
    ASSERT_TRUE(responder);
    RegisteredServer self;
    self.serverUri = "urn:test:pump";
    self.serverNames = {{"en", "Pump"}};
    self.discoveryUrls = {"opc.tcp://127.0.0.1:4841"};
    MdnsDiscoveryConfiguration mdns;
    mdns.mdnsServerName = "pump";
    auto registrar = loop.run([&] {
        responder->announce(pump(4841));
        auto r = lds::ServerRegistrar::create(loop.io().get_executor(), responder, self, mdns);
        r->start();
        return r;
    });
    ASSERT_TRUE(lds.waitRegistered("urn:test:pump", true));

    // FindServersOnNetwork, over a connection, lists both.
    BlockingClient client;
    ClientConfig cc;
    cc.createSession = false;
    ASSERT_EQ(client.connect(lds.server.url(), cc), status::Good);
    auto resp = client.request<FindServersOnNetworkRequest, FindServersOnNetworkResponse>({});
    ASSERT_TRUE(resp.ok()) << statusName(resp.status());
    std::vector<std::string> names;
    for (const auto& r : resp->servers) names.push_back(r.serverName);
    std::sort(names.begin(), names.end());
    EXPECT_EQ(names, (std::vector<std::string>{"pump", "the-lds"}));
    client.disconnect();

    std::promise<void> stopped;
    loop.run([&] {
        asio::co_spawn(loop.io(), registrar->stop(),
                       [&](std::exception_ptr) { stopped.set_value(); });
        return 0;
    });
    ASSERT_EQ(stopped.get_future().wait_for(10s), std::future_status::ready);
    EXPECT_FALSE(lds.registered("urn:test:pump"));
    loop.run([&] {
        responder->shutdown();
        return 0;
    });
}

TEST(Mdns, TheLdsLeavesAServerThatAnnouncesItselfAfterRegisteringToItself) {
    // The registration arrives before the server's own announcement: the LDS waits for it
    // (its grace) instead of announcing the server a second time.
    LdsUnderTest lds;
    Loop loop;
    auto responder = loop.run([&] { return makeResponder(loop.io()); });
    ASSERT_TRUE(responder);
    BlockingClient client;
    ClientConfig cc;
    cc.createSession = false;
    ASSERT_EQ(client.connect(lds.server.url(), cc), status::Good);
    RegisterServer2Request req;
    req.server.serverUri = "urn:test:late";
    req.server.serverNames = {{"", "Late"}};
    req.server.discoveryUrls = {"opc.tcp://198.18.9.9:4998"};
    MdnsDiscoveryConfiguration mdns;
    mdns.mdnsServerName = "late";
    req.discoveryConfiguration = {toExtensionObject(mdns)};
    ASSERT_TRUE((client.request<RegisterServer2Request, RegisterServer2Response>(req).ok()));
    const std::string uri = req.server.serverUri;
    EXPECT_TRUE(lds.server.inServer([&](Server&) { return lds.lds->awaitsSelfAnnouncement(uri); }));
    ServiceAnnouncement late;
    late.name = "late";
    late.port = 4998;
    loop.run([&] { return responder->announce(late); });
    bool decided = false;
    for (int i = 0; i < 200 && !decided; ++i) {
        decided =
            !lds.server.inServer([&](Server&) { return lds.lds->awaitsSelfAnnouncement(uri); });
        if (!decided) std::this_thread::sleep_for(25ms);
    }
    ASSERT_TRUE(decided);
    EXPECT_FALSE(lds.server.inServer([&](Server&) { return lds.lds->announcesOnBehalfOf(uri); }));
    EXPECT_TRUE(lds.registered(uri));
    client.disconnect();
    loop.run([&] {
        responder->shutdown();
        return 0;
    });
}

TEST(Mdns, TheLdsAnnouncesARegisteredServerOnItsBehalfUntilItUnregisters) {
    LdsUnderTest lds;
    Loop loop;
    EventLog log;
    auto listener = loop.run([&] { return makeResponder(loop.io(), &log); });
    ASSERT_TRUE(listener);
    BlockingClient client;
    ClientConfig cc;
    cc.createSession = false;
    ASSERT_EQ(client.connect(lds.server.url(), cc), status::Good);
    RegisterServer2Request req;
    req.server.serverUri = "urn:test:silent";
    req.server.serverNames = {{"", "Silent"}};
    req.server.discoveryUrls = {"opc.tcp://198.18.9.9:4999/path"};
    MdnsDiscoveryConfiguration mdns;
    mdns.mdnsServerName = "silent";
    mdns.serverCapabilities = {"DA"};
    req.discoveryConfiguration = {toExtensionObject(mdns)};
    ASSERT_TRUE((client.request<RegisterServer2Request, RegisterServer2Response>(req).ok()));
    EXPECT_TRUE(log.waitFor("announced silent opc.tcp://198.18.9.9:4999/path"));
    req.server.isOnline = false;
    ASSERT_TRUE((client.request<RegisterServer2Request, RegisterServer2Response>(req).ok()));
    EXPECT_TRUE(log.waitFor("gone silent goodbye"));
    client.disconnect();
    loop.run([&] {
        listener->shutdown();
        return 0;
    });
}

}  // namespace
}  // namespace skillcell::ua::mdns::mdns_test
