// The knowledge base's outside engines, run for real: a private Virtuoso (virtuoso-t,
// isql-vt) and the Konclude reasoner. Loopback only; every process and temporary
// directory is removed by RAII, also when an assertion fails.
#include <arpa/inet.h>
#include <gtest/gtest.h>
#include <netinet/in.h>
#include <spdlog/spdlog.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <chrono>
#include <csignal>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "http/http_client.hpp"
#include "kb/engine/konclude_reasoner.hpp"
#include "kb/engine/virtuoso_instance.hpp"
#include "kb/rdf/turtle.hpp"

namespace skillcell::kb::engine::engine_test {
namespace {

namespace fs = std::filesystem;
using namespace std::chrono_literals;
using Clock = std::chrono::steady_clock;

long long msSince(Clock::time_point t0) {
    return std::chrono::duration_cast<std::chrono::milliseconds>(Clock::now() - t0).count();
}

class TempDir {
public:
    TempDir() {
        std::string pattern = (fs::temp_directory_path() / "skillcell-engine-test-XXXXXX").string();
        if (::mkdtemp(pattern.data()) != nullptr) path_ = pattern;
    }
    ~TempDir() {
        std::error_code ec;
        if (path_.empty()) return;
        fs::permissions(path_, fs::perms::owner_all, ec);
        fs::remove_all(path_, ec);
    }
    TempDir(const TempDir&) = delete;
    TempDir& operator=(const TempDir&) = delete;
    [[nodiscard]] const fs::path& path() const { return path_; }

private:
    fs::path path_;
};

// ---------------------------------------------------------------------------------------
// Virtuoso

/// A form-encoded POST to the instance's SPARQL endpoint (the way INTEROP-NOTES says never
/// hangs), as the KB's SQL user with HTTP Digest; bounded by the client's timeout.
Expected<http::HttpReply> postSparql(const VirtuosoInstance& v, const std::string& field,
                                     const std::string& text) {
    auto url = http::HttpUrl::parse(v.sparqlUrl());
    if (!url) return url.failure();
    http::ClientOptions o;
    o.timeout = 30s;
    o.auth = {http::ClientAuth::Kind::Digest, VirtuosoInstance::sparqlUser(), v.sparqlPassword()};
    http::HttpClient client(*url, o);
    return client.postForm(url->path, {{field, text}}, "text/csv");
}

/// One Virtuoso in a temporary data directory; stopped before the directory goes.
struct ScratchVirtuoso {
    TempDir dir;
    VirtuosoInstance instance{VirtuosoConfig{dir.path() / "db"}};
};

class VirtuosoTest : public ::testing::Test {
protected:
    static void SetUpTestSuite() {
        shared_ = std::make_unique<ScratchVirtuoso>();
        const auto t0 = Clock::now();
        sharedStart_ = shared_->instance.start();
        spdlog::info("TIMING Virtuoso first start (creates the database): {} ms", msSince(t0));
    }
    static void TearDownTestSuite() { shared_.reset(); }
    void SetUp() override { ASSERT_TRUE(sharedStart_) << sharedStart_.error(); }

    static VirtuosoInstance& db() { return shared_->instance; }

    /// The objects of <s> <urn:p> ?o in `graph`, one a line, as isql prints them.
    static std::string objects(VirtuosoInstance& v, const std::string& graph) {
        auto out =
            v.isql("SPARQL SELECT ?o FROM <" + graph + "> WHERE { ?s <urn:p> ?o } ORDER BY ?o;");
        return out ? *out : "ERROR " + out.error();
    }

