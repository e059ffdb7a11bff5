#include "skills/conformance_checker.hpp"

#include <algorithm>
#include <cmath>
#include <deque>
#include <map>
#include <optional>
#include <set>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "skills/conformance_exercise.hpp"
#include "skills/instance_declarations.hpp"
#include "skills/skill_state_machine.hpp"
#include "ua/address_space/node.hpp"
#include "ua/encoding/codec.hpp"
#include "ua/nodeset/companion_models.hpp"
#include "ua/types/to_string.hpp"

namespace skillcell::skills {
namespace {

namespace ns0 = ua::ns0;
using Path = std::vector<ua::QualifiedName>;

constexpr std::string_view kServer = "server";
/// EventNotifier bit SubscribeToEvents (OPC 10000-3, 8.59).
constexpr std::uint8_t kSubscribeToEvents = 0x01;

/// Range (i=884) as it travels: Range_Encoding_DefaultBinary is i=886.
struct RangeValue {
    static constexpr std::uint32_t kBinaryEncodingId = 886;
    double low = 0;
    double high = 0;
    static auto tie(auto& s) { return std::tie(s.low, s.high); }
};

// What a report names: the standard's name, or the number a component sent.
std::string nodeClassText(ua::NodeClass c) {
    const auto name = ua::nodeClassName(c);
    return name.empty() ? "NodeClass " + std::to_string(static_cast<std::int32_t>(c))
                        : std::string(name);
}

std::string builtinText(ua::BuiltinType t) {
    const auto name = ua::builtinTypeName(t);
    return name.empty() ? "type " + std::to_string(static_cast<int>(t)) : std::string(name);
}

std::string valueRankText(std::int32_t rank) {
    switch (rank) {
        case ua::value_rank::kScalarOrOneDimension:
            return "-3 (scalar or one dimension)";
        case ua::value_rank::kAny:
            return "-2 (any)";
        case ua::value_rank::kScalar:
            return "-1 (scalar)";
        case ua::value_rank::kOneOrMoreDimensions:
            return "0 (one or more dimensions)";
        case ua::value_rank::kOneDimension:
            return "1 (one dimension)";
        default:
            return std::to_string(rank) + " dimensions";
    }
}

/// An instance may narrow its declaration's ValueRank (Any to Scalar, ...), never widen it.
bool valueRankCompatible(std::int32_t declared, std::int32_t actual) {
    if (declared == actual) return true;
    switch (declared) {
        case ua::value_rank::kAny:
            return true;
        case ua::value_rank::kScalarOrOneDimension:
            return actual == ua::value_rank::kScalar || actual == ua::value_rank::kOneDimension;
        case ua::value_rank::kOneOrMoreDimensions:
            return actual >= ua::value_rank::kOneDimension;
        default:
            return false;
    }
}

/// What a value's shape is when it does not fit `rank`; nullopt when it does.
std::optional<std::string> rankProblem(const ua::Variant& v, std::int32_t rank) {
    const std::size_t dims =
        v.isArray() ? std::max<std::size_t>(v.dimensions().size(), 1) : std::size_t{0};
    bool ok = false;
    switch (rank) {
        case ua::value_rank::kAny:
            ok = true;
            break;
        case ua::value_rank::kScalar:
            ok = dims == 0;
            break;
        case ua::value_rank::kScalarOrOneDimension:
            ok = dims <= 1;
            break;
        case ua::value_rank::kOneOrMoreDimensions:
            ok = dims >= 1;
            break;
        default:
            ok = rank > 0 && dims == static_cast<std::size_t>(rank);
    }
    if (ok) return std::nullopt;
    if (dims == 0) return "a scalar " + builtinText(v.type());
    return "a " + builtinText(v.type()) + " array of " + std::to_string(dims) + " dimension" +
           (dims == 1 ? "" : "s");
}

std::string shorten(std::string s, std::size_t max = 60) {
    if (s.size() > max) {
        s.resize(max);
        s += "...";
    }
    return s;
}

std::optional<double> asDouble(const ua::Scalar& s) {
    return std::visit(
        [](const auto& x) -> std::optional<double> {
            using T = std::decay_t<decltype(x)>;
            if constexpr (std::is_arithmetic_v<T> && !std::is_same_v<T, bool>) {
                return static_cast<double>(x);
            } else {
                return std::nullopt;
            }
        },
        s);
}

Path parentOf(const Path& p) {
    return Path(p.begin(), p.end() - 1);
}

/// A browse path as a map key ("0:CurrentState\n0:Id\n"). Keys are strings rather than
/// Paths so that no QualifiedName ordering is needed.
std::string keyOf(const Path& p) {
    std::string key;
    for (const auto& q : p) {
        key += std::to_string(q.namespaceIndex);
        key += ':';
        key += q.name;
        key += '\n';
    }
    return key;
}

struct FoundSkill {
    ua::NodeId nodeId;
    ua::NodeId type;
    std::string path;
};

/// A declaration that the instance has, with the node that stands for it.
struct Present {
    std::size_t declaration = 0;
    ua::ReferenceDescription ref;
    // Attributes read for it (Variables: DataType, ValueRank, Value; Methods: Executable,
    // UserExecutable).
    std::vector<ua::DataValue> attributes;
};

class Checker {
public:
    Checker(ua::Client& client, CheckOptions options, ConformanceReport& report)
        : remote_(client, options.limits), options_(std::move(options)), report_(report) {}

