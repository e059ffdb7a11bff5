// NodeSet2 -> OWL (src/kb/owl) and Turtle through libserd (src/kb/rdf).
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <random>
#include <set>

#include "kb/owl/embedded_ontologies.hpp"
#include "kb/owl/model_repository.hpp"
#include "kb/owl/node_iri.hpp"
#include "kb/owl/nodeset_ontology.hpp"
#include "kb/owl/ua_vocabulary.hpp"
#include "kb/rdf/turtle.hpp"

namespace skillcell::kb::owl_test {
namespace {

using rdf::iri;
using rdf::literal;
using rdf::Triple;

const std::string kRdfType = std::string(rdf::vocab::kRdf) + "type";
const std::string kSubClassOf = std::string(rdf::vocab::kRdfs) + "subClassOf";
const std::string kSubPropertyOf = std::string(rdf::vocab::kRdfs) + "subPropertyOf";
const std::string kUa = "http://opcfoundation.org/UA/";
const std::string kGripper = "http://skillcell.dev/UA/GripperSkills/";
const std::string kRobotic = "http://skillcell.dev/UA/RoboticSkills/";

std::set<Triple> asSet(const std::vector<Triple>& v) {
    return {v.begin(), v.end()};
}

bool has(const std::vector<Triple>& ts, const Triple& t) {
    return std::find(ts.begin(), ts.end(), t) != ts.end();
}

// The objects of (subject, predicate) in ts.
std::vector<rdf::Term> objects(const std::vector<Triple>& ts, const std::string& s,
                               const std::string& p) {
    std::vector<rdf::Term> out;
    for (const auto& t : ts) {
        if (t.subject.value == s && t.predicate.value == p) out.push_back(t.object);
    }
    return out;
}

TEST(Turtle, WritesAndReadsBackTheSameTriples) {
    const std::vector<Triple> triples{
        {iri("http://e.org/a"), iri("http://e.org/p"), literal("plain")},
        {iri("http://e.org/a"), iri("http://e.org/p"), literal("quote \" and \\ and\nnewline")},
        {iri("http://e.org/a"), iri("http://e.org/p"), literal("größe ✓")},
        {iri("http://e.org/a"), iri("http://e.org/p"),
         literal("42", std::string(rdf::vocab::kXsd) + "integer")},
        {iri("http://e.org/a"), iri("http://e.org/p"), rdf::langLiteral("Greifer", "de")},
        {iri("http://e.org/a"), iri("http://e.org/q"), rdf::blank("b1")},
        {rdf::blank("b1"), iri("http://e.org/p"), iri("http://e.org/i=5;s=a%20b")},
        {iri("http://e.org/x/y#z"), iri(kRdfType), iri("http://e.org/C")},
    };
    const std::string text =
        rdf::writeTurtle(triples, {{"e", "http://e.org/"}, {"rdf", std::string(rdf::vocab::kRdf)}});
    auto back = rdf::readTurtle(text);
    ASSERT_TRUE(back) << back.error() << "\n" << text;
    // Blank node labels may be renamed by the reader: compare with the label mapped.
    std::string label;
    for (const auto& t : *back) {
        if (t.subject.kind == rdf::Term::Kind::Blank) label = t.subject.value;
    }
    ASSERT_FALSE(label.empty());
    auto expected = triples;
    for (auto& t : expected) {
        if (t.subject.kind == rdf::Term::Kind::Blank) t.subject.value = label;
        if (t.object.kind == rdf::Term::Kind::Blank) t.object.value = label;
    }
    EXPECT_EQ(asSet(*back), asSet(expected)) << text;
}

TEST(Turtle, OutputDependsOnlyOnTheSetOfTriples) {
    std::vector<Triple> triples;
    for (int i = 0; i < 50; ++i) {
        triples.push_back({iri("http://e.org/s" + std::to_string(i % 7)),
                           iri("http://e.org/p" + std::to_string(i % 3)),
                           literal(std::to_string(i))});
    }
    const std::string first = rdf::writeTurtle(triples);
    auto shuffled = triples;
    shuffled.insert(shuffled.end(), triples.begin(), triples.begin() + 10);  // duplicates
    std::mt19937 rng(7);
    std::shuffle(shuffled.begin(), shuffled.end(), rng);
    EXPECT_EQ(rdf::writeTurtle(shuffled), first);
}

TEST(Turtle, ABadDocumentIsAnErrorNamingTheLine) {
    auto r = rdf::readTurtle("@prefix e: <http://e.org/> .\ne:a e:p e:b .\ne:a e:p \"open .\n");
    ASSERT_FALSE(r);
    EXPECT_NE(r.error().find("line 3"), std::string::npos) << r.error();
    auto unknownPrefix = rdf::readTurtle("x:a x:p x:b .\n");
    ASSERT_FALSE(unknownPrefix);
    EXPECT_NE(unknownPrefix.error().find("x:a"), std::string::npos) << unknownPrefix.error();
}

TEST(Turtle, RelativeIrisResolveAgainstTheBase) {
    auto r = rdf::readTurtle("<a> <p> <#b> .\n", "http://e.org/dir/doc");
    ASSERT_TRUE(r) << r.error();
    ASSERT_EQ(r->size(), 1U);
    EXPECT_EQ(r->front().subject.value, "http://e.org/dir/a");
    EXPECT_EQ(r->front().object.value, "http://e.org/dir/doc#b");
}

TEST(NodeIri, TypesByNameOtherNodesById) {
    EXPECT_EQ(owl::nodeIri(kGripper, ua::NodeId(2, 1002), ua::NodeClass::ObjectType,
                           "GraspGripperSkillType"),
              kGripper + "GraspGripperSkillType");
    EXPECT_EQ(owl::nodeIri(kGripper, ua::NodeId(2, 5009), ua::NodeClass::Variable, "GripForce"),
              kGripper + "i=5009");
    EXPECT_EQ(
        owl::nodeIri("urn:x", ua::NodeId(3, std::string("a b/c#d")), ua::NodeClass::Object, "x"),
        "urn:x#s=a%20b%2Fc%23d");
    // A type whose browse name is no plain name is named by its id.
    EXPECT_EQ(owl::nodeIri(kUa, ua::NodeId(0, 1), ua::NodeClass::DataType, "a b"), kUa + "i=1");
    EXPECT_EQ(owl::expandedNodeIdText(kUa, ua::NodeId(0, 85)), "nsu=" + kUa + ";i=85");
}

class EmbeddedOntologies : public ::testing::Test {
protected:
    static void SetUpTestSuite() {
        auto converted = owl::embeddedModelOntologies();
        ASSERT_TRUE(converted) << converted.error();
        ontologies_ = new std::vector<owl::Ontology>(std::move(*converted));  // NOLINT
        all_ = new std::vector<Triple>();  // NOLINT: suite-wide, freed in TearDownTestSuite
        for (const auto& o : *ontologies_) {
            all_->insert(all_->end(), o.triples.begin(), o.triples.end());
        }
    }
    static void TearDownTestSuite() {
        delete ontologies_;  // NOLINT
        delete all_;         // NOLINT
    }
    static std::vector<owl::Ontology>* ontologies_;
    static std::vector<Triple>* all_;
};
std::vector<owl::Ontology>* EmbeddedOntologies::ontologies_ = nullptr;
std::vector<Triple>* EmbeddedOntologies::all_ = nullptr;

TEST_F(EmbeddedOntologies, EveryNodeSetUnderModelsConvertsAndItsTurtleReadsBackToTheSameTriples) {
    ASSERT_EQ(ontologies_->size(), 10U);  // namespace 0 and the nine companion models
    for (const auto& o : *ontologies_) {
        SCOPED_TRACE(o.source);
        const std::string text = owl::toTurtle(o);
        auto back = rdf::readTurtle(text);
        ASSERT_TRUE(back) << back.error();
        EXPECT_EQ(asSet(*back), asSet(o.triples));
        EXPECT_EQ(owl::toTurtle(o), text);  // deterministic
    }
}

TEST_F(EmbeddedOntologies, EachIsAnOntologyImportingItsRequiredModelsAndTheCore) {
    const auto& gripper = *std::find_if(ontologies_->begin(), ontologies_->end(),
                                        [](const auto& o) { return o.iri == kGripper; });
    EXPECT_TRUE(has(gripper.triples, {iri(kGripper), iri(kRdfType),
                                      iri(std::string(rdf::vocab::kOwl) + "Ontology")}));
    const auto imports =
        objects(gripper.triples, kGripper, std::string(rdf::vocab::kOwl) + "imports");
    std::set<std::string> names;
    for (const auto& i : imports) names.insert(i.value);
    EXPECT_TRUE(names.count(kUa));
    EXPECT_TRUE(names.count("http://skillcell.dev/UA/Skills/"));
    EXPECT_TRUE(names.count(std::string(owl::kCoreOntologyIri)));
}

TEST_F(EmbeddedOntologies, TypesAreClassesWithHasSubtypeAsSubClassOf) {
    const std::string grasp = kGripper + "GraspGripperSkillType";
    EXPECT_TRUE(
        has(*all_, {iri(grasp), iri(kRdfType), iri(std::string(rdf::vocab::kOwl) + "Class")}));
    EXPECT_TRUE(has(*all_, {iri(grasp), iri(kSubClassOf), iri(kGripper + "GripperSkillType")}));
    // ... up to namespace 0, through the Skills model.
    EXPECT_TRUE(has(
        *all_, {iri(kUa + "BaseObjectType"), iri(kUa + "HasSubtype"), iri(kUa + "FolderType")}));
    EXPECT_TRUE(
        has(*all_, {iri(kUa + "FolderType"), iri(kSubClassOf), iri(kUa + "BaseObjectType")}));
}

TEST_F(EmbeddedOntologies, ReferenceTypesAreObjectPropertiesWithTheirHierarchy) {
    EXPECT_TRUE(has(*all_, {iri(kUa + "HasComponent"), iri(kRdfType),
                            iri(std::string(rdf::vocab::kOwl) + "ObjectProperty")}));
    EXPECT_TRUE(
        has(*all_, {iri(kUa + "HasComponent"), iri(kSubPropertyOf), iri(kUa + "Aggregates")}));
    EXPECT_TRUE(has(*all_, {iri(kUa + "Aggregates"), iri(kSubPropertyOf), iri(kUa + "HasChild")}));
    EXPECT_TRUE(has(
        *all_, {iri(kUa + "HasChild"), iri(kSubPropertyOf), iri(kUa + "HierarchicalReferences")}));
}

TEST_F(EmbeddedOntologies, SkillParametersCarryTheirDataTypeAndUnits) {
    // MaxVelocity of a robotic move skill: a Double in m/s with its range.
    std::string maxVelocity;
    for (const auto& t : *all_) {
        if (t.predicate.value == owl::opc(owl::term::kBrowseName) &&
            t.object.value == "MaxVelocity" && t.subject.value.rfind(kRobotic, 0) == 0 &&
            !objects(*all_, t.subject.value, owl::opc(owl::term::kEngineeringUnits)).empty()) {
            maxVelocity = t.subject.value;
            break;
        }
    }
    ASSERT_FALSE(maxVelocity.empty());
    EXPECT_TRUE(
        has(*all_, {iri(maxVelocity), iri(owl::opc(owl::term::kDataType)), iri(kUa + "Double")}));
    EXPECT_EQ(objects(*all_, maxVelocity, owl::opc(owl::term::kEngineeringUnits)),
              std::vector<rdf::Term>{literal("m/s")});
    EXPECT_EQ(objects(*all_, maxVelocity, owl::opc(owl::term::kEuRangeHigh)).size(), 1U);
    // An instance declaration is an individual of its type definition.
    EXPECT_TRUE(has(*all_, {iri(maxVelocity), iri(kRdfType),
                            iri(std::string(rdf::vocab::kOwl) + "NamedIndividual")}));
}

TEST_F(EmbeddedOntologies, EveryCoreTermTheConverterUsesIsDeclaredInTheCoreOntology) {
    auto core = rdf::readTurtle(owl::coreOntologyTurtle());
    ASSERT_TRUE(core) << core.error();
    std::set<std::string> declared;
    for (const auto& t : *core) {
        if (t.predicate.value == kRdfType) declared.insert(t.subject.value);
    }
    std::set<std::string> used;
    for (const auto& t : *all_) {
        for (const auto* term : {&t.subject, &t.predicate, &t.object}) {
            if (term->kind == rdf::Term::Kind::Iri && term->value.rfind(owl::kOpc, 0) == 0) {
                used.insert(term->value);
            }
        }
    }
    EXPECT_FALSE(used.empty());
    for (const auto& u : used) EXPECT_TRUE(declared.count(u)) << u << " is not declared";
}

TEST(NodeSetOntology, AReferenceToANodeNobodyDefinesIsAnErrorNamingFileAndLine) {
    const std::string xml = R"(<?xml version="1.0" encoding="utf-8"?>
<UANodeSet xmlns="http://opcfoundation.org/UA/2011/03/UANodeSet.xsd">
  <NamespaceUris><Uri>urn:test:bad</Uri></NamespaceUris>
  <Models><Model ModelUri="urn:test:bad" Version="1.0"/></Models>
  <UAObjectType NodeId="ns=1;i=1" BrowseName="1:T">
    <DisplayName>T</DisplayName>
    <References><Reference ReferenceType="i=45" IsForward="false">ns=1;i=99</Reference></References>
  </UAObjectType>
</UANodeSet>)";
    auto r = owl::convertNodeSets({{"bad.xml", xml}}, false);
    ASSERT_FALSE(r);
    EXPECT_NE(r.error().find("bad.xml"), std::string::npos) << r.error();
    EXPECT_NE(r.error().find("line 5"), std::string::npos) << r.error();
    EXPECT_NE(r.error().find("nsu=urn:test:bad;i=99"), std::string::npos) << r.error();
}

TEST(NodeSetOntology, MalformedXmlIsAnErrorNamingTheFile) {
    auto r = owl::convertNodeSets({{"broken.xml", "<UANodeSet><UAObject"}}, false);
    ASSERT_FALSE(r);
    EXPECT_NE(r.error().find("broken.xml"), std::string::npos) << r.error();
}

TEST(ModelRepository, ConvertsADirectorysNodeSetsThatRequireTheCompanionModels) {
    auto repo =
        owl::ModelRepository::fromDirectory(SKILLCELL_SOURCE_DIR "/examples/dispense_skill");
    ASSERT_TRUE(repo) << repo.error();
    const std::string dispense = "http://skillcell.dev/UA/Examples/Dispense/";
    ASSERT_EQ(repo->uris(), std::vector<std::string>{dispense});
    const auto chain = repo->withRequirements(dispense);
    ASSERT_EQ(chain.size(), 1U);  // what it requires is compiled in, not in the directory
    EXPECT_TRUE(has(chain.front()->triples, {iri(dispense + "DispenseSkillType"), iri(kSubClassOf),
                                             iri("http://skillcell.dev/UA/Skills/SkillType")}));
    EXPECT_TRUE(repo->withRequirements("urn:not:here").empty());
}

TEST(ModelRepository, SaysWhichRequiredModelNobodyProvides) {
    const auto dir = std::filesystem::temp_directory_path() / "skillcell-models-test";
    std::filesystem::create_directories(dir);
    {
        std::ofstream f(dir / "Needy.NodeSet2.xml");
        f << R"(<?xml version="1.0" encoding="utf-8"?>
<UANodeSet xmlns="http://opcfoundation.org/UA/2011/03/UANodeSet.xsd">
  <NamespaceUris><Uri>urn:test:needy</Uri></NamespaceUris>
  <Models><Model ModelUri="urn:test:needy" Version="1.0">
    <RequiredModel ModelUri="urn:test:missing" Version="1.0"/>
  </Model></Models>
</UANodeSet>)";
    }
    auto repo = owl::ModelRepository::fromDirectory(dir);
    std::filesystem::remove_all(dir);
    ASSERT_FALSE(repo);
    EXPECT_NE(repo.error().find("urn:test:missing"), std::string::npos) << repo.error();
    EXPECT_NE(repo.error().find("Needy.NodeSet2.xml"), std::string::npos) << repo.error();

    auto none = owl::ModelRepository::fromDirectory("/nonexistent/skillcell/models");
    ASSERT_FALSE(none);
    EXPECT_NE(none.error().find("/nonexistent/skillcell/models"), std::string::npos);
}

}  // namespace
}  // namespace skillcell::kb::owl_test
