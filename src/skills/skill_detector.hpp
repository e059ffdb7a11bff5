#pragma once
// SkillDetector: the skills the cell offers right now, as a map from skill type to the live
// skill instances of that type (ARCHITECTURE.md, "The skill model"; issue 5, item 5).
//
// Sources tell it which servers exist: `appeared(key, application, discoveryUrl)` and
// `gone(key, reason)`, where `key` names a server within its source ("mdns:<name>",
// "lds:<serverUri>"). attachMdns() and attachLds() below are the adapters for multicast
// discovery (ServerWatcher) and for the registrations of an LDS hosted in this process;
// tests feed the detector directly.
//
// For each server (a *component*, identified by its application URI, so that two sources
// reporting the same server give one component) the detector:
//  - connects with a session (connect timeout 2 s), reads ServerStatus.StartTime and
//    browses the whole address space for objects whose type is SkillType or a subtype of
//    it, resolving the types through the server's own hierarchy (RemoteSkillBrowser);
//  - keeps the connection, with a subscription that serves as keep-alive and watches
//    StartTime: a lost connection or a silent server removes the component's skills (then it
//    retries, backing off, while a source still lists the server); a new StartTime (a
//    restarted server) re-browses;
//  - removes the component's skills when the last source that listed it says it is gone
//    (mDNS goodbye or expiry, LDS unregistration or expiry).
// Seen again by a source (a new announcement, a new registration), a component is checked:
// a new StartTime or a new address re-browses it.
//
// Lookup is by any type of a skill's chain, from its own type up to SkillType: find() of
// MoveSkillType returns the CartesianLinearMoveSkillType instances too. Types are
// GlobalNodeIds (namespace URI + identifier), the same for every server.
//
// Threading: the detector and every connection it makes run on the executor given to
// create(), which must not run handlers concurrently (one thread or a strand).
// appeared/gone/stop, subscribe/unsubscribe must be called there, and listeners are called
// there. The queries (find, instances, components) may be called from any thread: the map
// they read is guarded by a mutex. The detector starts no thread; its coroutines hold it
// alive until they end, which stop() brings about promptly.
#include <asio/any_io_executor.hpp>
#include <asio/awaitable.hpp>
#include <asio/steady_timer.hpp>
#include <chrono>
#include <deque>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "skills/remote_skill_browser.hpp"
#include "ua/discovery/local_discovery_server.hpp"
#include "ua/discovery/mdns_responder.hpp"
#include "ua/discovery/server_watcher.hpp"

namespace skillcell::skills {

/// A skill instance offered by a live component.
struct SkillInstance : RemoteSkill {
    std::string componentUri;         // the component's application URI
    std::string endpointUrl;          // where the detector reached it
    ua::DateTime componentStartTime;  // its ServerStatus.StartTime
    friend bool operator==(const SkillInstance&, const SkillInstance&) = default;

