#pragma once
// Result<T>: a value or the StatusCode saying why there is none. std::expected arrives
// with C++23; this is the small subset skillcell needs, so that failures crossing the
// network boundary are values, never exceptions.
#include <cassert>
#include <utility>
#include <variant>

#include "ua/types/status_code.hpp"

namespace skillcell::ua {

template <class T>
class [[nodiscard]] Result {
public:
    Result(T value) : v_(std::move(value)) {}  // NOLINT(google-explicit-constructor)
    Result(StatusCode error) : v_(error) { assert(error.isBad()); }  // NOLINT

    [[nodiscard]] bool ok() const { return v_.index() == 0; }
    explicit operator bool() const { return ok(); }
    /// The failure; Good when there is a value.
    [[nodiscard]] StatusCode status() const { return ok() ? status::Good : std::get<1>(v_); }
    T& value() & { return std::get<0>(v_); }
    const T& value() const& { return std::get<0>(v_); }
    T&& value() && { return std::get<0>(std::move(v_)); }
    T& operator*() & { return value(); }
    const T& operator*() const& { return value(); }
    T&& operator*() && { return std::move(*this).value(); }
    T* operator->() { return &value(); }
    const T* operator->() const { return &value(); }

private:
    std::variant<T, StatusCode> v_;
};

}  // namespace skillcell::ua
