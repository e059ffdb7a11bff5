// The subscription core without sockets or clocks: ServerSubscription's publishing state machine,
// MonitoredItem queues and filters, the engine's Publish handling and event filters. Time
// is a fake steady_clock time point the tests advance by hand.
#include <gtest/gtest.h>

#include "ua/encoding/codec.hpp"
#include "ua/server/subscriptions/subscription_engine.hpp"

namespace subscription_core_test {

using namespace skillcell::ua;
using namespace std::chrono_literals;

namespace {

using TimePoint = std::chrono::steady_clock::time_point;
const TimePoint kT0{std::chrono::seconds(1000)};
const NodeId kSession(1, std::uint32_t{77});
const NodeId kValue(1, String("Test.Value"));
const NodeId kText(1, String("Test.Text"));
const NodeId kComputed(1, String("Test.Computed"));
const NodeId kSource(1, String("Test.Machine"));

/// Collects what a Deferred sends: decoded PublishResponses or ServiceFault statuses.
struct Outbox {
    std::vector<std::vector<std::uint8_t>> bodies;
    Deferred<PublishResponse> deferred(std::uint32_t handle = 1) {
        return {[this](std::vector<std::uint8_t> b) { bodies.push_back(std::move(b)); }, handle};
    }
    /// The ServiceFault status of body i, or Good if it is a PublishResponse.
    StatusCode fault(std::size_t i) const {
        BinaryReader r(bodies.at(i));
        NodeId type;
        decode(r, type);
        if (type != NodeId(ServiceFault::kBinaryEncodingId)) return status::Good;
        ServiceFault f;
        decode(r, f);
        return f.responseHeader.serviceResult;
    }
    PublishResponse response(std::size_t i) const {
        BinaryReader r(bodies.at(i));
        NodeId type;
        decode(r, type);
        EXPECT_EQ(type, NodeId(PublishResponse::kBinaryEncodingId));
        PublishResponse p;
        decode(r, p);
        EXPECT_TRUE(r.ok());
        return p;
    }
};

std::vector<MonitoredItemNotification> dataChanges(const NotificationMessage& m) {
    std::vector<MonitoredItemNotification> out;
    for (const auto& eo : m.notificationData) {
        DataChangeNotification n;
        if (fromExtensionObject(eo, n).isGood()) {
            out.insert(out.end(), n.monitoredItems.begin(), n.monitoredItems.end());
        }
    }
    return out;
}

std::vector<EventFieldList> events(const NotificationMessage& m) {
    std::vector<EventFieldList> out;
    for (const auto& eo : m.notificationData) {
        EventNotificationList n;
        if (fromExtensionObject(eo, n).isGood())
            out.insert(out.end(), n.events.begin(), n.events.end());
    }
    return out;
}

/// An address space with the few type nodes the tests need, built through the C++ API
/// (the BaseEventType model may not be loaded yet).
class Core : public ::testing::Test {
protected:
    Core() {
        engine_.setClock([this] { return now_; });
        auto addType = [this](std::uint32_t id, const char* name, NodeClass cls) {
            Node n;
            n.nodeId = NodeId(id);
            n.nodeClass = cls;
            n.browseName = {0, name};
            (void)as_.addNode(std::move(n));
        };
        addType(ns0::References, "References", NodeClass::ReferenceType);
        addType(ns0::HierarchicalReferences, "HierarchicalReferences", NodeClass::ReferenceType);
        addType(ns0::NonHierarchicalReferences, "NonHierarchicalReferences",
                NodeClass::ReferenceType);
        addType(ns0::HasChild, "HasChild", NodeClass::ReferenceType);
        addType(ns0::Aggregates, "Aggregates", NodeClass::ReferenceType);
        addType(ns0::HasComponent, "HasComponent", NodeClass::ReferenceType);
        addType(ns0::HasProperty, "HasProperty", NodeClass::ReferenceType);
        addType(ns0::Organizes, "Organizes", NodeClass::ReferenceType);
        addType(ns0::HasSubtype, "HasSubtype", NodeClass::ReferenceType);
        addType(ns0::HasTypeDefinition, "HasTypeDefinition", NodeClass::ReferenceType);
        addType(ns0::HasEventSource, "HasEventSource", NodeClass::ReferenceType);
        addType(ns0::HasNotifier, "HasNotifier", NodeClass::ReferenceType);
        addType(ns0::BaseDataType, "BaseDataType", NodeClass::DataType);
        addType(ns0::Number, "Number", NodeClass::DataType);
        addType(ns0::Double, "Double", NodeClass::DataType);
        addType(ns0::String, "String", NodeClass::DataType);
        addType(ns0::BaseObjectType, "BaseObjectType", NodeClass::ObjectType);
        addType(ns0::BaseVariableType, "BaseVariableType", NodeClass::VariableType);
        addType(ns0::BaseDataVariableType, "BaseDataVariableType", NodeClass::VariableType);
        addType(ns0::PropertyType, "PropertyType", NodeClass::VariableType);
        addType(event_ids::BaseEventType, "BaseEventType", NodeClass::ObjectType);
        addType(kAlarmType.numeric(), "TestAlarmType", NodeClass::ObjectType);
        auto sub = [this](std::uint32_t child, std::uint32_t parent) {
            (void)as_.addReference(NodeId(parent), NodeId(ns0::HasSubtype), NodeId(child));
        };
        sub(ns0::HierarchicalReferences, ns0::References);
        sub(ns0::NonHierarchicalReferences, ns0::References);
        sub(ns0::HasChild, ns0::HierarchicalReferences);
        sub(ns0::Organizes, ns0::HierarchicalReferences);
        sub(ns0::HasEventSource, ns0::HierarchicalReferences);
        sub(ns0::HasNotifier, ns0::HasEventSource);
        sub(ns0::Aggregates, ns0::HasChild);
        sub(ns0::HasSubtype, ns0::HasChild);
        sub(ns0::HasComponent, ns0::Aggregates);
        sub(ns0::HasProperty, ns0::Aggregates);
        sub(ns0::HasTypeDefinition, ns0::NonHierarchicalReferences);
        sub(ns0::Number, ns0::BaseDataType);
        sub(ns0::Double, ns0::Number);
        sub(ns0::String, ns0::BaseDataType);
        sub(ns0::BaseDataVariableType, ns0::BaseVariableType);
        sub(ns0::PropertyType, ns0::BaseVariableType);
        sub(event_ids::BaseEventType, ns0::BaseObjectType);
        sub(kAlarmType.numeric(), event_ids::BaseEventType);
        // BaseEventType's fields as properties, so select paths resolve in the hierarchy;
        // TestAlarmType adds one of its own.
        for (auto [id, name] : {std::pair{event_ids::EventId, "EventId"},
                                {event_ids::EventType, "EventType"},
                                {event_ids::SourceName, "SourceName"},
                                {event_ids::Message, "Message"},
                                {event_ids::Severity, "Severity"}}) {
            Node p;
            p.nodeId = NodeId(id);
            p.nodeClass = NodeClass::Variable;
            p.browseName = {0, name};
            (void)as_.addNode(std::move(p));
            (void)as_.addReference(NodeId(event_ids::BaseEventType), NodeId(ns0::HasProperty),
                                   NodeId(id));
        }
        (void)as_.addProperty(kAlarmType, NodeId(1, String("TestAlarmType.Level")), "Level",
                              NodeId(ns0::Double), Variant(0.0));

        Node objects;
        objects.nodeId = NodeId(ns0::ObjectsFolder);
        objects.browseName = {0, "Objects"};
        (void)as_.addNode(std::move(objects));
        Node server;
        server.nodeId = NodeId(ns0::Server);
        server.browseName = {0, "Server"};
        server.eventNotifier = kSubscribeToEvents;
        (void)as_.addNode(std::move(server));
        (void)as_.addVariable(NodeId(ns0::ObjectsFolder), kValue, "Test.Value", NodeId(ns0::Double),
                              Variant(1.0), access_level::kReadWrite);
        (void)as_.addVariable(NodeId(ns0::ObjectsFolder), kText, "Test.Text", NodeId(ns0::String),
                              Variant(String("a")), access_level::kReadWrite);
        (void)as_.addVariable(NodeId(ns0::ObjectsFolder), kComputed, "Test.Computed",
                              NodeId(ns0::Double), Variant(0.0));
        (void)as_.setValueSource(kComputed, [this] {
            DataValue dv;
            dv.value = Variant(computed_);
            return dv;
        });
        auto machine = as_.addObject(NodeId(ns0::ObjectsFolder), kSource, "Machine");
        if (machine) (*machine)->eventNotifier = kSubscribeToEvents;
    }

