#include "ua/server/services/attribute_service.hpp"

#include <spdlog/spdlog.h>

#include <charconv>

#include "ua/server/services/operations.hpp"
#include "ua/server/services/register_services.hpp"

namespace skillcell::ua {
namespace {

std::optional<std::uint32_t> parseIndex(std::string_view s) {
    std::uint32_t v = 0;
    auto [p, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
    if (s.empty() || ec != std::errc{} || p != s.data() + s.size()) return std::nullopt;
    return v;
}

/// The sub-range of a one-dimensional array, or of a String/ByteString's characters.
Result<Variant> applyRange(const Variant& v, const std::vector<IndexRange>& ranges) {
    if (ranges.size() != 1) return status::BadIndexRangeNoData;
    const IndexRange r = ranges.front();
    if (v.isArray()) {
        const auto& el = v.elements();
        if (v.dimensions().size() > 1 || r.first >= el.size()) return status::BadIndexRangeNoData;
        const std::size_t last = std::min<std::size_t>(r.last, el.size() - 1);
        return Variant::array(
            v.type(), std::vector<Scalar>(el.begin() + r.first,
                                          el.begin() + static_cast<std::ptrdiff_t>(last) + 1));
    }
    if (const auto* s = v.get<String>()) {
        if (r.first >= s->size()) return status::BadIndexRangeNoData;
        return Variant(s->substr(r.first, std::size_t{r.last} - r.first + 1));
    }
    if (const auto* b = v.get<ByteString>()) {
        if (r.first >= b->size()) return status::BadIndexRangeNoData;
        const std::size_t last = std::min<std::size_t>(r.last, b->size() - 1);
        return Variant(ByteString(std::vector<std::uint8_t>(
            b->bytes.begin() + r.first, b->bytes.begin() + static_cast<std::ptrdiff_t>(last) + 1)));
    }
    return status::BadIndexRangeNoData;
}

/// The value after writing `part` into elements first..last of `whole`.
Result<Variant> writeRange(const Variant& whole, const Variant& part,
                           const std::vector<IndexRange>& ranges) {
    if (ranges.size() != 1 || !whole.isArray() || whole.dimensions().size() > 1) {
        return status::BadIndexRangeNoData;
    }
    const IndexRange r = ranges.front();
    std::vector<Scalar> el = whole.elements();
    if (r.last >= el.size()) return status::BadIndexRangeNoData;
    if (!part.isArray() || part.type() != whole.type() ||
        part.elements().size() != std::size_t{r.last} - r.first + 1) {
        return status::BadIndexRangeInvalid;
    }
    std::copy(part.elements().begin(), part.elements().end(), el.begin() + r.first);
    return Variant::array(whole.type(), std::move(el));
}

bool canAccess(const Node& n, std::uint8_t bit) {
    if (n.nodeClass != NodeClass::Variable) return true;
    return (n.accessLevel & n.userAccessLevel & bit) != 0;
}

Variant attributeValue(const Node& n, AttributeId id) {
    using A = AttributeId;
    switch (id) {
        case A::NodeId:
            return n.nodeId;
        case A::NodeClass:
            return static_cast<std::int32_t>(n.nodeClass);
        case A::BrowseName:
            return n.browseName;
        case A::DisplayName:
            return n.displayName;
        case A::Description:
            return n.description;
        case A::WriteMask:
            return n.writeMask;
        case A::UserWriteMask:
            return n.writeMask & n.userWriteMask;
        case A::IsAbstract:
            return n.isAbstract;
        case A::Symmetric:
            return n.symmetric;
        case A::InverseName:
            return n.inverseName;
        case A::ContainsNoLoops:
            return n.containsNoLoops;
        case A::EventNotifier:
            return n.eventNotifier;
        case A::DataType:
            return n.dataType;
        case A::ValueRank:
            return n.valueRank;
        case A::ArrayDimensions:
            return Variant::array(n.arrayDimensions);
        case A::AccessLevel:
            return n.accessLevel;
        case A::UserAccessLevel:
            return static_cast<std::uint8_t>(n.accessLevel & n.userAccessLevel);
        case A::MinimumSamplingInterval:
            return n.minimumSamplingInterval;
        case A::Historizing:
            return n.historizing;
        case A::Executable:
            return n.executable;
        case A::UserExecutable:
            return n.executable && n.userExecutable;
        case A::AccessLevelEx:
            return std::uint32_t{n.accessLevel};
        case A::DataTypeDefinition:
            return dataTypeDefinitionValue(n.definition);
        default:
            return {};  // Value and the attributes hasAttribute() refuses
    }
}

void applyTimestamps(DataValue& dv, TimestampsToReturn t) {
    if (t == TimestampsToReturn::Server || t == TimestampsToReturn::Neither) {
        dv.sourceTimestamp.reset();
        dv.sourcePicoseconds.reset();
    }
    if (t == TimestampsToReturn::Server || t == TimestampsToReturn::Both) {
        dv.serverTimestamp = DateTime::now();
    } else {
        dv.serverTimestamp.reset();
        dv.serverPicoseconds.reset();
    }
}

}  // namespace

std::optional<std::vector<IndexRange>> parseIndexRange(std::string_view text) {
    std::vector<IndexRange> out;
    while (!text.empty()) {
        const auto comma = text.find(',');
        const std::string_view dim = text.substr(0, comma);
        const auto colon = dim.find(':');
        IndexRange r;
        if (colon == std::string_view::npos) {
            auto i = parseIndex(dim);
            if (!i) return std::nullopt;
            r = {*i, *i};
        } else {
            auto a = parseIndex(dim.substr(0, colon));
            auto b = parseIndex(dim.substr(colon + 1));
            if (!a || !b || *a >= *b) return std::nullopt;
            r = {*a, *b};
        }
        out.push_back(r);
        if (comma == std::string_view::npos) break;
        text.remove_prefix(comma + 1);
        if (text.empty()) return std::nullopt;  // trailing comma
    }
    return out;
}

DataValue readAttribute(const AddressSpace& as, const ReadValueId& item,
                        TimestampsToReturn timestamps) {
    const Node* n = as.find(item.nodeId);
    if (n == nullptr) return DataValue::withStatus(status::BadNodeIdUnknown);
    // DataTypeDefinition is optional per node: structures and enumerations have one, the
    // other data types (built-in, abstract, simple subtypes) do not.
    const bool hasDefinition =
        n->nodeClass == NodeClass::DataType &&
        item.attributeId == static_cast<std::uint32_t>(AttributeId::DataTypeDefinition) &&
        !std::holds_alternative<std::monostate>(n->definition);
    if (item.attributeId == 0 || item.attributeId > kMaxAttributeId ||
        (!hasAttribute(n->nodeClass, item.attributeId) && !hasDefinition)) {
        return DataValue::withStatus(status::BadAttributeIdInvalid);
    }
    const auto attribute = static_cast<AttributeId>(item.attributeId);
    const bool isValue = attribute == AttributeId::Value;
    const bool encodingRequested =
        !item.dataEncoding.name.empty() || item.dataEncoding.namespaceIndex != 0;
    if (encodingRequested && !isValue) return DataValue::withStatus(status::BadDataEncodingInvalid);
    auto range = parseIndexRange(item.indexRange);
    if (!range) return DataValue::withStatus(status::BadIndexRangeInvalid);

    DataValue dv;
    if (isValue) {
        if (!canAccess(*n, access_level::kCurrentRead)) {
            return DataValue::withStatus(status::BadNotReadable);
        }
        dv = as.readValue(*n);
        // A variable type without a default value still answers with a (null) value.
        if (!dv.value && dv.statusOrGood().isGood()) dv.value = Variant{};
        if (encodingRequested) {
            // Only structures have encodings, and this server only speaks binary.
            if (!dv.value || dv.value->type() != BuiltinType::ExtensionObject) {
                return DataValue::withStatus(status::BadDataEncodingInvalid);
            }
            if (item.dataEncoding != QualifiedName{0, "Default Binary"}) {
                return DataValue::withStatus(status::BadDataEncodingUnsupported);
            }
        }
        applyTimestamps(dv, timestamps);
    } else {
        dv.value = attributeValue(*n, attribute);
    }
    if (!range->empty() && dv.value) {
        auto sub = applyRange(*dv.value, *range);
        if (!sub) return DataValue::withStatus(sub.status());
        dv.value = std::move(*sub);
    }
    return dv;
}

StatusCode read(const AddressSpace& as, const ServerLimits& limits, const ReadRequest& request,
                ReadResponse& response) {
    if (request.maxAge < 0) return status::BadMaxAgeInvalid;
    const auto t = request.timestampsToReturn;
    if (t != TimestampsToReturn::Source && t != TimestampsToReturn::Server &&
        t != TimestampsToReturn::Both && t != TimestampsToReturn::Neither) {
        return status::BadTimestampsToReturnInvalid;
    }
    return forEachOperation(limits, request.nodesToRead, response.results,
                            [&](const ReadValueId& item) { return readAttribute(as, item, t); });
}

StatusCode writeAttribute(AddressSpace& as, const WriteValue& item, const Caller& caller) {
    Node* n = as.find(item.nodeId);
    if (n == nullptr) return status::BadNodeIdUnknown;
    if (item.attributeId == 0 || item.attributeId > kMaxAttributeId ||
        !hasAttribute(n->nodeClass, item.attributeId)) {
        return status::BadAttributeIdInvalid;
    }
    // Only variable values are writable: WriteMask is 0 on every node this server holds.
    if (static_cast<AttributeId>(item.attributeId) != AttributeId::Value ||
        n->nodeClass != NodeClass::Variable || !canAccess(*n, access_level::kCurrentWrite)) {
        return status::BadNotWritable;
    }
    // Writing a value sets what the plant does next (a skill parameter): operators only.
    if (!caller.roles.atLeast(n->requiredRole)) {
        spdlog::warn("session {}: Write of {} refused (BadUserAccessDenied): roles {}, needs {}",
                     caller.sessionId.toString(), item.nodeId.toString(), caller.roles.toString(),
                     roleName(n->requiredRole));
        return status::BadUserAccessDenied;
    }
    if (!item.value.value) return status::BadTypeMismatch;
    auto range = parseIndexRange(item.indexRange);
    if (!range) return status::BadIndexRangeInvalid;

    Variant newValue = *item.value.value;
    if (!range->empty()) {
        const DataValue current = as.readValue(*n);
        auto merged = writeRange(current.value.value_or(Variant{}), newValue, *range);
        if (!merged) return merged.status();
        newValue = std::move(*merged);
    }
    if (!as.valueMatches(newValue, n->dataType, n->valueRank)) return status::BadTypeMismatch;

    // Status and source timestamp are taken as written (node-opcua and UaExpert send a bare
    // value, some clients send a source timestamp); the server timestamp is always ours.
    DataValue dv;
    dv.value = std::move(newValue);
    dv.status = item.value.status;
    dv.sourceTimestamp = item.value.sourceTimestamp.value_or(DateTime::now());
    dv.sourcePicoseconds = item.value.sourcePicoseconds;
    // A value the application computes cannot take a write it has no sink for.
    if (n->valueSource && !n->valueSink) return status::BadNotWritable;
    if (n->valueSink) {
        const StatusCode s = n->valueSink(caller, dv);
        if (s.isBad()) return s;
    }
    // A variable with a ValueSource reads its value from the application; storing it too
    // would only keep a stale copy.
    if (!n->valueSource) n->value = std::move(dv);
    as.notifyValueChanged(*n);  // subscriptions report the write without polling
    return status::Good;
}

StatusCode write(AddressSpace& as, const ServerLimits& limits, const WriteRequest& request,
                 WriteResponse& response, const Caller& caller) {
    return forEachOperation(
        limits, request.nodesToWrite, response.results,
        [&](const WriteValue& item) { return writeAttribute(as, item, caller); });
}

void registerAttributeServices(ServiceTable& table, AddressSpace& as) {
    using A = ServiceTable::Access;
    table.add<ReadRequest, ReadResponse>(A::ActivatedSession,
                                         [&as](ServiceContext& ctx, const auto& req, auto& resp) {
                                             return read(as, limitsOf(ctx), req, resp);
                                         });
    table.add<WriteRequest, WriteResponse>(
        A::ActivatedSession, [&as](ServiceContext& ctx, const auto& req, auto& resp) {
            return write(as, limitsOf(ctx), req, resp, callerOf(ctx));
        });
}

}  // namespace skillcell::ua
