// The knowledge base's HTTP/1.1 layer: the parsers on strings (every split point, framing,
// limits, malformed input), URL and form encoding, content negotiation, and the server and
// the blocking client talking over loopback.
#include <gtest/gtest.h>

#include <array>
#include <cctype>
#include <chrono>
#include <future>
#include <optional>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include <asio.hpp>
#include <asio/experimental/as_tuple.hpp>

#include "kb/http/http_client.hpp"
#include "kb/http/http_message.hpp"
#include "kb/http/http_server.hpp"

namespace http_test {

using namespace skillcell::kb::http;
using std::chrono::milliseconds;
using Clock = std::chrono::steady_clock;

namespace {

std::span<const char> bytesOf(std::string_view s) {
    return {s.data(), s.size()};
}

/// Feeds `wire` in one piece; returns the parser for inspection.
RequestParser parsedRequest(std::string_view wire, ParserLimits limits = {}) {
    RequestParser parser(limits);
    (void)parser.feed(wire);
    return parser;
}

int requestErrorStatus(std::string_view wire, ParserLimits limits = {}) {
    RequestParser parser = parsedRequest(wire, limits);
    return parser.state() == ParseState::Error ? parser.error().status : 0;
}

const std::string kPostWire =
    "POST /sparql/query%20x?default-graph-uri=urn%3Ag&x=a+b HTTP/1.1\r\n"
    "Host: 127.0.0.1:8890\r\n"
    "Content-Type: application/x-www-form-urlencoded\r\n"
    "Content-Length: 18\r\n"
    "\r\n"
    "query=ASK+%7B%7D&x";

const std::string kChunkedWire =
    "POST /upload HTTP/1.1\r\n"
    "Host: h\r\n"
    "Transfer-Encoding: chunked\r\n"
    "\r\n"
    "5;name=value\r\nhello\r\n"
    "7\r\n, world\r\n"
    "0\r\n"
    "Trailer-Field: x\r\n"
    "\r\n";

}  // namespace

// ---- Request parsing ----

TEST(HttpRequestParser, ParsesTargetQueryHeadersAndBody) {
    RequestParser parser;
    ASSERT_EQ(parser.feed(kPostWire), ParseState::Done) << parser.error().message;
    const HttpRequest r = parser.take();
    EXPECT_EQ(r.method, "POST");
    EXPECT_EQ(r.target, "/sparql/query%20x?default-graph-uri=urn%3Ag&x=a+b");
    EXPECT_EQ(r.path, "/sparql/query x");
    ASSERT_EQ(r.query.size(), 2U);
    EXPECT_EQ(r.query[0], (std::pair<std::string, std::string>("default-graph-uri", "urn:g")));
    EXPECT_EQ(r.query[1].second, "a b");
    EXPECT_EQ(r.headers.get("content-TYPE"), "application/x-www-form-urlencoded");
    EXPECT_EQ(r.body, "query=ASK+%7B%7D&x");
    EXPECT_EQ(r.versionMinor, 1);
    EXPECT_TRUE(r.keepAlive());
}

TEST(HttpRequestParser, EverySplitPointGivesTheSameRequest) {
    for (const std::string& wire : {kPostWire, kChunkedWire}) {
        RequestParser whole;
        ASSERT_EQ(whole.feed(wire), ParseState::Done);
        const HttpRequest expected = whole.take();
        for (std::size_t split = 0; split <= wire.size(); ++split) {
            RequestParser parser;
            const auto first = parser.feed(bytesOf(wire).first(split));
            if (split < wire.size()) {
                ASSERT_EQ(first, ParseState::NeedMore) << "split " << split;
            }
            ASSERT_EQ(parser.feed(bytesOf(wire).subspan(split)), ParseState::Done)
                << "split " << split << ": " << parser.error().message;
            const HttpRequest r = parser.take();
            EXPECT_EQ(r.path, expected.path);
            EXPECT_EQ(r.query, expected.query);
            EXPECT_EQ(r.body, expected.body) << "split " << split;
            EXPECT_EQ(r.headers.size(), expected.headers.size());
        }
        // And one byte at a time.
        RequestParser parser;
        ParseState state = ParseState::NeedMore;
        for (const char c : wire) {
            ASSERT_EQ(state, ParseState::NeedMore);
            state = parser.feed(std::span<const char>(&c, 1));
        }
        ASSERT_EQ(state, ParseState::Done);
        EXPECT_EQ(parser.take().body, expected.body);
    }
}

TEST(HttpRequestParser, ChunkedBodyWithExtensionsAndTrailers) {
    RequestParser parser;
    ASSERT_EQ(parser.feed(kChunkedWire), ParseState::Done) << parser.error().message;
    const HttpRequest r = parser.take();
    EXPECT_EQ(r.body, "hello, world");
    EXPECT_FALSE(r.headers.contains("Trailer-Field"));  // trailers are not merged
}

TEST(HttpRequestParser, PipelinedRequestsComeOutOneByOne) {
    const std::string wire =
        "GET /a HTTP/1.1\r\nHost: h\r\n\r\n"
        "POST /b HTTP/1.1\r\nHost: h\r\nContent-Length: 3\r\n\r\nxyz"
        "GET /c HTTP/1.1\r\nHo";
    RequestParser parser;
    ASSERT_EQ(parser.feed(wire), ParseState::Done);
    EXPECT_EQ(parser.take().path, "/a");
    ASSERT_EQ(parser.feed(std::span<const char>()), ParseState::Done);
    const HttpRequest b = parser.take();
    EXPECT_EQ(b.path, "/b");
    EXPECT_EQ(b.body, "xyz");
    EXPECT_EQ(parser.feed(std::span<const char>()), ParseState::NeedMore);
    EXPECT_TRUE(parser.started());
    ASSERT_EQ(parser.feed("st: h\r\n\r\n"), ParseState::Done);
    EXPECT_EQ(parser.take().path, "/c");
    EXPECT_FALSE(parser.started());
}

TEST(HttpRequestParser, SkipsEmptyLinesBeforeTheRequestLine) {
    RequestParser parser;
    ASSERT_EQ(parser.feed("\r\n\r\nGET / HTTP/1.1\r\nHost: h\r\n\r\n"), ParseState::Done);
    EXPECT_EQ(parser.take().path, "/");
}

TEST(HttpRequestParser, AbsoluteFormAndAsteriskTargets) {
    auto a = parsedRequest("GET http://example.org:80/x%2Fy?q=1 HTTP/1.1\r\nHost: h\r\n\r\n");
    ASSERT_EQ(a.state(), ParseState::Done) << a.error().message;
    const HttpRequest r = a.take();
    EXPECT_EQ(r.path, "/x/y");
    EXPECT_EQ(findParam(r.query, "q"), "1");
    auto b = parsedRequest("OPTIONS * HTTP/1.1\r\nHost: h\r\n\r\n");
    ASSERT_EQ(b.state(), ParseState::Done);
    EXPECT_EQ(b.take().path, "*");
}

TEST(HttpRequestParser, KeepAliveFollowsVersionAndConnection) {
    auto v10 = parsedRequest("GET / HTTP/1.0\r\n\r\n");  // 1.0 needs no Host
    ASSERT_EQ(v10.state(), ParseState::Done);
    EXPECT_FALSE(v10.take().keepAlive());
    auto v10ka = parsedRequest("GET / HTTP/1.0\r\nConnection: Keep-Alive\r\n\r\n");
    EXPECT_TRUE(v10ka.take().keepAlive());
    auto v11close = parsedRequest("GET / HTTP/1.1\r\nHost: h\r\nConnection: foo, close\r\n\r\n");
    EXPECT_FALSE(v11close.take().keepAlive());
}

TEST(HttpRequestParser, ExpectContinueIsReportedOnceTheHeadIsComplete) {
    RequestParser parser;
    ASSERT_EQ(parser.feed("POST / HTTP/1.1\r\nHost: h\r\nExpect: 100-continue\r\n"
                          "Content-Length: 2\r\n\r\n"),
              ParseState::NeedMore);
    EXPECT_TRUE(parser.expectsContinue());
    ASSERT_EQ(parser.feed("ok"), ParseState::Done);
    EXPECT_EQ(parser.take().body, "ok");
    EXPECT_FALSE(parser.expectsContinue());
}

TEST(HttpRequestParser, RejectsMalformedInputWith400) {
    const std::vector<std::string> bad = {
        "GET /\r\n\r\n",                                              // no version
        "GET  / HTTP/1.1\r\nHost: h\r\n\r\n",                         // double space
        "G(T / HTTP/1.1\r\nHost: h\r\n\r\n",                          // method not a token
        "GET / http/1.1\r\nHost: h\r\n\r\n",                          // version is case-sensitive
        "GET / HTTP/1.1\r\n\r\n",                                     // 1.1 without Host
        "GET / HTTP/1.1\r\nHost: a\r\nHost: b\r\n\r\n",               // two Hosts
        "GET / HTTP/1.1\r\nHost : h\r\n\r\n",                         // space before colon
        "GET / HTTP/1.1\r\nHost: h\r\nX: a\r\n b\r\n\r\n",            // obs-fold
        "GET / HTTP/1.1\nHost: h\n\n",                                // bare LF
        "GET / HTTP/1.1\r\nHost: h\rX: y\r\n\r\n",                    // bare CR
        "GET / HTTP/1.1\r\nHost: h\r\nX: a\x01b\r\n\r\n",             // control character
        "GET / HTTP/1.1\r\nHost: h\r\nNoColon\r\n\r\n",               // no colon
        "GET /%zz HTTP/1.1\r\nHost: h\r\n\r\n",                       // bad escape in path
        "GET /?a=%4 HTTP/1.1\r\nHost: h\r\n\r\n",                     // bad escape in query
        "GET relative HTTP/1.1\r\nHost: h\r\n\r\n",                   // unknown target form
        "POST / HTTP/1.1\r\nHost: h\r\nContent-Length: 12a\r\n\r\n",  // bad CL
        "POST / HTTP/1.1\r\nHost: h\r\nContent-Length: -1\r\n\r\n",
        "POST / HTTP/1.1\r\nHost: h\r\nContent-Length: 1, 2\r\n\r\n",
        "POST / HTTP/1.1\r\nHost: h\r\nContent-Length: 1\r\nContent-Length: 2\r\n\r\n",
        "POST / HTTP/1.1\r\nHost: h\r\nTransfer-Encoding: chunked\r\n\r\nzz\r\n",  // chunk size
        "POST / HTTP/1.1\r\nHost: h\r\nTransfer-Encoding: chunked\r\n\r\n2\r\nabc\r\n",
        "POST / HTTP/1.1\r\nHost: h\r\nTransfer-Encoding: chunked, gzip\r\n\r\n",
        "POST / HTTP/1.0\r\nTransfer-Encoding: chunked\r\n\r\n",
    };
    for (const auto& wire : bad) {
        EXPECT_EQ(requestErrorStatus(wire), 400) << wire;
    }
    // Repeated identical lengths are one length.
    auto same = parsedRequest("POST / HTTP/1.1\r\nHost: h\r\nContent-Length: 2, 2\r\n\r\nab");
    EXPECT_EQ(same.state(), ParseState::Done);
}

TEST(HttpRequestParser, RejectsContentLengthWithTransferEncoding) {
    const std::string wire =
        "POST / HTTP/1.1\r\nHost: h\r\nContent-Length: 5\r\nTransfer-Encoding: chunked\r\n\r\n"
        "0\r\n\r\n";
    RequestParser parser = parsedRequest(wire);
    ASSERT_EQ(parser.state(), ParseState::Error);
    EXPECT_EQ(parser.error().status, 400);
    EXPECT_NE(parser.error().message.find("Transfer-Encoding"), std::string::npos);
}

TEST(HttpRequestParser, UnsupportedCodingsAndVersions) {
    EXPECT_EQ(requestErrorStatus("POST / HTTP/1.1\r\nHost: h\r\nTransfer-Encoding: gzip, "
                                 "chunked\r\n\r\n"),
              501);
    EXPECT_EQ(requestErrorStatus("GET / HTTP/2.0\r\nHost: h\r\n\r\n"), 505);
    EXPECT_EQ(requestErrorStatus("GET / HTTP/3.0\r\nHost: h\r\n\r\n"), 505);
}

TEST(HttpRequestParser, EnforcesHeaderAndBodyLimits) {
    ParserLimits limits;
    limits.maxHeaderBytes = 256;
    limits.maxHeaderCount = 4;
    limits.maxBodyBytes = 10;

    const std::string bigField = "GET / HTTP/1.1\r\nHost: h\r\nX: " + std::string(300, 'a');
    EXPECT_EQ(requestErrorStatus(bigField, limits), 431);  // even before the line ends
    EXPECT_EQ(requestErrorStatus(bigField + "\r\n\r\n", limits), 431);
    std::string many = "GET / HTTP/1.1\r\nHost: h\r\n";
    for (int i = 0; i < 5; ++i) many += "X" + std::to_string(i) + ": v\r\n";
    EXPECT_EQ(requestErrorStatus(many + "\r\n", limits), 431);
    EXPECT_EQ(requestErrorStatus("GET /" + std::string(300, 'a') + " HTTP/1.1\r\n", limits), 414);

    EXPECT_EQ(
        requestErrorStatus("POST / HTTP/1.1\r\nHost: h\r\nContent-Length: 11\r\n\r\n", limits),
        413);
    EXPECT_EQ(requestErrorStatus("POST / HTTP/1.1\r\nHost: h\r\nContent-Length: "
                                 "99999999999999999999999999\r\n\r\n",
                                 limits),
              413);
    EXPECT_EQ(requestErrorStatus("POST / HTTP/1.1\r\nHost: h\r\nTransfer-Encoding: chunked\r\n"
                                 "\r\n6\r\nabcdef\r\n5\r\n",
                                 limits),
              413);
    EXPECT_EQ(requestErrorStatus("POST / HTTP/1.1\r\nHost: h\r\nTransfer-Encoding: chunked\r\n"
                                 "\r\nfffffffffffffffffffff\r\n",
                                 limits),
              413);
    // Exactly at the limits is fine.
    auto atLimit =
        parsedRequest("POST / HTTP/1.1\r\nHost: h\r\nContent-Length: 10\r\n\r\n0123456789", limits);
    EXPECT_EQ(atLimit.state(), ParseState::Done);
}

TEST(HttpRequestParser, ErrorIsSticky) {
    RequestParser parser;
    ASSERT_EQ(parser.feed("BAD\r\n"), ParseState::Error);
    EXPECT_EQ(parser.feed("GET / HTTP/1.1\r\nHost: h\r\n\r\n"), ParseState::Error);
}

// ---- Response parsing ----

TEST(HttpResponseParser, ContentLengthChunkedAndUntilClose) {
    ResponseParser a;
    ASSERT_EQ(a.feed("HTTP/1.1 200 OK\r\nContent-Length: 2\r\n\r\nhi"), ParseState::Done);
    const HttpResponse ra = a.take();
    EXPECT_EQ(ra.status, 200);
    EXPECT_EQ(ra.reason, "OK");
    EXPECT_EQ(ra.body, "hi");

    const std::string chunked =
        "HTTP/1.1 201 Created\r\nTransfer-Encoding: chunked\r\n\r\n3\r\nabc\r\n1\r\nd\r\n0\r\n\r\n";
    for (std::size_t split = 0; split <= chunked.size(); ++split) {
        ResponseParser p;
        (void)p.feed(bytesOf(chunked).first(split));
        ASSERT_EQ(p.feed(bytesOf(chunked).subspan(split)), ParseState::Done) << split;
        EXPECT_EQ(p.take().body, "abcd");
    }

    ResponseParser c;
    ASSERT_EQ(c.feed("HTTP/1.0 200 OK\r\n\r\nuntil "), ParseState::NeedMore);
    ASSERT_EQ(c.feed("close"), ParseState::NeedMore);
    ASSERT_EQ(c.finish(), ParseState::Done);
    EXPECT_EQ(c.take().body, "until close");

    ResponseParser d;
    ASSERT_EQ(d.feed("HTTP/1.1 200 OK\r\nContent-Length: 5\r\n\r\nab"), ParseState::NeedMore);
    EXPECT_EQ(d.finish(), ParseState::Error);
}

TEST(HttpResponseParser, BodilessResponsesAndInterimOnes) {
    ResponseParser head;
    head.setHeadRequest(true);
    ASSERT_EQ(head.feed("HTTP/1.1 200 OK\r\nContent-Length: 99\r\n\r\n"), ParseState::Done);
    EXPECT_EQ(head.take().headers.get("Content-Length"), "99");

    ResponseParser noContent;
    ASSERT_EQ(noContent.feed("HTTP/1.1 204 No Content\r\n\r\n"), ParseState::Done);

    ResponseParser interim;
    ASSERT_EQ(interim.feed("HTTP/1.1 100 Continue\r\n\r\nHTTP/1.1 200 OK\r\nContent-Length: "
                           "1\r\n\r\nx"),
              ParseState::Done);
    const HttpResponse r = interim.take();
    EXPECT_EQ(r.status, 200);
    EXPECT_EQ(r.body, "x");
}

TEST(HttpResponseParser, ToleratesBareLfAndUnfoldsObsFold) {
    ResponseParser p;
    ASSERT_EQ(p.feed("HTTP/1.1 200\nX-Long: a\n\tb\nContent-Length: 1\n\nz"), ParseState::Done)
        << p.error().message;
    const HttpResponse r = p.take();
    EXPECT_EQ(r.headers.get("X-Long"), "a b");
    EXPECT_EQ(r.reason, "");
    EXPECT_EQ(r.body, "z");
}

TEST(HttpResponseParser, RejectsMalformedStatusLinesAndBodyOverLimit) {
    for (const std::string wire : {"HTTP/1.1 20 OK\r\n\r\n", "HTTP/1.1 600 X\r\n\r\n",
                                   "HTTX/1.1 200 OK\r\n\r\n", "HTTP/1.1 200OK\r\n\r\n"}) {
        ResponseParser p;
        EXPECT_EQ(p.feed(wire), ParseState::Error) << wire;
    }
    ParserLimits limits;
    limits.maxBodyBytes = 4;
    ResponseParser big(limits);
    ASSERT_EQ(big.feed("HTTP/1.1 200 OK\r\n\r\n12345"), ParseState::Error);
    EXPECT_EQ(big.error().status, 413);
}

// ---- Serialization ----

TEST(HttpSerialize, RequestRoundTripsThroughTheParser) {
    HttpRequest request;
    request.method = "POST";
    request.path = "/sparql endpoint";
    request.query = {{"a", "1 2"}, {"b&", "=?"}};
    request.headers.add("Host", "h");
    request.headers.add("Content-Length", "999");  // ignored: framing is computed
    request.headers.add("X-Evil", "a\r\nInjected: yes");
    request.body = "payload";
    const std::string wire = serialize(request);
    RequestParser parser;
    ASSERT_EQ(parser.feed(wire), ParseState::Done) << wire;
    const HttpRequest back = parser.take();
    EXPECT_EQ(back.path, request.path);
    EXPECT_EQ(back.query, request.query);
    EXPECT_EQ(back.body, "payload");
    EXPECT_EQ(back.headers.get("Content-Length"), "7");
    EXPECT_FALSE(back.headers.contains("Injected"));
    EXPECT_EQ(back.headers.get("X-Evil"), "a  Injected: yes");

    HttpRequest get;
    get.headers.add("Host", "h");
    EXPECT_EQ(serialize(get), "GET / HTTP/1.1\r\nHost: h\r\n\r\n");
}

TEST(HttpSerialize, ResponseAlwaysCarriesContentLength) {
    HttpResponse response = makeResponse(404, "gone", "text/plain");
    EXPECT_EQ(
        serialize(response),
        "HTTP/1.1 404 Not Found\r\nContent-Type: text/plain\r\nContent-Length: 4\r\n\r\ngone");
    EXPECT_EQ(serialize(response, true),
              "HTTP/1.1 404 Not Found\r\nContent-Type: text/plain\r\nContent-Length: 4\r\n\r\n");
    EXPECT_EQ(serialize(makeResponse(200)), "HTTP/1.1 200 OK\r\nContent-Length: 0\r\n\r\n");
    EXPECT_EQ(serialize(makeResponse(204)), "HTTP/1.1 204 No Content\r\n\r\n");
    ResponseParser parser;
    ASSERT_EQ(parser.feed(serialize(response)), ParseState::Done);
    EXPECT_EQ(parser.take().body, "gone");
}

// ---- URL and form encoding ----

TEST(HttpEncoding, PercentRoundTripsEveryByte) {
    std::string all;
    for (int c = 0; c < 256; ++c) all += static_cast<char>(c);
    const std::string encoded = percentEncode(all);
    for (const char c : encoded) {
        EXPECT_TRUE(std::isalnum(static_cast<unsigned char>(c)) ||
                    std::string_view("-._~%").find(c) != std::string_view::npos);
    }
    auto decoded = percentDecode(encoded);
    ASSERT_TRUE(decoded.ok());
    EXPECT_EQ(*decoded, all);
    EXPECT_EQ(percentEncode("a/b c", "/"), "a/b%20c");
    EXPECT_EQ(*percentDecode("a+b%2b"), "a+b+");
    EXPECT_EQ(*percentDecode("a+b%2b", true), "a b+");
    EXPECT_EQ(*percentDecode("%e2%82%AC"), "\xE2\x82\xAC");
}

TEST(HttpEncoding, BadEscapesAreErrors) {
    for (const char* bad : {"%", "%4", "abc%", "%zz", "%4g", "%%41"}) {
        EXPECT_FALSE(percentDecode(bad).ok()) << bad;
        EXPECT_FALSE(parseFormUrlEncoded(std::string("a=") + bad).ok()) << bad;
    }
    EXPECT_FALSE(percentDecode("%G0").error().empty());
}

TEST(HttpEncoding, FormDataParsesAndRoundTrips) {
    auto parsed = parseFormUrlEncoded("query=SELECT+*+%7B%3Fs+%3Fp+%3Fo%7D&&flag&empty=&a=b=c");
    ASSERT_TRUE(parsed.ok());
    const Params expected = {
        {"query", "SELECT * {?s ?p ?o}"}, {"flag", ""}, {"empty", ""}, {"a", "b=c"}};
    EXPECT_EQ(*parsed, expected);
    EXPECT_EQ(parseFormUrlEncoded("")->size(), 0U);

    const Params tricky = {{"a b", "c&d=e+f"}, {"ünï", "100% \"sure\"\n"}, {"", "x"}};
    const std::string encoded = formUrlEncode(tricky);
    EXPECT_EQ(encoded.find(' '), std::string::npos);
    auto back = parseFormUrlEncoded(encoded);
    ASSERT_TRUE(back.ok());
    EXPECT_EQ(*back, tricky);
    EXPECT_EQ(formUrlEncode({{"q", "a b"}}), "q=a+b");
    EXPECT_EQ(makeTarget("/x y", {{"k", "v"}}), "/x%20y?k=v");
}

// ---- Media types and negotiation ----

TEST(HttpMediaType, ParsesTypeSubtypeAndParameters) {
    auto mt = parseMediaType("Application/SPARQL-Results+JSON ; Charset=\"utf-8\";q=\"a\\\"b\"");
    ASSERT_TRUE(mt.ok()) << mt.error();
    EXPECT_EQ(mt->type, "application");
    EXPECT_EQ(mt->subtype, "sparql-results+json");
    EXPECT_EQ(mt->essence(), "application/sparql-results+json");
    EXPECT_EQ(mt->param("charset"), "utf-8");
    EXPECT_EQ(mt->param("Q"), "a\"b");
    EXPECT_TRUE(parseMediaType("text/turtle").ok());
    for (const char* bad : {"", "text", "text/", "/plain", "text/plain;charset", "text/plain x",
                            "text/plain;a=\"unterminated", "a/b, c/d"}) {
        EXPECT_FALSE(parseMediaType(bad).ok()) << bad;
    }
}

TEST(HttpMediaType, AcceptNegotiation) {
    const std::array<std::string_view, 3> offered = {"application/sparql-results+json",
                                                     "application/sparql-results+xml", "text/csv"};
    EXPECT_EQ(chooseMediaType("", offered), 0U);
    EXPECT_EQ(chooseMediaType("*/*", offered), 0U);
    EXPECT_EQ(chooseMediaType("text/csv", offered), 2U);
    EXPECT_EQ(chooseMediaType("application/sparql-results+xml;q=0.9, text/csv;q=0.8", offered), 1U);
    EXPECT_EQ(chooseMediaType("application/*;q=0.5, text/csv", offered), 2U);
    // Equal quality: the server's order decides.
    EXPECT_EQ(chooseMediaType("text/csv, application/sparql-results+xml", offered), 1U);
    // The most specific range sets the quality, even when a wildcard rates higher.
    EXPECT_EQ(chooseMediaType("*/*;q=1, application/sparql-results+json;q=0", offered), 1U);
    EXPECT_EQ(chooseMediaType("APPLICATION/SPARQL-RESULTS+XML", offered), 1U);
    EXPECT_EQ(chooseMediaType("image/png", offered), std::nullopt);
    EXPECT_EQ(chooseMediaType("text/csv;q=0, image/*", offered), std::nullopt);
    // Broken elements are skipped; q with bad syntax drops its element.
    EXPECT_EQ(chooseMediaType("garbage, text/csv;q=2, text/csv;q=0.3", offered), 2U);
    EXPECT_EQ(chooseMediaType("garbage", offered), 0U);
    // Parameters in a range must be present in the offer.
    const std::array<std::string_view, 2> turtle = {"text/turtle", "text/plain; charset=utf-8"};
    EXPECT_EQ(chooseMediaType("text/plain;charset=UTF-8, text/turtle;q=0.5", turtle), 1U);
    EXPECT_EQ(chooseMediaType("text/plain;charset=latin1, text/turtle;q=0.5", turtle), 0U);
    // Accept-extensions after q are not parameters.
    EXPECT_EQ(chooseMediaType("text/csv;q=0.5;ext=1, */*;q=0.1", offered), 2U);
}

// ---- Loopback server and client ----

namespace {

constexpr auto kNoThrow = asio::experimental::as_tuple(asio::use_awaitable);
constexpr milliseconds kBound{5000};  // no test waits longer for anything

/// Describes the request in the body, so tests assert on what the server saw.
asio::awaitable<HttpResponse> echoHandler(HttpRequest request) {
    if (request.path == "/missing") co_return makeResponse(404, "no such resource");
    if (request.path == "/throw") throw std::runtime_error("handler failure");
    if (request.path == "/slow") {
        // Suspends on the I/O thread's timer, as an engine call would.
        const auto executor = co_await asio::this_coro::executor;
        asio::steady_timer timer(executor, milliseconds(20));
        auto waiting = timer.async_wait(kNoThrow);
        co_await std::move(waiting);
    }
    std::string body = request.method + " " + request.path;
    auto describe = [&body](std::string_view tag, const Params& params) {
        for (const auto& [k, v] : params)
            body.append(" ").append(tag).append(k).append("=").append(v);
    };
    describe("q:", request.query);
    const auto type = parseMediaType(request.headers.get("Content-Type").value_or("x/none"));
    if (type && type->essence() == "application/x-www-form-urlencoded") {
        auto form = parseFormUrlEncoded(request.body);
        if (!form) co_return makeResponse(400, form.error());
        describe("f:", *form);
    } else if (!request.body.empty()) {
        body += " body:" + request.body;
    }
    co_return makeResponse(200, body);
}

/// A server on 127.0.0.1 with its io_context on a thread of its own.
class LoopbackServer {
public:
    template <class H>
    explicit LoopbackServer(H handler, HttpServerLimits limits = {})
        : server_(io_, {asio::ip::make_address("127.0.0.1"), 0}, std::move(handler), limits) {
        const auto started = server_.start();
        EXPECT_TRUE(started.ok()) << started.error();
        thread_ = std::thread([this] {
            io_.run();
            stopped_.set_value();
        });
    }
    LoopbackServer(const LoopbackServer&) = delete;
    LoopbackServer& operator=(const LoopbackServer&) = delete;
    ~LoopbackServer() {
        stopAsync();
        // Stopping must leave the io_context without work; if not, fail instead of hanging.
        if (stopped_.get_future().wait_for(kBound) != std::future_status::ready) {
            ADD_FAILURE() << "server coroutines still running after stop()";
            io_.stop();
        }
        thread_.join();
    }
    void stopAsync() {
        asio::post(io_, [this] { server_.stop(); });
    }
    [[nodiscard]] std::uint16_t port() const { return server_.port(); }

private:
    asio::io_context io_;
    HttpServer server_;
    std::promise<void> stopped_;
    std::thread thread_;
};

/// A hand-driven client socket: what a browser or a misbehaving peer could send.
class RawClient {
public:
    explicit RawClient(std::uint16_t port) {
        socket_.connect({asio::ip::make_address("127.0.0.1"), port});
    }
    void send(std::string_view bytes) { asio::write(socket_, asio::buffer(bytes)); }

