#pragma once
// The composite built-in types: ExtensionObject, Variant, DataValue, DiagnosticInfo
// (OPC 10000-6, 5.2.2.15-17 and 5.2.2.12).
#include <cstdint>
#include <optional>
#include <string_view>
#include <type_traits>
#include <variant>
#include <vector>

#include "ua/types/box.hpp"
#include "ua/types/builtin.hpp"
#include "ua/types/node_id.hpp"
#include "ua/types/status_code.hpp"

namespace skillcell::ua {

/// Built-in type ids; the numbers are the encoding's type ids (OPC 10000-6, Table 1).
// The enumerator names are the standard's; they shadow the C++ types of the same name only
// inside the enum's own scope.
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wshadow"
enum class BuiltinType : std::uint8_t {
    Null = 0,
    Boolean = 1,
    SByte = 2,
    Byte = 3,
    Int16 = 4,
    UInt16 = 5,
    Int32 = 6,
    UInt32 = 7,
    Int64 = 8,
    UInt64 = 9,
    Float = 10,
    Double = 11,
    String = 12,
    DateTime = 13,
    Guid = 14,
    ByteString = 15,
    XmlElement = 16,
    NodeId = 17,
    ExpandedNodeId = 18,
    StatusCode = 19,
    QualifiedName = 20,
    LocalizedText = 21,
    ExtensionObject = 22,
    DataValue = 23,
    Variant = 24,
    DiagnosticInfo = 25
};
#pragma GCC diagnostic pop
inline constexpr std::uint8_t kMaxBuiltinType = 25;

/// The type's name in the standard ("Double", "LocalizedText"), as NodeSet2 files spell it;
/// empty for an id past kMaxBuiltinType.
[[nodiscard]] std::string_view builtinTypeName(BuiltinType type);
/// The type that name spells; nothing for another name ("Null" included: no value is of it).
[[nodiscard]] std::optional<BuiltinType> builtinTypeByName(std::string_view name);

/// A structure carried opaquely: its encoding id and the encoded body. Whoever knows the
/// type decodes the body (see ua/encoding/structure_codec.hpp).
struct ExtensionObject {
    enum class Encoding : std::uint8_t { None = 0, Binary = 1, Xml = 2 };
    NodeId typeId;
    Encoding encoding = Encoding::None;
    ByteString body;  // for Xml: the UTF-8 XML text

    [[nodiscard]] bool empty() const { return encoding == Encoding::None; }
    friend bool operator==(const ExtensionObject&, const ExtensionObject&) = default;
};

struct DataValue;
struct DiagnosticInfo;
class Variant;

// The alternatives are in built-in type id order: index() == type id.
using Scalar = std::variant<std::monostate, bool, std::int8_t, std::uint8_t, std::int16_t,
                            std::uint16_t, std::int32_t, std::uint32_t, std::int64_t, std::uint64_t,
                            float, double, String, DateTime, Guid, ByteString, XmlElement, NodeId,
                            ExpandedNodeId, StatusCode, QualifiedName, LocalizedText,
                            ExtensionObject, Box<DataValue>, Box<Variant>, Box<DiagnosticInfo>>;

template <class T, class V = Scalar>
struct IsScalarAlternative;
template <class T, class... Ts>
struct IsScalarAlternative<T, std::variant<Ts...>>
    : std::bool_constant<(std::is_same_v<T, Ts> || ...)> {};
template <class T>
concept ScalarType = IsScalarAlternative<T>::value && !std::is_same_v<T, std::monostate>;

template <ScalarType T>
constexpr BuiltinType builtinTypeOf() {
    return static_cast<BuiltinType>(Scalar(std::in_place_type<T>).index());
}

class Variant {
public:
    Variant() = default;
    template <ScalarType T>
    Variant(T value) : scalar_(std::move(value)) {}  // NOLINT(google-explicit-constructor)
    Variant(const char* s) : scalar_(String(s)) {}   // NOLINT(google-explicit-constructor)

    /// A scalar from a decoded alternative (monostate gives the empty Variant).
    static Variant fromScalar(Scalar s) {
        Variant v;
        v.scalar_ = std::move(s);
        return v;
    }
    /// An array of built-in type `type`; every element must hold that type.
    static Variant array(BuiltinType type, std::vector<Scalar> elements,
                         std::vector<std::int32_t> dimensions = {});
    template <ScalarType T>
    static Variant array(std::vector<T> values) {
        std::vector<Scalar> elements;
        elements.reserve(values.size());
        for (auto& v : values) elements.emplace_back(std::move(v));
        return array(builtinTypeOf<T>(), std::move(elements));
    }

    [[nodiscard]] BuiltinType type() const {
        return isArray_ ? arrayType_ : static_cast<BuiltinType>(scalar_.index());
    }
    [[nodiscard]] bool isEmpty() const { return !isArray_ && scalar_.index() == 0; }
    [[nodiscard]] bool isArray() const { return isArray_; }
    [[nodiscard]] bool isScalar() const { return !isArray_ && !isEmpty(); }
    [[nodiscard]] const Scalar& scalar() const { return scalar_; }
    [[nodiscard]] const std::vector<Scalar>& elements() const { return elements_; }
    [[nodiscard]] const std::vector<std::int32_t>& dimensions() const { return dimensions_; }

    /// The scalar value if this Variant holds a scalar of type T, else nullptr.
    template <ScalarType T>
    [[nodiscard]] const T* get() const {
        return isArray_ ? nullptr : std::get_if<T>(&scalar_);
    }

    friend bool operator==(const Variant&, const Variant&) = default;

private:
    Scalar scalar_;
    std::vector<Scalar> elements_;
    std::vector<std::int32_t> dimensions_;
    BuiltinType arrayType_ = BuiltinType::Null;
    bool isArray_ = false;
};

struct DataValue {
    std::optional<Variant> value;
    std::optional<StatusCode> status;
    std::optional<DateTime> sourceTimestamp;
    std::optional<std::uint16_t> sourcePicoseconds;
    std::optional<DateTime> serverTimestamp;
    std::optional<std::uint16_t> serverPicoseconds;

    [[nodiscard]] static DataValue withStatus(StatusCode s) {
        DataValue dv;
        dv.status = s;
        return dv;
    }
    [[nodiscard]] StatusCode statusOrGood() const { return status.value_or(status::Good); }
    friend bool operator==(const DataValue&, const DataValue&) = default;
};

struct DiagnosticInfo {
    std::optional<std::int32_t> symbolicId;
    std::optional<std::int32_t> namespaceUri;
    std::optional<std::int32_t> localizedText;
    std::optional<std::int32_t> locale;
    std::optional<String> additionalInfo;
    std::optional<StatusCode> innerStatusCode;
    std::optional<Box<DiagnosticInfo>> innerDiagnosticInfo;

    friend bool operator==(const DiagnosticInfo&, const DiagnosticInfo&) = default;
};

}  // namespace skillcell::ua
