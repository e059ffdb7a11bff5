#include "server_process.hpp"

#include <spdlog/spdlog.h>

#include <asio.hpp>
#include <csignal>
#include <future>
#include <iostream>

#include "skill_report.hpp"
#include "skills/skill_detector.hpp"
#include "skills/skill_server.hpp"
#include "ua/nodeset/embedded_models.hpp"
#include "ua/server/user_database.hpp"

namespace skillcell::apps {

void addServerProcessOptions(CLI::App* cmd, ServerProcessOptions& o) {
    cmd->add_option("--port,-p", o.port, "OPC UA TCP port (0: any free port)")
        ->capture_default_str();
    cmd->add_option("--host", o.host, "address to listen on")->capture_default_str();
    cmd->add_option("--advertised-host", o.advertisedHost,
                    "host name put into endpoint URLs (default: the name the client used)");
    cmd->add_option("--application-uri", o.applicationUri, "the server's ApplicationUri")
        ->capture_default_str();
    cmd->add_option("--pki-dir", o.pkiDir,
                    "PKI directory (own/, trusted/, rejected/, issuers/); the application "
                    "certificate is created there on first start (default: $SKILLCELL_PKI_DIR, "
                    "else ~/.local/share/skillcell/pki/<application URI>)");
    cmd->add_option("--max-sessions", o.maxSessions, "session limit")
        ->check(CLI::Range(1u, 100000u))
        ->capture_default_str();
    cmd->add_option("--max-channels", o.maxChannels, "connection limit")
        ->check(CLI::Range(1u, 100000u))
        ->capture_default_str();
    cmd->add_flag("--insecure", o.insecure,
                  "development only: offer SecurityPolicy None alone and let anonymous users "
                  "do everything (the default offers Basic256Sha256, Aes128_Sha256_RsaOaep and "
                  "Aes256_Sha256_RsaPss with Sign and SignAndEncrypt, and users from --users)");
    cmd->add_flag("--allow-anonymous", o.allowAnonymous,
                  "accept anonymous sessions, with the Observer role (browse, read, subscribe)");
    cmd->add_option("--users", o.usersFile,
                    "user database (`skillcell user add`; default: <pki-dir>/users)");
    addClientUserOptions(cmd, o.client, "--client-");
    cmd->add_flag("--detect", o.detect,
                  "detect the skills of every component discovery finds (this one included) "
                  "and print SKILL ADDED/REMOVED lines on stdout, and SNAPSHOT..END on exit");
}

namespace {

/// While a simulated controller boots, SIGINT and SIGTERM are blocked in every thread and
/// taken by sigtimedwait: a component stopped during its boot exits at once, and cleanly.
class BootSequence {
public:
    explicit BootSequence(const devices::BootProfile& profile) : active_(!profile.empty()) {
        if (!active_) return;
        sigemptyset(&signals_);
        sigaddset(&signals_, SIGINT);
        sigaddset(&signals_, SIGTERM);
        pthread_sigmask(SIG_BLOCK, &signals_, &previous_);
        spdlog::info("boot profile: {} ms until the server announces itself",
                     profile.total().count());
    }
    ~BootSequence() { finish(); }
    BootSequence(const BootSequence&) = delete;
    BootSequence& operator=(const BootSequence&) = delete;

