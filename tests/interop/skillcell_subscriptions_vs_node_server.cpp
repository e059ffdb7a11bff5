// Interop: our client's subscriptions (BlockingClient) against node-opcua's server
// (tests/interop/server.js): a data change on Demo.Double written by us, and an event raised
// by Demo.FireEvent on the Server object, each received within a bounded wait.
//
// The suite starts `node server.js --port 0` once (process::ChildProcess, as the other interop
// suite does) and reads its READY line with a bounded wait. Without node or node-opcua the
// tests skip loudly, unless SKILLCELL_REQUIRE_NODE=1, where that is a failure.
#include <gtest/gtest.h>

#include <condition_variable>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include "node_server_suite.hpp"
#include "ua/client/blocking_client.hpp"

#ifndef SKILLCELL_INTEROP_DIR
#error "SKILLCELL_INTEROP_DIR must name tests/interop"
#endif

namespace skillcell::test {
namespace {

using namespace std::chrono_literals;
using ua::BlockingClient;
using ua::NodeId;
using ua::StatusCode;
using ua::Variant;
namespace status = ua::status;

constexpr std::string_view kDemoNamespaceUri = "urn:skillcell:demo";
constexpr std::uint32_t kNamespaceArray = 2255;
constexpr std::uint32_t kServerObject = 2253;

std::string name(StatusCode s) {
    return std::string(ua::statusName(s));
}

/// Values handed over from the client's thread (where callbacks run) to the test's.
template <class T>
class Mailbox {
public:
    void put(T value) {
        std::lock_guard lock(m_);
        items_.push_back(std::move(value));
        cv_.notify_all();
    }
    /// The first item `accept` takes, waiting up to `timeout` for it.
    template <class Pred>
    std::optional<T> waitFor(std::chrono::milliseconds timeout, Pred accept) {
        std::unique_lock lock(m_);
        std::optional<T> found;
        cv_.wait_for(lock, timeout, [&] {
            for (const auto& item : items_) {
                if (accept(item)) {
                    found = item;
                    return true;
                }
            }
            return false;
        });
        return found;
    }

private:
    std::mutex m_;
    std::condition_variable cv_;
    std::vector<T> items_;
};

class NodeServerSubscriptionTest : public test::NodeServerSuite {
protected:
    void SetUp() override {
        NodeServerSuite::SetUp();
        if (notReady()) return;
        client_ = std::make_unique<BlockingClient>();
        ua::ClientConfig config;
        config.requestTimeout = 10s;
        const auto s = client_->connect(url(), config);
        ASSERT_TRUE(s.isGood()) << "connect " << url() << ": " << name(s);
        auto ns = client_->readValue(NodeId(kNamespaceArray));
        ASSERT_TRUE(ns.ok()) << name(ns.status());
        ASSERT_TRUE(ns->isArray());
        const auto& uris = ns->elements();
        for (std::size_t i = 0; i < uris.size(); ++i) {
            const auto* uri = std::get_if<ua::String>(&uris[i]);
            if (uri != nullptr && *uri == kDemoNamespaceUri) ns_ = static_cast<std::uint16_t>(i);
        }
        ASSERT_NE(ns_, 0) << kDemoNamespaceUri << " not in NamespaceArray";
    }

    void TearDown() override {
        if (client_) {
            EXPECT_TRUE(client_->disconnect().isGood());
        }
    }

