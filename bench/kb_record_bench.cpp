// skillcell_bench_kb_record: what recording one component costs the knowledge base as the
// cell grows, with a private Virtuoso and Konclude, the project's models, and N synthetic
// component graphs (bench/synthetic_components.hpp) recorded as discovery records them.
// For each N of --components:
//   record one    KnowledgeBase::record() of one component again: checked against the
//                 models alone (how the KB records a component)
//   load one      KnowledgeBase::load() of one more component graph: the whole KB checked
//                 (how the KB recorded a component before; the baseline, in the same run)
//   reads         the grasp query that the MES asks before a step, idle and while another
//                 thread records components without pause (reads take no lock of the KB's)
// Usage: skillcell_bench_kb_record [--components 10,50,200] [--recordings N]
#include <spdlog/spdlog.h>

#include <atomic>
#include <chrono>
#include <iostream>
#include <thread>

#include "common/command_line.hpp"
#include "kb/engine/konclude_reasoner.hpp"
#include "kb/knowledge_base.hpp"
#include "kb/store/http_sparql_store.hpp"
#include "latency_stats.hpp"
#include "private_virtuoso.hpp"
#include "synthetic_components.hpp"

namespace {

using namespace skillcell;
using Clock = std::chrono::steady_clock;

// The MES's question before a pick, as a KB with a reasoner answers it: the inferred types
// make the subclass path unnecessary. (With them, Virtuoso 7.2 answers the property-path form
// of bench/kb_query_bench.cpp with no rows on a few components: a plan from the path.)
const std::string kGraspQuery = std::string(bench::kSyntheticPrefixes) +
                                "SELECT ?skill ?url WHERE {"
                                "  ?skill a gskill:GripperSkillType ; proc:available true ;"
                                "         proc:gripType \"parallel\" ."
                                "  ?component proc:offers ?skill ; proc:available true ;"
                                "             proc:discoveryUrl ?url } LIMIT 1";

double ms(const bench::LatencyStats& s, bool p99 = false) {
    return (p99 ? s.p99Us : s.medianUs) / 1000.0;
}

template <class F>
bench::Samples timed(int count, F&& f, bool& failed) {
    bench::Samples samples;
    for (int i = 0; i < count && !failed; ++i) {
        const auto t0 = Clock::now();
        failed = !f();
        samples.push_back(Clock::now() - t0);
    }
    return samples;
}

bool recorded(const std::vector<Status>& statuses) {
    for (const auto& s : statuses) {
        if (!s) {
            std::cerr << "record: " << s.error().substr(0, 2000) << "\n";
            return false;
        }
    }
    return true;
}

bool answers(kb::KnowledgeBase& knowledge, const std::string& fit) {
    auto r = knowledge.query(kGraspQuery, kb::media::kSparqlJson);
    if (!r || r->body.find(fit) == std::string::npos) {
        std::cerr << "wrong answer: " << (r ? r->body : r.error()) << "\n";
        return false;
    }
    return true;
}

}  // namespace

