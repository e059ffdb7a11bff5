// Byte-exact vectors for every built-in type (OPC 10000-6, 5.2), and the decoder's refusal
// of malformed or oversized input.
#include <gtest/gtest.h>

#include <cstdint>
#include <vector>

#include "ua/encoding/codec.hpp"
#include "ua/messages/common.hpp"

namespace encoding_test {

using namespace skillcell::ua;
using Bytes = std::vector<std::uint8_t>;

namespace {

template <class T>
void expectRoundTrip(const T& value, const Bytes& wire) {
    EXPECT_EQ(encodeToBytes(value), wire);
    T decoded{};
    ASSERT_EQ(decodeFromBytes(wire, decoded), status::Good);
    EXPECT_TRUE(decoded == value);
}

template <class T>
StatusCode decodeStatus(const Bytes& wire, DecodeLimits limits = {}) {
    T out{};
    return decodeFromBytes(wire, out, limits);
}

}  // namespace

// One table of names serves the NodeSet loader and exporter, the conformance checker and
// `skillcell browse`: each name leads back to its type, and what has no name says so.
TEST(TypeNames, EveryBuiltinTypeHasTheStandardsNameAndThatNameLeadsBackToIt) {
    for (std::uint8_t id = 1; id <= kMaxBuiltinType; ++id) {
        const auto type = static_cast<BuiltinType>(id);
        const auto name = builtinTypeName(type);
        ASSERT_FALSE(name.empty()) << int(id);
        EXPECT_EQ(builtinTypeByName(name), type) << name;
    }
    EXPECT_EQ(builtinTypeName(BuiltinType::Double), "Double");
    EXPECT_EQ(builtinTypeName(BuiltinType::DiagnosticInfo), "DiagnosticInfo");
    EXPECT_EQ(builtinTypeName(BuiltinType::Null), "Null");
    EXPECT_EQ(builtinTypeName(static_cast<BuiltinType>(kMaxBuiltinType + 1)), "");
    EXPECT_EQ(builtinTypeByName("Null"), std::nullopt);  // no value is of it
    EXPECT_EQ(builtinTypeByName("double"), std::nullopt);
    EXPECT_EQ(builtinTypeByName(""), std::nullopt);
}

TEST(TypeNames, NodeClassesHaveTheirNamesAndNoneIsMadeUpForOtherValues) {
    EXPECT_EQ(nodeClassName(NodeClass::Object), "Object");
    EXPECT_EQ(nodeClassName(NodeClass::VariableType), "VariableType");
    EXPECT_EQ(nodeClassName(NodeClass::View), "View");
    EXPECT_EQ(nodeClassName(NodeClass::Unspecified), "");
    EXPECT_EQ(nodeClassName(static_cast<NodeClass>(3)), "");  // Object | Variable: a filter
}

TEST(Encoding, Numbers) {
    expectRoundTrip(true, {0x01});
    expectRoundTrip(std::int8_t{-2}, {0xFE});
    expectRoundTrip(std::uint8_t{0xAB}, {0xAB});
    expectRoundTrip(std::int16_t{-2}, {0xFE, 0xFF});
    expectRoundTrip(std::uint16_t{0x1234}, {0x34, 0x12});
    expectRoundTrip(std::int32_t{-1000000}, {0xC0, 0xBD, 0xF0, 0xFF});
    expectRoundTrip(std::uint32_t{0x01020304}, {0x04, 0x03, 0x02, 0x01});
    expectRoundTrip(std::int64_t{-2}, {0xFE, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF});
    expectRoundTrip(std::uint64_t{0x0102030405060708},
                    {0x08, 0x07, 0x06, 0x05, 0x04, 0x03, 0x02, 0x01});
    expectRoundTrip(-6.5f, {0x00, 0x00, 0xD0, 0xC0});
    expectRoundTrip(1.5, {0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0xF8, 0x3F});
}

TEST(Encoding, BooleanAcceptsAnyNonZeroByte) {
    bool b = false;
    ASSERT_EQ(decodeFromBytes(Bytes{0x02}, b), status::Good);
    EXPECT_TRUE(b);
}

TEST(Encoding, Strings) {
    expectRoundTrip(String("abc"), {0x03, 0, 0, 0, 'a', 'b', 'c'});
    expectRoundTrip(String(), {0xFF, 0xFF, 0xFF, 0xFF});  // empty travels as null
    String s = "x";
    ASSERT_EQ(decodeFromBytes(Bytes{0, 0, 0, 0}, s), status::Good);  // empty decodes to ""
    EXPECT_EQ(s, "");
    expectRoundTrip(ByteString({1, 2}), {0x02, 0, 0, 0, 1, 2});
    expectRoundTrip(XmlElement{"<a/>"}, {0x04, 0, 0, 0, '<', 'a', '/', '>'});
}

TEST(Encoding, DateTimeAndGuid) {
    expectRoundTrip(DateTime{0x01D2C3B4A5968778}, {0x78, 0x87, 0x96, 0xA5, 0xB4, 0xC3, 0xD2, 0x01});
    // 72962B91-FA75-4AE6-8D28-B404DC7DAF63 (the example of OPC 10000-6, 5.1.3)
    Guid g{0x72962B91, 0xFA75, 0x4AE6, {0x8D, 0x28, 0xB4, 0x04, 0xDC, 0x7D, 0xAF, 0x63}};
    expectRoundTrip(g, {0x91, 0x2B, 0x96, 0x72, 0x75, 0xFA, 0xE6, 0x4A, 0x8D, 0x28, 0xB4, 0x04,
                        0xDC, 0x7D, 0xAF, 0x63});
    EXPECT_EQ(NodeId(0, g).toString(), "g=72962B91-FA75-4AE6-8D28-B404DC7DAF63");
}

TEST(Encoding, NodeIdInAllItsEncodings) {
    expectRoundTrip(NodeId(0, 72u), {0x00, 0x48});                                   // two-byte
    expectRoundTrip(NodeId(5, 1025u), {0x01, 0x05, 0x01, 0x04});                     // four-byte
    expectRoundTrip(NodeId(0, 70000u), {0x02, 0x00, 0x00, 0x70, 0x11, 0x01, 0x00});  // numeric
    expectRoundTrip(NodeId(300, 1u), {0x02, 0x2C, 0x01, 0x01, 0x00, 0x00, 0x00});
    expectRoundTrip(NodeId(1, String("Hot")),
                    {0x03, 0x01, 0x00, 0x03, 0x00, 0x00, 0x00, 'H', 'o', 't'});
    expectRoundTrip(NodeId(2, Guid{1, 2, 3, {4, 5, 6, 7, 8, 9, 10, 11}}),
                    {0x04, 0x02, 0x00, 1, 0, 0, 0, 2, 0, 3, 0, 4, 5, 6, 7, 8, 9, 10, 11});
    expectRoundTrip(NodeId(3, ByteString({0xAA})), {0x05, 0x03, 0x00, 0x01, 0, 0, 0, 0xAA});
}

TEST(Encoding, NodeIdTextForm) {
    for (const char* text :
         {"i=85", "ns=1;s=Demo.Double", "ns=3;b=qrs=", "ns=65535;i=4294967295"}) {
        auto id = NodeId::parse(text);
        ASSERT_TRUE(id.has_value()) << text;
        EXPECT_EQ(id->toString(), text);
    }
    for (const char* bad :
         {"", "i=", "x=1", "ns=1", "ns=a;i=1", "i=12z", "ns=70000;i=1", "g=1234"}) {
        EXPECT_FALSE(NodeId::parse(bad).has_value()) << bad;
    }
}

TEST(Encoding, ExpandedNodeId) {
    expectRoundTrip(ExpandedNodeId{NodeId(0, 72u), "", 0}, {0x00, 0x48});
    expectRoundTrip(ExpandedNodeId{NodeId(0, 72u), "u", 2},
                    {0xC0, 0x48, 0x01, 0, 0, 0, 'u', 0x02, 0, 0, 0});
    // The flags are not allowed in a plain NodeId.
    EXPECT_EQ(decodeStatus<NodeId>({0x80, 0x48, 0x01, 0, 0, 0, 'u'}), status::BadDecodingError);
    EXPECT_EQ(decodeStatus<NodeId>({0x06, 0x00}), status::BadDecodingError);
}

TEST(Encoding, StatusQualifiedNameLocalizedText) {
    expectRoundTrip(status::BadNodeIdUnknown, {0x00, 0x00, 0x34, 0x80});
    expectRoundTrip(QualifiedName{2, "Ab"}, {0x02, 0x00, 0x02, 0, 0, 0, 'A', 'b'});
    expectRoundTrip(LocalizedText{"", ""}, {0x00});
    expectRoundTrip(LocalizedText{"", "t"}, {0x02, 0x01, 0, 0, 0, 't'});
    expectRoundTrip(LocalizedText{"en", "t"}, {0x03, 0x02, 0, 0, 0, 'e', 'n', 0x01, 0, 0, 0, 't'});
}

TEST(Encoding, ExtensionObject) {
    expectRoundTrip(ExtensionObject{}, {0x00, 0x00, 0x00});
    ExtensionObject eo{NodeId(0, 321u), ExtensionObject::Encoding::Binary, ByteString({9})};
    expectRoundTrip(eo, {0x01, 0x00, 0x41, 0x01, 0x01, 0x01, 0x00, 0x00, 0x00, 0x09});
    EXPECT_EQ(decodeStatus<ExtensionObject>({0x00, 0x00, 0x03}), status::BadDecodingError);
}

TEST(Encoding, VariantScalarAndArrays) {
    expectRoundTrip(Variant{}, {0x00});
    expectRoundTrip(Variant(std::int32_t{7}), {0x06, 0x07, 0, 0, 0});
    expectRoundTrip(Variant(String("a")), {0x0C, 0x01, 0, 0, 0, 'a'});
    expectRoundTrip(Variant::array(std::vector<std::uint16_t>{1, 2}),
                    {0x85, 0x02, 0, 0, 0, 0x01, 0x00, 0x02, 0x00});
    expectRoundTrip(
        Variant::array(BuiltinType::Byte,
                       {std::uint8_t{1}, std::uint8_t{2}, std::uint8_t{3}, std::uint8_t{4}},
                       {2, 2}),
        {0xC3, 0x04, 0, 0, 0, 1, 2, 3, 4, 0x02, 0, 0, 0, 0x02, 0, 0, 0, 0x02, 0, 0, 0});
    expectRoundTrip(Variant(Box<Variant>(Variant(true))), {0x18, 0x01, 0x01});
}

TEST(Encoding, VariantRejectsInconsistentInput) {
    EXPECT_EQ(decodeStatus<Variant>({0x1A}), status::BadDecodingError);  // type id 26
    EXPECT_EQ(decodeStatus<Variant>({0x46, 0, 0, 0, 0}),
              status::BadDecodingError);  // dims, no array
    // Dimensions 2x3 for 4 elements.
    EXPECT_EQ(decodeStatus<Variant>(
                  {0xC3, 0x04, 0, 0, 0, 1, 2, 3, 4, 0x02, 0, 0, 0, 0x02, 0, 0, 0, 0x03, 0, 0, 0}),
              status::BadDecodingError);
    EXPECT_EQ(decodeStatus<Variant>({0x80, 0x01, 0, 0, 0}), status::BadDecodingError);  // Null[1]
    // Empty dimensions are fine for an empty array only.
    EXPECT_EQ(decodeStatus<Variant>({0xD1, 0, 0, 0, 0, 0, 0, 0, 0}), status::Good);
    EXPECT_EQ(decodeStatus<Variant>({0xC3, 0x01, 0, 0, 0, 7, 0, 0, 0, 0}),
              status::BadDecodingError);
    // An array whose elements disagree with its type does not encode.
    std::vector<std::uint8_t> out;
    BinaryWriter w(out);
    encode(w, Variant::array(BuiltinType::Double, {std::int32_t{1}}));
    EXPECT_EQ(w.status(), status::BadEncodingError);
}

TEST(Encoding, DataValue) {
    expectRoundTrip(DataValue{}, {0x00});
    DataValue dv;
    dv.value = Variant(1.0f);
    dv.status = status::BadNotReadable;
    dv.sourceTimestamp = DateTime{1};
    dv.sourcePicoseconds = 2;
    dv.serverTimestamp = DateTime{3};
    dv.serverPicoseconds = 4;
    expectRoundTrip(dv,
                    {0x3F, 0x0A, 0x00, 0x00, 0x80, 0x3F, 0x00, 0x00, 0x3A, 0x80, 1, 0, 0, 0, 0,
                     0,    0,    0,    2,    0,    3,    0,    0,    0,    0,    0, 0, 0, 4, 0});
}

TEST(Encoding, DiagnosticInfo) {
    DiagnosticInfo inner;
    inner.innerStatusCode = status::BadTimeout;
    DiagnosticInfo d;
    d.symbolicId = 1;
    d.locale = 2;
    d.localizedText = 3;
    d.additionalInfo = "x";
    d.innerDiagnosticInfo = Box<DiagnosticInfo>(inner);
    expectRoundTrip(d, {0x5D, 1,    0, 0, 0, 2,   0,    0,    0,    3,    0,   0,
                        0,    0x01, 0, 0, 0, 'x', 0x20, 0x00, 0x00, 0x0A, 0x80});
}

TEST(Encoding, TruncatedInputFailsCleanly) {
    const Bytes wire = encodeToBytes(NodeId(1, String("Hello")));
    for (std::size_t n = 0; n < wire.size(); ++n) {
        EXPECT_EQ(decodeStatus<NodeId>(Bytes(wire.begin(), wire.begin() + n)),
                  status::BadDecodingError)
            << "prefix " << n;
    }
    EXPECT_EQ(decodeStatus<std::uint32_t>({1, 2, 3, 4, 5}), status::BadDecodingError);  // trailing
}

TEST(Encoding, LengthsAreCheckedBeforeAllocating) {
    // A string claiming 2 GiB in a 5-byte message, and a negative length other than -1.
    EXPECT_EQ(decodeStatus<String>({0xFF, 0xFF, 0xFF, 0x7F, 'a'}), status::BadDecodingError);
    EXPECT_EQ(decodeStatus<String>({0xFE, 0xFF, 0xFF, 0xFF}), status::BadDecodingError);
    DecodeLimits small;
    small.maxStringLength = 2;
    EXPECT_EQ(decodeStatus<String>({0x03, 0, 0, 0, 'a', 'b', 'c'}, small),
              status::BadEncodingLimitsExceeded);
    small.maxArrayLength = 1;
    EXPECT_EQ(decodeStatus<std::vector<std::uint8_t>>({0x02, 0, 0, 0, 1, 2}, small),
              status::BadEncodingLimitsExceeded);
    EXPECT_EQ(decodeStatus<Variant>({0x87, 0xFF, 0xFF, 0xFF, 0x0F}), status::BadDecodingError);
}

TEST(Encoding, NestingDepthIsLimited) {
    Bytes wire;
    for (int i = 0; i < 100; ++i) wire.push_back(0x18);  // Variant inside Variant ...
    wire.push_back(0x00);
    EXPECT_EQ(decodeStatus<Variant>(wire), status::BadEncodingLimitsExceeded);
    Bytes diag;
    for (int i = 0; i < 100; ++i) diag.push_back(0x40);
    diag.push_back(0x00);
    EXPECT_EQ(decodeStatus<DiagnosticInfo>(diag), status::BadEncodingLimitsExceeded);
}

namespace {
struct Point {
    std::int32_t x = 0;
    String label;
    std::vector<double> weights;
    static constexpr std::uint32_t kBinaryEncodingId = 9999;
    static auto tie(auto& s) { return std::tie(s.x, s.label, s.weights); }
    friend bool operator==(const Point&, const Point&) = default;
};
}  // namespace

TEST(Encoding, StructuresAndExtensionObjects) {
    Point p{5, "p", {0.5}};
    expectRoundTrip(p, {5, 0, 0, 0, 1, 0, 0, 0, 'p', 1, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0xE0, 0x3F});
    auto eo = toExtensionObject(p);
    Point back;
    ASSERT_EQ(fromExtensionObject(eo, back), status::Good);
    EXPECT_EQ(back, p);
    eo.typeId = NodeId(1u);
    EXPECT_EQ(fromExtensionObject(eo, back), status::BadDataTypeIdUnknown);
}

}  // namespace encoding_test
