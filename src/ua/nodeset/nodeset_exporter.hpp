#pragma once
// NodeSet2 exporter: writes the nodes of chosen namespaces of an AddressSpace back to
// UANodeSet XML, in the form nodeset_loader reads. Used to check that loading loses nothing
// (load -> export -> load gives the same address space) and to hand a component's
// self-description to tools that read NodeSet2 (the knowledge base).
//
// What is written: every attribute the loader reads, all forward references of the
// exported nodes plus the inverse ones whose other end is not exported (so the file is
// self-contained), values in the XML Variant encoding (structures through their
// DataTypeDefinition), <Definition> of data types and the <Model>s registered for the
// exported namespaces. Values produced by ValueSource callbacks are not exported.
#include <cstdint>
#include <string>
#include <vector>

#include "ua/address_space/address_space.hpp"
#include "ua/nodeset/nodeset_loader.hpp"

namespace skillcell::ua {

struct NodeSetExportOptions {
    /// Server namespace indices whose nodes are written (e.g. {0} or {2}).
    std::vector<std::uint16_t> namespaces;
};

/// Writes the XML into `out`. The status names the first node whose value cannot be
/// written in the XML encoding (a DataValue or DiagnosticInfo value, a structure without a
/// definition).
[[nodiscard]] NodeSetStatus exportNodeSet(const AddressSpace& as,
                                          const NodeSetExportOptions& options, std::string& out);

}  // namespace skillcell::ua