    /// The instance's own type (the first of `types`).
    [[nodiscard]] const SkillTypeRef& type() const { return types.front(); }
    /// True if `type` is its type or one of its supertypes.
    [[nodiscard]] bool isA(const GlobalNodeId& type) const;
};

/// Why a source says a server is gone.
enum class GoneReason : std::uint8_t {
    Goodbye,       // mDNS goodbye (a graceful stop)
    Expired,       // mDNS records or an LDS registration expired
    Unregistered,  // it unregistered from the LDS
};

/// Why skills were removed.
enum class RemovalReason : std::uint8_t {
    Goodbye,
    Expired,
    Unregistered,
    Disconnected,  // the connection to the component was lost
    Timeout,       // it stopped answering, or did not answer within the connect timeout
    Restarted,     // it restarted (new StartTime) or moved: re-browsed, this one is no more
};
[[nodiscard]] std::string_view toString(RemovalReason reason);

struct SkillEvent {
    enum class Kind : std::uint8_t { Added, Removed };
    Kind kind = Kind::Added;
    SkillInstance instance;
    RemovalReason reason = RemovalReason::Disconnected;  // for Removed
};

/// What the detector knows of a component (for diagnostics and tests).
struct ComponentStatus {
    /// Connected: browsed, and its liveness watched (keep-alive subscription, or polling of
    /// StartTime where the server offers no subscriptions).
    /// Waiting: for a turn to connect (SkillDetectorConfig::maxConcurrentConnects).
    enum class State : std::uint8_t { Waiting, Connecting, Connected, Unreachable };
    std::string id;  // application URI, or "key:<source key>" when none was given
    std::string endpointUrl;
    State state = State::Connecting;
    ua::StatusCode lastError;  // why it is Unreachable
    ua::DateTime startTime;    // when Connected
    std::size_t skills = 0;
    std::uint64_t browses = 0;  // complete browses of it so far
};

/// A change of what the detector knows of a component. `forgotten`: no source lists it any
/// more (then `reason` says why: goodbye, expiry, unregistration).
struct ComponentEvent {
    ComponentStatus status;
    bool forgotten = false;
    RemovalReason reason = RemovalReason::Disconnected;
};

struct SkillDetectorConfig {
    SkillDetectorConfig() = default;  // not an aggregate: see ua::ClientConfig
    /// Resolve, TCP connect and Hello/Acknowledge.
    std::chrono::milliseconds connectTimeout{2000};
    /// Each request of the session and the browse.
    std::chrono::milliseconds requestTimeout{5000};
    /// A connected component is heard from at least this often (subscription keep-alive);
    /// silence for 1.5 times as long counts as a timeout. Only a host that vanishes without a
    /// word (a cable pulled) waits for it: a stopped or killed process closes its connection.
    /// Each keep-alive costs about three packets, for every component and every detector.
    std::chrono::milliseconds keepAlivePeriod{5000};
    /// How often a component's StartTime is sampled and published when it changes (a
    /// gateway whose backend restarted without closing the connection); at most
    /// keepAlivePeriod.
    std::chrono::milliseconds publishingInterval{1000};
    /// First delay before connecting again to a component a source still lists; doubles
    /// up to maxRetryDelay.
    std::chrono::milliseconds retryDelay{250};
    std::chrono::milliseconds maxRetryDelay{5000};
    /// How many components are connected to and browsed at once; the others wait their turn,
    /// oldest first. A detector that finds hundreds at once (a cold start) opens as many
    /// secure channels as the cell's two cores can handshake, instead of all of them timing
    /// out together. A component that never answers holds its turn only until its connect
    /// times out.
    std::size_t maxConcurrentConnects = 32;
    RemoteBrowseLimits limits;
    std::string applicationUri = "urn:skillcell:skill-detector";
    /// How the detector connects and whom it acts for (browsing and subscribing need no
    /// more than the Observer role).
    ua::ClientSecurity security;
};

class SkillDetector : public std::enable_shared_from_this<SkillDetector> {
public:
    using Listener = std::function<void(const SkillEvent&)>;
    using ComponentListener = std::function<void(const ComponentEvent&)>;

    [[nodiscard]] static std::shared_ptr<SkillDetector> create(asio::any_io_executor executor,
                                                               SkillDetectorConfig config = {});
    ~SkillDetector();
    SkillDetector(const SkillDetector&) = delete;
    SkillDetector& operator=(const SkillDetector&) = delete;

    [[nodiscard]] const asio::any_io_executor& executor() const { return executor_; }

    // --- Sources (on the executor) ---------------------------------------------------------
    /// A source lists the server `key` at `discoveryUrl`. A first sighting connects and
    /// browses; another one checks StartTime and address, re-browsing if they changed.
    /// `endpoints`: what the source learnt from GetEndpoints there, if it asked; the next
    /// connection to that URL chooses among them rather than asking again.
    void appeared(const std::string& key, const ua::ApplicationDescription& application,
                  const std::string& discoveryUrl,
                  std::vector<ua::EndpointDescription> endpoints = {});
    /// The source no longer lists `key`; a component no source lists any more loses its
    /// skills at once.
    void gone(const std::string& key, GoneReason reason);
    /// Forgets every component and listener and ends every connection (no events).
    void stop();
    /// stop(), then waits until every connection has ended: idle ones close their sessions
    /// politely; whatever is still going after `grace` is cut. A process that stops its
    /// io_context must await this first: a request in flight holds its connection (and the
    /// coroutine waiting for the reply) in a cycle that only the reply or a cut breaks.
    asio::awaitable<void> shutdown(std::chrono::milliseconds grace);

    // --- Listeners (on the executor) -------------------------------------------------------
    /// Calls `listener` with Added for every instance known now, then with every change.
    std::size_t subscribe(Listener listener);
    void unsubscribe(std::size_t id);
    /// Calls `listener` with the status of every component known now, then with every change
    /// of one (connecting, connected, unreachable, forgotten), components without skills too.
    /// Unsubscribed by unsubscribe().
    std::size_t subscribeComponents(ComponentListener listener);

    // --- Queries (any thread) --------------------------------------------------------------
    /// The instances whose type is `type` or a subtype of it.
    [[nodiscard]] std::vector<SkillInstance> find(const GlobalNodeId& type) const;
    [[nodiscard]] std::vector<SkillInstance> instances() const;
    /// The same list, shared and immutable: made once per change of the skills, not once per
    /// call (a MES with many orders asks for it at every step of each).
    [[nodiscard]] std::shared_ptr<const std::vector<SkillInstance>> snapshot() const;
    [[nodiscard]] std::vector<ComponentStatus> components() const;

private:
    struct Watch;  // a component: its sightings, its connection and the coroutine keeping it
    using InstanceKey = std::pair<std::string, ua::NodeId>;  // component id, skill node

