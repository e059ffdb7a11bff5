#pragma once
// Structures shared by every service (OPC 10000-4, 7.32 RequestHeader, 7.33 ResponseHeader)
// and the enumerations the services use. Each structure lists its fields in wire order in
// `tie`; the generic codec in ua/encoding/codec.hpp does the rest.
#include <cstdint>
#include <string_view>
#include <tuple>
#include <vector>

#include "ua/types/variant.hpp"

namespace skillcell::ua {

struct RequestHeader {
    NodeId authenticationToken;
    DateTime timestamp;
    std::uint32_t requestHandle = 0;
    std::uint32_t returnDiagnostics = 0;
    String auditEntryId;
    std::uint32_t timeoutHint = 0;
    ExtensionObject additionalHeader;
    static auto tie(auto& s) {
        return std::tie(s.authenticationToken, s.timestamp, s.requestHandle, s.returnDiagnostics,
                        s.auditEntryId, s.timeoutHint, s.additionalHeader);
    }
};

struct ResponseHeader {
    DateTime timestamp;
    std::uint32_t requestHandle = 0;
    StatusCode serviceResult;
    DiagnosticInfo serviceDiagnostics;
    std::vector<String> stringTable;
    ExtensionObject additionalHeader;
    static auto tie(auto& s) {
        return std::tie(s.timestamp, s.requestHandle, s.serviceResult, s.serviceDiagnostics,
                        s.stringTable, s.additionalHeader);
    }
};

struct ServiceFault {
    static constexpr std::uint32_t kBinaryEncodingId = 397;
    ResponseHeader responseHeader;
    static auto tie(auto& s) { return std::tie(s.responseHeader); }
};

enum class MessageSecurityMode : std::int32_t {
    Invalid = 0,
    None = 1,
    Sign = 2,
    SignAndEncrypt = 3
};
enum class ApplicationType : std::int32_t {
    Server = 0,
    Client = 1,
    ClientAndServer = 2,
    DiscoveryServer = 3
};
enum class UserTokenType : std::int32_t {
    Anonymous = 0,
    UserName = 1,
    Certificate = 2,
    IssuedToken = 3
};
enum class BrowseDirection : std::int32_t { Forward = 0, Inverse = 1, Both = 2, Invalid = 3 };
enum class TimestampsToReturn : std::int32_t {
    Source = 0,
    Server = 1,
    Both = 2,
    Neither = 3,
    Invalid = 4
};

/// Node classes are bit values so that browse filters can combine them (OPC 10000-3, 8.29).
enum class NodeClass : std::int32_t {
    Unspecified = 0,
    Object = 1,
    Variable = 2,
    Method = 4,
    ObjectType = 8,
    VariableType = 16,
    ReferenceType = 32,
    DataType = 64,
    View = 128
};

/// The node class's name in the standard ("Object", "ReferenceType"); empty for a value that
/// names none (Unspecified, a combination of bits, a number off the list).
[[nodiscard]] constexpr std::string_view nodeClassName(NodeClass c) {
    switch (c) {
        case NodeClass::Object:
            return "Object";
        case NodeClass::Variable:
            return "Variable";
        case NodeClass::Method:
            return "Method";
        case NodeClass::ObjectType:
            return "ObjectType";
        case NodeClass::VariableType:
            return "VariableType";
        case NodeClass::ReferenceType:
            return "ReferenceType";
        case NodeClass::DataType:
            return "DataType";
        case NodeClass::View:
            return "View";
        default:
            return {};
    }
}

/// Attribute ids (OPC 10000-6, A.1).
enum class AttributeId : std::uint32_t {
    NodeId = 1,
    NodeClass = 2,
    BrowseName = 3,
    DisplayName = 4,
    Description = 5,
    WriteMask = 6,
    UserWriteMask = 7,
    IsAbstract = 8,
    Symmetric = 9,
    InverseName = 10,
    ContainsNoLoops = 11,
    EventNotifier = 12,
    Value = 13,
    DataType = 14,
    ValueRank = 15,
    ArrayDimensions = 16,
    AccessLevel = 17,
    UserAccessLevel = 18,
    MinimumSamplingInterval = 19,
    Historizing = 20,
    Executable = 21,
    UserExecutable = 22,
    DataTypeDefinition = 23,
    RolePermissions = 24,
    UserRolePermissions = 25,
    AccessRestrictions = 26,
    AccessLevelEx = 27
};
inline constexpr std::uint32_t kMaxAttributeId = 27;

}  // namespace skillcell::ua
