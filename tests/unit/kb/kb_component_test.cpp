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

namespace skillcell::kb {
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
    std::random_device rd;
    const fs::path data = fs::temp_directory_path() / ("skillcell-kb-cell-" + std::to_string(rd()));
    struct Cleanup {
        fs::path dir;
        ~Cleanup() {
            std::error_code ec;
            fs::remove_all(dir, ec);
        }
    } cleanup{data};

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
    std::random_device rd;
    const fs::path data = fs::temp_directory_path() / ("skillcell-kb-cell-" + std::to_string(rd()));
    struct Cleanup {
        fs::path dir;
        ~Cleanup() {
            std::error_code ec;
            fs::remove_all(dir, ec);
        }
    } cleanup{data};
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

}  // namespace
}  // namespace skillcell::kb
