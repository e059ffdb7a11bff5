#include "skills/skill_connection.hpp"

#include <asio/experimental/as_tuple.hpp>
#include <asio/steady_timer.hpp>
#include <asio/use_awaitable.hpp>

#include <algorithm>

namespace skillcell::skills {

SkillConnection::SkillConnection(Token, asio::any_io_executor executor, std::string endpointUrl)
    : endpointUrl_(std::move(endpointUrl)), session_(std::make_shared<Session>(executor)) {}

SkillConnection::SkillConnection(Token, std::shared_ptr<Session> session, std::string endpointUrl)
    : endpointUrl_(std::move(endpointUrl)), session_(std::move(session)) {}

SkillConnection::~SkillConnection() = default;

namespace {

void say(std::string* why, const std::string& text) {
    if (why != nullptr) *why = text;
}

}  // namespace

asio::awaitable<ua::Result<std::unique_ptr<SkillConnection>>> SkillConnection::open(
    asio::any_io_executor executor, std::string endpointUrl, std::string typeName,
    ua::ClientConfig config, std::string* why) {
    auto c = std::make_unique<SkillConnection>(Token{}, executor, endpointUrl);
    const ua::StatusCode connected = co_await c->client().connect(endpointUrl, config);
    if (connected.isBad()) {
        say(why,
            "cannot connect to " + endpointUrl + ": " + std::string(ua::statusName(connected)));
        co_return connected;
    }
    auto skill = co_await c->find(typeName, why);
    if (!skill) {
        co_await c->abandon();
        co_return skill.status();
    }
    const ua::StatusCode attached = co_await c->attachTo(*skill, why, SkillClientOptions{});
    if (attached.isBad()) {
        co_await c->abandon();
        co_return attached;
    }
    co_return c;
}

asio::awaitable<ua::Result<std::unique_ptr<SkillConnection>>> SkillConnection::open(
    asio::any_io_executor executor, SkillInstance instance, ua::ClientConfig config,
    std::string* why, SkillClientOptions options) {
    auto c = std::make_unique<SkillConnection>(Token{}, executor, instance.endpointUrl);
    const ua::StatusCode connected = co_await c->client().connect(instance.endpointUrl, config);
    if (connected.isBad()) {
        say(why, "cannot connect to " + instance.endpointUrl + ": " +
                     std::string(ua::statusName(connected)));
        co_return connected;
    }
    const ua::StatusCode attached = co_await c->attachTo(instance, why, options);
    if (attached.isBad()) {
        co_await c->abandon();
        co_return attached;
    }
    co_return c;
}

asio::awaitable<ua::Result<std::unique_ptr<SkillConnection>>> SkillConnection::alongside(
    std::string typeName, std::string* why) {
    auto skill = co_await find(typeName, why);
    if (!skill) co_return skill.status();
    co_return co_await alongside(std::move(*skill), why);
}

asio::awaitable<ua::Result<std::unique_ptr<SkillConnection>>> SkillConnection::alongside(
    RemoteSkill skill, std::string* why, SkillClientOptions options) {
    if (session_->open == 0) {
        // The last connection closed it: attaching would fail on a dead session anyway.
        say(why, "the session to " + endpointUrl_ + " is closed");
        co_return ua::status::BadSessionClosed;
    }
    auto c = std::make_unique<SkillConnection>(Token{}, session_, endpointUrl_);
    const ua::StatusCode attached = co_await c->attachTo(skill, why, options);
    if (attached.isBad()) co_return attached;
    co_return c;
}

asio::awaitable<ua::Result<RemoteSkill>> SkillConnection::find(const std::string& typeName,
                                                               std::string* why) {
    if (session_->browsed.empty()) {
        RemoteSkillBrowser browser;
        auto found = co_await browser.browse(client());
        if (!found) {
            say(why, "cannot browse the skills of " + endpointUrl_ + ": " +
                         std::string(ua::statusName(found.status())));
            co_return found.status();
        }
        session_->browsed = std::move(*found);
    }
    const auto& found = session_->browsed;
    // A skill of that very type first: a subtype may want more (a force-limited move its
    // limit); else one of a subtype.
    auto it = std::find_if(found.begin(), found.end(), [&](const RemoteSkill& s) {
        return !s.types.empty() && s.types.front().browseName == typeName;
    });
    if (it == found.end()) {
        it = std::find_if(found.begin(), found.end(), [&](const RemoteSkill& s) {
            return std::any_of(s.types.begin(), s.types.end(),
                               [&](const SkillTypeRef& t) { return t.browseName == typeName; });
        });
    }
    if (it == found.end()) {
        say(why, endpointUrl_ + " offers no " + typeName);
        co_return ua::status::BadNotFound;
    }
    co_return *it;
}

asio::awaitable<ua::StatusCode> SkillConnection::attachTo(const RemoteSkill& skill,
                                                          std::string* why,
                                                          SkillClientOptions options) {
    remote_ = skill;
    auto attached = co_await SkillClient::attach(client(), skill.nodeId, options);
    if (!attached) {
        say(why, "cannot use " + skill.browsePathString() + " at " + endpointUrl_ + ": " +
                     std::string(ua::statusName(attached.status())));
        co_return attached.status();
    }
    skill_ = std::move(*attached);
    ++session_->open;
    counted_ = true;
    co_return ua::status::Good;
}

asio::awaitable<void> SkillConnection::abandon() {
    co_await client().disconnect();
}

asio::awaitable<ua::Result<ua::DateTime>> SkillConnection::lastTransitionTime() {
    // The node the SkillClient found at attach; else (a skill without it in its browse) asked
    // of the server by path.
    ua::NodeId node = skill_->lastTransitionTimeNode();
    if (node.isNull()) {
        std::vector<ua::QualifiedName> path;  // named: GCC 12 and temporaries in co_await
        path.push_back(ua::QualifiedName{0, ua::String("LastTransition")});
        path.push_back(ua::QualifiedName{0, ua::String("TransitionTime")});
        auto translated = co_await client().translateBrowsePath(remote_.nodeId, std::move(path));
        if (!translated) co_return translated.status();
        node = *translated;
    }
    auto value = co_await client().readValue(node);
    if (!value) co_return value.status();
    if (value->isEmpty()) co_return ua::DateTime{};  // no transition yet
    const auto* time = value->get<ua::DateTime>();
    if (time == nullptr) co_return ua::status::BadTypeMismatch;
    co_return *time;
}

asio::awaitable<ua::Result<ua::Variant>> SkillConnection::readParameter(std::string name) {
    const RemoteParameter* p = skill_->parameter(name);
    if (p == nullptr) co_return ua::status::BadNoMatch;
    co_return co_await client().readValue(p->nodeId);
}

asio::awaitable<void> SkillConnection::close() {
    if (!counted_) co_return;  // closed already
    counted_ = false;
    co_await skill_->detach();
    if (--session_->open == 0) co_await client().disconnect();
}

namespace {

bool isA(const SkillInstance& s, const std::string& typeName, const std::string& componentUri) {
    return (componentUri.empty() || s.componentUri == componentUri) &&
           std::any_of(s.types.begin(), s.types.end(),
                       [&](const SkillTypeRef& t) { return t.browseName == typeName; });
}

std::string endpointOf(const SkillDetector& detector, const std::string& typeName,
                       const std::string& componentUri, const std::vector<ComponentLife>& gone) {
    for (const auto& s : detector.instances()) {
        if (isA(s, typeName, componentUri) &&
            std::find(gone.begin(), gone.end(),
                      ComponentLife{s.endpointUrl, s.componentStartTime.ticks}) == gone.end()) {
            return s.endpointUrl;
        }
    }
    return {};
}

}  // namespace

ComponentLife lifeAt(const SkillDetector& detector, const std::string& endpointUrl) {
    for (const auto& s : detector.instances()) {
        if (s.endpointUrl == endpointUrl) return {endpointUrl, s.componentStartTime.ticks};
    }
    return {endpointUrl, 0};
}

asio::awaitable<std::string> detectedSkillEndpoint(SkillDetector& detector, std::string typeName,
                                                   std::chrono::milliseconds timeout,
                                                   std::string componentUri,
                                                   std::vector<ComponentLife> gone) {
    std::string url = endpointOf(detector, typeName, componentUri, gone);
    if (!url.empty()) co_return url;
    auto timer = std::make_shared<asio::steady_timer>(detector.executor(), timeout);
    const std::size_t id =
        detector.subscribe([timer, typeName, componentUri, gone](const SkillEvent& e) {
            if (e.kind == SkillEvent::Kind::Added && isA(e.instance, typeName, componentUri) &&
                std::find(gone.begin(), gone.end(),
                          ComponentLife{e.instance.endpointUrl,
                                        e.instance.componentStartTime.ticks}) == gone.end()) {
                timer->cancel();
            }
        });
    co_await timer->async_wait(asio::experimental::as_tuple(asio::use_awaitable));
    detector.unsubscribe(id);
    co_return endpointOf(detector, typeName, componentUri, gone);
}

}  // namespace skillcell::skills
