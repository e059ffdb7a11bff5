#pragma once
// BinaryReader: bounds- and limit-checked reading of OPC UA binary encoding.
//
// Errors are sticky: the first failure records its status, every later read returns a
// zero value without advancing, and the caller checks ok() once at the end. That keeps
// decoders straight-line code with no exceptions, and a failed decode never reads past
// the input or allocates more than the input could justify.
#include <cstdint>
#include <cstring>
#include <span>
#include <type_traits>

#include "ua/types/status_code.hpp"

namespace skillcell::ua {

struct DecodeLimits {
    std::uint32_t maxStringLength = 16u * 1024 * 1024;
    std::uint32_t maxByteStringLength = 16u * 1024 * 1024;
    std::uint32_t maxArrayLength = 1u << 20;
    /// Nesting of Variant / DataValue / DiagnosticInfo / ExtensionObject inside each other.
    std::uint32_t maxDepth = 32;
};

class BinaryReader {
public:
    explicit BinaryReader(std::span<const std::uint8_t> data, DecodeLimits limits = {})
        : data_(data), limits_(limits) {}

    template <class T>
    requires std::is_arithmetic_v<T> T read() {
        T value{};
        if (!require(sizeof(T))) return value;
        std::memcpy(&value, data_.data() + pos_, sizeof(T));
        pos_ += sizeof(T);
        return value;
    }

    /// The next n bytes, or an empty span (and failure) if fewer remain.
    std::span<const std::uint8_t> readBytes(std::size_t n) {
        if (!require(n)) return {};
        auto s = data_.subspan(pos_, n);
        pos_ += n;
        return s;
    }

    /// Reads an Int32 length prefix. -1 (null) yields 0. A length below -1 or larger than the
    /// remaining input allows (at `minElementSize` bytes each) is malformed input
    /// (BadDecodingError); a plausible length above `max` exceeds a limit.
    std::uint32_t readLength(std::uint32_t max, std::size_t minElementSize) {
        const auto n = read<std::int32_t>();
        if (!ok() || n == -1) return 0;
        if (n < -1) {
            fail(status::BadDecodingError);
            return 0;
        }
        const auto len = static_cast<std::uint32_t>(n);
        if (static_cast<std::uint64_t>(len) * minElementSize > remaining()) {
            fail(status::BadDecodingError);
            return 0;
        }
        if (len > max) {
            fail(status::BadEncodingLimitsExceeded);
            return 0;
        }
        return len;
    }

    /// RAII nesting counter for the recursive built-in types.
    class DepthGuard {
    public:
        explicit DepthGuard(BinaryReader& r) : r_(r) {
            if (++r_.depth_ > r_.limits_.maxDepth) r_.fail(status::BadEncodingLimitsExceeded);
        }
        DepthGuard(const DepthGuard&) = delete;
        DepthGuard& operator=(const DepthGuard&) = delete;
        ~DepthGuard() { --r_.depth_; }

    private:
        BinaryReader& r_;
    };

    void fail(StatusCode s) {
        if (status_.isGood()) status_ = s;
    }
    [[nodiscard]] bool ok() const { return status_.isGood(); }
    [[nodiscard]] StatusCode status() const { return status_; }
    [[nodiscard]] std::size_t position() const { return pos_; }
    [[nodiscard]] std::size_t remaining() const { return ok() ? data_.size() - pos_ : 0; }
    [[nodiscard]] const DecodeLimits& limits() const { return limits_; }

private:
    bool require(std::size_t n) {
        if (!ok()) return false;
        if (data_.size() - pos_ < n) {
            fail(status::BadDecodingError);
            return false;
        }
        return true;
    }

    std::span<const std::uint8_t> data_;
    std::size_t pos_ = 0;
    DecodeLimits limits_;
    std::uint32_t depth_ = 0;
    StatusCode status_;
};

}  // namespace skillcell::ua