    std::unique_ptr<BlockingClient> client_;
    std::uint16_t ns_ = 0;
    Mailbox<StatusCode> statuses_;
};

TEST_F(NodeServerSubscriptionTest, DataChangeOfDemoDouble) {
    auto sub = client_->createSubscription(ua::SubscriptionSettings(100, 300, 10),
                                           [this](StatusCode s) { statuses_.put(s); });
    ASSERT_TRUE(sub.ok()) << name(sub.status());
    EXPECT_GT((*sub)->revisedPublishingInterval(), 0);

    Mailbox<double> values;
    const NodeId dbl(ns_, ua::String("Demo.Double"));
    auto item = client_->monitorDataChange(*sub, dbl, ua::AttributeId::Value, 50, 10, std::nullopt,
                                           [&values](const ua::DataValue& dv) {
                                               if (dv.value && dv.value->get<double>()) {
                                                   values.put(*dv.value->get<double>());
                                               }
                                           });
    ASSERT_TRUE(item.ok()) << name(item.status());
    EXPECT_NE(item->monitoredItemId, 0u);
    // The first notification is the current value; what matters is the written one.
    const double written = 271.828;
    ASSERT_EQ(client_->writeValue(dbl, Variant(written)), status::Good);
    const auto got = values.waitFor(2s, [&](double v) { return v == written; });
    EXPECT_TRUE(got.has_value()) << "no data change with the written value within 2 s";

    // Disabled reporting, then delete: the services are accepted by node-opcua.
    auto modes =
        client_->setMonitoringMode(*sub, {item->monitoredItemId}, ua::MonitoringMode::Disabled);
    ASSERT_TRUE(modes.ok()) << name(modes.status());
    ASSERT_EQ(modes->size(), 1u);
    EXPECT_EQ((*modes)[0], status::Good);
    auto modified = client_->modifyMonitoredItem(*sub, item->monitoredItemId, 200, 5);
    EXPECT_TRUE(modified.ok()) << name(modified.status());
    EXPECT_EQ(client_->setPublishingMode(*sub, false), status::Good);
    EXPECT_EQ(client_->modifySubscription(*sub, ua::SubscriptionSettings(200, 300, 10)),
              status::Good);
    auto deleted = client_->deleteMonitoredItems(*sub, {item->monitoredItemId});
    ASSERT_TRUE(deleted.ok()) << name(deleted.status());
    EXPECT_EQ(client_->deleteSubscription(*sub), status::Good);
    EXPECT_FALSE(statuses_.waitFor(0ms, [](StatusCode s) { return s.isBad(); }))
        << "unexpected status report";
}

TEST_F(NodeServerSubscriptionTest, EventFromServerObject) {
    auto sub = client_->createSubscription(ua::SubscriptionSettings(100, 300, 10),
                                           [this](StatusCode s) { statuses_.put(s); });
    ASSERT_TRUE(sub.ok()) << name(sub.status());

    Mailbox<std::vector<Variant>> events;
    auto filter =
        ua::makeEventFilter({"EventId", "EventType", "SourceName", "Time", "Message", "Severity"});
    auto item = client_->monitorEvents(
        *sub, NodeId(kServerObject), filter,
        [&events](const std::vector<Variant>& fields) { events.put(fields); });
    ASSERT_TRUE(item.ok()) << name(item.status());

    const std::string message = "hello from skillcell";
    auto called =
        client_->call(NodeId(ns_, ua::String("Demo")), NodeId(ns_, ua::String("Demo.FireEvent")),
                      {Variant(ua::String(message))});
    ASSERT_TRUE(called.ok()) << "Demo.FireEvent: " << name(called.status());

    const auto event = events.waitFor(2s, [&](const std::vector<Variant>& fields) {
        if (fields.size() != 6) return false;
        const auto* text = fields[4].get<ua::LocalizedText>();
        return text != nullptr && text->text == message;
    });
    ASSERT_TRUE(event.has_value()) << "no event with the message within 2 s";
    const auto& f = *event;
    const auto* eventId = f[0].get<ua::ByteString>();
    ASSERT_NE(eventId, nullptr);
    EXPECT_FALSE(eventId->bytes.empty());
    const auto* type = f[1].get<NodeId>();
    ASSERT_NE(type, nullptr);
    EXPECT_EQ(*type, NodeId(2041));  // BaseEventType
    const auto* source = f[2].get<ua::String>();
    ASSERT_NE(source, nullptr);
    EXPECT_EQ(*source, "Demo");
    EXPECT_NE(f[3].get<ua::DateTime>(), nullptr);
    const auto* severity = f[5].get<std::uint16_t>();
    ASSERT_NE(severity, nullptr);
    EXPECT_EQ(*severity, 500);

    EXPECT_EQ(client_->deleteSubscription(*sub), status::Good);
    EXPECT_FALSE(statuses_.waitFor(0ms, [](StatusCode s) { return s.isBad(); }))
        << "unexpected status report";
}

}  // namespace
}  // namespace skillcell::test
