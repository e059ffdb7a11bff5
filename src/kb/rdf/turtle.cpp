#include "kb/rdf/turtle.hpp"

#include <serd/serd.h>

#include <algorithm>
#include <array>
#include <charconv>
#include <cstdarg>
#include <cstdio>
#include <memory>

namespace skillcell::kb::rdf {
namespace {

const std::uint8_t* bytes(const std::string& s) {
    return reinterpret_cast<const std::uint8_t*>(s.c_str());
}

SerdNode serdNode(SerdType type, const std::string& s) {
    return serd_node_from_substring(type, bytes(s), s.size());
}

SerdNode serdNodeOf(const Term& t) {
    switch (t.kind) {
        case Term::Kind::Iri:
            return serdNode(SERD_URI, t.value);
        case Term::Kind::Blank:
            return serdNode(SERD_BLANK, t.value);
        case Term::Kind::Literal:
            return serdNode(SERD_LITERAL, t.value);
    }
    return SERD_NODE_NULL;
}

struct EnvDeleter {
    void operator()(SerdEnv* e) const { serd_env_free(e); }
};
struct WriterDeleter {
    void operator()(SerdWriter* w) const { serd_writer_free(w); }
};
struct ReaderDeleter {
    void operator()(SerdReader* r) const { serd_reader_free(r); }
};
using EnvPtr = std::unique_ptr<SerdEnv, EnvDeleter>;

size_t appendToString(const void* buf, size_t len, void* stream) {
    static_cast<std::string*>(stream)->append(static_cast<const char*>(buf), len);
    return len;
}

// What the reader's callbacks fill in.
struct ReadState {
    SerdEnv* env = nullptr;
    std::vector<Triple> triples;
    std::string error;
};

std::string nodeText(const SerdNode* n) {
    return {reinterpret_cast<const char*>(n->buf), n->n_bytes};
}

// CURIEs and relative IRIs are expanded against the document's prefixes and base.
bool expandIri(ReadState& st, const SerdNode* n, std::string& out) {
    SerdNode expanded = serd_env_expand_node(st.env, n);
    if (expanded.buf == nullptr) {
        st.error = "cannot expand <" + nodeText(n) + "> (unknown prefix or no base IRI)";
        return false;
    }
    out = nodeText(&expanded);
    serd_node_free(&expanded);
    return true;
}

bool termOf(ReadState& st, const SerdNode* n, Term& out) {
    switch (n->type) {
        case SERD_URI:
        case SERD_CURIE:
            out.kind = Term::Kind::Iri;
            return expandIri(st, n, out.value);
        case SERD_BLANK:
            out.kind = Term::Kind::Blank;
            out.value = nodeText(n);
            return true;
        case SERD_LITERAL:
            out.kind = Term::Kind::Literal;
            out.value = nodeText(n);
            return true;
        case SERD_NOTHING:
            break;
    }
    st.error = "unexpected node type";
    return false;
}

SerdStatus onBase(void* handle, const SerdNode* uri) {
    return serd_env_set_base_uri(static_cast<ReadState*>(handle)->env, uri);
}

SerdStatus onPrefix(void* handle, const SerdNode* name, const SerdNode* uri) {
    return serd_env_set_prefix(static_cast<ReadState*>(handle)->env, name, uri);
}

SerdStatus onStatement(void* handle, SerdStatementFlags /*flags*/, const SerdNode* /*graph*/,
                       const SerdNode* subject, const SerdNode* predicate, const SerdNode* object,
                       const SerdNode* datatype, const SerdNode* lang) {
    auto& st = *static_cast<ReadState*>(handle);
    Triple t;
    if (!termOf(st, subject, t.subject) || !termOf(st, predicate, t.predicate) ||
        !termOf(st, object, t.object)) {
        return SERD_ERR_BAD_SYNTAX;
    }
    if (datatype != nullptr && datatype->buf != nullptr &&
        !expandIri(st, datatype, t.object.datatype)) {
        return SERD_ERR_BAD_SYNTAX;
    }
    if (lang != nullptr && lang->buf != nullptr) t.object.language = nodeText(lang);
    st.triples.push_back(std::move(t));
    return SERD_SUCCESS;
}

SerdStatus onError(void* handle, const SerdError* e) {
    auto& st = *static_cast<ReadState*>(handle);
    if (!st.error.empty()) return SERD_SUCCESS;  // the first error is the one that matters
    std::array<char, 512> text{};
    va_list args;
    // serd hands a started va_list; the analyzer cannot see that across the C API.
    va_copy(args, *e->args);  // NOLINT(clang-analyzer-valist.Uninitialized)
    std::vsnprintf(text.data(), text.size(), e->fmt, args);  // NOLINT: serd's printf-style API
    va_end(args);
    std::string message(text.data());
    while (!message.empty() && message.back() == '\n') message.pop_back();
    st.error =
        "line " + std::to_string(e->line) + ", column " + std::to_string(e->col) + ": " + message;
    return SERD_SUCCESS;
}

std::string write(SerdSyntax syntax, const std::vector<Triple>& triples,
                  const std::vector<Prefix>& prefixes) {
    // Sorted and unique: the text depends on the set of triples only, never on the order
    // they were produced in. What is sorted is pointers: a Triple is nine strings, and the
    // knowledge base writes its whole content this way for each consistency check.
    std::vector<const Triple*> order;
    order.reserve(triples.size());
    for (const auto& t : triples) order.push_back(&t);
    std::sort(order.begin(), order.end(), [](const Triple* a, const Triple* b) { return *a < *b; });
    order.erase(std::unique(order.begin(), order.end(),
                            [](const Triple* a, const Triple* b) { return *a == *b; }),
                order.end());

    std::string out;
    EnvPtr env(serd_env_new(nullptr));
    const auto style = syntax == SERD_TURTLE ? (SERD_STYLE_ABBREVIATED | SERD_STYLE_CURIED) : 0U;
    std::unique_ptr<SerdWriter, WriterDeleter> writer(serd_writer_new(
        syntax, static_cast<SerdStyle>(style), env.get(), nullptr, appendToString, &out));
    for (const auto& [name, ns] : prefixes) {
        SerdNode n = serdNode(SERD_LITERAL, name);
        SerdNode u = serdNode(SERD_URI, ns);
        serd_writer_set_prefix(writer.get(), &n, &u);
    }
    for (const Triple* triple : order) {
        const Triple& t = *triple;
        SerdNode s = serdNodeOf(t.subject);
        SerdNode p = serdNodeOf(t.predicate);
        SerdNode o = serdNodeOf(t.object);
        SerdNode dt =
            t.object.datatype.empty() ? SERD_NODE_NULL : serdNode(SERD_URI, t.object.datatype);
        SerdNode lang =
            t.object.language.empty() ? SERD_NODE_NULL : serdNode(SERD_LITERAL, t.object.language);
        serd_writer_write_statement(writer.get(), 0, nullptr, &s, &p, &o,
                                    dt.buf != nullptr ? &dt : nullptr,
                                    lang.buf != nullptr ? &lang : nullptr);
    }
    serd_writer_finish(writer.get());
    return out;
}

}  // namespace

std::string writeTurtle(const std::vector<Triple>& triples, const std::vector<Prefix>& prefixes) {
    return write(SERD_TURTLE, triples, prefixes);
}

std::string writeNTriples(const std::vector<Triple>& triples) {
    return write(SERD_NTRIPLES, triples, {});
}

Expected<std::vector<Triple>> readTurtle(std::string_view text, std::string_view baseIri) {
    std::string base(baseIri);
    SerdNode baseNode = serdNode(SERD_URI, base);
    EnvPtr env(serd_env_new(base.empty() ? nullptr : &baseNode));
    ReadState st;
    st.env = env.get();
    std::unique_ptr<SerdReader, ReaderDeleter> reader(
        serd_reader_new(SERD_TURTLE, &st, nullptr, onBase, onPrefix, onStatement, nullptr));
    serd_reader_set_strict(reader.get(), true);
    serd_reader_set_error_sink(reader.get(), onError, &st);
    std::string input(text);  // serd reads a NUL-terminated string
    SerdStatus status = serd_reader_read_string(reader.get(), bytes(input));
    if (status != SERD_SUCCESS || !st.error.empty()) {
        return Error{"Turtle: " +
                     (st.error.empty()
                          ? std::string(reinterpret_cast<const char*>(serd_strerror(status)))
                          : st.error)};
    }
    return std::move(st.triples);
}

Term decimalLiteral(double v) {
    std::array<char, 512> text{};  // DBL_MAX in fixed notation has 309 digits
    const auto [end, ec] =
        std::to_chars(text.data(), text.data() + text.size(), v, std::chars_format::fixed);
    const std::string lexical = ec == std::errc() ? std::string(text.data(), end) : "0";
    return literal(lexical, std::string(vocab::kXsd) + "decimal");
}

}  // namespace skillcell::kb::rdf
