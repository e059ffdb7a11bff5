// AddressSpace: namespaces, nodes, references in both directions, type hierarchies, value
// type checks, the C++ building API and the Server object's live values.
#include <gtest/gtest.h>

#include "ua/address_space/address_space.hpp"
#include "ua/address_space/server_object.hpp"
#include "ua/encoding/codec.hpp"
#include "ua/nodeset/embedded_models.hpp"

namespace address_space_test {

using namespace skillcell::ua;

namespace {

AddressSpace loadedSpace() {
    AddressSpace as("urn:test:server");
    const auto st = loadBaseNodeSet(as);
    EXPECT_TRUE(st.ok()) << st.error;
    return as;
}

bool hasRef(const Node& n, std::uint32_t type, const NodeId& target, bool forward) {
    for (const auto& r : n.references) {
        if (r.referenceTypeId == NodeId(type) && r.target == target && r.isForward == forward) {
            return true;
        }
    }
    return false;
}

}  // namespace

TEST(AddressSpace, NamespaceArray) {
    AddressSpace as("urn:app");
    ASSERT_EQ(as.namespaces().size(), 2u);
    EXPECT_EQ(as.namespaces()[0], "http://opcfoundation.org/UA/");
    EXPECT_EQ(as.namespaces()[1], "urn:app");
    EXPECT_EQ(as.registerNamespace("urn:x"), 2);
    EXPECT_EQ(as.registerNamespace("urn:y"), 3);
    EXPECT_EQ(as.registerNamespace("urn:x"), 2);
    EXPECT_EQ(as.namespaceIndex("urn:app"), std::optional<std::uint16_t>(1));
    EXPECT_FALSE(as.namespaceIndex("urn:none").has_value());
}

TEST(AddressSpace, AddNodeRefusesNullAndDuplicates) {
    AddressSpace as;
    Node n;
    EXPECT_EQ(as.addNode(n).status(), status::BadNodeIdInvalid);
    n.nodeId = NodeId(1, 5);
    EXPECT_TRUE(as.addNode(n).ok());
    EXPECT_EQ(as.addNode(n).status(), status::BadNodeIdExists);
    EXPECT_EQ(as.size(), 1u);
}

TEST(AddressSpace, ReferencesAreStoredAtBothEndsOnce) {
    AddressSpace as = loadedSpace();
    auto obj = as.addObject(NodeId(ns0::ObjectsFolder), NodeId(1, "Cell"), "Cell");
    ASSERT_TRUE(obj.ok());
    const Node* objects = as.find(NodeId(ns0::ObjectsFolder));
    const Node* cell = as.find(NodeId(1, "Cell"));
    EXPECT_TRUE(hasRef(*objects, ns0::Organizes, NodeId(1, "Cell"), true));
    EXPECT_TRUE(hasRef(*cell, ns0::Organizes, NodeId(ns0::ObjectsFolder), false));
    EXPECT_TRUE(hasRef(*cell, ns0::HasTypeDefinition, NodeId(ns0::BaseObjectType), true));
    const auto before = cell->references.size();
    EXPECT_EQ(
        as.addReference(NodeId(ns0::ObjectsFolder), NodeId(ns0::Organizes), NodeId(1, "Cell")),
        status::Good);
    EXPECT_EQ(cell->references.size(), before);
    EXPECT_EQ(as.addReference(NodeId(1, "Nope"), NodeId(ns0::Organizes), NodeId(1, "Cell")),
              status::BadNodeIdUnknown);
    EXPECT_EQ(as.addReference(NodeId(1, "Cell"), NodeId(ns0::ObjectsFolder), NodeId(1, "Cell")),
              status::BadReferenceTypeIdInvalid);
}

TEST(AddressSpace, ARemovedNodeLeavesNoReferenceBehind) {
    AddressSpace as = loadedSpace();
    ASSERT_TRUE(as.addObject(NodeId(ns0::ObjectsFolder), NodeId(1, "Order"), "Order").ok());
    const auto before = as.find(NodeId(ns0::ObjectsFolder))->references.size();
    ASSERT_TRUE(as.addObject(NodeId(ns0::ObjectsFolder), NodeId(1, "Gone"), "Gone").ok());
    EXPECT_EQ(as.removeNode(NodeId(1, "Gone")), status::Good);
    EXPECT_EQ(as.find(NodeId(1, "Gone")), nullptr);
    EXPECT_EQ(as.find(NodeId(ns0::ObjectsFolder))->references.size(), before);
    EXPECT_FALSE(hasRef(*as.find(NodeId(ns0::BaseObjectType)), ns0::HasTypeDefinition,
                        NodeId(1, "Gone"), false));
    EXPECT_NE(as.find(NodeId(1, "Order")), nullptr);
    EXPECT_EQ(as.removeNode(NodeId(1, "Gone")), status::BadNodeIdUnknown);
}

TEST(AddressSpace, TypeHierarchies) {
    AddressSpace as = loadedSpace();
    const auto sub = [&](std::uint32_t a, std::uint32_t b) {
        return as.isSubtypeOf(NodeId(a), NodeId(b));
    };
    EXPECT_TRUE(sub(ns0::HasComponent, ns0::HierarchicalReferences));
    EXPECT_TRUE(sub(ns0::HasOrderedComponent, ns0::Aggregates));
    EXPECT_TRUE(sub(ns0::HasProperty, ns0::References));
    EXPECT_TRUE(sub(ns0::HasTypeDefinition, ns0::NonHierarchicalReferences));
    EXPECT_FALSE(sub(ns0::HasProperty, ns0::HasComponent));
    EXPECT_FALSE(sub(ns0::HasTypeDefinition, ns0::HierarchicalReferences));
    EXPECT_TRUE(sub(ns0::Duration, ns0::Number));
    EXPECT_TRUE(sub(ns0::UInt32, ns0::UInteger));
    EXPECT_TRUE(sub(ns0::FolderType, ns0::BaseObjectType));
    EXPECT_TRUE(sub(ns0::ServerStatusType, ns0::BaseVariableType));
    EXPECT_TRUE(sub(ns0::Structure, ns0::Structure));
    EXPECT_FALSE(sub(ns0::Number, ns0::Double));
    EXPECT_TRUE(as.isReferenceType(NodeId(ns0::Organizes)));
    EXPECT_FALSE(as.isReferenceType(NodeId(ns0::ObjectsFolder)));
}

TEST(AddressSpace, ValueMatchesDataTypeAndRank) {
    AddressSpace as = loadedSpace();
    EXPECT_TRUE(as.valueMatches(Variant(2.5), NodeId(ns0::Duration), -1));
    EXPECT_TRUE(as.valueMatches(Variant(std::int32_t{3}), NodeId(ns0::Number), -1));
    EXPECT_TRUE(as.valueMatches(Variant(std::int32_t{0}), NodeId(ns0::ServerState), -1));
    EXPECT_TRUE(as.valueMatches(Variant("x"), NodeId(ns0::LocaleId), -1));
    EXPECT_TRUE(as.valueMatches(Variant("x"), NodeId(ns0::BaseDataType), -2));
    EXPECT_FALSE(as.valueMatches(Variant(std::int32_t{3}), NodeId(ns0::String), -1));
    EXPECT_FALSE(as.valueMatches(Variant(std::uint32_t{3}), NodeId(ns0::Int32), -1));
    const auto arr = Variant::array(std::vector<double>{1, 2});
    EXPECT_FALSE(as.valueMatches(arr, NodeId(ns0::Double), -1));
    EXPECT_TRUE(as.valueMatches(arr, NodeId(ns0::Double), 1));
    EXPECT_TRUE(as.valueMatches(arr, NodeId(ns0::Double), 0));
    EXPECT_TRUE(as.valueMatches(arr, NodeId(ns0::Double), -3));
    EXPECT_FALSE(as.valueMatches(arr, NodeId(ns0::Double), 2));
    EXPECT_FALSE(as.valueMatches(Variant(1.0), NodeId(ns0::Double), 1));
    EXPECT_FALSE(as.valueMatches(Variant{}, NodeId(ns0::Double), -1));
}

TEST(AddressSpace, VariablesStoreOrSourceTheirValue) {
    AddressSpace as = loadedSpace();
    ASSERT_TRUE(as.addVariable(NodeId(ns0::ObjectsFolder), NodeId(1, 7), "Speed",
                               NodeId(ns0::Double), 1.5, access_level::kReadWrite)
                    .ok());
    EXPECT_EQ(
        as.addVariable(NodeId(ns0::ObjectsFolder), NodeId(1, 8), "Bad", NodeId(ns0::Double), "text")
            .status(),
        status::BadTypeMismatch);
    const Node* v = as.find(NodeId(1, 7));
    ASSERT_NE(v, nullptr);
    EXPECT_EQ(v->browseName, (QualifiedName{1, "Speed"}));
    EXPECT_EQ(v->displayName.text, "Speed");
    EXPECT_EQ(*as.readValue(*v).value, Variant(1.5));
    EXPECT_EQ(as.setValue(NodeId(1, 7), 2.5), status::Good);
    EXPECT_EQ(*as.readValue(*v).value, Variant(2.5));
    EXPECT_EQ(as.setValue(NodeId(1, 7), "no"), status::BadTypeMismatch);
    EXPECT_EQ(as.setValue(NodeId(1, 99), 1.0), status::BadNodeIdUnknown);
    EXPECT_EQ(as.setValue(NodeId(ns0::ObjectsFolder), 1.0), status::BadNodeClassInvalid);
    int reads = 0;
    ASSERT_EQ(as.setValueSource(NodeId(1, 7),
                                [&reads] {
                                    DataValue dv;
                                    dv.value = Variant(double(++reads));
                                    return dv;
                                }),
              status::Good);
    EXPECT_EQ(*as.readValue(*v).value, Variant(1.0));
    EXPECT_EQ(*as.readValue(*v).value, Variant(2.0));
}

TEST(AddressSpace, MethodsGetArgumentProperties) {
    AddressSpace as = loadedSpace();
    ASSERT_TRUE(as.addObject(NodeId(ns0::ObjectsFolder), NodeId(1, "Calc"), "Calc").ok());
    std::vector<Argument> in{{"a", NodeId(ns0::Double), -1, {}, {}},
                             {"b", NodeId(ns0::Double), -1, {}, {}}};
    std::vector<Argument> out{{"sum", NodeId(ns0::Double), -1, {}, {"", "a+b"}}};
    auto m = as.addMethod(NodeId(1, "Calc"), NodeId(1, "Calc.Add"), "Add", in, out,
                          [](const Caller&, const NodeId&, std::span<const Variant>,
                             std::vector<Variant>&) { return status::Good; });
    ASSERT_TRUE(m.ok());
    const Node* calc = as.find(NodeId(1, "Calc"));
    EXPECT_TRUE(hasRef(*calc, ns0::HasComponent, NodeId(1, "Calc.Add"), true));
    const Node* inProp = as.findChild(NodeId(1, "Calc.Add"), QualifiedName{0, "InputArguments"});
    ASSERT_NE(inProp, nullptr);
    EXPECT_EQ(inProp->nodeId, NodeId(1, "Calc.Add/InputArguments"));
    EXPECT_EQ(inProp->dataType, NodeId(ns0::ArgumentType));
    EXPECT_EQ(as.typeDefinitionOf(*inProp), NodeId(ns0::PropertyType));
    ASSERT_TRUE(inProp->value.value->isArray());
    const auto& eo = std::get<ExtensionObject>(inProp->value.value->elements()[0]);
    EXPECT_EQ(eo.typeId, NodeId(298));
    auto args = as.methodArguments(NodeId(1, "Calc.Add"), "InputArguments");
    ASSERT_TRUE(args.ok());
    EXPECT_EQ(*args, in);
    auto outs = as.methodArguments(NodeId(1, "Calc.Add"), "OutputArguments");
    ASSERT_TRUE(outs.ok());
    EXPECT_EQ(*outs, out);
}

TEST(AddressSpace, ChildNodeIds) {
    EXPECT_EQ(AddressSpace::childNodeId(NodeId(2, "M"), "InputArguments"),
              NodeId(2, "M/InputArguments"));
    EXPECT_EQ(AddressSpace::childNodeId(NodeId(3, 17), "X"), NodeId(3, "i=17/X"));
}

TEST(ServerObject, NamespaceArrayIsAStringArrayOnTheWire) {
    AddressSpace as = loadedSpace();
    ServerInfo info;
    info.applicationUri = "urn:a";
    info.productUri = "urn:p";
    info.productName = "skillcell";
    info.softwareVersion = "0.1.0";
    info.startTime = DateTime::now();
    ASSERT_EQ(installServerObject(as, info), status::Good);
    const Node* ns = as.find(NodeId(ns0::Server_NamespaceArray));
    const DataValue dv = as.readValue(*ns);
    ASSERT_TRUE(dv.value.has_value());
    // Variant: mask 0x8C (String | array), Int32 length 2, then two Strings.
    std::vector<std::uint8_t> expected{0x8C, 2, 0, 0, 0, 28, 0, 0, 0};
    for (char c : std::string("http://opcfoundation.org/UA/")) expected.push_back(std::uint8_t(c));
    for (std::uint8_t b : {0x05, 0x00, 0x00, 0x00}) expected.push_back(b);
    for (char c : std::string("urn:a")) expected.push_back(std::uint8_t(c));
    EXPECT_EQ(encodeToBytes(*dv.value), expected);

    const DataValue status = as.readValue(*as.find(NodeId(ns0::Server_ServerStatus)));
    const auto* eo = status.value->get<ExtensionObject>();
    ASSERT_NE(eo, nullptr);
    ServerStatusDataType st;
    ASSERT_EQ(fromExtensionObject(*eo, st), status::Good);
    EXPECT_EQ(st.state, ServerState::Running);
    EXPECT_EQ(st.buildInfo.productName, "skillcell");
    EXPECT_EQ(st.startTime, info.startTime);
    const DataValue state = as.readValue(*as.find(NodeId(ns0::Server_ServerStatus_State)));
    EXPECT_EQ(*state.value, Variant(std::int32_t{0}));
    const DataValue name =
        as.readValue(*as.find(NodeId(ns0::Server_ServerStatus_BuildInfo_ProductName)));
    EXPECT_EQ(*name.value, Variant("skillcell"));
}

TEST(ServerObject, NeedsTheBaseNodeSet) {
    AddressSpace as;
    EXPECT_EQ(installServerObject(as, ServerInfo{}), status::BadNodeIdUnknown);
}

}  // namespace address_space_test
