// `skillcell server`: a demo OPC UA server (namespace 0, the Server object, a Demo object
// with variables and a method) that announces itself by mDNS and registers with the LDSs
// it discovers. With --noop-skill it also offers skills of any concrete skill type that do
// nothing, successfully: stand-ins for real components in discovery and skill tests and
// benchmarks. Prints "READY opc.tcp://HOST:PORT" on stdout once it accepts connections,
// so scripts wait for that line instead of sleeping.
#include <spdlog/spdlog.h>

#include "commands.hpp"
#include "demo_nodes.hpp"
#include "server_process.hpp"
#include "skills/noop_behaviour.hpp"
#include "skills/skill_server.hpp"
#include "ua/nodeset/companion_models.hpp"
#include "ua/nodeset/nodeset_loader.hpp"

namespace skillcell::apps {
namespace {

struct ServerCommandOptions {
    ServerProcessOptions process;
    std::vector<std::string> noopSkills;  // "<SkillTypeBrowseName>=<InstanceName>"
    std::vector<std::string> nodesets;    // NodeSet2 files with skill types of their own
    int noopSkillMs = 0;
    int noopHalts = 0;
};

/// The models the --noop-skill types come from, and what they require; all of them when a
/// --nodeset file may require any, or a type is not found in one (the error names it).
std::vector<std::string_view> noopSkillModels(const ServerCommandOptions& options) {
    std::vector<std::string_view> models;
    bool everyModel = !options.nodesets.empty();
    for (const auto& spec : options.noopSkills) {
        const auto model = ua::companionModelDeclaring(spec.substr(0, spec.find('=')));
        everyModel = everyModel || !model;
        if (model) models.push_back(*model);
    }
    if (everyModel) {
        models.clear();
        for (const auto& model : ua::kCompanionModels) models.push_back(model.uri);
    }
    return models;
}

ua::Result<ComponentContent> populate(const ServerCommandOptions& options, ua::Server& server,
                                      asio::io_context& io) {
    auto fireDemoEvent = [&server](const ua::NodeId& source, ua::String message) {
        ua::Event event;
        event.sourceNode = source;
        event.message = {"", std::move(message)};
        event.severity = 500;
        server.fireEvent(std::move(event));
    };
    if (const auto s = addDemoNodes(server.addressSpace(), fireDemoEvent); s.isBad()) return s;
    if (options.noopSkills.empty() && options.nodesets.empty()) return ComponentContent{};

    std::string error;
    std::shared_ptr<skills::SkillServer> skillServer =
        skills::SkillServer::create(server, io.get_executor(), options.process.skillModels, &error);
    if (!skillServer) {
        spdlog::critical("{}", error);
        return ua::status::BadConfigurationError;
    }
    // After the SkillServer, which loads the companion models the files may require.
    for (const auto& file : options.nodesets) {
        if (const auto s = ua::loadNodeSetFile(server.addressSpace(), file); !s.ok()) {
            spdlog::critical("--nodeset: {}", s.error);
            return ua::status::BadConfigurationError;
        }
        spdlog::info("loaded {}", file);
    }
    for (const auto& spec : options.noopSkills) {
        const auto eq = spec.find('=');
        const std::string typeName = spec.substr(0, eq);
        const std::string name = eq == std::string::npos ? typeName : spec.substr(eq + 1);
        const auto type = skillServer->findSkillType(typeName);
        if (!type || name.empty()) {
            spdlog::critical(
                "--noop-skill {}: '{}' is not a skill type of the companion models "
                "(see docs/models/) or of a --nodeset",
                spec, typeName);
            return ua::status::BadTypeDefinitionInvalid;
        }
        auto behaviour = std::make_unique<skills::NoOpBehaviour>(
            io.get_executor(), std::chrono::milliseconds(options.noopSkillMs), options.noopHalts);
        auto skill = skillServer->add(*type, name, std::move(behaviour));
        if (!skill) {
            spdlog::critical("--noop-skill {}: {}", spec, ua::statusName(skill.status()));
            return skill.status();
        }
        spdlog::info("skill {} ({}) at {}", name, typeName, (*skill)->nodeId().toString());
    }
    return ComponentContent(skillServer);
}

}  // namespace

Command addServerCommand(CLI::App& app) {
    auto options = std::make_shared<ServerCommandOptions>();
    options->process.applicationName = "skillcell demo server";
    CLI::App* cmd = app.add_subcommand(
        "server",
        "Run a demo OPC UA server: namespace 0, the Server object, and Objects/Demo with "
        "variables (Demo.Double, Demo.Int32, Demo.String, Demo.Boolean, Demo.DoubleArray, "
        "Demo.ReadOnly, Demo.Uptime) and a method Demo.Add(a, b); with --noop-skill, skills "
        "in Objects/Skills. It announces itself by mDNS and registers with every LDS it "
        "discovers; SIGTERM unregisters it and sends the mDNS goodbye. Prints 'READY <url>' "
        "on stdout when it accepts connections.");
    addServerProcessOptions(cmd, options->process);
    addDiscoveryOptions(cmd, options->process.discovery, /*registers=*/true, /*isLds=*/false);
    cmd->add_option("--noop-skill", options->noopSkills,
                    "offer a skill that does nothing, successfully: TYPE=NAME with TYPE a "
                    "concrete skill type of the companion models or of a --nodeset, e.g. "
                    "CartesianLinearMoveSkillType=Move (repeatable)");
    cmd->add_option("--nodeset", options->nodesets,
                    "load a NodeSet2 file (after the companion models), e.g. one with a skill "
                    "type of its own for --noop-skill (repeatable)")
        ->check(CLI::ExistingFile);
    cmd->add_option("--noop-skill-ms", options->noopSkillMs,
                    "how long a no-op skill runs before it finishes")
        ->check(CLI::Range(0, 3'600'000))
        ->capture_default_str();
    cmd->add_option("--noop-halts", options->noopHalts,
                    "the first N runs of each no-op skill end Halted, with a reason, as a "
                    "skill whose hardware faults does (to try retry policies)")
        ->check(CLI::Range(0, 1'000'000))
        ->capture_default_str();
    return {cmd, [options] {
                // Loaded beside namespace 0 (runServerProcess), not after it; populate()
                // creates its SkillServer over the same list.
                if (!options->noopSkills.empty() || !options->nodesets.empty()) {
                    options->process.skillModels = noopSkillModels(*options);
                }
                return runServerProcess(options->process, [options](const ComponentContext& c) {
                    return populate(*options, c.server, c.io);
                });
            }};
}

}  // namespace skillcell::apps
