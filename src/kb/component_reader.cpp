#include "kb/component_reader.hpp"

#include <cmath>
#include <set>
#include <type_traits>

#include "ua/address_space/ns0_ids.hpp"
#include "ua/client/blocking_client.hpp"
#include "ua/encoding/binary_reader.hpp"

namespace skillcell::kb {
namespace {

// 3DFrame's Default Binary encoding (namespace 0): six Doubles, CartesianCoordinates X, Y,
// Z then Orientation A, B, C (devices/common/frame.hpp).
constexpr std::uint32_t kThreeDFrameDefaultBinary = 18823;
constexpr std::size_t kFrameBodySize = 6 * sizeof(double);
// Nodes per Read request (servers limit operations per request).
constexpr std::size_t kReadsPerRequest = 100;

std::optional<PoseValue> pose(const ua::Variant& value) {
    const auto* eo = value.get<ua::ExtensionObject>();
    if (eo == nullptr || eo->encoding != ua::ExtensionObject::Encoding::Binary ||
        eo->typeId != ua::NodeId(kThreeDFrameDefaultBinary) || eo->body.size() != kFrameBodySize) {
        return std::nullopt;
    }
    ua::BinaryReader r(eo->body.bytes);
    PoseValue p;
    for (double* part : {&p.x, &p.y, &p.z, &p.roll, &p.pitch, &p.yaw}) {
        *part = r.read<double>();
        if (!std::isfinite(*part)) return std::nullopt;
    }
    if (!r.ok()) return std::nullopt;
    return p;
}

std::optional<double> number(const ua::Scalar& s) {
    return std::visit(
        [](const auto& v) -> std::optional<double> {
            using V = std::decay_t<decltype(v)>;
            if constexpr (std::is_arithmetic_v<V> && !std::is_same_v<V, bool>) {
                const auto d = static_cast<double>(v);
                if (std::isfinite(d)) return d;
            }
            return std::nullopt;
        },
        s);
}

// One Read of Value per node, in pieces; one DataValue per node, in order.
ua::Result<std::vector<ua::DataValue>> readValues(ua::BlockingClient& client,
                                                  const std::vector<ua::NodeId>& nodes) {
    std::vector<ua::DataValue> out;
    for (std::size_t first = 0; first < nodes.size(); first += kReadsPerRequest) {
        ua::ReadRequest request;
        request.timestampsToReturn = ua::TimestampsToReturn::Neither;
        for (std::size_t i = first; i < nodes.size() && i < first + kReadsPerRequest; ++i) {
            ua::ReadValueId id;
            id.nodeId = nodes[i];
            request.nodesToRead.push_back(std::move(id));
        }
        const std::size_t asked = request.nodesToRead.size();
        auto response = client.read(std::move(request));
        if (!response) return response.status();
        if (response->results.size() != asked) return ua::status::BadUnknownResponse;
        for (auto& dv : response->results) out.push_back(std::move(dv));
    }
    return out;
}

}  // namespace

std::optional<ParameterValue> parameterValue(const skills::SkillParameter& parameter,
                                             const ua::Variant& value,
                                             const std::vector<std::string>* enumStrings) {
    ParameterValue out;
    out.name = parameter.browseName.name;
    out.dataType = parameter.dataType;
    if (!value.isScalar()) return std::nullopt;
    if (const auto* text = value.get<ua::String>()) {
        out.value = *text;
    } else if (const auto* localized = value.get<ua::LocalizedText>()) {
        out.value = localized->text;
    } else if (const auto* index = value.get<std::int32_t>();
               index != nullptr && enumStrings != nullptr && *index >= 0 &&
               static_cast<std::size_t>(*index) < enumStrings->size() &&
               !(*enumStrings)[static_cast<std::size_t>(*index)].empty()) {
        out.value = (*enumStrings)[static_cast<std::size_t>(*index)];
    } else if (const auto p = pose(value)) {
        out.value = *p;
    } else if (const auto n = number(value.scalar())) {
        out.value = *n;
    } else {
        return std::nullopt;
    }
    return out;
}

ua::Result<ComponentReading> ComponentReader::read(
    const std::string& endpointUrl, const std::vector<skills::SkillInstance>& skills) {
    ua::BlockingClient client;
    {
        const std::lock_guard lock(mutex_);
        if (cancelled_) return ua::status::BadShutdown;
        current_ = &client;
    }
    auto reading = readWith(client, endpointUrl, skills);
    {
        const std::lock_guard lock(mutex_);
        current_ = nullptr;
    }
    return reading;  // the client disconnects as it goes
}

void ComponentReader::cancel() {
    const std::lock_guard lock(mutex_);
    cancelled_ = true;
    if (current_ == nullptr) return;
    // The read's request in flight fails at once (BadConnectionClosed); read() then stops
    // at its next step. Only the client's own thread touches the Client.
    (void)current_->run([](ua::Client& c) -> asio::awaitable<ua::StatusCode> {
        c.abort();
        co_return ua::status::Good;
    });
}

bool ComponentReader::cancelled() {
    const std::lock_guard lock(mutex_);
    return cancelled_;
}

ua::Result<ComponentReading> ComponentReader::readWith(
    ua::BlockingClient& client, const std::string& endpointUrl,
    const std::vector<skills::SkillInstance>& skills) {
    if (const auto s = client.connect(endpointUrl, config_); s.isBad()) return s;
    if (cancelled()) return ua::status::BadShutdown;

    // The NamespaceArray and every parameter's value, in one Read (or a few).
    std::vector<ua::NodeId> nodes{ua::NodeId(ua::ns0::Server_NamespaceArray)};
    std::vector<std::pair<const skills::SkillInstance*, const skills::SkillParameter*>> asked;
    for (const auto& skill : skills) {
        for (const auto& parameter : skill.parameters) {
            nodes.push_back(parameter.nodeId);
            asked.emplace_back(&skill, &parameter);
        }
    }
    auto values = readValues(client, nodes);
    if (!values) return values.status();
    if (cancelled()) return ua::status::BadShutdown;

    ComponentReading reading;
    const ua::DataValue& namespaces = (*values)[0];
    if (namespaces.statusOrGood().isBad() || !namespaces.value ||
        namespaces.value->type() != ua::BuiltinType::String) {
        return ua::status::BadTypeMismatch;  // every server has its NamespaceArray
    }
    for (const auto& uri : namespaces.value->elements()) {
        reading.namespaceArray.push_back(std::get<ua::String>(uri));
    }

    // The names of enumeration values: the EnumStrings of each data type of an Int32 value
    // (an enumeration is encoded as an Int32), asked of the component.
    std::vector<ua::NodeId> enumTypes;
    {
        std::set<ua::NodeId> seen;
        for (std::size_t i = 0; i < asked.size(); ++i) {
            const ua::DataValue& dv = (*values)[i + 1];
            const ua::NodeId& type = asked[i].second->dataTypeId;
            if (dv.value && dv.value->get<std::int32_t>() != nullptr &&
                type != ua::NodeId(ua::ns0::Int32) && seen.insert(type).second) {
                enumTypes.push_back(type);
            }
        }
    }
    std::map<ua::NodeId, std::vector<std::string>> enumStrings;
    if (!enumTypes.empty()) {
        ua::TranslateBrowsePathsToNodeIdsRequest request;
        for (const auto& type : enumTypes) {
            ua::RelativePathElement element;
            element.referenceTypeId = ua::NodeId(ua::ns0::HasProperty);
            element.targetName = ua::QualifiedName{0, "EnumStrings"};
            ua::BrowsePath path;
            path.startingNode = type;
            path.relativePath.elements.push_back(std::move(element));
            request.browsePaths.push_back(std::move(path));
        }
        auto translated = client.translateBrowsePaths(std::move(request));
        if (!translated) return translated.status();
        if (translated->results.size() != enumTypes.size()) return ua::status::BadUnknownResponse;
        std::vector<ua::NodeId> properties;
        std::vector<ua::NodeId> typesOfProperties;
        for (std::size_t i = 0; i < enumTypes.size(); ++i) {
            const auto& r = translated->results[i];
            // BadNoMatch: no EnumStrings (Int32 itself, or an enumeration with EnumValues).
            if (r.statusCode.isBad() || r.targets.empty() || !r.targets[0].targetId.isLocal()) {
                continue;
            }
            properties.push_back(r.targets[0].targetId.nodeId);
            typesOfProperties.push_back(enumTypes[i]);
        }
        if (cancelled()) return ua::status::BadShutdown;
        auto strings = readValues(client, properties);
        if (!strings) return strings.status();
        for (std::size_t i = 0; i < properties.size(); ++i) {
            const auto& dv = (*strings)[i];
            if (!dv.value || dv.value->type() != ua::BuiltinType::LocalizedText) continue;
            auto& names = enumStrings[typesOfProperties[i]];
            for (const auto& e : dv.value->elements()) {
                names.push_back(std::get<ua::LocalizedText>(e).text);
            }
        }
    }

    for (std::size_t i = 0; i < asked.size(); ++i) {
        const auto& [skill, parameter] = asked[i];
        auto& recorded = reading.values[skill->nodeId];  // read, even if it has no value
        const ua::DataValue& dv = (*values)[i + 1];
        if (dv.statusOrGood().isBad() || !dv.value) continue;
        const auto names = enumStrings.find(parameter->dataTypeId);
        auto v = parameterValue(*parameter, *dv.value,
                                names == enumStrings.end() ? nullptr : &names->second);
        if (v) recorded.push_back(std::move(*v));
    }
    for (const auto& skill : skills) (void)reading.values[skill.nodeId];  // no parameters
    return reading;
}

}  // namespace skillcell::kb