    static inline std::unique_ptr<ScratchVirtuoso> shared_;
    static inline Status sharedStart_ = Error{"not started"};
};

TEST_F(VirtuosoTest, InsertsAndQueriesThroughIsql) {
    auto inserted = db().isql(
        R"(SPARQL INSERT DATA { GRAPH <urn:t1> { <urn:a> <urn:p> "alpha" . <urn:b> <urn:p> "beta" } };)");
    ASSERT_TRUE(inserted) << inserted.error();
    const std::string found = objects(db(), "urn:t1");
    EXPECT_NE(found.find("alpha"), std::string::npos) << found;
    EXPECT_NE(found.find("beta"), std::string::npos) << found;

    auto bad = db().isql("SPARQL SELEC nonsense;");
    ASSERT_FALSE(bad);
    EXPECT_NE(bad.error().find("syntax error"), std::string::npos) << bad.error();
}

TEST_F(VirtuosoTest, ReplacesTheDefaultAdminPassword) {
    struct stat st {};
    ASSERT_EQ(::stat(db().passwordPath().c_str(), &st), 0);
    EXPECT_EQ(st.st_mode & 0777, 0600);
    std::ifstream in(db().passwordPath());
    std::string password;
    std::getline(in, password);
    EXPECT_GE(password.size(), 20u);
    EXPECT_NE(password, "dba");

    auto asDefault = process::runToCompletion(
        {"isql-vt", "127.0.0.1:" + std::to_string(db().sqlPort()), "dba", "dba", "EXEC=select 1;"},
        20s);
    ASSERT_TRUE(asDefault) << asDefault.error();
    EXPECT_NE(asDefault->err.find("Bad login"), std::string::npos) << asDefault->err;
    EXPECT_EQ(db().sparqlUrl(),
              "http://127.0.0.1:" + std::to_string(db().httpPort()) + "/sparql-auth");
    EXPECT_TRUE(fs::exists(db().logPath()));
}

TEST_F(VirtuosoTest, SparqlUpdateWorksOverHttpAsTheKbsUser) {
    auto update = [](const std::string& text) {
        auto reply = postSparql(db(), "update", text);
        return reply ? std::to_string(reply->status) + " " + reply->body : reply.error();
    };
    EXPECT_TRUE(update(R"(INSERT DATA { GRAPH <urn:h1> { <urn:x> <urn:p> "over-http" } })")
                    .starts_with("200"));
    EXPECT_TRUE(update("COPY <urn:h1> TO <urn:h2>").starts_with("200"));
    EXPECT_TRUE(update("MOVE <urn:h2> TO <urn:h3>").starts_with("200"));
    EXPECT_TRUE(update("CLEAR GRAPH <urn:h1>").starts_with("200"));
    {
        std::ofstream nt(db().dataDir() / "load.nt");
        nt << "<urn:l> <urn:p> \"loaded\" .\n";
    }
    const std::string load =
        update("LOAD <file://" + (db().dataDir() / "load.nt").string() + "> INTO GRAPH <urn:h4>");
    EXPECT_TRUE(load.starts_with("200")) << load;
    EXPECT_TRUE(update("CREATE GRAPH <urn:h5>").starts_with("200"));
    EXPECT_TRUE(update("DROP GRAPH <urn:h5>").starts_with("200"));

    auto query = postSparql(db(), "query",
                            "SELECT ?g ?o WHERE { GRAPH ?g { ?s <urn:p> ?o } "
                            "FILTER(STRSTARTS(STR(?g), \"urn:h\")) } ORDER BY ?g");
    ASSERT_TRUE(query) << query.error();
    EXPECT_EQ(query->status, 200);
    EXPECT_EQ(query->body, "\"g\",\"o\"\n\"urn:h3\",\"over-http\"\n\"urn:h4\",\"loaded\"\n");
}

TEST_F(VirtuosoTest, DataSurvivesARestart) {
    ASSERT_TRUE(
        db().isql(R"(SPARQL INSERT DATA { GRAPH <urn:r> { <urn:a> <urn:p> "before-restart" } };)"));
    const auto http = db().httpPort();
    ASSERT_TRUE(db().stop());
    EXPECT_FALSE(db().running());
    const auto t0 = Clock::now();
    auto started = db().start();
    spdlog::info("TIMING Virtuoso restart after a clean stop: {} ms", msSince(t0));
    ASSERT_TRUE(started) << started.error();
    EXPECT_EQ(db().httpPort(), http);  // picked once, kept: clients' URLs stay valid
    EXPECT_NE(objects(db(), "urn:r").find("before-restart"), std::string::npos);
}

TEST_F(VirtuosoTest, AcknowledgedDataSurvivesKill9) {
    ASSERT_TRUE(
        db().isql(R"(SPARQL INSERT DATA { GRAPH <urn:k> { <urn:a> <urn:p> "via-isql" } };)"));
    auto reply = postSparql(db(), "update",
                            R"(INSERT DATA { GRAPH <urn:k> { <urn:b> <urn:p> "via-http" } })");
    ASSERT_TRUE(reply) << reply.error();
    ASSERT_EQ(reply->status, 200) << reply->body;
    // Not yet checkpointed: the data is in the transaction log only.
    EXPECT_GT(fs::file_size(db().dataDir() / "virtuoso.trx"), 0u);
    db().kill();  // no checkpoint, no shutdown
    EXPECT_FALSE(db().running());
    const auto logBefore = fs::file_size(db().logPath());
    const auto t0 = Clock::now();
    auto started = db().start();
    spdlog::info("TIMING Virtuoso restart after SIGKILL (rolls the log forward): {} ms",
                 msSince(t0));
    ASSERT_TRUE(started) << started.error();
    std::ifstream log(db().logPath());
    log.seekg(static_cast<std::streamoff>(logBefore));
    const std::string restartLog{std::istreambuf_iterator<char>(log), {}};
    // The restart rolled the transaction log forward (how Virtuoso words the count varies).
    EXPECT_NE(restartLog.find("Roll forward"), std::string::npos) << restartLog;
    const std::string found = objects(db(), "urn:k");
    EXPECT_NE(found.find("via-isql"), std::string::npos) << found;
    EXPECT_NE(found.find("via-http"), std::string::npos) << found;
}

// A KB killed with SIGKILL leaves its virtuoso-t to the kernel (PR_SET_PDEATHSIG), which may
// still be exiting, lock held, when the KB is restarted. Here the "orphan" is a virtuoso-t
// started on the data directory by someone else than the instance: start() must stop it and
// start its own, with the data intact.
TEST_F(VirtuosoTest, StartStopsAnOrphanedVirtuosoOnItsDataDirectory) {
    ASSERT_TRUE(
        db().isql(R"(SPARQL INSERT DATA { GRAPH <urn:o> { <urn:a> <urn:p> "before-orphan" } };)"));
    ASSERT_TRUE(db().stop());
    process::ProcessOptions options;
    options.workingDir = db().dataDir();
    options.stdoutTo = process::OutputSink::discard();
    options.stderrTo = process::OutputSink::discard();
    auto orphan =
        process::ChildProcess::start({VirtuosoConfig{}.virtuosoBinary, "+foreground", "+configfile",
                                      (db().dataDir() / "virtuoso.ini").string()},
                                     options);
    ASSERT_TRUE(orphan) << orphan.error();
    // Bounded: the orphan writes its lock file early in its start-up.
    const auto deadline = Clock::now() + 30s;
    while (db().lockHolder() != orphan->pid() && Clock::now() < deadline) {
        ASSERT_FALSE(orphan->wait(20ms)) << "the orphan virtuoso-t ended by itself";
    }
    ASSERT_EQ(db().lockHolder(), orphan->pid());

    auto started = db().start();
    ASSERT_TRUE(started) << started.error();
    auto ended = orphan->wait(0ms);
    ASSERT_TRUE(ended) << "the orphan still runs beside the new Virtuoso";
    EXPECT_EQ(ended->signal, SIGKILL);
    EXPECT_NE(db().lockHolder(), orphan->pid());
    EXPECT_NE(objects(db(), "urn:o").find("before-orphan"), std::string::npos);
}

TEST_F(VirtuosoTest, SecondInstanceIsIndependent) {
    ScratchVirtuoso other;
    auto started = other.instance.start();
    ASSERT_TRUE(started) << started.error();
    EXPECT_NE(other.instance.httpPort(), db().httpPort());
    EXPECT_NE(other.instance.sqlPort(), db().sqlPort());
    ASSERT_TRUE(other.instance.isql(
        R"(SPARQL INSERT DATA { GRAPH <urn:i> { <urn:a> <urn:p> "other" } };)"));
    ASSERT_TRUE(db().isql(R"(SPARQL INSERT DATA { GRAPH <urn:i> { <urn:a> <urn:p> "shared" } };)"));
    const std::string inOther = objects(other.instance, "urn:i");
    const std::string inShared = objects(db(), "urn:i");
    EXPECT_NE(inOther.find("other"), std::string::npos) << inOther;
    EXPECT_EQ(inOther.find("shared"), std::string::npos) << inOther;
    EXPECT_NE(inShared.find("shared"), std::string::npos) << inShared;
    EXPECT_EQ(inShared.find("other"), std::string::npos) << inShared;
    std::ifstream a(other.instance.passwordPath());
    std::ifstream b(db().passwordPath());
    std::string pa;
    std::string pb;
    std::getline(a, pa);
    std::getline(b, pb);
    EXPECT_NE(pa, pb);
}

TEST(VirtuosoStartFailure, DataDirectoryThatCannotBeCreated) {
    TempDir dir;
    std::ofstream(dir.path() / "a-file") << "not a directory";
    VirtuosoInstance v(VirtuosoConfig{dir.path() / "a-file" / "db"});
    auto started = v.start();
    ASSERT_FALSE(started);
    EXPECT_NE(started.error().find((dir.path() / "a-file" / "db").string()), std::string::npos)
        << started.error();
    EXPECT_FALSE(v.running());
}

TEST(VirtuosoStartFailure, DatabaseThatCannotBeOpened) {
    TempDir dir;
    // A directory where the database file belongs: virtuoso-t exits at once.
    fs::create_directories(dir.path() / "db" / "virtuoso.db");
    VirtuosoInstance v(VirtuosoConfig{dir.path() / "db"});
    auto started = v.start();
    ASSERT_FALSE(started);
    EXPECT_NE(started.error().find("exited during start"), std::string::npos) << started.error();
    EXPECT_NE(started.error().find("Cannot open"), std::string::npos) << started.error();
    EXPECT_FALSE(v.running());
}

TEST(VirtuosoStartFailure, DataDirectoryNotWritable) {
    if (::geteuid() == 0) GTEST_SKIP() << "root writes anywhere; covered by the tests above";
    TempDir dir;
    fs::create_directories(dir.path() / "db");
    fs::permissions(dir.path() / "db", fs::perms::owner_read | fs::perms::owner_exec);
    VirtuosoInstance v(VirtuosoConfig{dir.path() / "db"});
    auto started = v.start();
    ASSERT_FALSE(started);
    EXPECT_NE(started.error().find((dir.path() / "db").string()), std::string::npos)
        << started.error();
}

TEST(VirtuosoStartFailure, FixedPortAlreadyInUse) {
    TempDir dir;
    const int fd = ::socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0);
    sockaddr_in addr{};
    addr.sin_family = AF_INET;
    addr.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    socklen_t len = sizeof addr;
    ASSERT_EQ(::bind(fd, reinterpret_cast<sockaddr*>(&addr), len), 0);
    ASSERT_EQ(::listen(fd, 1), 0);
    ASSERT_EQ(::getsockname(fd, reinterpret_cast<sockaddr*>(&addr), &len), 0);
    VirtuosoConfig config{dir.path() / "db"};
    config.sqlPort = ntohs(addr.sin_port);
    config.httpPort = 0;  // picked; the SQL port is fixed, so no retry elsewhere
    VirtuosoInstance v(config);
    auto started = v.start();
    ::close(fd);
    ASSERT_FALSE(started);
    EXPECT_NE(started.error().find("Failed to start listening"), std::string::npos)
        << started.error();
}

// ---------------------------------------------------------------------------------------
// Konclude

constexpr const char* kPrefixes = R"(@prefix : <http://example.org/cell#> .
@prefix owl: <http://www.w3.org/2002/07/owl#> .
@prefix rdf: <http://www.w3.org/1999/02/22-rdf-syntax-ns#> .
@prefix rdfs: <http://www.w3.org/2000/01/rdf-schema#> .
)";

