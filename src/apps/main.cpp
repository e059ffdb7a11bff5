// skillcell: one program, one subcommand per component (server, lds, browse, discover, skill,
// check, detect, device <kind>; later kb, mes, demo). Every component takes --port N for its OPC UA
// port.
#include <spdlog/sinks/stdout_color_sinks.h>
#include <spdlog/spdlog.h>

#include <CLI/CLI.hpp>
#include <vector>

#include "commands.hpp"

int main(int argc, char** argv) {
    CLI::App app{"skillcell: a Plug & Produce system for robot work cells built on OPC UA skills"};
    app.require_subcommand(1);
    std::string logLevel = "info";
    app.add_option("--log-level", logLevel, "trace, debug, info, warn, error, off")
        ->check(CLI::IsMember({"trace", "debug", "info", "warn", "error", "off"}))
        ->capture_default_str();

    std::vector<skillcell::apps::Command> commands{
        skillcell::apps::addServerCommand(app),    skillcell::apps::addBrowseCommand(app),
        skillcell::apps::addLdsCommand(app),       skillcell::apps::addDiscoverCommand(app),
        skillcell::apps::addSkillCommand(app),     skillcell::apps::addCheckCommand(app),
        skillcell::apps::addDetectCommand(app),    skillcell::apps::addPkiCommand(app),
        skillcell::apps::addUserCommand(app),      skillcell::apps::addNodeset2OwlCommand(app),
        skillcell::apps::addKbCommand(app),        skillcell::apps::addMesCommand(app),
        skillcell::apps::addRunCommand(app),       skillcell::apps::addDemoCommand(app),
        skillcell::apps::addCellCommand(app),      skillcell::apps::addProcessCommand(app),
        skillcell::apps::addDashboardCommand(app), skillcell::apps::addOrdersCommand(app),
    };
    for (auto& device : skillcell::apps::addDeviceCommands(app)) commands.push_back(device);

    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        // --help exits 0; every usage error exits 2, the usual code that scripts (and
        // `skillcell check`'s contract) expect, instead of CLI11's own 100+ codes.
        return app.exit(e) == 0 ? 0 : 2;
    }

    // Logs go to stderr: stdout carries the commands' output (READY lines, browse trees).
    auto logger = spdlog::stderr_color_mt("skillcell");
    spdlog::set_default_logger(logger);
    spdlog::set_level(spdlog::level::from_str(logLevel));

    for (const auto& command : commands) {
        if (command.cli->parsed()) return command.run();
    }
    return 2;
}
