#include "ua/nodeset/nodeset_exporter.hpp"

#include <algorithm>
#include <charconv>
#include <unordered_map>
#include <unordered_set>

namespace skillcell::ua {
namespace {

void escape(std::string& out, std::string_view s) {
    for (char c : s) {
        switch (c) {
            case '&':
                out += "&amp;";
                break;
            case '<':
                out += "&lt;";
                break;
            case '>':
                out += "&gt;";
                break;
            case '"':
                out += "&quot;";
                break;
            default:
                out += c;
        }
    }
}

std::string base64(const std::vector<std::uint8_t>& bytes) {
    static constexpr char kAlphabet[] =
        "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    std::string out;
    out.reserve((bytes.size() + 2) / 3 * 4);
    std::size_t i = 0;
    for (; i + 2 < bytes.size(); i += 3) {
        const std::uint32_t v = (bytes[i] << 16) | (bytes[i + 1] << 8) | bytes[i + 2];
        for (int s = 18; s >= 0; s -= 6) out += kAlphabet[(v >> s) & 63];
    }
    if (i < bytes.size()) {
        std::uint32_t v = bytes[i] << 16;
        if (i + 1 < bytes.size()) v |= bytes[i + 1] << 8;
        out += kAlphabet[(v >> 18) & 63];
        out += kAlphabet[(v >> 12) & 63];
        out += i + 1 < bytes.size() ? kAlphabet[(v >> 6) & 63] : '=';
        out += '=';
    }
    return out;
}

template <class T>
std::string number(T v) {
    char buf[64];
    // Shortest text that reads back to the same value, for floats too.
    auto [p, ec] = std::to_chars(buf, buf + sizeof buf, v);
    (void)ec;
    return std::string(buf, p);
}

class Exporter {
public:
    Exporter(const AddressSpace& as, const NodeSetExportOptions& options)
        : as_(as), exported_(options.namespaces.begin(), options.namespaces.end()) {
        // File namespace indices: 0 stays 0, the others are numbered in order.
        for (auto ns : options.namespaces) {
            if (ns != 0)
                fileNs_[ns] = static_cast<std::uint16_t>(fileUris_.size() + 1),
                fileUris_.push_back(as.namespaces()[ns]);
        }
    }

    NodeSetStatus run(std::string& out) {
        std::vector<const Node*> nodes;
        collect(nodes);
        // Nodes first: a reference into a namespace that is not exported adds a
        // NamespaceUris entry on the way, and the header is written last.
        std::string body;
        body.reserve(nodes.size() * 400);
        NodeSetStatus st;
        for (const Node* n : nodes) {
            if (!writeNode(body, *n)) {
                st.error = "node " + n->nodeId.toString() + ": " + error_;
                return st;
            }
            ++st.nodes;
        }
        out.clear();
        out.reserve(body.size() + 1024);
        out += "<?xml version=\"1.0\" encoding=\"utf-8\"?>\n";
        out +=
            "<UANodeSet xmlns=\"http://opcfoundation.org/UA/2011/03/UANodeSet.xsd\" "
            "xmlns:uax=\"http://opcfoundation.org/UA/2008/02/Types.xsd\">\n";
        if (!fileUris_.empty()) {
            out += "  <NamespaceUris>\n";
            for (const auto& u : fileUris_) {
                out += "    <Uri>";
                escape(out, u);
                out += "</Uri>\n";
            }
            out += "  </NamespaceUris>\n";
        }
        writeModels(out);
        out += body;
        out += "</UANodeSet>\n";
        return st;
    }

private:
    bool isExported(const NodeId& id) const { return exported_.contains(id.namespaceIndex()); }

    void collect(std::vector<const Node*>& nodes) const {
        as_.forEachNode([&](const Node& n) {
            if (isExported(n.nodeId)) nodes.push_back(&n);
        });
        // Stable output: by namespace, then numeric ids first, then by text.
        std::sort(nodes.begin(), nodes.end(), [](const Node* a, const Node* b) {
            if (a->nodeId.namespaceIndex() != b->nodeId.namespaceIndex()) {
                return a->nodeId.namespaceIndex() < b->nodeId.namespaceIndex();
            }
            const auto* na = std::get_if<std::uint32_t>(&a->nodeId.identifier());
            const auto* nb = std::get_if<std::uint32_t>(&b->nodeId.identifier());
            if (na && nb) return *na < *nb;
            if (na || nb) return na != nullptr;
            return a->nodeId.toString() < b->nodeId.toString();
        });
    }

