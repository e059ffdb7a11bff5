// The knowledge base over a real Virtuoso and Konclude (started by the test, never mocked):
// every NodeSet under models/ loaded as OWL and queried with property paths, updates, the
// reasoner's refusal of an inconsistent model, inferred types, and what survives a restart
// and a kill -9 of the store.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <memory>
#include <random>
#include <thread>

#include "cell/cell_file.hpp"
#include "cell/scene_graph.hpp"
#include "http/http_client.hpp"
#include "http/web_server.hpp"
#include "kb/engine/konclude_reasoner.hpp"
#include "kb/engine/virtuoso_instance.hpp"
#include "kb/knowledge_base.hpp"
#include "kb/rdf/turtle.hpp"
#include "kb/sparql_endpoint.hpp"
#include "kb/store/http_sparql_store.hpp"
#include "mes/process_description.hpp"
#include "mes/skill_facts.hpp"

namespace skillcell::kb::knowledge_base_test {
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
        store_ = std::make_unique<HttpSparqlStore>(HttpSparqlEndpoint::of(*virtuoso_));
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

TEST_F(KnowledgeBaseTest, TheProcessQueryGivesAProcesssObjectTheScenesMassSizeAndPose) {
    // The paper cell's scene (boxB: 0.05 kg, 4 cm, at 0.45, -0.05, 0.02), as `skillcell kb
    // --cell` loads it; the demo process names boxB by its id and gives its target only.
    const auto cell =
        cell::readCellFile(std::string(SKILLCELL_SOURCE_DIR) + "/examples/cells/paper.toml");
    ASSERT_TRUE(cell.cell);
    auto loaded = kb_->load({{cell::sceneGraphIri(*cell.cell), cell::sceneTriples(*cell.cell)}});
    ASSERT_TRUE(loaded) << loaded.error();
    auto p = mes::readProcess(*store_, "http://skillcell.dev/demo#pickAndPlaceTwoBoxes");
    ASSERT_TRUE(p) << p.error();
    ASSERT_EQ(p->steps.size(), 5U);
    const mes::DerivationSource* box = nullptr;
    for (const auto& q : p->steps[3].parameters) {
        if (q.name == "ObjectId") box = std::get_if<mes::DerivationSource>(&q.value);
    }
    ASSERT_NE(box, nullptr);
    EXPECT_EQ(box->objectId, "boxB");
    EXPECT_EQ(box->mass, 0.05);
    ASSERT_TRUE(box->size);
    EXPECT_DOUBLE_EQ((*box->size)[2], 0.04);
    ASSERT_TRUE(box->pose);
    EXPECT_DOUBLE_EQ(box->pose->x, 0.45);
    EXPECT_DOUBLE_EQ(box->pose->y, -0.05);
    EXPECT_DOUBLE_EQ(box->pose->z, 0.02);
    ASSERT_TRUE(box->targetPose);
    EXPECT_DOUBLE_EQ(box->targetPose->y, -0.2);
    // Where the robot must reach: boxB and its target.
    const auto targets = mes::stepTargets(p->steps[3]);
    EXPECT_EQ(targets.size(), 2U);
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

TEST_F(KnowledgeBaseTest, PartsLoadTogetherAndWhenRefusedEachAloneNamingTheOneAtFault) {
    const auto graph = [](const std::string& iri, const std::string& turtle) {
        auto triples = rdf::readTurtle(
            "@prefix proc: <http://skillcell.dev/ontology/process#> .\n" + turtle, iri);
        EXPECT_TRUE(triples) << triples.error();
        return GraphData{iri, triples ? *triples : std::vector<rdf::Triple>{}};
    };
    // Two good parts: one load, both there.
    auto both = kb_->loadParts({{graph("urn:test:a", "<urn:test:a#s> a proc:Step .")},
                                {graph("urn:test:b", "<urn:test:b#s> a proc:Step .")}});
    ASSERT_EQ(both.size(), 2U);
    EXPECT_TRUE(both[0]) << both[0].error();
    EXPECT_TRUE(both[1]) << both[1].error();
    EXPECT_TRUE(ask("GRAPH <urn:test:b> { ?s ?p ?o }"));
    // One part contradicts the models (a step that is a process): the joint load is refused,
    // then each part alone: the good ones load, the bad one is named.
    auto mixed =
        kb_->loadParts({{graph("urn:test:c", "<urn:test:c#s> a proc:Step .")},
                        {graph("urn:test:bad", "<urn:test:bad#s> a proc:Step , proc:Process .")},
                        {graph("urn:test:d", "<urn:test:d#s> a proc:Step .")}});
    ASSERT_EQ(mixed.size(), 3U);
    EXPECT_TRUE(mixed[0]) << mixed[0].error();
    ASSERT_FALSE(mixed[1]);
    EXPECT_EQ(mixed[1].errorKind(), ErrorKind::Refused);
    EXPECT_NE(mixed[1].error().find("urn:test:bad#s"), std::string::npos) << mixed[1].error();
    EXPECT_TRUE(mixed[2]) << mixed[2].error();
    EXPECT_TRUE(ask("GRAPH <urn:test:d> { ?s ?p ?o }"));
    EXPECT_FALSE(ask("GRAPH <urn:test:bad> { ?s ?p ?o }"));
    // A blank node label names a node in its own document only: a step in one graph and a
    // process in another, both labelled _:n, are two nodes, and the graphs load as one.
    auto blanks = kb_->load(
        {graph("urn:test:e", "_:n a proc:Step ."), graph("urn:test:f", "_:n a proc:Process .")});
    EXPECT_TRUE(blanks) << blanks.error();
    EXPECT_TRUE(ask("GRAPH <urn:test:f> { ?s a proc:Process }"));
}

TEST_F(KnowledgeBaseTest, ALoadReplacesItsGraph) {
    ASSERT_TRUE(kb_->loadTurtle("urn:test:replace", "<urn:test:r> <urn:test:p> \"old\" .\n"));
    ASSERT_TRUE(kb_->loadTurtle("urn:test:replace", "<urn:test:r> <urn:test:p> \"new\" .\n"));
    auto content = kb_->graphContent("urn:test:replace");
    ASSERT_TRUE(content) << content.error();
    ASSERT_EQ(content->size(), 1U);
    EXPECT_EQ(content->front().object.value, "new");
}

// A graph larger than one update request goes in as a document where the store takes
// whole graphs, and in pieces where it does not: the same content either way, blank node
// structures included (a piece boundary must not split one node into two).
TEST_F(KnowledgeBaseTest, ALargeGraphLoadsTheSameAsOneDocumentAndInPieces) {
    // 1500 plain triples (two update requests) and 200 blank node structures of three
    // triples each (Virtuoso's SPARQL compiler runs out of memory on a few thousand blank
    // node triples in one request, which the document path does not have to fear).
    std::string turtle;
    for (int i = 0; i < 1500; ++i) {
        const std::string n = std::to_string(i);
        turtle += "<urn:test:big" + n + "> <urn:test:p> \"" + n + "\" .\n";
        if (i < 200) {
            turtle += "<urn:test:big" + n + "> <urn:test:q> [ <urn:test:x> " + n +
                      " ; <urn:test:y> [ <urn:test:z> \"" + n + "\" ] ] .\n";
        }
    }
    auto endpoint = HttpSparqlEndpoint::of(*virtuoso_);
    endpoint.graphStorePath.clear();  // SPARQL Update only
    ASSERT_TRUE(store_->replacesGraphs());
    HttpSparqlStore updatesOnly(endpoint);
    ASSERT_FALSE(updatesOnly.replacesGraphs());
    KnowledgeBase inPieces(updatesOnly, nullptr);
    KnowledgeBase asDocument(*store_, nullptr);
    auto a = inPieces.loadTurtle("urn:test:big-pieces", turtle);
    ASSERT_TRUE(a) << a.error();
    auto b = asDocument.loadTurtle("urn:test:big-document", turtle);
    ASSERT_TRUE(b) << b.error();
    for (const char* g : {"urn:test:big-pieces", "urn:test:big-document"}) {
        const std::string body =
            select(std::string("SELECT (COUNT(*) AS ?n) WHERE { GRAPH <") + g + "> { ?s ?p ?o } }");
        EXPECT_NE(body.find("\"2300\""), std::string::npos) << g << ": " << body;
        // Each subject's two nested nodes are one structure: z hangs below q's node's y.
        const std::string deep = select(
            std::string("SELECT (COUNT(*) AS ?n) WHERE { GRAPH <") + g +
            "> { ?s <urn:test:p> ?v ; <urn:test:q> [ <urn:test:y> [ <urn:test:z> ?v ] ] } }");
        EXPECT_NE(deep.find("\"200\""), std::string::npos) << g << ": " << deep;
    }
    // Gone again, from the registry too: the suite's later checks read the whole KB.
    const std::string member = std::string("> a <") + kKbVocabulary + "Graph> .";
    auto dropped = kb_->update(
        "DROP SILENT GRAPH <urn:test:big-pieces> ; DROP SILENT GRAPH <urn:test:big-document> ; "
        "DELETE DATA { "
        "GRAPH <" +
        std::string(kRegistryGraph) + "> { <urn:test:big-pieces" + member +
        " <urn:test:big-document" + member + " } }");
    ASSERT_TRUE(dropped) << dropped.error();
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

GraphData turtleGraph(const std::string& iri, const std::string& turtle) {
    auto triples = rdf::readTurtle(
        "@prefix proc: <http://skillcell.dev/ontology/process#> .\n"
        "@prefix rdfs: <http://www.w3.org/2000/01/rdf-schema#> .\n" +
            turtle,
        iri);
    EXPECT_TRUE(triples) << triples.error();
    return GraphData{iri, triples ? *triples : std::vector<rdf::Triple>{}};
}

// A component's graph is recorded as an instance graph: its individuals' inferred types go
// to the inferred graph, and a new version replaces the types the old one brought, leaving
// the models' own inferred types alone.
TEST_F(KnowledgeBaseTest, ARecordingInfersItsTypesAndANewVersionReplacesThem) {
    ASSERT_TRUE(kb_->loadTurtle("urn:test:rec-model",
                                "@prefix proc: <http://skillcell.dev/ontology/process#> .\n"
                                "<urn:test:rec-model#m> proc:holds <urn:test:rec-model#t> .\n"));
    auto first = kb_->record(
        {turtleGraph("urn:test:rec", "<urn:test:rec#d> proc:holds <urn:test:rec#t> .")});
    ASSERT_EQ(first.size(), 1U);
    ASSERT_TRUE(first[0]) << first[0].error();
    EXPECT_TRUE(ask("GRAPH <urn:skillcell:kb:inferred> { <urn:test:rec#d> a proc:ToolDock }"));
    EXPECT_TRUE(
        ask("GRAPH <urn:skillcell:kb:graphs> { <urn:test:rec> a "
            "<http://skillcell.dev/ontology/kb#InstanceGraph> }"));
    auto listed = kb_->graphs();
    ASSERT_TRUE(listed) << listed.error();
    EXPECT_NE(std::find(listed->begin(), listed->end(), "urn:test:rec"), listed->end());

    auto second = kb_->record({turtleGraph("urn:test:rec",
                                           "<urn:test:rec#e> proc:holds <urn:test:rec#t> .\n"
                                           "<urn:test:rec#d> a proc:Step .")});
    ASSERT_TRUE(second[0]) << second[0].error();
    EXPECT_FALSE(ask("GRAPH <urn:skillcell:kb:inferred> { <urn:test:rec#d> a proc:ToolDock }"));
    EXPECT_TRUE(ask("GRAPH <urn:skillcell:kb:inferred> { <urn:test:rec#e> a proc:ToolDock }"));
    EXPECT_FALSE(ask("GRAPH <urn:skillcell:kb:inferred> { <urn:test:rec#d> a proc:Step }"))
        << "a stated type is not an inferred one";
    EXPECT_TRUE(ask("GRAPH <urn:skillcell:kb:inferred> { <urn:test:rec-model#m> a proc:ToolDock }"))
        << "the models' inferred types stay";
}

// Each graph of a recording is checked against the models: the one that contradicts them is
// refused, naming the statements, and the others are recorded.
TEST_F(KnowledgeBaseTest, ARecordingInconsistentWithTheModelsIsRefusedAndTheOthersRecorded) {
    auto r = kb_->record(
        {turtleGraph("urn:test:rec-a", "<urn:test:rec-a#s> a proc:Step ."),
         turtleGraph("urn:test:rec-bad", "<urn:test:rec-bad#s> a proc:Step , proc:Process ."),
         turtleGraph("urn:test:rec-c", "<urn:test:rec-c#s> a proc:Step .")});
    ASSERT_EQ(r.size(), 3U);
    EXPECT_TRUE(r[0]) << r[0].error();
    ASSERT_FALSE(r[1]);
    EXPECT_EQ(r[1].errorKind(), ErrorKind::Refused);
    EXPECT_NE(r[1].error().find("urn:test:rec-bad#s"), std::string::npos) << r[1].error();
    EXPECT_TRUE(r[2]) << r[2].error();
    EXPECT_TRUE(ask("GRAPH <urn:test:rec-c> { ?s ?p ?o }"));
    EXPECT_FALSE(ask("GRAPH <urn:test:rec-bad> { ?s ?p ?o }"));

    // Blank nodes of two graphs with one label are two nodes: neither graph is refused.
    auto blanks = kb_->record({turtleGraph("urn:test:rec-e", "_:n a proc:Step ."),
                               turtleGraph("urn:test:rec-f", "_:n a proc:Process .")});
    ASSERT_EQ(blanks.size(), 2U);
    EXPECT_TRUE(blanks[0]) << blanks[0].error();
    EXPECT_TRUE(blanks[1]) << blanks[1].error();

    auto twice = kb_->record({turtleGraph("urn:test:rec-a", "<urn:test:rec-a#s> a proc:Step ."),
                              turtleGraph("urn:test:rec-a", "<urn:test:rec-a#s> a proc:Step .")});
    EXPECT_TRUE(twice[0]) << twice[0].error();
    ASSERT_FALSE(twice[1]);
    EXPECT_EQ(twice[1].errorKind(), ErrorKind::BadInput);
}

// Without a reasoner, a recording is written as it is (nothing inferred), registered as an
// instance graph.
TEST_F(KnowledgeBaseTest, WithoutAReasonerARecordingIsWrittenAsItIs) {
    KnowledgeBase plain(*store_, nullptr);
    auto r = plain.record(
        {turtleGraph("urn:test:rec-plain", "<urn:test:rec-plain#s> proc:holds <urn:test:t> .")});
    ASSERT_EQ(r.size(), 1U);
    EXPECT_TRUE(r[0]) << r[0].error();
    EXPECT_TRUE(ask("GRAPH <urn:test:rec-plain> { <urn:test:rec-plain#s> proc:holds ?t }"));
    EXPECT_FALSE(ask("<urn:test:rec-plain#s> a proc:ToolDock"));  // nothing inferred
    EXPECT_TRUE(
        ask("GRAPH <urn:skillcell:kb:graphs> { <urn:test:rec-plain> a "
            "<http://skillcell.dev/ontology/kb#InstanceGraph> }"));
}

// A model loaded after a component was recorded is checked against everything, and what it
// makes of the component's individuals is inferred; the next recording reasons over it.
TEST_F(KnowledgeBaseTest, AModelLoadedAfterARecordingTypesTheRecordedIndividuals) {
    auto r = kb_->record(
        {turtleGraph("urn:test:rec-m", "<urn:test:rec-m#x> a <urn:test:vocab#Fixture> .")});
    ASSERT_TRUE(r[0]) << r[0].error();
    EXPECT_FALSE(ask("GRAPH <urn:skillcell:kb:inferred> { <urn:test:rec-m#x> a proc:Resource }"));
    ASSERT_TRUE(kb_->loadTurtle(
        "urn:test:vocab",
        "@prefix proc: <http://skillcell.dev/ontology/process#> .\n"
        "@prefix owl: <http://www.w3.org/2002/07/owl#> .\n"
        "@prefix rdfs: <http://www.w3.org/2000/01/rdf-schema#> .\n"
        "<urn:test:vocab#Fixture> a owl:Class ; rdfs:subClassOf proc:Resource .\n"));
    EXPECT_TRUE(ask("GRAPH <urn:skillcell:kb:inferred> { <urn:test:rec-m#x> a proc:Resource }"));
    r = kb_->record({turtleGraph("urn:test:rec-m",
                                 "<urn:test:rec-m#x> a <urn:test:vocab#Fixture> ."
                                 "<urn:test:rec-m#y> a <urn:test:vocab#Fixture> .")});
    ASSERT_TRUE(r[0]) << r[0].error();
    EXPECT_TRUE(ask("GRAPH <urn:skillcell:kb:inferred> { <urn:test:rec-m#x> a proc:Resource }"));
    EXPECT_TRUE(ask("GRAPH <urn:skillcell:kb:inferred> { <urn:test:rec-m#y> a proc:Resource }"));
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

// --- The SPARQL 1.1 Protocol endpoint over the same knowledge base ------------------------

namespace endpoint {

const ua::UserIdentity kEngineer{"emil", ua::RoleSet{ua::Role::Engineer}};
const ua::UserIdentity kObserver{"olga", ua::RoleSet{ua::Role::Observer}};

httplib::Request get(const std::string& path, const httplib::Params& params = {},
                     const std::string& accept = {}) {
    httplib::Request r;
    r.method = "GET";
    r.path = path;
    r.params = params;
    if (!accept.empty()) r.headers.emplace("Accept", accept);
    return r;
}

// `form`: the parameters of a form body, as the server parses them into params.
httplib::Request post(const std::string& path, const std::string& contentType, std::string body,
                      const httplib::Params& form = {}) {
    httplib::Request r;
    r.method = "POST";
    r.path = path;
    r.headers.emplace("Content-Type", contentType);
    r.body = std::move(body);
    r.params = form;
    return r;
}

httplib::Request form(const httplib::Params& params) {
    return post("/sparql", "application/x-www-form-urlencoded", "", params);
}

struct Answer {
    int status = 0;
    std::string body;
    std::string contentType;
    std::string allow;
};

Answer handle(SparqlEndpoint& e, const httplib::Request& request,
              const ua::UserIdentity& user = kEngineer) {
    httplib::Response r;
    e.handle(request, r, user);
    return {r.status, r.body, r.get_header_value("Content-Type"), r.get_header_value("Allow")};
}

}  // namespace endpoint

using endpoint::handle;

TEST_F(KnowledgeBaseTest, TheEndpointAnswersQueriesByGetAndPostInTheAskedMediaType) {
    SparqlEndpoint e(*kb_, true);
    const std::string q =
        "ASK { <http://skillcell.dev/UA/GripperSkills/GraspGripperSkillType> "
        "<http://www.w3.org/2000/01/rdf-schema#subClassOf>+ "
        "<http://skillcell.dev/UA/GripperSkills/GripperSkillType> }";
    auto r = handle(e, endpoint::get("/sparql", {{"query", q}}), endpoint::kObserver);
    EXPECT_EQ(r.status, 200) << r.body;
    EXPECT_NE(r.body.find("true"), std::string::npos) << r.body;
    EXPECT_NE(r.contentType.find("sparql-results+json"), std::string::npos);

    r = handle(e, endpoint::form({{"query", q}}), endpoint::kObserver);
    EXPECT_EQ(r.status, 200) << r.body;
    r = handle(e, endpoint::post("/sparql", "application/sparql-query", q), endpoint::kObserver);
    EXPECT_EQ(r.status, 200) << r.body;

    auto turtle = endpoint::get("/sparql",
                                {{"query",
                                  "CONSTRUCT { ?t a <urn:x:GripperType> } WHERE { ?t "
                                  "<http://www.w3.org/2000/01/rdf-schema#subClassOf> "
                                  "<http://skillcell.dev/UA/GripperSkills/GripperSkillType> }"}},
                                "text/turtle");
    r = handle(e, turtle);
    EXPECT_EQ(r.status, 200) << r.body;
    EXPECT_NE(r.contentType.find("text/turtle"), std::string::npos);
    auto parsed = rdf::readTurtle(r.body);
    ASSERT_TRUE(parsed) << parsed.error();
    EXPECT_EQ(parsed->size(), 3U) << r.body;
}

TEST_F(KnowledgeBaseTest, TheEndpointRunsUpdatesByPostOnly) {
    SparqlEndpoint e(*kb_, true);
    const std::string u = "INSERT DATA { GRAPH <urn:test:ep> { <urn:test:e> <urn:test:p> 1 } }";
    auto r = handle(e, endpoint::post("/sparql", "application/sparql-update", u));
    EXPECT_EQ(r.status, 200) << r.body;
    r = handle(e, endpoint::form({{"update", u}}));
    EXPECT_EQ(r.status, 200) << r.body;
    EXPECT_TRUE(ask("GRAPH <urn:test:ep> { <urn:test:e> <urn:test:p> 1 }"));
    r = handle(e, endpoint::get("/sparql", {{"update", u}}));
    EXPECT_EQ(r.status, 400) << r.body;
}

TEST_F(KnowledgeBaseTest, AnObserverQueriesButChangesNothingHoweverTheUpdateIsSent) {
    SparqlEndpoint e(*kb_, true);
    const std::string u = "INSERT DATA { GRAPH <urn:test:obs> { <urn:a> <urn:b> 1 } }";
    const auto& olga = endpoint::kObserver;
    EXPECT_EQ(handle(e, endpoint::form({{"update", u}}), olga).status, 403);
    EXPECT_EQ(handle(e, endpoint::post("/sparql", "application/sparql-update", u), olga).status,
              403);
    // Sent as a query, it is still an update.
    EXPECT_EQ(handle(e, endpoint::form({{"query", u}}), olga).status, 403);
    EXPECT_EQ(handle(e, endpoint::post("/sparql", "application/sparql-query", u), olga).status,
              403);
    EXPECT_EQ(handle(e, endpoint::get("/sparql", {{"query", u}}), olga).status, 400);
    EXPECT_EQ(
        handle(e, endpoint::form({{"query", "PREFIX a: <urn:a#> # SELECT\n" + u}}), olga).status,
        403);
    auto put = endpoint::post("/graphs", "text/turtle", "<urn:a> <urn:b> 1 .\n");
    put.method = "PUT";
    put.params = {{"graph", "urn:test:obs"}};
    EXPECT_EQ(handle(e, put, olga).status, 403);
    EXPECT_FALSE(ask("GRAPH <urn:test:obs> { ?s ?p ?o }"));
    // Someone without a reading role reads nothing either.
    const ua::UserIdentity nobody{"nobody", ua::RoleSet{ua::Role::AuthenticatedUser}};
    EXPECT_EQ(handle(e, endpoint::get("/sparql", {{"query", "ASK {}"}}), nobody).status, 403);
    // The knowledge base itself refuses an update as a query, whoever calls it.
    auto direct = kb_->query(u, media::kSparqlJson);
    ASSERT_FALSE(direct);
    EXPECT_EQ(direct.errorKind(), ErrorKind::BadInput);
    // An Engineer's update sent as a query is run as the update it is.
    auto r = handle(e, endpoint::form({{"query", u}}));
    EXPECT_EQ(r.status, 200) << r.body;
    EXPECT_TRUE(ask("GRAPH <urn:test:obs> { <urn:a> <urn:b> 1 }"));
    EXPECT_EQ(handle(e, endpoint::form({{"update", "DROP SILENT GRAPH <urn:test:obs>"}})).status,
              200);
}

TEST_F(KnowledgeBaseTest, AReadOnlyEndpointRefusesUpdatesAndLoads) {
    SparqlEndpoint e(*kb_, false);
    auto r = handle(e, endpoint::post("/sparql", "application/sparql-update",
                                      "INSERT DATA { GRAPH <urn:test:ro> { <urn:a> <urn:b> 1 } }"));
    EXPECT_EQ(r.status, 403) << r.body;
    auto put = endpoint::post("/graphs", "text/turtle", "<urn:a> <urn:b> 1 .\n");
    put.method = "PUT";
    put.params = {{"graph", "urn:test:ro"}};
    EXPECT_EQ(handle(e, put).status, 403);
    EXPECT_FALSE(ask("GRAPH <urn:test:ro> { ?s ?p ?o }"));
    EXPECT_EQ(handle(e, endpoint::get("/sparql", {{"query", "ASK {}"}})).status, 200);
}

TEST_F(KnowledgeBaseTest, TheEndpointAnswersBadRequestsPrecisely) {
    SparqlEndpoint e(*kb_, true);
    auto r = handle(e, endpoint::get("/sparql", {{"query", "SELECT ?x WHERE { ?x"}}));
    EXPECT_EQ(r.status, 400);
    EXPECT_NE(r.body.find("SP030"), std::string::npos) << r.body;  // Virtuoso's syntax error
    EXPECT_EQ(handle(e, endpoint::get("/sparql")).status, 400);
    EXPECT_EQ(handle(e, endpoint::form({{"query", "ASK {}"}, {"update", "x"}})).status, 400);
    EXPECT_EQ(handle(e, endpoint::post("/sparql", "text/plain", "ASK {}")).status, 415);
    EXPECT_EQ(handle(e, endpoint::get("/nothing")).status, 404);
    auto del = endpoint::get("/sparql");
    del.method = "DELETE";
    r = handle(e, del);
    EXPECT_EQ(r.status, 405);
    EXPECT_EQ(r.allow, "GET, POST");
}

TEST_F(KnowledgeBaseTest, TheEndpointLoadsGraphsCheckedByTheReasoner) {
    SparqlEndpoint e(*kb_, true);
    auto put = endpoint::post("/graphs", "text/turtle",
                              "<urn:test:g#a> a <http://skillcell.dev/ontology/process#Step> .\n");
    put.method = "PUT";
    put.params = {{"graph", "urn:test:put"}};
    auto r = handle(e, put);
    EXPECT_EQ(r.status, 200) << r.body;
    r = handle(e, endpoint::get("/graphs"));
    EXPECT_NE(r.body.find("urn:test:put\n"), std::string::npos) << r.body;

    put.body += "<urn:test:g#a> a <http://skillcell.dev/ontology/process#Process> .\n";
    r = handle(e, put);
    EXPECT_EQ(r.status, 409) << r.body;
    EXPECT_NE(r.body.find("process#Process"), std::string::npos) << r.body;
    put.body = "this is not turtle";
    EXPECT_EQ(handle(e, put).status, 400);
    put.params.clear();
    EXPECT_EQ(handle(e, put).status, 400);
}

TEST_F(KnowledgeBaseTest, TheEndpointSaysServiceUnavailableWhenTheStoreIsGone) {
    HttpSparqlEndpoint nowhere;
    nowhere.url.port = 1;  // nothing listens on port 1 of the loopback
    nowhere.client.timeout = std::chrono::milliseconds(2000);
    HttpSparqlStore gone(nowhere);
    KnowledgeBase cut(gone, nullptr);
    SparqlEndpoint e(cut, true);
    auto r = handle(e, endpoint::get("/sparql", {{"query", "ASK {}"}}));
    EXPECT_EQ(r.status, 503) << r.body;
}

TEST_F(KnowledgeBaseTest, VirtuosoTakesNoAnonymousRequestAndAWrongPasswordNeither) {
    http::HttpUrl url;
    url.port = virtuoso_->httpPort();
    const std::string insert = "INSERT DATA { GRAPH <http://evil.example/> { <urn:a> <urn:b> 1 } }";
    http::HttpClient anonymous(url, {});
    for (const char* path :
         {"/sparql", "/sparql-auth", "/sparql-graph-crud", "/sparql-graph-crud-auth", "/proxy",
          "/URIQA", "/uriqa", "/XMLA", "/SOAP", "/DAV/", "/sparql-sd", "/conductor"}) {
        for (const char* name : {"query", "update"}) {
            for (const auto& text : {insert, std::string("SELECT * WHERE { ?s ?p ?o } LIMIT 1")}) {
                auto r = anonymous.postForm(path, {{name, text}}, "");
                if (!r) continue;  // no answer is a refusal too
                EXPECT_TRUE(r->status == 401 || r->status == 403 || r->status == 404 ||
                            r->status == 405)
                    << path << " " << name << ": HTTP " << r->status << ": " << r->body;
            }
        }
    }
    http::ClientOptions wrong;
    wrong.auth = {http::ClientAuth::Kind::Digest, engine::VirtuosoInstance::sparqlUser(), "wrong"};
    url.path = "/sparql-auth";
    http::HttpClient guessing(url, wrong);
    auto r = guessing.postForm("/sparql-auth", {{"update", insert}}, "");
    ASSERT_TRUE(r) << r.error();
    EXPECT_EQ(r->status, 401);
    EXPECT_FALSE(ask("GRAPH <http://evil.example/> { ?s ?p ?o }"));
}

TEST_F(KnowledgeBaseTest, TheEndpointServesOverHttpWithFormsParsedByTheServer) {
    SparqlEndpoint e(*kb_, true);
    http::WebServerConfig config;
    config.gate = std::make_shared<http::UserGate>(
        nullptr, ua::RoleSet{ua::Role::Anonymous, ua::Role::Engineer});
    http::WebServer server(std::move(config));
    e.serveOn(server);
    ASSERT_TRUE(server.start());
    http::HttpUrl url;
    url.port = server.port();
    http::HttpClient client(url, {});
    auto reply = client.get("/sparql", {{"query", "ASK { ?s ?p ?o }"}}, media::kSparqlJson);
    ASSERT_TRUE(reply) << reply.error();
    EXPECT_EQ(reply->status, 200) << reply->body;
    EXPECT_NE(reply->body.find("true"), std::string::npos) << reply->body;
    const std::string u = "INSERT DATA { GRAPH <urn:test:wire> { <urn:a> <urn:b> \"a&b=c+d\" } }";
    auto update = client.postForm("/sparql", {{"update", u}}, "");
    ASSERT_TRUE(update) << update.error();
    EXPECT_EQ(update->status, 200) << update->body;
    EXPECT_TRUE(ask("GRAPH <urn:test:wire> { <urn:a> <urn:b> \"a&b=c+d\" }"));
    EXPECT_TRUE(client.postForm("/sparql", {{"update", "DROP SILENT GRAPH <urn:test:wire>"}}, ""));
}
}  // namespace
}  // namespace skillcell::kb::knowledge_base_test
