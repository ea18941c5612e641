// The stress report: checks with a verdict, Markdown tables (stdout and report.md), CSV and PNG
// plots of w_sum over time per stream and format.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "layers/status.h"
#include "stress/cpu_stress.h"
#include "stress/gpu_stress.h"

namespace wrsfov::stress {

/// Selection statistics pass when |z| < kZLimit (two-sided tail 6.8e-6) and the chi-square upper tail
/// exceeds kChiLimit. The seeds are fixed, so a run is deterministic; the limits say how unlikely a
/// failure is for a correct implementation under another seed.
inline constexpr double kZLimit = 4.5;
inline constexpr double kChiLimit = 1e-4;
/// The w_sum check allows the stored w_sum this factor above the exact-math bound (wsumBound): the
/// fp32 rounding of the bias term drifts a constant-weight trajectory by up to ~10 % before it
/// freezes, which takes it up to 6.7 % above w * bound (horizon study); within 10^6 frames no stream
/// exceeds the exact bound.
inline constexpr double kBoundSlack = 1.10;

/// The safe-horizon study: every format's w_sum for constant weights across the pipeline's range.
struct HorizonStudy {
    std::vector<Horizon> runs;
    /// The shipping layout for weights spread over one binade, [0.5, 1): the combine and fp32 storage
    /// are invariant under scaling every weight by a power of two (while w_sum stays within
    /// [WRS_WSUM_MIN, WRS_WSUM_MAX]), so this covers every weight from about 1e-26 to 1.
    std::vector<Horizon> binade;
    /// fp16 colour storage against the change term, over the 256 grey levels of an sRGB8 image:
    /// |ΔL| between a level and its fp16-rounded self, and the w_sum it settles at, 1/sqrt(|ΔL|) for w = 1.
    int greyLevels = 0, greyLevelsExact = 0;  ///< levels, and those whose fp16 rounding gives |ΔL| = 0
    double ceilingMin = 0, ceilingMedian = 0, ceilingMax = 0;
};
/// `quick`: fewer weights.
HorizonStudy runHorizonStudy(bool quick);

struct Check {
    std::string what;
    bool pass = true;
    std::string detail;
};
/// Every check of the run (the shipping layout's invariants and selection statistics, the GPU
/// lockstep): what the tests and the command's exit status use.
std::vector<Check> evaluate(const CpuResult* cpu, const GpuResult* gpu);
/// True when the check is about a stream whose selection statistics must hold in `format`.
bool selectionAsserted(const Stream& stream);

struct ReportInput {
    const CpuResult* cpu = nullptr;
    const GpuResult* gpu = nullptr;
    const HorizonStudy* horizon = nullptr;
    std::vector<Check> checks;
    double wall_s = 0;
    std::string commandLine;
};

/// The whole report as Markdown.
std::string markdownReport(const ReportInput& in);
/// Writes report.md, report.csv (CPU streams x formats), horizon.csv, gpu.csv and wsum_<stream>.png.
Status writeReport(const ReportInput& in, const std::string& dir);

}  // namespace wrsfov::stress
