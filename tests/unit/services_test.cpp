// View, Attribute and Method service sets, called through their operation functions (and
// once through the ServiceTable) on the base namespace plus a small demo model.
#include <gtest/gtest.h>

#include "ua/address_space/server_object.hpp"
#include "ua/nodeset/embedded_models.hpp"
#include "ua/server/browse_continuation_points.hpp"
#include "ua/server/services/attribute_service.hpp"
#include "ua/server/services/method_service.hpp"
#include "ua/server/services/register_services.hpp"
#include "ua/server/services/view_service.hpp"

namespace skillcell::ua {
// The server's Session owns the continuation points; this stand-in plays its part here.
class Session {
public:
    BrowseContinuationPoints points;
};
BrowseContinuationPoints& continuationPointsOf(ServiceContext& ctx) {
    return ctx.session->points;
}
}  // namespace skillcell::ua

using namespace skillcell::ua;

namespace {

const NodeId kCell(1, "Cell");
const NodeId kSpeed(1, "Cell.Speed");
const NodeId kReadOnly(1, "Cell.ReadOnly");
const NodeId kSecret(1, "Cell.Secret");
const NodeId kList(1, "Cell.List");
const NodeId kAdd(1, "Cell.Add");
const NodeId kStop(1, "Cell.Stop");

class Services : public ::testing::Test {
protected:
    void SetUp() override {
        auto st = loadBaseNodeSet(as);
        ASSERT_TRUE(st.ok()) << st.error;
        ServerInfo info;
        info.applicationUri = "urn:test:server";
        info.productName = "skillcell";
        info.startTime = DateTime::now();
        ASSERT_EQ(installServerObject(as, info), status::Good);
        ASSERT_TRUE(as.addObject(NodeId(ns0::ObjectsFolder), kCell, "Cell").ok());
        ASSERT_TRUE(as.addVariable(kCell, kSpeed, "Speed", NodeId(ns0::Double), 1.5,
                                   access_level::kReadWrite)
                        .ok());
        ASSERT_TRUE(
            as.addVariable(kCell, kReadOnly, "ReadOnly", NodeId(ns0::Int32), std::int32_t{7}).ok());
        ASSERT_TRUE(as.addVariable(kCell, kSecret, "Secret", NodeId(ns0::String), "s",
                                   access_level::kCurrentWrite)
                        .ok());
        ASSERT_TRUE(as.addVariable(kCell, kList, "List", NodeId(ns0::Int32),
                                   Variant::array(std::vector<std::int32_t>{10, 11, 12, 13}),
                                   access_level::kReadWrite, value_rank::kOneDimension)
                        .ok());
        std::vector<Argument> in{{"a", NodeId(ns0::Double), -1, {}, {}},
                                 {"b", NodeId(ns0::Double), -1, {}, {}}};
        std::vector<Argument> out{{"sum", NodeId(ns0::Double), -1, {}, {}}};
        ASSERT_TRUE(
            as.addMethod(kCell, kAdd, "Add", in, out,
                         [this](const Caller&, const NodeId& obj, std::span<const Variant> args,
                                std::vector<Variant>& outputs) {
                             lastObject = obj;
                             outputs.emplace_back(*args[0].get<double>() + *args[1].get<double>());
                             return status::Good;
                         })
                .ok());
        ASSERT_TRUE(as.addMethod(kCell, kStop, "Stop", {}, {},
                                 [](const Caller&, const NodeId&, std::span<const Variant>,
                                    std::vector<Variant>&) { return status::BadInvalidState; })
                        .ok());
        ctx.session = &session;
        ctx.limits = &limits;
    }

    BrowseResult browseOne(BrowseDescription d, std::uint32_t max = 0) {
        BrowseRequest req;
        req.requestedMaxReferencesPerNode = max;
        req.nodesToBrowse = {std::move(d)};
        BrowseResponse resp;
        EXPECT_EQ(browse(as, session.points, limits, req, resp), status::Good);
        return resp.results.at(0);
    }
    DataValue readOne(const NodeId& id, AttributeId attr, std::string range = {},
                      TimestampsToReturn t = TimestampsToReturn::Both) {
        ReadValueId item;
        item.nodeId = id;
        item.attributeId = static_cast<std::uint32_t>(attr);
        item.indexRange = std::move(range);
        return readAttribute(as, item, t);
    }
    StatusCode writeOne(const NodeId& id, Variant v, AttributeId attr = AttributeId::Value,
                        std::string range = {}) {
        WriteValue item;
        item.nodeId = id;
        item.attributeId = static_cast<std::uint32_t>(attr);
        item.indexRange = std::move(range);
        item.value.value = std::move(v);
        return writeAttribute(as, item);
    }
    CallMethodResult callOne(const NodeId& obj, const NodeId& method, std::vector<Variant> in) {
        return callMethod(as, CallMethodRequest{obj, method, std::move(in)});
    }

