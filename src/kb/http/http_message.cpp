#include "kb/http/http_message.hpp"

#include <algorithm>
#include <array>
#include <charconv>
#include <limits>

namespace skillcell::kb::http {
namespace {

// A chunk-size line with its extensions; nobody legitimate needs more.
constexpr std::size_t kMaxChunkLine = 1024;

char lower(char c) {
    return (c >= 'A' && c <= 'Z') ? static_cast<char>(c - 'A' + 'a') : c;
}

std::string lowered(std::string_view s) {
    std::string out(s);
    std::transform(out.begin(), out.end(), out.begin(), lower);
    return out;
}

bool isDigit(char c) {
    return c >= '0' && c <= '9';
}

int hexValue(char c) {
    if (isDigit(c)) return c - '0';
    if (c >= 'a' && c <= 'f') return c - 'a' + 10;
    if (c >= 'A' && c <= 'F') return c - 'A' + 10;
    return -1;
}

// tchar (RFC 9110, 5.6.2).
bool isTokenChar(char c) {
    if ((c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || isDigit(c)) return true;
    return std::string_view("!#$%&'*+-.^_`|~").find(c) != std::string_view::npos;
}

bool isToken(std::string_view s) {
    return !s.empty() && std::all_of(s.begin(), s.end(), isTokenChar);
}

bool isWhitespace(char c) {
    return c == ' ' || c == '\t';
}

// field-vchar / obs-text plus the whitespace a field value may contain.
bool isFieldValueChar(char c) {
    const auto u = static_cast<unsigned char>(c);
    return u == '\t' || (u >= 0x20 && u != 0x7f);
}

std::string_view trimWhitespace(std::string_view s) {
    while (!s.empty() && isWhitespace(s.front())) s.remove_prefix(1);
    while (!s.empty() && isWhitespace(s.back())) s.remove_suffix(1);
    return s;
}

// Splits a list field value (RFC 9110, 5.6.1) into its non-empty trimmed elements.
std::vector<std::string_view> listElements(std::string_view value) {
    std::vector<std::string_view> out;
    while (!value.empty()) {
        const auto comma = value.find(',');
        const auto element = trimWhitespace(value.substr(0, comma));
        if (!element.empty()) out.push_back(element);
        if (comma == std::string_view::npos) break;
        value.remove_prefix(comma + 1);
    }
    return out;
}

// "HTTP/1.x": -1 when malformed, -2 when another major version.
int parseVersion(std::string_view v) {
    if (v.size() != 8 || v.substr(0, 5) != "HTTP/" || !isDigit(v[5]) || v[6] != '.' ||
        !isDigit(v[7])) {
        return -1;
    }
    if (v[5] != '1') return -2;
    return v[7] - '0';
}

bool keepAliveOf(const Headers& headers, int versionMinor) {
    if (headers.hasToken("Connection", "close")) return false;
    return versionMinor >= 1 || headers.hasToken("Connection", "keep-alive");
}

// Header values may not carry line breaks onto the wire.
std::string sanitizedValue(std::string_view value) {
    std::string out(value);
    std::replace_if(
        out.begin(), out.end(), [](char c) { return c == '\r' || c == '\n' || c == '\0'; }, ' ');
    return out;
}

void appendFields(std::string& out, const Headers& headers) {
    for (const auto& [name, value] : headers) {
        // Framing is ours to decide; invalid names cannot be written at all.
        if (iequals(name, "Content-Length") || iequals(name, "Transfer-Encoding")) continue;
        if (!isToken(name)) continue;
        out += name;
        out += ": ";
        out += sanitizedValue(value);
        out += "\r\n";
    }
}

bool statusHasNoBody(int status) {
    return (status >= 100 && status < 200) || status == 204 || status == 304;
}

}  // namespace

bool iequals(std::string_view a, std::string_view b) {
    return a.size() == b.size() && std::equal(a.begin(), a.end(), b.begin(),
                                              [](char x, char y) { return lower(x) == lower(y); });
}

std::optional<std::string_view> findParam(const Params& params, std::string_view name) {
    for (const auto& [n, v] : params) {
        if (n == name) return std::string_view(v);
    }
    return std::nullopt;
}

// ---- Headers ----

void Headers::add(std::string name, std::string value) {
    fields_.emplace_back(std::move(name), std::move(value));
}

void Headers::set(std::string name, std::string value) {
    erase(name);
    add(std::move(name), std::move(value));
}

void Headers::erase(std::string_view name) {
    std::erase_if(fields_, [name](const Field& f) { return iequals(f.first, name); });
}

std::optional<std::string_view> Headers::get(std::string_view name) const {
    for (const auto& [n, v] : fields_) {
        if (iequals(n, name)) return std::string_view(v);
    }
    return std::nullopt;
}

std::size_t Headers::count(std::string_view name) const {
    return static_cast<std::size_t>(std::count_if(
        fields_.begin(), fields_.end(), [name](const Field& f) { return iequals(f.first, name); }));
}

std::string Headers::combined(std::string_view name) const {
    std::string out;
    for (const auto& [n, v] : fields_) {
        if (!iequals(n, name)) continue;
        if (!out.empty()) out += ", ";
        out += v;
    }
    return out;
}

bool Headers::hasToken(std::string_view name, std::string_view token) const {
    const std::string value = combined(name);
    const auto elements = listElements(value);
    return std::any_of(elements.begin(), elements.end(),
                       [token](std::string_view e) { return iequals(e, token); });
}

// ---- Messages ----

bool HttpRequest::keepAlive() const {
    return keepAliveOf(headers, versionMinor);
}

bool HttpResponse::keepAlive() const {
    return keepAliveOf(headers, versionMinor);
}

HttpResponse makeResponse(int status, std::string body, std::string contentType) {
    HttpResponse response;
    response.status = status;
    if (!body.empty()) response.headers.add("Content-Type", std::move(contentType));
    response.body = std::move(body);
    return response;
}

std::string_view reasonPhrase(int status) {
    switch (status) {
        case 100:
            return "Continue";
        case 101:
            return "Switching Protocols";
        case 200:
            return "OK";
        case 201:
            return "Created";
        case 202:
            return "Accepted";
        case 204:
            return "No Content";
        case 206:
            return "Partial Content";
        case 301:
            return "Moved Permanently";
        case 302:
            return "Found";
        case 303:
            return "See Other";
        case 304:
            return "Not Modified";
        case 307:
            return "Temporary Redirect";
        case 308:
            return "Permanent Redirect";
        case 400:
            return "Bad Request";
        case 401:
            return "Unauthorized";
        case 403:
            return "Forbidden";
        case 404:
            return "Not Found";
        case 405:
            return "Method Not Allowed";
        case 406:
            return "Not Acceptable";
        case 408:
            return "Request Timeout";
        case 409:
            return "Conflict";
        case 411:
            return "Length Required";
        case 412:
            return "Precondition Failed";
        case 413:
            return "Content Too Large";
        case 414:
            return "URI Too Long";
        case 415:
            return "Unsupported Media Type";
        case 417:
            return "Expectation Failed";
        case 422:
            return "Unprocessable Content";
        case 429:
            return "Too Many Requests";
        case 431:
            return "Request Header Fields Too Large";
        case 500:
            return "Internal Server Error";
        case 501:
            return "Not Implemented";
        case 502:
            return "Bad Gateway";
        case 503:
            return "Service Unavailable";
        case 504:
            return "Gateway Timeout";
        case 505:
            return "HTTP Version Not Supported";
        default:
            return "";
    }
}

// ---- Parser ----

namespace detail {

ParseState MessageParser::state() const {
    switch (phase_) {
        case Phase::Done:
            return ParseState::Done;
        case Phase::Error:
            return ParseState::Error;
        default:
            return ParseState::NeedMore;
    }
}

bool MessageParser::started() const {
    return phase_ != Phase::StartLine || pos_ < buf_.size() || headBytes_ > 0;
}

ParseState MessageParser::feed(std::span<const char> bytes) {
    if (phase_ == Phase::Error) return ParseState::Error;
    if (pos_ > 0) {  // drop what earlier messages consumed
        buf_.erase(0, pos_);
        scanned_ -= pos_;
        pos_ = 0;
    }
    buf_.append(bytes.data(), bytes.size());
    return run();
}

ParseState MessageParser::finish() {
    if (phase_ == Phase::UntilClose) {
        phase_ = Phase::Done;
    } else if (phase_ != Phase::Done && phase_ != Phase::Error) {
        fail(400, started() ? "connection closed before the message was complete"
                            : "connection closed before a message");
    }
    return state();
}

bool MessageParser::fail(int status, std::string message) {
    phase_ = Phase::Error;
    error_ = {status, std::move(message)};
    return false;
}

MessageParser::Line MessageParser::nextLine(std::string_view& line, std::size_t maxLength) {
    const auto lf = buf_.find('\n', scanned_);
    if (lf == std::string::npos) {
        scanned_ = buf_.size();
        return buf_.size() - pos_ > maxLength ? Line::Bad : Line::NeedMore;
    }
    if (lf + 1 - pos_ > maxLength) return Line::Bad;
    std::string_view raw(buf_.data() + pos_, lf - pos_);
    const std::size_t consumed = lf + 1 - pos_;
    if (!raw.empty() && raw.back() == '\r') {
        raw.remove_suffix(1);
    } else if (kind_ == Kind::Request) {
        // A lone LF is tolerated from servers only: differing line-ending rules between
        // an intermediary and us are how requests get smuggled.
        fail(400, "bare LF as line terminator");
        return Line::Bad;
    }
    if (raw.find('\r') != std::string_view::npos) {
        fail(400, "bare CR in a line");
        return Line::Bad;
    }
    pos_ += consumed;
    scanned_ = pos_;
    if (phase_ == Phase::StartLine || phase_ == Phase::Fields || phase_ == Phase::Trailers) {
        headBytes_ += consumed;
    }
    line = raw;
    return Line::Complete;
}

ParseState MessageParser::run() {
    for (;;) {
        switch (phase_) {
            case Phase::Done:
            case Phase::Error:
                return state();
            case Phase::StartLine:
            case Phase::Fields:
            case Phase::Trailers: {
                const std::size_t budget =
                    headBytes_ < limits_.maxHeaderBytes ? limits_.maxHeaderBytes - headBytes_ : 0;
                std::string_view line;
                const Line got = nextLine(line, budget);
                if (got == Line::NeedMore) return state();
                if (got == Line::Bad) {
                    if (phase_ == Phase::Error) return state();
                    if (phase_ == Phase::StartLine && kind_ == Kind::Request) {
                        fail(414, "request line too long");
                    } else {
                        fail(431, phase_ == Phase::Trailers ? "trailer section too large"
                                                            : "header section too large");
                    }
                    return state();
                }
                if (phase_ == Phase::StartLine) {
                    // A server should skip empty lines before a request line (RFC 9112, 2.2).
                    if (line.empty()) continue;
                    if (parseStartLine(line)) phase_ = Phase::Fields;
                } else if (line.empty()) {
                    if (phase_ == Phase::Trailers) {
                        phase_ = Phase::Done;
                    } else {
                        finishHead();
                    }
                } else {
                    parseField(line, phase_ == Phase::Trailers);
                }
                break;
            }
            case Phase::Body:
                if (takeBody(remaining_)) phase_ = Phase::Done;
                if (phase_ != Phase::Done) return state();
                break;
            case Phase::ChunkSize:
            case Phase::ChunkDataEnd: {
                std::string_view line;
                const Line got = nextLine(line, kMaxChunkLine);
                if (got == Line::NeedMore) return state();
                if (got == Line::Bad) {
                    if (phase_ != Phase::Error) fail(400, "chunk line too long");
                    return state();
                }
                if (phase_ == Phase::ChunkDataEnd) {
                    if (!line.empty()) {
                        fail(400, "chunk data longer than its size");
                        return state();
                    }
                    phase_ = Phase::ChunkSize;
                } else {
                    parseChunkSize(line);
                }
                break;
            }
            case Phase::ChunkData:
                if (takeBody(remaining_)) phase_ = Phase::ChunkDataEnd;
                if (phase_ != Phase::ChunkDataEnd) return state();
                break;
            case Phase::UntilClose: {
                const std::size_t available = buf_.size() - pos_;
                if (body().size() + available > limits_.maxBodyBytes) {
                    fail(413,
                         "body larger than " + std::to_string(limits_.maxBodyBytes) + " bytes");
                    return state();
                }
                body().append(buf_, pos_, available);
                pos_ = buf_.size();
                scanned_ = pos_;
                return state();
            }
        }
    }
}

bool MessageParser::takeBody(std::size_t& remaining) {
    const std::size_t n = std::min(remaining, buf_.size() - pos_);
    body().append(buf_, pos_, n);
    pos_ += n;
    scanned_ = pos_;
    remaining -= n;
    return remaining == 0;
}

bool MessageParser::parseStartLine(std::string_view line) {
    return kind_ == Kind::Request ? parseRequestLine(line) : parseStatusLine(line);
}

bool MessageParser::parseRequestLine(std::string_view line) {
    // method SP request-target SP HTTP-version: the target holds no spaces, so exactly two.
    const auto sp1 = line.find(' ');
    const auto sp2 = sp1 == std::string_view::npos ? sp1 : line.find(' ', sp1 + 1);
    if (sp2 == std::string_view::npos || line.find(' ', sp2 + 1) != std::string_view::npos) {
        return fail(400, "malformed request line");
    }
    const auto method = line.substr(0, sp1);
    const auto target = line.substr(sp1 + 1, sp2 - sp1 - 1);
    const int minor = parseVersion(line.substr(sp2 + 1));
    if (minor == -2) return fail(505, "only HTTP/1.x is supported");
    if (minor < 0) return fail(400, "malformed HTTP version");
    if (!isToken(method)) return fail(400, "malformed method");
    if (target.empty() || !std::all_of(target.begin(), target.end(), [](char c) {
            const auto u = static_cast<unsigned char>(c);
            return u > 0x20 && u < 0x7f;
        })) {
        return fail(400, "malformed request target");
    }
    request_.method = method;
    request_.target = target;
    request_.versionMinor = minor;

    // origin-form, absolute-form (what proxies send; we only keep its path) or "*".
    std::string_view pathAndQuery;
    if (target.front() == '/') {
        pathAndQuery = target;
    } else if (target == "*") {
        request_.path = "*";
        return true;
    } else {
        const auto scheme = target.find("://");
        if (scheme == std::string_view::npos || !(iequals(target.substr(0, scheme), "http") ||
                                                  iequals(target.substr(0, scheme), "https"))) {
            return fail(400, "unsupported request target form");
        }
        const auto slash = target.find_first_of("/?", scheme + 3);
        pathAndQuery = slash == std::string_view::npos ? "/" : target.substr(slash);
    }
    const auto question = pathAndQuery.find('?');
    auto path = percentDecode(pathAndQuery.substr(0, question));
    if (!path) return fail(400, "bad escape in the request path");
    if (path->find('\0') != std::string::npos) return fail(400, "NUL in the request path");
    request_.path = path->empty() ? "/" : std::move(*path);
    if (question != std::string_view::npos) {
        auto query = parseFormUrlEncoded(pathAndQuery.substr(question + 1));
        if (!query) return fail(400, "bad escape in the query string");
        request_.query = std::move(*query);
    }
    return true;
}

bool MessageParser::parseStatusLine(std::string_view line) {
    // HTTP-version SP 3DIGIT SP [reason]; a missing SP after the code is tolerated.
    const int minor = parseVersion(line.substr(0, 8));
    if (minor == -2) return fail(505, "only HTTP/1.x is supported");
    if (minor < 0 || line.size() < 12 || line[8] != ' ' || !isDigit(line[9]) ||
        !isDigit(line[10]) || !isDigit(line[11]) || (line.size() > 12 && line[12] != ' ')) {
        return fail(400, "malformed status line");
    }
    const int status = (line[9] - '0') * 100 + (line[10] - '0') * 10 + (line[11] - '0');
    if (status < 100 || status > 599) return fail(400, "status code out of range");
    const auto reason = line.size() > 13 ? line.substr(13) : std::string_view();
    if (!std::all_of(reason.begin(), reason.end(), isFieldValueChar)) {
        return fail(400, "malformed reason phrase");
    }
    response_.versionMinor = minor;
    response_.status = status;
    response_.reason = reason;
    return true;
}

bool MessageParser::parseField(std::string_view line, bool trailer) {
    Headers& target = headers();
    if (isWhitespace(line.front())) {
        // obs-fold: servers must reject it or unfold it; clients must unfold (RFC 9112, 5.2).
        if (kind_ == Kind::Request) return fail(400, "obsolete line folding");
        if (trailer) return true;
        if (target.empty()) return fail(400, "whitespace before the first field");
        const auto more = trimWhitespace(line);
        if (!std::all_of(more.begin(), more.end(), isFieldValueChar)) {
            return fail(400, "invalid character in a field value");
        }
        target.fields_.back().second += ' ';
        target.fields_.back().second += more;
        return true;
    }
    const auto colon = line.find(':');
    if (colon == std::string_view::npos) return fail(400, "field line without a colon");
    const auto name = line.substr(0, colon);
    // Whitespace before the colon must be rejected (RFC 9112, 5.1): isToken excludes it.
    if (!isToken(name)) return fail(400, "malformed field name");
    const auto value = trimWhitespace(line.substr(colon + 1));
    if (!std::all_of(value.begin(), value.end(), isFieldValueChar)) {
        return fail(400, "invalid character in a field value");
    }
    if (trailer) return true;  // trailers are checked, then dropped: nothing here needs them
    if (target.size() >= limits_.maxHeaderCount) return fail(431, "too many header fields");
    target.add(std::string(name), std::string(value));
    return true;
}

bool MessageParser::finishHead() {
    const Headers& h = headers();
    if (kind_ == Kind::Response) {
        const int status = response_.status;
        if (status >= 100 && status < 200 && status != 101) {
            // Interim response: the final one follows on the same stream.
            response_ = HttpResponse{};
            headBytes_ = 0;
            phase_ = Phase::StartLine;
            return true;
        }
        if (noBody_ || statusHasNoBody(status)) {
            phase_ = Phase::Done;
            return true;
        }
    } else if (!finishRequestHead()) {
        return false;
    }

    const bool hasTe = h.contains("Transfer-Encoding");
    const bool hasCl = h.contains("Content-Length");
    if (hasTe) {
        if (versionMinor() == 0) return fail(400, "Transfer-Encoding in an HTTP/1.0 message");
        if (hasCl) return fail(400, "both Content-Length and Transfer-Encoding");
        const std::string te = h.combined("Transfer-Encoding");
        const auto codings = listElements(te);
        if (codings.empty() || !iequals(codings.back(), "chunked")) {
            return fail(kind_ == Kind::Request ? 400 : 501, "body not framed by chunked coding");
        }
        if (codings.size() != 1) return fail(501, "unsupported transfer coding");
        phase_ = Phase::ChunkSize;
    } else if (hasCl) {
        const std::string cl = h.combined("Content-Length");
        const auto values = listElements(cl);
        // Repeated identical values are allowed (RFC 9112, 6.3); anything else is ambiguous.
        if (values.empty() || !std::all_of(values.begin(), values.end(), [&](std::string_view v) {
                return v == values.front();
            })) {
            return fail(400, "conflicting Content-Length values");
        }
        const auto v = values.front();
        std::uint64_t length = 0;
        const auto [end, ec] = std::from_chars(v.data(), v.data() + v.size(), length);
        if (ec == std::errc::result_out_of_range) {
            return fail(413, "body larger than " + std::to_string(limits_.maxBodyBytes) + " bytes");
        }
        if (ec != std::errc() || end != v.data() + v.size() ||
            !std::all_of(v.begin(), v.end(), isDigit)) {
            return fail(400, "malformed Content-Length");
        }
        if (length > limits_.maxBodyBytes) {
            return fail(413, "body larger than " + std::to_string(limits_.maxBodyBytes) + " bytes");
        }
        remaining_ = static_cast<std::size_t>(length);
        phase_ = remaining_ == 0 ? Phase::Done : Phase::Body;
    } else {
        // Without framing fields a request has no body; a response runs until the close.
        phase_ = kind_ == Kind::Request ? Phase::Done : Phase::UntilClose;
    }
    expectContinue_ = kind_ == Kind::Request && phase_ != Phase::Done &&
                      request_.versionMinor >= 1 && h.hasToken("Expect", "100-continue");
    return true;
}

bool MessageParser::finishRequestHead() {
    // An HTTP/1.1 request names exactly one host (RFC 9112, 3.2).
    const std::size_t hosts = request_.headers.count("Host");
    if (hosts > 1 || (hosts == 0 && request_.versionMinor >= 1)) {
        return fail(400, "an HTTP/1.1 request needs exactly one Host field");
    }
    return true;
}

bool MessageParser::parseChunkSize(std::string_view line) {
    std::size_t i = 0;
    std::uint64_t size = 0;
    for (; i < line.size() && hexValue(line[i]) >= 0; ++i) {
        if (size > (std::numeric_limits<std::uint64_t>::max() >> 4)) {
            return fail(413, "chunk too large");
        }
        size = size * 16 + static_cast<std::uint64_t>(hexValue(line[i]));
    }
    if (i == 0) return fail(400, "malformed chunk size");
    // Chunk extensions (after ';') carry nothing we use; they only have to be printable.
    auto rest = line.substr(i);
    while (!rest.empty() && isWhitespace(rest.front())) rest.remove_prefix(1);
    if (!rest.empty() &&
        (rest.front() != ';' || !std::all_of(rest.begin(), rest.end(), isFieldValueChar))) {
        return fail(400, "malformed chunk extension");
    }
    if (size > limits_.maxBodyBytes - std::min(limits_.maxBodyBytes, body().size())) {
        return fail(413, "body larger than " + std::to_string(limits_.maxBodyBytes) + " bytes");
    }
    if (size == 0) {
        headBytes_ = 0;  // the trailer section gets its own header budget
        phase_ = Phase::Trailers;
        return true;
    }
    remaining_ = static_cast<std::size_t>(size);
    phase_ = Phase::ChunkData;
    return true;
}

void MessageParser::resetMessage() {
    phase_ = Phase::StartLine;
    headBytes_ = 0;
    remaining_ = 0;
    expectContinue_ = false;
    request_ = HttpRequest{};
    response_ = HttpResponse{};
}

HttpRequest MessageParser::takeRequest() {
    HttpRequest out = std::move(request_);
    resetMessage();
    return out;
}

HttpResponse MessageParser::takeResponse() {
    HttpResponse out = std::move(response_);
    resetMessage();
    return out;
}

}  // namespace detail

// ---- Serialization ----

std::string serialize(const HttpRequest& request) {
    std::string out;
    out.reserve(request.body.size() + 256);
    out += request.method;
    out += ' ';
    out += request.target.empty() ? makeTarget(request.path, request.query) : request.target;
    out += request.versionMinor == 0 ? " HTTP/1.0\r\n" : " HTTP/1.1\r\n";
    appendFields(out, request.headers);
    // Content-Length only where a body is present or expected (RFC 9110, 8.6).
    if (!request.body.empty() || request.method == "POST" || request.method == "PUT" ||
        request.method == "PATCH") {
        out += "Content-Length: " + std::to_string(request.body.size()) + "\r\n";
    }
    out += "\r\n";
    out += request.body;
    return out;
}

std::string serialize(const HttpResponse& response, bool omitBody) {
    const int status = response.status >= 100 && response.status <= 999 ? response.status : 500;
    std::string out;
    out.reserve(response.body.size() + 256);
    out += response.versionMinor == 0 ? "HTTP/1.0 " : "HTTP/1.1 ";
    out += std::to_string(status);
    out += ' ';
    out += sanitizedValue(response.reason.empty() ? reasonPhrase(status)
                                                  : std::string_view(response.reason));
    out += "\r\n";
    appendFields(out, response.headers);
    const bool noBody = statusHasNoBody(status);
    if (!noBody) out += "Content-Length: " + std::to_string(response.body.size()) + "\r\n";
    out += "\r\n";
    if (!noBody && !omitBody) out += response.body;
    return out;
}

// ---- URL encoding ----

Expected<std::string> percentDecode(std::string_view text, bool plusAsSpace) {
    std::string out;
    out.reserve(text.size());
    for (std::size_t i = 0; i < text.size(); ++i) {
        const char c = text[i];
        if (c == '%') {
            if (i + 2 >= text.size()) {
                return Error{"truncated percent escape at offset " + std::to_string(i)};
            }
            const int hi = hexValue(text[i + 1]);
            const int lo = hexValue(text[i + 2]);
            if (hi < 0 || lo < 0) {
                return Error{"malformed percent escape at offset " + std::to_string(i)};
            }
            out += static_cast<char>(hi * 16 + lo);
            i += 2;
        } else if (c == '+' && plusAsSpace) {
            out += ' ';
        } else {
            out += c;
        }
    }
    return out;
}

std::string percentEncode(std::string_view text, std::string_view keep) {
    static constexpr std::string_view kHex = "0123456789ABCDEF";
    std::string out;
    out.reserve(text.size());
    for (const char c : text) {
        const bool unreserved = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || isDigit(c) ||
                                c == '-' || c == '.' || c == '_' || c == '~';
        if (unreserved || keep.find(c) != std::string_view::npos) {
            out += c;
        } else {
            const auto u = static_cast<unsigned char>(c);
            out += '%';
            out += kHex[u >> 4];
            out += kHex[u & 0x0f];
        }
    }
    return out;
}

Expected<Params> parseFormUrlEncoded(std::string_view text) {
    Params out;
    while (!text.empty()) {
        const auto amp = text.find('&');
        const auto pair = text.substr(0, amp);
        text = amp == std::string_view::npos ? std::string_view() : text.substr(amp + 1);
        if (pair.empty()) continue;
        const auto eq = pair.find('=');
        auto name = percentDecode(pair.substr(0, eq), true);
        if (!name) return Error{"form data: " + name.error()};
        auto value = percentDecode(
            eq == std::string_view::npos ? std::string_view() : pair.substr(eq + 1), true);
        if (!value) return Error{"form data: " + value.error()};
        out.emplace_back(std::move(*name), std::move(*value));
    }
    return out;
}

namespace {

// Spaces become '+', the way HTML forms send them; everything else as percentEncode.
std::string formEncode(std::string_view text) {
    std::string out;
    out.reserve(text.size());
    std::size_t start = 0;
    for (std::size_t space = text.find(' '); space != std::string_view::npos;
         space = text.find(' ', start)) {
        out += percentEncode(text.substr(start, space - start));
        out += '+';
        start = space + 1;
    }
    out += percentEncode(text.substr(start));
    return out;
}

}  // namespace

std::string formUrlEncode(const Params& params) {
    std::string out;
    for (const auto& [name, value] : params) {
        if (!out.empty()) out += '&';
        out += formEncode(name);
        out += '=';
        out += formEncode(value);
    }
    return out;
}

std::string makeTarget(std::string_view path, const Params& query) {
    std::string out = percentEncode(path.empty() ? std::string_view("/") : path, "/");
    if (!query.empty()) {
        out += '?';
        out += formUrlEncode(query);
    }
    return out;
}

// ---- Media types ----

std::optional<std::string_view> MediaType::param(std::string_view name) const {
    for (const auto& [n, v] : params) {
        if (iequals(n, name)) return std::string_view(v);
    }
    return std::nullopt;
}

namespace {

// Parses one media type (or media range) from `text` at `pos`, stopping before a ',' or at
// the end. Quoted strings may contain commas, so list splitting happens here, not before.
Expected<MediaType> parseMediaTypeAt(std::string_view text, std::size_t& pos) {
    auto skipWhitespace = [&] {
        while (pos < text.size() && isWhitespace(text[pos])) ++pos;
    };
    auto token = [&] {
        const std::size_t start = pos;
        while (pos < text.size() && isTokenChar(text[pos])) ++pos;
        return text.substr(start, pos - start);
    };
    skipWhitespace();
    MediaType mt;
    const auto type = token();
    if (type.empty() || pos >= text.size() || text[pos] != '/') {
        return Error{"media type without type/subtype"};
    }
    ++pos;
    const auto subtype = token();
    if (subtype.empty()) return Error{"media type without a subtype"};
    mt.type = lowered(type);
    mt.subtype = lowered(subtype);
    for (;;) {
        skipWhitespace();
        if (pos >= text.size() || text[pos] == ',') break;
        if (text[pos] != ';') return Error{"unexpected character in media type"};
        ++pos;
        skipWhitespace();
        if (pos >= text.size() || text[pos] == ',' || text[pos] == ';') continue;  // empty
        const auto name = token();
        if (name.empty() || pos >= text.size() || text[pos] != '=') {
            return Error{"malformed media type parameter"};
        }
        ++pos;
        std::string value;
        if (pos < text.size() && text[pos] == '"') {
            ++pos;
            bool closed = false;
            while (pos < text.size()) {
                const char c = text[pos++];
                if (c == '"') {
                    closed = true;
                    break;
                }
                if (c == '\\' && pos < text.size()) {
                    value += text[pos++];
                } else {
                    value += c;
                }
            }
            if (!closed) return Error{"unterminated quoted string in media type"};
        } else {
            value = token();
            if (value.empty()) return Error{"empty media type parameter value"};
        }
        mt.params.emplace_back(lowered(name), std::move(value));
    }
    return mt;
}

// q-value in thousandths (RFC 9110, 12.4.2), -1 when malformed.
int parseQuality(std::string_view q) {
    if (q.empty() || q.size() > 5 || (q[0] != '0' && q[0] != '1')) return -1;
    if (q.size() > 1 && q[1] != '.') return -1;
    int value = (q[0] - '0') * 1000;
    int scale = 100;
    for (std::size_t i = 2; i < q.size(); ++i, scale /= 10) {
        if (!isDigit(q[i])) return -1;
        value += (q[i] - '0') * scale;
    }
    return value <= 1000 ? value : -1;
}

struct MediaRange {
    MediaType type;  // parameters before q only
    int quality = 1000;
};

std::vector<MediaRange> parseAccept(std::string_view accept) {
    std::vector<MediaRange> ranges;
    std::size_t pos = 0;
    while (pos < accept.size()) {
        if (accept[pos] == ',' || isWhitespace(accept[pos])) {
            ++pos;
            continue;
        }
        auto parsed = parseMediaTypeAt(accept, pos);
        if (!parsed) {
            // Skip the unusable element; the others still count.
            const auto comma = accept.find(',', pos);
            pos = comma == std::string_view::npos ? accept.size() : comma + 1;
            continue;
        }
        MediaRange range;
        range.type.type = std::move(parsed->type);
        range.type.subtype = std::move(parsed->subtype);
        bool valid = range.type.type != "*" || range.type.subtype == "*";
        for (auto& [name, value] : parsed->params) {
            if (name == "q") {
                range.quality = parseQuality(value);
                valid = valid && range.quality >= 0;
                break;  // what follows q are accept-extensions, not media type parameters
            }
            range.type.params.emplace_back(std::move(name), std::move(value));
        }
        if (valid) ranges.push_back(std::move(range));
    }
    return ranges;
}

// How specifically `range` matches `offer`; -1 when it does not match.
int specificity(const MediaType& range, const MediaType& offer) {
    if (range.type != "*" && range.type != offer.type) return -1;
    if (range.subtype != "*" && range.subtype != offer.subtype) return -1;
    for (const auto& [name, value] : range.params) {
        const auto offered = offer.param(name);
        if (!offered || !iequals(*offered, value)) return -1;
    }
    return (range.type != "*" ? 1000 : 0) + (range.subtype != "*" ? 100 : 0) +
           static_cast<int>(range.params.size());
}

}  // namespace

Expected<MediaType> parseMediaType(std::string_view text) {
    std::size_t pos = 0;
    auto parsed = parseMediaTypeAt(text, pos);
    if (parsed && pos != text.size()) return Error{"more than one media type"};
    return parsed;
}

std::optional<std::size_t> chooseMediaType(std::string_view accept,
                                           std::span<const std::string_view> offered) {
    const auto ranges = parseAccept(accept);
    std::optional<std::size_t> best;
    int bestQuality = 0;
    for (std::size_t i = 0; i < offered.size(); ++i) {
        const auto offer = parseMediaType(offered[i]);
        if (!offer) continue;
        if (ranges.empty()) return i;  // no usable preference: the server's first choice
        int quality = 0;
        int bestSpecificity = -1;
        for (const auto& range : ranges) {
            const int s = specificity(range.type, *offer);
            if (s > bestSpecificity) {
                bestSpecificity = s;
                quality = range.quality;
            }
        }
        if (quality > bestQuality) {
            bestQuality = quality;
            best = i;
        }
    }
    return best;
}

}  // namespace skillcell::kb::http
