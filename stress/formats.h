// Reservoir storage formats for the precision study (docs/stability.md).
//
// The shipping layout is wrs_pack/wrs_unpack in shaders/wrs_reservoir.h (docs/stability.md "The layout of `wrs-paper`").
// Every other format here is a STUDY VARIANT: it exists only in the stress code, to show where a
// cheaper or a wider layout would behave differently. A format is simulated by what a reservoir
// looks like after it has been stored and loaded again (the combine itself always runs in fp32).
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <string_view>

#include "shaders/wrs_common.h"

namespace wrsfov::stress {

enum class FormatId : uint8_t {
    Chosen,   ///< shipping layout: fp16 colour + w, fp32 w_sum, fp16 z, u16 M (wrs_pack / wrs_unpack)
    F32,      ///< study: everything fp32, M u32 (the unpacked Reservoir struct, no rounding at all)
    WsumF16,  ///< study: the shipping layout with w_sum in fp16
    MU8,      ///< study: the shipping layout with M in 8 bits, saturating at 255
    MU8Wrap,  ///< study: M in 8 bits without saturation (what the cap prevents: 256 wraps to 0)
    MF16,     ///< study: M stored as an fp16 float
};

struct FormatInfo {
    FormatId id;
    std::string_view name;  ///< command-line name
    std::string_view description;
    bool shipping;
};

/// All formats, the shipping one first.
std::span<const FormatInfo> formats();
const FormatInfo& formatInfo(FormatId id);
std::optional<FormatId> parseFormat(std::string_view name);

/// The reservoir as the next frame loads it after storing `r` in format `id`.
gpu::Reservoir roundTrip(FormatId id, const gpu::Reservoir& r);

}  // namespace wrsfov::stress
