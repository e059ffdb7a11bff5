// `skillcell kb` as a component of a cell (in a private network namespace, with discovery):
// a component that starts is in the knowledge base, without anyone telling it, within a
// bounded time; after it stops, its skills are there still, marked unavailable.
#include <gtest/gtest.h>

#include <chrono>
#include <csignal>
#include <filesystem>
#include <fstream>
#include <random>
#include <set>
#include <sstream>
#include <thread>

#include "component_process.hpp"
#include "http/http_client.hpp"
#include "process_tree.hpp"
#include "temp_dir.hpp"
#include "ua/server/user_database.hpp"

namespace skillcell::kb::kb_component_test {
namespace {

using namespace std::chrono_literals;
namespace fs = std::filesystem;

const std::vector<std::string> kFastMdns{"--mdns-ttl", "5", "--mdns-query-period", "1"};

std::vector<std::string> with(std::vector<std::string> args, const std::vector<std::string>& more) {
    args.insert(args.end(), more.begin(), more.end());
    return args;
}

// The port of the "SPARQL http://127.0.0.1:PORT/sparql" line.
std::uint16_t sparqlPort(const test::ComponentProcess& p) {
    for (const auto& line : p.output()) {
        if (line.rfind("SPARQL http://127.0.0.1:", 0) == 0) {
            return static_cast<std::uint16_t>(std::stoi(line.substr(24)));
        }
    }
    return 0;
}

// A client of the plain-HTTP endpoint that a KB with --insecure serves on loopback.
http::HttpClient plainClient(std::uint16_t port) {
    http::HttpUrl url;
    url.port = port;
    http::ClientOptions o;
    o.timeout = 30s;
    return http::HttpClient(url, o);
}

std::string select(std::uint16_t port, const std::string& q) {
    auto reply =
        plainClient(port).get("/sparql", {{"query", q}}, "application/sparql-results+json");
    return reply ? reply->body : reply.error();
}

bool ask(std::uint16_t port, const std::string& pattern) {
    const std::string q =
        "PREFIX proc: <http://skillcell.dev/ontology/process#>\n"
        "PREFIX rskill: <http://skillcell.dev/UA/RoboticSkills/>\n"
        "PREFIX rdfs: <http://www.w3.org/2000/01/rdf-schema#>\n"
        "ASK { " +
        pattern + " }";
    auto reply =
        plainClient(port).get("/sparql", {{"query", q}}, "application/sparql-results+json");
    return reply && reply->status == 200 && reply->body.find("true") != std::string::npos;
}

// Asks until the answer is yes, at most `limit`; the time it took, or nullopt.
std::optional<std::chrono::milliseconds> askUntilTrue(std::uint16_t port, const std::string& q,
                                                      std::chrono::milliseconds limit) {
    const auto start = std::chrono::steady_clock::now();
    for (int attempt = 0; attempt < 1000; ++attempt) {
        if (ask(port, q)) {
            return std::chrono::duration_cast<std::chrono::milliseconds>(
                std::chrono::steady_clock::now() - start);
        }
        if (std::chrono::steady_clock::now() - start > limit) break;
        std::this_thread::sleep_for(100ms);  // the interval of a bounded poll of the KB
    }
    return std::nullopt;
}

TEST(KnowledgeBaseComponent, LearnsAComponentsSkillsByDiscoveryAndKeepsThemMarkedWhenItLeaves) {
    const test::TempDir dir("skillcell-kb-cell");
    const fs::path& data = dir.path();

    test::ComponentProcess kb(
        SKILLCELL_BINARY, with({"kb", "--http-port", "0", "--data-dir", data.string()}, kFastMdns),
        true);
    ASSERT_FALSE(kb.url().empty()) << "skillcell kb did not start";
    const std::uint16_t port = sparqlPort(kb);
    ASSERT_NE(port, 0) << "no SPARQL line";

    const std::string mover =
        "?c proc:applicationUri \"urn:test:mover\" ; proc:offers ?s . "
        "?s a rskill:CartesianLinearMoveSkillType ; proc:available ";
    EXPECT_FALSE(ask(port, mover + "true"));
    {
        test::ComponentProcess component(SKILLCELL_BINARY,
                                         with({"server", "--application-uri", "urn:test:mover",
                                               "--noop-skill", "CartesianLinearMoveSkillType=Move"},
                                              kFastMdns),
                                         true);
        ASSERT_FALSE(component.url().empty());
        const auto took = askUntilTrue(port, mover + "true", 30s);
        ASSERT_TRUE(took) << "the KB did not learn the component's skill within 30 s";
        std::cout << "the KB answered about the new component's skill after " << took->count()
                  << " ms\n";
        // Its graph names the component as available too.
        EXPECT_TRUE(ask(port, "?c proc:applicationUri \"urn:test:mover\" ; proc:available true"));
    }  // SIGTERM: the component says goodbye
    ASSERT_TRUE(askUntilTrue(port, mover + "false", 30s))
        << "the KB did not mark the skill unavailable within 30 s";
    EXPECT_FALSE(ask(port, mover + "true"))
        << select(port,
                  "SELECT ?g ?s ?v WHERE { GRAPH ?g { ?s "
                  "<http://skillcell.dev/ontology/process#available> ?v } }");
    EXPECT_TRUE(ask(port, "?c proc:applicationUri \"urn:test:mover\" ; proc:available false"));
}

// The reasoner killed while it checks a component (as the chaos suite's konclude trials do):
// the component is recorded again after a pause, not left out until its skills next change.
TEST(KnowledgeBaseComponent, AComponentWhoseRecordingFailedIsRecordedAgain) {
    const test::TempDir dir("skillcell-kb-retry");
    const fs::path data = dir.path() / "data";
    const fs::path killNext = dir.path() / "kill-next-konclude";
    // Konclude, except that the run after `killNext` appears is killed as it starts.
    const fs::path konclude = dir.path() / "konclude";
    {
        std::ofstream script(konclude);
        script << "#!/bin/sh\nif rm " << killNext << " 2>/dev/null; then kill -9 $$; fi\n"
               << "exec /usr/bin/Konclude \"$@\"\n";
    }
    fs::permissions(konclude, fs::perms::owner_all);
    test::ComponentProcess kb(SKILLCELL_BINARY,
                              with({"kb", "--http-port", "0", "--data-dir", data.string(),
                                    "--konclude", konclude.string()},
                                   kFastMdns),
                              true);
    ASSERT_FALSE(kb.url().empty()) << "skillcell kb did not start";
    const std::uint16_t port = sparqlPort(kb);
    ASSERT_NE(port, 0) << "no SPARQL line";

    std::ofstream(killNext).put('\n');
    test::ComponentProcess component(SKILLCELL_BINARY,
                                     with({"server", "--application-uri", "urn:test:retried",
                                           "--noop-skill", "CartesianLinearMoveSkillType=Move"},
                                          kFastMdns),
                                     true);
    ASSERT_FALSE(component.url().empty());
    const auto took = askUntilTrue(port,
                                   "?c proc:applicationUri \"urn:test:retried\" ; proc:offers ?s . "
                                   "?s a rskill:CartesianLinearMoveSkillType ; proc:available true",
                                   20s);
    EXPECT_FALSE(fs::exists(killNext)) << "no Konclude run was killed: the test tested nothing";
    EXPECT_TRUE(took) << "the component was not recorded again within 20 s";
}

// A reasoner that cannot run would fail every recording, again and again: the KB refuses to
// start, naming it, before it starts anything.
TEST(KnowledgeBaseComponent, AReasonerThatCannotRunStopsTheKbAtItsStartNamingIt) {
    const test::TempDir dir("skillcell-kb-no-reasoner");
    const fs::path errors = dir.path() / "kb.err";
    auto kb = process::ChildProcess::start(
        {SKILLCELL_BINARY, "kb", "--insecure", "--no-discovery", "--data-dir",
         (dir.path() / "data").string(), "--konclude", "/nonexistent/Konclude"},
        process::reportingChild(errors));
    ASSERT_TRUE(kb) << kb.error();
    const auto ended = kb->wait(30s);
    ASSERT_TRUE(ended) << ended.error();
    EXPECT_FALSE(ended->success());
    std::stringstream text;
    text << std::ifstream(errors).rdbuf();
    EXPECT_NE(text.str().find("--konclude /nonexistent/Konclude: no such executable"),
              std::string::npos)
        << text.str();
    EXPECT_FALSE(fs::exists(dir.path() / "data" / "virtuoso.lck")) << "Virtuoso was started";
}

TEST(KnowledgeBaseComponent, LoadsTheModelOfASkillTypeOfItsOwnWhenItsComponentAppears) {
    const test::TempDir dir("skillcell-kb-cell");
    const fs::path& data = dir.path();
    const std::string examples = SKILLCELL_SOURCE_DIR "/examples/dispense_skill";
    test::ComponentProcess kb(
        SKILLCELL_BINARY,
        with({"kb", "--http-port", "0", "--data-dir", data.string(), "--models", examples},
             kFastMdns),
        true);
    ASSERT_FALSE(kb.url().empty()) << "skillcell kb did not start";
    const std::uint16_t port = sparqlPort(kb);
    ASSERT_NE(port, 0) << "no SPARQL line";
    // Not a model the KB carries: it is loaded when a component offers a skill of its type.
    const std::string typed =
        "<http://skillcell.dev/UA/Examples/Dispense/DispenseSkillType> "
        "<http://www.w3.org/2000/01/rdf-schema#subClassOf>+ "
        "<http://skillcell.dev/UA/Skills/SkillType>";
    EXPECT_FALSE(ask(port, typed));
    test::ComponentProcess dispenser(
        SKILLCELL_BINARY,
        with({"server", "--application-uri", "urn:test:dispenser", "--nodeset",
              examples + "/Example.DispenseSkill.NodeSet2.xml", "--noop-skill",
              "DispenseSkillType=Dispense"},
             kFastMdns),
        true);
    ASSERT_FALSE(dispenser.url().empty());
    ASSERT_TRUE(askUntilTrue(port,
                             "?c proc:applicationUri \"urn:test:dispenser\" ; proc:offers ?s . ?s "
                             "a <http://skillcell.dev/UA/Examples/Dispense/DispenseSkillType> ; "
                             "proc:available true",
                             30s))
        << "the KB did not learn the dispense skill within 30 s";
    EXPECT_TRUE(ask(port, typed));
}

TEST(KnowledgeBaseComponent, RecordsTheParameterValuesAndGripTypesItReadsFromComponents) {
    const test::TempDir dir("skillcell-kb-cell");
    const fs::path& data = dir.path();
    test::ComponentProcess kb(
        SKILLCELL_BINARY, with({"kb", "--http-port", "0", "--data-dir", data.string()}, kFastMdns),
        true);
    ASSERT_FALSE(kb.url().empty()) << "skillcell kb did not start";
    const std::uint16_t port = sparqlPort(kb);
    ASSERT_NE(port, 0) << "no SPARQL line";
    // A Grasp skill with the model's defaults (GripPointType 0, PARALLEL), and the Schmalz
    // adapter, whose Grasp says VACUUM and has the grip point it was started with.
    test::ComponentProcess parallel(SKILLCELL_BINARY,
                                    with({"server", "--application-uri", "urn:test:parallel",
                                          "--noop-skill", "GraspGripperSkillType=Grasp"},
                                         kFastMdns),
                                    true);
    ASSERT_FALSE(parallel.url().empty());
    test::ComponentProcess vacuum(SKILLCELL_BINARY,
                                  with({"device", "schmalz", "--application-uri", "urn:test:vacuum",
                                        "--grip-offset", "0,0,0.12"},
                                       kFastMdns),
                                  true);
    ASSERT_FALSE(vacuum.url().empty());
    const std::string grasp =
        "?s a <http://skillcell.dev/UA/GripperSkills/GraspGripperSkillType> ; "
        "proc:available true ; ";
    ASSERT_TRUE(askUntilTrue(port,
                             "?c proc:applicationUri \"urn:test:parallel\" ; proc:offers ?s . " +
                                 grasp + "proc:gripType \"parallel\"",
                             30s))
        << "the KB did not record the parallel grasp's grip type within 30 s";
    ASSERT_TRUE(askUntilTrue(port,
                             "?c proc:applicationUri \"urn:test:vacuum\" ; proc:offers ?s . " +
                                 grasp + "proc:gripType \"vacuum\"",
                             30s))
        << "the KB did not record the vacuum grasp's grip type within 30 s";
    // The enumeration by its name (EnumStrings on the component), the pose as decimals.
    EXPECT_TRUE(ask(port,
                    "?c proc:applicationUri \"urn:test:parallel\" ; proc:offers ?s . ?s "
                    "proc:hasParameterValue ?p . ?p a proc:Parameter ; proc:parameterName "
                    "\"GripPointType\" ; proc:textValue \"PARALLEL\""));
    EXPECT_TRUE(ask(port,
                    "?c proc:applicationUri \"urn:test:vacuum\" ; proc:offers ?s . ?s "
                    "proc:hasParameterValue ?p . ?p proc:parameterName \"GripPointType\" ; "
                    "proc:textValue \"VACUUM\""));
    const std::string offset =
        "?c proc:applicationUri \"urn:test:vacuum\" ; proc:offers ?s . ?s proc:skillName ?n ; "
        "proc:hasParameterValue ?p . FILTER(STRENDS(?n, \"Grasp\")) ?p proc:parameterName "
        "\"GripPointOffset\" ; proc:poseValue ?pose . ?pose a proc:Pose ; proc:x ?x ; proc:z ?z "
        ". ";
    EXPECT_TRUE(ask(port, offset + "FILTER(?x = 0 && ?z = 0.12)"))
        << select(port,
                  "SELECT ?p ?o WHERE { ?s <http://skillcell.dev/ontology/process#poseValue> ?p . "
                  "?p ?q ?o }");
    EXPECT_FALSE(ask(port, offset + "FILTER(?z != 0.12)"));
}

TEST(KnowledgeBaseComponent, LoadsTheModelsOfTheNamespacesAComponentUsesNotOnlyOfItsSkillTypes) {
    const test::TempDir dir("skillcell-kb-cell");
    const fs::path& data = dir.path();
    const std::string examples = SKILLCELL_SOURCE_DIR "/examples/dispense_skill";
    test::ComponentProcess kb(
        SKILLCELL_BINARY,
        with({"kb", "--http-port", "0", "--data-dir", data.string(), "--models", examples},
             kFastMdns),
        true);
    ASSERT_FALSE(kb.url().empty()) << "skillcell kb did not start";
    const std::uint16_t port = sparqlPort(kb);
    ASSERT_NE(port, 0) << "no SPARQL line";
    const std::string dispenseModel =
        "<http://skillcell.dev/UA/Examples/Dispense/DispenseSkillType> "
        "<http://www.w3.org/2000/01/rdf-schema#subClassOf>+ "
        "<http://skillcell.dev/UA/Skills/SkillType>";
    EXPECT_FALSE(ask(port, dispenseModel));
    // The dispense model is in its NamespaceArray, but it offers only a move skill.
    test::ComponentProcess mover(SKILLCELL_BINARY,
                                 with({"server", "--application-uri", "urn:test:mover", "--nodeset",
                                       examples + "/Example.DispenseSkill.NodeSet2.xml",
                                       "--noop-skill", "CartesianLinearMoveSkillType=Move"},
                                      kFastMdns),
                                 true);
    ASSERT_FALSE(mover.url().empty());
    // The models come before the component's graph: once its skill is there, so are they.
    ASSERT_TRUE(askUntilTrue(port,
                             "?c proc:applicationUri \"urn:test:mover\" ; proc:offers ?s . ?s a "
                             "rskill:CartesianLinearMoveSkillType ; proc:available true",
                             30s))
        << "the KB did not learn the move skill within 30 s";
    EXPECT_TRUE(ask(port, dispenseModel));
    EXPECT_FALSE(ask(port, "?s a <http://skillcell.dev/UA/Examples/Dispense/DispenseSkillType>"));
}

// A SPARQL 1.1 update over HTTP (the KB started with --http-writes); the HTTP status.
int update(std::uint16_t port, const std::string& sparqlUpdate) {
    auto reply = plainClient(port).postForm("/sparql", {{"update", sparqlUpdate}}, "");
    return reply ? reply->status : 0;
}

TEST(KnowledgeBaseComponent, AnAcknowledgedUpdateSurvivesAKillOfTheKbProcess) {
    const test::TempDir dir("skillcell-kb-kill");
    const fs::path& data = dir.path();
    const std::vector<std::string> args = {
        "kb", "--http-port", "0", "--data-dir", data.string(), "--http-writes", "--no-discovery"};
    const std::string fact = "GRAPH <urn:test:kill> { <urn:test:a> <urn:test:b> \"acknowledged\" }";
    {
        test::ComponentProcess kb(SKILLCELL_BINARY, args);
        ASSERT_FALSE(kb.url().empty()) << "skillcell kb did not start";
        const std::uint16_t port = sparqlPort(kb);
        ASSERT_NE(port, 0);
        ASSERT_EQ(update(port, "INSERT DATA { " + fact + " }"), 200);
        // SIGKILL: no shutdown at all. Virtuoso goes with it (it is tied to the KB's life).
        const auto status = kb.kill(SIGKILL);
        ASSERT_TRUE(status && status->signal == SIGKILL);
    }
    test::ComponentProcess again(SKILLCELL_BINARY, args);
    ASSERT_FALSE(again.url().empty()) << "skillcell kb did not start again on the same data";
    const std::uint16_t port = sparqlPort(again);
    ASSERT_NE(port, 0);
    EXPECT_TRUE(ask(port, fact)) << select(port,
                                           "SELECT * WHERE { GRAPH <urn:test:kill> { ?s ?p ?o } }");
    // And the KB's own models, as after any start.
    EXPECT_TRUE(ask(port, "GRAPH <http://skillcell.dev/ontology/process> { ?s ?p ?o }"));
}

// The KB's Virtuoso killed on its own (the KB stays): the KB starts it again on the same data,
// and what was acknowledged before is there; meanwhile queries fail and are asked again.
TEST(KnowledgeBaseComponent, AKilledVirtuosoIsStartedAgainOnItsDataByTheKb) {
    const test::TempDir dir("skillcell-kb-virtuoso-kill");
    test::ComponentProcess kb(SKILLCELL_BINARY,
                              {"kb", "--http-port", "0", "--data-dir", dir.path().string(),
                               "--http-writes", "--no-discovery"});
    ASSERT_FALSE(kb.url().empty()) << "skillcell kb did not start";
    const std::uint16_t port = sparqlPort(kb);
    ASSERT_NE(port, 0);
    const std::string fact = "GRAPH <urn:test:vkill> { <urn:test:a> <urn:test:b> \"kept\" }";
    ASSERT_EQ(update(port, "INSERT DATA { " + fact + " }"), 200);
    auto virtuosoOf = [&]() -> pid_t {
        for (const pid_t child : test::childrenOf(kb.pid())) {
            std::ifstream comm("/proc/" + std::to_string(child) + "/comm");
            std::string name;
            if (std::getline(comm, name) && name == "virtuoso-t") return child;
        }
        return 0;
    };
    const pid_t first = virtuosoOf();
    ASSERT_NE(first, 0) << "no virtuoso-t among the KB's children";
    ASSERT_EQ(::kill(first, SIGKILL), 0);
    const auto took = askUntilTrue(port, fact, 90s);
    ASSERT_TRUE(took) << "the KB did not answer from its data within 90 s of Virtuoso's death";
    std::cout << "the KB answered again " << took->count() << " ms after Virtuoso was killed\n";
    const pid_t second = virtuosoOf();
    EXPECT_NE(second, 0);
    EXPECT_NE(second, first);
    // And it takes updates again.
    EXPECT_EQ(
        update(port, "INSERT DATA { GRAPH <urn:test:vkill> { <urn:test:c> <urn:test:d> 1 } }"),
        200);
}

TEST(KnowledgeBaseComponent, UsesAnyStoreGivenBySparqlUrlInsteadOfItsOwnVirtuoso) {
    const test::TempDir dir("skillcell-kb-url");
    const fs::path& data = dir.path();
    // The store: another KB's endpoint, a SPARQL 1.1 endpoint like any other.
    test::ComponentProcess store(
        SKILLCELL_BINARY,
        {"kb", "--http-port", "0", "--data-dir", data.string(), "--http-writes", "--no-discovery"});
    ASSERT_FALSE(store.url().empty());
    const std::uint16_t storePort = sparqlPort(store);
    ASSERT_NE(storePort, 0);
    test::ComponentProcess kb(
        SKILLCELL_BINARY,
        {"kb", "--http-port", "0", "--demo-process", "--http-writes", "--no-discovery",
         "--sparql-url", "http://127.0.0.1:" + std::to_string(storePort) + "/sparql"});
    ASSERT_FALSE(kb.url().empty()) << "skillcell kb --sparql-url did not start";
    const std::uint16_t port = sparqlPort(kb);
    ASSERT_NE(port, 0);
    for (const auto& line : kb.output()) {
        EXPECT_EQ(line.find("starting Virtuoso"), std::string::npos) << line;
    }
    // What it loaded (the demo process) is in the store; what is written through it too.
    EXPECT_TRUE(
        ask(storePort, "GRAPH <http://skillcell.dev/demo> { ?s proc:requiresSkillType ?t }"));
    ASSERT_EQ(update(port, "INSERT DATA { GRAPH <urn:test:url> { <urn:test:x> <urn:test:y> 1 } }"),
              200);
    EXPECT_TRUE(ask(storePort, "GRAPH <urn:test:url> { <urn:test:x> <urn:test:y> 1 }"));
    EXPECT_TRUE(ask(port, "GRAPH <urn:test:url> { <urn:test:x> <urn:test:y> 1 }"));
    // A URL that is not one is refused at once, with the reason.
    test::ComponentProcess bad(SKILLCELL_BINARY, {"kb", "--http-port", "0", "--no-discovery",
                                                  "--sparql-url", "ftp://127.0.0.1/sparql"});
    EXPECT_TRUE(bad.url().empty());
    const auto status = bad.kill(SIGTERM);  // it has exited already: this reaps it
    ASSERT_TRUE(status);
    EXPECT_EQ(status->code, 2) << status->describe();
}

// --- Security: HTTPS for the cell's users, and no anonymous way in on any port --------------

// The TCP ports that `pid` and its children (Virtuoso) listen on, from /proc.
std::set<std::uint16_t> listeningPorts(pid_t pid) {
    std::set<pid_t> pids{pid};
    for (const auto& e : fs::directory_iterator("/proc")) {
        const std::string name = e.path().filename();
        if (name.find_first_not_of("0123456789") != std::string::npos) continue;
        std::ifstream stat(e.path() / "stat");
        std::string line;
        std::getline(stat, line);
        const auto close = line.rfind(')');  // the command may hold blanks
        if (close == std::string::npos) continue;
        std::istringstream rest(line.substr(close + 2));
        std::string state;
        pid_t parent = 0;
        rest >> state >> parent;
        if (parent == pid) pids.insert(std::stoi(name));
    }
    std::set<std::string> inodes;
    for (const pid_t p : pids) {
        std::error_code ec;
        for (const auto& fd : fs::directory_iterator("/proc/" + std::to_string(p) + "/fd", ec)) {
            const auto target = fs::read_symlink(fd.path(), ec).string();
            if (target.rfind("socket:[", 0) == 0) {
                inodes.insert(target.substr(8, target.size() - 9));
            }
        }
    }
    std::set<std::uint16_t> ports;
    for (const char* table : {"/proc/net/tcp", "/proc/net/tcp6"}) {
        std::ifstream in(table);
        std::string line;
        std::getline(in, line);  // the header
        while (std::getline(in, line)) {
            std::istringstream f(line);
            std::string slot, local, remote, state, queues, timer, retransmits, uid, timeout, inode;
            f >> slot >> local >> remote >> state >> queues >> timer >> retransmits >> uid >>
                timeout >> inode;
            if (state == "0A" && inodes.count(inode) != 0) {  // 0A: LISTEN
                ports.insert(static_cast<std::uint16_t>(
                    std::stoul(local.substr(local.find(':') + 1), nullptr, 16)));
            }
        }
    }
    return ports;
}

TEST(KnowledgeBaseComponent, ServesHttpsToTheCellsUsersAndNothingToAnyoneOnAnyPort) {
    const test::TempDir dir("skillcell-kb-secure");
    ua::UserDatabase users;
    ASSERT_TRUE(users.setPassword("olga", ua::RoleSet{ua::Role::Observer}, "o-secret-1").isGood());
    ASSERT_TRUE(users.setPassword("emil", ua::RoleSet{ua::Role::Engineer}, "e-secret-2").isGood());
    ASSERT_TRUE(users.save(dir.path() / "users").isGood());
    test::ComponentProcess kb(
        SKILLCELL_BINARY,
        {"kb", "--http-port", "0", "--data-dir", (dir.path() / "data").string(), "--users",
         (dir.path() / "users").string()},
        false, /*insecure=*/false);
    ASSERT_FALSE(kb.url().empty()) << "skillcell kb did not start";
    std::uint16_t port = 0;
    for (const auto& line : kb.output()) {
        if (line.rfind("SPARQL https://localhost:", 0) == 0) {
            port = static_cast<std::uint16_t>(std::stoi(line.substr(25)));
        }
    }
    ASSERT_NE(port, 0) << "no 'SPARQL https://localhost:PORT' line";
    // The clients trust the KB's own certificate, as a cell's trust list would.
    std::ifstream certFile(kb.pkiDir() / "own/certs/cert.der", std::ios::binary);
    const ua::ByteString kbCertificate{
        std::vector<std::uint8_t>(std::istreambuf_iterator<char>(certFile), {})};
    ASSERT_FALSE(kbCertificate.empty());
    auto client = [&](const std::string& user, const std::string& password) {
        http::ClientOptions o;
        o.timeout = 30s;
        o.verifyServer = [kbCertificate](const ua::ByteString& der, std::string*) {
            return der == kbCertificate;
        };
        if (!user.empty()) o.auth = {http::ClientAuth::Kind::Basic, user, password};
        http::HttpUrl url;
        url.tls = true;
        url.host = "localhost";
        url.port = port;
        return std::make_unique<http::HttpClient>(url, o);
    };
    const std::string evil = "INSERT DATA { GRAPH <http://evil.example/> { <urn:e> <urn:v> 1 } }";
    const std::string fact = "INSERT DATA { GRAPH <urn:test:secure> { <urn:a> <urn:b> 1 } }";
    auto olga = client("olga", "o-secret-1");
    auto emil = client("emil", "e-secret-2");
    auto askAs = [](http::HttpClient& c, const std::string& graph) {
        auto r = c.get("/sparql", {{"query", "ASK { GRAPH <" + graph + "> { ?s ?p ?o } }"}},
                       "application/sparql-results+json");
        return r && r->status == 200 && r->body.find("true") != std::string::npos;
    };
    // An Observer reads, and may not write, however the update is sent.
    auto read = olga->get("/sparql", {{"query", "ASK {}"}}, "application/sparql-results+json");
    ASSERT_TRUE(read) << read.error();
    EXPECT_EQ(read->status, 200) << read->body;
    for (const char* field : {"update", "query"}) {
        auto refused = olga->postForm("/sparql", {{field, fact}}, "");
        ASSERT_TRUE(refused) << refused.error();
        EXPECT_EQ(refused->status, 403) << field << ": " << refused->body;
    }
    // An Engineer writes.
    auto written = emil->postForm("/sparql", {{"update", fact}}, "");
    ASSERT_TRUE(written) << written.error();
    EXPECT_EQ(written->status, 200) << written->body;
    EXPECT_TRUE(askAs(*olga, "urn:test:secure"));
    // A wrong password is nobody.
    auto wrong = client("emil", "o-secret-1")->postForm("/sparql", {{"update", evil}}, "");
    ASSERT_TRUE(wrong) << wrong.error();
    EXPECT_EQ(wrong->status, 401);

    // Every TCP port of the KB and its Virtuoso, over http and https, anonymously: an
    // INSERT (as update and as query) and a SELECT are refused, or get no HTTP answer.
    const auto ports = listeningPorts(kb.pid());
    EXPECT_GE(ports.size(), 4U) << "expected the OPC UA and SPARQL ports, Virtuoso's SQL and HTTP";
    EXPECT_EQ(ports.count(port), 1U);
    int answered = 0;
    for (const std::uint16_t p : ports) {
        for (const bool tls : {false, true}) {
            http::HttpUrl url;
            url.tls = tls;
            url.host = "localhost";
            url.port = p;
            http::ClientOptions anyone;
            // Bounded: a port that does not speak HTTP (OPC UA, Virtuoso's SQL) keeps quiet.
            anyone.timeout = 2s;
            // Trusting every certificate: what is tested is the refusal, not TLS.
            anyone.verifyServer = [](const ua::ByteString&, std::string*) { return true; };
            http::HttpClient anonymous(url, anyone);
            bool speaksHttp = true;
            for (const char* path : {"/sparql", "/sparql-auth", "/sparql-graph-crud"}) {
                for (const auto& [field, text] : std::vector<std::pair<std::string, std::string>>{
                         {"query", "SELECT * { ?s ?p ?o }"}, {"update", evil}, {"query", evil}}) {
                    if (!speaksHttp) break;
                    auto r = anonymous.postForm(path, {{field, text}}, "");
                    if (!r) {  // no HTTP answer: refused too, and nothing more to ask here
                        speaksHttp = false;
                        break;
                    }
                    ++answered;
                    EXPECT_TRUE(r->status == 400 || r->status == 401 || r->status == 403 ||
                                r->status == 404 || r->status == 405)
                        << url.toString() << path << " " << field << ": HTTP " << r->status << ": "
                        << r->body.substr(0, 300);
                }
            }
        }
    }
    EXPECT_GT(answered, 0);  // the HTTP servers did answer: the refusals are theirs
    EXPECT_FALSE(askAs(*emil, "http://evil.example/"));
}

}  // namespace
}  // namespace skillcell::kb::kb_component_test