const std::string kEx = "http://example.org/cell#";
const std::string kRdfType = std::string(rdf::vocab::kRdf) + "type";
const std::string kOwl(rdf::vocab::kOwl);
const std::string kRdfs(rdf::vocab::kRdfs);

rdf::Triple t(const std::string& s, const std::string& p, const std::string& o) {
    auto term = [](const std::string& x) {
        return x.starts_with("_:") ? rdf::blank(x.substr(2)) : rdf::iri(x);
    };
    return {term(s), term(p), term(o)};
}

TEST(Konclude, ConsistentOntology) {
    KoncludeReasoner reasoner;
    const auto t0 = Clock::now();
    auto consistent = reasoner.isConsistent(std::string(kPrefixes) + R"(
:Robot a owl:Class . :Gripper a owl:Class . :Robot owl:disjointWith :Gripper .
:ur5 a :Robot . :robotiq a :Gripper .
)");
    spdlog::info("TIMING one Konclude consistency run: {} ms", msSince(t0));
    ASSERT_TRUE(consistent) << consistent.error();
    EXPECT_TRUE(*consistent);
}

TEST(Konclude, InconsistentOntology) {
    KoncludeReasoner reasoner;
    auto consistent = reasoner.isConsistent(std::string(kPrefixes) + R"(
:Robot a owl:Class . :Gripper a owl:Class . :Robot owl:disjointWith :Gripper .
:thing a :Robot , :Gripper .
)");
    ASSERT_TRUE(consistent) << consistent.error();
    EXPECT_FALSE(*consistent);
}

