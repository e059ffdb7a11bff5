// `skillcell browse URL`: connects, browses the address space from a start node (Root by
// default) along forward hierarchical references, and prints it as a tree.
#include <spdlog/spdlog.h>

#include <iostream>
#include <set>

#include "client_security_options.hpp"
#include "commands.hpp"
#include "devices/common/frame.hpp"
#include "ua/client/blocking_client.hpp"
#include "ua/types/to_string.hpp"

namespace skillcell::apps {

namespace {

/// A value as text; a 3DFrame (the poses of the skill models and the world model) as its
/// position and orientation rather than as an opaque structure.
std::string valueText(const ua::Variant& value) {
    if (const auto frame = devices::frameFromVariant(value); frame.ok()) {
        return "3DFrame" + devices::describe(*frame);
    }
    return ua::toString(value);
}

struct BrowseOptions {
    std::string url;
    std::string start = "i=84";
    int maxDepth = 12;
    bool values = false;
    int timeoutMs = 2000;
    ClientSecurityOptions security;
};

class TreePrinter {
public:
    TreePrinter(ua::BlockingClient& client, const BrowseOptions& options)
        : client_(client), options_(options) {}

    /// Returns the first service-level failure (a node that cannot be browsed is printed
    /// with its status and does not stop the walk).
    ua::StatusCode print(const ua::NodeId& node, int depth) {
        if (depth > options_.maxDepth) return ua::status::Good;
        auto result = client_.browse(node, ua::BrowseDirection::Forward,
                                     ua::NodeId(33u) /* HierarchicalReferences */);
        if (!result) return result.status();
        auto references = std::move(result->references);
        if (result->statusCode.isBad()) {
            std::cout << indent(depth) << "(" << ua::statusName(result->statusCode) << ")\n";
            return ua::status::Good;
        }
        auto cp = result->continuationPoint;
        while (!cp.empty()) {  // the server limits references per call: fetch the rest
            auto next = client_.browseNext(cp);
            if (!next) return next.status();
            references.insert(references.end(), next->references.begin(), next->references.end());
            cp = next->continuationPoint;
        }
        for (const auto& ref : references) {
            const ua::NodeId& target = ref.nodeId.nodeId;
            const auto nodeClass = ua::nodeClassName(ref.nodeClass);
            std::cout << indent(depth) << ref.browseName.namespaceIndex << ":"
                      << ref.browseName.name << "  [" << (nodeClass.empty() ? "?" : nodeClass)
                      << " " << target.toString() << "]";
            if (options_.values && ref.nodeClass == ua::NodeClass::Variable) {
                auto value = client_.readAttribute(target, ua::AttributeId::Value);
                if (!value) {
                    std::cout << " = (" << ua::statusName(value.status()) << ")";
                } else if (value->status && value->status->isBad()) {
                    std::cout << " = (" << ua::statusName(*value->status) << ")";
                } else if (value->value) {
                    std::cout << " = " << valueText(*value->value);
                }
            }
            std::cout << "\n";
            if (!ref.nodeId.isLocal() || !visited_.insert(target).second) continue;
            if (auto s = print(target, depth + 1); s.isBad()) return s;
        }
        return ua::status::Good;
    }

private:
    static std::string indent(int depth) {
        return std::string(static_cast<std::size_t>(depth) * 2, ' ');
    }

    ua::BlockingClient& client_;
    const BrowseOptions& options_;
    std::set<ua::NodeId> visited_;
};

int runBrowse(const BrowseOptions& options) {
    auto start = ua::NodeId::parse(options.start);
    if (!start) {
        std::cerr << "invalid --start node id '" << options.start
                  << "' (expected e.g. i=84 or ns=2;s=Demo)\n";
        return 2;
    }
    auto config = commandClientConfig(options.security, "skillcell browse");
    if (!config) return 2;
    config->connectTimeout = std::chrono::milliseconds(options.timeoutMs);
    ua::BlockingClient client;
    if (const auto s = client.connect(options.url, *config); s.isBad()) {
        std::cerr << "cannot connect to " << options.url << ": " << explainConnectFailure(s)
                  << "\n";
        return 1;
    }
    std::cout << options.url << "  " << start->toString() << "\n";
    TreePrinter printer(client, options);
    const auto s = printer.print(*start, 1);
    (void)client.disconnect();
    if (s.isBad()) {
        std::cerr << "browse failed: " << ua::statusName(s) << "\n";
        return 1;
    }
    return 0;
}

}  // namespace

Command addBrowseCommand(CLI::App& app) {
    auto options = std::make_shared<BrowseOptions>();
    CLI::App* cmd = app.add_subcommand(
        "browse",
        "Print the address space of an OPC UA server as a tree (forward hierarchical "
        "references from --start).");
    cmd->add_option("url", options->url, "server endpoint, e.g. opc.tcp://localhost:4840")
        ->required();
    cmd->add_option("--start", options->start, "node to start from")->capture_default_str();
    cmd->add_option("--max-depth", options->maxDepth, "levels to descend")
        ->check(CLI::Range(0, 100))
        ->capture_default_str();
    cmd->add_flag("--values", options->values, "also read and print variable values");
    cmd->add_option("--timeout", options->timeoutMs, "connect timeout in milliseconds")
        ->check(CLI::Range(1, 600000))
        ->capture_default_str();
    addClientSecurityOptions(cmd, options->security);
    return {cmd, [options] { return runBrowse(*options); }};
}

}  // namespace skillcell::apps