    void writeModels(std::string& out) const {
        bool any = false;
        for (std::uint16_t ns : exported_) {
            const AddressSpace::Model* m = as_.findModel(as_.namespaces()[ns]);
            if (m == nullptr) continue;
            if (!any) out += "  <Models>\n";
            any = true;
            out += "    <Model ModelUri=\"";
            escape(out, m->uri);
            out += "\"";
            if (!m->version.empty()) {
                out += " Version=\"";
                escape(out, m->version);
                out += "\"";
            }
            if (m->publicationDate) {
                out += " PublicationDate=\"" + dateTime(*m->publicationDate) + "\"";
            }
            out += "/>\n";
        }
        if (any) out += "  </Models>\n";
    }

    std::string nodeId(const NodeId& id) const {
        std::string text = id.toString();
        const std::uint16_t ns = id.namespaceIndex();
        if (ns == 0) return text;
        // Drop the server's "ns=N;" prefix and put the file's index in front.
        if (text.starts_with("ns=")) text = text.substr(text.find(';') + 1);
        auto it = fileNs_.find(ns);
        const std::uint16_t fileIndex = it != fileNs_.end() ? it->second : addForeign(ns);
        return "ns=" + std::to_string(fileIndex) + ";" + text;
    }

    /// A namespace referenced but not exported still needs a NamespaceUris entry.
    std::uint16_t addForeign(std::uint16_t ns) const {
        fileUris_.push_back(as_.namespaces()[ns]);
        const auto index = static_cast<std::uint16_t>(fileUris_.size());
        fileNs_[ns] = index;
        return index;
    }

    std::string qualifiedName(const QualifiedName& q) const {
        if (q.namespaceIndex == 0) return q.name;
        auto it = fileNs_.find(q.namespaceIndex);
        const auto idx = it != fileNs_.end() ? it->second : addForeign(q.namespaceIndex);
        return std::to_string(idx) + ":" + q.name;
    }

    static std::string dateTime(const DateTime& d) {
        // Seconds from toIso8601, then all seven digits of 100 ns ticks, so values survive.
        std::string s = DateTime{d.ticks - d.ticks % 10'000'000}.toIso8601().substr(0, 19);
        const auto frac = d.ticks % 10'000'000;
        if (frac != 0) {
            std::string f = std::to_string(frac);
            s += "." + std::string(7 - f.size(), '0') + f;
        }
        return s + "Z";
    }

    static const char* nodeClassElement(NodeClass nc) {
        switch (nc) {
            case NodeClass::Object:
                return "UAObject";
            case NodeClass::Variable:
                return "UAVariable";
            case NodeClass::Method:
                return "UAMethod";
            case NodeClass::ObjectType:
                return "UAObjectType";
            case NodeClass::VariableType:
                return "UAVariableType";
            case NodeClass::ReferenceType:
                return "UAReferenceType";
            case NodeClass::DataType:
                return "UADataType";
            case NodeClass::View:
                return "UAView";
            default:
                return "UAObject";
        }
    }

    static void localizedElement(std::string& out, const char* tag, const LocalizedText& t) {
        out += "    <";
        out += tag;
        if (!t.locale.empty()) {
            out += " Locale=\"";
            escape(out, t.locale);
            out += "\"";
        }
        out += ">";
        escape(out, t.text);
        out += "</";
        out += tag;
        out += ">\n";
    }