TEST(Konclude, UnparsableInputIsAnErrorNotAVerdict) {
    KoncludeReasoner reasoner;
    auto consistent = reasoner.isConsistent(std::string(kPrefixes) + ":a :b \"unterminated .\n");
    ASSERT_FALSE(consistent);
    EXPECT_NE(consistent.error().find("parsers failed"), std::string::npos) << consistent.error();
}

TEST(Konclude, TimeoutIsAnError) {
    KoncludeConfig config;
    config.timeout = 1ms;
    auto consistent = KoncludeReasoner(config).isConsistent(kPrefixes);
    ASSERT_FALSE(consistent);
    EXPECT_NE(consistent.error().find("did not finish"), std::string::npos) << consistent.error();
}

TEST(Konclude, RealizationInfersTypes) {
    KoncludeReasoner reasoner;
    const auto t0 = Clock::now();
    auto realized = reasoner.realize(std::string(kPrefixes) + R"(
:Gripper a owl:Class . :Tool a owl:Class . :Vacuum a owl:Class . :SuctionTool a owl:Class .
:uses a owl:ObjectProperty .
:Gripper rdfs:subClassOf :Tool .
:SuctionTool owl:equivalentClass [ a owl:Restriction ; owl:onProperty :uses ;
                                   owl:someValuesFrom :Vacuum ] .
:robotiq a :Gripper .
:schmalz :uses :pump . :pump a :Vacuum .
)");
    spdlog::info("TIMING one Konclude realization run: {} ms", msSince(t0));
    ASSERT_TRUE(realized) << realized.error();
    EXPECT_TRUE(realized->consistent);
    const std::vector<ClassAssertion> expected{
        {kEx + "pump", kEx + "Vacuum"},
        {kEx + "robotiq", kEx + "Gripper"},
        {kEx + "robotiq", kEx + "Tool"},        // through rdfs:subClassOf
        {kEx + "schmalz", kEx + "SuctionTool"}  // through owl:someValuesFrom
    };
    EXPECT_EQ(realized->types, expected);
}

