#include "kb/owl/nodeset_ontology.hpp"

#include <charconv>
#include <cmath>
#include <map>
#include <set>
#include <unordered_map>

#include "kb/owl/embedded_ontologies.hpp"
#include "kb/owl/node_iri.hpp"
#include "kb/owl/ua_vocabulary.hpp"
#include "ua/address_space/ns0_ids.hpp"
#include "ua/nodeset/companion_models.hpp"
#include "ua/nodeset/embedded_models.hpp"

namespace skillcell::kb::owl {
namespace {

using rdf::iri;
using rdf::literal;
using rdf::Term;
using rdf::Triple;

std::string rdfTerm(std::string_view local) {
    return std::string(rdf::vocab::kRdf) + std::string(local);
}
std::string rdfsTerm(std::string_view local) {
    return std::string(rdf::vocab::kRdfs) + std::string(local);
}
std::string owlTerm(std::string_view local) {
    return std::string(rdf::vocab::kOwl) + std::string(local);
}
std::string xsdTerm(std::string_view local) {
    return std::string(rdf::vocab::kXsd) + std::string(local);
}

std::string_view nodeClassTerm(ua::NodeClass c) {
    switch (c) {
        case ua::NodeClass::Object:
            return term::kObjectNode;
        case ua::NodeClass::Variable:
            return term::kVariableNode;
        case ua::NodeClass::Method:
            return term::kMethodNode;
        case ua::NodeClass::ObjectType:
            return term::kObjectTypeNode;
        case ua::NodeClass::VariableType:
            return term::kVariableTypeNode;
        case ua::NodeClass::ReferenceType:
            return term::kReferenceTypeNode;
        case ua::NodeClass::DataType:
            return term::kDataTypeNode;
        case ua::NodeClass::View:
            return term::kViewNode;
        default:
            return {};
    }
}

bool isClassLike(ua::NodeClass c) {
    return c == ua::NodeClass::ObjectType || c == ua::NodeClass::VariableType ||
           c == ua::NodeClass::DataType;
}

std::string doubleText(double d) {
    std::array<char, 32> buf{};
    auto [end, ec] = std::to_chars(buf.data(), buf.data() + buf.size(), d);
    (void)ec;
    std::string s(buf.data(), end);
    // xsd:double's lexical space has no "inf"/"nan" spelled that way.
    if (std::isinf(d)) return d > 0 ? "INF" : "-INF";
    if (std::isnan(d)) return "NaN";
    return s;
}

// A simple scalar value as a typed literal; nullopt for what has no literal form here
// (structures, arrays, node ids).
std::optional<Term> valueLiteral(const ua::Variant& v) {
    if (!v.isScalar()) return std::nullopt;
    return std::visit(
        [](const auto& x) -> std::optional<Term> {
            using T = std::decay_t<decltype(x)>;
            if constexpr (std::is_same_v<T, bool>) {
                return literal(x ? "true" : "false", xsdTerm("boolean"));
            } else if constexpr (std::is_same_v<T, float> || std::is_same_v<T, double>) {
                return literal(doubleText(static_cast<double>(x)), xsdTerm("double"));
            } else if constexpr (std::is_integral_v<T>) {
                return literal(std::to_string(x), xsdTerm("integer"));
            } else if constexpr (std::is_same_v<T, ua::String>) {
                return literal(x);
            } else if constexpr (std::is_same_v<T, ua::LocalizedText>) {
                return literal(x.text);
            } else if constexpr (std::is_same_v<T, ua::QualifiedName>) {
                return literal(x.name);
            } else {
                return std::nullopt;
            }
        },
        v.scalar());
}

struct NodeFacts {
    std::string namespaceUri;
    ua::NodeClass nodeClass = ua::NodeClass::Unspecified;
    std::string browseName;
};

class Converter {
public:
    Converter(const ua::AddressSpace& known, const ua::ParsedNodeSet& parsed)
        : known_(known), parsed_(parsed) {
        for (const auto& p : parsed.nodes) parsedById_.emplace(p.node.nodeId, &p);
    }