int main(int argc, char** argv) {
    std::vector<std::size_t> sizes{10, 50, 200};
    int count = 10;
    CLI::App app{
        "Recording one component in a KB that holds N others: time to recorded, and "
        "SPARQL reads while it records"};
    app.add_option("--components", sizes, "sizes of the KB in components, comma-separated")
        ->delimiter(',')
        ->check(CLI::PositiveNumber)
        ->capture_default_str();
    app.add_option("--recordings", count, "recordings at each size")
        ->check(CLI::PositiveNumber)
        ->capture_default_str();
    if (const auto exit = skillcell::parseCommandLine(app, argc, argv)) return *exit;
    spdlog::set_level(spdlog::level::warn);
    std::string error;
    auto virtuoso = bench::PrivateVirtuoso::start("skillcell-bench-kb-record", &error);
    if (!virtuoso) {
        std::cerr << error << "\n";
        return 1;
    }
    int rc = 0;
    {
        kb::HttpSparqlStore store(kb::HttpSparqlEndpoint::of(virtuoso->instance()));
        const kb::engine::KoncludeReasoner reasoner;
        kb::KnowledgeBase knowledge(store, &reasoner);
        if (auto s = knowledge.loadBuiltInModels(false); !s) {
            std::cerr << s.error() << "\n";
            return 1;
        }
        std::printf("Virtuoso 7.2 and Konclude, %d recordings each; times in ms\n", count);
        std::printf("%-11s %-22s %-22s %-7s %-22s %-22s\n", "components", "record one p50/p99",
                    "load one p50/p99", "ratio", "reads idle p50/p99", "reads recording p50/p99");
        std::size_t have = 0;
        std::vector<kb::GraphData> graphs;
        for (const std::size_t n : sizes) {
            if (n <= have) continue;  // sizes grow: a cell is only added to
            // The cell of n, recorded as discovery records a cell starting: in batches.
            // n + 1 graphs: the last (one that fits the query) in the cell, the one before
            // it kept for the baseline.
            graphs = bench::syntheticComponents(n + 1);
            std::swap(graphs[n - 1], graphs[n]);
            const std::string fit = kb::componentIri("urn:bench:component:" + std::to_string(n));
            for (std::size_t at = have; at < n && rc == 0;
                 at += kb::KnowledgeBase::kMaxGraphsPerLoad) {
                const auto end = std::min(n, at + kb::KnowledgeBase::kMaxGraphsPerLoad);
                if (!recorded(knowledge.record(
                        std::vector<kb::GraphData>(graphs.begin() + static_cast<long>(at),
                                                   graphs.begin() + static_cast<long>(end))))) {
                    rc = 1;
                }
            }
            have = n;
            if (rc != 0) break;
            bool failed = false;
            const auto recordOne = bench::summarize(timed(
                count, [&] { return recorded(knowledge.record({graphs[n / 2]})); }, failed));
            // The baseline: a load of one more graph, checked with the whole KB; then gone
            // again, so that the next size starts from components only.
            const auto loadOne = bench::summarize(timed(
                std::max(1, count / 3),
                [&] {
                    auto s = knowledge.load({graphs[n]});
                    if (!s) std::cerr << "load: " << s.error().substr(0, 2000) << "\n";
                    return static_cast<bool>(s);
                },
                failed));
            if (auto s = knowledge.update(
                    "DROP SILENT GRAPH <" + graphs[n].iri + "> ; DELETE DATA { GRAPH <" +
                    std::string(kb::kRegistryGraph) + "> { <" + graphs[n].iri + "> a <" +
                    std::string(kb::kKbVocabulary) + "Graph> } }");
                !s) {
                std::cerr << "update: " << s.error() << "\n";
                failed = true;
            }
            const int reads = 10 * count;
            const auto idle = bench::summarize(timed(
                reads, [&] { return answers(knowledge, fit); }, failed));
            std::atomic<bool> stop{false};
            std::atomic<int> recordings{0};
            std::atomic<bool> recordFailed{false};
            std::thread recorder([&] {
                for (std::size_t i = 0; !stop; ++i) {
                    if (!recorded(knowledge.record({graphs[i % n]}))) {
                        recordFailed = true;
                        return;
                    }
                    ++recordings;
                }
            });
            const auto busy = bench::summarize(timed(
                reads, [&] { return answers(knowledge, fit); }, failed));
            stop = true;
            recorder.join();
            if (failed || recordFailed) {
                rc = 1;
                break;
            }
            const auto pair = [](const bench::LatencyStats& s) {
                char text[32];
                std::snprintf(text, sizeof text, "%8.1f / %-8.1f", ms(s), ms(s, true));
                return std::string(text);
            };
            std::printf("%-11zu %-22s %-22s %5.1fx  %-22s %-22s (%d recordings meanwhile)\n", n,
                        pair(recordOne).c_str(), pair(loadOne).c_str(),
                        loadOne.medianUs / recordOne.medianUs, pair(idle).c_str(),
                        pair(busy).c_str(), recordings.load());
        }
    }
    return rc;
}