TEST(Konclude, RealizationOfAnInconsistentOntologySaysSo) {
    auto realized = KoncludeReasoner().realize(std::string(kPrefixes) + R"(
:A a owl:Class . :B a owl:Class . :A owl:disjointWith :B . :x a :A , :B .
)");
    ASSERT_TRUE(realized) << realized.error();
    EXPECT_FALSE(realized->consistent);
    EXPECT_TRUE(realized->types.empty());
}

TEST(Konclude, ParsesAbbreviatedIrisAndEntities) {
    auto types = parseRealization(R"(<?xml version="1.0"?>
<Ontology xmlns="http://www.w3.org/2002/07/owl#">
  <Prefix name="ex" IRI="http://ex.org/a&amp;b#"/>
  <ClassAssertion><Class abbreviatedIRI="ex:C"/><NamedIndividual IRI="http://ex.org/i?x=1&amp;y=2"/></ClassAssertion>
  <ClassAssertion><Class IRI="http://www.w3.org/2002/07/owl#Thing"/><NamedIndividual IRI="http://ex.org/i"/></ClassAssertion>
  <ClassAssertion><Class IRI="http://ex.org/D"/><AnonymousIndividual nodeID="n1"/></ClassAssertion>
</Ontology>)");
    ASSERT_TRUE(types) << types.error();
    ASSERT_EQ(types->size(), 1u);
    EXPECT_EQ((*types)[0], (ClassAssertion{"http://ex.org/i?x=1&y=2", "http://ex.org/a&b#C"}));
    EXPECT_FALSE(parseRealization("garbage"));
}