    asio::awaitable<void> run() {
        if (!co_await checkModel()) co_return;
        co_await findSkills();
        std::vector<SkillUnderTest> tested;
        for (const auto& skill : skills_) {
            if (stopped("checked")) co_return;
            if (!remote_.client().isConnected()) {
                report_.fail(std::string(kServer), "connection", "the connection to stay open",
                             "it was lost");
                co_return;
            }
            if (auto t = co_await checkSkill(skill)) tested.push_back(std::move(*t));
        }
        if (!options_.exercise) co_return;
        ExerciseOptions exercise;
        exercise.skillTransitionEventType = skillEventType_;
        exercise.eventTimeout = options_.eventTimeout;
        exercise.runTimeout = options_.runTimeout;
        exercise.stopRequested = options_.stopRequested;
        for (const auto& t : tested) {
            if (stopped("exercised") || !remote_.client().isConnected()) break;
            co_await exerciseSkill(remote_, t, exercise, report_);
        }
    }

private:
    /// A stop was asked for: says what is left undone.
    bool stopped(const char* undone) {
        if (!options_.stopRequested || !options_.stopRequested()) return false;
        report_.fail(std::string(kServer), "check", "to run to its end",
                     std::string("interrupted: the skills that remain were not ") + undone);
        return true;
    }

    // --- The server's model -----------------------------------------------------------

    /// Namespaces, SkillType and its event type, the skill types. False when no skill can
    /// be recognised on this server.
    asio::awaitable<bool> checkModel() {
        const std::string server(kServer);
        const std::string skillsUri(ua::companion::kSkillsUri);
        auto skillsNs = co_await remote_.namespaceIndex(skillsUri);
        if (!skillsNs) {
            report_.fail(server, "NamespaceArray", "a readable NamespaceArray (i=2255)",
                         statusText(skillsNs.status()));
            co_return false;
        }
        if (!*skillsNs) {
            report_.fail(server, "Skills namespace", skillsUri + " in the NamespaceArray",
                         "not there: the server has no skill model");
            co_return false;
        }
        skillsNs_ = **skillsNs;
        report_.pass(server, "Skills namespace",
                     skillsUri + " is namespace " + std::to_string(skillsNs_));
        const std::string diUri(ua::companion::kDiUri);
        auto diNs = co_await remote_.namespaceIndex(diUri);
        if (diNs && *diNs) {
            report_.pass(server, "DI namespace", diUri + " is namespace " + std::to_string(**diNs));
        } else {
            report_.fail(server, "DI namespace",
                         diUri + " in the NamespaceArray (the Skills model requires it)",
                         diNs ? "not there" : statusText(diNs.status()));
        }

        skillType_ = ua::NodeId(skillsNs_, ua::companion::kSkillType);
        skillEventType_ = ua::NodeId(skillsNs_, ua::companion::kSkillTransitionEventType);
        if (!co_await checkObjectType(skillType_, "SkillType", ns0::ProgramStateMachineType,
                                      /*mustBeAbstract=*/true)) {
            co_return false;
        }
        (void)co_await checkObjectType(skillEventType_, "SkillTransitionEventType",
                                       ns0::ProgramTransitionEventType, /*mustBeAbstract=*/false);

        auto types = co_await remote_.subtypesOf(skillType_);
        if (!types) {
            report_.fail(server, "skill types", "the subtypes of SkillType browsable (HasSubtype)",
                         statusText(types.status()));
            co_return false;
        }
        std::vector<ua::ReadValueId> ids;
        for (const auto& t : *types) {
            ua::ReadValueId id;
            id.nodeId = t;
            id.attributeId = static_cast<std::uint32_t>(ua::AttributeId::IsAbstract);
            ids.push_back(std::move(id));
        }
        auto abstract = co_await remote_.read(std::move(ids));
        if (!abstract) {
            report_.fail(server, "skill types", "IsAbstract of every skill type readable",
                         statusText(abstract.status()));
            co_return false;
        }
        std::size_t concrete = 0;
        for (std::size_t i = 0; i < types->size(); ++i) {
            const auto& dv = (*abstract)[i];
            const bool* flag = dv.value ? dv.value->get<bool>() : nullptr;
            skillTypes_[(*types)[i]] = flag == nullptr || *flag;
            if (flag != nullptr && !*flag) ++concrete;
        }
        report_.pass(server, "skill types",
                     std::to_string(types->size()) + " (SkillType and its subtypes), " +
                         std::to_string(concrete) + " concrete");
        co_return true;
    }

