#pragma once
// Turtle in and out, through libserd (a real serializer: escaping, prefixes, literals).
// writeTurtle sorts and de-duplicates, so the same triples give byte-identical text.
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "kb/expected.hpp"
#include "kb/rdf/triple.hpp"

namespace skillcell::kb::rdf {

/// A prefix declaration: name ("ua") and namespace IRI.
using Prefix = std::pair<std::string, std::string>;

/// Serializes `triples` as Turtle with `prefixes` (abbreviated where they apply).
[[nodiscard]] std::string writeTurtle(const std::vector<Triple>& triples,
                                      const std::vector<Prefix>& prefixes = {});
/// Serializes `triples` as N-Triples (one triple per line, full IRIs): the form SPARQL's
/// INSERT DATA takes, and that Turtle readers read too. Sorted and unique like writeTurtle.
[[nodiscard]] std::string writeNTriples(const std::vector<Triple>& triples);
/// Parses Turtle (or N-Triples); `baseIri` resolves relative IRIs. Errors name the line.
[[nodiscard]] Expected<std::vector<Triple>> readTurtle(std::string_view text,
                                                       std::string_view baseIri = {});

/// An xsd:decimal literal of `v`: no exponent (1e-7 is no decimal), the shortest digits that
/// read back as the same double. The process ontology's numbers are decimals: xsd:double and
/// xsd:decimal have disjoint value spaces in OWL 2 (docs/knowledge_base.md).
[[nodiscard]] Term decimalLiteral(double v);

/// Well-known vocabularies.
namespace vocab {
inline constexpr std::string_view kRdf = "http://www.w3.org/1999/02/22-rdf-syntax-ns#";
inline constexpr std::string_view kRdfs = "http://www.w3.org/2000/01/rdf-schema#";
inline constexpr std::string_view kOwl = "http://www.w3.org/2002/07/owl#";
inline constexpr std::string_view kXsd = "http://www.w3.org/2001/XMLSchema#";
}  // namespace vocab

}  // namespace skillcell::kb::rdf