TEST(Konclude, BlankNodeStructuresStayTogether) {
    const std::vector<rdf::Triple> triples{
        t(kEx + "a", kRdfType, kEx + "A"),        t(kEx + "C", kRdfs + "subClassOf", "_:r"),
        t(kEx + "b", kRdfType, kEx + "B"),        t("_:r", kRdfType, kOwl + "Restriction"),
        t("_:r", kOwl + "someValuesFrom", "_:u"), t("_:u", kOwl + "unionOf", "_:l1"),
        t("_:l1", kOwl + "first", kEx + "A"),  // predicate does not matter here
        t("_:other", kRdfType, kEx + "A"),
    };
    const auto groups = blankNodeGroups(triples);
    ASSERT_EQ(groups.size(), 4u);
    EXPECT_EQ(groups[0].size(), 1u);
    EXPECT_EQ(groups[1].size(), 5u);  // C ⊑ _:r, and all of _:r, _:u, _:l1
    EXPECT_EQ(groups[2].size(), 1u);
    EXPECT_EQ(groups[3].size(), 1u);
}

/// A small cell ontology: the background that is known to be good.
std::vector<rdf::Triple> cellTBox() {
    std::vector<rdf::Triple> tbox;
    for (const char* c : {"Robot", "Gripper", "Tool", "Heavy", "Light", "StrongRobot", "Station"}) {
        tbox.push_back(t(kEx + c, kRdfType, kOwl + "Class"));
    }
    for (const char* p : {"holds", "mountedOn", "locatedAt"}) {
        tbox.push_back(t(kEx + p, kRdfType, kOwl + "ObjectProperty"));
    }
    tbox.push_back(t(kEx + "Gripper", kRdfs + "subClassOf", kEx + "Tool"));
    tbox.push_back(t(kEx + "Robot", kOwl + "disjointWith", kEx + "Tool"));
    tbox.push_back(t(kEx + "Heavy", kOwl + "disjointWith", kEx + "Light"));
    return tbox;
}

/// 30 harmless facts about a cell.
std::vector<rdf::Triple> harmlessFacts() {
    std::vector<rdf::Triple> facts;
    for (int i = 0; i < 10; ++i) {
        const std::string n = std::to_string(i);
        facts.push_back(t(kEx + "robot" + n, kRdfType, kEx + "Robot"));
        facts.push_back(t(kEx + "gripper" + n, kRdfType, kEx + "Gripper"));
        facts.push_back(t(kEx + "gripper" + n, kEx + "mountedOn", kEx + "robot" + n));
    }
    return facts;
}

TEST(Konclude, ExplainsADisjointnessViolation) {
    auto candidates = harmlessFacts();
    const auto bad1 = t(kEx + "robot3", kRdfType, kEx + "Gripper");  // a robot that is a tool
    candidates.insert(candidates.begin() + 17, bad1);
    KoncludeReasoner reasoner;
    const auto t0 = Clock::now();
    auto explanation = reasoner.explainInconsistency(cellTBox(), candidates);
    spdlog::info("TIMING explainInconsistency, 1 culprit pair among 31: {} ms, {} runs",
                 msSince(t0), explanation ? explanation->runs : 0);
    ASSERT_TRUE(explanation) << explanation.error();
    EXPECT_TRUE(explanation->inconsistent);
    EXPECT_FALSE(explanation->runLimitHit);
    const std::vector<rdf::Triple> expected{t(kEx + "robot3", kRdfType, kEx + "Robot"), bad1};
    auto conflict = explanation->conflict;
    std::sort(conflict.begin(), conflict.end());
    auto sortedExpected = expected;
    std::sort(sortedExpected.begin(), sortedExpected.end());
    EXPECT_EQ(conflict, sortedExpected);
}

