#include "cell_runtime.hpp"

#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>

#include "cell/component_uris.hpp"
#include "cell/device_arguments.hpp"
#include "private_network.hpp"
#include "process/child_process.hpp"
#include "program.hpp"
#include "ua/crypto/primitives.hpp"
#include "ua/pki/certificate_authority.hpp"
#include "ua/server/user_database.hpp"

namespace skillcell::apps {

namespace fs = std::filesystem;
using namespace std::chrono_literals;

namespace {

/// A password for a generated user: 96 random bits, in hex.
std::string newPassword() {
    static constexpr char kHex[] = "0123456789abcdef";
    std::string out;
    for (const auto b : ua::crypto::randomBytes(12)) {
        out += kHex[b >> 4];
        out += kHex[b & 0xf];
    }
    return out;
}

/// A TCP port free right now on `host`: the kernel's choice for a socket bound to port 0.
/// In the cell's private network namespace nobody else takes it before the component does.
std::uint16_t freeTcpPort() {
    const process::UniqueFd fd(::socket(AF_INET, SOCK_STREAM, 0));
    sockaddr_in a{};
    a.sin_family = AF_INET;
    a.sin_addr.s_addr = htonl(INADDR_ANY);
    socklen_t length = sizeof a;
    if (!fd.valid() || ::bind(fd.get(), reinterpret_cast<sockaddr*>(&a), sizeof a) != 0 ||
        ::getsockname(fd.get(), reinterpret_cast<sockaddr*>(&a), &length) != 0) {
        return 0;  // the component takes any free port, and is not kept
    }
    return ntohs(a.sin_port);
}

struct GeneratedUser {
    const char* name;
    ua::Role role;
    const char* roleName;
};
// The people's users. The components are users too, but by their certificates
// (componentUser()): passwords are for people.
constexpr GeneratedUser kGeneratedUsers[] = {{"operator", ua::Role::Operator, "Operator"},
                                             {"engineer", ua::Role::Engineer, "Engineer"},
                                             {"observer", ua::Role::Observer, "Observer"}};

/// Whether a component opens sessions on others (and so needs a user): all but the
/// discovery server and the world, which only serve.
bool actsAsCell(const std::string& name) {
    return name != "lds" && name != "world";
}

}  // namespace

kb::Expected<CellHosts> enterCellNetwork(const cell::CellFile& cell) {
    if (cell.network.kind != cell::Network::Kind::PrivateNamespace) return CellHosts{};
    const auto why = enterPrivateNetwork();
    if (!why.empty() && !multicastOnlyOnLoopback()) {
        return kb::Error{cell.path.string() +
                         " asks for a private network namespace (network.kind = \"private\"), "
                         "so that the cell's mDNS stays off your network, and " +
                         why + "; or use network.kind = \"host\""};
    }
    return CellHosts::create(cell.hostNames());
}

std::string skillcellProgram() {
    std::error_code ec;
    const auto path = fs::read_symlink("/proc/self/exe", ec);
    return ec ? std::string() : path.string();
}

std::string programFor(const std::string& skillcell, const std::vector<std::string>& args) {
    const auto components = componentSubcommands();
    if (args.empty() || std::none_of(components.begin(), components.end(),
                                     [&](const Subcommand& s) { return s.name == args.front(); })) {
        return skillcell;
    }
    const fs::path component = fs::path(skillcell).parent_path() / "skillcell-component";
    return ::access(component.c_str(), X_OK) == 0 ? component.string() : skillcell;
}

CellRuntime::CellRuntime(const cell::CellFile& cell, const WorkDirectory& work,
                         std::string skillcell, CellRuntimeOptions options)
    : cell_(cell), work_(work), skillcell_(std::move(skillcell)), options_(std::move(options)) {}

fs::path CellRuntime::caDir() const {
    return cell_.security.ca.empty() ? dir() / "ca" : cell_.security.ca;
}

fs::path CellRuntime::passwordFile(const std::string& user) const {
    // Given users: their passwords beside their database; generated: in the work directory.
    const fs::path folder =
        cell_.security.users.empty() ? dir() : cell_.security.users.parent_path();
    return folder / (user + ".pw");
}

std::vector<std::pair<std::string, std::string>> CellRuntime::environment() const {
    if (!secure()) return {};
    return {{"SKILLCELL_CA_DIR", caDir().string()}};
}

std::string CellRuntime::endpoint(const std::string& name) const {
    const auto it = endpoints_.find(name);
    return it == endpoints_.end() ? std::string() : it->second;
}

std::string CellRuntime::sparqlUrl() const {
    if (cell_.kb && !cell_.kb->sparqlUrl.empty()) return cell_.kb->sparqlUrl;
    return kbSparql_;
}

std::vector<Credential> CellRuntime::credentials() const {
    return credentials_;
}

double CellRuntime::speed() const {
    if (options_.speed > 0) return options_.speed;
    return cell_.robots.empty() ? 1.0 : cell_.robots.front().speed;
}

std::string CellRuntime::changerRobot(const std::string& changer) const {
    // A changer's robot is resolved when the cell file is read; the shelf's tools (the demo's
    // --swap) name none: they are for the cell's one changer.
    const cell::ToolChanger* c = cell_.toolChanger(changer);
    if (c == nullptr && !cell_.toolChangers.empty()) c = &cell_.toolChangers.front();
    return c == nullptr ? std::string() : c->robot;
}

std::string CellRuntime::applicationUri(const std::string& name) const {
    if (name == "lds" && cell_.lds) return std::string(cell::kLdsUri);
    if (name == "kb" && cell_.kb) return std::string(cell::kKbUri);
    if (name == "mes" && cell_.mes) return std::string(cell::kMesUri);
    if (name == "dashboard" && cell_.dashboard) return std::string(cell::kDashboardUri);
    if (name == "world") return std::string(cell::kWorldUri);
    if (cell_.toolChanger(name) != nullptr) {
        return cell::componentUri(cell::kToolChangerUri, name, cell::ToolChanger{}.name);
    }
    if (cell_.pickAndPlace(name) != nullptr) {
        return cell::componentUri(cell::kPickAndPlaceUri, name, cell::PickAndPlace{}.name);
    }
    for (const auto& r : cell_.robots) {
        if (r.name == name) {
            return cell::componentUri(r.model == "iiwa" ? cell::kIiwaUri : cell::kUr5Uri, name,
                                      r.model);
        }
    }
    return {};
}

std::vector<std::string> CellRuntime::components() const {
    return cell_.componentNames();
}

bool CellRuntime::prepare(std::string* error) {
    std::error_code ec;
    if (secure()) {
        // Generated once, then kept; a folder that is there but holds no CA is an error, not
        // something to replace.
        if (cell_.security.ca.empty() && !fs::exists(dir() / "ca", ec)) {
            ua::pki::CaOptions ca;
            ca.name = "skillcell cell " + cell_.name + " CA";
            if (!ua::pki::createCertificateAuthority(dir() / "ca", ca, error)) return false;
        } else if (!ua::pki::loadCertificateAuthority(caDir(), error)) {
            *error = "the cell CA " + caDir().string() + ": " + *error;
            return false;
        }
        if (!prepareUsers(error)) return false;
    }
    // Commissioning: each component gets its certificate before it first starts, else its
    // first start would make an RSA key and count that in its detection time.
    std::vector<std::pair<std::string, std::string>> all;
    for (const auto& name : components()) all.emplace_back(name, applicationUri(name));
    // Each changer's adapters, of any model: the demo's --swap powers another one.
    for (const auto& c : cell_.toolChangers) {
        for (const auto& m : cell::adapterModelTable()) {
            auto adapter = cell::adapterComponent(m, c.name);
            all.emplace_back(std::move(adapter.name), std::move(adapter.applicationUri));
        }
    }
    all.emplace_back("operator", "urn:skillcell:operator");
    // name, its RSA and ECC certificates
    std::vector<std::pair<std::string, std::vector<ua::ByteString>>> clients;
    const auto certificatesOf = [](const ApplicationIdentity& identity) {
        std::vector<ua::ByteString> out{identity.certificate().der};
        if (!identity.eccCertificate().der.empty()) out.push_back(identity.eccCertificate().der);
        return out;
    };
    for (const auto& [name, uri] : all) {
        auto identity = commission(name, uri, error);
        if (!identity) {
            *error = "the certificate of " + name + ": " + *error;
            return false;
        }
        if (name != "operator" && actsAsCell(name)) {
            clients.emplace_back(name, certificatesOf(*identity));
        }
        if (name == "world") {
            // The one its clients' links choose: ECC when it has one (ClientSecurity).
            worldCertificate_ = identity->eccCertificate().der.empty()
                                    ? identity->certificate().certificateFile
                                    : identity->eccCertificate().certificateFile;
        }
    }
    identity_ = commission(options_.selfName, selfUri(), error);
    if (!identity_) return false;
    clients.emplace_back(options_.selfName, certificatesOf(*identity_));
    return !certificateUsers() || addComponentUsers(clients, error);
}

bool CellRuntime::certificateUsers() const {
    return secure() && cell_.security.users.empty();
}

bool CellRuntime::addComponentUsers(
    const std::vector<std::pair<std::string, std::vector<ua::ByteString>>>& clients,
    std::string* error) {
    // Each component is the user "cell-NAME", Operator, known by its certificates'
    // thumbprints (RSA and ECC: its X.509 user token is the certificate of the channel's
    // policy): such a token costs one signature check where a password costs an scrypt hash
    // (tens of milliseconds, on purpose) on every session it opens.
    const fs::path file = dir() / "users";
    auto users = ua::UserDatabase::load(file, error);
    if (!users) return false;
    bool changed = false;
    for (const auto& [name, certificates] : clients) {
        const std::string user = "cell-" + name;
        // A second `cell up` of the same work directory finds them.
        if (std::all_of(certificates.begin(), certificates.end(), [&](const ua::ByteString& c) {
                auto known = users->authenticateCertificate(c);
                return known && known->name == user;
            })) {
            continue;
        }
        if (users->setCertificates(user, ua::RoleSet{ua::Role::Operator}, certificates).isBad()) {
            *error = "cannot make the user " + user + " of its certificate";
            return false;
        }
        changed = true;
    }
    return !changed || users->save(file, error).isGood();
}

ClientUserOptions CellRuntime::componentUser() const {
    ClientUserOptions user;
    if (!secure()) return user;
    if (certificateUsers()) {
        user.applicationCertificate = true;
    } else {
        user.name = "cell";
        user.passwordFile = passwordFile("cell").string();
    }
    return user;
}

bool CellRuntime::prepareUsers(std::string* error) {
    if (!cell_.security.users.empty()) {
        // The cell's own users: the components act as "cell", whose password must be there.
        auto users = ua::UserDatabase::load(cell_.security.users, error);
        if (!users) return false;
        const auto& records = users->users();
        const bool hasCell = std::any_of(records.begin(), records.end(),
                                         [](const ua::UserRecord& u) { return u.name == "cell"; });
        std::error_code ec;
        if (!hasCell || !fs::exists(passwordFile("cell"), ec)) {
            *error = cell_.security.users.string() +
                     ": the components act as the user 'cell' (role Operator), which needs to be "
                     "in this database with its password in " +
                     passwordFile("cell").string();
            return false;
        }
        for (const auto& u : records) {
            if (fs::exists(passwordFile(u.name), ec)) {
                credentials_.push_back({u.name, "", passwordFile(u.name)});
            }
        }
        return true;
    }
    // Generated once, then kept: a second `cell up` of the same work directory finds them.
    const fs::path file = dir() / "users";
    std::error_code ec;
    bool complete = fs::exists(file, ec);
    for (const auto& u : kGeneratedUsers) complete = complete && fs::exists(passwordFile(u.name));
    ua::UserDatabase users;
    if (complete) {
        auto loaded = ua::UserDatabase::load(file, error);
        if (!loaded) return false;
    } else {
        for (const auto& u : kGeneratedUsers) {
            const std::string password = newPassword();
            if (users.setPassword(u.name, ua::RoleSet{u.role}, password).isBad() ||
                !writeSecret(passwordFile(u.name), password)) {
                *error = std::string("cannot create the user ") + u.name;
                return false;
            }
        }
        if (users.save(file, error).isBad()) return false;
    }
    for (const auto& u : kGeneratedUsers) {
        credentials_.push_back({u.name, u.roleName, passwordFile(u.name)});
    }
    return true;
}

std::optional<ApplicationIdentity> CellRuntime::commission(const std::string& name,
                                                           const std::string& uri,
                                                           std::string* error) const {
    const fs::path pki = pkiDir(name);
    std::error_code ec;
    fs::create_directories(pki, ec);
    if (secure() && !fs::exists(pki / "cell-ca", ec)) {
        fs::create_directory_symlink(fs::absolute(caDir(), ec), pki / "cell-ca", ec);
    }
    if (ec) {
        *error = "cannot link " + pki.string() + "/cell-ca: " + ec.message();
        return std::nullopt;
    }
    std::vector<std::string> addresses;
    if (!hostOf(name).empty()) addresses.push_back(addressOf(name));
    auto identity = ApplicationIdentity::load(pki, uri, "skillcell " + name, error, addresses);
    if (!identity) return std::nullopt;
    return std::move(*identity);
}

std::uint16_t CellRuntime::port(const std::string& key) {
    if (!options_.keepPorts) return 0;
    auto [it, inserted] = ports_.try_emplace(key, 0);
    if (it->second == 0) it->second = freeTcpPort();
    return it->second;
}

std::string CellRuntime::hostOf(const std::string& name) const {
    // An adapter runs where the changer that powers it runs.
    for (const auto& c : cell_.toolChangers) {
        for (const auto& m : cell::adapterModelTable()) {
            if (cell::adapterComponent(m, c.name).name == name) return cell_.hostOf(c.name);
        }
    }
    return cell_.hostOf(name);
}

std::string CellRuntime::addressOf(const std::string& name) const {
    return options_.hosts != nullptr ? options_.hosts->address(hostOf(name)) : "127.0.0.1";
}

std::vector<std::string> CellRuntime::bindArgs(const char* option, const std::string& name) const {
    // On the host's own network a component serves on all its interfaces.
    if (cell_.network.kind == cell::Network::Kind::Host) return {};
    return {option, addressOf(name)};
}

std::vector<std::string> CellRuntime::componentArgs(const std::string& name,
                                                    std::uint16_t tcpPort) const {
    std::vector<std::string> a = {"--port", std::to_string(tcpPort)};
    const auto bind = bindArgs("--host", name);
    a.insert(a.end(), bind.begin(), bind.end());
    for (const auto& i : cell_.network.interfaces) a.insert(a.end(), {"--mdns-interface", i});
    a.insert(a.end(), {"--mdns-ttl", std::to_string(cell_.network.mdnsTtlSeconds),
                       "--mdns-query-period", std::to_string(cell_.network.mdnsQueryPeriodSeconds),
                       "--pki-dir", pkiDir(name).string()});
    if (!secure()) {
        a.emplace_back("--insecure");
        return a;
    }
    const fs::path users = cell_.security.users.empty() ? dir() / "users" : cell_.security.users;
    a.insert(a.end(), {"--users", users.string()});
    if (actsAsCell(name)) {
        const auto user = componentUser();
        if (user.applicationCertificate) {
            a.emplace_back("--client-user-certificate");
        } else {
            a.insert(a.end(),
                     {"--client-user", user.name, "--client-password-file", user.passwordFile});
        }
    }
    return a;
}

std::string CellRuntime::adapterCommand(const cell::Tool& tool,
                                        const cell::AdapterModel& model) const {
    // The tool changer splits this at blanks and runs it when it powers the tool.
    const auto args = adapterArgs(tool, model);
    std::string cmd = programFor(skillcell_, args);
    for (const auto& a : args) cmd += " " + a;
    return cmd;
}

std::vector<std::string> CellRuntime::worldArgs() const {
    std::vector<std::string> a = {"--world", endpoint("world")};
    // The cell issued it: its clients need not ask the world which it is (WorldConnection).
    if (secure() && !worldCertificate_.empty()) {
        a.insert(a.end(), {"--world-certificate", worldCertificate_.string()});
    }
    return a;
}

std::vector<std::string> CellRuntime::adapterArgs(const cell::Tool& tool,
                                                  const cell::AdapterModel& model) const {
    const auto adapter = cell::adapterComponent(model, tool.changer);
    char speed[32];
    std::snprintf(speed, sizeof speed, "%g", this->speed());
    std::vector<std::string> a = {"device", std::string(model.command)};
    const auto world = worldArgs();
    a.insert(a.end(), world.begin(), world.end());
    a.insert(a.end(),
             {"--robot", changerRobot(tool.changer), "--robot-uri",
              applicationUri(changerRobot(tool.changer)), "--application-uri",
              adapter.applicationUri, "--speed", speed, "--boot-profile", options_.bootProfile,
              "--grip-offset", cell::vectorArgument(tool.gripOffset)});
    // Powered adapters come and go: each start takes any free port.
    const auto tail = componentArgs(adapter.name, 0);
    a.insert(a.end(), tail.begin(), tail.end());
    return a;
}

kb::Expected<ComponentLaunch> CellRuntime::adapterLaunch(const cell::Tool& tool) {
    const cell::AdapterModel* model = cell::findAdapterModel(tool.adapter);
    if (model == nullptr) return kb::Error{"tool " + tool.name + ": no adapter " + tool.adapter};
    if (endpoint("world").empty()) return kb::Error{"the adapters need the world model first"};
    ComponentLaunch l;
    const auto adapter = cell::adapterComponent(*model, tool.changer);
    l.name = adapter.name;
    l.applicationUri = adapter.applicationUri;
    l.args = adapterArgs(tool, *model);
    l.readyTimeout = 120s;  // a tinyua boot takes 8-10 s, more under a sanitizer
    return l;
}

kb::Expected<ComponentLaunch> CellRuntime::launch(const std::string& name) {
    ComponentLaunch l;
    l.name = name;
    l.applicationUri = applicationUri(name);
    if (l.applicationUri.empty()) return kb::Error{"the cell has no component " + name};
    auto needs = [&](const std::string& other) -> std::optional<kb::Error> {
        if (endpoint(other).empty()) {
            return kb::Error{name + " needs " + other + ", which has not started"};
        }
        return std::nullopt;
    };
    std::vector<std::string>& a = l.args;
    // The tool changer and pick-and-place wait for the skills they compose; detection of a
    // tinyua adapter takes its boot time.
    const std::string detectionTimeout =
        std::to_string(options_.bootProfile == "none" ? 20'000 : 60'000);
    if (name == "lds") {
        a = {"lds"};
    } else if (name == "kb") {
        a = {"kb", "--data-dir", (dir() / "kb").string(), "--http-port",
             std::to_string(port("kb-http"))};
        const auto bind = bindArgs("--http-host", name);
        a.insert(a.end(), bind.begin(), bind.end());
        if (!cell_.kb->sparqlUrl.empty()) a.insert(a.end(), {"--sparql-url", cell_.kb->sparqlUrl});
        // The scene first: the processes refer to its docks and tools.
        a.insert(a.end(), {"--cell", fs::absolute(cell_.path).string()});
        for (const auto& p : cell_.kb->processes) a.insert(a.end(), {"--process", p.string()});
        // Virtuoso's first start creates its database and Konclude checks every model:
        // minutes on a slow machine, seconds on a fast one.
        l.readyTimeout = 300s;
    } else if (name == "mes") {
        if (sparqlUrl().empty()) return kb::Error{"mes needs the knowledge base's SPARQL endpoint"};
        a = {"mes",
             "--kb",
             sparqlUrl(),
             "--journal",
             journal().string(),
             "--step-timeout-ms",
             std::to_string(cell_.mes->stepTimeoutMs)};
    } else if (name == "dashboard" && cell_.dashboard) {
        const std::uint16_t page = cell_.dashboard->port != 0
                                       ? static_cast<std::uint16_t>(cell_.dashboard->port)
                                       : port("dashboard-http");
        a = {"dashboard", "--http-port", std::to_string(page)};
        const auto bind = bindArgs("--http-host", name);
        a.insert(a.end(), bind.begin(), bind.end());
        if (!endpoint("world").empty()) a.insert(a.end(), {"--world", endpoint("world")});
        if (cell_.mes) a.insert(a.end(), {"--journal", journal().string()});
        if (!sparqlUrl().empty()) a.insert(a.end(), {"--kb", sparqlUrl()});
    } else if (name == "world") {
        a = {"device", "world"};
        const auto scene = cell::worldArguments(cell_);
        a.insert(a.end(), scene.begin(), scene.end());
        if (options_.shelf) {
            const auto shelf = cell::worldArguments(*options_.shelf);
            a.insert(a.end(), shelf.begin(), shelf.end());
        }
        // The world's first start builds the scene the cell file draws; a restart (after a
        // crash) goes on from the cell as it was, as the physics it simulates would.
        const fs::path state = dir() / "world-state.json";
        if (!worldLaunched_) {
            std::error_code ec;
            fs::remove(state, ec);
            worldLaunched_ = true;
        }
        a.insert(a.end(), {"--state-file", state.string()});
    } else if (cell_.toolChanger(name) != nullptr) {
        if (auto e = needs("world")) return *e;
        const std::string robot = changerRobot(name);
        a = {"device", "toolchanger"};
        const auto world = worldArgs();
        a.insert(a.end(), world.begin(), world.end());
        a.insert(a.end(), {"--robot", robot, "--robot-uri", applicationUri(robot),
                           "--detection-timeout-ms", detectionTimeout});
        // Kept with the cell: a restarted changer puts the mounted tool back into its dock.
        a.insert(a.end(), {"--dock-map", (dir() / (name + "-docks.json")).string()});
        const auto power = [this](const cell::Tool& t, const cell::AdapterModel& m) {
            return adapterCommand(t, m);
        };
        const auto table = cell::toolTableArguments(cell_, power, name);
        a.insert(a.end(), table.begin(), table.end());
        if (options_.shelf) {
            const auto shelf = cell::toolTableArguments(*options_.shelf, power);
            a.insert(a.end(), shelf.begin(), shelf.end());
        }
    } else if (cell_.pickAndPlace(name) != nullptr) {
        if (auto e = needs("world")) return *e;
        a = {"device", "pickplace"};
        const auto world = worldArgs();
        a.insert(a.end(), world.begin(), world.end());
        a.insert(a.end(), {"--detection-timeout-ms", detectionTimeout});
    } else {
        if (auto e = needs("world")) return *e;
        const auto robot = std::find_if(cell_.robots.begin(), cell_.robots.end(),
                                        [&](const cell::Robot& r) { return r.name == name; });
        char speed[32];
        std::snprintf(speed, sizeof speed, "%g",
                      options_.speed > 0 ? options_.speed : robot->speed);
        a = {"device", robot->model};
        const auto world = worldArgs();
        a.insert(a.end(), world.begin(), world.end());
        a.insert(a.end(), {"--robot", robot->name, "--base", cell::poseArgument(robot->base),
                           "--speed", speed});
    }
    a.insert(a.end(), {"--application-uri", l.applicationUri});
    const auto tail = componentArgs(name, port(name));
    a.insert(a.end(), tail.begin(), tail.end());
    return l;
}

kb::Expected<CellProcess> CellRuntime::start(const ComponentLaunch& launch) {
    std::vector<std::string> argv = launch.args;
    argv.insert(argv.begin(), programFor(skillcell_, launch.args));
    const std::vector<int> namespaces = options_.hosts != nullptr
                                            ? options_.hosts->namespaces(hostOf(launch.name))
                                            : std::vector<int>{};
    auto p = CellProcess::start(launch.name, argv, environment(), log(launch.name),
                                launch.readyTimeout, namespaces);
    if (!p) return p;
    endpoints_[launch.name] = p->url();
    if (launch.name == "kb") kbSparql_ = p->reported("SPARQL");
    if (launch.name == "dashboard") dashboardUrl_ = p->reported("DASHBOARD");
    return p;
}

}  // namespace skillcell::apps