    SkillDetector(asio::any_io_executor executor, SkillDetectorConfig config);

    asio::awaitable<void> run(std::shared_ptr<Watch> watch);
    /// One connection's life after connect(): browse, then watch it. Returns why it ended
    /// (Good when the watch was ended from outside).
    /// A turn taken (takeTurn), given back once: by giveBack(), or when it goes.
    class Turn {
    public:
        explicit Turn(SkillDetector& detector) : detector_(detector) {}
        ~Turn() { giveBack(); }
        Turn(const Turn&) = delete;
        Turn& operator=(const Turn&) = delete;
        void giveBack() {
            if (!held_) return;
            held_ = false;
            detector_.giveTurn();
        }

    private:
        SkillDetector& detector_;
        bool held_ = true;
    };
    asio::awaitable<ua::StatusCode> serve(const std::shared_ptr<Watch>& watch, Turn& turn);
    asio::awaitable<ua::StatusCode> browseInto(const std::shared_ptr<Watch>& watch,
                                               ua::DateTime startTime,
                                               std::vector<std::string> namespaces,
                                               RemovalReason reason);
    void endWatch(Watch& watch);
    /// A turn to connect and browse: at once while fewer than maxConcurrentConnects are
    /// taken, else when one is given back. False when the watch ended while it waited.
    asio::awaitable<bool> takeTurn(Watch& watch);
    void giveTurn();
    void dropSighting(const std::string& key, RemovalReason reason);

    /// Makes the component's instances `next` (executor only); notifies the difference.
    void replaceSkills(const std::string& componentId, std::vector<SkillInstance> next,
                       RemovalReason reason);
    void setStatus(const std::string& componentId, const std::function<void(ComponentStatus&)>& f);
    void notify(const std::vector<SkillEvent>& events);
    void notifyComponent(const ComponentEvent& event);

    asio::any_io_executor executor_;
    SkillDetectorConfig config_;
    bool stopped_ = false;

    // Executor only.
    std::size_t running_ = 0;                    // run() coroutines not yet ended
    std::optional<asio::steady_timer> drained_;  // cancelled when running_ drops to 0
    struct TurnWaiter {
        explicit TurnWaiter(const asio::any_io_executor& executor) : timer(executor) {}
        asio::steady_timer timer;  // cancelled: the turn is given (granted) or the watch ended
        bool granted = false;
    };
    std::size_t turnsTaken_ = 0;
    std::deque<std::shared_ptr<TurnWaiter>> turnQueue_;         // oldest first
    std::map<std::string, std::shared_ptr<Watch>> components_;  // by component id
    std::map<std::string, std::string> keys_;                   // source key -> component id
    std::map<std::size_t, Listener> listeners_;
    std::map<std::size_t, ComponentListener> componentListeners_;
    std::size_t nextListener_ = 1;

    // Guarded by mutex_: written on the executor, read from anywhere.
    mutable std::mutex mutex_;
    std::map<InstanceKey, SkillInstance> instances_;
    /// instances_ as snapshot() gives it; reset by every change, made again when asked for.
    mutable std::shared_ptr<const std::vector<SkillInstance>> snapshot_;
    std::map<GlobalNodeId, std::set<InstanceKey>> byType_;
    std::map<std::string, ComponentStatus> status_;
};

/// Feeds `detector` from multicast discovery: a ServerWatcher on `responder` whose
/// "announced" and "gone" become appeared("mdns:<name>") and gone(). The instance named
/// `itself` (the one this process announces on `responder`; empty: none) is left out: a
/// composite uses other components' skills, and connecting to itself cost its one thread both
/// ends of a secured handshake while the cell's clients handshake with it. Returns the
/// started watcher; stop it before the responder shuts down. Call on the detector's executor.
[[nodiscard]] std::shared_ptr<ua::lds::ServerWatcher> attachMdns(
    const std::shared_ptr<SkillDetector>& detector,
    std::shared_ptr<ua::mdns::MdnsResponder> responder, const std::string& itself = {});

/// Feeds `detector` from the registrations of an LDS in this process (its registration
/// observer; the servers registered already are reported at once): appeared("lds:<uri>"),
/// gone() on unregistration and expiry. Call on the detector's (= the LDS's) executor.
void attachLds(const std::shared_ptr<SkillDetector>& detector, ua::lds::LocalDiscoveryServer& lds);

}  // namespace skillcell::skills
