#pragma once
// CellRuntime: a cell file made into running components, what `skillcell cell up` and
// `skillcell demo` share. It prepares the cell's security (the cell CA, the users, each
// component's certificate, commissioned before the component first starts, as a device gets
// its certificate before it joins a plant), and says how each component starts: its
// `skillcell` command line, from the cell file and from the endpoints of the components
// started before it. The cell file says each thing once; this is the one place that turns it
// into command lines.
#include <chrono>
#include <cstdint>
#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "application_identity.hpp"
#include "cell/cell_file.hpp"
#include "cell/device_arguments.hpp"
#include "cell_hosts.hpp"
#include "cell_process.hpp"
#include "client_security_options.hpp"
#include "kb/expected.hpp"
#include "work_directory.hpp"

namespace skillcell::apps {

/// Where the running skillcell program is (/proc/self/exe): every component is started from
/// the same one. Empty when it cannot be read.
[[nodiscard]] std::string skillcellProgram();

/// The program that runs `args` (a subcommand and its options): skillcell-component beside
/// `skillcell` for what it runs (server, lds, device), when it is there; `skillcell` for
/// everything else, and when it is not.
[[nodiscard]] std::string programFor(const std::string& skillcell,
                                     const std::vector<std::string>& args);

/// The cell file's network, for this process and the components it will start: its own
/// network namespace (network.kind = "private": needs root, or a network that is private
/// already will do), or the host's; and the hosts its components name (CellHosts). Call it
/// before any thread starts: a namespace is per thread. The error says why not and what to
/// do.
[[nodiscard]] kb::Expected<CellHosts> enterCellNetwork(const cell::CellFile& cell);

/// How one component of the cell starts.
struct ComponentLaunch {
    std::string name;  // as the cell file names it; its log is logs/<name>.log
    std::string applicationUri;
    std::vector<std::string> args;  // after the skillcell program
    std::chrono::milliseconds readyTimeout{30'000};
};

struct CellRuntimeOptions {
    /// Simulated seconds per real second for the robots and grippers; 0: each robot's own.
    double speed = 0;
    /// How gripper adapters start: "tinyua" like the paper's microcontroller boards, or
    /// "none" (at once).
    std::string bootProfile = "none";
    /// Each component keeps its TCP ports across restarts (`cell up`: the others were told
    /// its endpoint); else each start takes a free one.
    bool keepPorts = false;
    /// Docks and tools beside the cell's (the demo's --swap shelf): in the world model and
    /// the tool changer's table, not in the cell file.
    std::optional<cell::CellFile> shelf;
    /// The runtime's own name and application URI, for its certificate.
    std::string selfName = "cell-up";
    /// The cell's hosts (enterCellNetwork), where components run and what address they serve
    /// on; none: every component in this process's network, on the loopback. Outlives the
    /// runtime.
    const CellHosts* hosts = nullptr;
};

/// A user the runtime made, with the file that holds its password.
struct Credential {
    std::string user;
    std::string role;
    std::filesystem::path passwordFile;
};

class CellRuntime {
public:
    CellRuntime(const cell::CellFile& cell, const WorkDirectory& work, std::string skillcell,
                CellRuntimeOptions options);

    /// The cell's security before anything starts: the cell CA and the users (generated
    /// when the cell file says so, and kept in the work directory for the next start, or
    /// taken from the files it names) and every component's certificate. False, with
    /// `error`, when one is missing or cannot be made.
    [[nodiscard]] bool prepare(std::string* error);

    /// The cell's components in start order: lds, kb, world, the tool changer, the robots,
    /// pick-and-place, mes (those the file has).
    [[nodiscard]] std::vector<std::string> components() const;
    /// How `name` starts now. Its arguments name the endpoints of the components it needs,
    /// which must have started before it.
    [[nodiscard]] kb::Expected<ComponentLaunch> launch(const std::string& name);
    /// A tool's gripper adapter started on its own (the demo measures its detection; in the
    /// cell the tool changer powers it).
    [[nodiscard]] kb::Expected<ComponentLaunch> adapterLaunch(const cell::Tool& tool);
    /// Starts a component and waits for its READY line; remembers its endpoint.
    [[nodiscard]] kb::Expected<CellProcess> start(const ComponentLaunch& launch);

