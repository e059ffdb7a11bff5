#pragma once
// HTTP/1.1 messages and their wire format (RFC 9110, RFC 9112), without any I/O. The parsers
// are fed bytes as they arrive and enforce explicit limits, so the transports on top (the
// blocking client, the coroutine server) only move bytes; everything here is testable on
// strings.
#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <type_traits>
#include <utility>
#include <vector>

#include "kb/expected.hpp"

namespace skillcell::kb::http {

/// How much a client or server reads from its socket at a time.
inline constexpr std::size_t kReadChunk = std::size_t{16} * 1024;

/// Name/value pairs in their order of appearance (query strings, form bodies, parameters).
using Params = std::vector<std::pair<std::string, std::string>>;

/// ASCII case-insensitive comparison, as HTTP field names and tokens compare.
[[nodiscard]] bool iequals(std::string_view a, std::string_view b);

/// The first value of `name` in `params`, if any.
[[nodiscard]] std::optional<std::string_view> findParam(const Params& params,
                                                        std::string_view name);

namespace detail {
class MessageParser;
}

/// Header fields in arrival order; names compare case-insensitively (RFC 9110, 5.1).
class Headers {
public:
    using Field = std::pair<std::string, std::string>;

    void add(std::string name, std::string value);
    /// Replaces every field called `name` by one with `value`.
    void set(std::string name, std::string value);
    void erase(std::string_view name);
    /// The first value of `name`.
    [[nodiscard]] std::optional<std::string_view> get(std::string_view name) const;
    [[nodiscard]] bool contains(std::string_view name) const { return get(name).has_value(); }
    [[nodiscard]] std::size_t count(std::string_view name) const;
    /// All values of `name` joined by ", ": how RFC 9110 (5.3) combines list-valued fields.
    [[nodiscard]] std::string combined(std::string_view name) const;
    /// Whether the comma-separated list field `name` holds `token` (case-insensitive).
    [[nodiscard]] bool hasToken(std::string_view name, std::string_view token) const;

    [[nodiscard]] std::size_t size() const { return fields_.size(); }
    [[nodiscard]] bool empty() const { return fields_.empty(); }
    [[nodiscard]] auto begin() const { return fields_.begin(); }
    [[nodiscard]] auto end() const { return fields_.end(); }

private:
    friend class detail::MessageParser;  // appends folded lines to the last field

    std::vector<Field> fields_;
};

struct HttpRequest {
    std::string method = "GET";
    /// The request-target as on the wire. When serializing, an empty target is built from
    /// `path` and `query`; the parser fills all three.
    std::string target;
    std::string path;      ///< percent-decoded path ("*" for asterisk-form)
    Params query;          ///< decoded query parameters
    int versionMinor = 1;  ///< HTTP/1.x
    Headers headers;
    std::string body;

    /// Whether the connection stays open after this exchange (RFC 9112, 9.3).
    [[nodiscard]] bool keepAlive() const;
};

struct HttpResponse {
    int status = 200;
    std::string reason;  ///< empty: the standard phrase for `status`
    int versionMinor = 1;
    Headers headers;
    std::string body;

    [[nodiscard]] bool keepAlive() const;
};

/// A response with a body of `contentType` (plain UTF-8 text by default).
[[nodiscard]] HttpResponse makeResponse(int status, std::string body = {},
                                        std::string contentType = "text/plain; charset=utf-8");

/// The standard reason phrase of `status`, or "" for codes without one.
[[nodiscard]] std::string_view reasonPhrase(int status);

/// Bounds on what a peer may make the parser buffer.
struct ParserLimits {
    std::size_t maxHeaderBytes =
        std::size_t{16} * 1024;  ///< start line and header section (and trailers)
    std::size_t maxHeaderCount = 100;
    std::size_t maxBodyBytes = std::size_t{16} * 1024 * 1024;
};

enum class ParseState { NeedMore, Done, Error };

/// Why a message was rejected, with the status a server answers it with (400, 413, 414, 431,
/// 501, 505). For responses the status only classifies the fault.
struct ParseError {
    int status = 0;
    std::string message;
};

namespace detail {

/// The state machine both parsers share; the kind decides the start line and the framing
/// rules that differ between requests and responses.
class MessageParser {
public:
    enum class Kind { Request, Response };
    MessageParser(Kind kind, const ParserLimits& limits) : kind_(kind), limits_(limits) {}

    ParseState feed(std::span<const char> bytes);
    ParseState finish();
    [[nodiscard]] ParseState state() const;
    [[nodiscard]] const ParseError& error() const { return error_; }
    [[nodiscard]] bool started() const;
    [[nodiscard]] bool expectsContinue() const { return expectContinue_; }
    void setNoBody(bool noBody) { noBody_ = noBody; }
    HttpRequest takeRequest();
    HttpResponse takeResponse();

private:
    enum class Phase {
        StartLine,
        Fields,
        Body,
        ChunkSize,
        ChunkData,
        ChunkDataEnd,
        Trailers,
        UntilClose,
        Done,
        Error
    };
    enum class Line { Complete, NeedMore, Bad };

    ParseState run();
    Line nextLine(std::string_view& line, std::size_t maxLength);
    bool fail(int status, std::string message);
    bool parseStartLine(std::string_view line);
    bool parseRequestLine(std::string_view line);
    bool parseStatusLine(std::string_view line);
    bool parseField(std::string_view line, bool trailer);
    bool finishHead();
    bool finishRequestHead();
    bool takeBody(std::size_t& remaining);
    bool parseChunkSize(std::string_view line);
    void resetMessage();
    Headers& headers() { return kind_ == Kind::Request ? request_.headers : response_.headers; }
    std::string& body() { return kind_ == Kind::Request ? request_.body : response_.body; }
    [[nodiscard]] int versionMinor() const {
        return kind_ == Kind::Request ? request_.versionMinor : response_.versionMinor;
    }