    /// `type` is an ObjectType below `superType`; abstract if asked.
    asio::awaitable<bool> checkObjectType(ua::NodeId type, const std::string& label,
                                          std::uint32_t superType, bool mustBeAbstract) {
        const std::string server(kServer);
        const std::string super = co_await remote_.describe(ua::NodeId(superType));
        const std::string expected = "an ObjectType " + type.toString() + ", subtype of " + super;
        const ua::DataValue nodeClass =
            co_await remote_.readAttribute(type, ua::AttributeId::NodeClass);
        const auto* nc = nodeClass.value ? nodeClass.value->get<std::int32_t>() : nullptr;
        if (nodeClass.statusOrGood().isBad() || nc == nullptr) {
            report_.fail(server, label, expected,
                         nodeClass.statusOrGood().isBad() ? statusText(nodeClass.statusOrGood())
                                                          : "no NodeClass");
            co_return false;
        }
        if (*nc != static_cast<std::int32_t>(ua::NodeClass::ObjectType)) {
            report_.fail(server, label, expected,
                         "a " + nodeClassText(static_cast<ua::NodeClass>(*nc)));
            co_return false;
        }
        auto sub = co_await remote_.isSubtypeOf(type, ua::NodeId(superType));
        if (!sub || !*sub) {
            auto chain = co_await chainText(type);
            report_.fail(server, label, expected, sub ? chain : statusText(sub.status()));
            co_return false;
        }
        const ua::DataValue isAbstract =
            co_await remote_.readAttribute(type, ua::AttributeId::IsAbstract);
        const bool* flag = isAbstract.value ? isAbstract.value->get<bool>() : nullptr;
        if (mustBeAbstract && (flag == nullptr || !*flag)) {
            report_.fail(
                server, label, "an abstract ObjectType (IsAbstract true)",
                flag == nullptr ? statusText(isAbstract.statusOrGood()) : "IsAbstract false");
            co_return false;
        }
        report_.pass(server, label,
                     type.toString() + (flag != nullptr && *flag ? ", abstract" : "") +
                         ", subtype of " + super);
        co_return true;
    }

    /// "CartesianLinearMoveSkillType -> ... -> ProgramStateMachineType" (stops there).
    asio::awaitable<std::string> chainText(ua::NodeId type) {
        auto chain = co_await remote_.typeChain(type);
        if (!chain) co_return co_await remote_.describe(type);
        std::string s;
        for (const auto& t : *chain) {
            if (!s.empty()) s += " -> ";
            s += co_await remote_.browseName(t);
            if (t == ua::NodeId(ns0::ProgramStateMachineType)) break;
        }
        co_return s;
    }

    // --- Finding skills ---------------------------------------------------------------

    asio::awaitable<void> findSkills() {
        const std::string server(kServer);
        struct Pending {
            ua::NodeId node;
            std::string path;
            std::size_t depth = 0;
        };
        const std::string startName = co_await remote_.browseName(options_.start);
        std::deque<Pending> queue{{options_.start, startName, 0}};
        std::set<ua::NodeId> seen{options_.start};
        bool truncated = false;
        while (!queue.empty() && !truncated) {
            Pending at = std::move(queue.front());
            queue.pop_front();
            auto refs = co_await remote_.browse(at.node, ua::BrowseDirection::Forward,
                                                ua::NodeId(ns0::HierarchicalReferences),
                                                static_cast<std::uint32_t>(ua::NodeClass::Object));
            if (!refs) {
                report_.warn(
                    server, "search for skills", "every object browsable",
                    at.path + " (" + at.node.toString() + "): " + statusText(refs.status()));
                if (!remote_.client().isConnected()) break;
                continue;
            }
            for (const auto& ref : *refs) {
                if (!ref.nodeId.isLocal() || !seen.insert(ref.nodeId.nodeId).second) continue;
                if (seen.size() > options_.maxObjects) {
                    truncated = true;
                    break;
                }
                std::string path = at.path + "/" + ref.browseName.name;
                if (ref.typeDefinition.isLocal() &&
                    skillTypes_.contains(ref.typeDefinition.nodeId)) {
                    skills_.push_back({ref.nodeId.nodeId, ref.typeDefinition.nodeId, path});
                }
                if (at.depth + 1 < options_.maxDepth) {
                    queue.push_back({ref.nodeId.nodeId, std::move(path), at.depth + 1});
                }
            }
        }
        if (truncated) {
            report_.warn(server, "search for skills",
                         "every object below " + startName + " visited",
                         "stopped after " + std::to_string(options_.maxObjects) +
                             " objects (--max-objects)");
        }
        if (skills_.empty()) {
            report_.fail(
                server, "skills",
                "at least one object below " + startName + " whose type is a subtype of SkillType",
                "none among " + std::to_string(seen.size() - 1) + " objects");
            co_return;
        }
        std::string list;
        for (const auto& s : skills_) list += (list.empty() ? "" : ", ") + s.path;
        report_.pass(server, "skills", std::to_string(skills_.size()) + " found: " + list);
    }

