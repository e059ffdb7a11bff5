#include "kb/owl/node_iri.hpp"

#include <algorithm>
#include <array>

namespace skillcell::kb::owl {
namespace {

bool isTypeClass(ua::NodeClass c) {
    return c == ua::NodeClass::ObjectType || c == ua::NodeClass::VariableType ||
           c == ua::NodeClass::DataType || c == ua::NodeClass::ReferenceType;
}

// A browse name usable as it is at the end of an IRI (and as a Turtle local name).
bool isPlainName(std::string_view name) {
    if (name.empty()) return false;
    const auto ok = [](char c) {
        return (c >= 'A' && c <= 'Z') || (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') ||
               c == '_' || c == '-';
    };
    return std::all_of(name.begin(), name.end(), ok) && !(name[0] >= '0' && name[0] <= '9');
}

// Percent-encodes what may not stand in an IRI (RFC 3987) or would need escaping in Turtle;
// non-ASCII bytes pass unchanged (IRIs allow them).
std::string iriSafe(std::string_view text) {
    static constexpr std::array<char, 17> kHex{"0123456789ABCDEF"};
    std::string out;
    for (char ch : text) {
        const auto c = static_cast<unsigned char>(ch);
        const bool unsafe = c <= 0x20 || c == 0x7F || c == '<' || c == '>' || c == '"' ||
                            c == '{' || c == '}' || c == '|' || c == '\\' || c == '^' || c == '`' ||
                            c == '%' || c == '#' || c == '/' || c == '?';
        if (unsafe) {
            out += '%';
            out += kHex[c >> 4U];
            out += kHex[c & 0xFU];
        } else {
            out += ch;
        }
    }
    return out;
}

std::string withSeparator(std::string_view namespaceUri) {
    std::string base(namespaceUri);
    if (base.empty() || (base.back() != '/' && base.back() != '#')) base += '#';
    return base;
}

// "i=5002", "s=Name", "g=…", "b=…": the identifier part of a NodeId's text form.
std::string identifierText(const ua::NodeId& id) {
    std::string text = id.toString();
    if (text.rfind("ns=", 0) == 0) text.erase(0, text.find(';') + 1);
    return text;
}

}  // namespace

std::string nodeIri(std::string_view namespaceUri, const ua::NodeId& id, ua::NodeClass nodeClass,
                    std::string_view browseName) {
    if (isTypeClass(nodeClass) && isPlainName(browseName)) {
        return withSeparator(namespaceUri) + std::string(browseName);
    }
    return withSeparator(namespaceUri) + iriSafe(identifierText(id));
}

std::string expandedNodeIdText(std::string_view namespaceUri, const ua::NodeId& id) {
    return "nsu=" + std::string(namespaceUri) + ";" + identifierText(id);
}

}  // namespace skillcell::kb::owl
