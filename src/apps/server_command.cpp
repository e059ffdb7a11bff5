// `skillcell server`: a demo OPC UA server (namespace 0, the Server object, a Demo object
// with variables and a method) that announces itself by mDNS and registers with the LDSs
// it discovers. Prints "READY opc.tcp://HOST:PORT" on stdout once it accepts connections,
// so scripts wait for that line instead of sleeping.
#include "commands.hpp"
#include "demo_nodes.hpp"
#include "server_process.hpp"

namespace skillcell::apps {

Command addServerCommand(CLI::App& app) {
    auto options = std::make_shared<ServerProcessOptions>();
    options->applicationName = "skillcell demo server";
    CLI::App* cmd = app.add_subcommand(
        "server",
        "Run a demo OPC UA server: namespace 0, the Server object, and Objects/Demo with "
        "variables (Demo.Double, Demo.Int32, Demo.String, Demo.Boolean, Demo.DoubleArray, "
        "Demo.ReadOnly, Demo.Uptime) and a method Demo.Add(a, b). It announces itself by mDNS "
        "and registers with every LDS it discovers; SIGTERM unregisters it and sends the mDNS "
        "goodbye. Prints 'READY <url>' on stdout when it accepts connections.");
    addServerProcessOptions(cmd, *options);
    addDiscoveryOptions(cmd, options->discovery, /*registers=*/true, /*isLds=*/false);
    return {cmd, [options] {
                return runServerProcess(*options, [](ua::Server& server) {
                    auto fireDemoEvent = [&server](const ua::NodeId& source, ua::String message) {
                        ua::Event event;
                        event.sourceNode = source;
                        event.message = {"", std::move(message)};
                        event.severity = 500;
                        server.fireEvent(std::move(event));
                    };
                    return addDemoNodes(server.addressSpace(), fireDemoEvent);
                });
            }};
}

}  // namespace skillcell::apps
