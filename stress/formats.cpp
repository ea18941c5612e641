#include "stress/formats.h"

#include <algorithm>
#include <array>
#include <cmath>

namespace wrsfov::stress {

using namespace gpu;

namespace {

constexpr std::array<FormatInfo, 6> kFormats = {{
    {FormatId::Chosen, "chosen", "fp16 colour+w, fp32 w_sum, fp16 z, u16 M (shipping)", true},
    {FormatId::F32, "f32", "study: all fp32, M u32 (unpacked baseline)", false},
    {FormatId::WsumF16, "wsum16", "study: shipping layout with fp16 w_sum", false},
    {FormatId::MU8, "m8", "study: shipping layout with M as u8, saturating", false},
    {FormatId::MU8Wrap, "m8wrap", "study: shipping layout with M as u8, wrapping", false},
    {FormatId::MF16, "mf16", "study: shipping layout with M as fp16", false},
}};

}  // namespace

std::span<const FormatInfo> formats() { return kFormats; }

const FormatInfo& formatInfo(FormatId id) {
    for (const FormatInfo& f : kFormats)
        if (f.id == id) return f;
    return kFormats[0];
}

std::optional<FormatId> parseFormat(std::string_view name) {
    for (const FormatInfo& f : kFormats)
        if (f.name == name) return f.id;
    return std::nullopt;
}

Reservoir roundTrip(FormatId id, const Reservoir& r) {
    if (id == FormatId::F32) return r;
    Reservoir s = wrs_unpack(wrs_pack(r));  // the shipping layout; study variants change one field
    switch (id) {
        case FormatId::WsumF16:
            s.w_sum = wrs_round_f16(r.w_sum);
            break;
        case FormatId::MU8:
            s.M = std::min(r.M, 255u);
            break;
        case FormatId::MU8Wrap:
            s.M = r.M & 0xffu;
            break;
        case FormatId::MF16: {
            // Stored as fp16, read back as the integer it rounds to (fp16 holds every integer to 2048).
            const float m = wrs_round_f16(float(std::min(r.M, WRS_M_MAX)));
            s.M = wrs_finite(m) ? uint32_t(m) : WRS_M_MAX;
            break;
        }
        default:
            break;
    }
    return s;
}

}  // namespace wrsfov::stress