    /// The next response, or nullopt if none is complete within kBound.
    std::optional<HttpResponse> readResponse() {
        const auto deadline = Clock::now() + kBound;
        for (;;) {
            const ParseState state = parser_.feed(std::span<const char>());
            if (state == ParseState::Done) return parser_.take();
            if (state == ParseState::Error) return std::nullopt;
            auto [ec, n] = readSome(deadline);
            if (ec) {
                return parser_.finish() == ParseState::Done ? std::optional(parser_.take())
                                                            : std::nullopt;
            }
            (void)parser_.feed(std::span<const char>(buffer_.data(), n));
            received_.append(buffer_.data(), n);
        }
    }
    /// Reads until `text` has arrived (interim responses are invisible to readResponse).
    bool waitFor(std::string_view text) {
        const auto deadline = Clock::now() + kBound;
        while (received_.find(text) == std::string::npos) {
            auto [ec, n] = readSome(deadline);
            if (ec) return false;
            (void)parser_.feed(std::span<const char>(buffer_.data(), n));
            received_.append(buffer_.data(), n);
        }
        return true;
    }
    /// Whether the server closes the connection within kBound (bytes before are dropped).
    bool closedByPeer() {
        const auto deadline = Clock::now() + kBound;
        for (;;) {
            auto [ec, n] = readSome(deadline);
            if (ec) return ec != asio::error::timed_out;
        }
    }

private:
    std::pair<asio::error_code, std::size_t> readSome(Clock::time_point deadline) {
        // Asio does not report the end of a stream twice: a second read would wait forever.
        if (ended_) return {ended_, 0};
        asio::error_code result = asio::error::timed_out;
        std::size_t got = 0;
        bool done = false;
        socket_.async_read_some(asio::buffer(buffer_), [&](asio::error_code ec, std::size_t n) {
            done = true;
            if (ec != asio::error::operation_aborted) result = ec;
            got = n;
        });
        io_.restart();
        io_.run_until(deadline);
        if (!done) {
            socket_.cancel();
            io_.restart();
            io_.run();  // collects the cancelled read
        }
        if (result && result != asio::error::timed_out) ended_ = result;
        return {result, got};
    }

