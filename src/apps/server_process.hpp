#pragma once
// The life of a server process, shared by `skillcell server` and `skillcell lds` (and later
// every component): build the server, let the caller add its nodes, listen, announce and
// register (ComponentDiscovery), print "READY <url>", optionally detect the cell's skills
// (--detect), and on SIGINT/SIGTERM unregister, send the mDNS goodbye and stop.
#include <CLI/CLI.hpp>
#include <functional>
#include <string>
#include <string_view>
#include <vector>

#include "application_identity.hpp"
#include "client_security_options.hpp"
#include "component_discovery.hpp"
#include "devices/common/boot_profile.hpp"
#include "skills/skill_detector.hpp"
#include "ua/server/server.hpp"

namespace skillcell::apps {

struct ServerProcessOptions {
    std::uint16_t port = 4840;
    std::string host = "0.0.0.0";
    std::string advertisedHost;
    std::string applicationUri = "urn:skillcell:server";
    std::string applicationName = "skillcell server";
    ua::ApplicationType applicationType = ua::ApplicationType::Server;
    std::uint32_t maxSessions = 100;
    std::uint32_t maxChannels = 100;
    DiscoveryOptions discovery;
    bool isLds = false;
    std::string pkiDir;   // empty: ua::pki::defaultPkiDirectory()
    bool detect = false;  // run a SkillDetector and print its SKILL lines (skill_report.hpp)
    /// The component uses the cell's skills (a composite): it gets a SkillDetector fed by
    /// discovery in its ComponentContext.
    bool usesDetector = false;
    /// Whether that detector also finds this component's own skills. A composite's does not
    /// (it uses the others'), unless --detect asks for every skill: see skills::attachMdns.
    bool detectsItself = true;
    /// Security (docs/security.md): secured endpoints only and no anonymous users unless
    /// told otherwise. --insecure is for development: SecurityPolicy None only, anonymous
    /// users with every right, exactly what a server without security would do.
    bool insecure = false;
    bool allowAnonymous = false;  // anonymous sessions as Observer
    std::string usersFile;        // empty: <pki-dir>/users
    /// Whom the component acts for when it connects to others (detection, the world model,
    /// skills it uses); its certificate is the server's.
    ClientUserOptions client;
    /// A simulated controller's start (devices/common/boot_profile.hpp); empty: at once.
    devices::BootProfile boot;
    /// The companion models the component's skills are of (its component class's
    /// skillModels()): loaded with namespace 0 on a thread of its own while the component
    /// reads its identity and connects to what it needs, not after. Empty: none (a component
    /// without skills, or one that loads them itself).
    std::vector<std::string_view> skillModels;
};

/// --port, --host, --advertised-host, --application-uri, --pki-dir, --max-sessions,
/// --max-channels, --detect, --insecure, --allow-anonymous, --users, --client-user,
/// --client-password-file, --client-user-certificate.
void addServerProcessOptions(CLI::App* cmd, ServerProcessOptions& options);

/// What a component adds to its server (skills, device adapters): kept alive while the
/// server runs and destroyed before the server and its io_context. May be null.
using ComponentContent = std::shared_ptr<void>;
/// What a component has at hand while it adds its nodes.
struct ComponentContext {
    ua::Server& server;
    asio::io_context& io;
    /// How the component connects to other components: copy it into every ClientConfig.
    const ua::ClientSecurity& clientSecurity;
    const std::string& applicationUri;
    /// The cell's skills as discovery finds them (ServerProcessOptions::usesDetector or
    /// --detect), else null. Its sources attach once the server listens.
    std::shared_ptr<skills::SkillDetector> detector;
    /// Its certificate and trust list, for services beside OPC UA (the KB's HTTPS).
    const ApplicationIdentity& identity;
    /// The server's users (--users); null with --insecure, where there are none.
    std::shared_ptr<const ua::UserAuthenticator> users;
};
/// Adds the component's nodes; runs on the io_context's thread before the server listens.
using PopulateServer = std::function<ua::Result<ComponentContent>(const ComponentContext&)>;

/// Called once the component knows how it connects to others (its certificate is loaded) and
/// before its server loads its models: where it starts, on a thread of its own, what it needs
/// of other servers before it can add its nodes (a device's link to the world model:
/// WorldConnection), so that its start takes the longer of the two, not their sum.
using StartEarly =
    std::function<void(const ua::ClientSecurity& security, const std::string& applicationUri)>;

/// Runs until a signal. `populate` adds the component's nodes (may be empty).
int runServerProcess(const ServerProcessOptions& options, const PopulateServer& populate,
                     const StartEarly& startEarly = {});

}  // namespace skillcell::apps
