// DynamicStructure: structures defined only by a model's <Definition> encode and decode in
// binary byte-exactly, values in the XML encoding load through them, truncated bytes are
// BadDecodingError, and DataType nodes answer the DataTypeDefinition attribute.
#include <gtest/gtest.h>

#include "ua/address_space/dynamic_structure.hpp"
#include "ua/nodeset/embedded_models.hpp"

namespace dynamic_structure_test {

using namespace skillcell::ua;

namespace {

// A frame-like type with a nested structure, an array of structures, a string array and an
// enumeration; an optional-field structure; a union. ns=1 of the file maps to 2.
constexpr std::string_view kModel = R"(<?xml version="1.0"?>
<UANodeSet xmlns="http://opcfoundation.org/UA/2011/03/UANodeSet.xsd"
           xmlns:uax="http://opcfoundation.org/UA/2008/02/Types.xsd">
  <NamespaceUris><Uri>urn:test:geometry</Uri></NamespaceUris>
  <Models>
    <Model ModelUri="urn:test:geometry" Version="1.0.0" PublicationDate="2025-01-01T00:00:00Z">
      <RequiredModel ModelUri="http://opcfoundation.org/UA/" Version="1.05.00"/>
    </Model>
  </Models>
  <Aliases>
    <Alias Alias="Double">i=11</Alias>
    <Alias Alias="String">i=12</Alias>
    <Alias Alias="HasSubtype">i=45</Alias>
    <Alias Alias="HasEncoding">i=38</Alias>
  </Aliases>
  <UADataType NodeId="ns=1;i=1" BrowseName="1:Vec">
    <References>
      <Reference ReferenceType="HasSubtype" IsForward="false">i=22</Reference>
      <Reference ReferenceType="HasEncoding">ns=1;i=101</Reference>
    </References>
    <Definition Name="1:Vec">
      <Field Name="X" DataType="Double"/>
      <Field Name="Y" DataType="Double"/>
      <Field Name="Z" DataType="Double"/>
    </Definition>
  </UADataType>
  <UADataType NodeId="ns=1;i=2" BrowseName="1:Kind">
    <References><Reference ReferenceType="HasSubtype" IsForward="false">i=29</Reference></References>
    <Definition Name="1:Kind">
      <Field Name="Parallel" Value="0"/>
      <Field Name="Vacuum" Value="1"/>
    </Definition>
  </UADataType>
  <UADataType NodeId="ns=1;i=3" BrowseName="1:Pose">
    <References>
      <Reference ReferenceType="HasSubtype" IsForward="false">i=22</Reference>
      <Reference ReferenceType="HasEncoding">ns=1;i=103</Reference>
    </References>
    <Definition Name="1:Pose">
      <Field Name="Name" DataType="String"/>
      <Field Name="Position" DataType="ns=1;i=1"/>
      <Field Name="Path" DataType="ns=1;i=1" ValueRank="1"/>
      <Field Name="Tags" DataType="String" ValueRank="1"/>
      <Field Name="Kind" DataType="ns=1;i=2"/>
      <Field Name="Speed" DataType="i=290"/>
    </Definition>
  </UADataType>
  <UADataType NodeId="ns=1;i=4" BrowseName="1:Limits">
    <References>
      <Reference ReferenceType="HasSubtype" IsForward="false">i=22</Reference>
      <Reference ReferenceType="HasEncoding">ns=1;i=104</Reference>
    </References>
    <Definition Name="1:Limits">
      <Field Name="Max" DataType="Double"/>
      <Field Name="Min" DataType="Double" IsOptional="true"/>
      <Field Name="Unit" DataType="String" IsOptional="true"/>
    </Definition>
  </UADataType>
  <UADataType NodeId="ns=1;i=5" BrowseName="1:Choice">
    <References>
      <Reference ReferenceType="HasSubtype" IsForward="false">i=22</Reference>
      <Reference ReferenceType="HasEncoding">ns=1;i=105</Reference>
    </References>
    <Definition Name="1:Choice" IsUnion="true">
      <Field Name="Number" DataType="Double"/>
      <Field Name="Text" DataType="String"/>
    </Definition>
  </UADataType>
  <UAObject NodeId="ns=1;i=101" BrowseName="Default Binary"><References><Reference ReferenceType="i=40">i=76</Reference></References></UAObject>
  <UAObject NodeId="ns=1;i=103" BrowseName="Default Binary"><References><Reference ReferenceType="i=40">i=76</Reference></References></UAObject>
  <UAObject NodeId="ns=1;i=104" BrowseName="Default Binary"><References><Reference ReferenceType="i=40">i=76</Reference></References></UAObject>
  <UAObject NodeId="ns=1;i=105" BrowseName="Default Binary"><References><Reference ReferenceType="i=40">i=76</Reference></References></UAObject>
  <UAVariable NodeId="ns=1;s=Home" BrowseName="1:Home" DataType="ns=1;i=3">
    <References><Reference ReferenceType="i=47" IsForward="false">i=85</Reference></References>
    <Value>
      <uax:ExtensionObject>
        <uax:TypeId><uax:Identifier>ns=1;i=103</uax:Identifier></uax:TypeId>
        <uax:Body>
          <uax:Pose>
            <uax:Name>home</uax:Name>
            <uax:Position><uax:X>1</uax:X><uax:Y>2</uax:Y><uax:Z>3.5</uax:Z></uax:Position>
            <uax:Path>
              <uax:Vec><uax:X>4</uax:X><uax:Y>5</uax:Y><uax:Z>6</uax:Z></uax:Vec>
              <uax:Vec><uax:X>7</uax:X></uax:Vec>
            </uax:Path>
            <uax:Tags><uax:String>a</uax:String><uax:String>b</uax:String></uax:Tags>
            <uax:Kind>Vacuum_1</uax:Kind>
            <uax:Speed>0.25</uax:Speed>
          </uax:Pose>
        </uax:Body>
      </uax:ExtensionObject>
    </Value>
  </UAVariable>
</UANodeSet>)";

struct Fixture {
    AddressSpace as{"urn:test:server"};
    Fixture() {
        auto st = loadBaseNodeSet(as);
        EXPECT_TRUE(st.ok()) << st.error;
        st = loadNodeSet(as, kModel, "geometry.xml");
        EXPECT_TRUE(st.ok()) << st.error;
    }
};

ExtensionObject vecEo(const DataTypeRegistry& types, double x, double y, double z) {
    auto v = defaultStructure(types, NodeId(2, 1u));
    EXPECT_TRUE(v.ok());
    v->set("X", x);
    v->set("Y", y);
    v->set("Z", z);
    auto eo = toExtensionObject(types, *v);
    EXPECT_TRUE(eo.ok());
    return *eo;
}

}  // namespace