    AddressSpace as{"urn:test:server"};
    ServerLimits limits;
    Session session;
    ServiceContext ctx;
    NodeId lastObject;
};

std::vector<NodeId> targets(const BrowseResult& r) {
    std::vector<NodeId> out;
    for (const auto& d : r.references) out.push_back(d.nodeId.nodeId);
    return out;
}

bool contains(const std::vector<NodeId>& v, const NodeId& id) {
    return std::find(v.begin(), v.end(), id) != v.end();
}

}  // namespace

// ---- View -----------------------------------------------------------------------------------

TEST_F(Services, BrowseForwardFillsDescriptions) {
    BrowseDescription d;
    d.nodeId = NodeId(ns0::ObjectsFolder);
    d.referenceTypeId = NodeId(ns0::HierarchicalReferences);
    const auto r = browseOne(d);
    EXPECT_EQ(r.statusCode, status::Good);
    ASSERT_TRUE(contains(targets(r), NodeId(ns0::Server)));
    for (const auto& ref : r.references) {
        if (ref.nodeId.nodeId != NodeId(ns0::Server)) continue;
        EXPECT_EQ(ref.referenceTypeId, NodeId(ns0::Organizes));
        EXPECT_TRUE(ref.isForward);
        EXPECT_EQ(ref.browseName, (QualifiedName{0, "Server"}));
        EXPECT_EQ(ref.displayName.text, "Server");
        EXPECT_EQ(ref.nodeClass, NodeClass::Object);
        EXPECT_EQ(ref.typeDefinition.nodeId, NodeId(ns0::ServerType));
    }
}

TEST_F(Services, BrowseDirectionsAndFilters) {
    BrowseDescription d;
    d.nodeId = NodeId(ns0::Server);
    d.browseDirection = BrowseDirection::Inverse;
    auto r = browseOne(d);
    EXPECT_EQ(targets(r), std::vector<NodeId>{NodeId(ns0::ObjectsFolder)});
    EXPECT_FALSE(r.references[0].isForward);

    d.browseDirection = BrowseDirection::Both;
    r = browseOne(d);
    EXPECT_TRUE(contains(targets(r), NodeId(ns0::ObjectsFolder)));
    EXPECT_TRUE(contains(targets(r), NodeId(ns0::ServerType)));

    d.browseDirection = BrowseDirection::Forward;
    d.referenceTypeId = NodeId(ns0::HasProperty);
    r = browseOne(d);
    EXPECT_TRUE(contains(targets(r), NodeId(ns0::Server_NamespaceArray)));
    EXPECT_FALSE(contains(targets(r), NodeId(ns0::Server_ServerStatus)));

    // Aggregates with subtypes covers both HasProperty and HasComponent; without, neither.
    d.referenceTypeId = NodeId(ns0::Aggregates);
    r = browseOne(d);
    EXPECT_TRUE(contains(targets(r), NodeId(ns0::Server_ServerStatus)));
    d.includeSubtypes = false;
    EXPECT_TRUE(browseOne(d).references.empty());

    d.includeSubtypes = true;
    d.referenceTypeId = {};
    d.nodeClassMask = static_cast<std::uint32_t>(NodeClass::ObjectType);
    EXPECT_EQ(targets(browseOne(d)), std::vector<NodeId>{NodeId(ns0::ServerType)});

    d.nodeClassMask = 0;
    d.resultMask = 0;
    r = browseOne(d);
    ASSERT_FALSE(r.references.empty());
    EXPECT_TRUE(r.references[0].referenceTypeId.isNull());
    EXPECT_TRUE(r.references[0].browseName.name.empty());
    EXPECT_EQ(r.references[0].nodeClass, NodeClass::Unspecified);
}

TEST_F(Services, BrowseErrors) {
    BrowseDescription d;
    d.nodeId = NodeId(1, "missing");
    EXPECT_EQ(browseOne(d).statusCode, status::BadNodeIdUnknown);
    d.nodeId = NodeId(ns0::ObjectsFolder);
    d.browseDirection = static_cast<BrowseDirection>(7);
    EXPECT_EQ(browseOne(d).statusCode, status::BadBrowseDirectionInvalid);
    d.browseDirection = BrowseDirection::Forward;
    d.referenceTypeId = NodeId(ns0::Server);
    EXPECT_EQ(browseOne(d).statusCode, status::BadReferenceTypeIdInvalid);

    BrowseRequest empty;
    BrowseResponse resp;
    EXPECT_EQ(browse(as, session.points, limits, empty, resp), status::BadNothingToDo);
    BrowseRequest many;
    many.nodesToBrowse.resize(limits.maxOperationsPerRequest + 1);
    EXPECT_EQ(browse(as, session.points, limits, many, resp), status::BadTooManyOperations);
    BrowseRequest view;
    view.view.viewId = NodeId(ns0::ObjectsFolder);
    view.nodesToBrowse.resize(1);
    EXPECT_EQ(browse(as, session.points, limits, view, resp), status::BadViewIdUnknown);
}

