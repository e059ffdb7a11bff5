// skillcell_bench_model_load: what a component's start spends on its models. For namespace 0
// alone and for the models of each component (the skills' models its class names, with the
// models they require), loads them into a new address space --repeat times, both ways:
//   - xml: each embedded NodeSet2 file parsed (parseNodeSet) and committed;
//   - snapshot: as servers load them (loadBaseNodeSet, loadCompanionModels), from the
//     snapshots the build made of the same files;
// and prints the median and p99 of each, with the ratio xml / snapshot. The two address
// spaces are compared node for node once per row (a row whose loads differ fails the run).
//
//   skillcell_bench_model_load [--repeat N]
#include <chrono>
#include <cstdio>
#include <functional>
#include <string>
#include <vector>

#include "common/command_line.hpp"
#include "devices/arm/arm_component.hpp"
#include "devices/gripper/gripper_component.hpp"
#include "devices/pickplace/pick_and_place_component.hpp"
#include "devices/toolchanger/tool_changer_component.hpp"
#include "latency_stats.hpp"
#include "mes/mes_component.hpp"
#include "ua/nodeset/companion_models.hpp"
#include "ua/nodeset/embedded_models.hpp"
#include "ua/nodeset/nodeset_exporter.hpp"

namespace {

using namespace skillcell;
using Clock = std::chrono::steady_clock;

struct Row {
    const char* name;
    std::span<const std::string_view> models;  // empty: namespace 0 only
};

/// The files a server with `models` loads, in its order.
std::vector<ua::EmbeddedNodeSet> filesOf(std::span<const std::string_view> models) {
    std::vector<ua::EmbeddedNodeSet> files(ua::kNamespaceZeroFiles.begin(),
                                           ua::kNamespaceZeroFiles.end());
    if (!models.empty()) {
        for (const auto& m :
             ua::companionModelsFor(models).value_or(std::vector<ua::CompanionModel>{})) {
            files.push_back({m.fileName, m.fileName});
        }
    }
    return files;
}

bool loadXml(ua::AddressSpace& as, std::span<const std::string_view> models) {
    for (const auto& [file, source] : filesOf(models)) {
        const auto st = ua::loadNodeSet(as, ua::embeddedModel(file), source);
        if (!st.ok()) {
            std::fprintf(stderr, "%s\n", st.error.c_str());
            return false;
        }
    }
    return true;
}

bool loadSnapshots(ua::AddressSpace& as, std::span<const std::string_view> models) {
    auto st = ua::loadBaseNodeSet(as);
    if (st.ok() && !models.empty()) st = ua::loadCompanionModels(as, models);
    if (!st.ok()) std::fprintf(stderr, "%s\n", st.error.c_str());
    return st.ok();
}

/// Both loads write the same NodeSet2 (every namespace but the server's own).
bool sameLoads(std::span<const std::string_view> models) {
    ua::AddressSpace a("urn:bench"), b("urn:bench");
    if (!loadXml(a, models) || !loadSnapshots(b, models)) return false;
    if (a.namespaces() != b.namespaces()) return false;
    std::vector<std::uint16_t> namespaces;
    for (std::size_t i = 0; i < a.namespaces().size(); ++i) {
        if (i != 1) namespaces.push_back(static_cast<std::uint16_t>(i));
    }
    std::string xa, xb;
    return ua::exportNodeSet(a, {namespaces}, xa).ok() &&
           ua::exportNodeSet(b, {namespaces}, xb).ok() && xa == xb;
}

bench::Samples time(int repeat, const std::function<bool(ua::AddressSpace&)>& load) {
    bench::Samples samples;
    for (int i = 0; i < repeat; ++i) {
        ua::AddressSpace as("urn:bench");
        const auto t0 = Clock::now();
        if (!load(as)) return {};
        samples.push_back(Clock::now() - t0);
    }
    return samples;
}

}  // namespace

int main(int argc, char** argv) {
    int repeat = 30;
    CLI::App app{
        "Model loading at a component's start: NodeSet2 XML against the build's "
        "snapshots of it, per component kind."};
    app.add_option("--repeat", repeat, "loads per row and way")
        ->check(CLI::PositiveNumber)
        ->capture_default_str();
    if (const auto exit = parseCommandLine(app, argc, argv)) return *exit;

    const Row rows[] = {
        {"namespace 0", {}},
        {"gripper adapter", devices::GripperComponent::skillModels()},
        {"arm", devices::ArmComponent::skillModels()},
        {"tool changer", devices::toolchanger::ToolChangerComponent::skillModels()},
        {"pick and place", devices::pickplace::PickAndPlaceComponent::skillModels()},
        {"MES", mes::MesComponent::skillModels()},
    };
    std::printf("model loading, ms (median / p99 over %d loads)\n", repeat);
    std::printf("  %-18s %17s %17s %8s\n", "component", "xml", "snapshot", "xml/snap");
    bool ok = true;
    for (const auto& row : rows) {
        if (!sameLoads(row.models)) {
            std::fprintf(stderr, "%s: the snapshot load differs from the XML load\n", row.name);
            ok = false;
            continue;
        }
        const auto xml = bench::summarize(
            time(repeat, [&](ua::AddressSpace& as) { return loadXml(as, row.models); }));
        const auto snap = bench::summarize(
            time(repeat, [&](ua::AddressSpace& as) { return loadSnapshots(as, row.models); }));
        std::printf("  %-18s %8.2f / %6.2f %8.2f / %6.2f %7.2fx\n", row.name, xml.medianUs / 1e3,
                    xml.p99Us / 1e3, snap.medianUs / 1e3, snap.p99Us / 1e3,
                    xml.medianUs / snap.medianUs);
    }
    return ok ? 0 : 1;
}
