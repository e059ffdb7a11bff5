#pragma once
// NodeId and ExpandedNodeId (OPC 10000-3, 8.2; OPC 10000-6, 5.2.2.9-10).
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <string_view>
#include <variant>

#include "ua/types/builtin.hpp"

namespace skillcell::ua {

class NodeId {
public:
    using Identifier = std::variant<std::uint32_t, String, Guid, ByteString>;
    enum class IdType : std::uint8_t { Numeric = 0, Text = 1, Uuid = 2, Opaque = 3 };

    constexpr NodeId() = default;
    // NOLINTNEXTLINE: implicit on purpose, ns=0 numeric is the common case
    constexpr NodeId(std::uint32_t numeric) : id_(numeric) {}
    constexpr NodeId(std::uint16_t ns, std::uint32_t numeric) : ns_(ns), id_(numeric) {}
    NodeId(std::uint16_t ns, String s) : ns_(ns), id_(std::move(s)) {}
    NodeId(std::uint16_t ns, Guid g) : ns_(ns), id_(g) {}
    NodeId(std::uint16_t ns, ByteString b) : ns_(ns), id_(std::move(b)) {}

    [[nodiscard]] std::uint16_t namespaceIndex() const { return ns_; }
    [[nodiscard]] const Identifier& identifier() const { return id_; }
    [[nodiscard]] IdType idType() const { return static_cast<IdType>(id_.index()); }
    [[nodiscard]] bool isNumeric() const { return id_.index() == 0; }
    [[nodiscard]] std::uint32_t numeric() const { return std::get<std::uint32_t>(id_); }
    /// The null NodeId: ns=0, numeric 0 (other "null" forms are treated as non-null).
    [[nodiscard]] bool isNull() const { return ns_ == 0 && isNumeric() && numeric() == 0; }

    /// Text form of OPC 10000-6, 5.3.1.10: "i=85", "ns=1;s=Demo", "ns=2;g=...", "ns=3;b=BASE64".
    [[nodiscard]] std::string toString() const;
    /// Parses the text form; std::nullopt for malformed text.
    [[nodiscard]] static std::optional<NodeId> parse(std::string_view text);

    friend bool operator==(const NodeId&, const NodeId&) = default;
    // NOLINTNEXTLINE(modernize-use-nullptr): clang-tidy 14 flags the literal 0 of the defaulted <=>
    friend auto operator<=>(const NodeId&, const NodeId&) = default;

private:
    std::uint16_t ns_ = 0;
    Identifier id_{std::uint32_t{0}};
};

struct ExpandedNodeId {
    NodeId nodeId;
    String namespaceUri;  // empty: use nodeId's namespace index
    std::uint32_t serverIndex = 0;

    [[nodiscard]] bool isLocal() const { return serverIndex == 0 && namespaceUri.empty(); }
    [[nodiscard]] std::string toString() const;
    friend bool operator==(const ExpandedNodeId&, const ExpandedNodeId&) = default;
};

[[nodiscard]] std::size_t hashValue(const NodeId& id);

}  // namespace skillcell::ua

template <>
struct std::hash<skillcell::ua::NodeId> {
    std::size_t operator()(const skillcell::ua::NodeId& id) const noexcept {
        return skillcell::ua::hashValue(id);
    }
};
