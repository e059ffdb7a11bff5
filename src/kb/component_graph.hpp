#pragma once
// ComponentGraphs: what discovery says about the cell's components, as RDF for the knowledge
// base (process ontology, models/owl/process.ttl). One named graph per component (by its
// application URI) with the component and every skill it has offered: a skill that went
// away stays, with proc:available false, so that a process can still say which skill it
// lacks (the knowledge base forgets nothing because a gripper was unplugged).
//
// Not thread-safe: feed it from one thread (the KB's discovery worker).
#include <map>
#include <set>
#include <string>
#include <vector>

#include "kb/knowledge_base.hpp"
#include "skills/skill_detector.hpp"

namespace skillcell::kb {

inline constexpr const char* kProcessVocabulary = "http://skillcell.dev/ontology/process#";

/// "urn:skillcell:component:<application URI, percent-encoded>".
[[nodiscard]] std::string componentIri(const std::string& applicationUri);
/// The graph that holds what discovery says about a component.
[[nodiscard]] std::string componentGraphIri(const std::string& applicationUri);
/// The IRI of a skill type as the NodeSet converter names it (kb/owl/node_iri.hpp): what a
/// process's proc:requiresSkillType holds.
[[nodiscard]] std::string skillTypeIri(const skills::SkillTypeRef& type);

class ComponentGraphs {
public:
    /// Takes the skills `live` (what the detector offers now for `applicationUri`; empty
    /// when the component is gone) and returns the component's graph: every skill seen,
    /// each with proc:available.
    [[nodiscard]] GraphData update(const std::string& applicationUri,
                                   const std::vector<skills::SkillInstance>& live);
    /// The namespace URIs of the skill types seen (the models the KB needs).
    [[nodiscard]] std::set<std::string> typeNamespaces() const;

private:
    struct Component {
        std::string endpointUrl;
        std::map<std::string, skills::SkillInstance> skills;  // by node id text
    };
    std::map<std::string, Component> components_;
};

}  // namespace skillcell::kb