    bool writeNode(std::string& out, const Node& n) {
        const Node defaults;
        const char* tag = nodeClassElement(n.nodeClass);
        out += "  <";
        out += tag;
        out += " NodeId=\"";
        escape(out, nodeId(n.nodeId));
        out += "\" BrowseName=\"";
        escape(out, qualifiedName(n.browseName));
        out += "\"";
        const auto attr = [&](const char* name, const std::string& v) {
            out += " ";
            out += name;
            out += "=\"";
            escape(out, v);
            out += "\"";
        };
        if (n.writeMask != 0) attr("WriteMask", number(n.writeMask));
        if (n.userWriteMask != 0) attr("UserWriteMask", number(n.userWriteMask));
        const bool isType =
            n.nodeClass == NodeClass::ObjectType || n.nodeClass == NodeClass::VariableType ||
            n.nodeClass == NodeClass::ReferenceType || n.nodeClass == NodeClass::DataType;
        if (isType && n.isAbstract) attr("IsAbstract", "true");
        if (n.nodeClass == NodeClass::ReferenceType && n.symmetric) attr("Symmetric", "true");
        if (n.nodeClass == NodeClass::View && n.containsNoLoops) attr("ContainsNoLoops", "true");
        if ((n.nodeClass == NodeClass::Object || n.nodeClass == NodeClass::View) &&
            n.eventNotifier != 0) {
            attr("EventNotifier", number(n.eventNotifier));
        }
        if (n.nodeClass == NodeClass::Variable || n.nodeClass == NodeClass::VariableType) {
            attr("DataType", nodeId(n.dataType));
            if (n.valueRank != value_rank::kScalar) attr("ValueRank", number(n.valueRank));
            if (!n.arrayDimensions.empty()) {
                std::string dims;
                for (auto d : n.arrayDimensions) {
                    if (!dims.empty()) dims += ',';
                    dims += number(d);
                }
                attr("ArrayDimensions", dims);
            }
        }
        if (n.nodeClass == NodeClass::Variable) {
            if (n.accessLevel != defaults.accessLevel) attr("AccessLevel", number(n.accessLevel));
            if (n.userAccessLevel != defaults.userAccessLevel) {
                attr("UserAccessLevel", number(n.userAccessLevel));
            }
            if (n.minimumSamplingInterval != 0) {
                attr("MinimumSamplingInterval", number(n.minimumSamplingInterval));
            }
            if (n.historizing) attr("Historizing", "true");
        }
        if (n.nodeClass == NodeClass::Method) {
            if (!n.executable) attr("Executable", "false");
            if (!n.userExecutable) attr("UserExecutable", "false");
        }
        out += ">\n";
        localizedElement(out, "DisplayName", n.displayName);
        if (!n.description.text.empty() || !n.description.locale.empty()) {
            localizedElement(out, "Description", n.description);
        }
        bool refsOpen = false;
        for (const auto& r : n.references) {
            // Forward references from here; inverse ones only when the other end is not in
            // the file (the loader adds both ends from one entry).
            if (!r.isForward && isExported(r.target)) continue;
            if (!refsOpen) out += "    <References>\n";
            refsOpen = true;
            out += "      <Reference ReferenceType=\"" + nodeId(r.referenceTypeId) + "\"";
            if (!r.isForward) out += " IsForward=\"false\"";
            out += ">";
            escape(out, nodeId(r.target));
            out += "</Reference>\n";
        }
        if (refsOpen) out += "    </References>\n";
        if (n.nodeClass == NodeClass::ReferenceType &&
            (!n.inverseName.text.empty() || !n.inverseName.locale.empty())) {
            localizedElement(out, "InverseName", n.inverseName);
        }
        if (n.nodeClass == NodeClass::DataType) writeDefinition(out, n);
        if ((n.nodeClass == NodeClass::Variable || n.nodeClass == NodeClass::VariableType) &&
            n.value.value && !n.value.value->isEmpty()) {
            std::string v;
            if (!variant(v, *n.value.value, "      ")) return false;
            out += "    <Value>\n" + v + "    </Value>\n";
        }
        out += "  </";
        out += tag;
        out += ">\n";
        return true;
    }

    void writeDefinition(std::string& out, const Node& n) {
        if (const auto* s = std::get_if<StructureDefinition>(&n.definition)) {
            out += "    <Definition Name=\"";
            escape(out, qualifiedName(n.browseName));
            out += "\"";
            if (s->structureType == StructureType::Union) out += " IsUnion=\"true\"";
            out += ">\n";
            for (const auto& f : s->fields) {
                out += "      <Field Name=\"";
                escape(out, f.name);
                out += "\" DataType=\"" + nodeId(f.dataType) + "\"";
                if (f.valueRank != -1) out += " ValueRank=\"" + number(f.valueRank) + "\"";
                if (!f.arrayDimensions.empty()) {
                    std::string dims;
                    for (auto d : f.arrayDimensions) {
                        if (!dims.empty()) dims += ',';
                        dims += number(d);
                    }
                    out += " ArrayDimensions=\"" + dims + "\"";
                }
                if (f.maxStringLength != 0) {
                    out += " MaxStringLength=\"" + number(f.maxStringLength) + "\"";
                }
                if (f.isOptional) out += " IsOptional=\"true\"";
                if (f.description.text.empty()) {
                    out += "/>\n";
                } else {
                    out += ">\n  ";
                    localizedElement(out, "Description", f.description);
                    out += "      </Field>\n";
                }
            }
            out += "    </Definition>\n";
        } else if (const auto* e = std::get_if<EnumDefinition>(&n.definition)) {
            out += "    <Definition Name=\"";
            escape(out, qualifiedName(n.browseName));
            out += "\">\n";
            for (const auto& f : e->fields) {
                out += "      <Field Name=\"";
                escape(out, f.name);
                out += "\" Value=\"" + number(f.value) + "\">\n  ";
                localizedElement(out, "DisplayName", f.displayName);
                if (!f.description.text.empty()) {
                    out += "  ";
                    localizedElement(out, "Description", f.description);
                }
                out += "      </Field>\n";
            }
            out += "    </Definition>\n";
        }
    }

