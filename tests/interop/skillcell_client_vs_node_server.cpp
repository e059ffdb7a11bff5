// Interop: our client (BlockingClient) against node-opcua's server (tests/interop/server.js).
//
// The suite starts `node server.js --port 0` once, reads its READY line (bounded wait),
// and every test talks to that server; the suite teardown stops it (SIGTERM, then SIGKILL)
// whatever the tests did. Without node or node-opcua the tests skip loudly, unless
// SKILLCELL_REQUIRE_NODE=1, where that is a failure.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <map>
#include <memory>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "node_server_suite.hpp"
#include "ua/client/blocking_client.hpp"
#include "ua/types/to_string.hpp"

#ifndef SKILLCELL_INTEROP_DIR
#error "SKILLCELL_INTEROP_DIR must name tests/interop"
#endif

namespace skillcell::test {
namespace {

using namespace std::chrono_literals;
using ua::AttributeId;
using ua::BlockingClient;
using ua::NodeId;
using ua::StatusCode;
using ua::Variant;
namespace status = ua::status;

constexpr std::string_view kDemoNamespaceUri = "urn:skillcell:demo";
constexpr std::uint32_t kRootFolder = 84;
constexpr std::uint32_t kObjectsFolder = 85;
constexpr std::uint32_t kHierarchicalReferences = 33;
constexpr std::uint32_t kNamespaceArray = 2255;
/// Upper bound of the browse: the standard namespace plus the demo nodes are a few
/// thousand nodes; more means the walk is broken (or a cycle escaped the guard).
constexpr std::size_t kMaxNodes = 30'000;
constexpr std::size_t kNodesPerBrowse = 50;
constexpr std::size_t kValuesPerRead = 540;  // 20 nodes x 27 attributes
/// BrowseNext rounds per browse: with 5 references per round, 100'000 references.
constexpr std::size_t kMaxBrowseNextRounds = 20'000;

std::string name(StatusCode s) {
    return std::string(ua::statusName(s));
}

/// What a browse found about one node.
struct BrowsedNode {
    ua::NodeClass nodeClass = ua::NodeClass::Unspecified;
    ua::QualifiedName browseName;
};

/// The node-opcua server, shared by all tests of the suite.
class NodeServerTest : public test::NodeServerSuite {
protected:
    /// A client with a session on the node-opcua server.
    static std::unique_ptr<BlockingClient> connected() {
        auto client = std::make_unique<BlockingClient>();
        ua::ClientConfig config;
        config.requestTimeout = 20s;
        const auto s = client->connect(url(), config);
        EXPECT_TRUE(s.isGood()) << "connect " << url() << ": " << name(s);
        return s.isGood() ? std::move(client) : nullptr;
    }

    /// The namespace index of urn:skillcell:demo from Server.NamespaceArray.
    static std::optional<std::uint16_t> demoNamespace(BlockingClient& c) {
        auto v = c.readValue(NodeId(kNamespaceArray));
        EXPECT_TRUE(v.ok()) << "read NamespaceArray: " << name(v.status());
        if (!v || !v->isArray()) return std::nullopt;
        const auto& elements = v->elements();
        for (std::size_t i = 0; i < elements.size(); ++i) {
            const auto* uri = std::get_if<ua::String>(&elements[i]);
            if (uri != nullptr && *uri == kDemoNamespaceUri) return static_cast<std::uint16_t>(i);
        }
        ADD_FAILURE() << kDemoNamespaceUri << " not in NamespaceArray";
        return std::nullopt;
    }

