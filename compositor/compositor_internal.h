// What the compositor's sources share and nobody else needs: the passes' descriptor bindings and shader
// indices, the device-lost message, the frame's timestamps, and the helpers every part records with
// (compositor.cpp: resources; end_frame.cpp: endFrame, stage by stage; passes.cpp: configuration, the
// pass plan and the traffic model; record.cpp: the passes' commands and their times; readback.cpp:
// what the tests and tools read back). Internal to the compositor.
#pragma once

#include <cstdint>
#include <span>
#include <string>

#include "compositor/pass_table.h"
#include "compositor/vk_context.h"
#include "layers/status.h"

namespace wrsfov::detail {

// The bindings of the passes' descriptor set (Compositor::passSetBindings).
enum Binding : uint32_t {
    kFrame = 0,
    kColor = 1,
    kDepth = 2,
    kMotion = 3,
    kPyramidBuf = 4,  // binding 5 (a linear-depth buffer) is gone: passes linearize where they read
    kCandidate = 6,
    kResPrev = 7,
    kResCur = 8,
    kOutput = 9,
    kBirthPrev = 10,
    kBirthCur = 11,
    kSrgbTable = 12,
    kTiles = 13,
    kTileHeld = 14,
    kQuality = 15,
    kReference = 16,
    kDisplay = 17,
    kCompose = 18,
    kWide = 19
};

inline constexpr const char* kDeviceLost =
    "the Vulkan device was lost (VK_ERROR_DEVICE_LOST): this compositor refuses every frame from now on; "
    "create a new vk::Context and Compositor";

enum Shader : int { kPyramid, kFoveate, kWrs, kTaa, kCopy, kRetain, kClassify, kHalfProbe, kShaderCount };

// The module of a pass table's shader (pass_table.h; compose.comp is ComposePass's).
inline int shaderIndex(ShaderId s) {
    switch (s) {
        case ShaderId::Classify:
            return kClassify;
        case ShaderId::Pyramid:
            return kPyramid;
        case ShaderId::Foveate:
            return kFoveate;
        case ShaderId::Wrs:
            return kWrs;
        case ShaderId::Taa:
            return kTaa;
        case ShaderId::Retain:
            return kRetain;
        case ShaderId::Compose:
            break;
    }
    return kShaderCount;
}

// Timestamps: the frame's start, after compose (and classify), pyramid, foveate, wrs/taa/retain; then
// before and after a copy kernel, in a submission of its own (measureCopy).
constexpr uint32_t kFrameStamps = 5;
constexpr uint32_t kTimestamps = kFrameStamps + 2;

// Prefixes an allocation error with what it was for, e.g. "reservoirs: vkAllocateMemory (...) failed: ...".
inline Error named(const char* what, const Error& e) { return Error{e.code, std::string(what) + ": " + e.message}; }

// A pipeline that could not be made, named by what it is and its specialization constants:
// "<what> (constants 1,1,0,...): <the driver's error>".
inline Error pipelineError(const std::string& what, std::span<const uint32_t> constants, const Error& e) {
    std::string list;
    for (uint32_t c : constants) list += (list.empty() ? "" : ",") + std::to_string(c);
    return Error{e.code, what + " (constants " + list + "): " + e.message};
}

inline uint32_t groups(uint32_t n, uint32_t size) { return (n + size - 1) / size; }

inline void computeBarrier(VkCommandBuffer cb) {
    vk::memoryBarrier(cb, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_ACCESS_SHADER_WRITE_BIT,
                      VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT);
}

// computeBarrier, and the tile lists' dispatch arguments readable by indirect dispatches.
inline void listsBarrier(VkCommandBuffer cb) {
    vk::memoryBarrier(cb, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_ACCESS_SHADER_WRITE_BIT,
                      VK_PIPELINE_STAGE_DRAW_INDIRECT_BIT | VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT,
                      VK_ACCESS_INDIRECT_COMMAND_READ_BIT | VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT);
}

}  // namespace wrsfov::detail
