// The study's reports: results.csv, report.md and its plots (writeReport), and the scaling report.
#include "eval/bench.h"
#include "eval/bench_internal.h"
#include "eval/chart.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <limits>
#include <map>
#include <memory>
#include <span>
#include <sstream>

#include <filesystem>

#include <opencv2/core/utility.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "compositor/host_app.h"
#include "eval/metrics.h"
#include "eval/sequence.h"
#include "gaze/source.h"
#include "scenes/text.h"
#include "shaders/wrs_common.h"

namespace wrsfov::eval {

using namespace detail;

float equalQualityFovea(const std::vector<CellResult>& results, SceneKind scene, FoveationMode mode) {
    double target = std::numeric_limits<double>::quiet_NaN();
    for (const auto& c : results)
        if (c.scene == scene && c.mode == mode && c.method == Method::Fov && c.foveaDeg == 10.0f && !c.worthSweep)
            target = c.nearPsnr;
    if (std::isnan(target)) return 0.0f;
    float best = 0.0f;
    for (const auto& c : results)
        if (c.scene == scene && c.mode == mode && c.method == Method::Wrs && c.foveaDeg < 10.0f && c.nearPsnr >= target &&
            (best == 0.0f || c.foveaDeg < best))
            best = c.foveaDeg;
    return best;
}

namespace {


// Pixel density at the view centre of the atrium scenes for these options.
double centrePixelsPerDegree(const BenchOptions& o) {
    scenes::AtriumOptions ao;
    ao.monitor = o.monitor;
    ao.fovDeg = o.hmdFovDeg;
    const layers::Fov f = scenes::atriumFov(ao, 0);
    return pixelsPerDegreeAtCentre(o.width, glm::vec4(std::tan(f.angleLeft), std::tan(f.angleRight),
                                                      std::tan(f.angleUp), std::tan(f.angleDown)));
}

std::string fmt(double v, int prec = 2) {
    if (std::isinf(v)) return "inf";
    if (std::isnan(v)) return "n/a";
    std::ostringstream s;
    s.setf(std::ios::fixed);
    s.precision(prec);
    s << v;
    return s.str();
}

// Bytes per pass per method (they depend on the method, the mode and the inputs, not the scene
// content), the floor, and the times against both copy kernels.
void writeTrafficSection(std::ostream& md, const std::vector<CellResult>& results) {
    md << "\n## Traffic\n\n"
          "Bytes each pass reads and writes per pixel of one view, from its bindings and formats (shaders/), "
          "every texel of every binding counted once (the memory traffic with caches that hold a bilinear or 3×3 "
          "neighbourhood). The *floor* is what the method cannot avoid: the colour in and the output out, and for "
          "methods with history the 16-byte reservoir read and written and the depth and motion they use. Times "
          "are medians over the same cells as above; *copy* moves the method's bytes, *copy floor* the floor's, "
          "in the same submissions.\n\n"
          "| scene | mode | method | passes (read + write, B/px) | B/px | floor B/px | ×floor | GPU ms | ×copy | "
          "×copy floor |\n|---|---|---|---|---|---|---|---|---|---|\n";
    for (const CellResult& c : results) {
        std::string passes;
        for (const PassTraffic& p : c.traffic.passes)
            passes += (passes.empty() ? "" : ", ") + p.pass + " " + fmt(p.read, 1) + " + " + fmt(p.write, 1);
        md << "| " << toString(c.scene) << " | " << toString(c.mode) << " | " << toString(c.method) << " | " << passes
           << " | " << fmt(c.traffic.perPixel(), 1) << " | " << fmt(c.traffic.floor, 1) << " | "
           << fmt(c.traffic.perPixel() / c.traffic.floor) << " | " << fmt(c.gpu.total, 3) << " | "
           << fmt(c.gpu.total / c.copyMs) << " | " << fmt(c.gpu.total / c.copyFloorMs) << " |\n";
    }
}

std::string bandName(std::size_t b) {
    return std::isinf(kEccBands[b + 1]) ? "≥ " + fmt(kEccBands[b], 0) + "°"
                                   : fmt(kEccBands[b], 0) + "–" + fmt(kEccBands[b + 1], 0) + "°";
}

// Where the error and the oracles' gains lie: MSE per eccentricity band, η per band, and each band's
// share of each oracle's gain over the whole image (band MSE gain × the band's share of pixels).
void writeBandSection(std::ostream& md, const std::vector<CellResult>& results) {
    md << "\n## Error by eccentricity\n\n"
          "MSE (sRGB, ×1000) per band of eccentricity from the gaze, over all counted frames; *px* the band's "
          "share of the pixels; *η* per band against fov and the oracle of the same cell, *η_q* against the "
          "retention oracle (oracle-q), n/a where that oracle removes less than 1 % of fov's MSE in the band; "
          "*gain share*: the band's part of that oracle's whole-image MSE gain over "
          "fov (where a keep-or-replace rule could gain, and how much of it lies where every candidate is "
          "equally blurred).\n";
    auto same = [](const CellResult& a, const CellResult& b) {
        return a.scene == b.scene && a.mode == b.mode && a.foveaDeg == b.foveaDeg;
    };
    for (std::size_t i = 0; i < results.size(); ++i) {
        const CellResult& first = results[i];
        bool seen = false;
        for (std::size_t j = 0; j < i; ++j) seen = seen || same(results[j], first);
        if (seen) continue;
        const CellResult* fov = findCell(results, first.scene, first.mode, first.foveaDeg, Method::Fov);
        const CellResult* oracle = findCell(results, first.scene, first.mode, first.foveaDeg, Method::Oracle);
        const CellResult* oracleQ = findCell(results, first.scene, first.mode, first.foveaDeg, Method::OracleQ);
        md << "\n" << toString(first.scene) << ", " << toString(first.mode) << ", fovea " << fmt(first.foveaDeg, 1)
           << "°\n\n| method |";
        for (std::size_t b = 0; b < first.bandMse.size(); ++b) md << " " << bandName(b) << " |";
        md << "\n|---|";
        for (std::size_t b = 0; b < first.bandMse.size(); ++b) md << "---|";
        md << "\n| px |";
        for (double v : first.bandShare) md << " " << fmt(100 * v, 1) << " % |";
        md << "\n";
        for (const CellResult& c : results) {
            if (!same(c, first)) continue;
            md << "| " << toString(c.method) << " |";
            for (double v : c.bandMse) md << " " << fmt(1000 * v, 2) << " |";
            md << "\n";
        }
        if (!fov) continue;
        for (const CellResult* bound : {oracle, oracleQ}) {
            if (!bound) continue;
            double total = 0.0;
            for (std::size_t b = 0; b < first.bandMse.size(); ++b)
                total += (fov->bandMse[b] - bound->bandMse[b]) * fov->bandShare[b];
            md << "| " << toString(bound->method) << " gain share |";
            for (std::size_t b = 0; b < first.bandMse.size(); ++b)
                md << " "
                   << fmt(total > 0 ? 100 * (fov->bandMse[b] - bound->bandMse[b]) * fov->bandShare[b] / total : 0.0, 0)
                   << " % |";
            md << "\n";
            for (const CellResult& c : results) {
                if (!same(c, first) || c.method == Method::Fov || isOracle(c.method)) continue;
                md << "| " << (bound == oracle ? "η " : "η_q ") << toString(c.method) << " |";
                for (std::size_t b = 0; b < first.bandMse.size(); ++b) {
                    const double g = boundGain(fov->bandMse[b], bound->bandMse[b]);
                    md << " " << (g > 0 ? fmt((fov->bandMse[b] - c.bandMse[b]) / g) : std::string("n/a")) << " |";
                }
                md << "\n";
            }
        }
    }
}

}  // namespace

Status writeReport(const std::vector<CellResult>& results, const BenchOptions& o, const std::string& dir,
                   const std::string& deviceName) {
    std::ofstream csv(dir + "/results.csv");
    if (!csv) return Error{1, "cannot write " + dir + "/results.csv"};
    csv.precision(7);
    csv << "scene,method,mode,fovea_deg,frames,pyramid_ms,foveate_ms,temporal_ms,total_ms,per_eye_ms,"
           "copy_ms,copy_floor_ms,traffic_bytes,bytes_per_px,floor_bytes_per_px,ratio_to_floor_bytes,ratio_to_copy,"
           "ratio_to_copy_floor,ratio_to_fov,shading_fraction,psnr,jod,ssim,near_gaze_psnr,ecc_mse,flip,"
           "temporal_instability,mse,near_gaze_mse,eta,eta_near_gaze,stale_fraction,stale_mse,stale_fov_mse,eta_q,"
           "eta_q_near_gaze,retain_share,jod_frames,jod_near_gaze_psnr,worth_sweep\n";
    for (const auto& c : results)
        csv << toString(c.scene) << ',' << toString(c.method) << ',' << toString(c.mode) << ',' << c.foveaDeg << ','
            << c.frames << ',' << c.gpu.pyramid << ',' << c.gpu.foveate << ',' << c.gpu.temporal << ',' << c.gpu.total
            << ',' << c.gpu.total / 2 << ',' << c.copyMs << ',' << c.copyFloorMs << ',' << c.trafficBytes << ','
            << c.traffic.perPixel() << ',' << c.traffic.floor << ',' << c.traffic.perPixel() / c.traffic.floor << ','
            << c.gpu.total / c.copyMs << ',' << c.gpu.total / c.copyFloorMs << ',' << c.gpu.total / c.fovTotalMs << ','
            << c.shadingFraction << ',' << c.psnr << ',' << c.jod << ',' << c.ssim << ',' << c.nearPsnr << ',' << c.eccMse << ',' << c.flip << ',' << c.temporal
            << ',' << c.mse << ',' << c.nearMse << ',' << c.eta << ',' << c.etaNear << ',' << c.staleFraction << ','
            << c.staleMse << ',' << c.staleFovMse << ',' << c.etaQ << ',' << c.etaQNear << ',' << c.retainShare << ','
            << c.jodFrames << ',' << c.jodNearPsnr << ',' << (c.worthSweep ? 1 : 0) << '\n';

    // The fovea each method at the first fovea is worth: fov's fovea of equal JOD, and of equal near-gaze
    // PSNR over the same frames.
    struct Worth {
        SceneKind scene;
        FoveationMode mode;
        Method method;
        const CellResult* cell;
        FoveaWorth byJod, byPsnr;
        double fovMin = 0, fovMax = 0;
    };
    std::vector<Worth> worth;
    const float fovea0 = o.foveas.front();
    for (SceneKind scene : o.scenes)
        for (FoveationMode mode : o.modes) {
            std::vector<std::pair<double, double>> byJod, byPsnr;
            for (const CellResult& c : results)
                if (c.scene == scene && c.mode == mode && c.method == Method::Fov && c.foveaDeg >= fovea0) {
                    byJod.emplace_back(c.foveaDeg, c.jod);
                    byPsnr.emplace_back(c.foveaDeg, c.jodNearPsnr);
                }
            if (byJod.size() < 2) continue;
            double lo = 1e9, hi = 0;
            for (auto [f, v] : byJod) lo = std::min(lo, f), hi = std::max(hi, f);
            for (Method m : o.methods) {
                if (m == Method::Fov) continue;
                const CellResult* c = findCell(results, scene, mode, fovea0, m);
                if (!c || std::isnan(c->jod)) continue;
                worth.push_back({scene, mode, m, c, foveaWorth(byJod, c->jod), foveaWorth(byPsnr, c->jodNearPsnr), lo, hi});
            }
        }
    if (!worth.empty()) {
        std::ofstream wc(dir + "/fovea_worth.csv");
        if (!wc) return Error{1, "cannot write " + dir + "/fovea_worth.csv"};
        wc.precision(7);
        wc << "scene,mode,method,fovea_deg,jod,worth_jod_deg,worth_jod_bound,near_gaze_psnr,worth_psnr_deg,"
              "worth_psnr_bound,fov_min_deg,fov_max_deg,jod_frames\n";
        auto bound = [](FoveaWorth::Bound b) {
            return b == FoveaWorth::Bound::Exact      ? "exact"
                   : b == FoveaWorth::Bound::AtMost   ? "at_most"
                   : b == FoveaWorth::Bound::MoreThan ? "more_than"
                                                      : "unknown";
        };
        for (const Worth& w : worth)
            wc << toString(w.scene) << ',' << toString(w.mode) << ',' << toString(w.method) << ',' << fovea0 << ','
               << w.cell->jod << ',' << w.byJod.deg << ',' << bound(w.byJod.bound) << ',' << w.cell->jodNearPsnr << ','
               << w.byPsnr.deg << ',' << bound(w.byPsnr.bound) << ',' << w.fovMin << ',' << w.fovMax << ','
               << w.cell->jodFrames << '\n';
    }

    auto find = [&](SceneKind scene, FoveationMode mode, Method m, float fovea) {
        return findCell(results, scene, mode, fovea, m);
    };
    const bool cpuDevice = isCpuRenderer(deviceName);

    std::ofstream md(dir + "/table.md");
    if (!md) return Error{1, "cannot write " + dir + "/table.md"};
    md << "# wrsfov benchmark\n\n" << o.width << "x" << o.height
       << (o.monitor ? " (monitor mode: one 76x60 degree view as both eyes)"
                     : o.hmdFovDeg > 0 ? " per eye (HMD stereo, the central " + fmt(o.hmdFovDeg, 0) + "°x" +
                                            fmt(o.hmdFovDeg, 0) + "° of each eye's view)"
                                      : std::string(" per eye (HMD stereo)"))
       << ", " << fmt(centrePixelsPerDegree(o), 1)
       << " px/deg at the view centre (atrium, dynamic; text has its own layout; their procedural materials "
       << (o.materialSamples > 1 ? "filtered over each pixel, " + std::to_string(o.materialSamples) + " shading samples"
                                 : std::string("point-sampled, aliased"))
       << "), " << o.frames << " frames at 90 Hz (" << o.warmup << " warm-up). Times measured on **" << deviceName << "**"
       << (cpuDevice ? " — Mesa lavapipe, a CPU renderer: absolute times say little about a GPU, ratios in the same "
                       "run (×copy, ×fov) say more"
                     : "")
       << ".\n";
    if (o.monitor)
        md << "\nIn monitor mode both views are one image: every method but `wrs-paper` runs the passes (and the "
              "copy kernels) once and copies the result to the right eye; `wrs-paper` draws different random "
              "numbers per eye and runs both, so its GPU time is not comparable with the others' here (compare in "
              "HMD stereo).\n";
    if (std::find(o.scenes.begin(), o.scenes.end(), SceneKind::Sequence) != o.scenes.end())
        md << "\nScene `sequence`: the frames of " << o.sequenceDir
           << " at the fps of its sequence.json, gaze from its gaze.csv (synthetic free viewing without one).\n";
    if (std::find(o.scenes.begin(), o.scenes.end(), SceneKind::Photo) != o.scenes.end())
        md << "\nScene `photo`: " << o.photoImage << " on a plane 1 m away, one texel per pixel at the view's centre, "
           << "head " << scenes::toString(o.photoMotion)
           << (o.photoMotion == scenes::PhotoMotion::Static ? std::string()
                                                            : " at " + fmt(o.photoSpeed, 2) + " px/frame at the view's centre")
           << ", free-viewing gaze.\n";

    // Summary first: per scene and mode, each method against fov at the smallest fovea.
    md << "\n## Summary\n\n";
    const float f0 = o.foveas.front();
    for (SceneKind scene : o.scenes)
        for (FoveationMode mode : o.modes) {
            const CellResult* fov = find(scene, mode, Method::Fov, f0);
            if (!fov) continue;
            md << "- **" << toString(scene) << ", " << toString(mode) << ", fovea " << fmt(f0, 1) << "°**: ";
            const CellResult* oracle = find(scene, mode, Method::Oracle, f0);
            const CellResult* oracleQ = find(scene, mode, Method::OracleQ, f0);
            if (oracle)
                md << "the oracle bound gains " << fmt(oracle->psnr - fov->psnr) << " dB full / "
                   << fmt(oracle->nearPsnr - fov->nearPsnr) << " dB near gaze over fov"
                   << (std::isnan(oracle->jod) ? std::string() : " (JOD " + fmt(oracle->jod) + ")");
            if (oracleQ)
                md << (oracle ? ", the retention bound (oracle-q) " : "the retention bound (oracle-q) gains ")
                   << fmt(oracleQ->psnr - fov->psnr) << " dB full / " << fmt(oracleQ->nearPsnr - fov->nearPsnr)
                   << " dB near gaze" << (std::isnan(oracleQ->jod) ? std::string() : " (JOD " + fmt(oracleQ->jod) + ")");
            if (oracle || oracleQ) md << ". ";
            bool firstM = true;
            for (Method m : o.methods) {
                if (m == Method::Fov || isOracle(m)) continue;
                const CellResult* c = find(scene, mode, m, f0);
                if (!c) continue;
                const double dFull = c->psnr - fov->psnr, dNear = c->nearPsnr - fov->nearPsnr;
                md << (firstM ? "" : "; ") << "`" << toString(m) << "` ";
                if (!std::isnan(dNear) || !std::isnan(dFull))  // NaN: a run without error metrics (--scaling)
                    md << (dNear > 0.05 ? "beats fov by " : dNear < -0.05 ? "loses to fov by " : "ties with fov, ")
                       << fmt(dFull) << " dB full / " << fmt(dNear) << " dB near gaze";
                else
                    md << "runs";
                const bool eta = !std::isnan(c->eta) || !std::isnan(c->etaNear);
                const bool etaQ = !std::isnan(c->etaQ) || !std::isnan(c->etaQNear);
                if (eta || etaQ) {
                    md << " (";
                    if (eta) md << "η " << fmt(c->eta) << " / " << fmt(c->etaNear);
                    if (etaQ) md << (eta ? ", " : "") << "η_q " << fmt(c->etaQ) << " / " << fmt(c->etaQNear);
                    md << ")";
                }
                if (!std::isnan(c->jod)) md << ", JOD " << fmt(c->jod) << " vs fov " << fmt(fov->jod);
                md << " at " << fmt(c->gpu.total / fov->gpu.total) << "× fov's GPU time";
                if (!std::isnan(c->staleMse) && c->staleFraction > 0)
                    md << ", stale-pixel MSE " << fmt(c->staleMse, 5) << " vs fov " << fmt(c->staleFovMse, 5);
                firstM = false;
            }
            md << ".\n";
            for (const Worth& w : worth) {
                if (w.scene != scene || w.mode != mode || w.method != Method::Wrs) continue;
                md << "- **The fovea `wrs` at " << fmt(fovea0, 1) << "° is worth** (the `fov` fovea of equal score, fov "
                   << "swept over " << fmt(w.fovMin, 1) << "–" << fmt(w.fovMax, 1) << "°, linear in the score, over the "
                   << w.cell->jodFrames << " JOD frames): **" << toString(w.byJod) << " by FovVideoVDP** (JOD "
                   << fmt(w.cell->jod) << "), " << toString(w.byPsnr) << " by near-gaze PSNR ("
                   << fmt(w.cell->jodNearPsnr) << " dB). The paper's user study preferred WRS at 5° over FOV at 5° "
                   << "(64 %) and over FOV at 7.5° (62 %): WRS 5° judged about as good as FOV 7.5° or better; by JOD "
                   << "here it is "
                   << (w.byJod.bound == FoveaWorth::Bound::MoreThan || (w.byJod.bound == FoveaWorth::Bound::Exact && w.byJod.deg >= 7.5)
                           ? "as good as fov at 7.5° or better, as the study found"
                       : w.byJod.bound == FoveaWorth::Bound::Unknown ? "not known"
                                                                      : "worth less than fov at 7.5°, less than the study found")
                   << ".\n";
            }
        }

    md << "\n## Columns\n\n"
          "- *near PSNR*: PSNR (dB, sRGB 8-bit) over pixels within 10° of the gaze; *PSNR* over the whole image.\n"
          "- *JOD*: FovVideoVDP v1.2 (our implementation, eval/fvvdp.h, docs/metrics.md), foveated with the run's "
          "gaze, 10 = no visible difference, against the unfoveated reference; display "
       << (o.monitor ? "monitor (200 cd/m², 1000:1, 250 lux)" : "HMD (100 cd/m², black 0.1 cd/m²) for built-in scenes, monitor for sequences")
       << ", geometry from the submitted field of view, "
       << (o.jodFrames > 0 ? "over the last " + std::to_string(std::min(o.jodFrames, o.frames - o.warmup)) + " counted frames"
                           : std::string("over every counted frame"))
       << (o.monitor ? "" : ", mean of the two eyes") << ". *fov (sweep)* rows: fov at the fovea-worth sweep's extra "
          "foveas, submitted and scored over the JOD frames only (fov keeps nothing between frames); their near "
          "PSNR and PSNR are over those frames.\n"
          "- *η* / *η near*: retention efficiency (MSE_fov − MSE) / (MSE_fov − MSE_oracle) in the same cell, "
          "whole image / within 10°: 0 = no better than fov, 1 = as good as the oracle (which keeps, per pixel, "
          "whichever of history and candidate is closer to the reference). n/a without fov and oracle, or when "
          "the oracle removes less than 1 % of fov's MSE there. *η_q* / *η_q near*: the same against the "
          "retention oracle `oracle-q`, which "
          "keeps the history only where it is closer to the reference *and* of higher quality than the candidate: "
          "the ceiling of keeping what foveation throws away, without the oracle's choice among equally or less "
          "sharp samples (which needs the reference to see which of two blurred values happens to be closer).\n"
          "- *SSIM*, *FLIP* (NVIDIA FLIP, 0..1, lower is better): every "
       << o.heavyEvery
       << "th counted frame. *ecc-MSE*: MSE weighted by the cone-density falloff of eccentricity.\n"
          "- *temporal*: temporal instability, the mean absolute frame-to-frame change of the output where the "
          "reference did not change (0..1; lower is steadier).\n"
          "- *stale*: share of pixels showing a sample whose submitted colour when taken is more than 4/255 "
          "outside the 3×3 neighbourhood of the submitted colour now (methods that keep samples); *stale MSE* "
          "the method's MSE over those pixels, *fov there* fov's MSE over the same pixels (every "
       << o.heavyEvery
       << "th frame).\n"
          "- *GPU ms*: median GPU time per frame, both eyes; *×copy*: against a copy kernel moving the same "
          "bytes in the same submission; *×copy floor*: against a copy kernel moving only the method's floor "
          "bytes (see Traffic); *×fov*: against fov in the same cell; *B/px*: bytes the passes read and write per "
          "pixel of one view; *shading*: the fraction of full-rate shading the foveation represents; *retain*: "
          "the share of 8×8 tiles that ran retention (sparse retention skips far tiles that can hold nothing "
          "sharper than their candidates), mean over the counted frames.\n";

    for (SceneKind scene : o.scenes)
        for (FoveationMode mode : o.modes) {
            md << "\n## " << toString(scene) << ", foveation " << toString(mode) << "\n\n"
               << "| method | fovea | near PSNR | PSNR | JOD | η | η near | η_q | η_q near | SSIM | FLIP | ecc-MSE | temporal "
                  "| stale | stale MSE | fov there | GPU ms | ×copy | ×copy floor | ×fov | B/px | shading | retain |\n"
                  "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n";
            for (const auto& c : results) {
                if (c.scene != scene || c.mode != mode) continue;
                md << "| " << toString(c.method) << (c.worthSweep ? " (sweep)" : "") << " | " << fmt(c.foveaDeg, 1) << "° | "
                   << fmt(c.nearPsnr) << " | " << fmt(c.psnr) << " | " << fmt(c.jod) << " | " << fmt(c.eta) << " | " << fmt(c.etaNear) << " | " << fmt(c.etaQ) << " | "
                   << fmt(c.etaQNear) << " | " << fmt(c.ssim, 4)
                   << " | " << fmt(c.flip, 4) << " | " << fmt(c.eccMse, 5) << " | " << fmt(c.temporal, 5) << " | "
                   << (std::isnan(c.staleFraction) ? std::string("n/a") : fmt(100 * c.staleFraction, 3) + " %")
                   << " | " << fmt(c.staleMse, 5) << " | " << fmt(c.staleFovMse, 5) << " | " << fmt(c.gpu.total, 3)
                   << " | " << fmt(c.gpu.total / c.copyMs) << " | " << fmt(c.gpu.total / c.copyFloorMs) << " | "
                   << fmt(c.gpu.total / c.fovTotalMs) << " | " << fmt(c.traffic.perPixel(), 1) << " | "
                   << fmt(c.shadingFraction, 3) << " | "
                   << (std::isnan(c.retainShare) ? std::string("n/a") : fmt(100 * c.retainShare, 1) + " %") << " |\n";
            }
            float eq = equalQualityFovea(results, scene, mode);
            md << "\nEqual-quality fovea (smallest wrs fovea below 10° with near-gaze PSNR ≥ fov at 10°): "
               << (eq > 0 ? fmt(eq, 1) + "°" : std::string("none in this sweep")) << "\n";
        }

    if (!worth.empty()) {
        md << "\n## The fovea a method is worth\n\n"
              "For each method at "
           << fmt(fovea0, 1)
           << "°, the `fov` fovea that scores the same: fov's JOD (and near-gaze PSNR) against its fovea "
              "diameter, interpolated linearly in the score between the swept foveas; the smallest fovea that "
              "reaches the method's score (\"or less\": fov at the smallest fovea already does; \"more than\": no "
              "swept fovea does). Both scores over the same JOD frames. The paper's user study: WRS at 5° "
              "preferred over FOV at 5° by 64 % and over FOV at 7.5° by 62 % of the answers. fovea_worth.csv "
              "has the figures.\n\n"
              "| scene | mode | method | JOD | worth by JOD | near PSNR (JOD frames) | worth by near PSNR | fov swept |\n"
              "|---|---|---|---|---|---|---|---|\n";
        for (const Worth& w : worth)
            md << "| " << toString(w.scene) << " | " << toString(w.mode) << " | " << toString(w.method) << " | "
               << fmt(w.cell->jod) << " | " << toString(w.byJod) << " | " << fmt(w.cell->jodNearPsnr) << " dB | "
               << toString(w.byPsnr) << " | " << fmt(w.fovMin, 1) << "–" << fmt(w.fovMax, 1) << "° |\n";
    }

    writeTrafficSection(md, results);
    writeBandSection(md, results);

    std::ofstream bands(dir + "/ecc_bands.csv");
    if (!bands) return Error{1, "cannot write " + dir + "/ecc_bands.csv"};
    bands.precision(7);
    bands << "scene,method,mode,fovea_deg,band_lo_deg,band_hi_deg,pixel_share,mse\n";
    for (const auto& c : results)
        for (std::size_t b = 0; b < c.bandMse.size(); ++b)
            bands << toString(c.scene) << ',' << toString(c.method) << ',' << toString(c.mode) << ',' << c.foveaDeg
                  << ',' << kEccBands[b] << ',' << kEccBands[b + 1] << ',' << c.bandShare[b] << ',' << c.bandMse[b]
                  << '\n';

    // Per scene and mode: error against run time, against fovea size, and η per method.
    for (SceneKind scene : o.scenes)
        for (FoveationMode mode : o.modes) {
            std::vector<Series> vsTime, vsFovea, eta, jodTime;
            bool anyJod = false;
            for (Method m : o.methods) {
                Series st{std::string(toString(m)), methodColour(m)}, sf{std::string(toString(m)), methodColour(m)};
                Series se{std::string(toString(m)), methodColour(m)}, sj{std::string(toString(m)), methodColour(m)};
                sf.line = true;
                // Near-gaze PSNR against fovea size: with a fovea-worth sweep, fov's whole curve (5-15°) and
                // every method's point, all over the JOD frames the sweep is scored on (jodNearPsnr).
                const bool worthCurve = std::any_of(results.begin(), results.end(), [&](const CellResult& c) {
                    return c.scene == scene && c.mode == mode && c.worthSweep;
                });
                for (const auto& c : results) {
                    if (c.scene != scene || c.method != m || c.mode != mode) continue;
                    if (worthCurve && std::isfinite(c.jodNearPsnr)) sf.points.push_back({c.foveaDeg, c.jodNearPsnr});
                    // JOD against time: the sweep's fov points too (fov's whole curve).
                    if (!std::isnan(c.jod)) {
                        sj.points.push_back({c.gpu.total, c.jod});
                        sj.labels.push_back(fmt(c.foveaDeg, 1) + " deg");
                        anyJod = true;
                    }
                    if (c.worthSweep) continue;
                    st.points.push_back({c.gpu.total, c.nearPsnr});
                    st.labels.push_back(fmt(c.foveaDeg, 1) + " deg");
                    if (!worthCurve) sf.points.push_back({c.foveaDeg, c.nearPsnr});
                    se.points.push_back({c.eta, c.etaNear});
                    se.labels.push_back(fmt(c.foveaDeg, 1) + " deg");
                }
                vsTime.push_back(st);
                std::sort(sf.points.begin(), sf.points.end(), [](auto a, auto b) { return a.x < b.x; });
                vsFovea.push_back(sf);
                eta.push_back(se);
                jodTime.push_back(sj);
            }
            const std::string s(toString(scene)), m(toString(mode)), tag = s + "_" + m;
            if (anyJod)
                cv::imwrite(dir + "/jod_vs_time_" + tag + ".png",
                            chart(s + " (" + m + "): FovVideoVDP JOD against GPU time", "GPU ms per frame (both eyes)",
                                  "JOD (10 = no visible difference)", jodTime));
            cv::imwrite(dir + "/error_vs_time_" + tag + ".png",
                        chart(s + " (" + m + "): near-gaze PSNR against GPU time", "GPU ms per frame (both eyes)",
                              "near-gaze PSNR (dB)", vsTime));
            cv::imwrite(dir + "/error_vs_fovea_" + tag + ".png",
                        chart(s + " (" + m + "): near-gaze PSNR against fovea size", "fovea diameter (deg)",
                              "near-gaze PSNR (dB)", vsFovea));
            cv::imwrite(dir + "/eta_" + tag + ".png",
                        chart(s + " (" + m + "): retention efficiency (1 = oracle, 0 = fov)", "eta, whole image",
                              "eta, within 10 deg", eta));
        }
    return {};
}

Status writeScalingReport(const std::vector<ScalingStep>& steps, const BenchOptions& o, const std::string& dir,
                          const std::string& deviceName, const std::string& costModel) {
    std::ofstream csv(dir + "/scaling.csv");
    std::ofstream md(dir + "/scaling.md");
    if (!csv || !md) return Error{1, "cannot write " + dir + "/scaling.{csv,md}"};
    csv.precision(7);
    csv << "width,height,scene,method,mode,megapixels_per_frame,total_ms,copy_ms,copy_floor_ms,bytes_per_px,"
           "floor_bytes_per_px,ratio_to_fov,ratio_to_copy,ratio_to_copy_floor,ns_per_px,retain_share\n";
    const bool cpuDevice = isCpuRenderer(deviceName);
    md << "# wrsfov scaling\n\nTime and bytes per frame at " << steps.size() << " sizes, "
       << (o.monitor ? "monitor mode" : "HMD stereo (both eyes)") << ", fovea " << fmt(o.foveas.front(), 1)
       << "°, foveation " << toString(o.modes.front()) << ", " << o.frames - o.warmup << " counted frames per cell, "
       << "stale-pixel tracking off (the passes as an application gets them). Measured on **" << deviceName << "**"
       << (cpuDevice ? " — Mesa lavapipe, a CPU renderer: its timestamps do not bracket dispatches, so times are the "
                       "host's wall clock from submission to completion (PassTimes::hostTimed), and a CPU computes "
                       "rather than moves bytes; ratios in the same run say more than absolute times"
                     : "")
       << ".\n\n*ns/px*: time per pixel of both views: flat when the cost grows linearly with pixels. *×copy*: "
          "against a copy kernel moving the method's bytes, *×copy floor*: the floor's; each size's table.md "
          "(in its WxH directory) has the bytes per pass under Traffic. *retain*: the share of 8×8 tiles that "
          "ran retention over the timed frames (sparse retention: where the gaze has been).\n\n"
          "| size per eye | method | GPU ms | ns/px | ×fov | B/px | floor B/px | copy ms | ×copy | copy floor ms | "
          "×copy floor | retain |\n|---|---|---|---|---|---|---|---|---|---|---|---|\n";
    std::map<Method, Series> series;
    for (const ScalingStep& st : steps)
        for (const CellResult& c : st.cells) {
            const double px = double(st.width) * st.height * 2;  // both views
            const double nsPx = c.gpu.total * 1e6 / px;
            csv << st.width << ',' << st.height << ',' << toString(c.scene) << ',' << toString(c.method) << ','
                << toString(c.mode) << ',' << px / 1e6 << ',' << c.gpu.total << ',' << c.copyMs << ',' << c.copyFloorMs
                << ',' << c.traffic.perPixel() << ',' << c.traffic.floor << ',' << c.gpu.total / c.fovTotalMs << ','
                << c.gpu.total / c.copyMs << ',' << c.gpu.total / c.copyFloorMs << ',' << nsPx << ',' << c.retainShare
                << '\n';
            md << "| " << st.width << "×" << st.height << " | " << toString(c.method) << " | " << fmt(c.gpu.total, 2)
               << " | " << fmt(nsPx, 1) << " | " << fmt(c.gpu.total / c.fovTotalMs) << " | "
               << fmt(c.traffic.perPixel(), 1) << " | " << fmt(c.traffic.floor, 1) << " | " << fmt(c.copyMs, 2)
               << " | " << fmt(c.gpu.total / c.copyMs) << " | " << fmt(c.copyFloorMs, 2) << " | "
               << fmt(c.gpu.total / c.copyFloorMs) << " | "
               << (std::isnan(c.retainShare) ? std::string("n/a") : fmt(100 * c.retainShare, 1) + " %") << " |\n";
            auto it = series.find(c.method);
            if (it == series.end())
                it = series.emplace(c.method, Series{std::string(toString(c.method)), methodColour(c.method)}).first;
            it->second.line = true;
            it->second.points.push_back({px / 1e6, c.gpu.total});
        }
    if (!costModel.empty()) md << "\n" << costModel;
    std::vector<Series> all;
    for (auto& [m, s] : series) all.push_back(s);
    cv::imwrite(dir + "/scaling.png", chart("GPU time per frame against pixels (both views)", "megapixels per frame",
                                            "GPU ms per frame", all));
    return {};
}

}  // namespace wrsfov::eval
