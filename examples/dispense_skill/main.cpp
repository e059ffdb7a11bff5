// skillcell-example-dispense: a component offering one skill of a type that is not part of
// skillcell's companion models. Its type comes from a NodeSet2 file loaded at run time;
// its behaviour is DispenseBehaviour. Run it, then e.g.
//   skillcell browse opc.tcp://127.0.0.1:4850 --start "ns=1;s=Skills/Dispense" --values
#include <spdlog/spdlog.h>
#include <CLI/CLI.hpp>
#include <asio/io_context.hpp>
#include <asio/signal_set.hpp>
#include <iostream>

#include "dispense_behaviour.hpp"
#include "skills/skill_server.hpp"
#include "ua/nodeset/companion_models.hpp"
#include "ua/nodeset/nodeset_loader.hpp"

using namespace skillcell;

int main(int argc, char** argv) {
    CLI::App app{"An example component with a skill type of its own (examples/dispense_skill)."};
    std::uint16_t port = 4850;
    std::string model = SKILLCELL_EXAMPLE_MODEL;
    double reservoir = 100;
    double speed = 1;
    app.add_option("--port,-p", port, "OPC UA TCP port on 127.0.0.1 (0: any)")
        ->capture_default_str();
    app.add_option("--model", model, "the NodeSet2 file with DispenseSkillType")
        ->capture_default_str();
    app.add_option("--reservoir-ml", reservoir, "glue in the reservoir")->capture_default_str();
    app.add_option("--speed", speed, "simulated-time factor")
        ->check(CLI::PositiveNumber)
        ->capture_default_str();
    CLI11_PARSE(app, argc, argv);

    asio::io_context io{1};
    ua::ServerConfig config;
    config.bindAddress = "127.0.0.1";
    config.description.port = port;
    config.description.applicationUri = "urn:skillcell:example:dispenser";
    config.description.applicationName = "skillcell example dispenser";
    std::string error;
    auto server = ua::Server::create(io, config, &error);
    if (!server) {
        spdlog::critical("{}", error);
        return 1;
    }
    // The Skills model, which the new type's file requires, and nothing else: no skill type
    // of the other companion models is offered here.
    auto skills = skills::SkillServer::create(*server, io.get_executor(), {}, &error);
    if (!skills) {
        spdlog::critical("{}", error);
        return 1;
    }
    // The new type: one NodeSet2 file, loaded at run time after the models it requires.
    const auto loaded = ua::loadNodeSetFile(server->addressSpace(), model);
    if (!loaded.ok()) {
        spdlog::critical("{}", loaded.error);
        return 1;
    }
    const auto type = ua::findTypeByName(
        server->addressSpace(), "http://skillcell.dev/UA/Examples/Dispense/", "DispenseSkillType");
    auto skill =
        type ? skills->add(*type, "Dispense",
                           std::make_unique<examples::DispenseBehaviour>(io.get_executor(),
                                                                         reservoir, speed))
             : ua::Result<std::shared_ptr<skills::Skill>>(ua::status::BadTypeDefinitionInvalid);
    if (!skill) {
        spdlog::critical("cannot add the Dispense skill: {}", ua::statusName(skill.status()));
        return 1;
    }
    auto bound = server->listen();
    if (!bound) return 1;
    asio::signal_set signals(io, SIGINT, SIGTERM);
    signals.async_wait([&](const std::error_code&, int) {
        server->stop();
        io.stop();
    });
    std::cout << "READY opc.tcp://127.0.0.1:" << *bound << std::endl;
    io.run();
    return 0;
}