TEST_F(Services, ContinuationPoints) {
    BrowseDescription d;
    d.nodeId = NodeId(ns0::Server);
    const auto all = targets(browseOne(d));
    ASSERT_GE(all.size(), 4u);

    auto first = browseOne(d, 2);
    EXPECT_EQ(targets(first), std::vector<NodeId>(all.begin(), all.begin() + 2));
    ASSERT_FALSE(first.continuationPoint.empty());
    EXPECT_EQ(session.points.size(), 1u);

    std::vector<NodeId> collected = targets(first);
    ByteString cp = first.continuationPoint;
    while (!cp.empty()) {
        auto next = browseNextOne(session.points, cp, false);
        ASSERT_EQ(next.statusCode, status::Good);
        EXPECT_LE(next.references.size(), 2u);
        for (auto& id : targets(next)) collected.push_back(id);
        cp = next.continuationPoint;
    }
    EXPECT_EQ(collected, all);
    EXPECT_EQ(session.points.size(), 0u);
    EXPECT_EQ(browseNextOne(session.points, first.continuationPoint, false).statusCode,
              status::BadContinuationPointInvalid);

    // Release frees the point without returning references.
    auto again = browseOne(d, 1);
    auto released = browseNextOne(session.points, again.continuationPoint, true);
    EXPECT_EQ(released.statusCode, status::Good);
    EXPECT_TRUE(released.references.empty());
    EXPECT_EQ(session.points.size(), 0u);

    // The per-session limit.
    limits.maxBrowseContinuationPoints = 2;
    EXPECT_FALSE(browseOne(d, 1).continuationPoint.empty());
    EXPECT_FALSE(browseOne(d, 1).continuationPoint.empty());
    const auto refused = browseOne(d, 1);
    EXPECT_EQ(refused.statusCode, status::BadNoContinuationPoints);

    // The session's own limit applies as well.
    BrowseContinuationPoints small(1);
    EXPECT_TRUE(small.store({ReferenceDescription{}}, 1, 10).ok());
    EXPECT_EQ(small.store({ReferenceDescription{}}, 1, 10).status(),
              status::BadNoContinuationPoints);

    BrowseNextRequest nothing;
    BrowseNextResponse resp;
    EXPECT_EQ(browseNext(session.points, limits, nothing, resp), status::BadNothingToDo);
}

TEST_F(Services, ServerLimitCapsReferencesPerNode) {
    limits.maxReferencesPerBrowse = 3;
    BrowseDescription d;
    d.nodeId = NodeId(ns0::Server);
    const auto r = browseOne(d, 0);
    EXPECT_EQ(r.references.size(), 3u);
    EXPECT_FALSE(r.continuationPoint.empty());
}

TEST_F(Services, TranslateBrowsePaths) {
    const auto path = [](NodeId start, std::vector<std::string> names) {
        BrowsePath p;
        p.startingNode = std::move(start);
        for (auto& n : names) {
            RelativePathElement e;
            e.referenceTypeId = NodeId(ns0::HierarchicalReferences);
            e.targetName = QualifiedName{0, n};
            p.relativePath.elements.push_back(e);
        }
        return p;
    };
    auto r = translateBrowsePath(
        as, path(NodeId(ns0::RootFolder), {"Objects", "Server", "ServerStatus", "State"}));
    ASSERT_EQ(r.statusCode, status::Good);
    ASSERT_EQ(r.targets.size(), 1u);
    EXPECT_EQ(r.targets[0].targetId.nodeId, NodeId(ns0::Server_ServerStatus_State));
    EXPECT_EQ(r.targets[0].remainingPathIndex, 0xFFFFFFFFu);

    auto p = path(NodeId(ns0::Server_ServerStatus), {"Server"});
    p.relativePath.elements[0].isInverse = true;
    r = translateBrowsePath(as, p);
    ASSERT_EQ(r.statusCode, status::Good);
    EXPECT_EQ(r.targets[0].targetId.nodeId, NodeId(ns0::Server));

    EXPECT_EQ(
        translateBrowsePath(as, path(NodeId(ns0::RootFolder), {"Objects", "Nope"})).statusCode,
        status::BadNoMatch);
    EXPECT_EQ(translateBrowsePath(as, path(NodeId(ns0::RootFolder), {"Objects", ""})).statusCode,
              status::BadBrowseNameInvalid);
    EXPECT_EQ(translateBrowsePath(as, path(NodeId(ns0::RootFolder), {})).statusCode,
              status::BadNothingToDo);
    EXPECT_EQ(translateBrowsePath(as, path(NodeId(1, "x"), {"A"})).statusCode,
              status::BadNodeIdUnknown);
    TranslateBrowsePathsToNodeIdsRequest req;
    TranslateBrowsePathsToNodeIdsResponse resp;
    EXPECT_EQ(translateBrowsePathsToNodeIds(as, limits, req, resp), status::BadNothingToDo);
}