TEST(Konclude, ExplainsAConflictThroughARestriction) {
    // StrongRobot ⊑ ∀holds.Heavy (a blank-node restriction, among the candidates);
    // r holds a feather that is Light, and Heavy and Light are disjoint.
    auto candidates = harmlessFacts();
    const std::vector<rdf::Triple> restriction{
        t(kEx + "StrongRobot", kRdfs + "subClassOf", "_:r"),
        t("_:r", kRdfType, kOwl + "Restriction"),
        t("_:r", kOwl + "onProperty", kEx + "holds"),
        t("_:r", kOwl + "allValuesFrom", kEx + "Heavy"),
    };
    const std::vector<rdf::Triple> culprits{
        t(kEx + "robot7", kRdfType, kEx + "StrongRobot"),
        t(kEx + "robot7", kEx + "holds", kEx + "feather"),
        t(kEx + "feather", kRdfType, kEx + "Light"),
    };
    // Spread out, the restriction's triples apart from each other.
    candidates.insert(candidates.begin() + 2, restriction[0]);
    candidates.insert(candidates.begin() + 9, culprits[0]);
    candidates.insert(candidates.begin() + 14, restriction[1]);
    candidates.insert(candidates.begin() + 20, culprits[1]);
    candidates.insert(candidates.begin() + 25, restriction[2]);
    candidates.push_back(culprits[2]);
    candidates.push_back(restriction[3]);
    candidates.push_back(t(kEx + "anvil", kRdfType, kEx + "Heavy"));  // harmless
    KoncludeReasoner reasoner;
    const auto t0 = Clock::now();
    auto explanation = reasoner.explainInconsistency(cellTBox(), candidates);
    spdlog::info("TIMING explainInconsistency, 7 culprit triples among 38: {} ms, {} runs",
                 msSince(t0), explanation ? explanation->runs : 0);
    ASSERT_TRUE(explanation) << explanation.error();
    EXPECT_TRUE(explanation->inconsistent);
    EXPECT_FALSE(explanation->runLimitHit);
    auto expected = restriction;
    expected.insert(expected.end(), culprits.begin(), culprits.end());
    std::sort(expected.begin(), expected.end());
    auto conflict = explanation->conflict;
    std::sort(conflict.begin(), conflict.end());
    EXPECT_EQ(conflict, expected);
    EXPECT_LE(explanation->runs, 30u);
}

TEST(Konclude, ExplanationWithinARunBudgetSaysSo) {
    auto candidates = harmlessFacts();
    candidates.push_back(t(kEx + "robot3", kRdfType, kEx + "Gripper"));
    KoncludeReasoner reasoner;
    auto explanation = reasoner.explainInconsistency(cellTBox(), candidates, ExplainOptions{4});
    ASSERT_TRUE(explanation) << explanation.error();
    EXPECT_TRUE(explanation->inconsistent);
    EXPECT_TRUE(explanation->runLimitHit);
    EXPECT_LE(explanation->runs, 4u);
    // Not minimal, but still a conflict.
    auto all = cellTBox();
    all.insert(all.end(), explanation->conflict.begin(), explanation->conflict.end());
    auto consistent = reasoner.isConsistent(rdf::writeTurtle(all));
    ASSERT_TRUE(consistent) << consistent.error();
    EXPECT_FALSE(*consistent);
}

TEST(Konclude, NothingToExplainInAConsistentSet) {
    KoncludeReasoner reasoner;
    auto explanation = reasoner.explainInconsistency(cellTBox(), harmlessFacts());
    ASSERT_TRUE(explanation) << explanation.error();
    EXPECT_FALSE(explanation->inconsistent);
    EXPECT_TRUE(explanation->conflict.empty());
    EXPECT_EQ(explanation->runs, 2u);

    auto badBackground = cellTBox();
    badBackground.push_back(t(kEx + "x", kRdfType, kEx + "Robot"));
    badBackground.push_back(t(kEx + "x", kRdfType, kEx + "Gripper"));
    auto refused = reasoner.explainInconsistency(badBackground, harmlessFacts());
    ASSERT_FALSE(refused);
    EXPECT_NE(refused.error().find("background"), std::string::npos) << refused.error();
}

}  // namespace
}  // namespace skillcell::kb::engine::engine_test
