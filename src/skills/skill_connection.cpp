#include "skills/skill_connection.hpp"

#include <algorithm>

namespace skillcell::skills {

SkillConnection::SkillConnection(Token, asio::any_io_executor executor, std::string endpointUrl)
    : endpointUrl_(std::move(endpointUrl)), client_(std::make_unique<ua::Client>(executor)) {}

SkillConnection::~SkillConnection() = default;

asio::awaitable<ua::Result<std::unique_ptr<SkillConnection>>> SkillConnection::open(
    asio::any_io_executor executor, std::string endpointUrl, std::string typeName,
    ua::ClientConfig config, std::string* why) {
    auto c = std::make_unique<SkillConnection>(Token{}, executor, endpointUrl);
    auto say = [&](const std::string& text) {
        if (why != nullptr) *why = text;
    };
    const ua::StatusCode connected = co_await c->client_->connect(endpointUrl, config);
    if (connected.isBad()) {
        say("cannot connect to " + endpointUrl + ": " + std::string(ua::statusName(connected)));
        co_return connected;
    }
    RemoteSkillBrowser browser;
    auto found = co_await browser.browse(*c->client_);
    if (!found) {
        say("cannot browse the skills of " + endpointUrl + ": " +
            std::string(ua::statusName(found.status())));
        co_await c->client_->disconnect();
        co_return found.status();
    }
    const auto it = std::find_if(found->begin(), found->end(), [&](const RemoteSkill& s) {
        return std::any_of(s.types.begin(), s.types.end(),
                           [&](const SkillTypeRef& t) { return t.browseName == typeName; });
    });
    if (it == found->end()) {
        say(endpointUrl + " offers no " + typeName);
        co_await c->client_->disconnect();
        co_return ua::status::BadNotFound;
    }
    c->remote_ = *it;
    auto attached = co_await SkillClient::attach(*c->client_, it->nodeId);
    if (!attached) {
        say("cannot use " + it->browsePathString() + " at " + endpointUrl + ": " +
            std::string(ua::statusName(attached.status())));
        co_await c->client_->disconnect();
        co_return attached.status();
    }
    c->skill_ = std::move(*attached);
    co_return c;
}

asio::awaitable<ua::Result<ua::Variant>> SkillConnection::readParameter(std::string name) {
    const auto& ps = skill_->parameters();
    const auto it = std::find_if(ps.begin(), ps.end(),
                                 [&](const RemoteParameter& p) { return p.name == name; });
    if (it == ps.end()) co_return ua::status::BadNoMatch;
    co_return co_await client_->readValue(it->nodeId);
}

asio::awaitable<void> SkillConnection::close() {
    if (skill_) co_await skill_->detach();
    co_await client_->disconnect();
}

}  // namespace skillcell::skills
