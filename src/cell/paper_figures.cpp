#include "cell/paper_figures.hpp"

#include <array>
#include <utility>

#include "cell/component_uris.hpp"
#include "cell/device_arguments.hpp"

namespace skillcell::cell {
namespace {

// A URI of `kind`: the kind's own, or the kind's with ":<name>".
bool ofKind(std::string_view uri, std::string_view kind) {
    return uri == kind || (uri.size() > kind.size() && uri.substr(0, kind.size()) == kind &&
                           uri[kind.size()] == ':');
}

std::string_view adapterUri(std::string_view model) {
    const AdapterModel* m = findAdapterModel(model);
    return m == nullptr ? std::string_view() : m->applicationUri;
}

}  // namespace

const PaperDetection* paperDetection(std::string_view applicationUri) {
    static const std::array<std::pair<std::string_view, PaperDetection>, 6> kParts{{
        {adapterUri("robotiq-2f85"), {"Robotiq adapter", 8422}},
        {adapterUri("schmalz-ecbpi"), {"Schmalz adapter", 9635}},
        {adapterUri("dh-ag95"), {"AG-95 adapter", 0}},
        {kToolChangerUri, {"tool changer", 253}},
        {kUr5Uri, {"UR5", 313}},
        {kPickAndPlaceUri, {"pick-and-place", 211}},
    }};
    for (const auto& [kind, figure] : kParts) {
        if (!kind.empty() && ofKind(applicationUri, kind)) return &figure;
    }
    return nullptr;
}

}  // namespace skillcell::cell
