#include "cell/cell_file.hpp"

#include <toml++/toml.h>
#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <fstream>
#include <initializer_list>
#include <map>
#include <sstream>
#include <tuple>

#include "cell/device_arguments.hpp"
#include "devices/toolchanger/tool_table.hpp"

namespace skillcell::cell {
namespace {

std::string_view typeName(toml::node_type type) {
    switch (type) {
        case toml::node_type::table:
            return "a table";
        case toml::node_type::array:
            return "an array";
        case toml::node_type::string:
            return "a string";
        case toml::node_type::integer:
            return "an integer";
        case toml::node_type::floating_point:
            return "a number";
        case toml::node_type::boolean:
            return "a boolean";
        case toml::node_type::date:
        case toml::node_type::time:
        case toml::node_type::date_time:
            return "a date or time";
        case toml::node_type::none:
            break;
    }
    return "nothing";
}

/// Names go into command lines and log file names, and into the devices' option syntax
/// (ID@POSE, ID:BAND:URI): letters, digits, '-' and '_' only.
bool isName(std::string_view s) {
    return !s.empty() && s.size() <= 64 && std::all_of(s.begin(), s.end(), [](char c) {
        return std::isalnum(static_cast<unsigned char>(c)) != 0 || c == '-' || c == '_';
    });
}

/// "a, b, c"
template <class Names>
std::string joined(const Names& names) {
    std::string out;
    for (std::string_view n : names) {
        if (!out.empty()) out.append(", ");
        out.append(n);
    }
    return out;
}

/// Reads one file, collecting every problem instead of stopping at the first.
class Reader {
public:
    Reader(std::string sourceName, std::filesystem::path base)
        : source_(std::move(sourceName)), base_(std::move(base)) {}

    void problem(const toml::source_region& where, std::string message) {
        problems_.push_back({source_, static_cast<int>(where.begin.line),
                             static_cast<int>(where.begin.column), std::move(message)});
    }
    std::vector<Problem> takeProblems() { return std::move(problems_); }

    /// Every key of `table` must be one of `allowed`.
    void onlyKeys(const toml::table& table, std::string_view where,
                  std::initializer_list<std::string_view> allowed) {
        for (auto&& [key, node] : table) {
            if (std::find(allowed.begin(), allowed.end(), key.str()) != allowed.end()) continue;
            problem(key.source(), "unknown key '" + std::string(key.str()) + "' in " +
                                      std::string(where) + "; expected one of: " + joined(allowed));
        }
    }

    const toml::table* table(const toml::table& parent, std::string_view key,
                             std::string_view where) {
        const toml::node* n = parent.get(key);
        if (n == nullptr) return nullptr;
        if (!n->is_table()) {
            problem(n->source(), std::string(where) + " must be a table, not " +
                                     std::string(typeName(n->type())));
            return nullptr;
        }
        return n->as_table();
    }

    /// One table ([key]) or an array of them ([[key]]), empty when absent.
    std::vector<const toml::table*> tableOrTables(const toml::table& parent, std::string_view key) {
        const toml::node* n = parent.get(key);
        if (n != nullptr && n->is_table()) return {n->as_table()};
        return tables(parent, key, key);
    }

    /// An array of tables ([[key]]), empty when absent.
    std::vector<const toml::table*> tables(const toml::table& parent, std::string_view key,
                                           std::string_view where) {
        std::vector<const toml::table*> out;
        const toml::node* n = parent.get(key);
        if (n == nullptr) return out;
        const toml::array* a = n->as_array();
        if (a == nullptr) {
            problem(n->source(), std::string(where) + " must be an array of tables ([[" +
                                     std::string(where) + "]]), not " +
                                     std::string(typeName(n->type())));
            return out;
        }
        for (const auto& e : *a) {
            if (e.is_table()) {
                out.push_back(e.as_table());
            } else {
                problem(e.source(), "each " + std::string(where) + " must be a table, not " +
                                        std::string(typeName(e.type())));
            }
        }
        return out;
    }

    std::optional<std::string> string(const toml::table& t, std::string_view key,
                                      std::string_view where, bool required) {
        const toml::node* n = t.get(key);
        if (n == nullptr) {
            if (required) missing(t, key, where, "a string");
            return std::nullopt;
        }
        if (auto v = n->value_exact<std::string>()) return *v;
        wrongType(*n, key, where, "a string");
        return std::nullopt;
    }

    std::optional<std::string> name(const toml::table& t, std::string_view where) {
        auto v = string(t, "name", where, true);
        if (!v) return std::nullopt;
        if (!isName(*v)) {
            problem(t.get("name")->source(), "name '" + *v + "' in " + std::string(where) +
                                                 ": use 1 to 64 letters, digits, '-' or '_'");
            return std::nullopt;
        }
        return v;
    }

