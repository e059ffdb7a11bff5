// NodeSet2 loader: the embedded namespace 0 subset, a companion-style file with its own
// namespace, aliases and values, and precise errors (with line numbers) for bad files.
#include <gtest/gtest.h>

#include <chrono>
#include <cstdio>

#include "ua/encoding/codec.hpp"
#include "ua/nodeset/embedded_models.hpp"
#include "ua/nodeset/nodeset_loader.hpp"

namespace nodeset_test {

using namespace skillcell::ua;

namespace {

constexpr std::string_view kDemo = R"(<?xml version="1.0" encoding="utf-8"?>
<UANodeSet xmlns="http://opcfoundation.org/UA/2011/03/UANodeSet.xsd"
           xmlns:uax="http://opcfoundation.org/UA/2008/02/Types.xsd">
  <NamespaceUris>
    <Uri>urn:test:demo</Uri>
  </NamespaceUris>
  <Aliases>
    <Alias Alias="Double">i=11</Alias>
    <Alias Alias="String">i=12</Alias>
    <Alias Alias="Argument">i=296</Alias>
    <Alias Alias="Organizes">i=35</Alias>
    <Alias Alias="HasComponent">i=47</Alias>
    <Alias Alias="HasProperty">i=46</Alias>
    <Alias Alias="HasSubtype">i=45</Alias>
    <Alias Alias="HasTypeDefinition">i=40</Alias>
  </Aliases>
  <UAObjectType NodeId="ns=1;i=1000" BrowseName="1:MachineType" IsAbstract="true">
    <DisplayName Locale="en">MachineType</DisplayName>
    <Description>A machine.</Description>
    <References>
      <Reference ReferenceType="HasSubtype" IsForward="false">i=58</Reference>
    </References>
  </UAObjectType>
  <UAObject NodeId="ns=1;s=Machine" BrowseName="1:Machine" EventNotifier="1">
    <DisplayName>Machine</DisplayName>
    <References>
      <Reference ReferenceType="Organizes" IsForward="false">i=85</Reference>
      <Reference ReferenceType="HasTypeDefinition">ns=1;i=1000</Reference>
      <Reference ReferenceType="HasComponent">ns=1;s=Machine.Speed</Reference>
    </References>
  </UAObject>
  <UAVariable NodeId="ns=1;s=Machine.Speed" BrowseName="1:Speed" DataType="Double"
              AccessLevel="3" UserAccessLevel="3" MinimumSamplingInterval="100" Historizing="false">
    <DisplayName>Speed</DisplayName>
    <References>
      <Reference ReferenceType="HasComponent" IsForward="false">ns=1;s=Machine</Reference>
      <Reference ReferenceType="HasTypeDefinition">i=63</Reference>
    </References>
    <Value><uax:Double>1.25</uax:Double></Value>
  </UAVariable>
  <UAVariable NodeId="ns=1;s=Machine.Tags" BrowseName="1:Tags" DataType="String" ValueRank="1"
              ArrayDimensions="2" ParentNodeId="ns=1;s=Machine">
    <DisplayName>Tags</DisplayName>
    <References>
      <Reference ReferenceType="HasProperty" IsForward="false">ns=1;s=Machine</Reference>
    </References>
    <Value>
      <uax:ListOfString>
        <uax:String>a</uax:String>
        <uax:String>b</uax:String>
      </uax:ListOfString>
    </Value>
  </UAVariable>
  <UAVariable NodeId="ns=1;i=7" BrowseName="1:Misc" DataType="i=24" ValueRank="-2">
    <DisplayName>Misc</DisplayName>
    <Value>
      <uax:ListOfLocalizedText>
        <uax:LocalizedText><uax:Locale>de</uax:Locale><uax:Text>Hallo</uax:Text></uax:LocalizedText>
      </uax:ListOfLocalizedText>
    </Value>
  </UAVariable>
  <UAVariable NodeId="ns=1;i=8" BrowseName="1:Qn" DataType="i=20"><DisplayName>Qn</DisplayName>
    <Value><uax:QualifiedName><uax:NamespaceIndex>1</uax:NamespaceIndex><uax:Name>X</uax:Name></uax:QualifiedName></Value>
  </UAVariable>
  <UAVariable NodeId="ns=1;i=9" BrowseName="1:Id" DataType="i=17"><DisplayName>Id</DisplayName>
    <Value><uax:NodeId><uax:Identifier>ns=1;i=1000</uax:Identifier></uax:NodeId></Value>
  </UAVariable>
  <UAVariable NodeId="ns=1;i=10" BrowseName="1:When" DataType="i=13"><DisplayName>When</DisplayName>
    <Value><uax:DateTime>1970-01-02T00:00:01.5Z</uax:DateTime></Value>
  </UAVariable>
  <UAVariable NodeId="ns=1;i=11" BrowseName="1:Flag" DataType="i=1"><DisplayName>Flag</DisplayName>
    <Value><uax:Boolean>true</uax:Boolean></Value>
  </UAVariable>
  <UAMethod NodeId="ns=1;s=Machine.Start" BrowseName="1:Start" Executable="false">
    <DisplayName>Start</DisplayName>
    <References>
      <Reference ReferenceType="HasComponent" IsForward="false">ns=1;s=Machine</Reference>
      <Reference ReferenceType="HasProperty">ns=1;s=Machine.Start.In</Reference>
    </References>
  </UAMethod>
  <UAVariable NodeId="ns=1;s=Machine.Start.In" BrowseName="InputArguments" DataType="Argument"
              ValueRank="1" ArrayDimensions="1">
    <DisplayName>InputArguments</DisplayName>
    <References>
      <Reference ReferenceType="HasTypeDefinition">i=68</Reference>
    </References>
    <Value>
      <uax:ListOfExtensionObject>
        <uax:ExtensionObject>
          <uax:TypeId><uax:Identifier>i=297</uax:Identifier></uax:TypeId>
          <uax:Body>
            <uax:Argument>
              <uax:Name>Speed</uax:Name>
              <uax:DataType><uax:Identifier>i=11</uax:Identifier></uax:DataType>
              <uax:ValueRank>-1</uax:ValueRank>
              <uax:ArrayDimensions />
              <uax:Description><uax:Locale>en</uax:Locale><uax:Text>Target speed</uax:Text></uax:Description>
            </uax:Argument>
          </uax:Body>
        </uax:ExtensionObject>
      </uax:ListOfExtensionObject>
    </Value>
  </UAVariable>
</UANodeSet>
)";

AddressSpace baseSpace() {
    AddressSpace as("urn:test:server");
    const auto st = loadBaseNodeSet(as);
    EXPECT_TRUE(st.ok()) << st.error;
    return as;
}

/// A minimal file with one extra line placed at line 5.
std::string withBody(std::string_view body) {
    return std::string(R"(<?xml version="1.0"?>
<UANodeSet xmlns="http://opcfoundation.org/UA/2011/03/UANodeSet.xsd">
  <NamespaceUris><Uri>urn:bad</Uri></NamespaceUris>
  <Aliases><Alias Alias="Organizes">i=35</Alias></Aliases>
)") + std::string(body) +
           "\n</UANodeSet>\n";
}

std::string loadError(std::string_view xml) {
    AddressSpace as = baseSpace();
    const auto before = as.size();
    const auto st = loadNodeSet(as, xml, "models/x.xml");
    EXPECT_EQ(as.size(), before) << "a failed load must not change the address space";
    return st.error;
}

}  // namespace

