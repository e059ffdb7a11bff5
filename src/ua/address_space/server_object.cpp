#include "ua/address_space/server_object.hpp"

#include "ua/encoding/codec.hpp"

namespace skillcell::ua {
namespace {

DataValue now(Variant v) {
    DataValue dv;
    dv.value = std::move(v);
    dv.sourceTimestamp = DateTime::now();
    return dv;
}

}  // namespace

StatusCode installServerObject(AddressSpace& as, const ServerInfo& info, const ServerState* state) {
    if (as.find(NodeId(ns0::Server)) == nullptr ||
        as.find(NodeId(ns0::Server_ServerStatus)) == nullptr) {
        return status::BadNodeIdUnknown;
    }
    as.setApplicationUri(info.applicationUri);

    BuildInfo build;
    build.productUri = info.productUri;
    build.manufacturerName = info.manufacturerName;
    build.productName = info.productName;
    build.softwareVersion = info.softwareVersion;
    build.buildNumber = info.buildNumber;
    build.buildDate = info.buildDate;
    const DateTime start = info.startTime;
    const auto currentState = [state] { return state ? *state : ServerState::Running; };

    // Each callback captures only copies or the address space itself, which owns it.
    StatusCode s = status::Good;
    const auto source = [&](std::uint32_t id, ValueSource src) {
        const StatusCode r = as.setValueSource(NodeId(id), std::move(src));
        if (r.isBad() && s.isGood()) s = r;
    };
    source(ns0::Server_NamespaceArray,
           [&as] { return now(Variant::array(std::vector<String>(as.namespaces()))); });
    source(ns0::Server_ServerStatus, [build, start, currentState] {
        ServerStatusDataType st;
        st.startTime = start;
        st.currentTime = DateTime::now();
        st.state = currentState();
        st.buildInfo = build;
        return now(Variant(toExtensionObject(st)));
    });
    source(ns0::Server_ServerStatus_CurrentTime, [] { return now(Variant(DateTime::now())); });
    source(ns0::Server_ServerStatus_State,
           [currentState] { return now(Variant(static_cast<std::int32_t>(currentState()))); });
    source(ns0::Server_ServerStatus_BuildInfo,
           [build] { return now(Variant(toExtensionObject(build))); });
    if (s.isBad()) return s;

    // Values that do not change while the server runs are stored once. A stored value is
    // also what a monitored item reports on change only; a ValueSource's is sampled at the
    // item's interval: each detector watching StartTime (to see a restart) woke its server
    // once a second for a value that never changes.
    const auto store = [&](std::uint32_t id, Variant v) {
        const StatusCode r = as.setValue(NodeId(id), std::move(v));
        if (r.isBad() && s.isGood()) s = r;
    };
    store(ns0::Server_ServerStatus_StartTime, start);
    store(ns0::Server_ServerArray, Variant::array(std::vector<String>{info.applicationUri}));
    store(ns0::Server_ServerStatus_SecondsTillShutdown, std::uint32_t{0});
    store(ns0::Server_ServerStatus_ShutdownReason, LocalizedText{});
    store(ns0::Server_ServiceLevel, std::uint8_t{255});
    store(ns0::Server_ServerStatus_BuildInfo_ProductUri, build.productUri);
    store(ns0::Server_ServerStatus_BuildInfo_ManufacturerName, build.manufacturerName);
    store(ns0::Server_ServerStatus_BuildInfo_ProductName, build.productName);
    store(ns0::Server_ServerStatus_BuildInfo_SoftwareVersion, build.softwareVersion);
    store(ns0::Server_ServerStatus_BuildInfo_BuildNumber, build.buildNumber);
    store(ns0::Server_ServerStatus_BuildInfo_BuildDate, build.buildDate);
    store(ns0::Server_ServerCapabilities_ServerProfileArray,
          Variant::array(std::vector<String>(info.serverProfiles)));
    store(ns0::Server_ServerCapabilities_LocaleIdArray,
          Variant::array(std::vector<String>(info.localeIds)));
    store(ns0::Server_ServerCapabilities_MaxBrowseContinuationPoints,
          info.maxBrowseContinuationPoints);
    return s;
}

}  // namespace skillcell::ua
