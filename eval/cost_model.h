// A static cost model of the compositor's passes on GPUs this machine does not have (docs/speed.md
// "Cost model"): every pipeline variant a cell dispatches is compiled on a Vulkan device (by default
// RADV's null device for an AMD generation) with VK_PIPELINE_CREATE_CAPTURE_STATISTICS_BIT_KHR, and
// the compiler's statistics (VK_KHR_pipeline_executable_properties), the bytes of each pass
// (traffic()), its dispatch shape and the tile classes the cell's gaze produced combine into a
// roofline estimate per pass and tile class for a table of GPUs from public figures.
#pragma once

#include <vulkan/vulkan.h>

#include <array>
#include <cstdint>
#include <map>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "compositor/compositor.h"
#include "compositor/pass_table.h"
#include "layers/status.h"

namespace wrsfov::eval {

/// The compositor's compute shaders (compositor/pass_table.h), as embedded at build time
/// (shaders/CMakeLists.txt). Compose: the pass for frames submitted foveated (compose.comp, a layout of
/// its own: ComposePass).
using wrsfov::ShaderId;
/// The embedded SPIR-V of a shader.
std::span<const uint32_t> spirv(ShaderId s);

/// PipelineVariant::tileClass of a dispatch over the whole image (not one tile class), and of the compose
/// pass's dispatches over the inset's groups and the others (their PipelineVariant::cover of it).
inline constexpr int kWholeImage = -1;
inline constexpr int kInsetGroups = -2;
inline constexpr int kOutsideInset = -3;
/// "whole", "inset", "outside", or the tile list's name ("any", "fovea", "mid", "far", "skip").
std::string tileClassName(int tileClass);

/// One pipeline a frame dispatches and how: the unit of the cost model.
struct PipelineVariant {
    std::string pass;  ///< traffic()'s name of the pass ("classify", which traffic() leaves out, has none)
    ShaderId shader = ShaderId::Foveate;
    SpecConstants constants{};  ///< specialisation constants 0..9, as Compositor::pipeline binds them
    int tileClass = kWholeImage;          ///< gpu::WRS_TILE_*: the indirect dispatch of one class's tiles
    /// kWholeImage: workgroups of all the pass's dispatches of one frame (both eyes). A tile class: 0
    /// (one group per tile of the class, from the cell's tile shares).
    uint64_t groups = 0;
    uint32_t invocationsPerGroup = 64;  ///< WRS_GROUP_X x WRS_GROUP_Y
    /// Bytes read and written per pixel covered (traffic(); classify: its tile-list entry per tile).
    double bytesPerPx = 0;
    /// Consecutive dispatches of one phase are recorded with no barrier between them, so a GPU runs them
    /// together and one wave's latency bounds the phase, not each dispatch. kOwnPhase: barriers on both sides.
    int phase = -1;
    /// A dispatch over part of the image that is not a tile list (the compose pass's inset groups and the
    /// groups outside them): the share of the image it covers; 1 for a whole-image dispatch.
    double cover = 1.0;
};
inline constexpr int kOwnPhase = -1;

/// The pipelines Compositor::endFrame dispatches for `config` on views like `in` (depth and motion
/// where `in` has them, `eyes` views, no stale tracking), in the order they run: the frame's pass table
/// (framePasses, compositor/pass_table.h), which endFrame records and traffic() counts, one variant per
/// dispatch, with its workgroups and the phase its barriers put it in.
std::vector<PipelineVariant> pipelineVariants(const CompositorConfig& config, const TrafficInputs& in,
                                              uint32_t eyes = 2);

/// A pipeline to compile: shader and specialisation constants. Text form "retain:1,1,1,0,0,2".
struct VariantKey {
    ShaderId shader = ShaderId::Foveate;
    SpecConstants constants{};
    auto operator<=>(const VariantKey&) const = default;
};
std::string toString(const VariantKey& k);
std::optional<VariantKey> parseVariantKey(std::string_view text);

/// What the compiler says about one pipeline's executable (ACO's and RADV's statistics).
struct ExecutableStats {
    double instructions = 0, vgprs = 0, sgprs = 0;
    double wavesPerSimd = 0;   ///< "Subgroups per SIMD": occupancy the registers allow
    double latency = 0;        ///< cycles of one wave alone
    double invThroughput = 0;  ///< cycles per wave64 on one SIMD with the other waves hiding latency
    double spilledVgprs = 0, spilledSgprs = 0;
    uint32_t subgroupSize = 0;  ///< VkPipelineExecutablePropertiesKHR::subgroupSize (wave32 or wave64)
};
/// Reads the statistics by name ("Instructions", "VGPRs", "SGPRs", "Subgroups per SIMD", "Latency",
/// "Inverse Throughput", "Spilled VGPRs", "Spilled SGPRs"). A driver that lacks one of the first six
/// (another compiler, or no statistics at all) is an error naming what is missing.
Result<ExecutableStats> parseStatistics(std::span<const VkPipelineExecutableStatisticKHR> stats, uint32_t subgroupSize);

/// A GPU of the model's table: public figures and where each comes from.
struct GpuFigures {
    std::string name;     ///< the table's key, the statistics target of the RADV null device ("gfx1100")
    std::string product;  ///< what it is sold as
    std::string match;    ///< a real device whose name contains this uses these figures ("" = none)
    uint32_t computeUnits = 0;
    uint32_t simds = 0;  ///< SIMD32 units (2 per RDNA compute unit)
    double clockMHz = 0;
    double bandwidthGBs = 0;
    uint32_t eyeWidth = 0, eyeHeight = 0;  ///< the HMD cell reported for it, per eye
    std::string source;
};
/// gfx1100 (Radeon RX 7900 XTX) and vangogh (Steam Deck), with sources.
std::span<const GpuFigures> gpuTable();
const GpuFigures* findGpu(std::string_view name);

/// Error codes of the statistics collection: the device is missing (a skip with a message, not a failure).
/// Crashed: the statistics process died of a signal after it had offered a device (a driver's crash
/// while compiling; collectStatistics has then tried twice).
enum class CostError : int { Unavailable = 2, Failed = 3, Crashed = 4 };

/// Statistics target: "gfx1100", "vangogh" (RADV's null device for that family) or "device:NAME" (a
/// real device whose name contains NAME, with the environment as it is).
struct StatsTarget {
    std::string family;      ///< RADV_FORCE_FAMILY, or "" for a real device
    std::string deviceName;  ///< real device: part of its name
    std::string label() const { return family.empty() ? "device:" + deviceName : family; }
};
Result<StatsTarget> parseStatsTarget(std::string_view text);

/// Runs `exe --cost-model-child TARGET KEY...` (the bench re-executed) with the target's environment
/// and returns its statistics per key. A separate process per target: the loader and RADV read
/// VK_ICD_FILENAMES and RADV_FORCE_FAMILY when they start, this process's environment and its own
/// Vulkan instance stay untouched, and a driver that crashes on a null device loses that target only.
/// CostError::Unavailable (with the reason) where the null device, the extension or its statistics
/// are missing. A child that dies of a signal after offering a device is run once more (one cost-model
/// run in eleven lost the Steam Deck's statistics so to RADV's null device, docs/speed.md); a second
/// death is CostError::Crashed.
Result<std::map<VariantKey, ExecutableStats>> collectStatistics(const std::string& exe, const StatsTarget& target,
                                                                const std::vector<VariantKey>& keys);
/// The child's side: compiles `keys` on the device the environment gives (RADV's null device, or the
/// device whose name contains `deviceName`) and prints their statistics; the exit code is 0, 2 for an
/// unavailable device (a line "skip: REASON") or 1. Honours WRSFOV_VALIDATION (any message fails).
int statisticsChildMain(std::string_view target, const std::vector<std::string>& keys);

/// The tile lists of a cell: the share of all tiles (both eyes, counted frames) on each list
/// (gpu::WRS_TILE_*: the four classes and, with sparse retention, the skipped far tiles).
using TileShares = std::array<double, gpu::WRS_TILE_LISTS>;

/// One method at one size on one GPU.
struct CostCell {
    const GpuFigures* gpu = nullptr;
    uint32_t width = 0, height = 0;  ///< per eye
    uint32_t eyes = 2;
    Method method = Method::Fov;
    std::vector<PipelineVariant> variants;
    TileShares shares{};
};
/// A row of cost_model.csv: one variant, or the total of a cell (pass "total").
struct CostRow {
    std::string gpu, size, method, pass, cls;
    bool total = false;
    ExecutableStats stats;
    double groups = 0, cyclesPerPx = 0, bytesPerPx = 0, share = 0;
    double aluUs = 0, memUs = 0, predictedUs = 0;
};
/// The rows of a cell (its variants in dispatch order, then the total). `stats` holds every variant's
/// key. alu_us = waves64 x inv_throughput / SIMDs / clock, and a phase (PipelineVariant::phase) lasts
/// at least its longest wave's latency: where the phase's throughput cycles fall short of it, the
/// difference is added to the row of that wave (a dispatch alone: max(throughput, latency) / clock);
/// mem_us = bytes / bandwidth; predicted = max of the two. The total sums them.
std::vector<CostRow> costRows(const CostCell& cell, const std::map<VariantKey, ExecutableStats>& stats);

/// The columns of cost_model.csv, in order.
std::string_view costCsvHeader();
/// Writes cost_model.csv and cost_model.md (assumptions, GPU figures with sources, per-pass tables and
/// verdicts) into `dir`; `skipped` lists targets without statistics and why.
Status writeCostModel(const std::vector<CostRow>& rows, const std::vector<std::string>& skipped,
                      const std::string& cellDescription, const std::string& dir);
/// The totals table of cost_model.md (for scaling.md and the report's index).
std::string costTotalsMarkdown(const std::vector<CostRow>& rows);

}  // namespace wrsfov::eval