TEST_F(Services, RegisterAndUnregisterNodes) {
    RegisterNodesRequest req;
    RegisterNodesResponse resp;
    EXPECT_EQ(registerNodes(limits, req, resp), status::BadNothingToDo);
    req.nodesToRegister = {kSpeed, NodeId(ns0::Server)};
    EXPECT_EQ(registerNodes(limits, req, resp), status::Good);
    EXPECT_EQ(resp.registeredNodeIds, req.nodesToRegister);
    req.nodesToRegister.push_back(NodeId());
    EXPECT_EQ(registerNodes(limits, req, resp), status::BadNodeIdInvalid);
    UnregisterNodesRequest un;
    UnregisterNodesResponse unResp;
    EXPECT_EQ(unregisterNodes(limits, un, unResp), status::BadNothingToDo);
    un.nodesToUnregister = {kSpeed};
    EXPECT_EQ(unregisterNodes(limits, un, unResp), status::Good);
    un.nodesToUnregister = {NodeId()};
    EXPECT_EQ(unregisterNodes(limits, un, unResp), status::BadNodeIdInvalid);
}

// ---- Attribute ------------------------------------------------------------------------------

TEST_F(Services, ReadEveryAttributeOfEveryNodeClass) {
    const std::vector<std::pair<NodeId, NodeClass>> nodes{
        {NodeId(ns0::Server), NodeClass::Object},
        {kSpeed, NodeClass::Variable},
        {kAdd, NodeClass::Method},
        {NodeId(ns0::FolderType), NodeClass::ObjectType},
        {NodeId(ns0::PropertyType), NodeClass::VariableType},
        {NodeId(ns0::HasComponent), NodeClass::ReferenceType},
        {NodeId(ns0::Double), NodeClass::DataType},
    };
    for (const auto& [id, nc] : nodes) {
        for (std::uint32_t a = 0; a <= kMaxAttributeId + 1; ++a) {
            const auto dv = readOne(id, static_cast<AttributeId>(a));
            const bool expected = a >= 1 && a <= kMaxAttributeId && hasAttribute(nc, a);
            if (expected) {
                EXPECT_EQ(dv.statusOrGood(), status::Good) << id.toString() << " attr " << a;
                EXPECT_TRUE(dv.value.has_value()) << id.toString() << " attr " << a;
            } else {
                EXPECT_EQ(dv.statusOrGood(), status::BadAttributeIdInvalid)
                    << id.toString() << " attr " << a;
            }
        }
        EXPECT_EQ(*readOne(id, AttributeId::NodeClass).value,
                  Variant(static_cast<std::int32_t>(nc)));
        EXPECT_EQ(*readOne(id, AttributeId::NodeId).value, Variant(id));
    }
    // A View node (there is none in the base model, so build one).
    Node view;
    view.nodeId = NodeId(1, "View");
    view.nodeClass = NodeClass::View;
    view.browseName = {1, "View"};
    ASSERT_TRUE(as.addNode(view).ok());
    EXPECT_EQ(*readOne(NodeId(1, "View"), AttributeId::ContainsNoLoops).value, Variant(false));
    EXPECT_EQ(*readOne(NodeId(1, "View"), AttributeId::EventNotifier).value,
              Variant(std::uint8_t{0}));
    EXPECT_EQ(readOne(NodeId(1, "View"), AttributeId::Value).statusOrGood(),
              status::BadAttributeIdInvalid);

    EXPECT_EQ(*readOne(NodeId(ns0::HasComponent), AttributeId::InverseName).value,
              Variant(LocalizedText{"", "ComponentOf"}));
    EXPECT_EQ(*readOne(NodeId(ns0::References), AttributeId::Symmetric).value, Variant(true));
    EXPECT_EQ(*readOne(NodeId(ns0::BaseVariableType), AttributeId::IsAbstract).value,
              Variant(true));
    EXPECT_EQ(*readOne(kSpeed, AttributeId::DataType).value, Variant(NodeId(ns0::Double)));
    EXPECT_EQ(*readOne(kSpeed, AttributeId::AccessLevel).value, Variant(std::uint8_t{3}));
    EXPECT_EQ(*readOne(kSpeed, AttributeId::ValueRank).value, Variant(std::int32_t{-1}));
    EXPECT_EQ(*readOne(kList, AttributeId::ArrayDimensions).value,
              Variant::array(std::vector<std::uint32_t>{4}));
    EXPECT_EQ(*readOne(kAdd, AttributeId::Executable).value, Variant(true));
    EXPECT_EQ(*readOne(kSpeed, AttributeId::BrowseName).value, Variant(QualifiedName{1, "Speed"}));
    EXPECT_EQ(readOne(NodeId(1, "nope"), AttributeId::Value).statusOrGood(),
              status::BadNodeIdUnknown);
}

