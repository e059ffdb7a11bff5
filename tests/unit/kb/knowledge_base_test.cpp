// The knowledge base over a real Virtuoso and Konclude (started by the test, never mocked):
// every NodeSet under models/ loaded as OWL and queried with property paths, updates, the
// reasoner's refusal of an inconsistent model, inferred types, and what survives a restart
// and a kill -9 of the store.
#include <gtest/gtest.h>

#include <filesystem>
#include <memory>
#include <random>

#include "kb/engine/konclude_reasoner.hpp"
#include "kb/engine/virtuoso_instance.hpp"
#include "kb/knowledge_base.hpp"
#include "kb/store/http_sparql_store.hpp"

namespace skillcell::kb {
namespace {

namespace fs = std::filesystem;

const char* const kPrefixes =
    "PREFIX rdf: <http://www.w3.org/1999/02/22-rdf-syntax-ns#>\n"
    "PREFIX rdfs: <http://www.w3.org/2000/01/rdf-schema#>\n"
    "PREFIX opc: <http://skillcell.dev/ontology/opcua#>\n"
    "PREFIX ua: <http://opcfoundation.org/UA/>\n"
    "PREFIX gskill: <http://skillcell.dev/UA/GripperSkills/>\n"
    "PREFIX rskill: <http://skillcell.dev/UA/RoboticSkills/>\n"
    "PREFIX proc: <http://skillcell.dev/ontology/process#>\n"
    "PREFIX demo: <http://skillcell.dev/demo#>\n";

// One Virtuoso for the whole binary (its first start creates the database: ~12 s).
class KnowledgeBaseTest : public ::testing::Test {
protected:
    static void SetUpTestSuite() {
        std::random_device rd;
        dir_ = fs::temp_directory_path() / ("skillcell-kb-test-" + std::to_string(rd()));
        engine::VirtuosoConfig config;
        config.dataDir = dir_;
        virtuoso_ = std::make_unique<engine::VirtuosoInstance>(config);
        auto s = virtuoso_->start();
        ASSERT_TRUE(s) << s.error();
        auto endpoint = HttpSparqlEndpoint::fromUrl(virtuoso_->sparqlUrl());
        ASSERT_TRUE(endpoint) << endpoint.error();
        store_ = std::make_unique<HttpSparqlStore>(*endpoint);
        reasoner_ = std::make_unique<engine::KoncludeReasoner>();
        kb_ = std::make_unique<KnowledgeBase>(*store_, reasoner_.get());
        auto loaded = kb_->loadBuiltInModels(true);
        ASSERT_TRUE(loaded) << loaded.error();
    }
    static void TearDownTestSuite() {
        kb_.reset();
        store_.reset();
        reasoner_.reset();
        if (virtuoso_) (void)virtuoso_->stop();
        virtuoso_.reset();
        std::error_code ec;
        fs::remove_all(dir_, ec);
    }

    // The body of a SELECT/ASK in SPARQL JSON.
    static std::string select(const std::string& q) {
        auto r = kb_->query(kPrefixes + q, media::kSparqlJson);
        EXPECT_TRUE(r) << r.error();
        return r ? r->body : std::string();
    }
    static bool ask(const std::string& q) {
        const std::string body = select("ASK { " + q + " }");
        EXPECT_NE(body.find("\"boolean\""), std::string::npos) << body;
        return body.find("true") != std::string::npos;
    }