TEST(NodeSet, BaseNodeSetIsEmbeddedAndLoadsFast) {
    const auto names = embeddedModelNames();
    ASSERT_FALSE(names.empty());
    EXPECT_FALSE(embeddedModel("Opc.Ua.NodeSet2.Base.xml").empty());
    EXPECT_TRUE(embeddedModel("nope.xml").empty());

    AddressSpace as("urn:test:server");
    const auto t0 = std::chrono::steady_clock::now();
    const auto st = loadBaseNodeSet(as);
    const auto t1 = std::chrono::steady_clock::now();
    ASSERT_TRUE(st.ok()) << st.error;
    // Reported, not asserted: machine speed varies.
    std::printf(
        "[ timing ] loading Opc.Ua.NodeSet2.Base.xml: %zu nodes, %zu references in %.3f ms\n",
        st.nodes, st.references, std::chrono::duration<double, std::milli>(t1 - t0).count());
    EXPECT_GT(st.nodes, 100u);
}

TEST(NodeSet, BaseNodeSetContent) {
    AddressSpace as = baseSpace();
    const Node* server = as.find(NodeId(ns0::Server));
    ASSERT_NE(server, nullptr);
    EXPECT_EQ(server->browseName, (QualifiedName{0, "Server"}));
    EXPECT_EQ(server->eventNotifier, 1);
    EXPECT_EQ(as.typeDefinitionOf(*server), NodeId(ns0::ServerType));
    const Node* hasSubtype = as.find(NodeId(ns0::HasSubtype));
    ASSERT_NE(hasSubtype, nullptr);
    EXPECT_EQ(hasSubtype->nodeClass, NodeClass::ReferenceType);
    EXPECT_EQ(hasSubtype->inverseName.text, "SubtypeOf");
    EXPECT_TRUE(as.find(NodeId(ns0::References))->symmetric);
    EXPECT_TRUE(as.find(NodeId(ns0::References))->isAbstract);
    const Node* nsArray = as.find(NodeId(ns0::Server_NamespaceArray));
    EXPECT_EQ(nsArray->dataType, NodeId(ns0::String));
    EXPECT_EQ(nsArray->valueRank, 1);
    EXPECT_EQ(nsArray->minimumSamplingInterval, 1000.0);
    const Node* locales = as.find(NodeId(ns0::Server_ServerCapabilities_LocaleIdArray));
    EXPECT_EQ(*locales->value.value, Variant::array(std::vector<String>{"en"}));
    EXPECT_EQ(as.findChild(NodeId(ns0::RootFolder), QualifiedName{0, "Objects"})->nodeId,
              NodeId(ns0::ObjectsFolder));
    // HasEncoding is not hierarchical: the encoding is no child, but a reference.
    EXPECT_EQ(as.findChild(NodeId(ns0::ArgumentType), QualifiedName{0, "Default Binary"}), nullptr);
    const auto& argRefs = as.find(NodeId(ns0::ArgumentType))->references;
    EXPECT_NE(std::find(argRefs.begin(), argRefs.end(),
                        Reference{NodeId(ns0::HasEncoding),
                                  NodeId(ns0::Argument_Encoding_DefaultBinary), true}),
              argRefs.end());
}

