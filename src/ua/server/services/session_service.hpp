#pragma once
// Session service set (CreateSession, ActivateSession, CloseSession) and Discovery service
// set (GetEndpoints, FindServers): the services that run before or without a session.
#include "ua/server/server_description.hpp"
#include "ua/server/service_table.hpp"
#include "ua/server/session_manager.hpp"

namespace skillcell::ua {

void registerSessionServices(ServiceTable& table, SessionManager& sessions,
                             const ServerDescription& description, const ServerSecurity& security);
void registerDiscoveryServices(ServiceTable& table, const ServerDescription& description);

}  // namespace skillcell::ua