    /// A required string that must be one of `allowed` (`what` says what they are).
    std::optional<std::string> oneOf(const toml::table& t, std::string_view key,
                                     std::string_view where,
                                     const std::vector<std::string_view>& allowed,
                                     std::string_view what) {
        auto v = string(t, key, where, true);
        if (v && std::find(allowed.begin(), allowed.end(), *v) == allowed.end()) {
            problem(t.get(key)->source(), std::string(where) + ": " + std::string(key) + " '" + *v +
                                              "' is not " + std::string(what) +
                                              "; expected one of: " + joined(allowed));
            return std::nullopt;
        }
        return v;
    }

    /// The keys every component has: `restart`, into `cell.restart[component]`, and `host`,
    /// into `cell.hosts[component]` (both optional).
    void componentKeys(const toml::table& t, std::string_view where, const std::string& component,
                       CellFile& cell) {
        if (auto host = string(t, "host", where, false)) {
            if (auto why = hostProblem(cell, *host); !why.empty()) {
                problem(t.get("host")->source(), std::string(where) + ": " + why);
            } else {
                cell.hosts[component] = *host;
            }
        }
        if (t.get("restart") == nullptr) return;
        static const std::vector<std::string_view> policies = {"on-failure", "always", "never"};
        auto v = oneOf(t, "restart", where, policies, "a restart policy");
        if (!v) return;
        cell.restart[component] = *v == "always"  ? RestartPolicy::Always
                                  : *v == "never" ? RestartPolicy::Never
                                                  : RestartPolicy::OnFailure;
    }

    std::optional<bool> boolean(const toml::table& t, std::string_view key,
                                std::string_view where) {
        const toml::node* n = t.get(key);
        if (n == nullptr) return std::nullopt;
        if (auto v = n->value_exact<bool>()) return *v;
        wrongType(*n, key, where, "true or false");
        return std::nullopt;
    }

    std::optional<std::int64_t> integer(const toml::table& t, std::string_view key,
                                        std::string_view where, std::int64_t lo, std::int64_t hi) {
        const toml::node* n = t.get(key);
        if (n == nullptr) return std::nullopt;
        auto v = n->value_exact<std::int64_t>();
        if (!v) {
            wrongType(*n, key, where, "an integer");
            return std::nullopt;
        }
        if (*v < lo || *v > hi) {
            problem(n->source(), "'" + std::string(key) + "' in " + std::string(where) +
                                     " must be from " + std::to_string(lo) + " to " +
                                     std::to_string(hi) + ", not " + std::to_string(*v));
            return std::nullopt;
        }
        return v;
    }

    std::optional<double> number(const toml::table& t, std::string_view key, std::string_view where,
                                 double lo, double hi) {
        const toml::node* n = t.get(key);
        if (n == nullptr) return std::nullopt;
        auto v = numberOf(*n);
        if (!v) {
            wrongType(*n, key, where, "a number");
            return std::nullopt;
        }
        if (!(*v >= lo && *v <= hi)) {
            std::ostringstream m;
            m << "'" << key << "' in " << where << " must be from " << lo << " to " << hi
              << ", not " << *v;
            problem(n->source(), m.str());
            return std::nullopt;
        }
        return v;
    }

    /// An array of exactly `counts` finite numbers (one of them).
    std::optional<std::vector<double>> numbers(const toml::table& t, std::string_view key,
                                               std::string_view where,
                                               std::initializer_list<std::size_t> counts,
                                               std::string_view meaning, bool required) {
        const toml::node* n = t.get(key);
        std::string expected = "an array of ";
        for (auto c : counts) {
            expected += (c == *counts.begin() ? "" : " or ") + std::to_string(c);
        }
        expected += " numbers (" + std::string(meaning) + ")";
        if (n == nullptr) {
            if (required) missing(t, key, where, expected);
            return std::nullopt;
        }
        const toml::array* a = n->as_array();
        if (a == nullptr || std::find(counts.begin(), counts.end(), a->size()) == counts.end()) {
            wrongType(*n, key, where, expected);
            return std::nullopt;
        }
        std::vector<double> out;
        for (const auto& e : *a) {
            auto v = numberOf(e);
            if (!v || !std::isfinite(*v)) {
                problem(e.source(), "'" + std::string(key) + "' in " + std::string(where) + ": " +
                                        expected + ", but this element is " +
                                        std::string(typeName(e.type())));
                return std::nullopt;
            }
            out.push_back(*v);
        }
        return out;
    }

    std::optional<Pose> pose(const toml::table& t, std::string_view key, std::string_view where,
                             bool required) {
        auto v = numbers(t, key, where, {3, 6}, "x, y, z in m[, a, b, c in rad]", required);
        if (!v) return std::nullopt;
        Pose p{(*v)[0], (*v)[1], (*v)[2], 0, 0, 0};
        if (v->size() == 6) {
            p.a = (*v)[3];
            p.b = (*v)[4];
            p.c = (*v)[5];
        }
        return p;
    }