TEST_F(Services, ReadValueTimestampsAndServerVariables) {
    auto dv = readOne(kSpeed, AttributeId::Value);
    EXPECT_EQ(*dv.value, Variant(1.5));
    EXPECT_TRUE(dv.sourceTimestamp.has_value());
    EXPECT_TRUE(dv.serverTimestamp.has_value());
    dv = readOne(kSpeed, AttributeId::Value, {}, TimestampsToReturn::Source);
    EXPECT_TRUE(dv.sourceTimestamp.has_value());
    EXPECT_FALSE(dv.serverTimestamp.has_value());
    dv = readOne(kSpeed, AttributeId::Value, {}, TimestampsToReturn::Server);
    EXPECT_FALSE(dv.sourceTimestamp.has_value());
    EXPECT_TRUE(dv.serverTimestamp.has_value());
    dv = readOne(kSpeed, AttributeId::Value, {}, TimestampsToReturn::Neither);
    EXPECT_FALSE(dv.sourceTimestamp.has_value());
    EXPECT_FALSE(dv.serverTimestamp.has_value());
    dv = readOne(kSpeed, AttributeId::DisplayName);
    EXPECT_FALSE(dv.serverTimestamp.has_value());

    dv = readOne(NodeId(ns0::Server_NamespaceArray), AttributeId::Value);
    EXPECT_EQ(*dv.value, Variant::array(std::vector<String>{"http://opcfoundation.org/UA/",
                                                            "urn:test:server"}));
    dv = readOne(NodeId(ns0::Server_ServerStatus_CurrentTime), AttributeId::Value);
    ASSERT_NE(dv.value->get<DateTime>(), nullptr);

    ReadRequest req;
    ReadResponse resp;
    EXPECT_EQ(read(as, limits, req, resp), status::BadNothingToDo);
    req.nodesToRead = {ReadValueId{kSpeed, 13, {}, {}}};
    req.maxAge = -1;
    EXPECT_EQ(read(as, limits, req, resp), status::BadMaxAgeInvalid);
    req.maxAge = 0;
    req.timestampsToReturn = TimestampsToReturn::Invalid;
    EXPECT_EQ(read(as, limits, req, resp), status::BadTimestampsToReturnInvalid);
    req.timestampsToReturn = TimestampsToReturn::Both;
    EXPECT_EQ(read(as, limits, req, resp), status::Good);
    ASSERT_EQ(resp.results.size(), 1u);
    limits.maxOperationsPerRequest = 0;
    EXPECT_EQ(read(as, limits, req, resp), status::BadTooManyOperations);
}

TEST_F(Services, ReadIndexRangeEncodingAndAccess) {
    EXPECT_EQ(*readOne(kList, AttributeId::Value, "1:2").value,
              Variant::array(std::vector<std::int32_t>{11, 12}));
    EXPECT_EQ(*readOne(kList, AttributeId::Value, "3").value,
              Variant::array(std::vector<std::int32_t>{13}));
    EXPECT_EQ(*readOne(kList, AttributeId::Value, "2:9").value,
              Variant::array(std::vector<std::int32_t>{12, 13}));
    EXPECT_EQ(readOne(kList, AttributeId::Value, "4:5").statusOrGood(),
              status::BadIndexRangeNoData);
    EXPECT_EQ(readOne(kList, AttributeId::Value, "2:1").statusOrGood(),
              status::BadIndexRangeInvalid);
    EXPECT_EQ(readOne(kList, AttributeId::Value, "a").statusOrGood(), status::BadIndexRangeInvalid);
    EXPECT_EQ(readOne(kSpeed, AttributeId::Value, "0").statusOrGood(), status::BadIndexRangeNoData);
    EXPECT_EQ(readOne(kSecret, AttributeId::Value).statusOrGood(), status::BadNotReadable);

    ReadValueId item{kSpeed,
                     static_cast<std::uint32_t>(AttributeId::DisplayName),
                     {},
                     QualifiedName{0, "Default Binary"}};
    EXPECT_EQ(readAttribute(as, item, TimestampsToReturn::Both).statusOrGood(),
              status::BadDataEncodingInvalid);
    item.attributeId = static_cast<std::uint32_t>(AttributeId::Value);
    EXPECT_EQ(readAttribute(as, item, TimestampsToReturn::Both).statusOrGood(),
              status::BadDataEncodingInvalid);  // a Double has no encodings
    item.nodeId = NodeId(ns0::Server_ServerStatus);
    EXPECT_EQ(readAttribute(as, item, TimestampsToReturn::Both).statusOrGood(), status::Good);
    item.dataEncoding = QualifiedName{0, "Default XML"};
    EXPECT_EQ(readAttribute(as, item, TimestampsToReturn::Both).statusOrGood(),
              status::BadDataEncodingUnsupported);
}