    static inline fs::path dir_;
    static inline std::unique_ptr<engine::VirtuosoInstance> virtuoso_;
    static inline std::unique_ptr<HttpSparqlStore> store_;
    static inline std::unique_ptr<engine::KoncludeReasoner> reasoner_;
    static inline std::unique_ptr<KnowledgeBase> kb_;
};

TEST_F(KnowledgeBaseTest, EveryNodeSetUnderModelsIsLoadedAsAGraph) {
    auto graphs = kb_->graphs();
    ASSERT_TRUE(graphs) << graphs.error();
    for (const char* g :
         {"http://opcfoundation.org/UA/", "http://skillcell.dev/UA/GripperSkills/",
          "http://skillcell.dev/UA/RoboticSkills/", "http://skillcell.dev/ontology/opcua",
          "http://skillcell.dev/ontology/process", "http://skillcell.dev/demo"}) {
        EXPECT_NE(std::find(graphs->begin(), graphs->end(), g), graphs->end()) << g;
    }
}

TEST_F(KnowledgeBaseTest, FindsEverySkillTypeThatIsAGripperSkillTypeByAPropertyPath) {
    const std::string body =
        select("SELECT ?t WHERE { ?t rdfs:subClassOf+ gskill:GripperSkillType } ORDER BY ?t");
    for (const char* t :
         {"GraspGripperSkillType", "ReleaseGripperSkillType", "MoveGripperSkillType"}) {
        EXPECT_NE(body.find(std::string("http://skillcell.dev/UA/GripperSkills/") + t),
                  std::string::npos)
            << t << " in " << body;
    }
    EXPECT_EQ(body.find("CartesianLinearMoveSkillType"), std::string::npos);
    // And through the whole chain up to namespace 0.
    EXPECT_TRUE(ask("gskill:GraspGripperSkillType rdfs:subClassOf* ua:BaseObjectType"));
}

TEST_F(KnowledgeBaseTest, GivesTheParametersOfASkillTypeWithTheirDataTypesAndUnits) {
    // Declared on the type or inherited from a supertype.
    const std::string body = select(
        "SELECT ?name ?dataType ?unit WHERE {"
        "  rskill:CartesianLinearMoveSkillType rdfs:subClassOf* ?declaring ."
        "  ?declaring ua:HasComponent ?set . ?set opc:browseName \"ParameterSet\" ."
        "  ?set ua:HasComponent ?p . ?p opc:browseName ?name ; opc:dataType ?dt ."
        "  ?dt opc:browseName ?dataType ."
        "  OPTIONAL { ?p opc:engineeringUnits ?unit } } ORDER BY ?name");
    EXPECT_NE(body.find("\"MaxVelocity\""), std::string::npos) << body;
    EXPECT_NE(body.find("\"Double\""), std::string::npos) << body;
    EXPECT_NE(body.find("\"m/s\""), std::string::npos) << body;
}

TEST_F(KnowledgeBaseTest, TheDemoProcessHasFiveOrderedStepsEachRequiringASkillType) {
    // Two queries: Virtuoso 7.2 evaluates `firstStep/next*` right on its own, but joined with
    // further patterns it counts 1 here (even as a subquery).
    const std::string ordered =
        select("SELECT ?s WHERE { demo:pickAndPlaceTwoBoxes proc:firstStep/proc:next* ?s }");
    for (int i = 1; i <= 5; ++i) {
        EXPECT_NE(ordered.find("http://skillcell.dev/demo#step" + std::to_string(i)),
                  std::string::npos)
            << ordered;
    }
    const std::string typed = select(
        "SELECT (COUNT(?s) AS ?n) WHERE { demo:pickAndPlaceTwoBoxes proc:hasStep ?s ."
        "  ?s proc:requiresSkillType ?t ."
        "  ?t rdfs:subClassOf+ <http://skillcell.dev/UA/Skills/SkillType> }");
    EXPECT_NE(typed.find("\"5\""), std::string::npos) << typed;
}

TEST_F(KnowledgeBaseTest, UpdatesApplyAndABadOneIsRefusedWithTheEnginesReason) {
    auto s = kb_->update(
        "INSERT DATA { GRAPH <urn:test:update> { <urn:test:a> <urn:test:p> \"one\" } }");
    ASSERT_TRUE(s) << s.error();
    EXPECT_TRUE(ask("GRAPH <urn:test:update> { <urn:test:a> <urn:test:p> \"one\" }"));
    auto bad = kb_->update("INSERT DATA { GRAPH <urn:test:update> { <urn:test:a> }");
    ASSERT_FALSE(bad);
    EXPECT_NE(bad.error().find("HTTP 4"), std::string::npos) << bad.error();
    auto badQuery = kb_->query("SELECT ?x WHERE { ?x", media::kSparqlJson);
    ASSERT_FALSE(badQuery);
    EXPECT_NE(badQuery.error().find("HTTP 4"), std::string::npos) << badQuery.error();
}

TEST_F(KnowledgeBaseTest, AnInconsistentModelIsRefusedNamingTheConflictAndNothingChanges) {
    auto before = kb_->graphs();
    ASSERT_TRUE(before) << before.error();
    auto processBefore = kb_->graphContent("http://skillcell.dev/demo");
    ASSERT_TRUE(processBefore) << processBefore.error();

    // A step that is also a process (the process ontology makes them disjoint), among
    // harmless statements.
    std::string turtle =
        "@prefix proc: <http://skillcell.dev/ontology/process#> .\n"
        "@prefix t: <urn:test:bad#> .\n";
    for (int i = 0; i < 20; ++i) {
        turtle += "t:step" + std::to_string(i) + " a proc:Step ; proc:stepIndex " +
                  std::to_string(i) + " .\n";
    }
    turtle += "t:step7 a proc:Process .\n";
    auto refused = kb_->loadTurtle("urn:test:bad", turtle);
    ASSERT_FALSE(refused);
    EXPECT_NE(refused.error().find("inconsistent"), std::string::npos) << refused.error();
    EXPECT_NE(refused.error().find("<urn:test:bad#step7> "
                                   "<http://www.w3.org/1999/02/22-rdf-syntax-ns#type> "
                                   "<http://skillcell.dev/ontology/process#Process>"),
              std::string::npos)
        << refused.error();
    EXPECT_EQ(refused.error().find("step3"), std::string::npos) << refused.error();

    auto after = kb_->graphs();
    ASSERT_TRUE(after) << after.error();
    EXPECT_EQ(*after, *before);
    EXPECT_FALSE(ask("GRAPH <urn:test:bad> { ?s ?p ?o }"));
    auto processAfter = kb_->graphContent("http://skillcell.dev/demo");
    ASSERT_TRUE(processAfter) << processAfter.error();
    EXPECT_EQ(processAfter->size(), processBefore->size());
}

TEST_F(KnowledgeBaseTest, InferredTypesAreQueryableInTheirOwnGraph) {
    // A dock is what holds a tool (the domain of proc:holds); nobody says it is a dock.
    auto s = kb_->loadTurtle("urn:test:inferred",
                             "@prefix proc: <http://skillcell.dev/ontology/process#> .\n"
                             "<urn:test:inferred#d> proc:holds <urn:test:inferred#t> .\n");
    ASSERT_TRUE(s) << s.error();
    EXPECT_TRUE(ask("GRAPH <urn:skillcell:kb:inferred> { <urn:test:inferred#d> a proc:ToolDock }"));
    EXPECT_TRUE(ask("GRAPH <urn:skillcell:kb:inferred> { <urn:test:inferred#d> a proc:Resource }"));
    EXPECT_FALSE(ask("GRAPH <urn:test:inferred> { <urn:test:inferred#d> a proc:ToolDock }"));
}

TEST_F(KnowledgeBaseTest, AcknowledgedDataSurvivesARestartAndAKillOfTheStore) {
    auto s =
        kb_->loadTurtle("urn:test:durable", "<urn:test:d> <urn:test:p> \"before restart\" .\n");
    ASSERT_TRUE(s) << s.error();
    ASSERT_TRUE(virtuoso_->stop());
    ASSERT_TRUE(virtuoso_->start());
    EXPECT_TRUE(ask("GRAPH <urn:test:durable> { <urn:test:d> <urn:test:p> \"before restart\" }"));

    s = kb_->update(
        "INSERT DATA { GRAPH <urn:test:durable> { <urn:test:d> <urn:test:p> "
        "\"before kill\" } }");
    ASSERT_TRUE(s) << s.error();
    virtuoso_->kill();
    auto restarted = virtuoso_->start();
    ASSERT_TRUE(restarted) << restarted.error();
    EXPECT_TRUE(ask("GRAPH <urn:test:durable> { <urn:test:d> <urn:test:p> \"before kill\" }"));
    EXPECT_TRUE(ask("GRAPH <urn:test:durable> { <urn:test:d> <urn:test:p> \"before restart\" }"));
    // The models loaded at the start survived too.
    EXPECT_TRUE(ask("gskill:GraspGripperSkillType rdfs:subClassOf gskill:GripperSkillType"));
}

}  // namespace
}  // namespace skillcell::kb