    asio::io_context io_;
    asio::ip::tcp::socket socket_{io_};
    ResponseParser parser_;
    std::array<char, 4096> buffer_{};
    std::string received_;
    asio::error_code ended_;
};

HttpRequest get(std::string path, Params query = {}) {
    HttpRequest request;
    request.path = std::move(path);
    request.query = std::move(query);
    return request;
}

}  // namespace

TEST(HttpLoopback, GetWithQuery) {
    LoopbackServer server{HttpServer::Handler(echoHandler)};
    auto response =
        httpRequest("127.0.0.1", server.port(),
                    get("/sparql", {{"query", "ASK { ?s ?p ?o }"}, {"x", "a&b"}}), kBound);
    ASSERT_TRUE(response.ok()) << response.error();
    EXPECT_EQ(response->status, 200);
    EXPECT_EQ(response->body, "GET /sparql q:query=ASK { ?s ?p ?o } q:x=a&b");
    EXPECT_EQ(response->headers.get("Content-Type"), "text/plain; charset=utf-8");
}

TEST(HttpLoopback, PostFormAndHeadAndSyncHandler) {
    LoopbackServer server{HttpServer::Handler(echoHandler)};
    HttpRequest post;
    post.method = "POST";
    post.path = "/sparql";
    post.headers.add("Content-Type", "application/x-www-form-urlencoded");
    post.body = formUrlEncode({{"update", "INSERT DATA { <a> <b> \"c d\" }"}});
    auto response = httpRequest("127.0.0.1", server.port(), post, kBound);
    ASSERT_TRUE(response.ok()) << response.error();
    EXPECT_EQ(response->body, "POST /sparql f:update=INSERT DATA { <a> <b> \"c d\" }");

    HttpRequest head = get("/x");
    head.method = "HEAD";
    auto headResponse = httpRequest("127.0.0.1", server.port(), head, kBound);
    ASSERT_TRUE(headResponse.ok()) << headResponse.error();
    EXPECT_EQ(headResponse->body, "");
    EXPECT_EQ(headResponse->headers.get("Content-Length"), "7");  // "HEAD /x"

    LoopbackServer sync{
        [](const HttpRequest& request) { return makeResponse(200, "sync " + request.path); }};
    auto syncResponse = httpRequest("127.0.0.1", sync.port(), get("/p"), kBound);
    ASSERT_TRUE(syncResponse.ok()) << syncResponse.error();
    EXPECT_EQ(syncResponse->body, "sync /p");
}

TEST(HttpLoopback, AsyncHandler404And500) {
    LoopbackServer server{HttpServer::Handler(echoHandler)};
    auto slow = httpRequest("127.0.0.1", server.port(), get("/slow"), kBound);
    ASSERT_TRUE(slow.ok()) << slow.error();
    EXPECT_EQ(slow->body, "GET /slow");
    auto missing = httpRequest("127.0.0.1", server.port(), get("/missing"), kBound);
    ASSERT_TRUE(missing.ok()) << missing.error();
    EXPECT_EQ(missing->status, 404);
    EXPECT_EQ(missing->reason, "Not Found");
    auto thrown = httpRequest("127.0.0.1", server.port(), get("/throw"), kBound);
    ASSERT_TRUE(thrown.ok()) << thrown.error();
    EXPECT_EQ(thrown->status, 500);
    EXPECT_EQ(thrown->body.find("handler failure"), std::string::npos);  // no internals leak
}

TEST(HttpLoopback, KeepAliveServesTwoRequestsOnOneConnection) {
    LoopbackServer server{HttpServer::Handler(echoHandler)};
    RawClient client(server.port());
    client.send("GET /one HTTP/1.1\r\nHost: h\r\n\r\n");
    auto first = client.readResponse();
    ASSERT_TRUE(first.has_value());
    EXPECT_EQ(first->body, "GET /one");
    EXPECT_TRUE(first->keepAlive());
    client.send("POST /two HTTP/1.1\r\nHost: h\r\nContent-Length: 3\r\n\r\nabc");
    auto second = client.readResponse();
    ASSERT_TRUE(second.has_value());
    EXPECT_EQ(second->body, "POST /two body:abc");

    // Pipelined, with the async handler first: answers keep the order of the requests.
    client.send(
        "GET /slow HTTP/1.1\r\nHost: h\r\n\r\nGET /three HTTP/1.1\r\nHost: h\r\nConnection: "
        "close\r\n\r\n");
    auto third = client.readResponse();
    auto fourth = client.readResponse();
    ASSERT_TRUE(third.has_value());
    ASSERT_TRUE(fourth.has_value());
    EXPECT_EQ(third->body, "GET /slow");
    EXPECT_EQ(fourth->body, "GET /three");
    EXPECT_FALSE(fourth->keepAlive());
    EXPECT_TRUE(client.closedByPeer());
}

TEST(HttpLoopback, Http10ClosesUnlessKeptAlive) {
    LoopbackServer server{HttpServer::Handler(echoHandler)};
    RawClient client(server.port());
    client.send("GET /a HTTP/1.0\r\nConnection: keep-alive\r\n\r\n");
    auto first = client.readResponse();
    ASSERT_TRUE(first.has_value());
    EXPECT_EQ(first->headers.get("Connection"), "keep-alive");
    client.send("GET /b HTTP/1.0\r\n\r\n");
    auto second = client.readResponse();
    ASSERT_TRUE(second.has_value());
    EXPECT_EQ(second->body, "GET /b");
    EXPECT_TRUE(client.closedByPeer());
}

TEST(HttpLoopback, ExpectContinueGetsAnInterimAnswer) {
    LoopbackServer server{HttpServer::Handler(echoHandler)};
    RawClient client(server.port());
    client.send("PUT /c HTTP/1.1\r\nHost: h\r\nExpect: 100-continue\r\nContent-Length: 4\r\n\r\n");
    ASSERT_TRUE(client.waitFor("HTTP/1.1 100 Continue\r\n\r\n"));
    client.send("data");
    auto response = client.readResponse();
    ASSERT_TRUE(response.has_value());
    EXPECT_EQ(response->body, "PUT /c body:data");
}

TEST(HttpLoopback, BadRequestsGetTheParsersStatus) {
    HttpServerLimits limits;
    limits.parser.maxBodyBytes = 1024;
    limits.parser.maxHeaderBytes = 512;
    LoopbackServer server{HttpServer::Handler(echoHandler), limits};
    {
        // The body is on its way when the 413 is sent; the server drains it, then closes.
        RawClient client(server.port());
        client.send("POST /big HTTP/1.1\r\nHost: h\r\nContent-Length: 5000\r\n\r\n" +
                    std::string(5000, 'a'));
        auto response = client.readResponse();
        ASSERT_TRUE(response.has_value());
        EXPECT_EQ(response->status, 413);
        EXPECT_FALSE(response->keepAlive());
        EXPECT_TRUE(client.closedByPeer());
    }
    {
        HttpRequest big = get("/big");
        big.method = "POST";
        big.body.assign(std::size_t{100} * 1024, 'b');
        auto response = httpRequest("127.0.0.1", server.port(), big, kBound);
        ASSERT_TRUE(response.ok()) << response.error();
        EXPECT_EQ(response->status, 413);
    }
    const std::vector<std::pair<std::string, int>> cases = {
        {"GET / HTTP/1.1\r\nHost: h\r\nX: " + std::string(600, 'x') + "\r\n\r\n", 431},
        {"GET / HTTP/1.1\r\n\r\n", 400},
        {"GET / HTTP/2.0\r\nHost: h\r\n\r\n", 505},
        {"POST / HTTP/1.1\r\nHost: h\r\nContent-Length: 1\r\nTransfer-Encoding: chunked\r\n\r\n",
         400},
    };
    for (const auto& [wire, status] : cases) {
        RawClient client(server.port());
        client.send(wire);
        auto response = client.readResponse();
        ASSERT_TRUE(response.has_value()) << wire;
        EXPECT_EQ(response->status, status) << wire;
        EXPECT_TRUE(client.closedByPeer());
    }
}

TEST(HttpLoopback, SlowClientGets408) {
    HttpServerLimits limits;
    limits.readTimeout = milliseconds(150);
    LoopbackServer server{HttpServer::Handler(echoHandler), limits};
    RawClient client(server.port());
    const auto start = Clock::now();
    client.send("GET / HTTP/1.1\r\nHost: h\r\n");  // the header section never ends
    auto response = client.readResponse();
    const auto elapsed = Clock::now() - start;
    ASSERT_TRUE(response.has_value());
    EXPECT_EQ(response->status, 408);
    EXPECT_GE(elapsed, milliseconds(150));
    EXPECT_LT(elapsed, milliseconds(3000));
    EXPECT_TRUE(client.closedByPeer());
}

TEST(HttpLoopback, IdleConnectionIsClosedSilently) {
    HttpServerLimits limits;
    limits.idleTimeout = milliseconds(100);
    LoopbackServer server{HttpServer::Handler(echoHandler), limits};
    RawClient client(server.port());
    EXPECT_TRUE(client.closedByPeer());
    EXPECT_FALSE(client.readResponse().has_value());
}

TEST(HttpLoopback, ConnectionLimitAnswers503) {
    HttpServerLimits limits;
    limits.maxConnections = 1;
    LoopbackServer server{HttpServer::Handler(echoHandler), limits};
    RawClient first(server.port());
    first.send("GET /a HTTP/1.1\r\nHost: h\r\n\r\n");
    ASSERT_TRUE(first.readResponse().has_value());  // now surely accepted and counted
    RawClient second(server.port());
    auto refused = second.readResponse();
    ASSERT_TRUE(refused.has_value());
    EXPECT_EQ(refused->status, 503);
}

TEST(HttpLoopback, StopClosesOpenConnections) {
    LoopbackServer server{HttpServer::Handler(echoHandler)};
    RawClient client(server.port());
    client.send("GET /a HTTP/1.1\r\nHost: h\r\n\r\n");
    ASSERT_TRUE(client.readResponse().has_value());
    server.stopAsync();
    EXPECT_TRUE(client.closedByPeer());
}

TEST(HttpLoopback, ServerDestroyedWhileAHandlerRuns) {
    // The io_context outlives the server; the suspended handler finishes afterwards.
    asio::io_context io;
    bool entered = false;  // all on this thread: the handler runs inside io.run_one_for
    auto handler = [&entered](HttpRequest request) -> asio::awaitable<HttpResponse> {
        entered = true;
        auto answering = echoHandler(std::move(request));
        co_return co_await std::move(answering);
    };
    std::optional<HttpServer> server;
    server.emplace(io, asio::ip::tcp::endpoint{asio::ip::make_address("127.0.0.1"), 0},
                   HttpServer::Handler(handler));
    ASSERT_TRUE(server->start().ok());
    RawClient client(server->port());
    client.send("GET /slow HTTP/1.1\r\nHost: h\r\n\r\n");
    for (int i = 0; i < 1000 && !entered; ++i) io.run_one_for(kBound);
    ASSERT_TRUE(entered);
    server.reset();
    io.run_for(kBound);  // returns early once every coroutine has finished
    EXPECT_TRUE(io.stopped());
    EXPECT_TRUE(client.closedByPeer());
}

TEST(HttpClient, TimesOutAgainstASilentServer) {
    // Listens (the kernel completes the handshake) but never reads or answers.
    asio::io_context io;
    asio::ip::tcp::acceptor silent(io, {asio::ip::make_address("127.0.0.1"), 0});
    const auto port = silent.local_endpoint().port();
    const auto start = Clock::now();
    auto response = httpRequest("127.0.0.1", port, get("/"), milliseconds(200));
    const auto elapsed = Clock::now() - start;
    ASSERT_FALSE(response.ok());
    EXPECT_NE(response.error().find("127.0.0.1:" + std::to_string(port)), std::string::npos)
        << response.error();
    EXPECT_NE(response.error().find("timed out"), std::string::npos) << response.error();
    EXPECT_GE(elapsed, milliseconds(200));
    EXPECT_LT(elapsed, milliseconds(3000));
}

TEST(HttpClient, RefusedConnectionNamesTheEndpoint) {
    std::uint16_t port = 0;
    {
        asio::io_context io;
        asio::ip::tcp::acceptor probe(io, {asio::ip::make_address("127.0.0.1"), 0});
        port = probe.local_endpoint().port();
    }  // closed again: nothing listens there now
    auto response = httpRequest("127.0.0.1", port, get("/"), kBound);
    ASSERT_FALSE(response.ok());
    EXPECT_NE(response.error().find("127.0.0.1:" + std::to_string(port)), std::string::npos)
        << response.error();
    EXPECT_NE(response.error().find("connect"), std::string::npos) << response.error();
}

TEST(HttpClient, RejectsInvalidRequestsAndMalformedAnswers) {
    HttpRequest bad = get("/");
    bad.method = "GET /x HTTP/1.1\r\n";
    EXPECT_FALSE(httpRequest("127.0.0.1", 1, bad, kBound).ok());

    // A "server" that answers garbage, driven from this thread's io_context.
    asio::io_context io;
    asio::ip::tcp::acceptor acceptor(io, {asio::ip::make_address("127.0.0.1"), 0});
    const auto port = acceptor.local_endpoint().port();
    std::thread peer([&] {
        asio::error_code ec;
        asio::ip::tcp::socket socket(io);
        acceptor.accept(socket, ec);
        if (ec) return;
        asio::write(socket, asio::buffer(std::string_view("NOT HTTP\r\n\r\n")), ec);
        socket.shutdown(asio::ip::tcp::socket::shutdown_both, ec);
    });
    auto response = httpRequest("127.0.0.1", port, get("/"), kBound);
    peer.join();
    ASSERT_FALSE(response.ok());
    EXPECT_NE(response.error().find("malformed response"), std::string::npos) << response.error();
}

}  // namespace http_test