    // --- One skill ----------------------------------------------------------------------

    asio::awaitable<std::optional<SkillUnderTest>> checkSkill(const FoundSkill& skill) {
        const std::string& subject = skill.path;
        const std::string typeText = co_await remote_.describe(skill.type);
        report_.addSkill({skill.path, skill.nodeId.toString(), typeText});

        // The type: concrete, and a program state machine.
        const std::string chain = co_await chainText(skill.type);
        auto isPsm =
            co_await remote_.isSubtypeOf(skill.type, ua::NodeId(ns0::ProgramStateMachineType));
        if (skillTypes_[skill.type]) {
            report_.fail(subject, "type", "a concrete (not abstract) subtype of SkillType",
                         typeText + ", abstract");
        } else if (!isPsm || !*isPsm) {
            report_.fail(subject, "type", "a subtype of ProgramStateMachineType (i=2391)", chain);
        } else {
            report_.pass(subject, "type", typeText + ", concrete: " + chain);
        }

        auto cached = declarations_.find(skill.type);
        if (cached == declarations_.end()) {
            auto decls =
                co_await instanceDeclarations(remote_, skill.type, options_.maxDeclarationDepth);
            if (!decls) {
                report_.fail(subject, "instance declarations",
                             "the declarations of " + typeText + " browsable",
                             statusText(decls.status()));
                co_return std::nullopt;
            }
            cached = declarations_.emplace(skill.type, std::move(*decls)).first;
        }
        std::vector<InstanceDeclaration> decls = cached->second;
        std::vector<bool> required(decls.size());
        for (std::size_t i = 0; i < decls.size(); ++i) required[i] = decls[i].isMandatory();
        // The skill model requires every method of the state machine, whatever rule the
        // server's namespace 0 gives them (OptionalPlaceholder in 1.05).
        for (const auto method : kAllMethods) {
            const ua::QualifiedName qn{0, std::string(name(method))};
            auto it = std::find_if(decls.begin(), decls.end(), [&qn](const auto& d) {
                return d.path.size() == 1 && d.path[0] == qn;
            });
            if (it == decls.end()) {
                InstanceDeclaration d;
                d.path = {qn};
                d.nodeClass = ua::NodeClass::Method;
                decls.push_back(std::move(d));
                required.push_back(true);
            } else {
                required[static_cast<std::size_t>(it - decls.begin())] = true;
            }
        }

        // Find the instance's node for each declaration, parents first.
        std::map<std::string, ua::ReferenceDescription> nodes;  // by keyOf(path)
        std::vector<Present> present;
        for (std::size_t i = 0; i < decls.size(); ++i) {
            const auto& d = decls[i];
            ua::NodeId parent = skill.nodeId;
            if (d.path.size() > 1) {
                auto it = nodes.find(keyOf(parentOf(d.path)));
                if (it == nodes.end()) continue;  // the parent is missing: reported already
                parent = it->second.nodeId.nodeId;
            }
            auto child = co_await remote_.child(parent, d.path.back());
            if (!child) {
                report_.fail(subject, d.pathText(), "its parent browsable",
                             statusText(child.status()));
                continue;
            }
            if (!*child) {
                if (required[i]) {
                    report_.fail(subject, d.pathText(), co_await declarationText(d, required[i]),
                                 "nothing");
                } else if (d.path.back() == ua::QualifiedName{0, "EURange"} && !d.isPlaceholder()) {
                    report_.warn(subject, d.pathText(),
                                 "an EURange (declared " + modellingRuleName(d.modellingRule) +
                                     " by the type) so that clients can check the value",
                                 "none");
                }
                continue;
            }
            nodes.emplace(keyOf(d.path), **child);
            present.push_back({i, **child, {}});
        }

        // Read what the comparison needs, for every node at once.
        std::vector<ua::ReadValueId> ids;
        auto ask = [&ids](const ua::NodeId& node, ua::AttributeId attribute) {
            ua::ReadValueId id;
            id.nodeId = node;
            id.attributeId = static_cast<std::uint32_t>(attribute);
            ids.push_back(std::move(id));
        };
        for (const auto& p : present) {
            const auto& node = p.ref.nodeId.nodeId;
            if (p.ref.nodeClass == ua::NodeClass::Variable) {
                ask(node, ua::AttributeId::DataType);
                ask(node, ua::AttributeId::ValueRank);
                ask(node, ua::AttributeId::Value);
            } else if (p.ref.nodeClass == ua::NodeClass::Method) {
                ask(node, ua::AttributeId::Executable);
                ask(node, ua::AttributeId::UserExecutable);
            }
        }
        ask(skill.nodeId, ua::AttributeId::EventNotifier);
        auto values = co_await remote_.read(std::move(ids));
        if (!values) {
            report_.fail(subject, "attributes", "the skill's attributes readable",
                         statusText(values.status()));
            co_return std::nullopt;
        }
        std::size_t next = 0;
        for (auto& p : present) {
            const std::size_t n = p.ref.nodeClass == ua::NodeClass::Variable ? 3
                                  : p.ref.nodeClass == ua::NodeClass::Method ? 2
                                                                             : 0;
            for (std::size_t k = 0; k < n; ++k) p.attributes.push_back((*values)[next++]);
        }
        const ua::DataValue eventNotifier = (*values)[next];

        std::map<std::string, const Present*> byPath;  // by keyOf(path)
        for (const auto& p : present) {
            byPath[keyOf(decls[p.declaration].path)] = &p;
            co_await checkChild(subject, decls[p.declaration], p);
        }
        co_await checkRanges(subject, decls, byPath);
        checkStates(subject, byPath);
        checkEventNotifier(subject, eventNotifier);

        SkillUnderTest t;
        t.path = skill.path;
        t.nodeId = skill.nodeId;
        for (const auto method : kAllMethods) {
            auto it = byPath.find(keyOf(Path{ua::QualifiedName{0, std::string(name(method))}}));
            if (it != byPath.end() && it->second->ref.nodeClass == ua::NodeClass::Method) {
                t.methods.at(static_cast<std::size_t>(method)) = it->second->ref.nodeId.nodeId;
            }
        }
        auto nodeAt = [&byPath](const Path& p) -> std::optional<ua::NodeId> {
            auto it = byPath.find(keyOf(p));
            if (it == byPath.end()) return std::nullopt;
            return it->second->ref.nodeId.nodeId;
        };
        const ua::QualifiedName current{0, "CurrentState"};
        const ua::QualifiedName last{0, "LastTransition"};
        const ua::QualifiedName id{0, "Id"};
        t.currentState = nodeAt({current});
        t.currentStateId = nodeAt({current, id});
        t.currentStateNumber = nodeAt({current, ua::QualifiedName{0, "Number"}});
        t.lastTransition = nodeAt({last});
        t.lastTransitionId = nodeAt({last, id});
        const auto* bits = eventNotifier.value ? eventNotifier.value->get<std::uint8_t>() : nullptr;
        t.eventNotifier = bits != nullptr && (*bits & kSubscribeToEvents) != 0;
        co_return t;
    }

