#include "ua/server/subscriptions/event.hpp"

#include <cmath>

#include "ua/encoding/codec.hpp"

namespace skillcell::ua {
namespace {

const NodeId kBaseEventType(event_ids::BaseEventType);

bool isType(const AddressSpace& as, const NodeId& type, const NodeId& superType) {
    return type == superType || as.isSubtypeOf(type, superType);
}

/// The BaseEventType field names: valid select paths even before the model has the type.
bool isBaseEventField(const std::vector<QualifiedName>& path) {
    if (path.size() != 1 || path[0].namespaceIndex != 0) return false;
    const auto& n = path[0].name;
    return n == "EventId" || n == "EventType" || n == "SourceNode" || n == "SourceName" ||
           n == "Time" || n == "ReceiveTime" || n == "Message" || n == "Severity" ||
           n == "LocalTime";
}

/// Follows `path` from `type`, looking in the supertypes for inherited fields.
bool resolvesInType(const AddressSpace& as, const NodeId& type,
                    const std::vector<QualifiedName>& path) {
    NodeId current = type;
    for (int depth = 0; depth < 32 && !current.isNull(); ++depth) {
        const Node* node = as.find(current);
        if (node == nullptr) return false;
        NodeId at = current;
        bool found = true;
        for (const auto& name : path) {
            const Node* child = as.findChild(at, name);
            if (child == nullptr) {
                found = false;
                break;
            }
            at = child->nodeId;
        }
        if (found) return true;
        current = node->superType;
    }
    return false;
}

StatusCode checkOperand(const AddressSpace& as, const SimpleAttributeOperand& op) {
    if (op.typeDefinitionId.isNull()) return status::BadTypeDefinitionInvalid;
    const Node* type = as.find(op.typeDefinitionId);
    // Without the type in the model (BaseEventType not loaded) only BaseEventType's own
    // fields can be named; with it, the path must exist in the type hierarchy.
    if (type == nullptr) {
        if (op.typeDefinitionId != kBaseEventType) return status::BadTypeDefinitionInvalid;
    } else if (type->nodeClass != NodeClass::ObjectType ||
               (as.find(kBaseEventType) != nullptr &&
                !isType(as, op.typeDefinitionId, kBaseEventType))) {
        return status::BadTypeDefinitionInvalid;
    }
    const auto attribute = static_cast<AttributeId>(op.attributeId);
    if (attribute == AttributeId::NodeId && op.browsePath.empty())
        return status::Good;  // ConditionId
    if (attribute != AttributeId::Value) return status::BadAttributeIdInvalid;
    if (!op.indexRange.empty()) return status::BadIndexRangeInvalid;  // not supported on events
    if (op.browsePath.empty()) return status::BadBrowseNameInvalid;
    if (type == nullptr)
        return isBaseEventField(op.browsePath) ? status::Good : status::BadNodeIdUnknown;
    if (resolvesInType(as, op.typeDefinitionId, op.browsePath)) return status::Good;
    // Fields of BaseEventType are always filled in, whatever the model holds yet.
    if (isBaseEventField(op.browsePath)) return status::Good;
    // With BaseEventType the path is evaluated without regard to the type (OPC 10000-4,
    // 7.22.4): clients (node-opcua's constructEventFilter) name subtype fields such as
    // FromState/Id so. A path that no event type in the model has is still an error.
    if (op.typeDefinitionId == kBaseEventType) {
        bool known = false;
        as.forEachNode([&](const Node& n) {
            if (!known && n.nodeClass == NodeClass::ObjectType &&
                isType(as, n.nodeId, kBaseEventType) &&
                resolvesInType(as, n.nodeId, op.browsePath)) {
                known = true;
            }
        });
        if (known) return status::Good;
    }
    return status::BadNodeIdUnknown;
}

std::size_t operandCount(FilterOperator op) {
    switch (op) {
        case FilterOperator::IsNull:
        case FilterOperator::Not:
        case FilterOperator::OfType:
            return 1;
        default:
            return 2;
    }
}

bool isSupported(FilterOperator op) {
    switch (op) {
        case FilterOperator::Equals:
        case FilterOperator::IsNull:
        case FilterOperator::GreaterThan:
        case FilterOperator::LessThan:
        case FilterOperator::GreaterThanOrEqual:
        case FilterOperator::LessThanOrEqual:
        case FilterOperator::Not:
        case FilterOperator::And:
        case FilterOperator::Or:
        case FilterOperator::OfType:
            return true;
        default:
            return false;
    }
}

Result<CompiledEventFilter::Operand> decodeOperand(const AddressSpace& as,
                                                   const ExtensionObject& eo, std::size_t element,
                                                   std::size_t elementCount) {
    ElementOperand e;
    if (fromExtensionObject(eo, e).isGood()) {
        // Only later elements may be referenced, which rules out cycles.
        if (e.index <= element || e.index >= elementCount) return status::BadFilterOperandInvalid;
        return CompiledEventFilter::Operand{e};
    }
    LiteralOperand l;
    if (fromExtensionObject(eo, l).isGood()) return CompiledEventFilter::Operand{std::move(l)};
    SimpleAttributeOperand s;
    if (fromExtensionObject(eo, s).isGood()) {
        if (checkOperand(as, s).isBad()) return status::BadFilterOperandInvalid;
        return CompiledEventFilter::Operand{std::move(s)};
    }
    return status::BadFilterOperandInvalid;  // AttributeOperand (not for events) or garbage
}

std::optional<double> asNumber(const Variant& v) {
    if (!v.isScalar()) return std::nullopt;
    return std::visit(
        [](const auto& x) -> std::optional<double> {
            using T = std::decay_t<decltype(x)>;
            if constexpr (std::is_arithmetic_v<T> && !std::is_same_v<T, bool>) {
                return static_cast<double>(x);
            } else if constexpr (std::is_same_v<T, DateTime>) {
                return static_cast<double>(x.ticks);
            } else {
                return std::nullopt;
            }
        },
        v.scalar());
}

/// -1, 0, 1, or nullopt for values that do not compare (different kinds, or empty).
std::optional<int> compare(const Variant& a, const Variant& b) {
    if (a.isEmpty() || b.isEmpty()) return std::nullopt;
    const auto x = asNumber(a);
    const auto y = asNumber(b);
    if (x && y) return *x < *y ? -1 : (*x > *y ? 1 : 0);
    if (const auto* s = a.get<String>()) {
        if (const auto* t = b.get<String>()) return s->compare(*t) < 0 ? -1 : (*s == *t ? 0 : 1);
    }
    if (a == b) return 0;
    return std::nullopt;
}

struct Evaluator {
    const AddressSpace& as;
    const CompiledEventFilter& filter;
    const EventRecord& record;

