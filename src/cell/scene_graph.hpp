#pragma once
// A cell's scene as the knowledge base knows it: the cell file's docks (with the flange pose
// at which their tools lock), the tools they hold (with their grip type) and the objects (with
// their ids and poses), as triples of the process ontology (models/owl/process.ttl). A process
// refers to them by IRI (`@prefix cell: <http://skillcell.dev/cell/paper#>`, `cell:dockP`)
// instead of repeating their poses: the cell file is the one place where they are written.
#include <string>
#include <vector>

#include "cell/cell_file.hpp"
#include "kb/rdf/triple.hpp"

namespace skillcell::cell {

/// The graph of the cell's scene, and the namespace of its resources ("<graph>#<name>").
[[nodiscard]] std::string sceneGraphIri(const CellFile& cell);

/// The scene's triples: each dock a proc:ToolDock with its proc:pose and what it proc:holds;
/// each tool a proc:Tool with the proc:gripType of its adapter model; each object a
/// proc:PhysicalObject with its proc:objectId and proc:pose.
[[nodiscard]] std::vector<kb::rdf::Triple> sceneTriples(const CellFile& cell);

}  // namespace skillcell::cell