TEST(NodeSet, CompanionFileWithNamespaceAliasesAndValues) {
    AddressSpace as = baseSpace();
    (void)as.registerNamespace("urn:other");  // index 2: the file's ns=1 must map to 3
    const auto st = loadNodeSet(as, kDemo, "demo.xml");
    ASSERT_TRUE(st.ok()) << st.error;
    EXPECT_EQ(as.namespaceIndex("urn:test:demo"), std::optional<std::uint16_t>(3));

    const Node* machine = as.find(NodeId(3, "Machine"));
    ASSERT_NE(machine, nullptr);
    EXPECT_EQ(machine->browseName, (QualifiedName{3, "Machine"}));
    EXPECT_EQ(as.typeDefinitionOf(*machine), NodeId(3, 1000));
    EXPECT_TRUE(as.isSubtypeOf(NodeId(3, 1000), NodeId(ns0::BaseObjectType)));
    EXPECT_TRUE(as.find(NodeId(3, 1000))->isAbstract);
    EXPECT_EQ(as.find(NodeId(3, 1000))->description.text, "A machine.");
    EXPECT_EQ(as.find(NodeId(3, 1000))->displayName.locale, "en");

    const Node* speed = as.find(NodeId(3, "Machine.Speed"));
    ASSERT_NE(speed, nullptr);
    EXPECT_EQ(speed->dataType, NodeId(ns0::Double));
    EXPECT_EQ(speed->accessLevel, 3);
    EXPECT_EQ(speed->minimumSamplingInterval, 100.0);
    EXPECT_EQ(*speed->value.value, Variant(1.25));
    // The reverse side of a reference listed only once is there.
    const Node* objects = as.find(NodeId(ns0::ObjectsFolder));
    EXPECT_NE(std::find(objects->references.begin(), objects->references.end(),
                        Reference{NodeId(ns0::Organizes), NodeId(3, "Machine"), true}),
              objects->references.end());
    // Listed at both ends: stored once per end.
    EXPECT_EQ(std::count(machine->references.begin(), machine->references.end(),
                         Reference{NodeId(ns0::HasComponent), NodeId(3, "Machine.Speed"), true}),
              1);

    const Node* tags = as.find(NodeId(3, "Machine.Tags"));
    EXPECT_EQ(*tags->value.value, Variant::array(std::vector<String>{"a", "b"}));
    EXPECT_EQ(tags->arrayDimensions, std::vector<std::uint32_t>{2});
    EXPECT_EQ(*as.find(NodeId(3, 7))->value.value,
              Variant::array(std::vector<LocalizedText>{{"de", "Hallo"}}));
    EXPECT_EQ(*as.find(NodeId(3, 8))->value.value, Variant(QualifiedName{3, "X"}));
    EXPECT_EQ(*as.find(NodeId(3, 9))->value.value, Variant(NodeId(3, 1000)));
    EXPECT_EQ(*as.find(NodeId(3, 10))->value.value,
              Variant(DateTime::fromUnixNanoseconds(86'401'500'000'000LL)));
    EXPECT_EQ(*as.find(NodeId(3, 11))->value.value, Variant(true));

    EXPECT_FALSE(as.find(NodeId(3, "Machine.Start"))->executable);
    auto args = as.methodArguments(NodeId(3, "Machine.Start"), "InputArguments");
    ASSERT_TRUE(args.ok());
    ASSERT_EQ(args->size(), 1u);
    EXPECT_EQ((*args)[0].name, "Speed");
    EXPECT_EQ((*args)[0].dataType, NodeId(ns0::Double));
    EXPECT_EQ((*args)[0].description.text, "Target speed");
}