    /// "Variable (Mandatory), type BaseAnalogType, DataType Double, ValueRank -1 (scalar)".
    asio::awaitable<std::string> declarationText(const InstanceDeclaration& d, bool required) {
        std::string s = nodeClassText(d.nodeClass);
        if (d.isMandatory()) {
            s += " (Mandatory)";
        } else if (required) {
            s += " (required by the skill model; " + modellingRuleName(d.modellingRule) +
                 " in namespace 0)";
        }
        if (!d.typeDefinition.isNull())
            s += ", type " + co_await remote_.describe(d.typeDefinition);
        if (d.nodeClass == ua::NodeClass::Variable) {
            s += ", DataType " + co_await remote_.describe(d.dataType) + ", ValueRank " +
                 valueRankText(d.valueRank);
        }
        co_return s;
    }

    /// Node class, type definition, DataType, ValueRank, value, executable.
    asio::awaitable<void> checkChild(const std::string& subject, const InstanceDeclaration& d,
                                     const Present& p) {
        const std::string check = d.pathText();
        if (p.ref.nodeClass != d.nodeClass) {
            report_.fail(
                subject, check, nodeClassText(d.nodeClass),
                "a " + nodeClassText(p.ref.nodeClass) + " " + p.ref.nodeId.nodeId.toString());
            co_return;
        }
        bool ok = true;
        std::string found = nodeClassText(d.nodeClass);
        if (!d.typeDefinition.isNull()) {
            const ua::NodeId actual =
                p.ref.typeDefinition.isLocal() ? p.ref.typeDefinition.nodeId : ua::NodeId();
            auto sub = co_await remote_.isSubtypeOf(actual, d.typeDefinition);
            if (!sub || !*sub) {
                ok = false;
                report_.fail(subject, check,
                             "type definition " + co_await remote_.describe(d.typeDefinition) +
                                 " or a subtype",
                             actual.isNull() ? "none" : co_await remote_.describe(actual));
            } else {
                found += ", " + co_await remote_.browseName(actual);
            }
        }
        if (d.nodeClass == ua::NodeClass::Variable && p.attributes.size() == 3) {
            ok = co_await checkVariable(subject, check, d, p, found) && ok;
        } else if (d.nodeClass == ua::NodeClass::Method && p.attributes.size() == 2) {
            const auto* executable =
                p.attributes[0].value ? p.attributes[0].value->get<bool>() : nullptr;
            const auto* userExecutable =
                p.attributes[1].value ? p.attributes[1].value->get<bool>() : nullptr;
            if (executable == nullptr || !*executable) {
                ok = false;
                report_.fail(
                    subject, check, "Executable true (a client must be able to call it)",
                    executable == nullptr ? statusText(p.attributes[0].statusOrGood()) : "false");
            } else if (userExecutable == nullptr || !*userExecutable) {
                ok = false;
                report_.warn(subject, check, "UserExecutable true for this (anonymous) session",
                             userExecutable == nullptr ? statusText(p.attributes[1].statusOrGood())
                                                       : "false");
            } else {
                found += ", executable";
            }
        }
        if (ok) report_.pass(subject, check, found);
    }

