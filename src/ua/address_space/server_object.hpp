#pragma once
// The live part of the standard Server object (i=2253): the nodes come from the base
// NodeSet2 file; installServerObject gives the dynamic ones value callbacks.
#include <cstdint>
#include <string>
#include <vector>

#include "ua/address_space/address_space.hpp"

namespace skillcell::ua {

/// ServerState (OPC 10000-5, 12.6).
enum class ServerState : std::int32_t {
    Running = 0,
    Failed = 1,
    NoConfiguration = 2,
    Suspended = 3,
    Shutdown = 4,
    Test = 5,
    CommunicationFault = 6,
    Unknown = 7
};

/// BuildInfo (OPC 10000-5, 12.4).
struct BuildInfo {
    static constexpr std::uint32_t kBinaryEncodingId = ns0::BuildInfo_Encoding_DefaultBinary;
    String productUri;
    String manufacturerName;
    String productName;
    String softwareVersion;
    String buildNumber;
    DateTime buildDate;
    static auto tie(auto& s) {
        return std::tie(s.productUri, s.manufacturerName, s.productName, s.softwareVersion,
                        s.buildNumber, s.buildDate);
    }
};

/// ServerStatusDataType (OPC 10000-5, 12.10).
struct ServerStatusDataType {
    static constexpr std::uint32_t kBinaryEncodingId =
        ns0::ServerStatusDataType_Encoding_DefaultBinary;
    DateTime startTime;
    DateTime currentTime;
    ServerState state = ServerState::Running;
    BuildInfo buildInfo;
    std::uint32_t secondsTillShutdown = 0;
    LocalizedText shutdownReason;
    static auto tie(auto& s) {
        return std::tie(s.startTime, s.currentTime, s.state, s.buildInfo, s.secondsTillShutdown,
                        s.shutdownReason);
    }
};

struct ServerInfo {
    std::string applicationUri;
    std::string productUri;
    std::string productName;
    std::string softwareVersion;
    DateTime startTime;
    std::string manufacturerName = "skillcell";
    std::string buildNumber;
    DateTime buildDate;
    std::uint16_t maxBrowseContinuationPoints = 10;
    std::vector<std::string> serverProfiles;
    std::vector<std::string> localeIds{"en"};
};

/// Sets namespace 1 to the application URI and installs value sources on NamespaceArray,
/// ServerArray, ServerStatus and its children, ServiceLevel and the capabilities listed in
/// ServerInfo. The state is read through `state` so the server can report shutdown; it
/// must outlive the address space. BadNodeIdUnknown if the base NodeSet is not loaded.
StatusCode installServerObject(AddressSpace& as, const ServerInfo& info,
                               const ServerState* state = nullptr);

}  // namespace skillcell::ua