    [[nodiscard]] const cell::CellFile& cell() const { return cell_; }
    [[nodiscard]] const std::filesystem::path& dir() const { return work_.path(); }
    [[nodiscard]] std::filesystem::path log(const std::string& name) const {
        return work_.log(name);
    }
    [[nodiscard]] std::filesystem::path pkiDir(const std::string& name) const {
        return dir() / ("pki-" + name);
    }
    [[nodiscard]] std::filesystem::path journal() const { return dir() / "journal.sqlite"; }
    [[nodiscard]] std::filesystem::path passwordFile(const std::string& user) const;
    /// Added to every component's environment (the cell CA that issues certificates).
    [[nodiscard]] std::vector<std::pair<std::string, std::string>> environment() const;
    /// The endpoint a component reported when it last started; empty before.
    [[nodiscard]] std::string endpoint(const std::string& name) const;
    /// The knowledge base's SPARQL endpoint: the cell file's store, or the KB's own.
    [[nodiscard]] std::string sparqlUrl() const;
    /// The dashboard's page, once it runs; empty before, or when the cell has none.
    [[nodiscard]] const std::string& dashboardUrl() const { return dashboardUrl_; }
    [[nodiscard]] std::vector<Credential> credentials() const;
    /// Whom a component acts as on the others, and so the runtime's own clients: its
    /// certificate as an X.509 user token, or "cell" with a password where the cell file
    /// brings a users database of its own; anonymous without security.
    [[nodiscard]] ClientUserOptions componentUser() const;
    /// The runtime's own certificate (after prepare()), for its clients and detector.
    [[nodiscard]] const ApplicationIdentity& identity() const { return *identity_; }
    /// The runtime's own application URI (its detector's, its clients').
    [[nodiscard]] std::string selfUri() const { return "urn:skillcell:" + options_.selfName; }
    [[nodiscard]] bool secure() const { return cell_.security.enabled; }
    /// The speed of the robot and grippers: the option's, else the first robot's.
    [[nodiscard]] double speed() const;
    /// The robot the tool changer `changer` is on (the world's id of it), which the grippers
    /// of its adapters are mounted on too.
    [[nodiscard]] std::string changerRobot(const std::string& changer) const;
    /// The application URI of a component of the cell (by name); empty for an unknown one.
    [[nodiscard]] std::string applicationUri(const std::string& name) const;

private:
    /// What every component takes: its address and ports, mDNS, its PKI, the users and,
    /// for those that are clients of others, the user it acts as ("cell").
    [[nodiscard]] std::vector<std::string> componentArgs(const std::string& name,
                                                         std::uint16_t tcpPort) const;
    /// `option` and the address the component `name` serves on, where the cell has a network
    /// of its own; nothing on the host's network (all interfaces).
    [[nodiscard]] std::vector<std::string> bindArgs(const char* option,
                                                    const std::string& name) const;
    [[nodiscard]] std::uint16_t port(const std::string& key);
    /// `skillcell` arguments of the adapter of `model` for `tool` (its changer's robot, its
    /// own application URI), and the command line its changer runs to power it.
    [[nodiscard]] std::vector<std::string> adapterArgs(const cell::Tool& tool,
                                                       const cell::AdapterModel& model) const;
    [[nodiscard]] std::string adapterCommand(const cell::Tool& tool,
                                             const cell::AdapterModel& model) const;
    bool prepareUsers(std::string* error);
    /// Whether the components authenticate by their certificates (the generated users), or
    /// as "cell" with its password (a users database of the cell file's, which we don't write).
    [[nodiscard]] bool certificateUsers() const;
    /// Each client component's certificates (RSA and ECC) as the user "cell-NAME" (Operator).
    bool addComponentUsers(
        const std::vector<std::pair<std::string, std::vector<ua::ByteString>>>& clients,
        std::string* error);
    [[nodiscard]] std::optional<ApplicationIdentity> commission(const std::string& name,
                                                                const std::string& uri,
                                                                std::string* error) const;
    [[nodiscard]] std::filesystem::path caDir() const;
    /// The host `name` runs on (a gripper adapter: its tool changer's); empty: the cell's own.
    [[nodiscard]] std::string hostOf(const std::string& name) const;
    /// The address `name` serves on.
    [[nodiscard]] std::string addressOf(const std::string& name) const;
    /// --world and the world model's certificate (--world-certificate), for its clients.
    [[nodiscard]] std::vector<std::string> worldArgs() const;

    const cell::CellFile& cell_;
    const WorkDirectory& work_;
    std::string skillcell_;
    CellRuntimeOptions options_;
    std::optional<ApplicationIdentity> identity_;
    std::map<std::string, std::uint16_t> ports_;    // keepPorts: by component (and "kb-http")
    std::map<std::string, std::string> endpoints_;  // by component, from READY
    std::filesystem::path worldCertificate_;        // secured: the one its clients use
    std::string kbSparql_;                          // the KB's SPARQL line
    std::string dashboardUrl_;                      // the dashboard's DASHBOARD line
    std::vector<Credential> credentials_;
    bool worldLaunched_ = false;  // the world's first start begins from the cell file
};

}  // namespace skillcell::apps