    asio::awaitable<bool> checkVariable(const std::string& subject, const std::string& check,
                                        const InstanceDeclaration& d, const Present& p,
                                        std::string& found) {
        bool ok = true;
        const ua::DataValue& dataTypeValue = p.attributes[0];
        const ua::DataValue& rankValue = p.attributes[1];
        const ua::DataValue& value = p.attributes[2];
        const auto* dataType =
            dataTypeValue.value ? dataTypeValue.value->get<ua::NodeId>() : nullptr;
        const auto* rank = rankValue.value ? rankValue.value->get<std::int32_t>() : nullptr;
        if (dataType == nullptr) {
            ok = false;
            report_.fail(subject, check, "a readable DataType",
                         statusText(dataTypeValue.statusOrGood()));
        } else {
            auto sub = co_await remote_.isSubtypeOf(*dataType, d.dataType);
            if (!sub || !*sub) {
                ok = false;
                report_.fail(subject, check,
                             "DataType " + co_await remote_.describe(d.dataType) + " or a subtype",
                             co_await remote_.describe(*dataType));
            } else {
                found += ", " + co_await remote_.browseName(*dataType);
            }
        }
        if (rank == nullptr) {
            ok = false;
            report_.fail(subject, check, "a readable ValueRank",
                         statusText(rankValue.statusOrGood()));
        } else if (!valueRankCompatible(d.valueRank, *rank)) {
            ok = false;
            report_.fail(subject, check, "ValueRank " + valueRankText(d.valueRank),
                         valueRankText(*rank));
        } else if (*rank != ua::value_rank::kScalar) {
            found += ", ValueRank " + std::to_string(*rank);
        }
        const ua::StatusCode status = value.statusOrGood();
        if (status.isBad()) {
            ok = false;
            report_.fail(subject, check, "a readable value", statusText(status));
        } else if (status.isUncertain()) {
            ok = false;
            report_.warn(subject, check, "a value with status Good", statusText(status));
        } else if (!value.value || value.value->isEmpty()) {
            found += ", value null";
        } else {
            const ua::NodeId declared = d.dataType;
            auto problem = co_await valueProblem(*value.value, declared, d.valueRank);
            if (problem) {
                ok = false;
                report_.fail(subject, check,
                             "a value of DataType " + co_await remote_.browseName(declared) +
                                 ", ValueRank " + valueRankText(d.valueRank),
                             *problem);
            } else {
                found += " = " + shorten(ua::toString(*value.value));
            }
        }
        co_return ok;
    }

    /// Why `v` does not fit `dataType` and `rank`; nullopt when it does (or when the
    /// server's model cannot tell).
    asio::awaitable<std::optional<std::string>> valueProblem(const ua::Variant& v,
                                                             ua::NodeId dataType,
                                                             std::int32_t rank) {
        if (auto shape = rankProblem(v, rank)) co_return shape;
        if (dataType == ua::NodeId(ns0::BaseDataType)) co_return std::nullopt;
        const ua::BuiltinType builtin = v.type();
        const auto builtinId = ua::NodeId(static_cast<std::uint32_t>(builtin));
        if (auto sub = co_await remote_.isSubtypeOf(builtinId, dataType); sub && *sub) {
            co_return std::nullopt;  // Double for Number, Int32 for Int32, ...
        }
        const auto encoded = co_await builtinOf(dataType);
        if (encoded && *encoded == builtin && builtin != ua::BuiltinType::Variant) {
            if (builtin != ua::BuiltinType::ExtensionObject) co_return std::nullopt;
            // A structure: the encoding says which DataType each element holds.
            std::vector<ua::Scalar> elements =
                v.isArray() ? v.elements() : std::vector<ua::Scalar>{v.scalar()};
            for (const auto& e : elements) {
                const auto* eo = std::get_if<ua::ExtensionObject>(&e);
                if (eo == nullptr || eo->empty()) continue;
                auto held = co_await remote_.browse(eo->typeId, ua::BrowseDirection::Inverse,
                                                    ua::NodeId(ns0::HasEncoding));
                if (!held || held->empty() || !held->front().nodeId.isLocal()) continue;
                const ua::NodeId heldType = held->front().nodeId.nodeId;
                auto sub = co_await remote_.isSubtypeOf(heldType, dataType);
                if (sub && !*sub) {
                    co_return "a " + co_await remote_.browseName(heldType) + " structure";
                }
            }
            co_return std::nullopt;
        }
        std::string what =
            v.isArray() ? "a " + builtinText(builtin) + " array" : "a " + builtinText(builtin);
        co_return what;
    }

