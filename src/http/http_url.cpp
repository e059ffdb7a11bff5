#include "http/http_url.hpp"

#include <charconv>

namespace skillcell::http {

Expected<HttpUrl> HttpUrl::parse(const std::string& url) {
    HttpUrl u;
    std::string rest;
    if (url.rfind("https://", 0) == 0) {
        u.tls = true;
        u.port = 443;
        rest = url.substr(8);
    } else if (url.rfind("http://", 0) == 0) {
        rest = url.substr(7);
    } else {
        return badInput("'" + url + "': only http:// and https:// URLs are supported");
    }
    const auto slash = rest.find('/');
    std::string authority = rest.substr(0, slash);
    u.path = slash == std::string::npos ? "/" : rest.substr(slash);
    if (authority.find('@') != std::string::npos) {
        return badInput("'" + url + "': no user in the URL (passwords do not belong there)");
    }
    std::string portText;
    if (!authority.empty() && authority.front() == '[') {  // [IPv6]:port
        const auto close = authority.find(']');
        if (close == std::string::npos) return badInput("'" + url + "': unclosed '['");
        u.host = authority.substr(1, close - 1);
        if (close + 1 < authority.size()) {
            if (authority[close + 1] != ':') return badInput("'" + url + "': bad authority");
            portText = authority.substr(close + 2);
        }
    } else {
        const auto colon = authority.rfind(':');
        u.host = authority.substr(0, colon);
        if (colon != std::string::npos) portText = authority.substr(colon + 1);
    }
    if (u.host.empty()) return badInput("'" + url + "': no host");
    if (!portText.empty() || authority.back() == ':') {
        unsigned port = 0;
        auto [end, ec] = std::from_chars(portText.data(), portText.data() + portText.size(), port);
        if (ec != std::errc{} || end != portText.data() + portText.size() || port == 0 ||
            port > 65535) {
            return badInput("'" + url + "': bad port '" + portText + "'");
        }
        u.port = static_cast<std::uint16_t>(port);
    }
    return u;
}

std::string HttpUrl::toString() const {
    const bool v6 = host.find(':') != std::string::npos;
    return std::string(tls ? "https://" : "http://") + (v6 ? "[" + host + "]" : host) + ":" +
           std::to_string(port) + path;
}

HttpUrl HttpUrl::withPath(std::string p) const {
    HttpUrl u = *this;
    u.path = std::move(p);
    return u;
}

}  // namespace skillcell::http
