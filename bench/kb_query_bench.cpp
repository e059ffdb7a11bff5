// The knowledge base's query latency for what the MES asks before every step: "an available
// skill of type X (any subtype) with constraints", with 10, 100 and 500 components recorded.
// It runs a private Virtuoso (kb/engine), loads the project's models and synthetic
// component graphs (as discovery records them, kb/component_graph), and times two queries
// through the KB's store client:
//   grasp: an available GripperSkillType instance with grip type "parallel", offered by an
//          available component, with its discovery URL;
//   move:  an available MoveSkillType instance whose type declares a MaxVelocity parameter
//          with an EURange reaching at least 1 m/s (a constraint on the skill model).
// Only the last component's skills fit, so every query searches all components; each answer
// is checked. Baseline in the same run: ASK {} (the HTTP and engine round trip alone).
// Usage: skillcell_bench_kb_query [--components 10,100,500] [--queries N]
#include <spdlog/spdlog.h>

#include <chrono>
#include <iostream>

#include "common/command_line.hpp"
#include "kb/knowledge_base.hpp"
#include "kb/store/http_sparql_store.hpp"
#include "latency_stats.hpp"
#include "private_virtuoso.hpp"
#include "synthetic_components.hpp"

namespace {

using namespace skillcell;
using Clock = std::chrono::steady_clock;

// The declaring types first, in a subquery: Virtuoso 7.2 answers a join of two property
// paths over an unbound middle (?type subClassOf* MoveSkillType, ?type subClassOf*
// ?declaring) with only some of the rows, depending on the plan (measured here: one declaring
// type of six). A subquery is evaluated on its own.
const std::string kMoveQuery =
    std::string(bench::kSyntheticPrefixes) +
    "SELECT ?skill WHERE {"
    "  { SELECT DISTINCT ?declaring WHERE {"
    "      ?declaring ua:HasComponent ?set . ?set opc:browseName \"ParameterSet\" ."
    "      ?set ua:HasComponent ?p . ?p opc:browseName \"MaxVelocity\" ;"
    "         opc:euRangeHigh ?max . FILTER(?max >= 1.0) } }"
    "  ?type rdfs:subClassOf* ?declaring ."
    "  ?type rdfs:subClassOf* rskill:MoveSkillType ."
    "  ?skill a ?type ; proc:available true } LIMIT 1";

bench::Samples timeQuery(kb::KnowledgeBase& kb, const std::string& q, int count,
                         const std::string& mustContain, bool& wrong) {
    bench::Samples samples;
    for (int i = 0; i < count; ++i) {
        const auto t0 = Clock::now();
        auto r = kb.query(q, kb::media::kSparqlJson);
        samples.push_back(Clock::now() - t0);
        if (!r || r->body.find(mustContain) == std::string::npos) {
            std::cerr << "wrong answer: " << (r ? r->body : r.error()) << "\n";
            wrong = true;
            break;
        }
    }
    return samples;
}

void print(const char* what, std::size_t n, const bench::Samples& s, double baselineMedianUs) {
    const auto st = bench::summarize(s);
    std::printf(
        "%-9s components=%-4zu n=%-4zu median=%8.0f us  p99=%8.0f us  (%.1fx the ASK {} "
        "round trip)\n",
        what, n, st.n, st.medianUs, st.p99Us, st.medianUs / baselineMedianUs);
}

}  // namespace

int main(int argc, char** argv) {
    std::vector<std::size_t> sizes{10, 100, 500};
    int count = 200;
    CLI::App app{
        "SPARQL queries of the MES and the KB against Virtuoso holding N synthetic "
        "components, beside the store's empty round trip"};
    app.add_option("--components", sizes, "cell sizes, comma-separated")
        ->delimiter(',')
        ->check(CLI::PositiveNumber)
        ->capture_default_str();
    app.add_option("--queries", count, "queries of each kind at each size")
        ->check(CLI::PositiveNumber)
        ->capture_default_str();
    if (const auto exit = skillcell::parseCommandLine(app, argc, argv)) return *exit;
    spdlog::set_level(spdlog::level::warn);
    std::string error;
    auto virtuoso = bench::PrivateVirtuoso::start("skillcell-bench-kb", &error);
    if (!virtuoso) {
        std::cerr << error << "\n";
        return 1;
    }
    int rc = 0;
    {
        kb::HttpSparqlStore store(kb::HttpSparqlEndpoint::of(virtuoso->instance()));
        kb::KnowledgeBase knowledge(store, nullptr);  // the store's speed, not the reasoner's
        if (auto s = knowledge.loadBuiltInModels(false); !s) {
            std::cerr << s.error() << "\n";
            return 1;
        }
        std::printf("Virtuoso 7.2, SPARQL over HTTP on loopback, %d queries each\n", count);
        for (const std::size_t n : sizes) {
            const auto t0 = Clock::now();
            auto graphs = bench::syntheticComponents(n);
            // In loads of 40 components: each is one request of ~800 triples.
            for (std::size_t at = 0; at < graphs.size() && rc == 0; at += 40) {
                const std::vector<kb::GraphData> batch(
                    graphs.begin() + static_cast<std::ptrdiff_t>(at),
                    graphs.begin() + static_cast<std::ptrdiff_t>(std::min(graphs.size(), at + 40)));
                if (auto s = knowledge.load(batch); !s) {
                    std::cerr << s.error().substr(0, 2000) << "\n";
                    rc = 1;
                }
            }
            if (rc != 0) break;
            std::printf("loaded %zu components in %.0f ms\n", n,
                        std::chrono::duration<double, std::milli>(Clock::now() - t0).count());
            bool wrong = false;
            const std::string last = "urn:bench:component:" + std::to_string(n - 1);
            const auto baseline =
                bench::summarize(timeQuery(knowledge, "ASK {}", count, "boolean", wrong));
            const std::string lastIri = kb::componentIri(last);
            print("grasp", n,
                  timeQuery(knowledge, bench::kSyntheticGraspQuery, count, lastIri + "/", wrong),
                  baseline.medianUs);
            print("move", n, timeQuery(knowledge, kMoveQuery, count, lastIri + "/", wrong),
                  baseline.medianUs);
            std::printf("%-9s components=%-4zu median=%8.0f us\n", "ASK {}", n, baseline.medianUs);
            if (wrong) {
                rc = 1;
                break;
            }
        }
    }
    return rc;
}