TEST(DynamicStructure, EncodesAndDecodesByteExactly) {
    Fixture f;
    const auto& types = f.as.dataTypes();
    auto pose = defaultStructure(types, NodeId(2, 3u));
    ASSERT_TRUE(pose.ok()) << statusName(pose.status());
    ASSERT_EQ(pose->fields.size(), 6u);
    pose->set("Name", "p1");
    pose->set("Position", vecEo(types, 1, 2, 3));
    pose->set("Path", Variant::array(std::vector<ExtensionObject>{vecEo(types, 4, 5, 6)}));
    pose->set("Tags", Variant::array(std::vector<String>{"x"}));
    pose->set("Kind", std::int32_t{1});
    pose->set("Speed", 0.5);

    std::vector<std::uint8_t> bytes;
    BinaryWriter w(bytes);
    ASSERT_TRUE(encodeStructure(w, types, *pose).isGood());

    // The same bytes written by hand, field by field.
    std::vector<std::uint8_t> expected;
    BinaryWriter e(expected);
    encode(e, String("p1"));
    for (double d : {1.0, 2.0, 3.0}) encode(e, d);
    encode(e, std::int32_t{1});
    for (double d : {4.0, 5.0, 6.0}) encode(e, d);
    encode(e, std::vector<String>{"x"});
    encode(e, std::int32_t{1});
    encode(e, 0.5);
    EXPECT_EQ(bytes, expected);

    BinaryReader r(bytes);
    DynamicStructure back;
    ASSERT_TRUE(decodeStructure(r, types, NodeId(2, 3u), back).isGood());
    EXPECT_EQ(r.remaining(), 0u);
    EXPECT_EQ(back, *pose);

    // Every truncation is a decoding error, never a crash or a partial success.
    for (std::size_t n = 0; n < bytes.size(); ++n) {
        BinaryReader t(std::span<const std::uint8_t>(bytes.data(), n));
        DynamicStructure out;
        EXPECT_EQ(decodeStructure(t, types, NodeId(2, 3u), out), status::BadDecodingError) << n;
    }
    // Through an ExtensionObject, with trailing garbage refused.
    auto eo = toExtensionObject(types, *pose);
    ASSERT_TRUE(eo.ok());
    EXPECT_EQ(eo->typeId, NodeId(2, 103u));
    auto again = fromExtensionObject(types, *eo);
    ASSERT_TRUE(again.ok());
    EXPECT_EQ(*again, *pose);
    eo->body.bytes.push_back(0);
    EXPECT_EQ(fromExtensionObject(types, *eo).status(), status::BadDecodingError);
    // A huge array length is refused before anything is allocated.
    std::vector<std::uint8_t> bad = expected;
    bad[6 + 24] = 0xFF;
    bad[6 + 24 + 1] = 0xFF;
    bad[6 + 24 + 2] = 0xFF;
    bad[6 + 24 + 3] = 0x7F;
    BinaryReader br(bad);
    DynamicStructure out;
    EXPECT_EQ(decodeStructure(br, types, NodeId(2, 3u), out), status::BadDecodingError);
    // A value that does not fit the definition is refused on encode.
    pose->set("Speed", "fast");
    std::vector<std::uint8_t> sink;
    BinaryWriter ws(sink);
    EXPECT_EQ(encodeStructure(ws, types, *pose), status::BadEncodingError);
}

