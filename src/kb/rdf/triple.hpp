#pragma once
// RDF terms and triples as small values. The knowledge base builds them (from NodeSets, from
// discovery) and hands them to a serializer or an engine; nothing here parses or prints.
#include <compare>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace skillcell::kb::rdf {

struct Term {
    enum class Kind { Iri, Blank, Literal };
    Kind kind = Kind::Iri;
    std::string value;     // the IRI, the blank node label, or the literal's lexical form
    std::string datatype;  // literals: datatype IRI; empty means xsd:string
    std::string language;  // literals: language tag; then datatype is rdf:langString

    // NOLINTNEXTLINE(modernize-use-nullptr): clang-tidy 14 flags the literal 0 of the defaulted <=>
    friend auto operator<=>(const Term&, const Term&) = default;
    friend bool operator==(const Term&, const Term&) = default;
};

[[nodiscard]] inline Term iri(std::string value) {
    return {Term::Kind::Iri, std::move(value), {}, {}};
}
[[nodiscard]] inline Term blank(std::string label) {
    return {Term::Kind::Blank, std::move(label), {}, {}};
}
[[nodiscard]] inline Term literal(std::string lexical, std::string datatype = {}) {
    return {Term::Kind::Literal, std::move(lexical), std::move(datatype), {}};
}
[[nodiscard]] inline Term langLiteral(std::string lexical, std::string language) {
    return {Term::Kind::Literal, std::move(lexical), {}, std::move(language)};
}

struct Triple {
    Term subject;
    Term predicate;
    Term object;

    // NOLINTNEXTLINE(modernize-use-nullptr): as above
    friend auto operator<=>(const Triple&, const Triple&) = default;
    friend bool operator==(const Triple&, const Triple&) = default;
};

/// The triples with every blank node label prefixed by `scope`. A label names a node within
/// one document only: two documents put together (for the reasoner, in one request) keep
/// their blank nodes apart only when each has a scope of its own.
[[nodiscard]] inline std::vector<Triple> scopeBlankNodes(std::vector<Triple> triples,
                                                         std::string_view scope) {
    for (auto& t : triples) {
        for (Term* term : {&t.subject, &t.object}) {
            if (term->kind == Term::Kind::Blank) term->value.insert(0, scope);
        }
    }
    return triples;
}

}  // namespace skillcell::kb::rdf