    Expected<Ontology> run() {
        Ontology out;
        out.source = parsed_.source;
        if (!header(out)) return Error{error_};
        for (const auto& p : parsed_.nodes) {
            if (!node(p)) return Error{error_};
        }
        units();
        if (!error_.empty()) return Error{error_};
        out.triples.insert(out.triples.end(), std::make_move_iterator(triples_.begin()),
                           std::make_move_iterator(triples_.end()));
        return out;
    }

private:
    bool header(Ontology& out) {
        if (!parsed_.models.empty()) {
            const auto& m = parsed_.models.front();
            out.iri = m.uri;
            out.version = m.version;
            for (const auto& r : m.required) out.imports.push_back(r.uri);
        } else if (!parsed_.namespaceUris.empty()) {
            out.iri = parsed_.namespaceUris.front();
        } else {
            out.iri = "http://opcfoundation.org/UA/";  // the base NodeSet may omit <Models>
        }
        if (out.iri.empty()) return fail("the NodeSet names no model URI");
        out.imports.emplace_back(kCoreOntologyIri);
        const Term self = iri(out.iri);
        add(self, iri(rdfTerm("type")), iri(owlTerm("Ontology")));
        for (const auto& i : out.imports) add(self, iri(owlTerm("imports")), iri(i));
        if (!out.version.empty()) add(self, iri(owlTerm("versionInfo")), literal(out.version));
        return true;
    }

    bool node(const ua::ParsedNode& p) {
        const ua::Node& n = p.node;
        auto self = termOf(n.nodeId, p.line);
        if (!self) return false;
        const Term& s = *self;
        const Term type = iri(rdfTerm("type"));
        const std::string_view classTerm = nodeClassTerm(n.nodeClass);
        if (classTerm.empty())
            return fail("line " + std::to_string(p.line) + ": unknown node class");
        add(s, type, iri(opc(classTerm)));
        if (isClassLike(n.nodeClass)) {
            add(s, type, iri(owlTerm("Class")));
        } else if (n.nodeClass == ua::NodeClass::ReferenceType) {
            add(s, type, iri(owlTerm("ObjectProperty")));
            if (n.symmetric) add(s, type, iri(owlTerm("SymmetricProperty")));
        } else {
            add(s, type, iri(owlTerm("NamedIndividual")));
        }
        const std::string& nsUri = namespaceOf(n.nodeId);
        add(s, iri(opc(term::kNodeId)), literal(expandedNodeIdText(nsUri, n.nodeId)));
        add(s, iri(opc(term::kBrowseName)), literal(n.browseName.name));
        add(s, iri(rdfsTerm("isDefinedBy")), iri(ontologyIri()));
        if (!n.displayName.text.empty())
            add(s, iri(rdfsTerm("label")), literal(n.displayName.text));
        if (!n.description.text.empty()) {
            add(s, iri(rdfsTerm("comment")), literal(n.description.text));
        }
        if (n.nodeClass != ua::NodeClass::Object && n.nodeClass != ua::NodeClass::Variable &&
            n.nodeClass != ua::NodeClass::Method && n.nodeClass != ua::NodeClass::View) {
            add(s, iri(opc(term::kIsAbstract)),
                literal(n.isAbstract ? "true" : "false", xsdTerm("boolean")));
        }
        if (n.nodeClass == ua::NodeClass::Variable || n.nodeClass == ua::NodeClass::VariableType) {
            auto dt = termOf(n.dataType, p.line);
            if (!dt) return false;
            add(s, iri(opc(term::kDataType)), *dt);
            add(s, iri(opc(term::kValueRank)),
                literal(std::to_string(n.valueRank), xsdTerm("integer")));
            if (n.value.value) {
                if (auto v = valueLiteral(*n.value.value)) add(s, iri(opc(term::kValue)), *v);
            }
        }
        for (const auto& r : p.references) {
            if (!reference(n, s, r, p.line)) return false;
        }
        return true;
    }

    bool reference(const ua::Node& n, const Term& s, const ua::ParsedReference& r,
                   std::size_t line) {
        auto refType = termOf(r.referenceTypeId, line);
        auto target = termOf(r.target, line);
        if (!refType || !target) return false;
        // Inverse references are stated from their source, like the forward ones.
        const Term& from = r.isForward ? s : *target;
        const Term& to = r.isForward ? *target : s;
        add(from, *refType, to);
        if (r.referenceTypeId == ua::NodeId(ua::ns0::HasSubtype)) {
            // Subtype -> supertype, whichever end this node is (both ends are of one class).
            if (n.nodeClass == ua::NodeClass::ReferenceType) {
                add(to, iri(rdfsTerm("subPropertyOf")), from);
            } else if (isClassLike(n.nodeClass)) {
                add(to, iri(rdfsTerm("subClassOf")), from);
            }
        } else if (r.referenceTypeId == ua::NodeId(ua::ns0::HasTypeDefinition) && r.isForward) {
            add(s, iri(rdfTerm("type")), *target);
        } else if (r.referenceTypeId == ua::NodeId(ua::ns0::HasProperty)) {
            properties_.emplace_back(r.isForward ? n.nodeId : r.target,
                                     r.isForward ? r.target : n.nodeId);
        }
        return true;
    }