    /// Browses everything reachable from Root along forward HierarchicalReferences, several
    /// nodes per Browse and BrowseNext until no continuation point is left.
    static std::map<NodeId, BrowsedNode> browseAll(BlockingClient& c,
                                                   std::uint32_t maxReferencesPerNode,
                                                   std::size_t* browseNextCalls) {
        std::map<NodeId, BrowsedNode> visited;
        visited[NodeId(kRootFolder)] = {ua::NodeClass::Object, {0, "Root"}};
        std::vector<NodeId> frontier{NodeId(kRootFolder)};
        std::size_t next = 0;
        auto take = [&](const std::vector<ua::ReferenceDescription>& refs) {
            for (const auto& ref : refs) {
                if (!ref.nodeId.isLocal()) continue;  // another server: not ours to walk
                // The cycle guard: a node reached twice is browsed once.
                auto [it, inserted] = visited.try_emplace(
                    ref.nodeId.nodeId, BrowsedNode{ref.nodeClass, ref.browseName});
                if (inserted) frontier.push_back(it->first);
            }
        };
        while (next < frontier.size() && visited.size() <= kMaxNodes) {
            ua::BrowseRequest req;
            req.requestedMaxReferencesPerNode = maxReferencesPerNode;
            for (; next < frontier.size() && req.nodesToBrowse.size() < kNodesPerBrowse; ++next) {
                ua::BrowseDescription d;
                d.nodeId = frontier[next];
                d.referenceTypeId = NodeId(kHierarchicalReferences);
                req.nodesToBrowse.push_back(std::move(d));
            }
            const auto batch = req.nodesToBrowse;
            auto resp = c.browse(std::move(req));
            if (!resp) {
                ADD_FAILURE() << "Browse: " << name(resp.status());
                return visited;
            }
            if (resp->results.size() != batch.size()) {
                ADD_FAILURE() << "Browse returned " << resp->results.size() << " results for "
                              << batch.size() << " nodes";
                return visited;
            }
            std::vector<ua::ByteString> continuations;
            for (std::size_t i = 0; i < batch.size(); ++i) {
                const auto& r = resp->results[i];
                EXPECT_TRUE(r.statusCode.isGood())
                    << "Browse " << batch[i].nodeId.toString() << ": " << name(r.statusCode);
                if (maxReferencesPerNode != 0) {
                    EXPECT_LE(r.references.size(), maxReferencesPerNode);
                }
                take(r.references);
                if (!r.continuationPoint.empty()) continuations.push_back(r.continuationPoint);
            }
            for (std::size_t round = 0; !continuations.empty(); ++round) {
                if (round >= kMaxBrowseNextRounds) {
                    ADD_FAILURE() << "BrowseNext did not finish in " << round << " rounds";
                    return visited;
                }
                ua::BrowseNextRequest nextReq;
                nextReq.continuationPoints = continuations;
                auto more = c.browseNext(std::move(nextReq));
                ++*browseNextCalls;
                if (!more || more->results.size() != continuations.size()) {
                    ADD_FAILURE() << "BrowseNext: "
                                  << (more ? "wrong result count" : name(more.status()));
                    return visited;
                }
                continuations.clear();
                for (const auto& r : more->results) {
                    EXPECT_TRUE(r.statusCode.isGood()) << "BrowseNext: " << name(r.statusCode);
                    take(r.references);
                    if (!r.continuationPoint.empty()) continuations.push_back(r.continuationPoint);
                }
            }
        }
        EXPECT_LE(visited.size(), kMaxNodes) << "browse did not end within the node bound";
        return visited;
    }
};

TEST_F(NodeServerTest, GetEndpointsAndFindServers) {
    BlockingClient c;
    ua::ClientConfig config;
    config.createSession = false;
    ASSERT_TRUE(c.connect(url(), config).isGood());

    auto endpoints = c.getEndpoints();
    ASSERT_TRUE(endpoints.ok()) << name(endpoints.status());
    ASSERT_FALSE(endpoints->empty());
    const bool hasNone = std::any_of(endpoints->begin(), endpoints->end(), [](const auto& e) {
        return e.securityPolicyUri == "http://opcfoundation.org/UA/SecurityPolicy#None" &&
               e.securityMode == ua::MessageSecurityMode::None &&
               e.endpointUrl.rfind("opc.tcp://", 0) == 0;
    });
    EXPECT_TRUE(hasNone) << "no SecurityPolicy None endpoint";

    auto servers = c.findServers();
    ASSERT_TRUE(servers.ok()) << name(servers.status());
    ASSERT_FALSE(servers->empty());
    EXPECT_EQ(servers->front().applicationUri, "urn:skillcell:interop:node-opcua-server");
    EXPECT_TRUE(c.disconnect().isGood());
}

TEST_F(NodeServerTest, BrowseEverythingAndReadEveryAttribute) {
    auto c = connected();
    ASSERT_TRUE(c);

    std::size_t browseNextUnlimited = 0;
    const auto nodes = browseAll(*c, 0, &browseNextUnlimited);
    ASSERT_FALSE(HasFailure());
    // Root, Objects, Types, Views, the Server object, the type trees and the Demo nodes.
    ASSERT_GT(nodes.size(), 1000u);
    std::cerr << "browsed " << nodes.size() << " nodes (" << browseNextUnlimited
              << " BrowseNext calls without a reference limit)\n";

    // The same walk 5 references at a time must find exactly the same nodes.
    std::size_t browseNextSmall = 0;
    const auto again = browseAll(*c, 5, &browseNextSmall);
    ASSERT_FALSE(HasFailure());
    EXPECT_GT(browseNextSmall, 0u) << "continuation points were never exercised";
    EXPECT_EQ(again.size(), nodes.size());
    EXPECT_TRUE(std::equal(nodes.begin(), nodes.end(), again.begin(), again.end(),
                           [](const auto& a, const auto& b) { return a.first == b.first; }))
        << "browsing with requestedMaxReferencesPerNode=5 found other nodes";
    std::cerr << "same walk with requestedMaxReferencesPerNode=5: " << browseNextSmall
              << " BrowseNext calls\n";

    // Every attribute of every node, many ReadValueIds per Read.
    std::vector<NodeId> ids;
    ids.reserve(nodes.size());
    for (const auto& [id, info] : nodes) ids.push_back(id);
    std::size_t values = 0;
    std::size_t good = 0;
    std::size_t problems = 0;
    constexpr std::size_t kNodesPerRead = kValuesPerRead / ua::kMaxAttributeId;
    for (std::size_t first = 0; first < ids.size() && problems < 20; first += kNodesPerRead) {
        const std::size_t last = std::min(ids.size(), first + kNodesPerRead);
        ua::ReadRequest req;
        req.timestampsToReturn = ua::TimestampsToReturn::Neither;
        for (std::size_t i = first; i < last; ++i) {
            for (std::uint32_t a = 1; a <= ua::kMaxAttributeId; ++a) {
                ua::ReadValueId rv;
                rv.nodeId = ids[i];
                rv.attributeId = a;
                req.nodesToRead.push_back(std::move(rv));
            }
        }
        const std::size_t count = req.nodesToRead.size();
        auto resp = c->read(std::move(req));
        if (!resp) {
            // Name the values the batch failed on, one Read per value.
            std::string culprits;
            for (std::size_t i = first; i < last; ++i) {
                for (std::uint32_t a = 1; a <= ua::kMaxAttributeId; ++a) {
                    ua::ReadRequest single;
                    ua::ReadValueId rv;
                    rv.nodeId = ids[i];
                    rv.attributeId = a;
                    single.nodesToRead.push_back(std::move(rv));
                    auto one = c->read(std::move(single));
                    if (!one) {
                        culprits += " " + ids[i].toString() + "/attr" + std::to_string(a) + ":" +
                                    name(one.status());
                    }
                }
            }
            ADD_FAILURE() << "Read of " << count << " values: " << name(resp.status())
                          << "; the values whose single Read fails too:" << culprits;
            if (++problems >= 20) break;
            continue;
        }
        ASSERT_EQ(resp->results.size(), count);
        for (std::size_t i = first; i < last; ++i) {
            const auto* dv = &resp->results[(i - first) * ua::kMaxAttributeId];
            auto attr = [&](AttributeId a) -> const ua::DataValue& {
                return dv[static_cast<std::uint32_t>(a) - 1];
            };
            for (std::uint32_t a = 0; a < ua::kMaxAttributeId; ++a) {
                ++values;
                if (dv[a].statusOrGood().isGood()) ++good;
            }
            const std::string where = ids[i].toString();
            const auto& nodeIdDv = attr(AttributeId::NodeId);
            const auto* nodeId = nodeIdDv.value ? nodeIdDv.value->get<NodeId>() : nullptr;
            const auto& classDv = attr(AttributeId::NodeClass);
            const auto* nodeClass = classDv.value ? classDv.value->get<std::int32_t>() : nullptr;
            const auto& nameDv = attr(AttributeId::BrowseName);
            const auto* browseName =
                nameDv.value ? nameDv.value->get<ua::QualifiedName>() : nullptr;
            const bool ok = nodeIdDv.statusOrGood().isGood() && nodeId && *nodeId == ids[i] &&
                            classDv.statusOrGood().isGood() && nodeClass &&
                            *nodeClass == static_cast<std::int32_t>(nodes.at(ids[i]).nodeClass) &&
                            nameDv.statusOrGood().isGood() && browseName &&
                            !browseName->name.empty() && *browseName == nodes.at(ids[i]).browseName;
            if (!ok) {
                ++problems;
                ADD_FAILURE() << where << ": NodeId " << name(nodeIdDv.statusOrGood())
                              << (nodeId ? " " + nodeId->toString() : " <no NodeId>")
                              << ", NodeClass " << name(classDv.statusOrGood())
                              << (nodeClass ? " " + std::to_string(*nodeClass) : " <none>")
                              << ", BrowseName " << name(nameDv.statusOrGood())
                              << (browseName ? " '" + browseName->name + "'" : " <none>");
            }
            EXPECT_TRUE(attr(AttributeId::DisplayName).statusOrGood().isGood())
                << where << " DisplayName";
        }
    }
    EXPECT_EQ(problems, 0u);
    std::cerr << "read " << values << " attribute values, " << good << " Good\n";
}

TEST_F(NodeServerTest, WriteAndReadBack) {
    auto c = connected();
    ASSERT_TRUE(c);
    const auto ns = demoNamespace(*c);
    ASSERT_TRUE(ns);
    const NodeId dbl(*ns, ua::String("Demo.Double"));
    ASSERT_EQ(c->writeValue(dbl, Variant(3.25)), status::Good);
    auto v = c->readValue(dbl);
    ASSERT_TRUE(v.ok()) << name(v.status());
    ASSERT_NE(v->get<double>(), nullptr);
    EXPECT_EQ(*v->get<double>(), 3.25);

    const StatusCode ro =
        c->writeValue(NodeId(*ns, ua::String("Demo.ReadOnly")), Variant(std::uint32_t{8}));
    EXPECT_TRUE(ro == status::BadNotWritable || ro == status::BadUserAccessDenied) << name(ro);
    auto unchanged = c->readValue(NodeId(*ns, ua::String("Demo.ReadOnly")));
    ASSERT_TRUE(unchanged.ok());
    ASSERT_NE(unchanged->get<std::uint32_t>(), nullptr);
    EXPECT_EQ(*unchanged->get<std::uint32_t>(), 7u);
}

TEST_F(NodeServerTest, CallDemoAdd) {
    auto c = connected();
    ASSERT_TRUE(c);
    const auto ns = demoNamespace(*c);
    ASSERT_TRUE(ns);
    const NodeId demo(*ns, ua::String("Demo"));
    const NodeId add(*ns, ua::String("Demo.Add"));

    auto sum = c->call(demo, add, {Variant(2.0), Variant(3.5)});
    ASSERT_TRUE(sum.ok()) << name(sum.status());
    ASSERT_EQ(sum->size(), 1u);
    ASSERT_NE((*sum)[0].get<double>(), nullptr);
    EXPECT_EQ(*(*sum)[0].get<double>(), 5.5);

    auto missing = c->call(demo, add, {Variant(2.0)});
    ASSERT_FALSE(missing.ok());
    EXPECT_EQ(missing.status(), status::BadArgumentsMissing) << name(missing.status());

    auto wrongType = c->call(demo, add, {Variant(2.0), Variant(ua::String("x"))});
    ASSERT_FALSE(wrongType.ok());
    EXPECT_TRUE(wrongType.status() == status::BadTypeMismatch ||
                wrongType.status() == status::BadInvalidArgument)
        << name(wrongType.status());
}

TEST_F(NodeServerTest, TranslateBrowsePathToDemoDouble) {
    auto c = connected();
    ASSERT_TRUE(c);
    const auto ns = demoNamespace(*c);
    ASSERT_TRUE(ns);
    const NodeId dbl(*ns, ua::String("Demo.Double"));
    // The variable's browse name as the server declares it ("Double" in server.js,
    // "Demo.Double" in our demo server): the path is built from what the server says.
    auto browseName = c->readAttribute(dbl, AttributeId::BrowseName);
    ASSERT_TRUE(browseName.ok()) << name(browseName.status());
    ASSERT_TRUE(browseName->value && browseName->value->get<ua::QualifiedName>());
    const ua::QualifiedName leaf = *browseName->value->get<ua::QualifiedName>();
    EXPECT_EQ(leaf.namespaceIndex, *ns);
    if (leaf.name != "Demo.Double") {
        std::cerr << "note: node-opcua's Demo.Double has BrowseName '" << leaf.name
                  << "' (skillcell server: 'Demo.Double')\n";
    }

    auto target = c->translateBrowsePath(NodeId(kObjectsFolder), {{*ns, "Demo"}, leaf});
    ASSERT_TRUE(target.ok()) << name(target.status());
    EXPECT_EQ(*target, dbl) << target->toString();

    auto none = c->translateBrowsePath(NodeId(kObjectsFolder), {{*ns, "Demo"}, {*ns, "Nope"}});
    EXPECT_FALSE(none.ok());
}

}  // namespace
}  // namespace skillcell::test