    /// A path: relative ones are from the cell file's folder; it must exist.
    std::optional<std::filesystem::path> existingPath(const toml::node& n, std::string_view key,
                                                      std::string_view where) {
        auto v = n.value_exact<std::string>();
        if (!v) {
            wrongType(n, key, where, "a path (string)");
            return std::nullopt;
        }
        std::filesystem::path p(*v);
        if (p.is_relative()) p = base_ / p;
        std::error_code ec;
        if (!std::filesystem::exists(p, ec)) {
            problem(n.source(), "'" + std::string(key) + "' in " + std::string(where) + ": " +
                                    p.string() + " does not exist");
            return std::nullopt;
        }
        return p.lexically_normal();
    }

    void missing(const toml::table& t, std::string_view key, std::string_view where,
                 std::string_view expected) {
        problem(t.source(), std::string(where) + " lacks '" + std::string(key) + "' (" +
                                std::string(expected) + ")");
    }
    void wrongType(const toml::node& n, std::string_view key, std::string_view where,
                   std::string_view expected) {
        std::string got(typeName(n.type()));
        if (const auto* a = n.as_array()) got = "an array of " + std::to_string(a->size());
        problem(n.source(), "'" + std::string(key) + "' in " + std::string(where) + " must be " +
                                std::string(expected) + ", not " + got);
    }

private:
    static std::optional<double> numberOf(const toml::node& n) {
        if (auto i = n.value_exact<std::int64_t>()) return static_cast<double>(*i);
        if (auto d = n.value_exact<double>()) return *d;
        return std::nullopt;
    }