TEST_F(Services, WriteValues) {
    EXPECT_EQ(writeOne(kSpeed, 3.0), status::Good);
    EXPECT_EQ(*readOne(kSpeed, AttributeId::Value).value, Variant(3.0));
    EXPECT_EQ(writeOne(kSpeed, "fast"), status::BadTypeMismatch);
    EXPECT_EQ(writeOne(kSpeed, Variant::array(std::vector<double>{1.0})), status::BadTypeMismatch);
    EXPECT_EQ(writeOne(kReadOnly, std::int32_t{1}), status::BadNotWritable);
    EXPECT_EQ(writeOne(kSpeed, LocalizedText{"", "x"}, AttributeId::DisplayName),
              status::BadNotWritable);
    EXPECT_EQ(writeOne(kSpeed, true, AttributeId::IsAbstract), status::BadAttributeIdInvalid);
    EXPECT_EQ(writeOne(NodeId(1, "nope"), 1.0), status::BadNodeIdUnknown);
    EXPECT_EQ(writeOne(NodeId(ns0::BaseDataVariableType), 1.0), status::BadNotWritable);

    EXPECT_EQ(writeOne(kList, Variant::array(std::vector<std::int32_t>{21, 22}), AttributeId::Value,
                       "1:2"),
              status::Good);
    EXPECT_EQ(*readOne(kList, AttributeId::Value).value,
              Variant::array(std::vector<std::int32_t>{10, 21, 22, 13}));
    EXPECT_EQ(
        writeOne(kList, Variant::array(std::vector<std::int32_t>{1}), AttributeId::Value, "1:2"),
        status::BadIndexRangeInvalid);
    EXPECT_EQ(
        writeOne(kList, Variant::array(std::vector<std::int32_t>{1, 2}), AttributeId::Value, "3:4"),
        status::BadIndexRangeNoData);

    std::vector<double> seen;
    ASSERT_EQ(as.setValueSink(kSpeed,
                              [&seen](const Caller&, const DataValue& dv) {
                                  const double v = *dv.value->get<double>();
                                  if (v < 0) return StatusCode(status::BadOutOfRange);
                                  seen.push_back(v);
                                  return StatusCode(status::Good);
                              }),
              status::Good);
    EXPECT_EQ(writeOne(kSpeed, 4.0), status::Good);
    EXPECT_EQ(writeOne(kSpeed, -1.0), status::BadOutOfRange);
    EXPECT_EQ(seen, std::vector<double>{4.0});
    EXPECT_EQ(*readOne(kSpeed, AttributeId::Value).value, Variant(4.0));

    WriteRequest req;
    WriteResponse resp;
    EXPECT_EQ(write(as, limits, req, resp), status::BadNothingToDo);
    req.nodesToWrite = {
        WriteValue{kSpeed, 13, {}, DataValue{Variant(5.0), {}, {}, {}, {}, {}}},
        WriteValue{kReadOnly, 13, {}, DataValue{Variant(std::int32_t{1}), {}, {}, {}, {}, {}}}};
    EXPECT_EQ(write(as, limits, req, resp), status::Good);
    EXPECT_EQ(resp.results, (std::vector<StatusCode>{status::Good, status::BadNotWritable}));
}

// ---- Method ---------------------------------------------------------------------------------

TEST_F(Services, CallSucceeds) {
    const auto r = callOne(kCell, kAdd, {Variant(1.5), Variant(2.0)});
    EXPECT_EQ(r.statusCode, status::Good);
    EXPECT_EQ(r.outputArguments, std::vector<Variant>{Variant(3.5)});
    EXPECT_EQ(r.inputArgumentResults, (std::vector<StatusCode>{status::Good, status::Good}));
    EXPECT_EQ(lastObject, kCell);
}

TEST_F(Services, CallArgumentErrors) {
    EXPECT_EQ(callOne(kCell, kAdd, {Variant(1.5)}).statusCode, status::BadArgumentsMissing);
    EXPECT_EQ(callOne(kCell, kAdd, {Variant(1.5), Variant(1.5), Variant(1.5)}).statusCode,
              status::BadTooManyArguments);
    const auto r = callOne(kCell, kAdd, {Variant(1.5), Variant("two")});
    EXPECT_EQ(r.statusCode, status::BadInvalidArgument);
    EXPECT_EQ(r.inputArgumentResults,
              (std::vector<StatusCode>{status::Good, status::BadTypeMismatch}));
    EXPECT_TRUE(r.outputArguments.empty());
}