    // EngineeringUnits and EURange, stated on the variable they describe.
    void units() {
        for (const auto& [owner, property] : properties_) {
            auto it = parsedById_.find(property);
            if (it == parsedById_.end()) continue;
            const ua::Node& prop = it->second->node;
            if (!prop.value.value) continue;
            const auto* eo = prop.value.value->get<ua::ExtensionObject>();
            if (eo == nullptr) continue;
            auto decoded = ua::fromExtensionObject(known_.dataTypes(), *eo);
            if (!decoded) continue;  // a structure this address space cannot decode: skip
            auto ownerTerm = termOf(owner, it->second->line);
            if (!ownerTerm) return;
            if (prop.browseName.name == "EngineeringUnits") {
                if (const auto* name = decoded->get("DisplayName")) {
                    if (const auto* text = name->get<ua::LocalizedText>()) {
                        add(*ownerTerm, iri(opc(term::kEngineeringUnits)), literal(text->text));
                    }
                }
            } else if (prop.browseName.name == "EURange") {
                const auto* low = decoded->get("Low");
                const auto* high = decoded->get("High");
                if (low != nullptr && low->get<double>() != nullptr) {
                    add(*ownerTerm, iri(opc(term::kEuRangeLow)),
                        literal(doubleText(*low->get<double>()), xsdTerm("double")));
                }
                if (high != nullptr && high->get<double>() != nullptr) {
                    add(*ownerTerm, iri(opc(term::kEuRangeHigh)),
                        literal(doubleText(*high->get<double>()), xsdTerm("double")));
                }
            }
        }
    }

    const std::string& namespaceOf(const ua::NodeId& id) const {
        static const std::string kUnknown;
        const auto& table = parsed_.serverNamespaces;
        return id.namespaceIndex() < table.size() ? table[id.namespaceIndex()] : kUnknown;
    }

    const NodeFacts* facts(const ua::NodeId& id) {
        if (auto c = cache_.find(id); c != cache_.end()) return &c->second;
        NodeFacts f;
        if (auto it = parsedById_.find(id); it != parsedById_.end()) {
            f.nodeClass = it->second->node.nodeClass;
            f.browseName = it->second->node.browseName.name;
        } else if (const ua::Node* k = known_.find(id)) {
            f.nodeClass = k->nodeClass;
            f.browseName = k->browseName.name;
        } else {
            return nullptr;
        }
        f.namespaceUri = namespaceOf(id);
        if (f.namespaceUri.empty()) return nullptr;
        return &cache_.emplace(id, std::move(f)).first->second;
    }

    std::optional<Term> termOf(const ua::NodeId& id, std::size_t line) {
        const NodeFacts* f = facts(id);
        if (f == nullptr) {
            const std::string& ns = namespaceOf(id);
            fail("line " + std::to_string(line) + ": node " +
                 (ns.empty() ? id.toString() : expandedNodeIdText(ns, id)) +
                 " is neither in this NodeSet nor in the models loaded before it");
            return std::nullopt;
        }
        return iri(nodeIri(f->namespaceUri, id, f->nodeClass, f->browseName));
    }

    std::string ontologyIri() const {
        return !parsed_.models.empty()
                   ? parsed_.models.front().uri
                   : (!parsed_.namespaceUris.empty() ? parsed_.namespaceUris.front()
                                                     : std::string("http://opcfoundation.org/UA/"));
    }

    void add(Term s, Term p, Term o) {
        triples_.push_back(Triple{std::move(s), std::move(p), std::move(o)});
    }

    bool fail(std::string message) {
        if (error_.empty()) error_ = parsed_.source + ": " + std::move(message);
        return false;
    }

