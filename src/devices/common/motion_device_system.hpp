#pragma once
// A robot as the OPC Foundation's Robotics model (OPC 40010-1) describes it, so that a client
// that knows that model and nothing of skillcell finds it: a MotionDeviceSystemType instance
// in DI's DeviceSet, with one MotionDeviceType (its nameplate and category) and an AxisType
// per joint whose ParameterSet/ActualPosition follows the arm.
//
// The nodes come from the model by instantiate(): the Robotics NodeSet must be loaded (the
// companion models are). Build and update on the server's io_context thread.
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "ua/address_space/address_space.hpp"
#include "ua/types/result.hpp"

namespace skillcell::devices {

struct MotionDeviceDescription {
    std::string name;  // the system's and the device's browse name, e.g. "UR5"
    std::string manufacturer;
    std::string model;
    std::string productCode;
    std::string serialNumber;
    /// MotionDeviceCategoryEnumeration: 1 ARTICULATED_ROBOT, 2 SCARA_ROBOT, ...
    std::int32_t category = 1;
    /// One name per joint, in the order update() gets the positions.
    std::vector<std::string> axes;
};

class MotionDeviceSystem {
public:
    /// Adds the system under DeviceSet. BadTypeDefinitionInvalid without the Robotics model,
    /// else instantiate()'s errors; on error what was added stays (the component fails).
    [[nodiscard]] static ua::Result<MotionDeviceSystem> create(
        ua::AddressSpace& as, const MotionDeviceDescription& description);

    /// The joints' positions in radians, in the order of MotionDeviceDescription::axes.
    void update(ua::AddressSpace& as, std::span<const double> positions) const;

    [[nodiscard]] const ua::NodeId& systemNode() const { return system_; }
    [[nodiscard]] const std::vector<ua::NodeId>& actualPositions() const {
        return actualPositions_;
    }

private:
    ua::NodeId system_;
    std::vector<ua::NodeId> actualPositions_;
};

}  // namespace skillcell::devices