TEST(DynamicStructure, OptionalFieldsAndUnions) {
    Fixture f;
    const auto& types = f.as.dataTypes();
    auto limits = defaultStructure(types, NodeId(2, 4u));
    ASSERT_TRUE(limits.ok());
    limits->set("Max", 2.0);
    limits->set("Unit", "mm");
    auto bytes = [&](const DynamicStructure& s) {
        std::vector<std::uint8_t> out;
        BinaryWriter w(out);
        EXPECT_TRUE(encodeStructure(w, types, s).isGood());
        return out;
    };
    std::vector<std::uint8_t> expected;
    BinaryWriter e(expected);
    encode(e, std::uint32_t{0b10});  // Min absent, Unit present
    encode(e, 2.0);
    encode(e, String("mm"));
    EXPECT_EQ(bytes(*limits), expected);
    BinaryReader r(expected);
    DynamicStructure back;
    ASSERT_TRUE(decodeStructure(r, types, NodeId(2, 4u), back).isGood());
    EXPECT_EQ(back, *limits);
    EXPECT_TRUE(back.get("Min")->isEmpty());

    auto choice = defaultStructure(types, NodeId(2, 5u));
    ASSERT_TRUE(choice.ok());
    choice->set("Text", "hi");
    std::vector<std::uint8_t> u;
    BinaryWriter uw(u);
    encode(uw, std::uint32_t{2});
    encode(uw, String("hi"));
    EXPECT_EQ(bytes(*choice), u);
    u[0] = 7;  // no such field
    BinaryReader ur(u);
    EXPECT_EQ(decodeStructure(ur, types, NodeId(2, 5u), back), status::BadDecodingError);
}