// A structure argument takes only that structure (or a subtype): the ExtensionObject's type id,
// an encoding node, must belong to the argument's DataType. Structure takes any.
TEST_F(Services, CallChecksTheStructureOfAnArgument) {
    const NodeId place(1, "Cell.Place");
    std::vector<Argument> in{{"Pose", NodeId(ns0::ThreeDFrame), -1, {}, {}},
                             {"Anything", NodeId(ns0::Structure), -1, {}, {}},
                             {"Frame", NodeId(18813), -1, {}, {}}};  // Frame: abstract
    int calls = 0;
    ASSERT_TRUE(as.addMethod(kCell, place, "Place", in, {},
                             [&calls](const Caller&, const NodeId&, std::span<const Variant>,
                                      std::vector<Variant>&) {
                                 ++calls;
                                 return status::Good;
                             })
                    .ok());
    const auto structure = [](std::uint32_t encoding, std::size_t doubles) {
        ExtensionObject eo;
        eo.typeId = NodeId(encoding);
        eo.encoding = ExtensionObject::Encoding::Binary;
        eo.body = ByteString(std::vector<std::uint8_t>(doubles * 8, 0));
        return Variant(std::move(eo));
    };
    const Variant frame = structure(18823, 6);   // 3DFrame's Default Binary
    const Variant vector = structure(18817, 3);  // 3DVector's Default Binary
    const Variant unknown(ExtensionObject{NodeId(1, "NoSuchEncoding"),
                                          ExtensionObject::Encoding::Binary, ByteString{}});

    auto r = callOne(kCell, place, {frame, vector, frame});
    EXPECT_EQ(r.statusCode, status::Good);
    EXPECT_EQ(r.inputArgumentResults,
              (std::vector<StatusCode>{status::Good, status::Good, status::Good}));
    EXPECT_EQ(calls, 1);

    r = callOne(kCell, place, {vector, vector, frame});
    EXPECT_EQ(r.statusCode, status::BadInvalidArgument);
    EXPECT_EQ(r.inputArgumentResults,
              (std::vector<StatusCode>{status::BadTypeMismatch, status::Good, status::Good}));
    EXPECT_TRUE(r.outputArguments.empty());
    // Not a Frame's subtype either; an encoding nobody knows is no 3DFrame's but a Structure.
    r = callOne(kCell, place, {unknown, unknown, vector});
    EXPECT_EQ(r.statusCode, status::BadInvalidArgument);
    EXPECT_EQ(
        r.inputArgumentResults,
        (std::vector<StatusCode>{status::BadTypeMismatch, status::Good, status::BadTypeMismatch}));
    EXPECT_EQ(calls, 1);  // the method body ran for the right structures only

    // 3DFrame's other encoding is a 3DFrame as well (the method decodes, or refuses, it).
    r = callOne(kCell, place, {structure(18859, 0), frame, frame});
    EXPECT_EQ(r.statusCode, status::Good);
    EXPECT_EQ(calls, 2);

    // The check itself, for arrays and the types that take anything.
    EXPECT_TRUE(as.structuresMatch(Variant(1.5), NodeId(ns0::ThreeDFrame)));
    EXPECT_TRUE(as.structuresMatch(vector, NodeId(ns0::BaseDataType)));
    EXPECT_TRUE(as.structuresMatch(Variant(ExtensionObject{}), NodeId(ns0::ThreeDFrame)));
    const auto eoOf = [](const Variant& v) { return *v.get<ExtensionObject>(); };
    EXPECT_TRUE(
        as.structuresMatch(Variant::array(std::vector<ExtensionObject>{eoOf(frame), eoOf(frame)}),
                           NodeId(ns0::ThreeDFrame)));
    EXPECT_FALSE(
        as.structuresMatch(Variant::array(std::vector<ExtensionObject>{eoOf(frame), eoOf(vector)}),
                           NodeId(ns0::ThreeDFrame)));
    ASSERT_NE(as.dataTypeOfEncoding(NodeId(18823)), nullptr);
    EXPECT_EQ(*as.dataTypeOfEncoding(NodeId(18823)), NodeId(ns0::ThreeDFrame));
    EXPECT_EQ(as.dataTypeOfEncoding(NodeId(1, "NoSuchEncoding")), nullptr);

    // A data type built in C++ (not in the registry): its HasEncoding reference tells.
    Node type;
    type.nodeId = NodeId(1, "MyStructure");
    type.nodeClass = NodeClass::DataType;
    type.browseName = {1, "MyStructure"};
    ASSERT_TRUE(as.addNode(type).ok());
    ASSERT_EQ(as.addReference(NodeId(ns0::Structure), NodeId(ns0::HasSubtype), type.nodeId),
              status::Good);
    ASSERT_TRUE(as.addObject(NodeId(ns0::ObjectsFolder), NodeId(1, "MyStructure.Binary"),
                             "Default Binary", NodeId(ns0::DataTypeEncodingType))
                    .ok());
    ASSERT_EQ(
        as.addReference(type.nodeId, NodeId(ns0::HasEncoding), NodeId(1, "MyStructure.Binary")),
        status::Good);
    const Variant mine(ExtensionObject{NodeId(1, "MyStructure.Binary"),
                                       ExtensionObject::Encoding::Binary, ByteString{}});
    ASSERT_NE(as.dataTypeOfEncoding(NodeId(1, "MyStructure.Binary")), nullptr);
    EXPECT_EQ(*as.dataTypeOfEncoding(NodeId(1, "MyStructure.Binary")), type.nodeId);
    EXPECT_TRUE(as.structuresMatch(mine, type.nodeId));
    EXPECT_FALSE(as.structuresMatch(mine, NodeId(ns0::ThreeDFrame)));
    EXPECT_FALSE(as.structuresMatch(frame, type.nodeId));
    EXPECT_FALSE(as.structuresMatch(unknown, type.nodeId));  // its encodings are known
}

