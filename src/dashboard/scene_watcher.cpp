#include "dashboard/scene_watcher.hpp"

#include <spdlog/spdlog.h>

#include <asio/co_spawn.hpp>
#include <asio/detached.hpp>
#include <asio/post.hpp>
#include <asio/redirect_error.hpp>
#include <asio/use_awaitable.hpp>
#include <variant>

#include "devices/common/frame.hpp"
#include "devices/world/world_nodes.hpp"
#include "ua/address_space/ns0_ids.hpp"

namespace skillcell::dashboard {
namespace {

using namespace std::chrono_literals;

std::array<double, 3> position(const ua::Variant& v) {
    auto frame = devices::frameFromVariant(v);
    if (!frame) return {};
    return {frame->p.x(), frame->p.y(), frame->p.z()};
}

std::string text(const ua::Variant& v) {
    const auto* s = v.get<ua::String>();
    return s != nullptr ? *s : std::string();
}

/// The forward Object children of a node, by browse name.
asio::awaitable<ua::Result<std::vector<std::string>>> children(ua::Client& client,
                                                               ua::NodeId node) {
    auto found = co_await client.browse(std::move(node));
    if (!found) co_return found.status();
    std::vector<std::string> names;
    for (const auto& r : found->references) {
        if (r.isForward && r.nodeClass == ua::NodeClass::Object) names.push_back(r.browseName.name);
    }
    co_return names;
}

}  // namespace

std::shared_ptr<SceneWatcher> SceneWatcher::start(asio::any_io_executor executor, std::string url,
                                                  ua::ClientConfig config, Listener onScene) {
    auto w = std::make_shared<SceneWatcher>(Token{}, executor, std::move(url), std::move(config),
                                            std::move(onScene));
    asio::co_spawn(executor, w->run(), asio::detached);
    return w;
}

SceneWatcher::SceneWatcher(Token, asio::any_io_executor executor, std::string url,
                           ua::ClientConfig config, Listener onScene)
    : executor_(std::move(executor)),
      url_(std::move(url)),
      config_(std::move(config)),
      onScene_(std::move(onScene)),
      wake_(executor_) {}

void SceneWatcher::stop() {
    stopped_ = true;
    onScene_ = nullptr;
    wake_.cancel();
}

void SceneWatcher::changed() {
    if (flushPending_) return;
    flushPending_ = true;
    // After the rest of this publish's notifications: one scene per publish.
    asio::post(executor_, [weak = weak_from_this()] {
        auto self = weak.lock();
        if (!self) return;
        self->flushPending_ = false;
        if (self->onScene_) self->onScene_(self->scene_);
    });
}

asio::awaitable<void> SceneWatcher::run() {
    auto self = shared_from_this();  // alive while this runs
    bool complained = false;
    while (!stopped_) {
        ua::Client client(executor_);
        const std::uint64_t before = connection_;
        ua::StatusCode why = co_await client.connect(url_, config_);
        if (why.isGood()) why = co_await watch(client);
        co_await client.disconnect();
        if (stopped_) break;
        // Said once while the world cannot be reached, and again after each watch it ended.
        const bool watched = connection_ != before;
        if (!complained || watched) {
            spdlog::warn("dashboard: the world model at {}: {} (trying again every 2 s)", url_,
                         ua::statusName(why));
        }
        complained = true;
        wake_.expires_after(2s);
        std::error_code ec;
        co_await wake_.async_wait(asio::redirect_error(asio::use_awaitable, ec));
    }
}

asio::awaitable<ua::StatusCode> SceneWatcher::watch(ua::Client& client) {
    // The world's namespace, then what it holds now.
    auto namespaces = co_await client.readValue(ua::NodeId(ua::ns0::Server_NamespaceArray));
    if (!namespaces) co_return namespaces.status();
    std::optional<std::uint16_t> ns;
    const auto& uris = namespaces->elements();
    for (std::size_t i = 0; i < uris.size(); ++i) {
        const auto* uri = std::get_if<ua::String>(&uris[i]);
        if (uri != nullptr && *uri == devices::kWorldNamespaceUri) {
            ns = static_cast<std::uint16_t>(i);
        }
    }
    if (!ns) co_return ua::status::BadNotFound;  // a server, but no world model
    const auto id = [n = *ns](const std::string& path) { return ua::NodeId(n, ua::String(path)); };
    auto objects = co_await children(client, id("World/Objects"));
    if (!objects) co_return objects.status();
    auto docks = co_await children(client, id("World/Docks"));
    if (!docks) co_return docks.status();
    // A world from before rails has no Rails folder: no rails.
    auto rails = co_await children(client, id("World/Rails"));
    if (!rails && rails.status() != ua::StatusCode(ua::status::BadNodeIdUnknown)) {
        co_return rails.status();
    }

    // Nor fuse slots before them.
    auto slots = co_await children(client, id("World/FuseSlots"));
    if (!slots && slots.status() != ua::StatusCode(ua::status::BadNodeIdUnknown)) {
        co_return slots.status();
    }

    SceneView scene;
    for (const auto& o : *objects) {
        auto size = co_await client.readValue(id("World/Objects/" + o + "/Size"));
        if (!size) co_return size.status();
        SceneView::Box box;
        box.id = o;
        const auto& edges = size->elements();
        for (std::size_t i = 0; i < 3 && i < edges.size(); ++i) {
            if (const auto* d = std::get_if<double>(&edges[i])) box.size[i] = *d;
        }
        // Only a terminal block has a Rail.
        auto rail = co_await client.readValue(id("World/Objects/" + o + "/Rail"));
        box.terminalBlock = rail.ok();
        scene.objects.push_back(std::move(box));
    }
    for (const auto& r : rails ? *rails : std::vector<std::string>()) {
        auto pose = co_await client.readValue(id("World/Rails/" + r + "/Pose"));
        if (!pose) co_return pose.status();
        auto length = co_await client.readValue(id("World/Rails/" + r + "/Length"));
        if (!length) co_return length.status();
        const auto frame = devices::frameFromVariant(*pose);
        const double* l = length->get<double>();
        if (!frame || l == nullptr) co_return ua::status::BadTypeMismatch;
        const KDL::Vector end = *frame * KDL::Vector(*l, 0, 0);
        scene.rails.push_back(
            {r, {frame->p.x(), frame->p.y(), frame->p.z()}, {end.x(), end.y(), end.z()}});
    }
    for (const auto& f : slots ? *slots : std::vector<std::string>()) {
        auto pose = co_await client.readValue(id("World/FuseSlots/" + f + "/Pose"));
        if (!pose) co_return pose.status();
        scene.fuseSlots.push_back({f, position(*pose), {}});
    }
    for (const auto& d : *docks) {
        auto pose = co_await client.readValue(id("World/Docks/" + d + "/Pose"));
        if (!pose) co_return pose.status();
        scene.docks.push_back({d, position(*pose), {}});
    }
    auto robots = co_await children(client, id("World/Robots"));
    if (!robots) co_return robots.status();
    for (const auto& r : *robots) {
        auto base = co_await client.readValue(id("World/Robots/" + r + "/Base"));
        if (!base) co_return base.status();
        scene.robots.push_back({r, position(*base), {}, {}, {}});
    }

    // Everything that moves: read once, so that the first scene is whole, then watched; each
    // callback updates its part of scene_.
    using Update = std::function<void(SceneView&, const ua::Variant&)>;
    std::vector<std::pair<std::string, Update>> watched;
    for (std::size_t i = 0; i < scene.robots.size(); ++i) {
        const std::string path = "World/Robots/" + scene.robots[i].id;
        watched.emplace_back(path + "/FlangePose", [i](SceneView& s, const ua::Variant& v) {
            if (i < s.robots.size()) s.robots[i].flange = position(v);
        });
        watched.emplace_back(path + "/MountedTool", [i](SceneView& s, const ua::Variant& v) {
            if (i < s.robots.size()) s.robots[i].mountedTool = text(v);
        });
        watched.emplace_back(path + "/GraspedObject", [i](SceneView& s, const ua::Variant& v) {
            if (i < s.robots.size()) s.robots[i].graspedObject = text(v);
        });
    }
    for (std::size_t i = 0; i < scene.objects.size(); ++i) {
        watched.emplace_back("World/Objects/" + scene.objects[i].id + "/Pose",
                             [i](SceneView& s, const ua::Variant& v) {
                                 if (i < s.objects.size()) s.objects[i].position = position(v);
                             });
    }
    for (std::size_t i = 0; i < scene.objects.size(); ++i) {
        if (!scene.objects[i].terminalBlock) continue;
        const std::string path = "World/Objects/" + scene.objects[i].id;
        watched.emplace_back(path + "/Rail", [i](SceneView& s, const ua::Variant& v) {
            if (i < s.objects.size()) s.objects[i].rail = text(v);
        });
        watched.emplace_back(path + "/RailPosition", [i](SceneView& s, const ua::Variant& v) {
            const double* d = v.get<double>();
            if (i < s.objects.size()) s.objects[i].railPosition = d != nullptr ? *d : 0;
        });
    }
    for (std::size_t i = 0; i < scene.docks.size(); ++i) {
        watched.emplace_back("World/Docks/" + scene.docks[i].id + "/Tool",
                             [i](SceneView& s, const ua::Variant& v) {
                                 if (i < s.docks.size()) s.docks[i].tool = text(v);
                             });
    }
    for (std::size_t i = 0; i < scene.fuseSlots.size(); ++i) {
        watched.emplace_back("World/FuseSlots/" + scene.fuseSlots[i].id + "/Fuse",
                             [i](SceneView& s, const ua::Variant& v) {
                                 if (i < s.fuseSlots.size()) s.fuseSlots[i].fuse = text(v);
                             });
    }
    for (const auto& [path, update] : watched) {
        auto value = co_await client.readValue(id(path));
        if (!value) co_return value.status();
        update(scene, *value);
    }
    scene_ = scene;
    if (onScene_) onScene_(scene_);

    const std::uint64_t connection = ++connection_;
    lost_ = ua::status::Good;
    const std::weak_ptr<SceneWatcher> weak = weak_from_this();
    ua::Subscription::StatusCallback onStatus = [weak, connection](ua::StatusCode st) {
        auto self = weak.lock();
        if (!self || st.isGood() || self->connection_ != connection) return;
        self->lost_ = st;
        self->wake_.cancel();
    };
    // 50 ms: a moving flange is redrawn twenty times a second at most.
    const ua::SubscriptionSettings settings(50, 60, 20);
    auto subscription = co_await client.createSubscription(settings, std::move(onStatus));
    if (!subscription) co_return subscription.status();
    const std::optional<ua::DataChangeFilter> noFilter;
    for (auto& [path, update] : watched) {
        ua::Subscription::DataChangeCallback onChange =
            [weak, connection, update = std::move(update)](const ua::DataValue& dv) {
                auto self = weak.lock();
                if (!self || self->connection_ != connection || !dv.value) return;
                update(self->scene_, *dv.value);
                self->changed();
            };
        auto item = co_await (*subscription)
                        ->monitorDataChange(id(path), ua::AttributeId::Value, 0, 1, noFilter,
                                            std::move(onChange));
        if (!item) co_return item.status();
    }
    // Until the subscription is lost or the watch stopped.
    while (!stopped_ && lost_.isGood()) {
        wake_.expires_at(asio::steady_timer::time_point::max());
        std::error_code ec;
        co_await wake_.async_wait(asio::redirect_error(asio::use_awaitable, ec));
    }
    co_return stopped_ ? ua::StatusCode(ua::status::Good) : lost_;
}

}  // namespace skillcell::dashboard