TEST(DynamicStructure, XmlValuesAndNamespaceZeroFrames) {
    Fixture f;
    const auto& types = f.as.dataTypes();
    const Node* home = f.as.find(NodeId(3, "Home"));  // the file's ns=1 is server ns 3
    if (home == nullptr) home = f.as.find(NodeId(2, "Home"));
    ASSERT_NE(home, nullptr);
    const auto* eo = home->value.value->get<ExtensionObject>();
    ASSERT_NE(eo, nullptr);
    auto pose = fromExtensionObject(types, *eo);
    ASSERT_TRUE(pose.ok()) << statusName(pose.status());
    EXPECT_EQ(*pose->get("Name"), Variant("home"));
    EXPECT_EQ(*pose->get("Kind"), Variant(std::int32_t{1}));
    EXPECT_EQ(*pose->get("Speed"), Variant(0.25));
    EXPECT_EQ(pose->get("Path")->elements().size(), 2u);
    auto position =
        fromExtensionObject(types, std::get<ExtensionObject>(pose->get("Position")->scalar()));
    ASSERT_TRUE(position.ok());
    EXPECT_EQ(*position->get("Z"), Variant(3.5));
    auto second =
        fromExtensionObject(types, std::get<ExtensionObject>(pose->get("Path")->elements()[1]));
    ASSERT_TRUE(second.ok());
    EXPECT_EQ(*second->get("X"), Variant(7.0));
    EXPECT_EQ(*second->get("Y"), Variant(0.0));  // missing field: default

    // The standard's 3D frame: two nested structures of three Doubles, 48 bytes.
    auto frame = defaultStructure(types, NodeId(18814u));
    ASSERT_TRUE(frame.ok());
    auto frameEo = toExtensionObject(types, *frame);
    ASSERT_TRUE(frameEo.ok());
    EXPECT_EQ(frameEo->typeId, NodeId(18823u));
    EXPECT_EQ(frameEo->body.bytes.size(), 48u);

    // DataTypeDefinition attribute values.
    const Node* frameType = f.as.find(NodeId(18814u));
    ASSERT_NE(frameType, nullptr);
    const Variant def = dataTypeDefinitionValue(frameType->definition);
    const auto* defEo = def.get<ExtensionObject>();
    ASSERT_NE(defEo, nullptr);
    EXPECT_EQ(defEo->typeId, NodeId(122u));
    StructureDefinition sd;
    ASSERT_TRUE(fromExtensionObject(*defEo, sd).isGood());
    ASSERT_EQ(sd.fields.size(), 2u);
    EXPECT_EQ(sd.fields[0].name, "CartesianCoordinates");
    EXPECT_EQ(sd.fields[0].dataType, NodeId(18810u));
    EXPECT_EQ(sd.defaultEncodingId, NodeId(18823u));
    EXPECT_EQ(sd.baseDataType, NodeId(18813u));
    const Node* kind =
        f.as.find(NodeId(3, 2u)) ? f.as.find(NodeId(3, 2u)) : f.as.find(NodeId(2, 2u));
    ASSERT_NE(kind, nullptr);
    const Variant kdef = dataTypeDefinitionValue(kind->definition);
    ASSERT_NE(kdef.get<ExtensionObject>(), nullptr);
    EXPECT_EQ(kdef.get<ExtensionObject>()->typeId, NodeId(123u));
    // Argument values of namespace 0 decode through Argument's model definition too.
    EXPECT_TRUE(types.structureOf(NodeId(ns0::ArgumentType)) != nullptr);
    EXPECT_EQ(types.builtinTypeOf(NodeId(ns0::Duration)), BuiltinType::Double);
    EXPECT_EQ(types.builtinTypeOf(NodeId(2, 2u)), BuiltinType::Int32);
}

}  // namespace dynamic_structure_test