    std::string source_;
    std::filesystem::path base_;
    std::vector<Problem> problems_;
};

void readNetwork(Reader& r, const toml::table& root, Network& out) {
    const toml::table* t = r.table(root, "network", "[network]");
    if (t == nullptr) return;
    r.onlyKeys(*t, "[network]", {"kind", "interfaces", "mdns-ttl", "mdns-query-period"});
    if (auto kind = r.string(*t, "kind", "[network]", false)) {
        if (*kind == "private") {
            out.kind = Network::Kind::PrivateNamespace;
        } else if (*kind == "host") {
            out.kind = Network::Kind::Host;
        } else {
            r.problem(t->get("kind")->source(),
                      "'kind' in [network] must be \"private\" (a network namespace of the "
                      "cell's own; needs root) or \"host\", not \"" +
                          *kind + "\"");
        }
    }
    if (const toml::node* n = t->get("interfaces")) {
        const toml::array* a = n->as_array();
        if (a == nullptr) {
            r.wrongType(*n, "interfaces", "[network]", "an array of interface names");
        } else {
            for (const auto& e : *a) {
                auto name = e.value_exact<std::string>();
                if (!name || name->empty()) {
                    r.problem(e.source(),
                              "'interfaces' in [network]: each must be an "
                              "interface name (a string)");
                } else {
                    out.interfaces.push_back(*name);
                }
            }
            if (out.kind != Network::Kind::Host && !out.interfaces.empty()) {
                r.problem(n->source(),
                          "'interfaces' in [network] needs kind = \"host\": a "
                          "private namespace has its own");
            }
        }
    }
    // RFC 6762 10: 120 s for records of a host; a TTL below the query period would expire
    // records between two refreshes.
    if (auto v = r.integer(*t, "mdns-ttl", "[network]", 1, 4500)) {
        out.mdnsTtlSeconds = static_cast<int>(*v);
    }
    if (auto v = r.integer(*t, "mdns-query-period", "[network]", 1, 3600)) {
        out.mdnsQueryPeriodSeconds = static_cast<int>(*v);
    }
}

void readSecurity(Reader& r, const toml::table& root, Security& out) {
    const toml::table* t = r.table(root, "security", "[security]");
    if (t == nullptr) return;
    r.onlyKeys(*t, "[security]", {"enabled", "ca", "users"});
    if (auto v = r.boolean(*t, "enabled", "[security]")) out.enabled = *v;
    if (const toml::node* n = t->get("ca")) {
        if (auto p = r.existingPath(*n, "ca", "[security]")) out.ca = *p;
    }
    if (const toml::node* n = t->get("users")) {
        if (auto p = r.existingPath(*n, "users", "[security]")) out.users = *p;
    }
    if (!out.enabled && (t->get("ca") != nullptr || t->get("users") != nullptr)) {
        r.problem(t->source(),
                  "[security] has 'ca' or 'users' but enabled = false: they would not be used");
    }
}

void readKnowledgeBase(Reader& r, const toml::table& root, CellFile& cell) {
    const toml::table* t = r.table(root, "kb", "[kb]");
    if (t == nullptr) return;
    auto& out = cell.kb;
    out.emplace();
    r.onlyKeys(*t, "[kb]", {"processes", "sparql-url", "restart", "host"});
    r.componentKeys(*t, "[kb]", "kb", cell);
    if (const toml::node* n = t->get("processes")) {
        const toml::array* a = n->as_array();
        if (a == nullptr) {
            r.wrongType(*n, "processes", "[kb]", "an array of Turtle files");
        } else {
            for (const auto& e : *a) {
                if (auto p = r.existingPath(e, "processes", "[kb]")) out->processes.push_back(*p);
            }
        }
    }
    if (auto url = r.string(*t, "sparql-url", "[kb]", false)) {
        if (url->rfind("http://", 0) != 0 && url->rfind("https://", 0) != 0) {
            r.problem(
                t->get("sparql-url")->source(),
                "'sparql-url' in [kb] must be an http:// or https:// URL, not \"" + *url + "\"");
        } else {
            out->sparqlUrl = *url;
        }
    }
}

void readMes(Reader& r, const toml::table& root, CellFile& cell) {
    const toml::table* t = r.table(root, "mes", "[mes]");
    if (t == nullptr) return;
    auto& out = cell.mes;
    out.emplace();
    r.onlyKeys(*t, "[mes]", {"step-timeout-ms", "restart", "host"});
    r.componentKeys(*t, "[mes]", "mes", cell);
    if (auto v = r.integer(*t, "step-timeout-ms", "[mes]", 100, 86'400'000)) {
        out->stepTimeoutMs = static_cast<int>(*v);
    }
}

void readDemo(Reader& r, const toml::table& root, CellFile& cell) {
    const toml::table* t = r.table(root, "demo", "[demo]");
    if (t == nullptr) return;
    r.onlyKeys(*t, "[demo]", {"process"});
    if (auto iri = r.string(*t, "process", "[demo]", true)) {
        if (iri->find("://") == std::string::npos) {
            r.problem(
                t->get("process")->source(),
                "'process' in [demo] must be a process IRI (http://...), not \"" + *iri + "\"");
        } else {
            cell.demoProcess = *iri;
        }
    }
}

void readDashboard(Reader& r, const toml::table& root, CellFile& cell) {
    const toml::table* t = r.table(root, "dashboard", "[dashboard]");
    if (t == nullptr) return;
    cell.dashboard.emplace();
    r.onlyKeys(*t, "[dashboard]", {"port", "restart", "host"});
    r.componentKeys(*t, "[dashboard]", "dashboard", cell);
    if (auto v = r.integer(*t, "port", "[dashboard]", 0, 65535)) {
        cell.dashboard->port = static_cast<int>(*v);
    }
}

/// Names must be unique among `kind`; reports the second one.
class NameSet {
public:
    explicit NameSet(std::string kind) : kind_(std::move(kind)) {}
    /// `t` is where the name stands: its 'name' key, or the table itself when the name is a
    /// default ([toolchanger] without one is "toolchanger").
    bool add(Reader& r, const toml::table& t, const std::string& name) {
        const toml::node* key = t.get("name");
        const toml::source_region& where = key != nullptr ? key->source() : t.source();
        auto [it, inserted] = lines_.emplace(name, static_cast<int>(t.source().begin.line));
        if (!inserted) {
            r.problem(where, kind_ + " '" + name + "' is defined twice (first on line " +
                                 std::to_string(it->second) + ")");
        }
        return inserted;
    }
    [[nodiscard]] bool has(const std::string& name) const { return lines_.count(name) != 0; }

private:
    std::string kind_;
    std::map<std::string, int> lines_;
};

void readWorld(Reader& r, const toml::table& root, CellFile& out, NameSet& docks) {
    const toml::table* t = r.table(root, "world", "[world]");
    if (t == nullptr) return;
    r.onlyKeys(*t, "[world]", {"dock", "object", "rail", "fuse-slot", "restart", "host"});
    r.componentKeys(*t, "[world]", "world", out);
    for (const toml::table* d : r.tables(*t, "dock", "world.dock")) {
        r.onlyKeys(*d, "[[world.dock]]", {"name", "pose"});
        auto name = r.name(*d, "[[world.dock]]");
        auto pose = r.pose(*d, "pose", "[[world.dock]]", true);
        if (name && docks.add(r, *d, *name) && pose) out.docks.push_back({*name, *pose});
    }
    // Rails, docks and objects share the world's ids.
    NameSet objects("object");
    for (const toml::table* rail : r.tables(*t, "rail", "world.rail")) {
        r.onlyKeys(*rail, "[[world.rail]]", {"name", "pose", "length"});
        auto name = r.name(*rail, "[[world.rail]]");
        auto pose = r.pose(*rail, "pose", "[[world.rail]]", true);
        auto length = r.number(*rail, "length", "[[world.rail]]", 0.01, 10);
        if (!length && rail->get("length") == nullptr) {
            r.problem(rail->source(), "[[world.rail]] needs 'length' (m)");
        }
        if (name && docks.has(*name)) {
            r.problem(rail->get("name")->source(),
                      "rail '" + *name + "': the name is a [[world.dock]]'s already");
        } else if (name && objects.add(r, *rail, *name) && pose && length) {
            out.rails.push_back({*name, *pose, *length});
        }
    }
    for (const toml::table* slot : r.tables(*t, "fuse-slot", "world.fuse-slot")) {
        r.onlyKeys(*slot, "[[world.fuse-slot]]", {"name", "pose", "misalignment"});
        auto name = r.name(*slot, "[[world.fuse-slot]]");
        auto pose = r.pose(*slot, "pose", "[[world.fuse-slot]]", true);
        std::array<double, 3> misalignment{};
        if (slot->get("misalignment") != nullptr) {
            auto m = r.numbers(*slot, "misalignment", "[[world.fuse-slot]]", {3},
                               "its terminals' offset from its pose, x, y, z in m", false);
            if (m &&
                std::any_of(m->begin(), m->end(), [](double v) { return std::abs(v) > 0.01; })) {
                r.problem(slot->get("misalignment")->source(),
                          "'misalignment' in [[world.fuse-slot]]: at most 0.01 m each way");
                m.reset();
            }
            if (!m) continue;
            misalignment = {(*m)[0], (*m)[1], (*m)[2]};
        }
        if (name && docks.has(*name)) {
            r.problem(slot->get("name")->source(),
                      "fuse slot '" + *name + "': the name is a [[world.dock]]'s already");
        } else if (name && objects.add(r, *slot, *name) && pose) {
            out.fuseSlots.push_back({*name, *pose, misalignment});
        }
    }
    static const std::vector<std::string_view> kinds = {"box", "terminal-block", "fuse"};
    for (const toml::table* o : r.tables(*t, "object", "world.object")) {
        r.onlyKeys(*o, "[[world.object]]", {"name", "size", "pose", "mass", "kind"});
        auto name = r.name(*o, "[[world.object]]");
        auto kind = WorldObject::Kind::Box;
        if (o->get("kind") != nullptr) {
            const auto k = r.oneOf(*o, "kind", "[[world.object]]", kinds, "an object kind");
            if (k == "terminal-block") kind = WorldObject::Kind::TerminalBlock;
            if (k == "fuse") kind = WorldObject::Kind::Fuse;
        }
        const auto mass = r.number(*o, "mass", "[[world.object]]", 1e-6, 10'000);
        auto size = r.numbers(*o, "size", "[[world.object]]", {3}, "edges x, y, z in m", true);
        auto pose = r.pose(*o, "pose", "[[world.object]]", true);
        if (size && std::any_of(size->begin(), size->end(), [](double e) { return e <= 0; })) {
            r.problem(o->get("size")->source(), "'size' in [[world.object]]: edges must be > 0");
            size.reset();
        }
        if (name && objects.add(r, *o, *name) && size && pose) {
            out.objects.push_back({*name, {(*size)[0], (*size)[1], (*size)[2]}, *pose, mass, kind});
        }
    }
}

/// Where the keys that are checked only after the whole file is read are (or the table that
/// lacks them), by the name of what they belong to.
struct KeySources {
    std::map<std::string, toml::source_region> changerRobot;  // tool changer -> its 'robot'
    std::map<std::string, toml::source_region> toolChanger;   // tool -> its 'changer'
};

void readTools(Reader& r, const toml::table& root, CellFile& out, const NameSet& docks,
               KeySources& sources) {
    NameSet names("tool");
    std::map<std::string, const toml::node*> dockUsers;  // one tool per dock
    struct Band {
        std::string tool;
        std::string changer;  // the tool's 'changer' key: one changer's tools must differ
        double lo, hi;
    };
    std::vector<Band> bands;
    for (const toml::table* t : r.tables(root, "tool", "tool")) {
        r.onlyKeys(*t, "[[tool]]",
                   {"name", "dock", "adapter", "grip-offset", "pin-voltage", "changer"});
        auto name = r.name(*t, "[[tool]]");
        const std::string where = name ? "tool '" + *name + "'" : std::string("[[tool]]");
        // Checked against the changers once they are read (checkToolChangers).
        const auto changer = r.string(*t, "changer", where, false).value_or("");
        auto dock = r.string(*t, "dock", where, true);
        if (dock && !docks.has(*dock)) {
            r.problem(t->get("dock")->source(),
                      where + ": dock '" + *dock + "' is not a [[world.dock]] of this cell");
            dock.reset();
        } else if (dock) {
            auto [it, first] = dockUsers.emplace(*dock, t->get("dock"));
            if (!first) {
                r.problem(t->get("dock")->source(),
                          where + ": dock '" + *dock + "' already holds another tool (line " +
                              std::to_string(it->second->source().begin.line) + ")");
                dock.reset();
            }
        }
        auto adapter = r.oneOf(*t, "adapter", where, adapterModels(), "a gripper model");
        auto offset = r.numbers(*t, "grip-offset", where, {3},
                                "its grip point from the mounting plate, x, y, z in m", true);
        auto band = r.numbers(*t, "pin-voltage", where, {2},
                              "the band the tool changer reads on its identification pin, "
                              "min and max in V",
                              true);
        if (band) {
            const double lo = (*band)[0];
            const double hi = (*band)[1];
            const auto* n = t->get("pin-voltage");
            if (!(lo < hi) || lo < devices::toolchanger::kNoToolVolts) {
                std::ostringstream m;
                m << where << ": 'pin-voltage' must be [MIN, MAX] with MIN < MAX and MIN >= "
                  << devices::toolchanger::kNoToolVolts << " V (below: no tool)";
                r.problem(n->source(), m.str());
                band.reset();
            } else {
                for (const auto& b : bands) {
                    if (b.changer == changer && lo <= b.hi && b.lo <= hi) {
                        r.problem(n->source(), where + ": 'pin-voltage' overlaps that of tool '" +
                                                   b.tool +
                                                   "': the changer could not tell them apart");
                        band.reset();
                        break;
                    }
                }
                if (band && name) bands.push_back({*name, changer, lo, hi});
            }
        }
        if (name && names.add(r, *t, *name) && dock && adapter && offset && band) {
            sources.toolChanger.emplace(
                *name, t->get("changer") != nullptr ? t->get("changer")->source() : t->source());
            out.tools.push_back({*name,
                                 *dock,
                                 *adapter,
                                 {(*offset)[0], (*offset)[1], (*offset)[2]},
                                 {(*band)[0], (*band)[1]},
                                 changer});
        }
    }
}

void readDevices(Reader& r, const toml::table& root, CellFile& out, NameSet& components,
                 KeySources& sources) {
    for (const toml::table* t : r.tables(root, "robot", "robot")) {
        r.onlyKeys(*t, "[[robot]]", {"name", "model", "speed", "base", "restart", "host"});
        auto name = r.name(*t, "[[robot]]");
        if (name) r.componentKeys(*t, "robot '" + *name + "'", *name, out);
        const std::string where = name ? "robot '" + *name + "'" : std::string("[[robot]]");
        auto model = r.oneOf(*t, "model", where, robotModels(), "a robot model");
        Robot robot;
        if (auto s = r.number(*t, "speed", where, 0.01, 1000)) robot.speed = *s;
        if (auto base = r.pose(*t, "base", where, false)) robot.base = *base;
        if (name && components.add(r, *t, *name) && model) {
            robot.name = *name;
            robot.model = *model;
            out.robots.push_back(std::move(robot));
        }
    }
    // A tool changer per robot, a pick-and-place composite per robot that should work at
    // once: [toolchanger] for one, [[toolchanger]] for several, and the same for [pickplace].
    for (const toml::table* t : r.tableOrTables(root, "toolchanger")) {
        r.onlyKeys(*t, "[toolchanger]", {"name", "model", "robot", "restart", "host"});
        ToolChanger changer;
        if (t->get("name") != nullptr) {
            if (auto name = r.name(*t, "[toolchanger]")) changer.name = *name;
        }
        const std::string where = "tool changer '" + changer.name + "'";
        r.componentKeys(*t, where, changer.name, out);
        if (auto model = r.string(*t, "model", where, false)) {
            if (*model != "kelvin") {
                r.problem(t->get("model")->source(),
                          "'model' in " + where + " must be \"kelvin\", not \"" + *model + "\"");
            }
        }
        changer.robot = r.string(*t, "robot", where, false).value_or("");
        if (components.add(r, *t, changer.name)) {
            sources.changerRobot.emplace(
                changer.name, t->get("robot") != nullptr ? t->get("robot")->source() : t->source());
            out.toolChangers.push_back(changer);
        }
    }
    for (const toml::table* t : r.tableOrTables(root, "pickplace")) {
        r.onlyKeys(*t, "[pickplace]", {"name", "restart", "host"});
        PickAndPlace composite;
        if (t->get("name") != nullptr) {
            if (auto name = r.name(*t, "[pickplace]")) composite.name = *name;
        }
        r.componentKeys(*t, "pick-and-place '" + composite.name + "'", composite.name, out);
        if (components.add(r, *t, composite.name)) out.pickAndPlaces.push_back(composite);
    }
}

/// Which robot each tool changer is on, and which changer each tool is for: said by their
/// 'robot' and 'changer' keys, which may be left out where there is only one to name.
/// `where`: the key (or the table without it) of each changer and tool, by name.
void checkToolChangers(Reader& r, CellFile& cell, const KeySources& where) {
    std::map<std::string, std::string> changerOn;  // robot -> the changer on it
    for (ToolChanger& c : cell.toolChangers) {
        const std::string what = "tool changer '" + c.name + "'";
        const toml::source_region at = where.changerRobot.at(c.name);
        if (c.robot.empty()) {
            if (cell.robots.size() == 1) {
                c.robot = cell.robots.front().name;
            } else if (cell.robots.size() > 1) {
                r.problem(at, what + ": say which [[robot]] it is on ('robot'): the cell has " +
                                  std::to_string(cell.robots.size()));
            }
            if (c.robot.empty()) continue;  // none at all: checkDependencies says so
        } else if (std::none_of(cell.robots.begin(), cell.robots.end(),
                                [&](const Robot& robot) { return robot.name == c.robot; })) {
            r.problem(at, what + ": 'robot' " + c.robot + " is not a [[robot]] of this cell");
            continue;
        }
        const auto [other, first] = changerOn.emplace(c.robot, c.name);
        if (!first) {
            r.problem(at, what + ": robot " + c.robot + " has tool changer '" + other->second +
                              "' already");
        }
    }
    for (Tool& tool : cell.tools) {
        const std::string what = "tool '" + tool.name + "'";
        const toml::source_region at = where.toolChanger.at(tool.name);
        if (tool.changer.empty()) {
            if (cell.toolChangers.size() == 1) {
                tool.changer = cell.toolChangers.front().name;
            } else if (cell.toolChangers.size() > 1) {
                r.problem(at, what +
                                  ": say which tool changer it is for ('changer'): the cell "
                                  "has " +
                                  std::to_string(cell.toolChangers.size()));
            }
        } else if (cell.toolChanger(tool.changer) == nullptr) {
            r.problem(at,
                      what + ": 'changer' " + tool.changer + " is not a tool changer of this cell");
        }
    }
}

/// What one part needs of another: reported once, at the part that needs it.
void checkDependencies(Reader& r, const toml::table& root, const CellFile& cell) {
    auto at = [&](std::string_view key) { return root.get(key)->source(); };
    const bool world = root.get("world") != nullptr;
    if (cell.mes && !cell.kb) {
        r.problem(at("mes"), "[mes] needs a [kb]: it reads the processes and skills there");
    }
    if (root.get("tool") != nullptr && cell.toolChangers.empty()) {
        r.problem(at("tool"), "[[tool]] needs a [toolchanger] to mount the tools");
    }
    if (!cell.toolChangers.empty() && (cell.robots.empty() || !world)) {
        r.problem(at("toolchanger"),
                  "[toolchanger] needs a [[robot]] to move and a [world] with its docks");
    }
    if (!cell.pickAndPlaces.empty() && (cell.robots.empty() || cell.toolChangers.empty())) {
        r.problem(at("pickplace"),
                  "[pickplace] needs a [[robot]] and a [toolchanger]: it composes their skills");
    }
    if (!cell.robots.empty() && !world) {
        r.problem(at("robot"), "[[robot]] needs a [world]: the robot reports its flange there");
    }
}

}  // namespace

std::string_view toString(RestartPolicy policy) {
    switch (policy) {
        case RestartPolicy::Always:
            return "always";
        case RestartPolicy::Never:
            return "never";
        case RestartPolicy::OnFailure:
            break;
    }
    return "on-failure";
}

RestartPolicy CellFile::restartPolicy(const std::string& component) const {
    const auto it = restart.find(component);
    return it == restart.end() ? RestartPolicy::OnFailure : it->second;
}

std::string CellFile::hostOf(const std::string& component) const {
    const auto it = hosts.find(component);
    return it == hosts.end() ? std::string() : it->second;
}

std::vector<std::string> CellFile::hostNames() const {
    std::vector<std::string> out;
    for (const auto& [component, host] : hosts) out.push_back(host);
    std::sort(out.begin(), out.end());
    out.erase(std::unique(out.begin(), out.end()), out.end());
    return out;
}

const ToolChanger* CellFile::toolChanger(const std::string& changer) const {
    for (const auto& c : toolChangers) {
        if (c.name == changer) return &c;
    }
    return nullptr;
}

const PickAndPlace* CellFile::pickAndPlace(const std::string& composite) const {
    for (const auto& p : pickAndPlaces) {
        if (p.name == composite) return &p;
    }
    return nullptr;
}

std::vector<std::string> CellFile::componentNames() const {
    std::vector<std::string> out;
    if (lds) out.emplace_back("lds");
    if (kb) out.emplace_back("kb");
    if (!docks.empty() || !objects.empty() || !robots.empty()) out.emplace_back("world");
    for (const auto& c : toolChangers) out.push_back(c.name);
    for (const auto& r : robots) out.push_back(r.name);
    for (const auto& p : pickAndPlaces) out.push_back(p.name);
    if (mes) out.emplace_back("mes");
    if (dashboard) out.emplace_back("dashboard");
    return out;
}

std::string hostProblem(const CellFile& cell, std::string_view host) {
    const bool named = !host.empty() && host.size() <= 12 &&
                       std::islower(static_cast<unsigned char>(host.front())) != 0 &&
                       std::all_of(host.begin(), host.end(), [](char c) {
                           return std::islower(static_cast<unsigned char>(c)) != 0 ||
                                  std::isdigit(static_cast<unsigned char>(c)) != 0 || c == '-';
                       });
    if (!named) {
        return "host '" + std::string(host) +
               "': use 1 to 12 lower-case letters, digits or '-', beginning with a letter (it "
               "names the host's link, v-" +
               std::string(host) + ")";
    }
    if (cell.network.kind != Network::Kind::PrivateNamespace) {
        return "host '" + std::string(host) +
               "' needs network.kind = \"private\": a host is a network namespace beside the "
               "cell's";
    }
    return {};
}

std::string placeOnHost(CellFile& cell, const std::string& component, const std::string& host) {
    const auto names = cell.componentNames();
    if (std::find(names.begin(), names.end(), component) == names.end()) {
        return "the cell has no component '" + component + "'; it has: " + joined(names);
    }
    if (auto why = hostProblem(cell, host); !why.empty()) return why;
    cell.hosts[component] = host;
    return {};
}

std::string Problem::describe() const {
    if (line <= 0) return file + ": " + message;
    return file + ":" + std::to_string(line) + ":" + std::to_string(column) + ": " + message;
}

const std::vector<std::string_view>& adapterModels() {
    static const std::vector<std::string_view> names = [] {
        std::vector<std::string_view> out;
        for (const auto& m : adapterModelTable()) out.push_back(m.name);
        return out;
    }();
    return names;
}

const std::vector<std::string_view>& robotModels() {
    static const std::vector<std::string_view> models = {"ur5", "iiwa"};
    return models;
}

ReadResult readCellText(std::string_view text, const std::string& sourceName,
                        const std::filesystem::path& baseDirectory) {
    ReadResult result;
    toml::table root;
    try {
        root = toml::parse(text, sourceName);
    } catch (const toml::parse_error& e) {
        result.problems.push_back({sourceName, static_cast<int>(e.source().begin.line),
                                   static_cast<int>(e.source().begin.column),
                                   std::string(e.description())});
        return result;
    }
    Reader r(sourceName, baseDirectory);
    CellFile cell;
    r.onlyKeys(root, "the cell file",
               {"name", "network", "security", "lds", "kb", "mes", "demo", "dashboard", "world",
                "tool", "robot", "toolchanger", "pickplace"});
    if (auto name = r.name(root, "the cell file")) cell.name = *name;
    readNetwork(r, root, cell.network);
    readSecurity(r, root, cell.security);
    if (const toml::table* t = r.table(root, "lds", "[lds]")) {
        r.onlyKeys(*t, "[lds]", {"restart", "host"});
        r.componentKeys(*t, "[lds]", "lds", cell);
        cell.lds = true;
    }
    readKnowledgeBase(r, root, cell);
    readMes(r, root, cell);
    readDemo(r, root, cell);
    readDashboard(r, root, cell);
    NameSet docks("dock");
    readWorld(r, root, cell, docks);
    KeySources sources;
    readTools(r, root, cell, docks, sources);
    NameSet components("component");
    readDevices(r, root, cell, components, sources);
    checkToolChangers(r, cell, sources);
    checkDependencies(r, root, cell);
    result.problems = r.takeProblems();
    std::stable_sort(result.problems.begin(), result.problems.end(),
                     [](const Problem& a, const Problem& b) {
                         return std::tie(a.line, a.column) < std::tie(b.line, b.column);
                     });
    if (result.problems.empty()) result.cell = std::move(cell);
    return result;
}

ReadResult readCellFile(const std::filesystem::path& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) {
        return {std::nullopt,
                {{path.string(), 0, 0, "cannot open: " + std::string(std::strerror(errno))}}};
    }
    std::ostringstream text;
    text << in.rdbuf();
    auto base = path.parent_path();
    if (base.empty()) base = ".";
    auto result = readCellText(text.str(), path.string(), base);
    if (result.cell) result.cell->path = path;
    return result;
}

}  // namespace skillcell::cell
