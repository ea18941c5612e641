#include "eval/study.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <map>
#include <set>
#include <sstream>
#include <tuple>

#include <opencv2/imgcodecs.hpp>

#include "eval/chart.h"

namespace wrsfov::eval {

namespace {

Error studyError(const std::string& m) { return Error{1, "study: " + m}; }

std::string fmt(const char* f, double v) { return savingNumber(f, v); }

// A cell's identity and a configuration's (jittered quad views), as map keys.
using CellKey = std::tuple<SceneKind, std::string, std::string>;
using ConfigKey = std::tuple<float, float, uint32_t>;

bool isTarget(const SavingRow& r) {
    return r.input == SavingInput::Quad && r.method == Method::Fov && r.jitterPhases <= 1 &&
           std::abs(r.wideScale - 0.4f) < 1e-4f && std::abs(r.insetDeg - 30.0f) < 1e-3f;
}

double mean(const std::vector<double>& v) {
    double s = 0;
    for (double x : v) s += x;
    return v.empty() ? std::numeric_limits<double>::quiet_NaN() : s / double(v.size());
}

// The share of the pixels as a percentage, with its bound ("≤ 4.6 %", "> 9.5 %").
std::string reachText(const SavingReach& r) {
    switch (r.bound) {
        case FoveaWorth::Bound::Exact: return fmt("%.1f %%", 100 * r.pixels);
        case FoveaWorth::Bound::AtMost: return "≤ " + fmt("%.1f %%", 100 * r.pixels);
        case FoveaWorth::Bound::MoreThan: return "> " + fmt("%.1f %%", 100 * r.pixels);
        default: return "n/a";
    }
}
// Where a reach within `limit` is certain (an exact or at-most figure at or under it).
bool reachWithin(const SavingReach& r, double limit) {
    return (r.bound == FoveaWorth::Bound::Exact || r.bound == FoveaWorth::Bound::AtMost) && r.pixels <= limit;
}

}  // namespace

double tQuantile975(int df) {
    static constexpr double kTable[30] = {12.706, 4.303, 3.182, 2.776, 2.571, 2.447, 2.365, 2.306, 2.262, 2.228,
                                          2.201,  2.179, 2.160, 2.145, 2.131, 2.120, 2.110, 2.101, 2.093, 2.086,
                                          2.080,  2.074, 2.069, 2.064, 2.060, 2.056, 2.052, 2.048, 2.045, 2.042};
    if (df < 1) return std::numeric_limits<double>::quiet_NaN();
    return df <= 30 ? kTable[df - 1] : 1.960;
}

const char* PairedInterval::verdict() const {
    if (n < 2 || !std::isfinite(lo) || !std::isfinite(hi)) return "n/a";
    return lo > 0 ? "beats" : hi < 0 ? "loses" : "tie";
}

PairedInterval pairedInterval(const std::vector<double>& d) {
    PairedInterval p;
    p.n = int(d.size());
    if (d.empty()) return p;
    p.mean = mean(d);
    if (p.n < 2) return p;
    double ss = 0;
    for (double x : d) ss += (x - p.mean) * (x - p.mean);
    const double half = tQuantile975(p.n - 1) * std::sqrt(ss / double(p.n - 1)) / std::sqrt(double(p.n));
    p.lo = p.mean - half;
    p.hi = p.mean + half;
    return p;
}

Result<StudyResult> summarizeStudy(const std::vector<SavingRow>& rows) {
    StudyResult out;
    std::map<CellKey, std::size_t> cellIndex;
    // Per cell: the full resolution's pixels, the target's JOD per seed, and per configuration and method
    // the JOD, instability and pixels per seed.
    struct PerSeed {
        double jod, instability, pixels;
    };
    struct CellData {
        std::map<uint32_t, double> target;
        std::map<ConfigKey, std::map<Method, std::map<uint32_t, PerSeed>>> configs;
        std::set<uint32_t> seeds;
    };
    std::vector<CellData> data;
    for (const SavingRow& r : rows) {
        const CellKey key{r.scene, r.headPath, r.split};
        auto [it, added] = cellIndex.emplace(key, out.cells.size());
        if (added) {
            StudyCell c;
            c.scene = r.scene;
            c.headPath = r.headPath;
            c.split = r.split;
            c.headDegPerS = r.headDegPerS;
            out.cells.push_back(c);
            data.emplace_back();
        }
        StudyCell& cell = out.cells[it->second];
        CellData& d = data[it->second];
        d.seeds.insert(r.seed);
        if (r.input == SavingInput::Full) {
            cell.fullPixels = r.pixelsRendered;
        } else if (isTarget(r)) {
            if (!d.target.emplace(r.seed, r.jod).second)
                return studyError("two target rows for " + std::string(toString(r.scene)) + " " + r.headPath + " seed " +
                                  std::to_string(r.seed));
        } else if (r.input == SavingInput::Quad && r.jitterPhases > 1) {
            auto& perSeed = d.configs[ConfigKey{r.wideScale, r.insetDeg, r.jitterPhases}][r.method];
            if (!perSeed.emplace(r.seed, PerSeed{r.jod, r.temporalInstability, r.pixelsRendered}).second)
                return studyError("two rows of " + std::string(toString(r.method)) + " at " + fmt("%.2f", r.wideScale) +
                                  " / " + fmt("%.0f°", r.insetDeg) + " for " + std::string(toString(r.scene)) + " " +
                                  r.headPath + " seed " + std::to_string(r.seed));
        }
    }
    bool anyWrs = false;
    for (std::size_t ci = 0; ci < out.cells.size(); ++ci) {
        StudyCell& cell = out.cells[ci];
        CellData& d = data[ci];
        cell.seeds.assign(d.seeds.begin(), d.seeds.end());
        std::vector<double> target;
        for (auto& [seed, jod] : d.target) target.push_back(jod);
        cell.targetJod = mean(target);
        // Each method's seed-mean JOD per configuration: its front against the pixels, and where it reaches
        // the target.
        std::map<Method, std::vector<SavingRow>> curves;
        for (auto& [config, methods] : d.configs) {
            double pixels = -1;
            for (auto& [m, perSeed] : methods) {
                std::vector<double> jods;
                for (auto& [seed, v] : perSeed) {
                    if (pixels >= 0 && std::abs(v.pixels - pixels) > 0.5)
                        return studyError(std::string(toString(cell.scene)) + " " + cell.headPath + ": seeds differ in the "
                                          "pixels of one configuration (" + fmt("%.0f", pixels) + " against " +
                                          fmt("%.0f", v.pixels) + ")");
                    pixels = v.pixels;
                    jods.push_back(v.jod);
                }
                SavingRow point;
                point.pixelsRendered = cell.fullPixels > 0 ? pixels / cell.fullPixels : pixels;
                point.jod = mean(jods);
                point.renderMs = 0;
                curves[m].push_back(point);
                anyWrs = anyWrs || m == Method::Wrs;
            }
            // The comparisons at this configuration, paired by the seeds both methods ran.
            auto wrs = methods.find(Method::Wrs);
            if (wrs == methods.end()) continue;
            for (Method other : {Method::Taau, Method::Fov, Method::TaauSimple}) {
                auto b = methods.find(other);
                if (b == methods.end()) continue;
                StudyComparison c;
                c.cell = ci;
                std::tie(c.wideScale, c.insetDeg, c.jitterPhases) = config;
                c.pixelShare = cell.fullPixels > 0 ? pixels / cell.fullPixels : std::numeric_limits<double>::quiet_NaN();
                c.a = Method::Wrs;
                c.b = other;
                std::vector<double> diff, ja, jb, ia, ib;
                for (auto& [seed, va] : wrs->second) {
                    auto vb = b->second.find(seed);
                    if (vb == b->second.end()) continue;
                    diff.push_back(va.jod - vb->second.jod);
                    ja.push_back(va.jod);
                    jb.push_back(vb->second.jod);
                    ia.push_back(va.instability);
                    ib.push_back(vb->second.instability);
                }
                c.jod = pairedInterval(diff);
                c.jodA = mean(ja);
                c.jodB = mean(jb);
                c.instabilityA = mean(ia);
                c.instabilityB = mean(ib);
                out.comparisons.push_back(c);
            }
        }
        auto reach = [&](Method m) {
            auto it = curves.find(m);
            return it == curves.end() ? SavingReach{} : savingReach(savingFront(it->second), cell.targetJod);
        };
        cell.wrsReach = reach(Method::Wrs);
        cell.taauReach = reach(Method::Taau);
        cell.oracleReach = reach(Method::Oracle);
    }
    if (!anyWrs) return studyError("no jittered quad views composed with wrs among the rows");
    return out;
}

Status writeStudyReport(const StudyResult& study, const std::string& dir, std::string* summary) {
    auto cellName = [&](const StudyCell& c) { return std::string(toString(c.scene)) + " " + c.headPath; };
    // ---- the goals, on the test cells
    std::vector<double> reaches;
    int testCells = 0, within10 = 0;
    std::string misses;
    for (const StudyCell& c : study.cells) {
        if (c.split != "test") continue;
        ++testCells;
        if (reachWithin(c.wrsReach, 0.10)) {
            ++within10;
        } else {
            misses += (misses.empty() ? "" : "; ") + cellName(c) + " " + reachText(c.wrsReach) + " (the oracle " +
                      reachText(c.oracleReach) + ")";
        }
        // Unknown or beyond the study's points: at least that far (a median over bounds).
        reaches.push_back(c.wrsReach.bound == FoveaWorth::Bound::MoreThan || !std::isfinite(c.wrsReach.pixels)
                              ? std::numeric_limits<double>::infinity()
                              : c.wrsReach.pixels);
    }
    std::sort(reaches.begin(), reaches.end());
    const double medianReach = reaches.empty() ? std::numeric_limits<double>::quiet_NaN()
                               : reaches.size() % 2 ? reaches[reaches.size() / 2]
                                                    : 0.5 * (reaches[reaches.size() / 2 - 1] + reaches[reaches.size() / 2]);
    int vsTaau = 0, beatsTaau = 0, vsFov = 0, belowFov = 0, flickerOk = 0;
    double worstExcess = -1e300;
    for (const StudyComparison& c : study.comparisons) {
        if (study.cells[c.cell].split != "test") continue;
        if (c.b == Method::Taau) {
            ++vsTaau;
            beatsTaau += std::string(c.jod.verdict()) == "beats";
            flickerOk += c.instabilityExcess() <= 0.03;
            worstExcess = std::max(worstExcess, c.instabilityExcess());
        }
        if (c.b == Method::Fov) {
            ++vsFov;
            belowFov += std::string(c.jod.verdict()) == "loses";
        }
    }
    auto met = [](bool ok) { return ok ? "**met**" : "**not met**"; };
    std::ostringstream goals;
    goals << "- `wrs` reaches each test cell's target (`fov`, unjittered 0.4 / 30° quad views) with at most 10 % of "
             "full resolution's pixels: "
          << met(testCells > 0 && within10 == testCells) << ", " << within10 << " of " << testCells << " cells"
          << (misses.empty() ? "" : "; short: " + misses) << ".\n";
    goals << "- on the median test cell with at most 6.7 %: " << met(std::isfinite(medianReach) && medianReach <= 0.067)
          << ", the median " << (std::isinf(medianReach) ? std::string("beyond the study's points") : fmt("%.1f %%", 100 * medianReach))
          << ".\n";
    goals << "- at equal pixels `wrs` above `taau` with the 95 % interval above zero on at least 80 % of the test cells "
             "and configurations: "
          << met(vsTaau > 0 && beatsTaau * 5 >= vsTaau * 4) << ", " << beatsTaau << " of " << vsTaau << ".\n";
    goals << "- never below `fov` on the same views: " << met(vsFov > 0 && belowFov == 0) << ", " << belowFov << " of "
          << vsFov << " below with the interval under zero.\n";
    goals << "- temporal instability at most 3 % above `taau`'s: " << met(vsTaau > 0 && flickerOk == vsTaau) << ", "
          << flickerOk << " of " << vsTaau << " within it"
          << (vsTaau > 0 ? ", the worst " + fmt("%+.1f %%", 100 * worstExcess) : std::string()) << ".\n";
    if (summary) *summary = goals.str();

    // ---- study.md
    std::ofstream md(dir + "/study.md");
    if (!md) return studyError("cannot write " + dir + "/study.md");
    std::set<uint32_t> allSeeds;
    for (const StudyCell& c : study.cells) allSeeds.insert(c.seeds.begin(), c.seeds.end());
    md << "# The moving-content study\n\n"
       << study.cells.size() << " cells (scene and head path; `train`: where the methods' parameters were chosen, `test`: "
       << "where the figures are reported), " << allSeeds.size() << " seeds (the gaze, the jitter's start, the compositor's "
       << "random choices). Each comparison pairs two methods' JOD on the same seed's frames and views; the interval "
       << "is the paired differences' 95 % t interval, and a method \"beats\" another only where it excludes zero. "
       << "Command: `bash tools/run-study.sh` (docs/metrics.md, \"The moving-content study\").\n\n"
       << "![wrs against taau and fov per test configuration](study.png)\n\n"
       << "## Goals, on the test cells\n\n"
       << goals.str() << "\n"
       << "## Cells\n\n"
       << "The target: `fov` on unjittered quad views at 0.4 of the density with a 30° inset; the reach: the share of "
          "full resolution's pixels at which a method's jittered views reach the target's JOD (seed means, linear "
          "between configurations; ≤: its cheapest configuration already does, >: none does).\n\n"
       << "| split | scene | head path | head °/s | seeds | target JOD | wrs reaches | taau reaches | oracle reaches |\n"
       << "|---|---|---|---|---|---|---|---|---|\n";
    for (const char* split : {"test", "train"})
        for (const StudyCell& c : study.cells) {
            if (c.split != split) continue;
            md << "| " << c.split << " | " << toString(c.scene) << " | " << c.headPath << " | " << fmt("%.0f", c.headDegPerS)
               << " | " << c.seeds.size() << " | " << fmt("%.2f", c.targetJod) << " | " << reachText(c.wrsReach) << " | "
               << reachText(c.taauReach) << " | " << reachText(c.oracleReach) << " |\n";
        }
    md << "\n## At equal pixels\n\n"
       << "`wrs` against each other method on the same jittered views (mean over the seeds both ran; a − b with its "
          "95 % interval); temporal instability as seed means and a's excess over b's.\n\n"
       << "| split | cell | wide / inset | pixels | a | b | n | JOD a | JOD b | a − b [95 %] | verdict | instability a | "
          "instability b | excess |\n"
       << "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n";
    for (const char* split : {"test", "train"})
        for (const StudyComparison& c : study.comparisons) {
            const StudyCell& cell = study.cells[c.cell];
            if (cell.split != split) continue;
            md << "| " << cell.split << " | " << cellName(cell) << " | " << fmt("%.2f", c.wideScale) << " / "
               << fmt("%.0f°", c.insetDeg) << " | " << fmt("%.1f %%", 100 * c.pixelShare) << " | " << toString(c.a) << " | "
               << toString(c.b) << " | " << c.jod.n << " | " << fmt("%.3f", c.jodA) << " | " << fmt("%.3f", c.jodB) << " | "
               << fmt("%+.3f", c.jod.mean) << " [" << fmt("%+.3f", c.jod.lo) << ", " << fmt("%+.3f", c.jod.hi) << "] | "
               << c.jod.verdict() << " | " << fmt("%.4f", c.instabilityA) << " | " << fmt("%.4f", c.instabilityB) << " | "
               << fmt("%+.1f %%", 100 * c.instabilityExcess()) << " |\n";
        }

    // ---- study.csv
    std::ofstream csv(dir + "/study.csv");
    if (!csv) return studyError("cannot write " + dir + "/study.csv");
    csv << "split,scene,head_path,head_deg_per_s,wide_density,inset_deg,jitter,pixel_share,a,b,n,jod_a,jod_b,jod_diff,"
           "jod_diff_lo,jod_diff_hi,verdict,instability_a,instability_b,target_jod,wrs_reach,wrs_reach_bound\n";
    auto bound = [](FoveaWorth::Bound b) {
        return b == FoveaWorth::Bound::Exact ? "exact" : b == FoveaWorth::Bound::AtMost ? "at_most"
                                                     : b == FoveaWorth::Bound::MoreThan ? "more_than" : "unknown";
    };
    for (const StudyComparison& c : study.comparisons) {
        const StudyCell& cell = study.cells[c.cell];
        csv << cell.split << ',' << toString(cell.scene) << ',' << cell.headPath << ',' << cell.headDegPerS << ','
            << c.wideScale << ',' << c.insetDeg << ',' << c.jitterPhases << ',' << c.pixelShare << ',' << toString(c.a)
            << ',' << toString(c.b) << ',' << c.jod.n << ',' << c.jodA << ',' << c.jodB << ',' << c.jod.mean << ','
            << c.jod.lo << ',' << c.jod.hi << ',' << c.jod.verdict() << ',' << c.instabilityA << ',' << c.instabilityB
            << ',' << cell.targetJod << ',' << cell.wrsReach.pixels << ',' << bound(cell.wrsReach.bound) << '\n';
    }

    // ---- study.png: the test configurations in order, wrs − taau and wrs − fov with their intervals.
    std::vector<Series> series;
    Series zero{"0", cv::Scalar(120, 120, 120), {}, {}, true, false};
    for (Method b : {Method::Taau, Method::Fov}) {
        Series s{std::string("wrs - ") + std::string(toString(b)), methodColour(b), {}, {}, false, true};
        std::vector<Series> bars;
        int x = 0;
        for (const StudyComparison& c : study.comparisons) {
            if (study.cells[c.cell].split != "test" || c.b != Method::Taau) continue;
            ++x;
            // The same configuration's comparison with `b`.
            for (const StudyComparison& d : study.comparisons)
                if (d.cell == c.cell && d.b == b && d.wideScale == c.wideScale && d.insetDeg == c.insetDeg &&
                    d.jitterPhases == c.jitterPhases) {
                    const double px = x + (b == Method::Fov ? 0.15 : 0.0);
                    s.points.push_back({px, d.jod.mean});
                    if (b == Method::Taau)
                        s.labels.push_back(cellName(study.cells[c.cell]) + " " + fmt("%.2f", c.wideScale));
                    bars.push_back(Series{"", methodColour(b), {{px, d.jod.lo}, {px, d.jod.hi}}, {}, true, false});
                }
        }
        if (zero.points.empty() && x > 0) zero.points = {{0.5, 0.0}, {x + 0.5, 0.0}};
        series.push_back(s);
        series.insert(series.end(), bars.begin(), bars.end());
    }
    series.push_back(zero);
    const cv::Mat img = chart("wrs - taau, wrs - fov at equal pixels, test cells (95 % intervals)",
                              "test cell and configuration", "JOD difference", series);
    if (!cv::imwrite(dir + "/study.png", img)) return studyError("cannot write " + dir + "/study.png");
    return {};
}

}  // namespace wrsfov::eval
