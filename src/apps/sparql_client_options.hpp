#pragma once
// How a component or a command reaches a knowledge base's SPARQL endpoint over HTTPS: it
// trusts the server as it trusts an OPC UA server (its trust list, which holds the cell CA)
// and acts as the same user as on OPC UA (a password as HTTP Basic, a user certificate as
// the TLS client certificate). With --insecure there is neither, and only http:// works.
#include "http/http_client.hpp"
#include "ua/client/client.hpp"

namespace skillcell::apps {

[[nodiscard]] http::ClientOptions sparqlClientOptions(const ua::ClientSecurity& security);

}  // namespace skillcell::apps
