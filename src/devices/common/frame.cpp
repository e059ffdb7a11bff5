#include "devices/common/frame.hpp"

#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <vector>

#include "ua/address_space/ns0_ids.hpp"
#include "ua/encoding/binary_writer.hpp"

namespace skillcell::devices {
namespace {

// 3DFrame's Default Binary encoding node (namespace 0); its body is six Doubles because
// both nested structures are plain Double records encoded inline.
constexpr std::uint32_t kThreeDFrameDefaultBinary = 18823;
constexpr std::size_t kFrameBodySize = 6 * sizeof(double);

}  // namespace

KDL::Frame toFrame(const Pose6& p) {
    return KDL::Frame(KDL::Rotation::RPY(p.a, p.b, p.c), KDL::Vector(p.x, p.y, p.z));
}

Pose6 toPose6(const KDL::Frame& f) {
    Pose6 p{f.p.x(), f.p.y(), f.p.z(), 0, 0, 0};
    f.M.GetRPY(p.a, p.b, p.c);
    return p;
}

ua::Variant frameToVariant(const KDL::Frame& frame) {
    const Pose6 p = toPose6(frame);
    std::vector<std::uint8_t> body;
    ua::BinaryWriter w(body);
    for (double v : {p.x, p.y, p.z, p.a, p.b, p.c}) w.write(v);
    ua::ExtensionObject eo;
    eo.typeId = ua::NodeId(kThreeDFrameDefaultBinary);
    eo.encoding = ua::ExtensionObject::Encoding::Binary;
    eo.body = ua::ByteString(std::move(body));
    return ua::Variant(std::move(eo));
}

ua::Result<KDL::Frame> frameFromVariant(const ua::Variant& value) {
    const auto* eo = value.get<ua::ExtensionObject>();
    if (eo == nullptr || eo->encoding != ua::ExtensionObject::Encoding::Binary ||
        eo->typeId != ua::NodeId(kThreeDFrameDefaultBinary) || eo->body.size() != kFrameBodySize) {
        return ua::status::BadTypeMismatch;
    }
    double v[6];
    std::memcpy(v, eo->body.bytes.data(), kFrameBodySize);  // little-endian, as the wire
    for (double d : v) {
        if (!std::isfinite(d)) return ua::status::BadOutOfRange;
    }
    return toFrame(Pose6{v[0], v[1], v[2], v[3], v[4], v[5]});
}

std::optional<Pose6> parsePose6(std::string_view text) {
    std::vector<double> numbers;
    while (!text.empty()) {
        const auto comma = text.find(',');
        std::string_view item = text.substr(0, comma);
        while (!item.empty() && item.front() == ' ') item.remove_prefix(1);
        while (!item.empty() && item.back() == ' ') item.remove_suffix(1);
        double d = 0;
        const auto [end, ec] = std::from_chars(item.data(), item.data() + item.size(), d);
        if (ec != std::errc() || end != item.data() + item.size() || !std::isfinite(d)) {
            return std::nullopt;
        }
        numbers.push_back(d);
        if (comma == std::string_view::npos) break;
        text.remove_prefix(comma + 1);
        if (text.empty()) return std::nullopt;  // a trailing comma
    }
    if (numbers.size() != 3 && numbers.size() != 6) return std::nullopt;
    numbers.resize(6, 0.0);
    return Pose6{numbers[0], numbers[1], numbers[2], numbers[3], numbers[4], numbers[5]};
}

std::string describe(const KDL::Frame& frame) {
    return describe(toPose6(frame));
}

std::string describe(const Pose6& p) {
    char buf[160];
    std::snprintf(buf, sizeof buf, "(%.3f, %.3f, %.3f | %.3f, %.3f, %.3f)", p.x, p.y, p.z, p.a, p.b,
                  p.c);
    return buf;
}

bool near(const KDL::Frame& a, const KDL::Frame& b, double positionTolerance,
          double angleTolerance) {
    if ((a.p - b.p).Norm() > positionTolerance) return false;
    KDL::Vector axis;
    const double angle = (a.M.Inverse() * b.M).GetRotAngle(axis);
    return std::abs(angle) <= angleTolerance;
}

bool isFinite(const KDL::Frame& frame) {
    for (int i = 0; i < 3; ++i) {
        if (!std::isfinite(frame.p(i))) return false;
        for (int j = 0; j < 3; ++j) {
            if (!std::isfinite(frame.M(i, j))) return false;
        }
    }
    return true;
}

}  // namespace skillcell::devices