    const ua::AddressSpace& known_;
    const ua::ParsedNodeSet& parsed_;
    std::unordered_map<ua::NodeId, const ua::ParsedNode*> parsedById_;
    std::unordered_map<ua::NodeId, NodeFacts> cache_;
    std::vector<std::pair<ua::NodeId, ua::NodeId>> properties_;  // (owner, property)
    std::vector<Triple> triples_;
    std::string error_;
};

}  // namespace

Expected<Ontology> nodeSetToOntology(const ua::AddressSpace& known,
                                     const ua::ParsedNodeSet& parsed) {
    return Converter(known, parsed).run();
}

Expected<std::vector<Ontology>> convertNodeSets(const std::vector<NodeSetText>& files,
                                                bool includeBase, bool afterCompanionModels,
                                                bool withClosure) {
    std::vector<Ontology> out;
    if (includeBase) {
        // Namespace 0 converted on its own: our subset parsed against an empty address
        // space (every node it points to is in the file itself), then the Foundation's
        // nodes the companion models use beyond it, into the same ontology.
        ua::AddressSpace ns0;
        Ontology merged;
        for (const auto& embedded : ua::kNamespaceZeroFiles) {
            const std::string_view file = embedded.fileName;
            if (!withClosure && &embedded != &ua::kNamespaceZeroFiles.front()) break;
            ua::ParsedNodeSet parsed;
            if (auto s = ua::parseNodeSet(ns0, ua::embeddedModel(file), file, parsed); !s.ok()) {
                return Error{s.error};
            }
            auto ontology = nodeSetToOntology(ns0, parsed);
            if (!ontology) return Error{ontology.error()};
            if (auto s = ua::commitNodeSet(ns0, parsed); !s.ok()) return Error{s.error};
            if (merged.iri.empty()) {
                merged = std::move(*ontology);
                continue;
            }
            std::set<Triple> have(merged.triples.begin(), merged.triples.end());
            for (auto& t : ontology->triples) {
                if (have.insert(t).second) merged.triples.push_back(std::move(t));
            }
        }
        out.push_back(std::move(merged));
    }
    ua::AddressSpace known;
    if (auto s = ua::loadBaseNodeSet(known); !s.ok()) return Error{s.error};
    if (afterCompanionModels) {
        if (auto s = ua::loadCompanionModels(known); !s.ok()) return Error{s.error};
    }
    for (const auto& f : files) {
        ua::ParsedNodeSet parsed;
        if (auto s = ua::parseNodeSet(known, f.xml, f.name, parsed); !s.ok()) {
            return Error{s.error};
        }
        auto ontology = nodeSetToOntology(known, parsed);
        if (!ontology) return Error{ontology.error()};
        out.push_back(std::move(*ontology));
        // Committed so that the next NodeSet may require it (and its types decode).
        if (auto s = ua::commitNodeSet(known, parsed); !s.ok()) return Error{s.error};
    }
    return out;
}

Expected<std::vector<Ontology>> embeddedModelOntologies(bool withFoundationModels) {
    std::vector<NodeSetText> files;
    files.reserve(ua::kCompanionModels.size());
    for (const auto& m : ua::kCompanionModels) {
        files.push_back({std::string(m.fileName), std::string(ua::embeddedModel(m.fileName))});
    }
    auto all = convertNodeSets(files, true, false, withFoundationModels);
    if (!all || withFoundationModels) return all;
    // Converted all the same (each file is parsed against the ones before it); dropped here.
    std::erase_if(*all, [](const Ontology& o) {
        return o.iri == ua::companion::kDiUri || o.iri == ua::companion::kIaUri ||
               o.iri == ua::companion::kRoboticsUri;
    });
    return all;
}

std::vector<rdf::Prefix> standardPrefixes() {
    std::vector<rdf::Prefix> p{
        {"rdf", std::string(rdf::vocab::kRdf)},
        {"rdfs", std::string(rdf::vocab::kRdfs)},
        {"owl", std::string(rdf::vocab::kOwl)},
        {"xsd", std::string(rdf::vocab::kXsd)},
        {"opc", std::string(kOpc)},
        {"ua", "http://opcfoundation.org/UA/"},
        {"di", std::string(ua::companion::kDiUri)},
        {"ia", std::string(ua::companion::kIaUri)},
        {"rob", std::string(ua::companion::kRoboticsUri)},
        {"skill", std::string(ua::companion::kSkillsUri)},
        {"rskill", std::string(ua::companion::kRoboticSkillsUri)},
        {"gskill", std::string(ua::companion::kGripperSkillsUri)},
        {"tskill", std::string(ua::companion::kToolChangerSkillsUri)},
        {"cskill", std::string(ua::companion::kCompositeSkillsUri)},
        {"mskill", std::string(ua::companion::kMesSkillsUri)},
    };
    return p;
}

std::string toTurtle(const Ontology& ontology) {
    return rdf::writeTurtle(ontology.triples, standardPrefixes());
}

std::string_view coreOntologyTurtle() {
    return embeddedOntology("opcua-core.ttl");
}

}  // namespace skillcell::kb::owl
