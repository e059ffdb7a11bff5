#pragma once
// BinaryWriter: appends OPC UA binary encoding (little-endian) to a caller's buffer.
#include <bit>
#include <cstdint>
#include <cstring>
#include <span>
#include <type_traits>
#include <vector>

#include "ua/types/status_code.hpp"

namespace skillcell::ua {

static_assert(std::endian::native == std::endian::little,
              "the binary codec copies numbers as they lie in memory");

class BinaryWriter {
public:
    explicit BinaryWriter(std::vector<std::uint8_t>& out) : out_(out) {}

    template <class T>
    requires std::is_arithmetic_v<T>
    void write(T value) {
        const auto at = out_.size();
        out_.resize(at + sizeof(T));
        std::memcpy(out_.data() + at, &value, sizeof(T));
    }
    void writeBytes(std::span<const std::uint8_t> bytes) {
        out_.insert(out_.end(), bytes.begin(), bytes.end());
    }
    /// Overwrites four bytes written earlier (message sizes known only at the end).
    void patchUInt32(std::size_t at, std::uint32_t value) {
        std::memcpy(out_.data() + at, &value, sizeof value);
    }

    [[nodiscard]] std::size_t size() const { return out_.size(); }
    [[nodiscard]] std::vector<std::uint8_t>& buffer() { return out_; }

    /// Encoding can fail only for values the type system cannot rule out (an array whose
    /// elements do not match its declared type, a string longer than 2^31-1).
    void fail(StatusCode s) {
        if (status_.isGood()) status_ = s;
    }
    [[nodiscard]] bool ok() const { return status_.isGood(); }
    [[nodiscard]] StatusCode status() const { return status_; }

private:
    std::vector<std::uint8_t>& out_;
    StatusCode status_;
};

}  // namespace skillcell::ua
