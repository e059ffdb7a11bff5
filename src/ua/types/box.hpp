#pragma once
// Box<T>: a heap-held value with value semantics (deep copy, equality by value).
// Recursive built-in types (a Variant holding a DataValue holding a Variant...) need an
// indirection; Box keeps them regular types without exposing pointers.
#include <memory>
#include <utility>

namespace skillcell::ua {

template <class T>
class Box {
public:
    Box() : p_(std::make_unique<T>()) {}
    // NOLINTNEXTLINE(google-explicit-constructor)
    Box(T value) : p_(std::make_unique<T>(std::move(value))) {}
    Box(const Box& o) : p_(std::make_unique<T>(*o.p_)) {}
    Box(Box&& o) noexcept : p_(std::move(o.p_)) {}
    Box& operator=(const Box& o) {
        if (this != &o) p_ = std::make_unique<T>(*o.p_);
        return *this;
    }
    Box& operator=(Box&& o) noexcept {
        p_ = std::move(o.p_);
        return *this;
    }
    ~Box() = default;

    // A moved-from Box is only assigned to or destroyed; accessors assume a value.
    T& operator*() { return *p_; }
    const T& operator*() const { return *p_; }
    T* operator->() { return p_.get(); }
    const T* operator->() const { return p_.get(); }

    friend bool operator==(const Box& a, const Box& b) { return *a.p_ == *b.p_; }

private:
    std::unique_ptr<T> p_;
};

}  // namespace skillcell::ua