    /// Waits out the stages; false when a signal asked us to stop.
    bool run(const std::vector<devices::BootStage>& stages) {
        for (const auto& stage : stages) {
            spdlog::info("boot: {} ({} ms)", stage.name, stage.duration.count());
            const auto deadline = std::chrono::steady_clock::now() + stage.duration;
            for (;;) {
                const auto left = deadline - std::chrono::steady_clock::now();
                if (left <= std::chrono::nanoseconds::zero()) break;
                const auto ns = std::chrono::duration_cast<std::chrono::nanoseconds>(left).count();
                timespec wait{static_cast<time_t>(ns / 1'000'000'000),
                              static_cast<long>(ns % 1'000'000'000)};
                const int signal = sigtimedwait(&signals_, nullptr, &wait);
                if (signal == SIGINT || signal == SIGTERM) {
                    spdlog::info("signal {} during boot ({}): stopping", signal, stage.name);
                    return false;
                }
            }
        }
        return true;
    }

    /// Signals go back to the server's handlers.
    void finish() {
        if (!active_) return;
        active_ = false;
        pthread_sigmask(SIG_SETMASK, &previous_, nullptr);
    }

private:
    bool active_;
    sigset_t signals_{};
    sigset_t previous_{};
};

/// Endpoints, keys, trust and users from the options; 0, or the exit code after logging.
int configureSecurity(const ServerProcessOptions& options, const ApplicationIdentity& identity,
                      ua::ServerConfig& config) {
    auto& description = config.description;
    auto& security = config.security;
    const auto& pkiDir = identity.pkiDirectory();
    if (options.insecure) {
        spdlog::warn("--insecure: SecurityPolicy None only, anonymous users may do everything");
        description.securityEndpoints = {
            {std::string(ua::kSecurityPolicyNoneUri), ua::MessageSecurityMode::None}};
        description.userTokenPolicies = {ua::ServerDescription::anonymousTokenPolicy()};
        security.allowAnonymous = true;
        security.anonymousRoles = ua::RoleSet{ua::Role::Anonymous, ua::Role::Admin};
        return 0;
    }
    security.privateKey = identity.privateKey();
    // ECC_nistP256 beside the RSA policies, with the second certificate (under a cell CA):
    // the cell's components choose it among themselves (an ECDSA handshake costs half an RSA
    // one), clients without ECC (node-opcua, UaExpert) keep the RSA endpoints.
    std::vector<ua::crypto::AsymmetricKey::Kind> keyKinds{ua::crypto::AsymmetricKey::Kind::Rsa};
    if (identity.eccPrivateKey().valid()) {
        description.eccCertificate = identity.eccCertificate().der;
        security.eccPrivateKey = identity.eccPrivateKey();
        keyKinds.push_back(identity.eccPrivateKey().kind());
    }
    // The validator reloads trusted/ when it changes: `skillcell pki trust` takes effect
    // on the next connection, without a restart.
    security.validateCertificate = identity.clientCertificateCheck();
    description.securityEndpoints = ua::allSecurityEndpoints(false, keyKinds);

    const auto usersFile =
        options.usersFile.empty() ? pkiDir / "users" : std::filesystem::path(options.usersFile);
    std::string error;
    auto users = ua::UserDatabase::load(usersFile, &error);
    if (!users) {
        spdlog::critical("user database: {}", error);
        return 1;
    }
    if (users->users().empty() && !options.allowAnonymous) {
        spdlog::warn(
            "no users in {} and anonymous users refused: nobody can open a session "
            "(add one with `skillcell user add NAME --role Operator --users {}`)",
            usersFile.string(), usersFile.string());
    }
    security.users = std::make_shared<ua::UserDatabase>(std::move(*users));
    description.userTokenPolicies.clear();
    if (options.allowAnonymous) {
        description.userTokenPolicies.push_back(ua::ServerDescription::anonymousTokenPolicy());
    }
    ua::UserTokenPolicy password;
    password.policyId = std::string(ua::kUserNamePolicyId);
    password.tokenType = ua::UserTokenType::UserName;
    description.userTokenPolicies.push_back(password);
    ua::UserTokenPolicy x509;
    x509.policyId = std::string(ua::kCertificatePolicyId);
    x509.tokenType = ua::UserTokenType::Certificate;
    description.userTokenPolicies.push_back(x509);
    security.allowAnonymous = options.allowAnonymous;
    security.anonymousRoles = ua::RoleSet{ua::Role::Anonymous, ua::Role::Observer};
    spdlog::info("security: {} endpoints, users from {}, anonymous {}",
                 description.securityEndpoints.size(), usersFile.string(),
                 options.allowAnonymous ? "as Observer" : "refused");
    return 0;
}

}  // namespace

int runServerProcess(const ServerProcessOptions& options, const PopulateServer& populate,
                     const StartEarly& startEarly) {
    BootSequence boot(options.boot);  // before any thread starts: they inherit the mask
    if (!boot.run(options.boot.powerOn)) return 0;
    asio::io_context io{1};  // one thread runs it: no scheduler locking needed
    ua::ServerConfig config;
    config.bindAddress = options.host;
    config.description.port = options.port;
    config.description.applicationUri = options.applicationUri;
    config.description.applicationName = options.applicationName;
    config.description.applicationType = options.applicationType;
    if (!options.advertisedHost.empty()) {
        config.description.advertisedHost = options.advertisedHost;
    } else if (options.host != "0.0.0.0" && options.host != "::") {
        config.description.advertisedHost = options.host;
    }
    config.limits.maxSessions = options.maxSessions;
    config.limits.maxChannels = options.maxChannels;

    // Namespace 0 (2.6 ms of a start) and the skills' models (2.7 ms for a gripper's, 8 ms for
    // an arm's) load on a thread of their own while this one reads the certificates, keys
    // and users (2.5 ms) and the component connects to what it needs (a device's world link,
    // 5 ms): a plugged component is READY sooner when a core is free, as one mostly is before
    // it has announced itself.
    auto namespace0 = std::async(std::launch::async | std::launch::deferred,
                                 [uri = options.applicationUri, models = options.skillModels] {
                                     ua::AddressSpace as(uri);
                                     auto loaded = ua::loadBaseNodeSet(as);
                                     if (!loaded.ok()) {
                                         loaded.error = "namespace 0: " + loaded.error;
                                     } else if (!models.empty()) {
                                         loaded = skills::SkillServer::loadModels(as, models);
                                         if (!loaded.ok())
                                             loaded.error = "the skills' models: " + loaded.error;
                                     }
                                     return std::make_pair(std::move(as), std::move(loaded));
                                 });
    std::string error;
    auto identity = ApplicationIdentity::load(options.pkiDir, options.applicationUri,
                                              options.applicationName, &error);
    if (!identity) {
        spdlog::critical("{}", error);
        return 1;
    }
    config.description.certificate = identity->certificate().der;
    auto clientSecurity =
        componentClientSecurity(*identity, options.client, options.insecure, &error);
    if (!clientSecurity) {
        spdlog::critical("{}", error);
        return 1;
    }
    // What the component needs of other servers is fetched beside the loading of its models.
    if (startEarly) startEarly(*clientSecurity, options.applicationUri);
    if (const int s = configureSecurity(options, *identity, config); s != 0) return s;

    auto [addressSpace, loaded] = namespace0.get();
    if (!loaded.ok()) {
        spdlog::critical("cannot build the server: {}", loaded.error);
        return 1;
    }
    auto server = ua::Server::create(io, config, std::move(addressSpace), &error);
    if (!server) {
        spdlog::critical("cannot build the server: {}", error);
        return 1;
    }
    // The cell's skills, from what discovery finds (and what registers with our LDS); the
    // component may use them, so it exists before the component does.
    std::shared_ptr<skills::SkillDetector> detector;
    if (options.detect || options.usesDetector) {
        skills::SkillDetectorConfig detectorConfig;
        detectorConfig.applicationUri = options.applicationUri;
        detectorConfig.security = *clientSecurity;
        detector = skills::SkillDetector::create(io.get_executor(), detectorConfig);
    }
    ComponentContent content;  // after the server: destroyed before it
    if (populate) {
        const ComponentContext context{*server,
                                       io,
                                       *clientSecurity,
                                       options.applicationUri,
                                       detector,
                                       *identity,
                                       options.insecure ? nullptr : config.security.users};
        auto populated = populate(context);
        if (!populated) {
            spdlog::critical("cannot add the component's nodes: {}",
                             ua::statusName(populated.status()));
            return 1;
        }
        content = std::move(*populated);
    }
    if (!boot.run(options.boot.applicationStart)) return 0;
    boot.finish();
    auto port = server->listen();
    if (!port) return 1;  // listen() logged why

    std::unique_ptr<ComponentDiscovery> discovery;
    if (options.discovery.enabled || options.isLds) {
        discovery = ComponentDiscovery::start(io, *server, *port, options.host, options.discovery,
                                              options.isLds, *clientSecurity, &error);
        if (!discovery && options.isLds) {
            spdlog::critical("LDS-ME: {}", error);
            return 1;
        }
        if (!discovery) {
            // Still a working server, reachable by its address; say loudly what is missing.
            spdlog::error("discovery is off: {} (--no-discovery silences this)", error);
        }
    }

    std::shared_ptr<ua::lds::ServerWatcher> detectorWatcher;
    if (detector && discovery) {
        if (options.detect) {
            detector->subscribe(
                [](const skills::SkillEvent& e) { printSkillEvent(std::cout, e, false); });
        }
        detectorWatcher = skills::attachMdns(
            detector, discovery->responder(),
            options.detectsItself || options.detect ? std::string() : discovery->mdnsName());
        if (discovery->lds()) skills::attachLds(detector, *discovery->lds());
    } else if (detector) {
        spdlog::error("{} needs discovery: no skills will be detected",
                      options.detect ? "--detect" : "this component");
    }

    asio::signal_set signals(io, SIGINT, SIGTERM);
    signals.async_wait([&](const asio::error_code& ec, int signal) {
        if (ec) return;
        spdlog::info("signal {}: shutting down", signal);
        asio::co_spawn(
            io,
            [&]() -> asio::awaitable<void> {
                if (detector) {
                    if (options.detect) {
                        printSkillSnapshot(std::cout, detector->instances(), false);
                    }
                    if (detectorWatcher) detectorWatcher->stop();
                    co_await detector->shutdown(std::chrono::seconds(1));
                }
                if (discovery) co_await discovery->stop();
                server->stop();
                io.stop();
            },
            asio::detached);
    });
    std::cout << "READY opc.tcp://" << server->config().description.advertisedHost << ":" << *port
              << std::endl;  // flushed: scripts wait for this line
    // After the announcement, while it travels and the peers connect: what their first
    // handshake would wait for otherwise.
    if (!options.insecure) asio::post(io, [&identity] { identity->prepareForPeers(); });
    io.run();
    return 0;
}

}  // namespace skillcell::apps