    bool variant(std::string& out, const Variant& v, const std::string& ind) {
        const auto name = builtinTypeName(v.type());
        if (v.isArray()) {
            out += ind + "<uax:ListOf" + std::string(name) + ">\n";
            for (const auto& e : v.elements()) {
                if (!scalar(out, e, name, ind + "  ")) return false;
            }
            out += ind + "</uax:ListOf" + std::string(name) + ">\n";
            return true;
        }
        return scalar(out, v.scalar(), name, ind);
    }

    bool scalar(std::string& out, const Scalar& s, std::string_view name, const std::string& ind) {
        std::string body;
        if (!scalarBody(body, s, ind + "  ")) return false;
        out +=
            ind + "<uax:" + std::string(name) + ">" + body + "</uax:" + std::string(name) + ">\n";
        return true;
    }

    /// The content of a value's element: text for simple types, child elements otherwise.
    bool scalarBody(std::string& out, const Scalar& s, const std::string& ind) {
        return std::visit(
            [&](const auto& x) -> bool {
                using T = std::decay_t<decltype(x)>;
                if constexpr (std::is_same_v<T, bool>) {
                    out += x ? "true" : "false";
                } else if constexpr (std::is_same_v<T, std::int8_t> ||
                                     std::is_same_v<T, std::uint8_t>) {
                    out += std::to_string(static_cast<int>(x));
                } else if constexpr (std::is_arithmetic_v<T>) {
                    out += number(x);
                } else if constexpr (std::is_same_v<T, String>) {
                    escape(out, x);
                } else if constexpr (std::is_same_v<T, DateTime>) {
                    out += dateTime(x);
                } else if constexpr (std::is_same_v<T, Guid>) {
                    char buf[40];
                    std::snprintf(buf, sizeof buf,
                                  "%08X-%04X-%04X-%02X%02X-%02X%02X%02X%02X%02X%02X", x.data1,
                                  x.data2, x.data3, x.data4[0], x.data4[1], x.data4[2], x.data4[3],
                                  x.data4[4], x.data4[5], x.data4[6], x.data4[7]);
                    out += "<uax:String>" + std::string(buf) + "</uax:String>";
                } else if constexpr (std::is_same_v<T, ByteString>) {
                    out += base64(x.bytes);
                } else if constexpr (std::is_same_v<T, XmlElement>) {
                    out += x.xml;
                } else if constexpr (std::is_same_v<T, NodeId>) {
                    out += "<uax:Identifier>";
                    if (!x.isNull()) escape(out, nodeId(x));
                    out += "</uax:Identifier>";
                } else if constexpr (std::is_same_v<T, ExpandedNodeId>) {
                    out += "<uax:Identifier>";
                    if (!x.nodeId.isNull()) escape(out, nodeId(x.nodeId));
                    out += "</uax:Identifier>";
                } else if constexpr (std::is_same_v<T, StatusCode>) {
                    out += "<uax:Code>" + number(x.code) + "</uax:Code>";
                } else if constexpr (std::is_same_v<T, QualifiedName>) {
                    out += "<uax:NamespaceIndex>" + number(fileIndexOf(x.namespaceIndex)) +
                           "</uax:NamespaceIndex><uax:Name>";
                    escape(out, x.name);
                    out += "</uax:Name>";
                } else if constexpr (std::is_same_v<T, LocalizedText>) {
                    if (!x.locale.empty()) {
                        out += "<uax:Locale>";
                        escape(out, x.locale);
                        out += "</uax:Locale>";
                    }
                    out += "<uax:Text>";
                    escape(out, x.text);
                    out += "</uax:Text>";
                } else if constexpr (std::is_same_v<T, ExtensionObject>) {
                    return extensionObject(out, x, ind);
                } else {
                    error_ = "value type not representable in the XML encoding";
                    return false;
                }
                return true;
            },
            s);
    }

