#pragma once
// Expected<T>: a value, or the message saying why there is none. For failures that are
// reported to people and come from outside the OPC UA stack (a SPARQL syntax error, a
// reasoner's verdict, a child process that would not start): they carry text, not a
// StatusCode; an OPC UA face maps them to status codes at its edge.
#include <cassert>
#include <string>
#include <utility>
#include <variant>

namespace skillcell {

/// What kind of failure, for the edges that map failures to protocol answers (HTTP status,
/// OPC UA status code).
enum class ErrorKind {
    Failed,       // anything else
    BadInput,     // the caller's request is wrong (a SPARQL syntax error, a bad IRI)
    Refused,      // well-formed, but refused (a load that would make the KB inconsistent)
    Unavailable,  // an engine cannot be reached or did not answer in time
};

/// The failure of an Expected: a message for people.
struct Error {
    std::string message;
    ErrorKind kind = ErrorKind::Failed;
};

/// A failure of the caller's input.
[[nodiscard]] inline Error badInput(std::string message) {
    return Error{std::move(message), ErrorKind::BadInput};
}

template <class T>
class [[nodiscard]] Expected {
public:
    Expected(T value) : v_(std::move(value)) {}      // NOLINT(google-explicit-constructor)
    Expected(Error error) : v_(std::move(error)) {}  // NOLINT(google-explicit-constructor)

    [[nodiscard]] bool ok() const { return v_.index() == 0; }
    explicit operator bool() const { return ok(); }
    /// The failure's message; empty when there is a value.
    [[nodiscard]] const std::string& error() const {
        static const std::string kNone;
        return ok() ? kNone : std::get<1>(v_).message;
    }
    /// The failure's kind; Failed when there is a value (ask ok() first).
    [[nodiscard]] ErrorKind errorKind() const {
        return ok() ? ErrorKind::Failed : std::get<1>(v_).kind;
    }
    /// The failure itself, to pass on.
    [[nodiscard]] Error failure() const { return ok() ? Error{} : std::get<1>(v_); }
    T& value() & { return std::get<0>(v_); }
    const T& value() const& { return std::get<0>(v_); }
    T&& value() && { return std::get<0>(std::move(v_)); }
    T& operator*() & { return value(); }
    const T& operator*() const& { return value(); }
    T* operator->() { return &value(); }
    const T* operator->() const { return &value(); }

private:
    std::variant<T, Error> v_;
};

/// For operations that yield nothing but may fail.
struct Done {};
using Status = Expected<Done>;

}  // namespace skillcell
