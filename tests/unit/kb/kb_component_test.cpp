// `skillcell kb` as a component of a cell (in a private network namespace, with discovery):
// a component that starts is in the knowledge base, without anyone telling it, within a
// bounded time; after it stops, its skills are there still, marked unavailable.
#include <gtest/gtest.h>

#include <chrono>
#include <filesystem>
#include <random>
#include <thread>

#include "component_process.hpp"
#include "kb/http/http_client.hpp"
#include "kb/http/http_message.hpp"
#include "temp_dir.hpp"

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

std::string select(std::uint16_t port, const std::string& q) {
    http::HttpRequest r;
    r.path = "/sparql";
    r.query = {{"query", q}};
    r.headers.add("Accept", "application/sparql-results+json");
    auto reply = http::httpRequest("127.0.0.1", port, std::move(r), 10s);
    return reply ? reply->body : reply.error();
}

bool ask(std::uint16_t port, const std::string& pattern) {
    http::HttpRequest r;
    r.path = "/sparql";
    r.query = {{"query",
                "PREFIX proc: <http://skillcell.dev/ontology/process#>\n"
                "PREFIX rskill: <http://skillcell.dev/UA/RoboticSkills/>\n"
                "PREFIX rdfs: <http://www.w3.org/2000/01/rdf-schema#>\n"
                "ASK { " +
                    pattern + " }"}};
    r.headers.add("Accept", "application/sparql-results+json");
    auto reply = http::httpRequest("127.0.0.1", port, std::move(r), 10s);
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
    http::HttpRequest r;
    r.method = "POST";
    r.path = "/sparql";
    r.headers.add("Content-Type", "application/x-www-form-urlencoded");
    r.body = "update=" + http::percentEncode(sparqlUpdate);
    auto reply = http::httpRequest("127.0.0.1", port, std::move(r), 30s);
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

}  // namespace
}  // namespace skillcell::kb::kb_component_test