    Variant operand(const CompiledEventFilter::Operand& op, int depth) const {
        if (const auto* e = std::get_if<ElementOperand>(&op)) return element(e->index, depth + 1);
        if (const auto* l = std::get_if<LiteralOperand>(&op)) return l->value;
        const auto& s = std::get<SimpleAttributeOperand>(op);
        if (!isType(as, record.event.eventType, s.typeDefinitionId)) return {};
        return eventField(record, s.browsePath);
    }

    static std::optional<bool> truth(const Variant& v) {
        if (const auto* b = v.get<bool>()) return *b;
        return std::nullopt;
    }

    Variant element(std::size_t index, int depth) const {
        if (index >= filter.where.size() || depth > 64) return {};
        const auto& el = filter.where[index];
        const auto& ops = el.operands;
        auto cmp = [&](auto pred) -> Variant {
            const auto c = compare(operand(ops[0], depth), operand(ops[1], depth));
            return c ? Variant(static_cast<bool>(pred(*c))) : Variant(false);
        };
        switch (el.op) {
            case FilterOperator::Equals:
                return cmp([](int c) { return c == 0; });
            case FilterOperator::GreaterThan:
                return cmp([](int c) { return c > 0; });
            case FilterOperator::LessThan:
                return cmp([](int c) { return c < 0; });
            case FilterOperator::GreaterThanOrEqual:
                return cmp([](int c) { return c >= 0; });
            case FilterOperator::LessThanOrEqual:
                return cmp([](int c) { return c <= 0; });
            case FilterOperator::IsNull:
                return Variant(operand(ops[0], depth).isEmpty());
            case FilterOperator::Not: {
                const auto t = truth(operand(ops[0], depth));
                return t ? Variant(!*t) : Variant{};
            }
            case FilterOperator::And: {
                const auto a = truth(operand(ops[0], depth));
                if (a == false) return Variant(false);
                const auto b = truth(operand(ops[1], depth));
                if (b == false) return Variant(false);
                return a && b ? Variant(true) : Variant{};
            }
            case FilterOperator::Or: {
                const auto a = truth(operand(ops[0], depth));
                if (a == true) return Variant(true);
                const auto b = truth(operand(ops[1], depth));
                if (b == true) return Variant(true);
                return a && b ? Variant(false) : Variant{};
            }
            case FilterOperator::OfType: {
                const Variant t = operand(ops[0], depth);
                const auto* type = t.get<NodeId>();
                return Variant(type != nullptr && isType(as, record.event.eventType, *type));
            }
            default:
                return {};
        }
    }
};

}  // namespace

Variant eventField(const EventRecord& record, const std::vector<QualifiedName>& browsePath) {
    const Event& e = record.event;
    if (browsePath.size() == 1 && browsePath[0].namespaceIndex == 0) {
        const auto& n = browsePath[0].name;
        if (n == "EventId") return record.eventId;
        if (n == "EventType") return e.eventType;
        if (n == "SourceNode") return e.sourceNode;
        if (n == "SourceName") return e.sourceName;
        if (n == "Time") return record.time;
        if (n == "ReceiveTime") return record.receiveTime;
        if (n == "Message") return e.message;
        if (n == "Severity") return e.severity;
    }
    for (const auto& [path, value] : e.fields) {
        if (path == browsePath) return value;
    }
    return {};
}

Result<CompiledEventFilter> compileEventFilter(const AddressSpace& as, const EventFilter& filter,
                                               EventFilterResult& result) {
    CompiledEventFilter out;
    result = {};
    bool anySelected = false;
    for (const auto& clause : filter.selectClauses) {
        const StatusCode s = checkOperand(as, clause);
        anySelected = anySelected || s.isGood();
        result.selectClauseResults.push_back(s);
        out.select.push_back(clause);
        out.selectStatus.push_back(s);
    }
    // All Good: the standard allows leaving the per-clause results out.
    if (anySelected && std::all_of(out.selectStatus.begin(), out.selectStatus.end(),
                                   [](StatusCode s) { return s.isGood(); })) {
        result.selectClauseResults.clear();
    }

    bool whereOk = true;
    const auto& elements = filter.whereClause.elements;
    for (std::size_t i = 0; i < elements.size(); ++i) {
        const auto& el = elements[i];
        ContentFilterElementResult er;
        CompiledEventFilter::Element compiled;
        compiled.op = el.filterOperator;
        const auto op = static_cast<std::int32_t>(el.filterOperator);
        if (op < 0 || op > static_cast<std::int32_t>(FilterOperator::BitwiseOr)) {
            er.statusCode = status::BadFilterOperatorInvalid;
        } else if (!isSupported(el.filterOperator)) {
            er.statusCode = status::BadFilterOperatorUnsupported;
        } else if (el.filterOperands.size() != operandCount(el.filterOperator)) {
            er.statusCode = status::BadFilterOperandCountMismatch;
        } else {
            for (const auto& eo : el.filterOperands) {
                auto operand = decodeOperand(as, eo, i, elements.size());
                er.operandStatusCodes.push_back(operand.status());
                if (!operand) {
                    er.statusCode = status::BadFilterOperandInvalid;
                    continue;
                }
                compiled.operands.push_back(std::move(*operand));
            }
            if (el.filterOperator == FilterOperator::OfType && er.statusCode.isGood()) {
                const auto* lit = std::get_if<LiteralOperand>(&compiled.operands[0]);
                if (lit == nullptr || lit->value.get<NodeId>() == nullptr) {
                    er.statusCode = status::BadFilterOperandInvalid;
                }
            }
            if (er.statusCode.isGood()) er.operandStatusCodes.clear();
        }
        whereOk = whereOk && er.statusCode.isGood();
        result.whereClauseResult.elementResults.push_back(std::move(er));
        out.where.push_back(std::move(compiled));
    }
    if (whereOk) result.whereClauseResult.elementResults.clear();
    if (!anySelected || !whereOk) return status::BadMonitoredItemFilterInvalid;
    return out;
}

std::optional<std::vector<Variant>> evaluateEventFilter(const AddressSpace& as,
                                                        const CompiledEventFilter& filter,
                                                        const EventRecord& record) {
    if (!filter.where.empty()) {
        const Evaluator ev{as, filter, record};
        const Variant passed = ev.element(0, 0);
        if (const auto* b = passed.get<bool>(); b == nullptr || !*b) return std::nullopt;
    }
    std::vector<Variant> fields;
    fields.reserve(filter.select.size());
    for (std::size_t i = 0; i < filter.select.size(); ++i) {
        const auto& clause = filter.select[i];
        if (filter.selectStatus[i].isBad() || clause.browsePath.empty() ||
            !isType(as, record.event.eventType, clause.typeDefinitionId)) {
            fields.emplace_back();
            continue;
        }
        fields.push_back(eventField(record, clause.browsePath));
    }
    return fields;
}

}  // namespace skillcell::ua