    ServerSubscription& create(double intervalMs = 100, std::uint32_t keepAlive = 3,
                               std::uint32_t lifetime = 9, std::uint32_t maxPerPublish = 0) {
        CreateSubscriptionRequest req;
        req.requestedPublishingInterval = intervalMs;
        req.requestedMaxKeepAliveCount = keepAlive;
        req.requestedLifetimeCount = lifetime;
        req.maxNotificationsPerPublish = maxPerPublish;
        auto sub = engine_.createSubscription(kSession, req, now_);
        EXPECT_TRUE(sub);
        return **sub;
    }

    MonitoredItemCreateResult monitor(ServerSubscription& sub, const NodeId& node,
                                      std::uint32_t queueSize = 1, bool discardOldest = true,
                                      ExtensionObject filter = {}, std::uint32_t attribute = 13) {
        MonitoredItemCreateRequest req;
        req.itemToMonitor.nodeId = node;
        req.itemToMonitor.attributeId = attribute;
        req.requestedParameters.clientHandle = ++handles_;
        req.requestedParameters.queueSize = queueSize;
        req.requestedParameters.discardOldest = discardOldest;
        req.requestedParameters.filter = std::move(filter);
        return engine_.createMonitoredItem(sub, TimestampsToReturn::Both, req, now_);
    }

    void advance(std::chrono::milliseconds d) {
        now_ += d;
        engine_.tick(now_);
    }
    void publish(std::vector<SubscriptionAcknowledgement> acks = {}) {
        PublishRequest req;
        req.subscriptionAcknowledgements = std::move(acks);
        engine_.publish(kSession, req, out_.deferred(), now_);
    }

