// Long CPU runs of the reservoir update over adversarial streams (stress/streams.h), for every
// storage format of the precision study (stress/formats.h), with the statistics the report prints.
//
// Each stream has `pixels` independent pixels (x = pixel, y = stream index, eye 0 in wrs_rand), and
// every format runs the same frames with the same random numbers in lockstep, so that a format's
// selections can be compared with the fp32 baseline frame by frame.
#pragma once

#include <cstdint>
#include <functional>
#include <map>
#include <string>
#include <vector>

#include "layers/status.h"
#include "stress/formats.h"
#include "stress/model.h"
#include "stress/streams.h"

namespace wrsfov::stress {

struct Progress {
    const char* phase = "";
    double fraction = 0;  ///< 0..1
    double elapsed_s = 0;
    double framesPerSecond = 0;  ///< stream frames (all pixels and formats of one stream) per second
};
using ProgressFn = std::function<void(const Progress&)>;

struct CpuOptions {
    uint64_t frames = 1000000;
    uint32_t pixels = 64;  ///< per stream
    uint32_t seed = 1;
    std::vector<std::string> streams;  ///< empty: all
    std::vector<FormatId> formats;     ///< empty: all (the first one is the shipping layout)
    unsigned threads = 0;              ///< 0: one per core
    uint32_t seriesPoints = 200;       ///< w_sum samples per stream and format for the plots
    ProgressFn progress;               ///< called about every 5 % (from the calling thread)
};

/// w_sum over the pixels of a stream at sample frames.
struct Series {
    std::vector<uint64_t> frames;
    std::vector<double> mean, min, max;
};

/// One stream in one format.
struct FormatStats {
    FormatId format = FormatId::Chosen;
    // w_sum as stored, over every pixel and frame.
    double wsumMin = INFINITY, wsumMax = 0, wsumFinalMean = 0;
    double boundRatioMax = 0;     ///< max of w_sum / bound(n), bound of docs/stability.md (streams with w <= 1)
    uint64_t wsumFrozenFrom = 0;  ///< pixel 0: w_sum unchanged from this frame to the end (0: still changing)
    // M.
    uint32_t mMax = 0;
    uint64_t mAtCap = 0;         ///< pixel-frames with M = 65535 stored
    uint64_t firstCapFrame = 0;  ///< first frame any pixel stored M = 65535 (0: never)
    uint64_t mWraps = 0;         ///< history continued but the loaded M did not grow or hold at its cap
    // History.
    uint64_t decisions = 0;  ///< combines with history
    uint64_t replaced = 0;   ///< ... that took the candidate
    uint64_t fresh = 0;      ///< frames that started a reservoir (no valid history or a flush)
    uint64_t flushes = 0;    ///< depth test dropped a valid history
    uint64_t lost = 0;       ///< the history stored last frame came back invalid (format)
    // Invariants.
    uint64_t nonFiniteStored = 0;     ///< pixel-frames with a non-finite field or w_sum <= 0 as stored
    uint64_t nonFiniteOutput = 0;     ///< pixel-frames whose output colour was not finite
    uint64_t zeroWeightSelected = 0;  ///< a weight-0 candidate replaced existing history
    uint64_t identityViolations = 0;  ///< kept sample's stored words differ from its candidate's
    uint64_t divergentFrames = 0;     ///< pixel-frames whose kept sample differs from the f32 baseline's
    // Selection statistics.
    ZTest conditional;           ///< replacements vs eq. 7 / Alg. 2 given the loaded history
    ZTest conditionalAfterCap;   ///< the same, frames after M first reached its cap
    ZTest unconditional;         ///< streams with a model: new-candidate frames vs the exact model
    ChiSquare chiMid, chiFinal;  ///< streams with a model: kept sample's (class, age) at N/2 and N
    Series series;
};

struct StreamResult {
    Stream stream;
    std::vector<FormatStats> formats;  ///< in CpuOptions::formats order
    std::vector<double> modelWsum;     ///< exact model's w_sum at the series frames (streams with a model)
};

struct CpuResult {
    CpuOptions options;
    std::vector<StreamResult> streams;
    double wall_s = 0;
};

/// The w_sum bound of a stream whose weights are at most 1: sqrt(1 + 2.25 (n − 1)) with the bias,
/// n without (docs/stability.md "Bound").
double wsumBound(uint64_t frame, bool bernoulli);

/// Runs the streams; fails on unknown stream names or bad options.
Result<CpuResult> runCpu(const CpuOptions& options);

/// Safe horizon: a pixel that sees the same weight w every frame (grey, no flush) until its w_sum
/// stops growing because the increment is below half an ulp of the stored w_sum.
struct Horizon {
    FormatId format = FormatId::Chosen;
    float weight = 1;
    bool bernoulli = true;
    uint64_t frame = 0;        ///< first frame whose stored w_sum equals the previous frame's (0: not within maxFrames)
    double wsum = 0;           ///< stored w_sum from then on
    double exactWsum = 0;      ///< exact model's w_sum at that frame
    bool lost = false;         ///< the stored reservoir became invalid (w_sum rounds to 0): history dropped every frame
    uint64_t drift1 = 0;       ///< first frame the stored w_sum is more than 1 % off the exact model's (0: never)
    double maxBoundRatio = 0;  ///< max over the frames of w_sum / (w bound(n)), wsumBound's exact-math bound
};
Horizon horizon(FormatId format, float weight, bool bernoulli, uint64_t maxFrames);

}  // namespace wrsfov::stress
