#include "kb/sparql_form.hpp"

#include <cctype>
#include <string>

namespace skillcell::kb {
namespace {

bool space(char c) {
    return c == ' ' || c == '\t' || c == '\n' || c == '\r';
}

// Skips white space and '#' comments.
void skipBlank(std::string_view& t) {
    for (;;) {
        while (!t.empty() && space(t.front())) t.remove_prefix(1);
        if (t.empty() || t.front() != '#') return;
        const auto eol = t.find_first_of("\r\n");
        t = eol == std::string_view::npos ? std::string_view() : t.substr(eol);
    }
}

// The keyword at the front (letters only), upper-cased.
std::string keyword(std::string_view t) {
    std::string k;
    for (const char c : t) {
        if (std::isalpha(static_cast<unsigned char>(c)) == 0) break;
        k += static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
    }
    return k;
}

// Skips "<IRI>" at the front; false when there is none.
bool skipIri(std::string_view& t) {
    skipBlank(t);
    if (t.empty() || t.front() != '<') return false;
    const auto close = t.find('>');
    if (close == std::string_view::npos) return false;
    t.remove_prefix(close + 1);
    return true;
}

}  // namespace

SparqlForm sparqlForm(std::string_view t) {
    for (int declarations = 0; declarations < 10'000; ++declarations) {
        skipBlank(t);
        const std::string k = keyword(t);
        if (k == "SELECT") return SparqlForm::Select;
        if (k == "CONSTRUCT") return SparqlForm::Construct;
        if (k == "DESCRIBE") return SparqlForm::Describe;
        if (k == "ASK") return SparqlForm::Ask;
        if (k == "BASE") {
            t.remove_prefix(k.size());
            if (!skipIri(t)) return SparqlForm::Update;
        } else if (k == "PREFIX") {
            t.remove_prefix(k.size());
            skipBlank(t);
            // PNAME_NS: an optional prefix name, then ':'.
            const auto colon = t.find(':');
            if (colon == std::string_view::npos) return SparqlForm::Update;
            for (const char c : t.substr(0, colon)) {
                if (space(c) || c == '<' || c == '#') return SparqlForm::Update;
            }
            t.remove_prefix(colon + 1);
            if (!skipIri(t)) return SparqlForm::Update;
        } else {
            return SparqlForm::Update;
        }
    }
    return SparqlForm::Update;
}

}  // namespace skillcell::kb
