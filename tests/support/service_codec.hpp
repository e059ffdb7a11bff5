#pragma once
// A service message as the body of a secure-channel message: its encoding NodeId, then the
// message (OPC 10000-6, 7.1.2). For tests that drive a SecureChannel directly, without a
// client or a server.
#include <gtest/gtest.h>

#include <cstdint>
#include <vector>

#include "ua/encoding/codec.hpp"

namespace skillcell::test {

template <class T>
std::vector<std::uint8_t> encodeService(const T& message) {
    std::vector<std::uint8_t> out;
    ua::BinaryWriter w(out);
    ua::encode(w, ua::NodeId(T::kBinaryEncodingId));
    ua::encode(w, message);
    return out;
}

/// Decodes a body that must hold exactly one `T` (a test failure otherwise).
template <class T>
T decodeService(const std::vector<std::uint8_t>& body) {
    ua::BinaryReader r(body);
    ua::NodeId id;
    ua::decode(r, id);
    EXPECT_EQ(id, ua::NodeId(T::kBinaryEncodingId));
    T out{};
    ua::decode(r, out);
    EXPECT_TRUE(r.ok());
    EXPECT_EQ(r.remaining(), 0U);
    return out;
}

}  // namespace skillcell::test