TEST_F(Services, CallTargetErrors) {
    EXPECT_EQ(callOne(NodeId(1, "nope"), kAdd, {}).statusCode, status::BadNodeIdUnknown);
    EXPECT_EQ(callOne(kSpeed, kAdd, {}).statusCode, status::BadNodeIdInvalid);
    EXPECT_EQ(callOne(kCell, NodeId(1, "nope"), {}).statusCode, status::BadMethodInvalid);
    EXPECT_EQ(callOne(kCell, kSpeed, {}).statusCode, status::BadMethodInvalid);
    EXPECT_EQ(callOne(NodeId(ns0::Server), kAdd, {Variant(1.0), Variant(2.0)}).statusCode,
              status::BadMethodInvalid);
    EXPECT_EQ(callOne(kCell, kStop, {}).statusCode, status::BadInvalidState);
    as.find(kStop)->executable = false;
    EXPECT_EQ(callOne(kCell, kStop, {}).statusCode, status::BadNotExecutable);
    CallRequest req;
    CallResponse resp;
    EXPECT_EQ(call(as, limits, req, resp), status::BadNothingToDo);
}

TEST_F(Services, MethodDeclaredOnTheTypeIsCallableOnInstances) {
    Node type;
    type.nodeId = NodeId(1, "MachineType");
    type.nodeClass = NodeClass::ObjectType;
    type.browseName = {1, "MachineType"};
    ASSERT_TRUE(as.addNode(type).ok());
    ASSERT_EQ(as.addReference(NodeId(ns0::BaseObjectType), NodeId(ns0::HasSubtype),
                              NodeId(1, "MachineType")),
              status::Good);
    ASSERT_TRUE(as.addMethod(NodeId(1, "MachineType"), NodeId(1, "MachineType.Reset"), "Reset", {},
                             {},
                             [](const Caller&, const NodeId&, std::span<const Variant>,
                                std::vector<Variant>& out) {
                                 out.emplace_back(true);
                                 return status::Good;
                             })
                    .ok());
    ASSERT_TRUE(
        as.addObject(NodeId(ns0::ObjectsFolder), NodeId(1, "M1"), "M1", NodeId(1, "MachineType"))
            .ok());
    const auto r = callOne(NodeId(1, "M1"), NodeId(1, "MachineType.Reset"), {});
    EXPECT_EQ(r.statusCode, status::Good);
    EXPECT_EQ(r.outputArguments, std::vector<Variant>{Variant(true)});
}

// ---- Registration ---------------------------------------------------------------------------

TEST_F(Services, RegisteredHandlersDecodeAndEncode) {
    ServiceTable table;
    registerViewServices(table, as);
    registerAttributeServices(table, as);
    registerMethodServices(table, as);
    for (std::uint32_t id : {527u, 533u, 554u, 560u, 566u, 631u, 673u, 712u}) {
        const auto* e = table.find(id);
        ASSERT_NE(e, nullptr) << id;
        EXPECT_EQ(e->access, ServiceTable::Access::ActivatedSession);
    }

    ReadRequest req;
    req.requestHeader.requestHandle = 42;
    req.nodesToRead = {ReadValueId{NodeId(ns0::Server_ServerStatus_State), 13, {}, {}}};
    req.timestampsToReturn = TimestampsToReturn::Neither;
    const auto body = encodeToBytes(req);
    BinaryReader r(body);
    std::vector<std::uint8_t> out;
    ASSERT_EQ(table.find(631)->invoke(ctx, r, out), status::Good);
    BinaryReader rr(out);
    NodeId type;
    decode(rr, type);
    EXPECT_EQ(type, NodeId(634));
    ReadResponse resp;
    decode(rr, resp);
    ASSERT_TRUE(rr.ok());
    EXPECT_EQ(resp.responseHeader.requestHandle, 42u);
    ASSERT_EQ(resp.results.size(), 1u);
    // State = Running: DataValue mask 0x01 (value), Variant Int32 (6), 0.
    EXPECT_EQ(encodeToBytes(resp.results[0]),
              (std::vector<std::uint8_t>{0x01, 0x06, 0x00, 0x00, 0x00, 0x00}));

    BrowseRequest b;
    b.requestedMaxReferencesPerNode = 1;
    BrowseDescription d;
    d.nodeId = NodeId(ns0::Server);
    b.nodesToBrowse = {d};
    const auto bbody = encodeToBytes(b);
    BinaryReader br(bbody);
    out.clear();
    ASSERT_EQ(table.find(527)->invoke(ctx, br, out), status::Good);
    EXPECT_EQ(session.points.size(), 1u);  // stored in the calling session
}