    /// The built-in type that encodes values of `dataType`: the first namespace-0 built-in
    /// type (1..25) on its supertype chain; an enumeration is an Int32.
    asio::awaitable<std::optional<ua::BuiltinType>> builtinOf(ua::NodeId dataType) {
        auto chain = co_await remote_.typeChain(std::move(dataType));
        if (!chain) co_return std::nullopt;
        for (const auto& t : *chain) {
            if (t.namespaceIndex() != 0 || !t.isNumeric()) continue;
            if (t.numeric() == ns0::Enumeration) co_return ua::BuiltinType::Int32;
            if (t.numeric() >= 1 && t.numeric() <= ua::kMaxBuiltinType) {
                co_return static_cast<ua::BuiltinType>(t.numeric());
            }
        }
        co_return std::nullopt;
    }

    /// A declared EURange: Low <= High and the parameter's value inside.
    asio::awaitable<void> checkRanges(const std::string& subject,
                                      const std::vector<InstanceDeclaration>& decls,
                                      const std::map<std::string, const Present*>& byPath) {
        const ua::QualifiedName euRange{0, "EURange"};
        for (const auto& d : decls) {
            if (d.path.size() < 2 || d.path.back() != euRange) continue;
            auto range = byPath.find(keyOf(d.path));
            auto owner = byPath.find(keyOf(parentOf(d.path)));
            if (range == byPath.end() || owner == byPath.end()) continue;
            const Present& r = *range->second;
            const Present& o = *owner->second;
            if (r.attributes.size() != 3 || o.attributes.size() != 3) continue;
            const std::string check = pathText(parentOf(d.path)) + " in EURange";
            const auto* eo =
                r.attributes[2].value ? r.attributes[2].value->get<ua::ExtensionObject>() : nullptr;
            RangeValue rv;
            if (eo == nullptr || ua::fromExtensionObject(*eo, rv).isBad()) {
                report_.fail(subject, check, "EURange holding a Range (Low, High)",
                             r.attributes[2].value ? shorten(ua::toString(*r.attributes[2].value))
                                                   : "no value");
                continue;
            }
            const std::string rangeText = "[" + ua::toString(ua::Variant(rv.low)) + ", " +
                                          ua::toString(ua::Variant(rv.high)) + "]";
            if (!(rv.low <= rv.high)) {
                report_.fail(subject, check, "EURange with Low <= High", rangeText);
                continue;
            }
            const auto& value = o.attributes[2].value;
            if (!value || value->isEmpty()) {
                report_.pass(subject, check, "range " + rangeText + ", no value yet");
                continue;
            }
            std::vector<ua::Scalar> elements =
                value->isArray() ? value->elements() : std::vector<ua::Scalar>{value->scalar()};
            std::optional<double> outside;
            for (const auto& e : elements) {
                const auto x = asDouble(e);
                if (x && (std::isnan(*x) || *x < rv.low || *x > rv.high)) outside = *x;
            }
            if (outside) {
                report_.warn(subject, check, "a value inside " + rangeText,
                             ua::toString(ua::Variant(*outside)) + " (Start would be refused)");
            } else {
                report_.pass(subject, check, shorten(ua::toString(*value)) + " in " + rangeText);
            }
        }
        co_return;
    }

