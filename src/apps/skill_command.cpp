// `skillcell skill URL SKILL [--set NAME=VALUE]... [--timeout S]`: runs one skill of a
// remote component through a SkillClient and prints what happens: its parameters, every
// transition event, and the outcome. SKILL is the skill's NodeId ("ns=1;s=Skills/Move") or
// its browse name in the component's Skills folder ("Move"). Values are parsed by the
// parameter's declared data type (Boolean, integers, Float, Double, String). Exit code 0
// when the run finished, 1 when it failed or was refused, timed out or lost, 2 on bad input.
#include <spdlog/spdlog.h>
#include <asio/co_spawn.hpp>
#include <asio/detached.hpp>
#include <asio/io_context.hpp>
#include <charconv>
#include <iostream>

#include "client_security_options.hpp"
#include "commands.hpp"
#include "skills/skill_client.hpp"
#include "ua/types/to_string.hpp"

namespace skillcell::apps {
namespace {

struct SkillOptions {
    std::string url;
    std::string skill;
    std::vector<std::string> sets;
    double timeoutSeconds = 60;
    bool list = false;
    ClientSecurityOptions security;
};

template <class T>
std::optional<ua::Variant> parseNumber(const std::string& text) {
    T value{};
    const auto* end = text.data() + text.size();
    const auto r = std::from_chars(text.data(), end, value);
    if (r.ec != std::errc{} || r.ptr != end) return std::nullopt;
    return ua::Variant(value);
}

/// A value for a parameter of built-in data type `dataType` (ns=0 numeric ids 1..12).
std::optional<ua::Variant> parseValue(const ua::NodeId& dataType, const std::string& text) {
    if (dataType.namespaceIndex() != 0) return std::nullopt;
    const auto* id = std::get_if<std::uint32_t>(&dataType.identifier());
    if (id == nullptr) return std::nullopt;
    switch (*id) {
        case 1:
            if (text == "true") return ua::Variant(true);
            if (text == "false") return ua::Variant(false);
            return std::nullopt;
        case 2:
            return parseNumber<std::int8_t>(text);
        case 3:
            return parseNumber<std::uint8_t>(text);
        case 4:
            return parseNumber<std::int16_t>(text);
        case 5:
            return parseNumber<std::uint16_t>(text);
        case 6:
            return parseNumber<std::int32_t>(text);
        case 7:
            return parseNumber<std::uint32_t>(text);
        case 8:
            return parseNumber<std::int64_t>(text);
        case 9:
            return parseNumber<std::uint64_t>(text);
        case 10:
            return parseNumber<float>(text);
        case 11:
            return parseNumber<double>(text);
        case 12:
            return ua::Variant(ua::String(text));
        default:
            return std::nullopt;
    }
}

asio::awaitable<int> runSkill(ua::Client& client, const SkillOptions& o) {
    auto config = commandClientConfig(o.security, "skillcell skill");
    if (!config) co_return 2;
    const std::string url = o.url;
    if (const auto s = co_await client.connect(url, std::move(*config)); s.isBad()) {
        std::cerr << "cannot connect to " << o.url << ": " << explainConnectFailure(s) << "\n";
        co_return 1;
    }
    ua::NodeId id;
    if (auto parsed = ua::NodeId::parse(o.skill)) {
        id = *parsed;
    } else {
        id = ua::NodeId(1, ua::String("Skills/" + o.skill));
    }
    auto attached = co_await skills::SkillClient::attach(client, id);
    if (!attached) {
        std::cerr << "no skill " << o.skill << " (" << id.toString() << ") at " << o.url << ": "
                  << ua::statusName(attached.status()) << "\n";
        (void)co_await client.disconnect();
        co_return 1;
    }
    auto sc = *attached;
    std::cout << "SKILL " << id.toString() << " state "
              << (sc->state() ? std::string(skills::name(*sc->state())) : "?") << "\n";
    for (const auto& p : sc->parameters()) {
        std::cout << "PARAMETER " << p.name << " " << p.dataType.toString()
                  << (p.valueRank >= 0 ? "[]" : "") << "\n";
    }
    int code = 0;
    if (!o.list) {
        std::map<std::string, ua::Variant> values;
        for (const auto& set : o.sets) {
            const auto eq = set.find('=');
            const std::string name = set.substr(0, eq);
            const auto it = std::find_if(sc->parameters().begin(), sc->parameters().end(),
                                         [&](const auto& p) { return p.name == name; });
            if (eq == std::string::npos || it == sc->parameters().end()) {
                std::cerr << "--set " << set << ": no parameter " << name << "\n";
                code = 2;
                break;
            }
            auto value = parseValue(it->dataType, set.substr(eq + 1));
            if (!value) {
                std::cerr << "--set " << set << ": cannot read '" << set.substr(eq + 1) << "' as "
                          << it->dataType.toString()
                          << " (the command line takes built-in scalar types only)\n";
                code = 2;
                break;
            }
            values.emplace(name, std::move(*value));
        }
        if (code == 0) {
            const auto timeout =
                std::chrono::milliseconds(static_cast<long>(o.timeoutSeconds * 1000));
            const auto outcome = co_await sc->run(std::move(values), timeout);
            for (const auto& t : sc->transitions()) {
                const std::string name =
                    t.transition ? std::string(skills::name(*t.transition)) : "?";
                std::cout << "TRANSITION " << t.time.toIso8601() << " " << name
                          << (t.message.empty() || t.message == name ? "" : "  " + t.message)
                          << "\n";
            }
            std::cout << "OUTCOME " << skills::name(outcome.kind);
            if (outcome.status.isBad()) std::cout << " " << ua::statusName(outcome.status);
            if (!outcome.reason.empty()) std::cout << " (" << outcome.reason << ")";
            std::cout << "\n";
            code = outcome.ok() ? 0 : 1;
        }
    }
    co_await sc->detach();
    (void)co_await client.disconnect();
    co_return code;
}

}  // namespace

Command addSkillCommand(CLI::App& app) {
    auto o = std::make_shared<SkillOptions>();
    CLI::App* cmd = app.add_subcommand(
        "skill",
        "Run one skill of a remote component: write its parameters, Start, follow its "
        "transition events to the end. Prints PARAMETER, TRANSITION and OUTCOME lines; exit "
        "code 0 when the run finished, 1 when it failed, was refused, timed out or the "
        "component was lost, 2 on bad input.");
    cmd->add_option("url", o->url, "the component's endpoint, e.g. opc.tcp://localhost:4841")
        ->required();
    cmd->add_option("skill", o->skill,
                    "the skill: its NodeId (ns=1;s=Skills/Move) or its name in Objects/Skills")
        ->required();
    cmd->add_option("--set", o->sets, "NAME=VALUE for a parameter (repeatable)");
    cmd->add_option("--timeout", o->timeoutSeconds, "seconds to wait for the end; then Halt")
        ->check(CLI::PositiveNumber)
        ->capture_default_str();
    cmd->add_flag("--list", o->list, "only print the skill's state and parameters");
    addClientSecurityOptions(cmd, o->security);
    return {cmd, [o] {
                return runClientCommand([o](ua::Client& client) { return runSkill(client, *o); });
            }};
}

}  // namespace skillcell::apps