    std::uint16_t fileIndexOf(std::uint16_t ns) const {
        if (ns == 0) return 0;
        auto it = fileNs_.find(ns);
        return it != fileNs_.end() ? it->second : addForeign(ns);
    }

    bool extensionObject(std::string& out, const ExtensionObject& eo, const std::string& ind) {
        auto value = fromExtensionObject(as_.dataTypes(), eo);
        if (!value) {
            error_ = "ExtensionObject " + eo.typeId.toString() + " has no usable definition";
            return false;
        }
        const DataTypeInfo* info = as_.dataTypes().find(value->dataTypeId);
        const NodeId typeId = !info->xmlEncodingId.isNull() ? info->xmlEncodingId : eo.typeId;
        out += "\n" + ind + "<uax:TypeId><uax:Identifier>" + nodeId(typeId) +
               "</uax:Identifier></uax:TypeId>\n" + ind + "<uax:Body>\n";
        if (!structure(out, *value, info->browseName.name, ind + "  ")) return false;
        out += ind + "</uax:Body>\n" + ind.substr(2);
        return true;
    }

    bool structure(std::string& out, const DynamicStructure& value, std::string_view name,
                   const std::string& ind) {
        const StructureDefinition* def = as_.dataTypes().structureOf(value.dataTypeId);
        if (def == nullptr) return false;
        out += ind + "<uax:" + std::string(name) + ">\n";
        for (std::size_t i = 0; i < def->fields.size(); ++i) {
            const auto& f = def->fields[i];
            const Variant& v = value.fields[i].value;
            if (v.isEmpty()) continue;  // absent optional field / unset union member
            const std::string fi = ind + "  ";
            out += fi + "<uax:" + f.name + ">";
            const StructureDefinition* nested = as_.dataTypes().structureOf(f.dataType);
            const auto bt = as_.dataTypes().builtinTypeOf(f.dataType);
            if (nested != nullptr || (bt && *bt != BuiltinType::Variant && f.valueRank >= 0)) {
                out += "\n";
                const auto elementName = nested != nullptr
                                             ? as_.dataTypes().find(f.dataType)->browseName.name
                                             : std::string(builtinTypeName(*bt));
                const auto one = [&](const Scalar& s) -> bool {
                    if (nested != nullptr) {
                        auto inner =
                            fromExtensionObject(as_.dataTypes(), std::get<ExtensionObject>(s));
                        if (!inner) return false;
                        return structure(out, *inner, f.valueRank >= 0 ? elementName : f.name,
                                         fi + "  ");
                    }
                    return scalar(out, s, elementName, fi + "  ");
                };
                if (f.valueRank >= 0) {
                    for (const auto& e : v.elements()) {
                        if (!one(e)) return false;
                    }
                } else {
                    // A nested structure's fields go directly inside the field element.
                    auto inner =
                        fromExtensionObject(as_.dataTypes(), std::get<ExtensionObject>(v.scalar()));
                    if (!inner) return false;
                    std::string body;
                    if (!structure(body, *inner, "X", fi)) return false;
                    // Strip the wrapper element <uax:X> ... </uax:X> written above.
                    const auto open = body.find('\n') + 1;
                    const auto close = body.rfind(fi + "</uax:X>");
                    out += body.substr(open, close - open);
                }
                out += fi + "</uax:" + f.name + ">\n";
                continue;
            }
            if (bt && *bt == BuiltinType::Variant) {
                out += "\n" + fi + "  <uax:Value>\n";
                if (!variant(out, v, fi + "    ")) return false;
                out.append(fi).append("  </uax:Value>\n").append(fi);
            } else if (!scalarBody(out, v.scalar(), fi + "  ")) {
                return false;
            }
            out += "</uax:" + f.name + ">\n";
        }
        out += ind + "</uax:" + std::string(name) + ">\n";
        return true;
    }

    const AddressSpace& as_;
    std::unordered_set<std::uint16_t> exported_;
    mutable std::unordered_map<std::uint16_t, std::uint16_t> fileNs_;
    mutable std::vector<String> fileUris_;
    std::string error_;
};

}  // namespace

NodeSetStatus exportNodeSet(const AddressSpace& as, const NodeSetExportOptions& options,
                            std::string& out) {
    return Exporter(as, options).run(out);
}

}  // namespace skillcell::ua