    Kind kind_;
    ParserLimits limits_;
    Phase phase_ = Phase::StartLine;
    std::string buf_;  // received, not yet consumed bytes start at pos_
    std::size_t pos_ = 0;
    std::size_t scanned_ = 0;  // where the search for the next LF resumes
    std::size_t headBytes_ = 0;
    std::size_t remaining_ = 0;  // of the Content-Length body or the current chunk
    bool noBody_ = false;
    bool expectContinue_ = false;
    HttpRequest request_;
    HttpResponse response_;
    ParseError error_;
};

}  // namespace detail

/// Parses requests from a byte stream; several pipelined requests may arrive in one feed.
/// Requests are parsed strictly: a bare LF, obsolete line folding, both Content-Length and
/// Transfer-Encoding, or an HTTP/1.1 request without one Host field are errors (RFC 9112).
class RequestParser {
public:
    explicit RequestParser(ParserLimits limits = {})
        : core_(detail::MessageParser::Kind::Request, limits) {}

    /// Appends `bytes` and parses as far as they go. Once Done, bytes fed beyond the message
    /// stay buffered for the next one; feed an empty span after take() to parse them.
    ParseState feed(std::span<const char> bytes) { return core_.feed(bytes); }
    /// Strings and literals (a literal's terminating NUL is not fed).
    template <class Text>
    requires std::is_convertible_v<const Text&, std::string_view> ParseState
    feed(const Text& text) {
        const std::string_view view(text);
        return feed(std::span<const char>(view.data(), view.size()));
    }
    [[nodiscard]] ParseState state() const { return core_.state(); }
    [[nodiscard]] const ParseError& error() const { return core_.error(); }
    /// Whether any byte of the next request has arrived (a server answers 408 only then).
    [[nodiscard]] bool started() const { return core_.started(); }
    /// The header section is complete and asks for "100 Continue" before the body is sent.
    [[nodiscard]] bool expectsContinue() const { return core_.expectsContinue(); }
    /// The parsed request (state() must be Done); the parser starts on the next one.
    [[nodiscard]] HttpRequest take() { return core_.takeRequest(); }

private:
    detail::MessageParser core_;
};

/// Parses responses. Lenient where RFC 9112 allows a client to be (bare LF, obsolete line
/// folding); interim 1xx responses other than 101 are skipped.
class ResponseParser {
public:
    explicit ResponseParser(ParserLimits limits = {})
        : core_(detail::MessageParser::Kind::Response, limits) {}

    /// The response answers a HEAD request: it has no body whatever its framing fields say.
    void setHeadRequest(bool head) { core_.setNoBody(head); }
    ParseState feed(std::span<const char> bytes) { return core_.feed(bytes); }
    /// Strings and literals (a literal's terminating NUL is not fed).
    template <class Text>
    requires std::is_convertible_v<const Text&, std::string_view> ParseState
    feed(const Text& text) {
        const std::string_view view(text);
        return feed(std::span<const char>(view.data(), view.size()));
    }
    /// The peer closed the connection: completes a body delimited by the close, fails an
    /// incomplete message.
    ParseState finish() { return core_.finish(); }
    [[nodiscard]] ParseState state() const { return core_.state(); }
    [[nodiscard]] const ParseError& error() const { return core_.error(); }
    [[nodiscard]] HttpResponse take() { return core_.takeResponse(); }

private:
    detail::MessageParser core_;
};

/// The request on the wire, framed by Content-Length (never chunked). Header values lose any
/// CR, LF or NUL (replaced by spaces) so that a value cannot inject fields.
[[nodiscard]] std::string serialize(const HttpRequest& request);
/// The response on the wire; `omitBody` for an answer to HEAD (Content-Length still counts
/// the body).
[[nodiscard]] std::string serialize(const HttpResponse& response, bool omitBody = false);

/// Decodes %XX escapes (and '+' as space for form data); a malformed escape is an error.
[[nodiscard]] Expected<std::string> percentDecode(std::string_view text, bool plusAsSpace = false);
/// Escapes every byte except RFC 3986 unreserved characters and those in `keep`.
[[nodiscard]] std::string percentEncode(std::string_view text, std::string_view keep = {});
/// Parses application/x-www-form-urlencoded data (also a query string).
[[nodiscard]] Expected<Params> parseFormUrlEncoded(std::string_view text);
/// Encodes pairs as application/x-www-form-urlencoded ('+' for spaces).
[[nodiscard]] std::string formUrlEncode(const Params& params);
/// An origin-form request-target from a decoded path and query parameters.
[[nodiscard]] std::string makeTarget(std::string_view path, const Params& query = {});

/// A parsed media type (RFC 9110, 8.3.1): type, subtype and parameter names in lower case,
/// parameter values unquoted.
struct MediaType {
    std::string type;
    std::string subtype;
    Params params;

    /// "type/subtype" without parameters.
    [[nodiscard]] std::string essence() const { return type + '/' + subtype; }
    [[nodiscard]] std::optional<std::string_view> param(std::string_view name) const;
};

[[nodiscard]] Expected<MediaType> parseMediaType(std::string_view text);

/// Content negotiation (RFC 9110, 12.5.1): the index into `offered` of the type `accept`
/// prefers, by q-value and then by the order of `offered`; the most specific matching range
/// gives a type its q-value. An absent or unusable Accept accepts the first offer. nullopt
/// when nothing offered is acceptable (406).
[[nodiscard]] std::optional<std::size_t> chooseMediaType(std::string_view accept,
                                                         std::span<const std::string_view> offered);

}  // namespace skillcell::kb::http
