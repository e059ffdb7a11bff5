#include "ua/nodeset/nodeset_loader.hpp"

#include <pugixml.hpp>

#include <algorithm>
#include <charconv>
#include <fstream>
#include <optional>
#include <sstream>
#include <type_traits>
#include <unordered_map>
#include <unordered_set>

#include "ua/encoding/codec.hpp"

namespace skillcell::ua {
namespace {

/// Element names may carry a prefix ("uax:String"); the schema is identified by name only.
std::string_view localName(const pugi::xml_node& n) {
    std::string_view name = n.name();
    const auto colon = name.find(':');
    return colon == std::string_view::npos ? name : name.substr(colon + 1);
}

pugi::xml_node child(const pugi::xml_node& n, std::string_view name) {
    for (auto c : n.children()) {
        if (c.type() == pugi::node_element && localName(c) == name) return c;
    }
    return {};
}

/// Hashes std::string and std::string_view alike, so that a map keyed by strings is searched
/// with a view.
struct TextHash {
    using is_transparent = void;
    std::size_t operator()(std::string_view s) const { return std::hash<std::string_view>{}(s); }
};

std::string_view trim(std::string_view s) {
    const auto b = s.find_first_not_of(" \t\r\n");
    if (b == std::string_view::npos) return {};
    const auto e = s.find_last_not_of(" \t\r\n");
    return s.substr(b, e - b + 1);
}

template <class T>
std::optional<T> parseNumber(std::string_view s) {
    s = trim(s);
    if (!s.empty() && s.front() == '+') s.remove_prefix(1);
    T v{};
    auto [p, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
    if (ec != std::errc{} || p != s.data() + s.size() || s.empty()) return std::nullopt;
    return v;
}

std::optional<bool> parseBool(std::string_view s) {
    s = trim(s);
    if (s == "true" || s == "1") return true;
    if (s == "false" || s == "0") return false;
    return std::nullopt;
}

// Days since 1970-01-01 of a civil date (proleptic Gregorian).
std::int64_t daysFromCivil(std::int64_t y, unsigned m, unsigned d) {
    y -= m <= 2 ? 1 : 0;
    const std::int64_t era = (y >= 0 ? y : y - 399) / 400;
    const auto yoe = static_cast<unsigned>(y - era * 400);
    const unsigned doy = (153 * (m + (m > 2 ? -3 : 9)) + 2) / 5 + d - 1;
    const unsigned doe = yoe * 365 + yoe / 4 - yoe / 100 + doy;
    return era * 146097 + static_cast<std::int64_t>(doe) - 719468;
}

/// xs:dateTime: YYYY-MM-DDThh:mm:ss[.fraction][Z|(+|-)hh:mm].
std::optional<DateTime> parseDateTime(std::string_view s) {
    s = trim(s);
    if (s.size() < 19 || s[4] != '-' || s[7] != '-' || s[10] != 'T' || s[13] != ':' ||
        s[16] != ':') {
        return std::nullopt;
    }
    auto y = parseNumber<int>(s.substr(0, 4));
    auto mo = parseNumber<unsigned>(s.substr(5, 2));
    auto d = parseNumber<unsigned>(s.substr(8, 2));
    auto h = parseNumber<int>(s.substr(11, 2));
    auto mi = parseNumber<int>(s.substr(14, 2));
    auto se = parseNumber<int>(s.substr(17, 2));
    if (!y || !mo || !d || !h || !mi || !se || *mo < 1 || *mo > 12 || *d < 1 || *d > 31 ||
        *h > 23 || *mi > 59 || *se > 60) {
        return std::nullopt;
    }
    std::size_t i = 19;
    std::int64_t ticks = 0;
    if (i < s.size() && s[i] == '.') {
        ++i;
        std::int64_t scale = 1'000'000;  // ticks per 0.1 s
        const std::size_t start = i;
        while (i < s.size() && s[i] >= '0' && s[i] <= '9') {
            ticks += (s[i] - '0') * scale;
            scale /= 10;
            ++i;
        }
        if (i == start) return std::nullopt;
    }
    std::int64_t offsetMinutes = 0;
    if (i < s.size()) {
        if (s[i] == 'Z' && i + 1 == s.size()) {
            // UTC
        } else if ((s[i] == '+' || s[i] == '-') && s.size() == i + 6 && s[i + 3] == ':') {
            auto oh = parseNumber<int>(s.substr(i + 1, 2));
            auto om = parseNumber<int>(s.substr(i + 4, 2));
            if (!oh || !om) return std::nullopt;
            offsetMinutes = (std::int64_t{*oh} * 60 + *om) * (s[i] == '+' ? 1 : -1);
        } else {
            return std::nullopt;
        }
    }
    const std::int64_t secs = daysFromCivil(*y, *mo, *d) * 86400 + std::int64_t{*h} * 3600 +
                              std::int64_t{*mi} * 60 + *se - offsetMinutes * 60;
    return DateTime{DateTime::kUnixEpochTicks + secs * 10'000'000 + ticks};
}

/// RFC 4648 base64 (the XML encoding of ByteString); whitespace is ignored.
std::optional<std::vector<std::uint8_t>> decodeBase64(std::string_view text) {
    std::vector<std::uint8_t> out;
    out.reserve(text.size() * 3 / 4);
    std::uint32_t acc = 0;
    int bits = 0;
    std::size_t padding = 0;
    for (char c : text) {
        int v = -1;
        if (c >= 'A' && c <= 'Z')
            v = c - 'A';
        else if (c >= 'a' && c <= 'z')
            v = c - 'a' + 26;
        else if (c >= '0' && c <= '9')
            v = c - '0' + 52;
        else if (c == '+')
            v = 62;
        else if (c == '/')
            v = 63;
        else if (c == '=') {
            ++padding;
            continue;
        } else if (c == ' ' || c == '\n' || c == '\r' || c == '\t') {
            continue;
        } else {
            return std::nullopt;
        }
        if (padding != 0) return std::nullopt;  // data after padding
        acc = (acc << 6) | static_cast<std::uint32_t>(v);
        bits += 6;
        if (bits >= 8) {
            bits -= 8;
            out.push_back(static_cast<std::uint8_t>((acc >> bits) & 0xFF));
        }
    }
    if (padding > 2) return std::nullopt;
    return out;
}

/// "72962B91-FA75-4AE6-8D28-B404DC7DAF63"
std::optional<Guid> parseGuid(std::string_view s) {
    s = trim(s);
    if (s.size() != 36 || s[8] != '-' || s[13] != '-' || s[18] != '-' || s[23] != '-') {
        return std::nullopt;
    }
    const auto hex = [&](std::size_t at, std::size_t n) -> std::optional<std::uint32_t> {
        std::uint32_t v = 0;
        auto [p, ec] = std::from_chars(s.data() + at, s.data() + at + n, v, 16);
        if (ec != std::errc{} || p != s.data() + at + n) return std::nullopt;
        return v;
    };
    Guid g;
    auto d1 = hex(0, 8);
    auto d2 = hex(9, 4);
    auto d3 = hex(14, 4);
    if (!d1 || !d2 || !d3) return std::nullopt;
    g.data1 = *d1;
    g.data2 = static_cast<std::uint16_t>(*d2);
    g.data3 = static_cast<std::uint16_t>(*d3);
    static constexpr std::size_t kAt[8] = {19, 21, 24, 26, 28, 30, 32, 34};
    for (std::size_t i = 0; i < 8; ++i) {
        auto b = hex(kAt[i], 2);
        if (!b) return std::nullopt;
        g.data4[i] = static_cast<std::uint8_t>(*b);
    }
    return g;
}

/// Compares dotted versions ("1.05.03" vs "1.05") numerically, part by part; parts that
/// are not numbers compare as text. Missing parts count as 0.
int compareVersions(std::string_view a, std::string_view b) {
    while (!a.empty() || !b.empty()) {
        const auto da = a.find('.');
        const auto db = b.find('.');
        const auto pa = a.substr(0, da);
        const auto pb = b.substr(0, db);
        auto na = parseNumber<std::uint64_t>(pa.empty() ? "0" : pa);
        auto nb = parseNumber<std::uint64_t>(pb.empty() ? "0" : pb);
        if (na && nb) {
            if (*na != *nb) return *na < *nb ? -1 : 1;
        } else if (pa != pb) {
            return pa < pb ? -1 : 1;
        }
        a = da == std::string_view::npos ? std::string_view{} : a.substr(da + 1);
        b = db == std::string_view::npos ? std::string_view{} : b.substr(db + 1);
    }
    return 0;
}

std::string lineText(const ParsedNodeSet& p, std::size_t line);
NodeSetStatus checkRequiredModels(const AddressSpace& as, const ParsedNodeSet& parsed);

class Parser {
public:
    Parser(const AddressSpace& as, std::string_view xml, std::string_view source)
        : as_(as), xml_(xml), source_(source) {}

    NodeSetStatus run(ParsedNodeSet& out) {
        NodeSetStatus st = runPasses(out);
        if (st.ok()) return st;
        // A file read before its prerequisites fails on their types or aliases: say what
        // is missing rather than which of its uses broke first.
        NodeSetStatus required = checkRequiredModels(as_, out);
        return required.ok() ? st : required;
    }

private:
    NodeSetStatus runPasses(ParsedNodeSet& out) {
        pugi::xml_document doc;
        const auto res =
            doc.load_buffer(xml_.data(), xml_.size(), pugi::parse_default, pugi::encoding_utf8);
        if (!res)
            return fail(static_cast<std::size_t>(res.offset),
                        std::string("malformed XML: ") + res.description());
        const auto root = doc.document_element();
        if (localName(root) != "UANodeSet") {
            return failAt(
                root, "root element is '" + std::string(root.name()) + "', expected 'UANodeSet'");
        }
        out.source = source_;
        // Pass 1: namespaces and aliases, wherever they are in the file.
        if (auto uris = child(root, "NamespaceUris")) {
            for (auto u : uris.children()) {
                if (u.type() != pugi::node_element) continue;
                out.namespaceUris.emplace_back(trim(u.text().get()));
            }
        }
        nsMap_ = namespaceMap(as_, out.namespaceUris);
        out.serverNamespaces = serverNamespaceTable(as_, out.namespaceUris, nsMap_);
        nsMap_.insert(nsMap_.begin(), 0);  // the file's index 0 is namespace 0
        if (auto aliases = child(root, "Aliases")) {
            for (auto a : aliases.children()) {
                if (a.type() != pugi::node_element) continue;
                const std::string name = a.attribute("Alias").value();
                if (name.empty()) return failAt(a, "Alias without a name");
                auto id = parseNodeIdText(a, trim(a.text().get()), false);
                if (!id) return status_;
                aliases_[name] = *id;
            }
        }
        if (auto models = child(root, "Models")) {
            for (auto m : models.children()) {
                if (m.type() != pugi::node_element || localName(m) != "Model") continue;
                ParsedModel pm;
                pm.line = lineOf(m);
                pm.uri = m.attribute("ModelUri").value();
                pm.version = m.attribute("Version").value();
                if (!modelDate(m, pm.publicationDate)) return status_;
                for (auto r : m.children()) {
                    if (r.type() != pugi::node_element || localName(r) != "RequiredModel") continue;
                    ParsedModel::Requirement req;
                    req.uri = r.attribute("ModelUri").value();
                    req.version = r.attribute("Version").value();
                    if (!modelDate(r, req.publicationDate)) return status_;
                    if (req.uri.empty()) return failAt(r, "RequiredModel without ModelUri");
                    pm.required.push_back(std::move(req));
                }
                if (pm.uri.empty()) return failAt(m, "Model without ModelUri");
                out.models.push_back(std::move(pm));
            }
        }
        // Pass 2: nodes.
        out.nodes.reserve(static_cast<std::size_t>(
            std::distance(root.children().begin(), root.children().end())));
        for (auto e : root.children()) {
            if (e.type() != pugi::node_element) continue;
            const auto name = localName(e);
            if (name == "NamespaceUris" || name == "ServerUris" || name == "Models" ||
                name == "Aliases" || name == "Extensions") {
                continue;
            }
            auto nc = nodeClassOf(name);
            if (!nc) return failAt(e, "unexpected element '" + std::string(e.name()) + "'");
            ParsedNode pn;
            if (!parseNode(e, *nc, pn)) return status_;
            out.nodes.push_back(std::move(pn));
        }
        // Pass 3: data types (supertypes, encodings, definitions) into a registry layered
        // over the address space's, then the values, which may be structures of those types.
        if (!collectDataTypes(out)) return status_;
        for (const auto& [index, valueElement] : pendingValues_) {
            auto value = parseVariant(valueElement);
            if (!value) return status_;
            out.nodes[index].node.value.value = std::move(*value);
        }
        NodeSetStatus ok;
        ok.nodes = out.nodes.size();
        for (const auto& n : out.nodes) ok.references += n.references.size();
        return ok;
    }

    static std::optional<NodeClass> nodeClassOf(std::string_view name) {
        if (name == "UAObject") return NodeClass::Object;
        if (name == "UAVariable") return NodeClass::Variable;
        if (name == "UAMethod") return NodeClass::Method;
        if (name == "UAObjectType") return NodeClass::ObjectType;
        if (name == "UAVariableType") return NodeClass::VariableType;
        if (name == "UAReferenceType") return NodeClass::ReferenceType;
        if (name == "UADataType") return NodeClass::DataType;
        if (name == "UAView") return NodeClass::View;
        return std::nullopt;
    }

    /// Lines are asked for in document order, so counting on from the last answer keeps
    /// the whole parse linear in the file size.
    std::size_t lineOf(std::size_t offset) {
        // Where each line starts, found once: the values are read after all the nodes, so
        // offsets come back to the start again and again (counting newlines up to each was
        // an eighth of a component's model loading).
        if (lineStarts_.empty()) {
            lineStarts_.push_back(0);
            for (std::size_t i = xml_.find('\n'); i != std::string_view::npos;
                 i = xml_.find('\n', i + 1)) {
                lineStarts_.push_back(i + 1);
            }
        }
        offset = std::min(offset, xml_.size());
        const auto after = std::upper_bound(lineStarts_.begin(), lineStarts_.end(), offset);
        return static_cast<std::size_t>(after - lineStarts_.begin());
    }
    std::size_t lineOf(const pugi::xml_node& n) {
        const auto off = n.offset_debug();
        return off < 0 ? 0 : lineOf(static_cast<std::size_t>(off));
    }
    NodeSetStatus fail(std::size_t offset, std::string what) {
        status_.error = source_ + ":" + std::to_string(lineOf(offset)) + ": " + std::move(what);
        return status_;
    }
    NodeSetStatus failAt(const pugi::xml_node& n, std::string what) {
        status_.error = source_ + ":" + std::to_string(lineOf(n)) + ": " + std::move(what);
        return status_;
    }

    std::optional<std::uint16_t> mapNamespace(const pugi::xml_node& at, std::uint32_t fileIndex) {
        if (fileIndex >= nsMap_.size()) {
            failAt(at, "namespace index " + std::to_string(fileIndex) +
                           " is not declared in NamespaceUris");
            return std::nullopt;
        }
        return nsMap_[fileIndex];
    }

    /// NodeId text or, when allowed, an alias name.
    std::optional<NodeId> parseNodeIdText(const pugi::xml_node& at, std::string_view text,
                                          bool allowAlias = true) {
        if (allowAlias && text.find('=') == std::string_view::npos) {
            auto it = aliases_.find(text);  // no string made: every reference names one
            if (it == aliases_.end()) {
                failAt(at, "unknown alias '" + std::string(text) + "'");
                return std::nullopt;
            }
            return it->second;
        }
        auto id = NodeId::parse(text);
        if (!id) {
            failAt(at, "bad NodeId '" + std::string(text) + "'");
            return std::nullopt;
        }
        auto ns = mapNamespace(at, id->namespaceIndex());
        if (!ns) return std::nullopt;
        if (*ns == id->namespaceIndex()) return id;
        return std::visit([&](const auto& v) { return NodeId(*ns, v); }, id->identifier());
    }

    std::optional<QualifiedName> parseBrowseName(const pugi::xml_node& at, std::string_view text) {
        // "n:Name" names namespace n of the file; a colon not preceded by digits is part of
        // the name.
        const auto colon = text.find(':');
        if (colon != std::string_view::npos && colon > 0) {
            if (auto idx = parseNumber<std::uint32_t>(text.substr(0, colon))) {
                auto ns = mapNamespace(at, *idx);
                if (!ns) return std::nullopt;
                return QualifiedName{*ns, String(text.substr(colon + 1))};
            }
        }
        return QualifiedName{0, String(text)};
    }

    template <class T>
    bool numberAttr(const pugi::xml_node& e, const char* name, T& out) {
        const auto a = e.attribute(name);
        return !a || numberValue(e, a, out);
    }
    bool boolAttr(const pugi::xml_node& e, const char* name, bool& out) {
        const auto a = e.attribute(name);
        return !a || boolValue(e, a, out);
    }
    /// The number attribute `a` of `e` into `out`; a bad one fails, naming it.
    template <class T>
    bool numberValue(const pugi::xml_node& e, const pugi::xml_attribute& a, T& out) {
        auto v = parseNumber<T>(a.value());
        if (!v) {
            failAt(e, std::string("bad ") + a.name() + " '" + a.value() + "'");
            return false;
        }
        out = *v;
        return true;
    }
    bool boolValue(const pugi::xml_node& e, const pugi::xml_attribute& a, bool& out) {
        auto v = parseBool(a.value());
        if (!v) {
            failAt(e,
                   std::string("bad ") + a.name() + " '" + a.value() + "' (expected true/false)");
            return false;
        }
        out = *v;
        return true;
    }
    static LocalizedText localizedText(const pugi::xml_node& e) {
        return LocalizedText{e.attribute("Locale").value(), String(trim(e.text().get()))};
    }

    bool parseNode(const pugi::xml_node& e, NodeClass nc, ParsedNode& pn) {
        Node& n = pn.node;
        pn.line = lineOf(e);
        n.nodeClass = nc;
        // One pass over the attributes and one over the children: asking for each by name
        // scans them all again, and a node has some fifteen to ask for (most of a
        // component's start went to reading its models).
        pugi::xml_attribute idAttr, bn, dt, ad;
        bool ok = true;
        for (auto a : e.attributes()) {
            const std::string_view name = a.name();
            if (name == "NodeId") {
                idAttr = a;
            } else if (name == "BrowseName") {
                bn = a;
            } else if (name == "DataType") {
                dt = a;
            } else if (name == "ArrayDimensions") {
                ad = a;
            } else if (name == "WriteMask") {
                ok = numberValue(e, a, n.writeMask);
            } else if (name == "UserWriteMask") {
                ok = numberValue(e, a, n.userWriteMask);
            } else if (name == "IsAbstract") {
                ok = boolValue(e, a, n.isAbstract);
            } else if (name == "Symmetric") {
                ok = boolValue(e, a, n.symmetric);
            } else if (name == "EventNotifier") {
                ok = numberValue(e, a, n.eventNotifier);
            } else if (name == "ContainsNoLoops") {
                ok = boolValue(e, a, n.containsNoLoops);
            } else if (name == "ValueRank") {
                ok = numberValue(e, a, n.valueRank);
            } else if (name == "AccessLevel") {
                ok = numberValue(e, a, n.accessLevel);
            } else if (name == "UserAccessLevel") {
                ok = numberValue(e, a, n.userAccessLevel);
            } else if (name == "MinimumSamplingInterval") {
                ok = numberValue(e, a, n.minimumSamplingInterval);
            } else if (name == "Historizing") {
                ok = boolValue(e, a, n.historizing);
            } else if (name == "Executable") {
                ok = boolValue(e, a, n.executable);
            } else if (name == "UserExecutable") {
                ok = boolValue(e, a, n.userExecutable);
            }
            if (!ok) return false;
        }
        pugi::xml_node dn, desc, inv, refs, v, def;
        for (auto c : e.children()) {
            if (c.type() != pugi::node_element) continue;
            const auto name = localName(c);
            auto first = [&c](pugi::xml_node& slot) {
                if (!slot) slot = c;
            };
            if (name == "DisplayName") {
                first(dn);
            } else if (name == "Description") {
                first(desc);
            } else if (name == "InverseName") {
                first(inv);
            } else if (name == "References") {
                first(refs);
            } else if (name == "Value") {
                first(v);
            } else if (name == "Definition") {
                first(def);
            }
        }
        if (!idAttr) return failAt(e, "node without NodeId"), false;
        auto id = parseNodeIdText(e, idAttr.value(), false);
        if (!id) return false;
        n.nodeId = std::move(*id);
        if (!bn || std::string_view(bn.value()).empty()) {
            return failAt(e, "node " + n.nodeId.toString() + " without BrowseName"), false;
        }
        auto qn = parseBrowseName(e, bn.value());
        if (!qn) return false;
        n.browseName = std::move(*qn);
        if (dn) {
            n.displayName = localizedText(dn);
        } else {
            n.displayName.text = n.browseName.name;
        }
        if (desc) n.description = localizedText(desc);
        if (inv) n.inverseName = localizedText(inv);
        if (dt) {
            auto t = parseNodeIdText(e, trim(dt.value()));
            if (!t) return false;
            n.dataType = std::move(*t);
        }
        if (ad) {
            if (!parseDimensions(e, ad.value(), n.arrayDimensions)) return false;
        }
        if (refs) {
            for (auto r : refs.children()) {
                if (r.type() != pugi::node_element) continue;
                if (localName(r) != "Reference") {
                    return failAt(r, "unexpected element '" + std::string(r.name()) + "'"), false;
                }
                ParsedReference pr;
                pr.line = lineOf(r);
                const auto rt = r.attribute("ReferenceType");
                if (!rt) return failAt(r, "Reference without ReferenceType"), false;
                auto type = parseNodeIdText(r, trim(rt.value()));
                if (!type) return false;
                pr.referenceTypeId = std::move(*type);
                if (!boolAttr(r, "IsForward", pr.isForward)) return false;
                auto target = parseNodeIdText(r, trim(r.text().get()));
                if (!target) return false;
                pr.target = std::move(*target);
                pn.references.push_back(std::move(pr));
            }
        }
        if (v) {
            pugi::xml_node typed;
            for (auto c : v.children()) {
                if (c.type() == pugi::node_element) {
                    typed = c;
                    break;
                }
            }
            if (typed) pendingValues_.emplace_back(nodeIndex_, typed);
        }
        if (def) {
            if (nc != NodeClass::DataType)
                return failAt(def, "Definition on a node that is not a DataType"), false;
            if (!parseDefinition(def, pn)) return false;
        }
        ++nodeIndex_;
        return true;
    }

    /// <Definition>: enumerations (fields with Value, or a subtype of Enumeration) become
    /// an EnumDefinition, everything else a StructureDefinition. Encoding ids and base type
    /// are filled in by collectDataTypes once all references are known.
    bool parseDefinition(const pugi::xml_node& d, ParsedNode& pn) {
        bool isEnum = false;
        for (const auto& r : pn.references) {
            if (!r.isForward && r.referenceTypeId == NodeId(ns0::HasSubtype) &&
                r.target == NodeId(ns0::Enumeration)) {
                isEnum = true;
            }
        }
        for (auto f : d.children()) {
            if (f.type() == pugi::node_element && localName(f) == "Field" && f.attribute("Value")) {
                isEnum = true;
            }
        }
        if (isEnum) {
            EnumDefinition def;
            for (auto f : d.children()) {
                if (f.type() != pugi::node_element || localName(f) != "Field") continue;
                EnumField ef;
                ef.name = f.attribute("Name").value();
                if (ef.name.empty()) return failAt(f, "Definition field without Name"), false;
                if (!numberAttr(f, "Value", ef.value)) return false;
                if (auto dn = child(f, "DisplayName")) {
                    ef.displayName = localizedText(dn);
                } else {
                    ef.displayName.text = ef.name;
                }
                if (auto ds = child(f, "Description")) ef.description = localizedText(ds);
                def.fields.push_back(std::move(ef));
            }
            pn.node.definition = std::move(def);
            return true;
        }
        StructureDefinition def;
        bool isUnion = false;
        if (!boolAttr(d, "IsUnion", isUnion)) return false;
        bool anyOptional = false;
        for (auto f : d.children()) {
            if (f.type() != pugi::node_element || localName(f) != "Field") continue;
            StructureField sf;
            sf.name = f.attribute("Name").value();
            if (sf.name.empty()) return failAt(f, "Definition field without Name"), false;
            const auto dt = f.attribute("DataType");
            if (dt) {
                auto t = parseNodeIdText(f, trim(dt.value()));
                if (!t) return false;
                sf.dataType = std::move(*t);
            } else {
                sf.dataType = NodeId(ns0::BaseDataType);
            }
            if (!numberAttr(f, "ValueRank", sf.valueRank) ||
                !numberAttr(f, "MaxStringLength", sf.maxStringLength) ||
                !boolAttr(f, "IsOptional", sf.isOptional)) {
                return false;
            }
            if (auto ad = f.attribute("ArrayDimensions")) {
                if (!parseDimensions(f, ad.value(), sf.arrayDimensions)) return false;
            }
            if (auto ds = child(f, "Description")) sf.description = localizedText(ds);
            anyOptional = anyOptional || sf.isOptional;
            def.fields.push_back(std::move(sf));
        }
        def.structureType = isUnion       ? StructureType::Union
                            : anyOptional ? StructureType::StructureWithOptionalFields
                                          : StructureType::Structure;
        pn.node.definition = std::move(def);
        return true;
    }

    bool parseDimensions(const pugi::xml_node& e, std::string_view text,
                         std::vector<std::uint32_t>& out) {
        std::string_view rest = text;
        while (!trim(rest).empty()) {
            const auto comma = rest.find(',');
            auto d = parseNumber<std::uint32_t>(rest.substr(0, comma));
            if (!d) return failAt(e, "bad ArrayDimensions '" + std::string(text) + "'"), false;
            out.push_back(*d);
            if (comma == std::string_view::npos) break;
            rest.remove_prefix(comma + 1);
        }
        return true;
    }

    bool modelDate(const pugi::xml_node& e, std::optional<DateTime>& out) {
        const auto a = e.attribute("PublicationDate");
        if (!a) return true;
        out = parseDateTime(a.value());
        if (!out) return failAt(e, std::string("bad PublicationDate '") + a.value() + "'"), false;
        return true;
    }

    /// Registers every DataType of the file in the parser's registry (supertype, encodings,
    /// definition) and completes the definitions' base type and default encoding.
    bool collectDataTypes(ParsedNodeSet& out) {
        std::unordered_map<NodeId, std::size_t> byId;
        for (std::size_t i = 0; i < out.nodes.size(); ++i)
            byId.emplace(out.nodes[i].node.nodeId, i);
        const auto browseNameOf = [&](const NodeId& id) -> const QualifiedName* {
            auto it = byId.find(id);
            if (it != byId.end()) return &out.nodes[it->second].node.browseName;
            const Node* n = as_.find(id);
            return n != nullptr ? &n->browseName : nullptr;
        };
        std::unordered_map<NodeId, DataTypeInfo> infos;
        const auto infoFor = [&](const NodeId& id) -> DataTypeInfo* {
            auto it = byId.find(id);
            if (it == byId.end() || out.nodes[it->second].node.nodeClass != NodeClass::DataType) {
                return nullptr;
            }
            auto& info = infos[id];
            info.dataTypeId = id;
            return &info;
        };
        const auto noteEncoding = [&](DataTypeInfo& info, const NodeId& encoding) {
            const QualifiedName* name = browseNameOf(encoding);
            if (name == nullptr) return;
            if (name->name == "Default Binary") info.binaryEncodingId = encoding;
            if (name->name == "Default XML") info.xmlEncodingId = encoding;
        };
        for (const auto& pn : out.nodes) {
            if (pn.node.nodeClass == NodeClass::DataType) {
                DataTypeInfo* info = infoFor(pn.node.nodeId);
                info->browseName = pn.node.browseName;
                info->definition = pn.node.definition;
            }
            for (const auto& r : pn.references) {
                if (r.referenceTypeId == NodeId(ns0::HasSubtype)) {
                    const NodeId& sub = r.isForward ? r.target : pn.node.nodeId;
                    const NodeId& super = r.isForward ? pn.node.nodeId : r.target;
                    if (DataTypeInfo* info = infoFor(sub)) info->superType = super;
                } else if (r.referenceTypeId == NodeId(ns0::HasEncoding)) {
                    const NodeId& type = r.isForward ? pn.node.nodeId : r.target;
                    const NodeId& encoding = r.isForward ? r.target : pn.node.nodeId;
                    if (DataTypeInfo* info = infoFor(type)) noteEncoding(*info, encoding);
                }
            }
        }
        for (auto& [id, info] : infos) {
            if (auto* def = std::get_if<StructureDefinition>(&info.definition)) {
                def->baseDataType = info.superType;
                def->defaultEncodingId = info.binaryEncodingId;
                out.nodes[byId[id]].node.definition = *def;
            }
            types_.add(info);
            out.dataTypes.push_back(info);
        }
        return true;
    }

    // --- Values in the XML Variant encoding (OPC 10000-6, 5.3.1) ---------------------------

    std::optional<Scalar> parseScalar(const pugi::xml_node& e, std::string_view type) {
        const std::string_view text = e.text().get();
        const auto bad = [&]() -> std::optional<Scalar> {
            failAt(e, "bad " + std::string(type) + " value '" + std::string(trim(text)) + "'");
            return std::nullopt;
        };
        const auto num = [&]<class T>(T) -> std::optional<Scalar> {
            auto v = parseNumber<T>(text);
            if (!v) return bad();
            return Scalar(*v);
        };
        const auto builtin = builtinTypeByName(type);  // the element is named after its type
        if (!builtin) {
            failAt(e, "unsupported value type '" + std::string(type) + "'");
            return std::nullopt;
        }
        switch (*builtin) {
            case BuiltinType::Boolean: {
                auto b = parseBool(text);
                if (!b) return bad();
                return Scalar(*b);
            }
            case BuiltinType::SByte:
                return num(std::int8_t{});
            case BuiltinType::Byte:
                return num(std::uint8_t{});
            case BuiltinType::Int16:
                return num(std::int16_t{});
            case BuiltinType::UInt16:
                return num(std::uint16_t{});
            case BuiltinType::Int32:
                return num(std::int32_t{});
            case BuiltinType::UInt32:
                return num(std::uint32_t{});
            case BuiltinType::Int64:
                return num(std::int64_t{});
            case BuiltinType::UInt64:
                return num(std::uint64_t{});
            case BuiltinType::Float:
                return num(float{});
            case BuiltinType::Double:
                return num(double{});
            case BuiltinType::String:
                return Scalar(String(text));
            case BuiltinType::DateTime: {
                auto d = parseDateTime(text);
                if (!d) return bad();
                return Scalar(*d);
            }
            case BuiltinType::StatusCode: {
                auto c = parseNumber<std::uint32_t>(child(e, "Code").text().get());
                if (!c) return bad();
                return Scalar(StatusCode{*c});
            }
            case BuiltinType::LocalizedText:
                return Scalar(LocalizedText{String(trim(child(e, "Locale").text().get())),
                                            String(child(e, "Text").text().get())});
            case BuiltinType::QualifiedName: {
                std::uint32_t fileNs = 0;
                if (auto ni = child(e, "NamespaceIndex")) {
                    auto v = parseNumber<std::uint32_t>(ni.text().get());
                    if (!v) return bad();
                    fileNs = *v;
                }
                auto ns = mapNamespace(e, fileNs);
                if (!ns) return std::nullopt;
                return Scalar(QualifiedName{*ns, String(trim(child(e, "Name").text().get()))});
            }
            case BuiltinType::NodeId:
            case BuiltinType::ExpandedNodeId: {
                // An alias is accepted where a NodeId is written (Argument DataTypes often
                // are); an empty Identifier is the null NodeId.
                const bool plain = *builtin == BuiltinType::NodeId;
                const auto idText = trim(child(e, "Identifier").text().get());
                if (idText.empty()) return plain ? Scalar(NodeId{}) : Scalar(ExpandedNodeId{});
                auto id = parseNodeIdText(e, idText, true);
                if (!id) return std::nullopt;
                if (plain) return Scalar(std::move(*id));
                return Scalar(ExpandedNodeId{std::move(*id), {}, 0});
            }
            case BuiltinType::Guid: {
                // <Guid><String>...</String></Guid>; a bare text body is accepted too.
                const auto str = child(e, "String");
                const std::string_view guidText = str ? str.text().get() : text;
                auto g = parseGuid(guidText);
                if (!g) {
                    failAt(e, "bad Guid value '" + std::string(trim(guidText)) + "'");
                    return std::nullopt;
                }
                return Scalar(*g);
            }
            case BuiltinType::ByteString: {
                auto b = decodeBase64(text);
                if (!b) return bad();
                return Scalar(ByteString(std::move(*b)));
            }
            case BuiltinType::XmlElement: {
                std::ostringstream xml;
                for (auto c : e.children()) c.print(xml, "", pugi::format_raw);
                return Scalar(XmlElement{std::move(xml).str()});
            }
            case BuiltinType::ExtensionObject:
                return parseExtensionObject(e);
            case BuiltinType::Null:
            case BuiltinType::DataValue:
            case BuiltinType::Variant:
            case BuiltinType::DiagnosticInfo:
                break;
        }
        failAt(e, "unsupported value type '" + std::string(type) + "'");
        return std::nullopt;
    }

    std::optional<Scalar> parseExtensionObject(const pugi::xml_node& e) {
        const auto body = child(e, "Body");
        pugi::xml_node content;
        for (auto c : body.children()) {
            if (c.type() == pugi::node_element) {
                content = c;
                break;
            }
        }
        if (!content) {
            failAt(e, "ExtensionObject without a Body");
            return std::nullopt;
        }
        // The TypeId names the XML encoding (sometimes the binary one or the data type); a
        // file that leaves it out is understood by the body's element name.
        const DataTypeInfo* info = nullptr;
        const std::string_view typeText =
            trim(child(child(e, "TypeId"), "Identifier").text().get());
        if (!typeText.empty()) {
            auto typeId = parseNodeIdText(e, typeText, true);
            if (!typeId) return std::nullopt;
            info = types_.findByEncoding(*typeId);
            if (info == nullptr) info = types_.find(*typeId);
        }
        if (info == nullptr) info = types_.findByName(localName(content));
        if (info == nullptr || types_.structureOf(info->dataTypeId) == nullptr) {
            failAt(content,
                   "unsupported ExtensionObject body '" + std::string(content.name()) +
                       "' (no structure with a DataTypeDefinition of that type is loaded)");
            return std::nullopt;
        }
        auto value = parseStructure(content, info->dataTypeId, 0);
        if (!value) return std::nullopt;
        // Stored binary-encoded, the form the services hand out.
        auto eo = toExtensionObject(types_, *value);
        if (!eo) {
            failAt(content, "cannot encode " + std::string(content.name()) + ": " +
                                std::string(statusName(eo.status())));
            return std::nullopt;
        }
        return Scalar(std::move(*eo));
    }

    /// A structure in the XML encoding (OPC 10000-6, 5.3.6): one element per field, named
    /// like the field; a missing field keeps its default (absent if optional).
    std::optional<DynamicStructure> parseStructure(const pugi::xml_node& e, const NodeId& type,
                                                   int depth) {
        if (depth > static_cast<int>(DecodeLimits{}.maxDepth)) {
            failAt(e, "structure nested too deeply");
            return std::nullopt;
        }
        const StructureDefinition* def = types_.structureOf(type);
        auto value = defaultStructure(types_, type);
        if (def == nullptr || !value) {
            failAt(e, "no usable definition for structure " + type.toString());
            return std::nullopt;
        }
        for (std::size_t i = 0; i < def->fields.size(); ++i) {
            const StructureField& f = def->fields[i];
            const auto fe = child(e, f.name);
            if (!fe) continue;
            auto v = parseField(fe, f, depth);
            if (!v) return std::nullopt;
            value->fields[i].value = std::move(*v);
        }
        return std::move(*value);
    }

    std::optional<Variant> parseField(const pugi::xml_node& e, const StructureField& f, int depth) {
        const bool isArray = f.valueRank >= 0;
        if (types_.structureOf(f.dataType) != nullptr) {
            const auto one = [&](const pugi::xml_node& el) -> std::optional<Scalar> {
                auto s = parseStructure(el, f.dataType, depth + 1);
                if (!s) return std::nullopt;
                auto eo = toExtensionObject(types_, *s);
                if (!eo) {
                    failAt(el, "cannot encode field " + f.name);
                    return std::nullopt;
                }
                return Scalar(std::move(*eo));
            };
            if (!isArray) {
                auto s = one(e);
                if (!s) return std::nullopt;
                return Variant::fromScalar(std::move(*s));
            }
            std::vector<Scalar> elements;
            for (auto c : e.children()) {
                if (c.type() != pugi::node_element) continue;
                auto s = one(c);
                if (!s) return std::nullopt;
                elements.push_back(std::move(*s));
            }
            return Variant::array(BuiltinType::ExtensionObject, std::move(elements));
        }
        const auto bt = types_.builtinTypeOf(f.dataType);
        if (!bt) {
            failAt(e, "field " + f.name + " has unknown data type " + f.dataType.toString());
            return std::nullopt;
        }
        if (*bt == BuiltinType::Variant) {
            // BaseDataType: <Field><Value><Int32>..</Int32></Value></Field> or the typed
            // element directly.
            pugi::xml_node typed = firstElement(e);
            if (typed && localName(typed) == "Value") typed = firstElement(typed);
            if (!typed) return Variant{};
            return parseVariant(typed);
        }
        const std::string_view typeName = builtinTypeName(*bt);
        const bool isEnum = *bt == BuiltinType::Int32 && !isBuiltinId(f.dataType);
        const auto one = [&](const pugi::xml_node& el) -> std::optional<Scalar> {
            if (isEnum) return parseEnumValue(el);
            return parseScalar(el, typeName);
        };
        if (!isArray) {
            auto s = one(e);
            if (!s) return std::nullopt;
            return Variant::fromScalar(std::move(*s));
        }
        std::vector<Scalar> elements;
        for (auto c : e.children()) {
            if (c.type() != pugi::node_element) continue;
            auto s = one(c);
            if (!s) return std::nullopt;
            elements.push_back(std::move(*s));
        }
        return Variant::array(*bt, std::move(elements));
    }

    /// Enumerations are written "Name_Value" ("Running_13") or as the bare number.
    std::optional<Scalar> parseEnumValue(const pugi::xml_node& e) {
        std::string_view text = trim(e.text().get());
        const auto us = text.rfind('_');
        auto v =
            parseNumber<std::int32_t>(us == std::string_view::npos ? text : text.substr(us + 1));
        if (!v) {
            failAt(e, "bad enumeration value '" + std::string(text) + "'");
            return std::nullopt;
        }
        return Scalar(*v);
    }

    static bool isBuiltinId(const NodeId& id) {
        const auto* n = std::get_if<std::uint32_t>(&id.identifier());
        return id.namespaceIndex() == 0 && n != nullptr && *n >= 1 && *n <= kMaxBuiltinType;
    }

    static pugi::xml_node firstElement(const pugi::xml_node& e) {
        for (auto c : e.children()) {
            if (c.type() == pugi::node_element) return c;
        }
        return {};
    }

    std::optional<Variant> parseVariant(const pugi::xml_node& e) {
        const auto name = localName(e);
        if (name.starts_with("ListOf")) {
            const auto type = name.substr(6);
            std::vector<Scalar> elements;
            for (auto c : e.children()) {
                if (c.type() != pugi::node_element) continue;
                if (localName(c) != type) {
                    failAt(c, "element '" + std::string(c.name()) + "' in " + std::string(name));
                    return std::nullopt;
                }
                auto s = parseScalar(c, type);
                if (!s) return std::nullopt;
                elements.push_back(std::move(*s));
            }
            const auto typeId = elements.empty()
                                    ? builtinTypeOfElement(e, type)
                                    : std::optional<BuiltinType>(
                                          static_cast<BuiltinType>(elements.front().index()));
            if (!typeId) return std::nullopt;
            return Variant::array(*typeId, std::move(elements));
        }
        auto s = parseScalar(e, name);
        if (!s) return std::nullopt;
        return Variant::fromScalar(std::move(*s));
    }

    std::optional<BuiltinType> builtinTypeOfElement(const pugi::xml_node& e,
                                                    std::string_view type) {
        auto bt = builtinTypeByName(type);
        if (!bt) failAt(e, "unsupported value type '" + std::string(type) + "'");
        return bt;
    }

    const AddressSpace& as_;
    // The file's data types over the address space's: values may use either.
    DataTypeRegistry types_{&as_.dataTypes()};
    std::vector<std::pair<std::size_t, pugi::xml_node>> pendingValues_;
    std::size_t nodeIndex_ = 0;
    std::string_view xml_;
    std::string source_;
    std::vector<std::uint16_t> nsMap_;
    std::unordered_map<std::string, NodeId, TextHash, std::equal_to<>> aliases_;
    NodeSetStatus status_;
    std::vector<std::size_t> lineStarts_;  // offsets of the lines' first characters
};

std::string lineText(const ParsedNodeSet& p, std::size_t line) {
    return p.source + ":" + std::to_string(line) + ": ";
}

// Required models first (loaded before, or declared by this file, and recent enough): a
// file loaded before its prerequisites is told so, not that a node or a type is missing.
NodeSetStatus checkRequiredModels(const AddressSpace& as, const ParsedNodeSet& parsed) {
    NodeSetStatus st;
    for (const auto& m : parsed.models) {
        for (const auto& req : m.required) {
            const AddressSpace::Model* loaded = as.findModel(req.uri);
            AddressSpace::Model sameFile;
            if (loaded == nullptr) {
                for (const auto& other : parsed.models) {
                    if (other.uri == req.uri) {
                        sameFile = {other.uri, other.version, other.publicationDate};
                        loaded = &sameFile;
                    }
                }
            }
            const bool tooOld =
                loaded != nullptr &&
                ((!req.version.empty() && compareVersions(loaded->version, req.version) < 0) ||
                 (req.publicationDate && loaded->publicationDate &&
                  *loaded->publicationDate < *req.publicationDate));
            if (loaded == nullptr || tooOld) {
                std::string want = req.version.empty() ? "" : " version " + req.version;
                if (req.publicationDate) {
                    want += " of " + req.publicationDate->toIso8601().substr(0, 10);
                }
                std::string have = "none";
                if (loaded != nullptr) {
                    have = loaded->version.empty() ? "unversioned" : loaded->version;
                    if (loaded->publicationDate) {
                        have += " of " + loaded->publicationDate->toIso8601().substr(0, 10);
                    }
                }
                st.error = lineText(parsed, m.line);
                st.error.append("requires model ")
                    .append(req.uri)
                    .append(want)
                    .append(" or later, loaded: ")
                    .append(have);
                return st;
            }
        }
    }
    return st;
}

}  // namespace

std::vector<std::uint16_t> namespaceMap(const AddressSpace& as,
                                        std::span<const std::string> fileUris) {
    std::vector<std::uint16_t> map;
    map.reserve(fileUris.size());
    auto next = static_cast<std::uint16_t>(as.namespaces().size());
    for (std::size_t i = 0; i < fileUris.size(); ++i) {
        if (auto known = as.namespaceIndex(fileUris[i])) {
            map.push_back(*known);
            continue;
        }
        // A URI listed twice in the file maps to the same new index.
        const auto end = fileUris.begin() + static_cast<std::ptrdiff_t>(i);
        const auto prev = std::find(fileUris.begin(), end, fileUris[i]);
        if (prev != end) {
            map.push_back(map[static_cast<std::size_t>(prev - fileUris.begin())]);
        } else {
            map.push_back(next++);
        }
    }
    return map;
}

std::vector<std::string> serverNamespaceTable(const AddressSpace& as,
                                              std::span<const std::string> fileUris,
                                              std::span<const std::uint16_t> map) {
    std::vector<std::string> table(as.namespaces().begin(), as.namespaces().end());
    for (std::size_t i = 0; i < fileUris.size(); ++i) {
        if (map[i] >= table.size()) table.resize(std::size_t{map[i]} + 1);
        table[map[i]] = fileUris[i];
    }
    return table;
}

NodeSetStatus parseNodeSet(const AddressSpace& as, std::string_view xml,
                           std::string_view sourceName, ParsedNodeSet& out) {
    out = ParsedNodeSet{};
    return Parser(as, xml, sourceName).run(out);
}

namespace {

// commitNodeSet, for a parsed set to copy from or (`Parsed` not const) to move from: a load
// that parses only to commit need not copy each node's attributes and values once more.
template <class Parsed>
NodeSetStatus commit(AddressSpace& as, Parsed& parsed) {
    // Check everything first: a failed load leaves the address space as it was.
    NodeSetStatus st = checkRequiredModels(as, parsed);
    if (!st.ok()) return st;

    std::unordered_map<NodeId, const ParsedNode*> inFile;
    inFile.reserve(parsed.nodes.size());
    for (const auto& pn : parsed.nodes) {
        if (as.find(pn.node.nodeId) != nullptr) {
            st.error = lineText(parsed, pn.line) + "node " + pn.node.nodeId.toString() +
                       " already exists in the address space";
            return st;
        }
        if (!inFile.emplace(pn.node.nodeId, &pn).second) {
            st.error = lineText(parsed, pn.line) + "duplicate node " + pn.node.nodeId.toString();
            return st;
        }
    }
    const auto exists = [&](const NodeId& id) -> const Node* {
        auto it = inFile.find(id);
        if (it != inFile.end()) return &it->second->node;
        return as.find(id);
    };
    for (const auto& pn : parsed.nodes) {
        for (const auto& r : pn.references) {
            const Node* type = exists(r.referenceTypeId);
            if (type == nullptr || type->nodeClass != NodeClass::ReferenceType) {
                st.error = lineText(parsed, r.line) + "unknown reference type " +
                           r.referenceTypeId.toString();
                return st;
            }
            if (exists(r.target) == nullptr) {
                st.error =
                    lineText(parsed, r.line) + "reference to unknown node " + r.target.toString();
                return st;
            }
        }
    }

    for (const auto& uri : parsed.namespaceUris) (void)as.registerNamespace(uri);
    for (const auto& m : parsed.models) as.registerModel({m.uri, m.version, m.publicationDate});
    for (const auto& info : parsed.dataTypes) as.dataTypes().add(info);
    for (auto& pn : parsed.nodes) {
        const NodeId id = pn.node.nodeId;
        Result<Node*> added = status::BadInternalError;
        if constexpr (std::is_const_v<Parsed>) {
            added = as.addNode(pn.node);
        } else {
            added = as.addNode(std::move(pn.node));
            pn.node.nodeId = id;  // the references below still name it
        }
        if (!added) {  // checked above; kept so an invariant break is not silent
            st.error = lineText(parsed, pn.line) + "cannot add node " + id.toString();
            return st;
        }
        ++st.nodes;
    }
    for (const auto& pn : parsed.nodes) {
        for (const auto& r : pn.references) {
            (void)as.addReference(pn.node.nodeId, r.referenceTypeId, r.target, r.isForward);
            ++st.references;
        }
    }
    return st;
}

}  // namespace

NodeSetStatus commitNodeSet(AddressSpace& as, const ParsedNodeSet& parsed) {
    return commit(as, parsed);
}

NodeSetStatus commitNodeSet(AddressSpace& as, ParsedNodeSet&& parsed) {
    return commit(as, parsed);
}

NodeSetStatus loadNodeSet(AddressSpace& as, std::string_view xml, std::string_view sourceName) {
    ParsedNodeSet parsed;
    auto st = parseNodeSet(as, xml, sourceName, parsed);
    if (!st.ok()) return st;
    return commit(as, parsed);
}

NodeSetStatus loadNodeSetFile(AddressSpace& as, const std::filesystem::path& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) return NodeSetStatus{path.string() + ": cannot open file", 0, 0};
    std::ostringstream buf;
    buf << in.rdbuf();
    const std::string xml = std::move(buf).str();
    return loadNodeSet(as, xml, path.string());
}

}  // namespace skillcell::ua