    static inline const NodeId kAlarmType{std::uint32_t{5000}};  // a made-up ns0 subtype
    AddressSpace as_;
    ServerLimits limits_;
    ServerSubscriptionEngine engine_{as_, limits_};
    TimePoint now_ = kT0;
    Outbox out_;
    std::uint32_t handles_ = 0;
    double computed_ = 0;
};

// --- Subscription state machine ------------------------------------------------------

TEST(ServerSubscriptionSettings, AreRevisedIntoTheLimits) {
    ServerLimits limits;
    auto s = reviseSettings(limits, 0, 0, 0, 0, 0);
    EXPECT_EQ(s.publishingIntervalMs, limits.minPublishingIntervalMs);
    EXPECT_EQ(s.maxKeepAliveCount, 1u);
    EXPECT_EQ(s.lifetimeCount, 3u);
    EXPECT_EQ(s.maxNotificationsPerPublish, limits.maxNotificationsPerPublish);
    s = reviseSettings(limits, 1e12, 5, 10, 7, 3);
    EXPECT_EQ(s.publishingIntervalMs, limits.maxPublishingIntervalMs);
    EXPECT_EQ(s.lifetimeCount, 30u);  // at least three keep-alive counts
    EXPECT_EQ(s.maxNotificationsPerPublish, 7u);
}

TEST(SubscriptionStateMachine, KeepAliveAfterMaxKeepAliveCountCycles) {
    ServerSubscriptionSettings settings{100, 30, 3, 100, 0};
    ServerSubscription sub(1, kSession, settings, true, 5, kT0);
    EXPECT_EQ(sub.nextCycle(), kT0 + 100ms);
    // The first cycle sends a keep-alive at once; then every third.
    EXPECT_EQ(sub.onPublishingTimer(kT0 + 100ms, true), ServerSubscription::Action::KeepAlive);
    const auto ka = sub.keepAlive(DateTime::now());
    EXPECT_EQ(ka.sequenceNumber, 1u);  // the next number, not consumed
    EXPECT_TRUE(ka.notificationData.empty());
    EXPECT_EQ(sub.onPublishingTimer(kT0 + 200ms, true), ServerSubscription::Action::None);
    EXPECT_EQ(sub.onPublishingTimer(kT0 + 300ms, true), ServerSubscription::Action::None);
    EXPECT_EQ(sub.onPublishingTimer(kT0 + 400ms, true), ServerSubscription::Action::KeepAlive);
    EXPECT_EQ(sub.keepAlive(DateTime::now()).sequenceNumber, 1u);
}

TEST(SubscriptionStateMachine, ExpiresAfterLifetimeCountCyclesWithoutPublish) {
    ServerSubscriptionSettings settings{100, 9, 3, 100, 0};
    ServerSubscription sub(1, kSession, settings, true, 5, kT0);
    TimePoint t = kT0;
    for (int i = 1; i < 9; ++i) {
        t += 100ms;
        EXPECT_NE(sub.onPublishingTimer(t, false), ServerSubscription::Action::Expired) << i;
        EXPECT_TRUE(sub.isLate());  // the keep-alive is waiting for a request
    }
    EXPECT_EQ(sub.onPublishingTimer(t + 100ms, false), ServerSubscription::Action::Expired);
}

TEST(SubscriptionStateMachine, PublishRequestsResetTheLifetime) {
    ServerSubscriptionSettings settings{100, 3, 1, 100, 0};
    ServerSubscription sub(1, kSession, settings, true, 5, kT0);
    TimePoint t = kT0;
    for (int i = 0; i < 10; ++i) {
        t += 100ms;
        EXPECT_NE(sub.onPublishingTimer(t, false), ServerSubscription::Action::Expired);
        sub.resetLifetime();
    }
}

TEST(SubscriptionStateMachine, NextDueAndCatchUpCountTheCyclesItSleptThrough) {
    ServerSubscriptionSettings settings{100, 30, 3, 100, 0};
    ServerSubscription sub(1, kSession, settings, true, 5, kT0);
    EXPECT_EQ(sub.nextDue(true), kT0 + 100ms);  // the first cycle's keep-alive
    ASSERT_EQ(sub.onPublishingTimer(kT0 + 100ms, true), ServerSubscription::Action::KeepAlive);
    (void)sub.keepAlive(DateTime::now());
    EXPECT_EQ(sub.nextDue(true), kT0 + 400ms);    // three cycles on
    EXPECT_EQ(sub.nextDue(false), kT0 + 3100ms);  // no request: the lifetime's end
    sub.catchUp(kT0 + 350ms, true);               // 200 and 300 passed empty
    EXPECT_EQ(sub.nextCycle(), kT0 + 400ms);
    EXPECT_EQ(sub.nextDue(true), kT0 + 400ms);
    sub.catchUp(kT0 + 900ms, true);  // never past the due cycle
    EXPECT_EQ(sub.nextCycle(), kT0 + 400ms);
    EXPECT_EQ(sub.onPublishingTimer(kT0 + 400ms, true), ServerSubscription::Action::KeepAlive);
}

TEST(SubscriptionStateMachine, AfterAStallTheScheduleRestartsInsteadOfBursting) {
    ServerSubscriptionSettings settings{100, 300, 100, 100, 0};
    ServerSubscription sub(1, kSession, settings, true, 5, kT0);
    (void)sub.onPublishingTimer(kT0 + 10s, true);
    EXPECT_EQ(sub.nextCycle(), kT0 + 10s + 100ms);
}

// --- Monitored items -----------------------------------------------------------------------

DataValue dv(double v, StatusCode s = status::Good) {
    DataValue d;
    d.value = Variant(v);
    if (s != status::Good) d.status = s;
    return d;
}

TEST(DataChangeFilter, TriggersAndAbsoluteDeadband) {
    DataChangeFilter f;  // StatusValue, no deadband
    EXPECT_FALSE(dataChangePasses(f, dv(1), dv(1)));
    EXPECT_TRUE(dataChangePasses(f, dv(1), dv(1.0001)));
    EXPECT_TRUE(dataChangePasses(f, dv(1), dv(1, status::BadNotReadable)));
    f.trigger = DataChangeTrigger::Status;
    EXPECT_FALSE(dataChangePasses(f, dv(1), dv(2)));
    EXPECT_TRUE(dataChangePasses(f, dv(1), dv(1, status::Uncertain)));
    f.trigger = DataChangeTrigger::StatusValueTimestamp;
    DataValue a = dv(1);
    DataValue b = dv(1);
    a.sourceTimestamp = DateTime{1};
    b.sourceTimestamp = DateTime{2};
    EXPECT_TRUE(dataChangePasses(f, a, b));
    f.trigger = DataChangeTrigger::StatusValue;
    EXPECT_FALSE(dataChangePasses(f, a, b));
    f.deadbandType = static_cast<std::uint32_t>(DeadbandType::Absolute);
    f.deadbandValue = 0.5;
    EXPECT_FALSE(dataChangePasses(f, dv(1), dv(1.5)));
    EXPECT_TRUE(dataChangePasses(f, dv(1), dv(1.6)));
    EXPECT_TRUE(dataChangePasses(f, dv(1), dv(0.4)));
    DataValue arr1;
    arr1.value = Variant::array(std::vector<double>{1, 2});
    DataValue arr2;
    arr2.value = Variant::array(std::vector<double>{1.2, 2.7});
    EXPECT_TRUE(dataChangePasses(f, arr1, arr2));  // one element moved beyond the deadband
}

TEST(MonitoredItemQueue, OverflowDiscardsOldestAndMarksTheNext) {
    MonitoredItem item(1, MonitoredItem::Kind::DataChange, ReadValueId{}, TimestampsToReturn::Both);
    item.configure(7, 100, 3, true, TimestampsToReturn::Both);
    item.setMode(MonitoringMode::Reporting);
    for (double v : {1.0, 2.0, 3.0, 4.0}) item.offerValue(dv(v), DateTime::now());
    std::vector<MonitoredItemNotification> out;
    ASSERT_EQ(item.takeDataChanges(out, 10), 3u);
    EXPECT_EQ(*out[0].value.value->get<double>(), 2.0);
    EXPECT_EQ(out[0].value.statusOrGood().code & kOverflowInfoBits, kOverflowInfoBits);
    EXPECT_EQ(out[1].value.statusOrGood(), status::Good);
    EXPECT_EQ(*out[2].value.value->get<double>(), 4.0);
    EXPECT_EQ(out[0].clientHandle, 7u);
}

TEST(MonitoredItemQueue, OverflowWithoutDiscardOldestReplacesTheNewest) {
    MonitoredItem item(1, MonitoredItem::Kind::DataChange, ReadValueId{}, TimestampsToReturn::Both);
    item.configure(7, 100, 2, false, TimestampsToReturn::Both);
    item.setMode(MonitoringMode::Reporting);
    for (double v : {1.0, 2.0, 3.0}) item.offerValue(dv(v), DateTime::now());
    std::vector<MonitoredItemNotification> out;
    ASSERT_EQ(item.takeDataChanges(out, 10), 2u);
    EXPECT_EQ(*out[0].value.value->get<double>(), 1.0);
    EXPECT_EQ(*out[1].value.value->get<double>(), 3.0);
    EXPECT_EQ(out[1].value.statusOrGood().code & kOverflowInfoBits, kOverflowInfoBits);
}

TEST(MonitoredItemQueue, QueueOfOneKeepsTheNewestWithoutOverflow) {
    MonitoredItem item(1, MonitoredItem::Kind::DataChange, ReadValueId{}, TimestampsToReturn::Both);
    item.configure(7, 100, 1, true, TimestampsToReturn::Neither);
    item.setMode(MonitoringMode::Reporting);
    for (double v : {1.0, 2.0}) item.offerValue(dv(v), DateTime::now());
    std::vector<MonitoredItemNotification> out;
    ASSERT_EQ(item.takeDataChanges(out, 10), 1u);
    EXPECT_EQ(*out[0].value.value->get<double>(), 2.0);
    EXPECT_EQ(out[0].value.statusOrGood(), status::Good);
    EXPECT_FALSE(out[0].value.serverTimestamp);  // TimestampsToReturn::Neither
}

// --- Engine: Publish, acknowledgements, Republish ------------------------------------------

TEST_F(Core, PublishWithoutSubscriptionIsBadNoSubscription) {
    publish();
    ASSERT_EQ(out_.bodies.size(), 1u);
    EXPECT_EQ(out_.fault(0), status::BadNoSubscription);
}

TEST_F(Core, WriteIsReportedAtTheNextPublishingCycleWithoutPolling) {
    ServerSubscription& sub = create();
    ASSERT_EQ(monitor(sub, kValue).statusCode, status::Good);
    publish();
    EXPECT_TRUE(out_.bodies.empty());  // the request waits for the cycle
    advance(100ms);
    ASSERT_EQ(out_.bodies.size(), 1u);
    auto first = out_.response(0);
    EXPECT_EQ(first.subscriptionId, sub.id());
    auto initial = dataChanges(first.notificationMessage);
    ASSERT_EQ(initial.size(), 1u);
    EXPECT_EQ(*initial[0].value.value->get<double>(), 1.0);
    EXPECT_EQ(first.notificationMessage.sequenceNumber, 1u);

    ASSERT_EQ(as_.setValue(kValue, Variant(5.0)), status::Good);
    publish({{sub.id(), 1}});
    advance(100ms);
    ASSERT_EQ(out_.bodies.size(), 2u);
    auto second = out_.response(1);
    ASSERT_EQ(second.results.size(), 1u);
    EXPECT_EQ(second.results[0], status::Good);  // sequence 1 acknowledged
    auto changes = dataChanges(second.notificationMessage);
    ASSERT_EQ(changes.size(), 1u);
    EXPECT_EQ(*changes[0].value.value->get<double>(), 5.0);
    EXPECT_EQ(second.notificationMessage.sequenceNumber, 2u);
    EXPECT_EQ(second.availableSequenceNumbers, std::vector<std::uint32_t>{2});
}

// The server is not woken every publishing interval for a subscription with nothing to
// send: only for its keep-alive, or the next cycle after something is queued.
TEST_F(Core, AnIdleSubscriptionIsDueOnlyForItsKeepAliveAndAWriteAtTheNextCycle) {
    ServerSubscription& sub = create(100, 5, 30);
    ASSERT_EQ(monitor(sub, kValue).statusCode, status::Good);
    publish();
    advance(100ms);  // the initial value
    ASSERT_EQ(out_.bodies.size(), 1u);
    publish({{sub.id(), 1}});
    EXPECT_EQ(engine_.nextDeadline(), kT0 + 600ms);  // the keep-alive, five cycles on
    now_ += 250ms;                                   // the server sleeps: no tick
    ASSERT_EQ(as_.setValue(kValue, Variant(7.0)), status::Good);
    EXPECT_EQ(engine_.nextDeadline(), kT0 + 400ms);  // the first cycle after the write
    advance(50ms);
    ASSERT_EQ(out_.bodies.size(), 2u);
    auto changes = dataChanges(out_.response(1).notificationMessage);
    ASSERT_EQ(changes.size(), 1u);
    EXPECT_EQ(*changes[0].value.value->get<double>(), 7.0);
    // Nothing more: the keep-alive comes five cycles after that message, on schedule.
    publish({{sub.id(), 2}});
    EXPECT_EQ(engine_.nextDeadline(), kT0 + 900ms);
    now_ = kT0 + 900ms;
    engine_.tick(now_);
    ASSERT_EQ(out_.bodies.size(), 3u);
    EXPECT_TRUE(out_.response(2).notificationMessage.notificationData.empty());  // keep-alive
}

// Without Publish requests, an idle subscription is due when its lifetime ends, and the
// cycles it slept through count toward it.
TEST_F(Core, WithoutRequestsAnIdleSubscriptionIsDueAtTheEndOfItsLifetime) {
    ServerSubscription& sub = create(100, 1, 3);
    publish();
    advance(100ms);  // a keep-alive takes the request
    ASSERT_EQ(out_.bodies.size(), 1u);
    EXPECT_EQ(engine_.nextDeadline(), kT0 + 400ms);
    now_ = kT0 + 400ms;
    engine_.tick(now_);
    EXPECT_EQ(engine_.subscriptionCount(), 0u);
    (void)sub;
}

// A request arriving after cycles the server slept through finds the keep-alive those
// cycles made due, and gets it at once.
TEST_F(Core, ARequestAfterASleepGetsTheKeepAliveThoseCyclesMadeDue) {
    ServerSubscription& sub = create(100, 3, 30);
    publish();
    advance(100ms);  // the first keep-alive
    ASSERT_EQ(out_.bodies.size(), 1u);
    now_ += 450ms;  // no tick: four cycles pass, three of them enough for a keep-alive
    publish();
    ASSERT_EQ(out_.bodies.size(), 2u);
    EXPECT_TRUE(out_.response(1).notificationMessage.notificationData.empty());
    EXPECT_FALSE(sub.isLate());
}

TEST_F(Core, LateSubscriptionAnswersTheNextPublishAtOnce) {
    ServerSubscription& sub = create();
    (void)monitor(sub, kValue);
    advance(100ms);  // notifications ready, no request
    EXPECT_TRUE(sub.isLate());
    publish();
    ASSERT_EQ(out_.bodies.size(), 1u);
    EXPECT_EQ(dataChanges(out_.response(0).notificationMessage).size(), 1u);
}

TEST_F(Core, AcknowledgeUnknownSequenceNumberAndRepublish) {
    ServerSubscription& sub = create();
    (void)monitor(sub, kValue);
    publish();
    advance(100ms);
    EXPECT_EQ(sub.republish(1).status(), status::Good);
    EXPECT_EQ(sub.republish(2).status(), status::BadMessageNotAvailable);
    publish({{sub.id(), 42}, {sub.id() + 100, 1}});
    ASSERT_EQ(engine_.queuedPublishRequests(kSession), 1u);
    ASSERT_EQ(as_.setValue(kValue, Variant(2.0)), status::Good);
    advance(100ms);
    auto r = out_.response(1);
    ASSERT_EQ(r.results.size(), 2u);
    EXPECT_EQ(r.results[0], status::BadSequenceNumberUnknown);
    EXPECT_EQ(r.results[1], status::BadSubscriptionIdInvalid);
    EXPECT_EQ(sub.acknowledge(1), status::Good);
    EXPECT_EQ(sub.republish(1).status(), status::BadMessageNotAvailable);
}

TEST_F(Core, RetransmissionQueueIsBounded) {
    limits_.maxRetransmissionQueueSize = 2;
    ServerSubscription& sub = create();
    (void)monitor(sub, kValue);
    for (int i = 0; i < 4; ++i) {
        ASSERT_EQ(as_.setValue(kValue, Variant(10.0 + i)), status::Good);
        publish();
        advance(100ms);
    }
    EXPECT_EQ(sub.availableSequenceNumbers(), (std::vector<std::uint32_t>{3, 4}));
}

TEST_F(Core, MaxNotificationsPerPublishSplitsAndSetsMoreNotifications) {
    ServerSubscription& sub = create(100, 3, 9, 2);
    (void)monitor(sub, kValue, 5);
    for (double v : {2.0, 3.0, 4.0}) ASSERT_EQ(as_.setValue(kValue, Variant(v)), status::Good);
    publish();
    publish();
    advance(100ms);
    ASSERT_EQ(out_.bodies.size(), 2u);
    auto a = out_.response(0);
    auto b = out_.response(1);
    EXPECT_TRUE(a.moreNotifications);
    EXPECT_EQ(dataChanges(a.notificationMessage).size(), 2u);
    EXPECT_FALSE(b.moreNotifications);
    EXPECT_EQ(dataChanges(b.notificationMessage).size(), 2u);  // 1.0 initial + 4 values
}

TEST_F(Core, LifetimeExpiryDeletesAndSendsStatusChange) {
    ServerSubscription& sub = create(100, 1, 3);
    const auto id = sub.id();
    // Keep one request aside to learn about the expiry: it is served as a keep-alive first,
    // so the subscription then runs without requests until its lifetime elapses.
    publish();
    advance(100ms);
    ASSERT_EQ(out_.bodies.size(), 1u);
    advance(100ms);
    advance(100ms);
    EXPECT_EQ(engine_.subscriptionCount(), 1u);
    advance(100ms);
    EXPECT_EQ(engine_.subscriptionCount(), 0u);
    EXPECT_EQ(engine_.find(kSession, id), nullptr);
    publish();
    EXPECT_EQ(out_.fault(1), status::BadNoSubscription);
}

TEST_F(Core, LateKeepAliveAnswersTheNextPublishAtOnce) {
    ServerSubscription& sub = create(100, 1, 3);
    sub.setPublishingEnabled(false);
    // maxKeepAlive 1 and no requests: the lifetime counts down; a request arriving resets
    // it, so simulate a request that arrives and is then consumed by an earlier keep-alive.
    advance(100ms);
    advance(100ms);
    publish();  // served at once (late keep-alive); lifetime reset
    ASSERT_EQ(out_.bodies.size(), 1u);
    EXPECT_TRUE(out_.response(0).notificationMessage.notificationData.empty());
}

TEST_F(Core, TooManyPublishRequestsAndSubscriptions) {
    limits_.maxPublishRequestsPerSession = 2;
    limits_.maxSubscriptionsPerSession = 1;
    ServerSubscription& sub = create(1000, 1000, 3000);
    (void)sub;
    publish();
    publish();
    publish();
    ASSERT_EQ(out_.bodies.size(), 1u);
    EXPECT_EQ(out_.fault(0), status::BadTooManyPublishRequests);
    CreateSubscriptionRequest req;
    EXPECT_EQ(engine_.createSubscription(kSession, req, now_).status(),
              status::BadTooManySubscriptions);
}

TEST_F(Core, ClosingTheSessionFreesItsSubscriptionsAndAnswersItsRequests) {
    ServerSubscription& sub = create();
    (void)monitor(sub, kValue);
    (void)monitor(sub, kComputed);
    publish();
    publish();
    advance(100ms);
    engine_.closeSession(kSession);
    EXPECT_EQ(engine_.subscriptionCount(), 0u);
    ASSERT_EQ(out_.bodies.size(), 2u);
    EXPECT_EQ(out_.fault(1), status::BadSessionClosed);
    // The observer and the poller no longer know the items.
    ASSERT_EQ(as_.setValue(kValue, Variant(3.0)), status::Good);
    advance(100ms);
    EXPECT_EQ(engine_.nextDeadline(), TimePoint::max());
}

TEST_F(Core, ValueSourceIsSampledAtTheSamplingInterval) {
    ServerSubscription& sub = create(100, 100, 300);
    MonitoredItemCreateRequest req;
    req.itemToMonitor.nodeId = kComputed;
    req.requestedParameters.samplingInterval = 50;
    req.requestedParameters.queueSize = 10;
    auto r = engine_.createMonitoredItem(sub, TimestampsToReturn::Both, req, now_);
    ASSERT_EQ(r.statusCode, status::Good);
    EXPECT_EQ(r.revisedSamplingInterval, 50);
    computed_ = 1;
    advance(50ms);
    computed_ = 2;
    advance(50ms);  // second sample, then the publishing cycle
    publish();
    ASSERT_EQ(out_.bodies.size(), 1u);
    auto changes = dataChanges(out_.response(0).notificationMessage);
    ASSERT_EQ(changes.size(), 3u);  // initial 0, 1, 2
    EXPECT_EQ(*changes[2].value.value->get<double>(), 2.0);
}

TEST_F(Core, SamplingIntervalRevision) {
    ServerSubscription& sub = create(250);
    MonitoredItemCreateRequest req;
    req.itemToMonitor.nodeId = kValue;
    req.requestedParameters.samplingInterval = -1;
    EXPECT_EQ(engine_.createMonitoredItem(sub, TimestampsToReturn::Both, req, now_)
                  .revisedSamplingInterval,
              250);
    req.requestedParameters.samplingInterval = 0;
    EXPECT_EQ(engine_.createMonitoredItem(sub, TimestampsToReturn::Both, req, now_)
                  .revisedSamplingInterval,
              limits_.minSamplingIntervalMs);
}

TEST_F(Core, MonitoredItemStatusCodes) {
    ServerSubscription& sub = create();
    EXPECT_EQ(monitor(sub, NodeId(1, String("nope"))).statusCode, status::BadNodeIdUnknown);
    EXPECT_EQ(monitor(sub, kValue, 1, true, {}, 99).statusCode, status::BadAttributeIdInvalid);
    DataChangeFilter dcf;
    EXPECT_EQ(monitor(sub, NodeId(ns0::Server), 1, true, toExtensionObject(dcf), 12).statusCode,
              status::BadFilterNotAllowed);
    EventFilter ef;
    EXPECT_EQ(monitor(sub, kValue, 1, true, toExtensionObject(ef)).statusCode,
              status::BadFilterNotAllowed);
    dcf.deadbandType = static_cast<std::uint32_t>(DeadbandType::Percent);
    EXPECT_EQ(monitor(sub, kValue, 1, true, toExtensionObject(dcf)).statusCode,
              status::BadMonitoredItemFilterUnsupported);
    dcf.deadbandType = 9;
    EXPECT_EQ(monitor(sub, kValue, 1, true, toExtensionObject(dcf)).statusCode,
              status::BadMonitoredItemFilterInvalid);
    dcf.deadbandType = static_cast<std::uint32_t>(DeadbandType::Absolute);
    dcf.deadbandValue = 1;
    EXPECT_EQ(monitor(sub, kText, 1, true, toExtensionObject(dcf)).statusCode,
              status::BadFilterNotAllowed);  // no deadband on strings
    EXPECT_EQ(monitor(sub, kValue, 1, true, toExtensionObject(AggregateFilter{})).statusCode,
              status::BadMonitoredItemFilterUnsupported);
    EXPECT_EQ(monitor(sub, NodeId(ns0::Server), 1, true, {}, 12).statusCode,
              status::BadMonitoredItemFilterInvalid);  // an event item needs an EventFilter
    MonitoredItemCreateRequest bad;
    bad.itemToMonitor.nodeId = kValue;
    bad.monitoringMode = static_cast<MonitoringMode>(7);
    EXPECT_EQ(engine_.createMonitoredItem(sub, TimestampsToReturn::Both, bad, now_).statusCode,
              status::BadMonitoringModeInvalid);
    EXPECT_EQ(engine_.setMonitoringMode(sub, 9999, MonitoringMode::Sampling, now_),
              status::BadMonitoredItemIdInvalid);
    EXPECT_EQ(engine_.deleteMonitoredItem(sub, 9999), status::BadMonitoredItemIdInvalid);
    EXPECT_EQ(engine_.deleteSubscription(kSession, 9999), status::BadSubscriptionIdInvalid);
    limits_.maxMonitoredItemsPerSubscription = 1;
    EXPECT_EQ(monitor(sub, kValue).statusCode, status::Good);
    EXPECT_EQ(monitor(sub, kValue).statusCode, status::BadTooManyMonitoredItems);
}

TEST_F(Core, SamplingModeQueuesWithoutReporting) {
    ServerSubscription& sub = create();
    auto r = monitor(sub, kValue);
    ASSERT_EQ(engine_.setMonitoringMode(sub, r.monitoredItemId, MonitoringMode::Sampling, now_),
              status::Good);
    ASSERT_EQ(as_.setValue(kValue, Variant(9.0)), status::Good);
    publish();
    advance(100ms);
    ASSERT_EQ(out_.bodies.size(), 1u);
    EXPECT_TRUE(out_.response(0).notificationMessage.notificationData.empty());  // keep-alive
    ASSERT_EQ(engine_.setMonitoringMode(sub, r.monitoredItemId, MonitoringMode::Reporting, now_),
              status::Good);
    publish();
    advance(100ms);
    EXPECT_EQ(dataChanges(out_.response(1).notificationMessage).size(), 1u);
}

// --- Events --------------------------------------------------------------------------------

SimpleAttributeOperand field(const char* name, std::uint32_t type = event_ids::BaseEventType) {
    SimpleAttributeOperand op;
    op.typeDefinitionId = NodeId(type);
    op.browsePath = {QualifiedName{0, name}};
    return op;
}

EventFilter standardSelect() {
    EventFilter f;
    for (const char* n : {"EventId", "EventType", "SourceName", "Time", "Message", "Severity"}) {
        f.selectClauses.push_back(field(n));
    }
    return f;
}

TEST_F(Core, EventOnTheServerObjectWithSelectClauses) {
    ServerSubscription& sub = create();
    auto r = monitor(sub, NodeId(ns0::Server), 10, true, toExtensionObject(standardSelect()), 12);
    ASSERT_EQ(r.statusCode, status::Good);
    Event e;
    e.sourceNode = kSource;
    e.message = {"", "hello"};
    e.severity = 700;
    const ByteString id1 = engine_.fireEvent(e);
    const ByteString id2 = engine_.fireEvent(e);
    EXPECT_NE(id1, id2);
    publish();
    advance(100ms);
    auto evs = events(out_.response(0).notificationMessage);
    ASSERT_EQ(evs.size(), 2u);
    const auto& f = evs[0].eventFields;
    ASSERT_EQ(f.size(), 6u);
    EXPECT_EQ(*f[0].get<ByteString>(), id1);
    EXPECT_EQ(*f[1].get<NodeId>(), NodeId(event_ids::BaseEventType));
    EXPECT_EQ(*f[2].get<String>(), "Machine");  // the source's browse name
    EXPECT_NE(f[3].get<DateTime>(), nullptr);
    EXPECT_EQ(f[4].get<LocalizedText>()->text, "hello");
    EXPECT_EQ(*f[5].get<std::uint16_t>(), 700);
}

TEST_F(Core, EventsReachNotifiersAboveTheSource) {
    const NodeId area(1, String("Area"));
    auto a = as_.addObject(NodeId(ns0::ObjectsFolder), area, "Area");
    ASSERT_TRUE(a);
    (*a)->eventNotifier = kSubscribeToEvents;
    ASSERT_EQ(as_.addReference(area, NodeId(ns0::HasNotifier), kSource), status::Good);
    ServerSubscription& sub = create();
    ASSERT_EQ(monitor(sub, area, 10, true, toExtensionObject(standardSelect()), 12).statusCode,
              status::Good);
    Event e;
    e.sourceNode = kSource;
    engine_.fireEvent(e);
    e.sourceNode = NodeId(ns0::Server);  // not below Area
    engine_.fireEvent(e);
    publish();
    advance(100ms);
    EXPECT_EQ(events(out_.response(0).notificationMessage).size(), 1u);
}

ExtensionObject literal(Variant v) {
    return toExtensionObject(LiteralOperand{std::move(v)});
}

TEST_F(Core, WhereClauseOfTypeEqualsAndOr) {
    EventFilter f = standardSelect();
    f.selectClauses.push_back(field("Level", kAlarmType.numeric()));
    f.selectClauses.back().typeDefinitionId = kAlarmType;
    // (OfType TestAlarmType AND Severity == 900) OR Message == "always"
    f.whereClause.elements = {
        {FilterOperator::Or,
         {toExtensionObject(ElementOperand{1}), toExtensionObject(ElementOperand{4})}},
        {FilterOperator::And,
         {toExtensionObject(ElementOperand{2}), toExtensionObject(ElementOperand{3})}},
        {FilterOperator::OfType, {literal(kAlarmType)}},
        {FilterOperator::Equals,
         {toExtensionObject(field("Severity")), literal(std::uint16_t{900})}},
        {FilterOperator::Equals,
         {toExtensionObject(field("Message")), literal(LocalizedText{"", "always"})}},
    };
    f.selectClauses.back().browsePath = {QualifiedName{1, "Level"}};
    ServerSubscription& sub = create();
    auto r = monitor(sub, NodeId(ns0::Server), 10, true, toExtensionObject(f), 12);
    ASSERT_EQ(r.statusCode, status::Good);

    Event alarm;
    alarm.eventType = kAlarmType;
    alarm.sourceNode = kSource;
    alarm.severity = 900;
    alarm.fields = {{{QualifiedName{1, "Level"}}, Variant(3.5)}};
    engine_.fireEvent(alarm);  // passes: alarm with severity 900
    alarm.severity = 100;
    engine_.fireEvent(alarm);  // fails
    Event plain;
    plain.sourceNode = kSource;
    plain.severity = 900;
    engine_.fireEvent(plain);  // fails: not an alarm
    plain.message = {"", "always"};
    engine_.fireEvent(plain);  // passes the Or
    publish();
    advance(100ms);
    auto evs = events(out_.response(0).notificationMessage);
    ASSERT_EQ(evs.size(), 2u);
    EXPECT_EQ(*evs[0].eventFields[6].get<double>(), 3.5);  // the subtype's own field
    EXPECT_TRUE(evs[1].eventFields[6].isEmpty());          // not a TestAlarmType
}

TEST_F(Core, InvalidEventFiltersAreReportedPerElement) {
    ServerSubscription& sub = create();
    EventFilter f = standardSelect();
    f.whereClause.elements = {
        {FilterOperator::Like, {literal(String("a")), literal(String("b"))}},
    };
    auto r = monitor(sub, NodeId(ns0::Server), 1, true, toExtensionObject(f), 12);
    EXPECT_EQ(r.statusCode, status::BadMonitoredItemFilterInvalid);
    EventFilterResult result;
    ASSERT_EQ(fromExtensionObject(r.filterResult, result), status::Good);
    ASSERT_EQ(result.whereClauseResult.elementResults.size(), 1u);
    EXPECT_EQ(result.whereClauseResult.elementResults[0].statusCode,
              status::BadFilterOperatorUnsupported);

    f.whereClause.elements = {{FilterOperator::Equals, {literal(1)}}};
    r = monitor(sub, NodeId(ns0::Server), 1, true, toExtensionObject(f), 12);
    ASSERT_EQ(fromExtensionObject(r.filterResult, result), status::Good);
    EXPECT_EQ(result.whereClauseResult.elementResults[0].statusCode,
              status::BadFilterOperandCountMismatch);

    EventFilter unknownField;
    unknownField.selectClauses = {field("NoSuchField")};
    r = monitor(sub, NodeId(ns0::Server), 1, true, toExtensionObject(unknownField), 12);
    EXPECT_EQ(r.statusCode, status::BadMonitoredItemFilterInvalid);
    ASSERT_EQ(fromExtensionObject(r.filterResult, result), status::Good);
    ASSERT_EQ(result.selectClauseResults.size(), 1u);
    EXPECT_EQ(result.selectClauseResults[0], status::BadNodeIdUnknown);
}

}  // namespace

}  // namespace subscription_core_test
