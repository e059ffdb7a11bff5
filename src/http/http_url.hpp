#pragma once
// HttpUrl: "http[s]://HOST[:PORT][/PATH]" as a user types it on a command line or in a cell
// file. Only what a client needs to connect; query strings belong to requests.
#include <cstdint>
#include <string>

#include "common/expected.hpp"

namespace skillcell::http {

struct HttpUrl {
    bool tls = false;                // https
    std::string host = "127.0.0.1";  // a name or an IPv4 address ([v6] without brackets)
    std::uint16_t port = 80;
    std::string path = "/";

    /// An Error says what is wrong with `url` (scheme, host, port).
    [[nodiscard]] static Expected<HttpUrl> parse(const std::string& url);
    /// The URL again, with the port always written.
    [[nodiscard]] std::string toString() const;
    /// The same server, another path.
    [[nodiscard]] HttpUrl withPath(std::string p) const;
};

}  // namespace skillcell::http
