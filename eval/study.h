// The moving-content study across cells and seeds (wrsfov-bench --study, tools/run-study.sh,
// docs/metrics.md "The moving-content study"): the rows of many `--saving` runs (one a cell, seed and
// configuration) grouped into cells (scene, head path, split), each method's JOD and temporal
// instability paired across seeds at equal pixels, 95 % intervals of the paired differences, the
// pixels each method needs to reach the cell's target, and the goals judged on the test cells.
#pragma once

#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include "eval/saving.h"

namespace wrsfov::eval {

/// The two-sided 95 % quantile of Student's t with `df` degrees of freedom (df >= 1; exact to the
/// third decimal from a table to df 30, the normal's 1.960 beyond it).
double tQuantile975(int df);

/// A mean difference with its 95 % interval: mean ± t(0.975, n-1) s / sqrt(n) over n paired
/// differences (NaN bounds for n < 2).
struct PairedInterval {
    int n = 0;
    double mean = std::numeric_limits<double>::quiet_NaN();
    double lo = std::numeric_limits<double>::quiet_NaN(), hi = std::numeric_limits<double>::quiet_NaN();
    /// "beats" where the interval lies above zero, "loses" where below, "tie" where it holds zero,
    /// "n/a" with fewer than two pairs.
    const char* verdict() const;
};
PairedInterval pairedInterval(const std::vector<double>& differences);

/// A study's cell: scene, head path and split; the seeds it ran.
struct StudyCell {
    SceneKind scene = SceneKind::Atrium;
    std::string headPath, split;
    double headDegPerS = 0;
    std::vector<uint32_t> seeds;
    /// The target: `fov` on unjittered quad views at 0.4 of the density with a 30° inset, its JOD averaged
    /// over the seeds (NaN where the cell has no such row), and the full-resolution pixels a frame.
    double targetJod = std::numeric_limits<double>::quiet_NaN();
    double fullPixels = 0;
    /// The share of full resolution's pixels at which wrs, taau and the oracle reach the target (their
    /// jittered configurations' seed-mean JOD, linear between them; FoveaWorth's bounds).
    SavingReach wrsReach, taauReach, oracleReach;
};

/// One configuration of a cell (jittered quad views at a density and inset) and one comparison there:
/// method `a` against `b`, paired by seed.
struct StudyComparison {
    std::size_t cell = 0;  ///< index into StudyResult::cells
    float wideScale = 0, insetDeg = 0;
    uint32_t jitterPhases = 0;
    double pixelShare = 0;  ///< of full resolution's pixels
    Method a = Method::Wrs, b = Method::Taau;
    double jodA = std::numeric_limits<double>::quiet_NaN(), jodB = std::numeric_limits<double>::quiet_NaN();
    PairedInterval jod;  ///< JOD of a minus b
    /// Temporal instability: seed means, and a's over b's less one (positive: a flickers more).
    double instabilityA = std::numeric_limits<double>::quiet_NaN(), instabilityB = std::numeric_limits<double>::quiet_NaN();
    double instabilityExcess() const { return instabilityA / instabilityB - 1.0; }
};

struct StudyResult {
    std::vector<StudyCell> cells;
    std::vector<StudyComparison> comparisons;  ///< wrs against taau, fov and taau-simple where present
};

/// Groups rows (readSavingCsv of every run) into cells and comparisons. An error where the rows hold no
/// jittered quad views with wrs, where a cell's seeds disagree on a configuration's pixels, or where one
/// (cell, configuration, method, seed) appears twice.
Result<StudyResult> summarizeStudy(const std::vector<SavingRow>& rows);

/// Writes study.md (the goals met or not with their figures, per cell and split: target, reach, the
/// paired differences), study.csv (one comparison a row) and study.png (wrs − taau and wrs − fov with
/// their intervals, per test configuration) into `dir`; `summary` gets the goals' paragraph.
Status writeStudyReport(const StudyResult& study, const std::string& dir, std::string* summary = nullptr);

}  // namespace wrsfov::eval
