#include "ua/types/to_string.hpp"

#include <cstdio>

#include <array>
#include <charconv>
#include <type_traits>

namespace skillcell::ua {

std::string toString(const Scalar& s) {
    return std::visit(
        [](const auto& v) -> std::string {
            using T = std::decay_t<decltype(v)>;
            if constexpr (std::is_same_v<T, std::monostate>) {
                return "null";
            } else if constexpr (std::is_same_v<T, bool>) {
                return v ? "true" : "false";
            } else if constexpr (std::is_floating_point_v<T>) {
                std::array<char, 32> buf{};  // shortest text that reads back the same value
                auto [end, ec] = std::to_chars(buf.data(), buf.data() + buf.size(), v);
                return std::string(buf.data(), ec == std::errc{} ? end : buf.data());
            } else if constexpr (std::is_arithmetic_v<T>) {
                return std::to_string(v);
            } else if constexpr (std::is_same_v<T, String>) {
                return "\"" + v + "\"";
            } else if constexpr (std::is_same_v<T, DateTime>) {
                return v.toIso8601();
            } else if constexpr (std::is_same_v<T, NodeId> || std::is_same_v<T, ExpandedNodeId>) {
                return v.toString();
            } else if constexpr (std::is_same_v<T, StatusCode>) {
                return std::string(statusName(v));
            } else if constexpr (std::is_same_v<T, QualifiedName>) {
                return std::to_string(v.namespaceIndex) + ":" + v.name;
            } else if constexpr (std::is_same_v<T, LocalizedText>) {
                return "\"" + v.text + "\"";
            } else if constexpr (std::is_same_v<T, ByteString>) {
                return "ByteString[" + std::to_string(v.size()) + "]";
            } else if constexpr (std::is_same_v<T, ExtensionObject>) {
                return "ExtensionObject(" + v.typeId.toString() + ")";
            } else if constexpr (std::is_same_v<T, Box<Variant>>) {
                return toString(*v);
            } else {
                return "<" + std::string(typeid(T).name()) + ">";
            }
        },
        s);
}

std::string toString(const Variant& v) {
    if (!v.isArray()) return toString(v.scalar());
    std::string out = "[";
    for (std::size_t i = 0; i < v.elements().size(); ++i) {
        if (i > 0) out += ", ";
        if (i == 16) {
            out += "... (" + std::to_string(v.elements().size()) + " elements)";
            break;
        }
        out += toString(v.elements()[i]);
    }
    return out + "]";
}

}  // namespace skillcell::ua
