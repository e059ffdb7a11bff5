#pragma once
// What a SPARQL request is, from its first keyword after the prologue: a query (SELECT,
// CONSTRUCT, DESCRIBE, ASK) or anything else, which may change the store and is treated as
// an update wherever it comes from. Stores execute updates sent as queries (Virtuoso does,
// as `query=INSERT DATA ...`), so the knowledge base decides by the text, not by the
// parameter it came in.
#include <string_view>

namespace skillcell::kb {

enum class SparqlForm { Select, Construct, Describe, Ask, Update };

/// The form of `text`. The prologue (BASE, PREFIX), comments and white space are skipped;
/// anything but the four query forms after them, engine pragmas such as Virtuoso's DEFINE
/// included, is an Update.
[[nodiscard]] SparqlForm sparqlForm(std::string_view text);

[[nodiscard]] inline bool isQuery(std::string_view text) {
    return sparqlForm(text) != SparqlForm::Update;
}

}  // namespace skillcell::kb
