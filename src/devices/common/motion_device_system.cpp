#include "devices/common/motion_device_system.hpp"

#include "ua/address_space/dynamic_structure.hpp"
#include "ua/address_space/instantiate.hpp"
#include "ua/address_space/ns0_ids.hpp"
#include "ua/nodeset/companion_models.hpp"

namespace skillcell::devices {
namespace {

// Facts of the Foundation's models: DI's DeviceSet, Robotics' types (OPC 40010-1).
constexpr std::uint32_t kDeviceSet = 5001;
constexpr std::uint32_t kMotionDeviceSystemType = 1002;
constexpr std::uint32_t kMotionDeviceType = 1004;
constexpr std::uint32_t kAxisType = 16601;
// The radian in UNECE's common codes (C81), as OPC 10000-8 5.6.3 numbers it.
constexpr std::int32_t kRadianUnitId = 0x433831;

/// EUInformation of the radian, built through the data type's definition.
ua::Variant radians(const ua::AddressSpace& as) {
    auto eu = ua::defaultStructure(as.dataTypes(), ua::NodeId(ua::ns0::EUInformation));
    if (!eu) return {};
    eu->set("NamespaceUri", ua::String("http://www.opcfoundation.org/UA/units/un/cefact"));
    eu->set("UnitId", kRadianUnitId);
    eu->set("DisplayName", ua::LocalizedText{"", "rad"});
    eu->set("Description", ua::LocalizedText{"", "radian"});
    auto eo = ua::toExtensionObject(as.dataTypes(), *eu);
    return eo ? ua::Variant(std::move(*eo)) : ua::Variant();
}

}  // namespace

ua::Result<MotionDeviceSystem> MotionDeviceSystem::create(
    ua::AddressSpace& as, const MotionDeviceDescription& description) {
    const auto di = as.namespaceIndex(ua::companion::kDiUri);
    const auto rob = as.namespaceIndex(ua::companion::kRoboticsUri);
    if (!di || !rob) return ua::status::BadTypeDefinitionInvalid;
    const ua::NodeId hasComponent(ua::ns0::HasComponent);
    const auto child = [&](const ua::NodeId& parent, std::uint16_t ns,
                           const char* name) -> ua::Result<ua::NodeId> {
        const ua::Node* n = as.findChild(parent, ua::QualifiedName{ns, name});
        if (n == nullptr) return ua::status::BadNodeIdUnknown;
        return n->nodeId;
    };

    MotionDeviceSystem out;
    auto system =
        ua::instantiate(as, ua::NodeId(*rob, kMotionDeviceSystemType), ua::NodeId(*di, kDeviceSet),
                        hasComponent, ua::QualifiedName{1, description.name + "System"});
    if (!system) return system.status();
    out.system_ = *system;
    auto devices = child(*system, *rob, "MotionDevices");
    if (!devices) return devices.status();
    auto device = ua::instantiate(as, ua::NodeId(*rob, kMotionDeviceType), *devices, hasComponent,
                                  ua::QualifiedName{1, description.name});
    if (!device) return device.status();
    const auto property = [&](std::uint16_t ns, const char* name, ua::Variant value) {
        if (auto p = child(*device, ns, name)) (void)as.setValue(*p, std::move(value));
    };
    property(*di, "Manufacturer", ua::LocalizedText{"", description.manufacturer});
    property(*di, "Model", ua::LocalizedText{"", description.model});
    property(*di, "ProductCode", ua::String(description.productCode));
    property(*di, "SerialNumber", ua::String(description.serialNumber));
    property(*rob, "MotionDeviceCategory", description.category);

    auto axes = child(*device, *rob, "Axes");
    if (!axes) return axes.status();
    const ua::Variant unit = radians(as);
    for (const auto& name : description.axes) {
        auto axis = ua::instantiate(as, ua::NodeId(*rob, kAxisType), *axes, hasComponent,
                                    ua::QualifiedName{1, name});
        if (!axis) return axis.status();
        auto params = child(*axis, *di, "ParameterSet");
        if (!params) return params.status();
        auto position = child(*params, *rob, "ActualPosition");
        if (!position) return position.status();
        if (auto eu = child(*position, 0, "EngineeringUnits"); eu && !unit.isEmpty()) {
            (void)as.setValue(*eu, unit);
        }
        // MotionProfile: AxisMotionProfileEnumeration 1 = ROTARY (a revolute joint).
        if (auto profile = child(*axis, *rob, "MotionProfile")) {
            (void)as.setValue(*profile, std::int32_t{1});
        }
        out.actualPositions_.push_back(*position);
    }
    return out;
}

void MotionDeviceSystem::update(ua::AddressSpace& as, std::span<const double> positions) const {
    for (std::size_t i = 0; i < positions.size() && i < actualPositions_.size(); ++i) {
        (void)as.setValue(actualPositions_[i], positions[i]);
    }
}

}  // namespace skillcell::devices