TEST(NodeSet, LoadsFromAPath) {
    AddressSpace as("urn:test:server");
    const auto st = loadNodeSetFile(as, SKILLCELL_MODELS_DIR "/Opc.Ua.NodeSet2.Base.xml");
    EXPECT_TRUE(st.ok()) << st.error;
    const auto missing = loadNodeSetFile(as, "/nonexistent/x.xml");
    EXPECT_EQ(missing.error, "/nonexistent/x.xml: cannot open file");
}

TEST(NodeSet, UnknownAlias) {
    EXPECT_EQ(loadError(withBody(R"(  <UAObject NodeId="ns=1;i=1" BrowseName="1:A">
    <References><Reference ReferenceType="Foo">i=85</Reference></References></UAObject>)")),
              "models/x.xml:6: unknown alias 'Foo'");
}

TEST(NodeSet, MalformedXml) {
    EXPECT_EQ(
        loadError(withBody("  <UAObject NodeId=\"ns=1;i=1\" BrowseName=\"1:A\">\n  </UAObjekt>")),
        "models/x.xml:6: malformed XML: Start-end tags mismatch");
}

TEST(NodeSet, BadNodeIdText) {
    EXPECT_EQ(loadError(withBody(R"(  <UAObject NodeId="ns=1;x=1" BrowseName="1:A"/>)")),
              "models/x.xml:5: bad NodeId 'ns=1;x=1'");
    EXPECT_EQ(loadError(withBody(R"(  <UAObject NodeId="ns=4;i=1" BrowseName="1:A"/>)")),
              "models/x.xml:5: namespace index 4 is not declared in NamespaceUris");
}

TEST(NodeSet, UnknownReferenceTypeAndTarget) {
    EXPECT_EQ(loadError(withBody(R"(  <UAObject NodeId="ns=1;i=1" BrowseName="1:A">
    <References>
      <Reference ReferenceType="i=85">i=84</Reference>
    </References>
  </UAObject>)")),
              "models/x.xml:7: unknown reference type i=85");
    EXPECT_EQ(loadError(withBody(R"(  <UAObject NodeId="ns=1;i=1" BrowseName="1:A">
    <References><Reference ReferenceType="Organizes">ns=1;i=99</Reference></References>
  </UAObject>)")),
              "models/x.xml:6: reference to unknown node ns=2;i=99");
}

TEST(NodeSet, OtherErrors) {
    EXPECT_EQ(loadError(withBody(R"(  <UAObject NodeId="i=85" BrowseName="Objects"/>)")),
              "models/x.xml:5: node i=85 already exists in the address space");
    EXPECT_EQ(loadError(withBody("  <UAObject NodeId=\"ns=1;i=1\" BrowseName=\"1:A\"/>\n"
                                 "  <UAObject NodeId=\"ns=1;i=1\" BrowseName=\"1:B\"/>")),
              "models/x.xml:6: duplicate node ns=2;i=1");
    EXPECT_EQ(
        loadError(withBody(R"(  <UAVariable NodeId="ns=1;i=1" BrowseName="1:A" ValueRank="x"/>)")),
        "models/x.xml:5: bad ValueRank 'x'");
    EXPECT_EQ(
        loadError(withBody(
            R"(  <UAVariable NodeId="ns=1;i=1" BrowseName="1:A"><Value><Int32>z</Int32></Value></UAVariable>)")),
        "models/x.xml:5: bad Int32 value 'z'");
    EXPECT_EQ(loadError(withBody(R"(  <UAThing NodeId="ns=1;i=1" BrowseName="1:A"/>)")),
              "models/x.xml:5: unexpected element 'UAThing'");
    EXPECT_EQ(loadError(withBody(R"(  <UAObject NodeId="ns=1;i=1"/>)")),
              "models/x.xml:5: node ns=2;i=1 without BrowseName");
    EXPECT_EQ(loadError("<Nodes/>"),
              "models/x.xml:1: root element is 'Nodes', expected 'UANodeSet'");
}

// The OPC Foundation's own DI, IA and Robotics NodeSets (models/opcfoundation/) load over
// namespace 0 as loadBaseNodeSet loads it: our subset plus the nodes they use from the
// Foundation's (Opc.Ua.NodeSet2.Closure.xml).
TEST(NodeSet, TheOpcFoundationsDiIaAndRoboticsModelsLoad) {
    AddressSpace as = baseSpace();
    EXPECT_NE(as.find(NodeId(11575)), nullptr) << "FileType, from the closure";
    for (const char* name :
         {"Opc.Ua.Di.NodeSet2.xml", "Opc.Ua.IA.NodeSet2.xml", "Opc.Ua.Robotics.NodeSet2.xml"}) {
        const auto t0 = std::chrono::steady_clock::now();
        const auto st = loadNodeSet(as, embeddedModel(name), name);
        const auto t1 = std::chrono::steady_clock::now();
        ASSERT_TRUE(st.ok()) << st.error;
        std::printf("[ timing ] loading %s: %zu nodes, %zu references in %.3f ms\n", name, st.nodes,
                    st.references, std::chrono::duration<double, std::milli>(t1 - t0).count());
    }
}

}  // namespace nodeset_test