    /// CurrentState is a state of the table with its Id and Number; LastTransition ends there.
    void checkStates(const std::string& subject,
                     const std::map<std::string, const Present*>& byPath) {
        auto valueAt = [&byPath](const Path& p) -> const ua::Variant* {
            auto it = byPath.find(keyOf(p));
            if (it == byPath.end() || it->second->attributes.size() != 3) return nullptr;
            const auto& dv = it->second->attributes[2];
            if (dv.statusOrGood().isBad() || !dv.value) return nullptr;
            return &*dv.value;
        };
        const ua::QualifiedName current{0, "CurrentState"};
        const ua::QualifiedName last{0, "LastTransition"};
        const ua::QualifiedName id{0, "Id"};
        const ua::QualifiedName number{0, "Number"};

        std::string states;
        for (const auto s : kAllStates)
            states += (states.empty() ? "" : ", ") + std::string(name(s));
        std::optional<SkillState> state;
        if (const ua::Variant* text = valueAt({current})) {
            const auto* lt = text->get<ua::LocalizedText>();
            state = lt != nullptr ? stateFromName(lt->text) : std::nullopt;
            if (!state) {
                report_.fail(subject, "CurrentState value", "one of " + states,
                             lt != nullptr ? "'" + lt->text + "'" : shorten(ua::toString(*text)));
            }
        }
        if (state) {
            bool ok = true;
            const ua::Variant* idValue = valueAt({current, id});
            const auto* idNode = idValue != nullptr ? idValue->get<ua::NodeId>() : nullptr;
            if (idNode == nullptr || stateFromNodeId(*idNode) != state) {
                ok = false;
                report_.fail(subject, "CurrentState/Id value",
                             stateNodeId(*state).toString() + " (" + std::string(name(*state)) +
                                 " of ProgramStateMachineType)",
                             idNode != nullptr ? idNode->toString() : "no NodeId");
            }
            const ua::Variant* numberValue = valueAt({current, number});
            const auto* n = numberValue != nullptr ? numberValue->get<std::uint32_t>() : nullptr;
            const auto expectedNumber = static_cast<std::uint32_t>(*state);
            if (n == nullptr || *n != expectedNumber) {
                ok = false;
                report_.fail(subject, "CurrentState/Number value", std::to_string(expectedNumber),
                             n != nullptr ? std::to_string(*n) : "no UInt32");
            }
            if (ok) {
                report_.pass(subject, "CurrentState value",
                             std::string(name(*state)) + " (Id " + stateNodeId(*state).toString() +
                                 ", Number " + std::to_string(expectedNumber) + ")");
            }
        }

        const ua::Variant* lastId = valueAt({last, id});
        const auto* lastNode = lastId != nullptr ? lastId->get<ua::NodeId>() : nullptr;
        if (byPath.find(keyOf(Path{last})) == byPath.end()) return;  // missing: reported already
        if (lastNode == nullptr || lastNode->isNull()) {
            report_.pass(subject, "LastTransition value", "none yet");
            return;
        }
        const auto transition = transitionFromNodeId(*lastNode);
        if (!transition) {
            report_.fail(subject, "LastTransition/Id value",
                         "a transition of ProgramStateMachineType (i=2408 .. i=2424)",
                         lastNode->toString());
            return;
        }
        bool ok = true;
        const std::string transitionName(name(*transition));
        if (const ua::Variant* text = valueAt({last})) {
            const auto* lt = text->get<ua::LocalizedText>();
            if (lt == nullptr || lt->text != transitionName) {
                ok = false;
                report_.fail(subject, "LastTransition value",
                             "'" + transitionName + "' (its Id's name)",
                             lt != nullptr ? "'" + lt->text + "'" : shorten(ua::toString(*text)));
            }
        }
        const ua::Variant* numberValue = valueAt({last, number});
        const auto* n = numberValue != nullptr ? numberValue->get<std::uint32_t>() : nullptr;
        if (n == nullptr || *n != static_cast<std::uint32_t>(*transition)) {
            ok = false;
            report_.fail(subject, "LastTransition/Number value",
                         std::to_string(static_cast<std::uint32_t>(*transition)),
                         n != nullptr ? std::to_string(*n) : "no UInt32");
        }
        if (state && toState(*transition) != *state) {
            ok = false;
            report_.fail(subject, "LastTransition value",
                         "a transition into " + std::string(name(*state)) + " (CurrentState)",
                         transitionName);
        }
        if (ok) {
            report_.pass(subject, "LastTransition value",
                         transitionName + " (Id " + lastNode->toString() + ", Number " +
                             std::to_string(static_cast<std::uint32_t>(*transition)) + ")");
        }
    }

    void checkEventNotifier(const std::string& subject, const ua::DataValue& eventNotifier) {
        const auto* bits = eventNotifier.value ? eventNotifier.value->get<std::uint8_t>() : nullptr;
        if (bits != nullptr && (*bits & kSubscribeToEvents) != 0) {
            report_.pass(subject, "events",
                         "EventNotifier has SubscribeToEvents: clients subscribe on the skill");
            return;
        }
        report_.warn(subject, "events",
                     "EventNotifier with SubscribeToEvents (bit 0), so that clients can subscribe "
                     "to the skill's transitions",
                     bits != nullptr ? "EventNotifier " + std::to_string(*bits) +
                                           ": events only through the Server object "
                                           "(--exercise checks that they arrive)"
                                     : statusText(eventNotifier.statusOrGood()));
    }

    RemoteAddressSpace remote_;
    CheckOptions options_;
    ConformanceReport& report_;
    std::uint16_t skillsNs_ = 0;
    ua::NodeId skillType_;
    ua::NodeId skillEventType_;
    std::map<ua::NodeId, bool> skillTypes_;  // SkillType and subtypes -> IsAbstract
    std::vector<FoundSkill> skills_;
    std::map<ua::NodeId, std::vector<InstanceDeclaration>> declarations_;  // by type
};

}  // namespace

asio::awaitable<void> checkConformance(ua::Client& client, CheckOptions options,
                                       ConformanceReport& report) {
    Checker checker(client, std::move(options), report);
    co_await checker.run();
}

}  // namespace skillcell::skills
