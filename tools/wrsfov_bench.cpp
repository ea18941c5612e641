// wrsfov-bench: run time against error. Sweeps scenes x methods x fovea sizes x foveation modes
// with synthetic gaze, and writes results.csv, table.md, PNG plots and crops into --out.
// --sequence DIR evaluates external frames (docs/sequence.md); --write-sequence DIR writes a
// built-in scene out as such a directory.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "eval/bench.h"
#include "eval/saving.h"
#include "eval/study.h"
#include "eval/flicker.h"
#include "eval/cost_model.h"
#include "eval/sequence.h"
#include "cli/cli.h"

using namespace wrsfov;

namespace {

// Prints the report's table and where it is, or why it could not be written; the exit code.
int printReport(const Status& written, const std::string& table, const std::string& where) {
    if (!written) {
        std::fprintf(stderr, "wrsfov-bench: %s\n", written.message().c_str());
        return 1;
    }
    std::ifstream in(table);
    std::printf("%s", std::string(std::istreambuf_iterator<char>(in), {}).c_str());
    std::printf("\nwrsfov-bench: %s\n", where.c_str());
    return 0;
}

// --cost-model: the configured cell's pipelines compiled per target, their statistics, bytes and tile
// shares as a roofline estimate per GPU of eval::gpuTable() (cost_model.csv, cost_model.md in `out`), at
// each GPU's HMD size and at `sizes`. `section` gets the totals for another report (scaling.md).
struct CostModelRun {
    int exitCode = 0;
    std::string section;
};
// Sparse retention: which far tiles skip retention depends on where the gaze has been, so a method
// that runs it has its share of retention tiles measured: the cell runs on this machine's device
// (no metrics) at kShareProxy per eye, same views and gaze, and the share is the mean over the 30
// frames after 300 frames (3.3 s) of gaze. A tile there spans the angle of four at 2048 px, so the
// share of retention tiles is if anything overstated for larger images.
constexpr uint32_t kShareProxy = 512;
struct SparseShares {
    double retain = 1.0;  ///< tiles that ran retention
    double motion = 0.0;  ///< tiles whose motion the classification read
};
Result<SparseShares> measuredSparseShares(vk::Context& ctx, eval::BenchOptions o, Method m) {
    o.methods = {m};
    o.scenes.resize(1);
    o.modes.resize(1);
    o.foveas.resize(1);
    o.width = o.height = kShareProxy;
    o.frames = 330;
    o.warmup = 300;
    o.qualityMetrics = false;
    o.staleStats = false;
    o.copyEvery = 0;
    o.cropDir = "";
    o.progress = nullptr;
    auto r = eval::runBench(ctx, o);
    if (!r) return r.error();
    for (const eval::CellResult& c : *r)
        if (c.method == m && std::isfinite(c.retainShare) && std::isfinite(c.motionShare))
            return SparseShares{c.retainShare, c.motionShare};
    return Error{1, "no retention share measured"};
}

// --cost-quad: the cost model's frames submitted as quad views, as the saving study renders them.
struct QuadCostCell {
    float wideScale = 0.4f, insetDeg = 10.0f;
    uint32_t jitterPhases = 0;
};

CostModelRun runCostModel(const eval::BenchOptions& o, const std::vector<std::string>& targetNames,
                          const std::vector<std::pair<uint32_t, uint32_t>>& sizes, const std::string& out,
                          vk::Context* ctx, const std::optional<QuadCostCell>& quad = std::nullopt) {
    CostModelRun run;
    const eval::SceneKind scene = o.scenes.front();
    const FoveationMode mode = o.modes.front();
    const float fovea = o.foveas.front();
    auto configFor = [&](Method m) {
        CompositorConfig c = eval::compositorConfig(o);
        c.method = m;
        c.foveation = quad ? FoveationMode::Submitted : mode;
        c.foveaDeg = fovea;
        return c;  // no stale tracking: the passes as an application gets them
    };
    // The views' bytes and tile shares at a size: the cell's own gaze replayed (simulated foveation), or
    // the quad views' layer (a frame of wrs that merges every phase of jittered views: every tile any).
    std::map<std::pair<uint32_t, uint32_t>, eval::CellGeometry> geometry;
    auto geometryFor = [&](Method m, uint32_t w, uint32_t h) -> Result<eval::CellGeometry> {
        if (quad) {
            const CompositorConfig c = configFor(m);
            const bool merges = m == Method::Wrs && c.phaseMerge && c.landedSamples && quad->jitterPhases > 1;
            return eval::quadCellGeometry(o, scene, w, h, quad->wideScale, quad->insetDeg, merges);
        }
        auto it = geometry.find({w, h});
        if (it == geometry.end()) {
            auto g = eval::cellGeometry(o, scene, mode, fovea, w, h);
            if (!g) return g.error();
            it = geometry.emplace(std::pair{w, h}, *g).first;
        }
        return it->second;
    };
    std::error_code ec;
    const std::string exe = std::filesystem::read_symlink("/proc/self/exe", ec).string();
    std::vector<eval::CostRow> rows;
    std::vector<std::string> skipped;
    std::map<Method, SparseShares> sparseShares;
    std::string shareNote;
    if (quad)
        shareNote = "; sparse retention's skipped tiles not measured on quad views: every far tile counted as retaining "
                    "(with jittered views wrs merges every phase and has no far tiles)";
    for (Method m : o.methods) {
        if (quad || !runsSparse(configFor(m))) continue;
        if (!ctx) {
            shareNote = "; no Vulkan device to measure sparse retention's share on: every far tile counted as retaining";
            break;
        }
        std::printf("wrsfov-bench: cost model: measuring %s's share of retention tiles (%ux%u per eye, 330 frames)\n",
                    std::string(toString(m)).c_str(), kShareProxy, kShareProxy);
        auto s = measuredSparseShares(*ctx, o, m);
        if (!s) {
            std::fprintf(stderr, "wrsfov-bench: cost model: %s\n", s.error().message.c_str());
            run.exitCode = 1;
            return run;
        }
        sparseShares[m] = *s;
        shareNote += "; " + std::string(toString(m)) + " ran retention in " +
                     std::to_string(100.0 * s->retain).substr(0, 4) + " % of the tiles and its classification read the motion of " +
                     std::to_string(100.0 * s->motion).substr(0, 4) + " % (measured at " + std::to_string(kShareProxy) + "x" +
                     std::to_string(kShareProxy) + " per eye, frames 300-329)";
    }
    for (const std::string& name : targetNames) {
        auto target = eval::parseStatsTarget(name);
        if (!target) {
            std::fprintf(stderr, "wrsfov-bench: cost model: %s\n", target.error().message.c_str());
            run.exitCode = 1;
            continue;
        }
        // The GPU's public figures: the family's entry, or the entry a real device's name matches.
        const eval::GpuFigures* gpu = eval::findGpu(target->family);
        for (const eval::GpuFigures& g : eval::gpuTable())
            if (!gpu && target->family.empty() &&
                (target->deviceName.find(g.match) != std::string::npos || g.match.find(target->deviceName) != std::string::npos))
                gpu = &g;
        if (!gpu) {
            skipped.push_back(name + ": no public figures for it in eval::gpuTable() (eval/cost_model.cpp)");
            std::printf("wrsfov-bench: cost model: skipping %s\n", skipped.back().c_str());
            continue;
        }
        std::vector<std::pair<uint32_t, uint32_t>> cellSizes{{gpu->eyeWidth, gpu->eyeHeight}};
        for (auto s : sizes)
            if (std::find(cellSizes.begin(), cellSizes.end(), s) == cellSizes.end()) cellSizes.push_back(s);
        // The pipelines depend on the views (depth, motion, composition), not on their size.
        std::vector<eval::VariantKey> keys;
        for (Method m : o.methods) {
            auto geo = geometryFor(m, cellSizes.front().first, cellSizes.front().second);
            if (!geo) {
                std::fprintf(stderr, "wrsfov-bench: cost model: %s\n", geo.error().message.c_str());
                run.exitCode = 1;
                return run;
            }
            for (const eval::PipelineVariant& v : eval::pipelineVariants(configFor(m), geo->inputs))
                if (std::find(keys.begin(), keys.end(), eval::VariantKey{v.shader, v.constants}) == keys.end())
                    keys.push_back({v.shader, v.constants});
        }
        const auto t0 = std::chrono::steady_clock::now();
        auto stats = eval::collectStatistics(exe, *target, keys);
        if (!stats) {
            if (stats.error().code == int(eval::CostError::Unavailable)) {
                skipped.push_back(name + ": " + stats.error().message);
                std::printf("wrsfov-bench: cost model: skipping %s\n", skipped.back().c_str());
            } else {
                std::fprintf(stderr, "wrsfov-bench: cost model: %s\n", stats.error().message.c_str());
                skipped.push_back(name + ": failed: " + stats.error().message);
                run.exitCode = 1;
            }
            continue;
        }
        std::printf("wrsfov-bench: cost model: %zu pipelines compiled for %s in %.1f s\n", keys.size(), name.c_str(),
                    std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
        for (auto [w, h] : cellSizes) {
            for (Method m : o.methods) {
                auto g = geometryFor(m, w, h);
                if (!g) {
                    std::fprintf(stderr, "wrsfov-bench: cost model: %s\n", g.error().message.c_str());
                    run.exitCode = 1;
                    return run;
                }
                eval::TileShares shares = g->tileShare;
                // Bytes per pass: without a measurement the classification reads every far tile's motion.
                TrafficInputs in = g->inputs;
                in.motionShare = shares[gpu::WRS_TILE_FAR];
                if (auto rs = sparseShares.find(m); rs != sparseShares.end()) {
                    // The skipped tiles are far tiles: they come off the far list.
                    const double skip = std::clamp(1.0 - rs->second.retain, 0.0, shares[gpu::WRS_TILE_FAR]);
                    shares[gpu::WRS_TILE_FAR] -= skip;
                    shares[gpu::WRS_TILE_SKIP] = skip;
                    in.motionShare = std::min(rs->second.motion, shares[gpu::WRS_TILE_FAR] + skip);
                }
                eval::CostCell cell{gpu, w, h, 2, m, eval::pipelineVariants(configFor(m), in), shares};
                auto r = eval::costRows(cell, *stats);
                rows.insert(rows.end(), r.begin(), r.end());
            }
        }
    }
    auto num = [](double v, const char* f) {
        char b[32];
        std::snprintf(b, sizeof b, f, v);
        return std::string(b);
    };
    std::string description =
        quad ? "Frames submitted as quad views of the " + std::string(eval::toString(scene)) + " (HMD stereo, " +
                   (o.hmdFovDeg > 0 ? num(o.hmdFovDeg, "%.0f") + "° per eye" : std::string("the default field of view")) +
                   "), as the saving study renders them: wide views at " +
                   num(quad->wideScale, "%.2f") + " of the display's pixels" +
                   (quad->jitterPhases > 1 ? ", jittered over " + std::to_string(quad->jitterPhases) + " phases" : "") +
                   ", an inset " + num(quad->insetDeg, "%.0f") + "° across at the display's density; the compose pass "
                   "first, its bytes those of the layer's images; tile classes far outside the inset (placed at the "
                   "view's centre), any within it" + shareNote + "."
             : "Scene " + std::string(eval::toString(scene)) + " (" +
                              (o.monitor ? "monitor mode" : "HMD stereo") + ", camera path " +
                              std::string(toString(o.path)) + "), fovea " + std::to_string(fovea).substr(0, 4) +
                              "°, foveation " + std::string(toString(mode)) + (o.skipTiles ? "" : ", no tile classes") +
                              "; tile-class shares from the sweep's gaze (seed " + std::to_string(o.seed) +
                              ") over frames " + std::to_string(o.warmup) + "-" + std::to_string(o.frames - 1) +
                              " at 90 Hz, classified as the compositor does" + shareNote + ".";
    if (Status s = eval::writeCostModel(rows, skipped, description, out); !s) {
        std::fprintf(stderr, "wrsfov-bench: %s\n", s.message().c_str());
        run.exitCode = 1;
        return run;
    }
    std::string section = "## Cost model (static estimate)\n\nThe same passes on GPUs this machine lacks, from the compiler's "
                          "statistics on RADV's null device, the bytes and the tile shares: [cost_model.md](cost_model.md) "
                          "(model, figures, per pass and class), cost_model.csv.\n\n";
    for (const std::string& s : skipped) section += "- skipped " + s + "\n";
    if (!skipped.empty()) section += "\n";
    if (!rows.empty()) section += eval::costTotalsMarkdown(rows);
    run.section = section;
    std::printf("%s\nwrsfov-bench: cost model in %s (cost_model.csv, cost_model.md)\n", section.c_str(), out.c_str());
    return run;
}

// --scaling: the sweep at each size with the scene's frames kept on the device (runDeviceSweep: no
// read-back, no metrics, stale tracking off), and a scaling table over all of them.
int runScaling(vk::Context& ctx, eval::BenchOptions o, const std::vector<cli::Size>& sizes, const std::string& out,
               bool framesGiven, bool warmupGiven, bool scenesGiven, bool methodsGiven,
               const std::vector<std::string>& costTargets) {
    if (!scenesGiven) o.scenes = {eval::SceneKind::Atrium};
    if (!methodsGiven) o.methods = {Method::Fov, Method::FovTaa, Method::Wrs};
    if (!framesGiven) o.frames = 20;
    if (!warmupGiven) o.warmup = 5;
    o.scenes.resize(1);
    o.foveas.resize(1);
    o.modes.resize(1);
    o.staleStats = false;
    o.qualityMetrics = false;  // this sweep is about time and bytes: no read-back, no error metrics
    std::vector<eval::ScalingStep> steps;
    for (const cli::Size& size : sizes) {
        eval::BenchOptions so = o;
        so.width = size.width;
        so.height = size.height;
        const std::string name = std::to_string(size.width) + "x" + std::to_string(size.height);
        const std::string dir = out + "/" + name;
        std::filesystem::create_directories(dir);
        so.cropDir = "";
        std::printf("wrsfov-bench: scaling %s per eye, %d frames per cell -> %s\n", name.c_str(), so.frames,
                    dir.c_str());
        const auto start = std::chrono::steady_clock::now();
        eval::DeviceSweepStats stats;
        auto results = eval::runDeviceSweep(ctx, so, &stats);
        if (!results) {
            std::fprintf(stderr, "wrsfov-bench: %s\n", results.error().message.c_str());
            return 1;
        }
        std::printf("wrsfov-bench: %s done in %.1f s (%d frames rendered on the device, %d uploaded, %d frame ends)\n",
                    name.c_str(), std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(),
                    stats.rendered, stats.uploads, stats.submitted);
        if (Status s = eval::writeReport(*results, so, dir, ctx.deviceName()); !s) {
            std::fprintf(stderr, "wrsfov-bench: %s\n", s.message().c_str());
            return 1;
        }
        steps.push_back({size.width, size.height, *results});
    }
    CostModelRun cost;
    if (!costTargets.empty()) {
        std::vector<std::pair<uint32_t, uint32_t>> cellSizes;
        for (const cli::Size& size : sizes) cellSizes.emplace_back(size.width, size.height);
        cost = runCostModel(o, costTargets, cellSizes, out, &ctx);
    }
    const int rc = printReport(eval::writeScalingReport(steps, o, out, ctx.deviceName(), cost.section),
                               out + "/scaling.md", "scaling report in " + out + " (scaling.md, scaling.csv, scaling.png)");
    return rc != 0 ? rc : cost.exitCode;
}

// The rows of saving.csv files (eval::readSavingCsv) appended to `rows`; false, with the message on
// stderr, at the first file that cannot be read.
bool readSavingRows(const std::vector<std::string>& files, std::vector<eval::SavingRow>& rows) {
    for (const std::string& f : files) {
        auto r = eval::readSavingCsv(f);
        if (!r) {
            std::fprintf(stderr, "wrsfov-bench: %s\n", r.error().message.c_str());
            return false;
        }
        rows.insert(rows.end(), r->begin(), r->end());
    }
    return true;
}

// Creates a report's directory; false, with the message on stderr, where it cannot.
bool makeOutDir(const std::string& out) {
    std::error_code ec;
    std::filesystem::create_directories(out, ec);
    if (ec) std::fprintf(stderr, "wrsfov-bench: cannot create %s: %s\n", out.c_str(), ec.message().c_str());
    return !ec;
}

// --saving-plot: the rows of saving.csv files as JOD against pixels (eval::writeJodAgainstPixels).
int runSavingPlot(const std::vector<std::string>& files, const std::string& targetText, const std::string& out) {
    std::optional<eval::SavingTarget> target;
    if (!targetText.empty()) {
        auto t = eval::parseSavingTarget(targetText);
        if (!t) {
            std::fprintf(stderr, "wrsfov-bench: %s\n", t.error().message.c_str());
            return 2;
        }
        target = *t;
    }
    std::vector<eval::SavingRow> rows;
    if (!readSavingRows(files, rows) || !makeOutDir(out)) return 1;
    return printReport(eval::writeJodAgainstPixels(rows, target, out), out + "/jod_vs_pixels.md",
                       "JOD against pixels in " + out + " (jod_vs_pixels.md, jod_vs_pixels.png)");
}

// --study: the rows of every run of the moving-content study, grouped and paired (eval::writeStudyReport).
int runStudy(const std::vector<std::string>& files, const std::string& out) {
    std::vector<eval::SavingRow> rows;
    if (!readSavingRows(files, rows)) return 1;
    auto study = eval::summarizeStudy(rows);
    if (!study) {
        std::fprintf(stderr, "wrsfov-bench: %s\n", study.error().message.c_str());
        return 1;
    }
    if (!makeOutDir(out)) return 1;
    return printReport(eval::writeStudyReport(*study, out), out + "/study.md",
                       "study in " + out + " (study.md, study.csv, study.png) from " + std::to_string(files.size()) +
                           " runs");
}

// The names an option takes for `values`: the enums' own names.
template <typename T>
std::vector<std::pair<std::string, T>> named(std::span<const T> values) {
    std::vector<std::pair<std::string, T>> out;
    for (T v : values) out.emplace_back(std::string(toString(v)), v);
    return out;
}
template <typename T>
std::vector<std::pair<std::string, T>> named(std::initializer_list<T> values) {
    return named(std::span<const T>(values.begin(), values.size()));
}
template <typename T, size_t N>
std::vector<std::pair<std::string, T>> named(const T (&values)[N]) {
    return named(std::span<const T>(values));
}

}  // namespace

int main(int argc, char** argv) {
    if (argc >= 3 && std::string_view(argv[1]) == "--cost-model-child")
        return eval::statisticsChildMain(argv[2], std::vector<std::string>(argv + 3, argv + argc));
    eval::BenchOptions o;
    std::string out = "out/bench";
    std::string writeDir;
    std::vector<cli::Size> scaling;  // --scaling: sizes per eye
    cli::Size size{o.width, o.height};
    bool flicker = false, noJod = false;
    bool quick = false, noStale = false, noSkip = false, dense = false, floorMerge = false, costModel = false,
         noLanded = false, noPhaseMerge = false;
    std::vector<float> taauParams, taauSimpleParams;
    bool steadyFloor = false;
    bool costQuad = false;
    std::vector<std::string> savingPlot, studyFiles;
    std::string savingTarget;
    std::vector<std::string> costTargets{"gfx1100", "vangogh"};
    bool saving = false, noRate = false;
    eval::SavingOptions savingOptions;

    CLI::App app{
        "Run time against error: sweeps scenes x methods x fovea sizes x foveation modes with synthetic gaze, "
        "every method against the unfoveated reference of the same frames, and writes results.csv, table.md, "
        "PNG plots and crops into --out. --sequence evaluates external frames (docs/sequence.md), "
        "--write-sequence writes a built-in scene out as such a directory, --scaling times the methods over "
        "image sizes.",
        "wrsfov-bench"};
    cli::setup(app);
    cli::option(app, "--out", out, cli::text("a directory name", "DIR"),
                "Directory for the report: results.csv, table.md, error_vs_*.png, eta_*.png, crops_*.png; with "
                "--scaling, scaling.md, scaling.csv, scaling.png and each size's report in DIR/WxH.");
    cli::listOption(app, "--scenes", o.scenes,
                cli::list(cli::oneOf(named({eval::SceneKind::Text, eval::SceneKind::Atrium, eval::SceneKind::Dynamic,
                                            eval::SceneKind::Sequence, eval::SceneKind::Photo, eval::SceneKind::Thin}))),
                "Scenes: text (a page of text, reading gaze), atrium and dynamic (3D rooms with depth and motion, "
                "free-viewing gaze), sequence (the frames of --sequence), photo (see --photo), thin (the atrium "
                "with railings, cables and foliage under highlights).");
    cli::option(app, "--photo", o.photoImage, cli::text("an image file, grass or wood", "IMAGE"),
                "Scene photo's image: a PNG or JPEG file (one texel per pixel at the view's centre, repeated "
                "mirrored), or a generated texture: grass (1/f noise with strands, the default) or wood.");
    cli::option(app, "--photo-motion", o.photoMotion,
                cli::oneOf(named({scenes::PhotoMotion::Static, scenes::PhotoMotion::Pan, scenes::PhotoMotion::Turn})),
                "Scene photo's head: static, pan (sideways, parallel to the plane; the default) or turn (yaw).");
    cli::option(app, "--photo-speed", o.photoSpeed, cli::number<float>(-64, 64),
                "Scene photo's pan or turn speed in pixels per frame at the view's centre (default 0.37).")
        ->type_name("PX");
    cli::listOption(app, "--methods", o.methods,
                cli::list(cli::oneOf(named({Method::Fov, Method::FovTaa, Method::WrsPaper, Method::Wrs,
                                            Method::Oracle, Method::OracleQ, Method::Taau, Method::TaauSimple}))),
                "Methods: fov (foveation only), fov+taa (foveation and TAA), wrs-paper (WRS as published), wrs "
                "(quality-aware retention), oracle (keeps whichever of history and candidate is closer to the "
                "reference: the ceiling of a keep-or-replace rule, evaluation only), oracle-q (the oracle keeping "
                "the history only where it is also of higher quality than the candidate: the ceiling of retention "
                "alone, evaluation only), taau (temporal upsampling of jittered quad views as engines ship it, after "
                "FSR 2's design, --taau), taau-simple (the first, simpler upsampler, --taau-simple).");
    cli::listOption(app, "--fovea", o.foveas, cli::list(cli::number<float>(0, 60, cli::Ends::OpenLow)),
                "Fovea diameters in degrees, each in (0, 60].")
        ->type_name("DEG,...");
    cli::listOption(app, "--modes", o.modes,
                cli::list(cli::oneOf(named({FoveationMode::Mip, FoveationMode::Gauss, FoveationMode::None}))),
                "Foveation modes: mip, gauss, none (no foveation).");
    cli::option(app, "--size", size, cli::size(32, 4096), "Image size per eye, W and H in 32..4096.");
    cli::option(app, "--frames", o.frames, cli::integer(2, 100000),
                "Frames per cell at 90 Hz, warm-up included, 2..100000; more than --warmup.");
    cli::option(app, "--warmup", o.warmup, cli::integer(0, 100000),
                "Frames at the start of each cell that count in no timing or metric, 0..100000.");
    cli::option(app, "--heavy-every", o.heavyEvery, cli::integer(1, 100000),
                "SSIM, FLIP and the stale-pixel statistics on every N-th counted frame (1..100000); every counted "
                "frame gets the PSNR-type metrics (PSNR, near-gaze PSNR, eccentricity-weighted MSE) and the "
                "temporal instability.");
    cli::option(app, "--copy-every", o.copyEvery, cli::integer(1, 100000),
                "The copy kernels (one moving the passes' bytes, one the method's floor) after every N-th counted "
                "frame (1..100000), each in a submission of its own.");
    cli::option(app, "--path", o.path,
                cli::oneOf(named(scenes::kCameraPaths)),
                "Camera path of atrium and dynamic: static, lateral (sideways back and forth), turn (head yaw ±25°) "
                "yaw30, yaw60, yaw120 (head yaw at a constant 30, 60, 120 °/s) or look-around (the head follows "
                "gaze shifts of 15-50° every 0.6 s, up to 184 °/s, the gaze with it).");
    cli::option(app, "--change", o.change,
                cli::oneOf(named({ChangeMetric::Off, ChangeMetric::LStar, ChangeMetric::DeltaE94})),
                "The change term of method wrs-paper, its published eq. 7: the history's weight is scaled by one "
                "minus the colour difference between the candidate and the kept sample. off: no change term "
                "(eq. 6 alone); lstar: the CIE L* difference; de94: the CIE ΔE94 colour difference.");
    cli::option(app, "--seed", o.seed, cli::integer<uint32_t>(0, 0xffffffffu),
                "Seed of the synthetic gaze, the text scene's words and WRS's random numbers, 0..4294967295.");
    app.add_flag("--monitor", o.monitor,
                 "The built-in scenes in monitor mode: one symmetric 76x60 degree view as both eyes, instead of "
                 "the stereo HMD views.");
    cli::option(app, "--hmd-fov", o.hmdFovDeg, cli::number<float>(10, 120),
                "HMD stereo (atrium, dynamic) with a symmetric DEG x DEG view per eye, 10..120: the central part "
                "of the HMD's, to reach a pixel density at a size the device can afford.")
        ->type_name("DEG")
        ->default_str("the HMD's own views");
    cli::option(app, "--material-samples", o.materialSamples,
                cli::oneOf(std::vector<std::pair<std::string, uint32_t>>{{"1", 1u}, {"4", 4u}}),
                "Shading samples per pixel of atrium's and dynamic's procedural materials: 4 filters them over "
                "the pixel (as mipmapping filters textures), 1 point-samples them (aliased stripes and checker "
                "edges, which no sub-pixel reprojection can follow).")
        ->type_name("N");
    app.add_flag("--no-stale", noStale,
                 "No stale-pixel statistics, so wrs-paper, wrs and the oracle run without the birth buffers "
                 "(32 B/px of evaluation-only traffic): the passes as an application gets them.");
    app.add_flag("--no-skip", noSkip,
                 "Every pixel through the per-pixel path: no tile classes (fovea, mid and far periphery "
                 "tiles with constant levels, docs/speed.md \"Tiles\"). The output is the same bit for bit; "
                 "the time shows what the classes save.");
    app.add_flag("--dense-retention", dense,
                 "Retention in every tile (no sparse retention, docs/retention.md \"Sparse retention\"): the "
                 "same output bit for bit; the time and bytes show what skipping the far tiles that hold "
                 "nothing sharper saves.");
    app.add_flag("--no-landed", noLanded,
                 "Quad views: retention keeps the composed candidates only, without the wide samples that landed "
                 "near each pixel (CompositorConfig::landedSamples, docs/retention.md \"Landed wide samples\").");
    app.add_flag("--no-phase-merge", noPhaseMerge,
                 "Quad views jittered, wrs: each phase's wide candidate taken fresh under the floor rule instead of "
                 "merged over the phases (CompositorConfig::phaseMerge, docs/retention.md \"Every phase merged\").");
    app.add_flag("--landed-weights", o.landedWeights,
                 "Quad views, wrs: each landed wide sample weighs into its pixel's running mean by its footprint's "
                 "overlap with the pixel rather than equally (CompositorConfig::landedWeights, docs/retention.md "
                 "\"Landed weights\").");
    app.add_option("--steady-display", o.steadyDisplay,
                   "Quad views, wrs: weight of the current frame in the steady display, which filters what retention "
                   "shows in the wide views over time (CompositorConfig::steadyDisplay, docs/retention.md \"Steady "
                   "display\"); 0 turns it off.")
        ->capture_default_str();
    app.add_option("--steady-display-speed", o.steadyDisplaySpeed,
                   "Quad views, wrs: the steady display's full speed in output pixels a frame; a pixel moving faster "
                   "weighs the current frame by the weight times this speed over its own, down to half the weight "
                   "(CompositorConfig::steadyDisplaySpeed, docs/retention.md \"`wrs`'s parameters, searched on the training "
                   "cell\"); 0: one weight at every speed.")
        ->capture_default_str();
    app.add_option("--landed-footprint", o.landedFootprint,
                   "Quad views, wrs: the half-width in wide pixels, at least one output pixel, of the footprint "
                   "within which a landed wide sample is offered to a pixel (CompositorConfig::landedFootprint, "
                   "docs/retention.md \"`wrs`'s parameters, searched on the training cell\"), 0 to 1; 0: one output "
                   "pixel at every density.")
        ->capture_default_str();
    app.add_flag("--steady-floor", steadyFloor,
                 "Filter the floor level (level 4, the far periphery's candidate under wrs's floor rule) over time at "
                 "its own resolution: a steadier far periphery under motion, a softer one, and a lower FovVideoVDP "
                 "score on the scenes measured (docs/retention.md \"The steady floor\").");
    app.add_flag("--floor-merge", floorMerge,
                 "wrs merges equal-quality samples at the floor quality too (the far periphery's running mean, "
                 "which smooths its flicker under motion), with retention in every tile: the rule before sparse "
                 "retention (docs/retention.md \"Sparse retention\").");
    cli::listOption(app, "--taau-simple", taauSimpleParams, cli::list(cli::number<float>(0, 1024, cli::Ends::OpenLow)),
                    "Method taau-simple's gather radius (output pixels), cap of the history's accumulated weight and "
                    "clip box (sigmas) (CompositorConfig::taauSimple; docs/retention.md \"The first baseline: "
                    "taau-simple\").")
        ->type_name("R,W,G")
        ->default_str("1.25,2,20");
    cli::listOption(app, "--taau", taauParams, cli::list(cli::number<float>(0, 1024)),
                    "Method taau's Lanczos-2 kernel scale (wide pixels), cap of the history's accumulated weight, "
                    "still clamp box (sigmas), velocity at which the box is one sigma (output pixels a frame), "
                    "thin-feature lock frames and threshold, luma stability (CompositorConfig::taau; "
                    "docs/retention.md \"The field's baseline: taau\").")
        ->type_name("K,W,B,V,L,T,S")
        ->default_str("0.35,1.5,6,8,8,0.2,0");
    cli::option(app, "--motion-reach", o.motionReachDeg, cli::number<float>(0, 180),
                "Degrees per frame (at the view's centre) beyond which a pixel's motion tracks no kept sample "
                "(docs/retention.md \"Motion reach\"); 0: no limit, the classification reads every far tile's "
                "motion.")
        ->type_name("DEG");
    app.add_flag("--no-jod", noJod,
                 "No FovVideoVDP JOD (eval/fvvdp.h, docs/metrics.md): it is computed per method by default, "
                 "foveated, with the monitor display in monitor mode and for sequences and the HMD display "
                 "otherwise.");
    cli::option(app, "--jod-frames", o.jodFrames, cli::integer(0, 100000),
                "JOD over the last N counted frames of each cell only (the same frames for every method), to "
                "make it cheaper; 0 (the default): every counted frame.")
        ->type_name("N");
    cli::listOption(app, "--fovea-worth", o.worthFoveas, cli::list(cli::number<float>(0, 60, cli::Ends::OpenLow)),
                "The fovea each method at the first --fovea is worth: fov also runs at these fovea diameters "
                "(e.g. 7.5,10,12.5,15) in the first fovea's cell, submitted and scored over the JOD frames only, and "
                "the report gives the fov fovea whose JOD (and near-gaze PSNR) equals each method's "
                "(fovea_worth.csv, table.md). Needs JOD.")
        ->type_name("DEG,...");
    cli::option(app, "--write-outputs", o.outputsDir, cli::text("a directory name", "DIR"),
                "Write what the metrics score: every method's output and the reference as PNG over the counted "
                "frames, DIR/SCENE_MODE_FOVEA/{reference,METHOD}/L/NNNNNN.png (and R/ in HMD stereo), with gaze.csv "
                "(the gaze in pixels per frame) and view.csv (fov tangents, display, fps); docs/metrics.md. With --saving: "
                "every composition's output over the JOD frames, DIR/SCENE/RUN/{L,R}/NNNNNN.png (RUN: full_fov, the "
                "reference, or INPUT_METHOD_INSET, e.g. quad_wrs_10), and the left eye's gaze.csv.");
    app.add_flag("--quick", quick,
                 "A CI-sized sweep: text and atrium, 160x144, 24 frames with 4 warm-up, fovea 5 and 10, mip "
                 "(options given as well win).");
    cli::listOption(app, "--scaling", scaling, cli::list(cli::squareOrSize(64, 4096)),
                "Time and bytes at sizes per eye, each S (S x S) or WxH with sides in 64..4096 (e.g. "
                "512,2048,1920x2160): one scene, the first fovea and mode, the scene's frames kept on the device "
                "(the atrium rendered into the compositors' inputs, another scene uploaded once per distinct "
                "frame), the passes and copy kernels timed, nothing read back and no error metrics; unless given, "
                "scene atrium, methods fov,fov+taa,wrs, 20 frames with 5 warm-up. Writes scaling.md, scaling.csv, "
                "scaling.png.")
        ->type_name("S|WxH,...");
    app.add_flag("--cost-model", costModel,
                 "A static cost estimate instead of a sweep (with --scaling: after it, into the same report): every "
                 "pipeline of the first scene, mode and fovea compiled for each --cost-targets device, and the "
                 "compiler's statistics, the passes' bytes and the cell's tile classes as a roofline estimate per "
                 "pass for the GPUs of docs/speed.md \"Cost model\", at each GPU's HMD size and the --size or "
                 "--scaling sizes given. Unless given: scene atrium, methods fov,fov+taa,wrs-paper,wrs, mode mip. "
                 "Writes cost_model.csv and cost_model.md; a target without a device or statistics is skipped "
                 "with the reason.");
    app.add_flag("--cost-quad", costQuad,
                 "--cost-model: frames submitted as quad views instead of foveated by the compositor, as --saving renders "
                 "the atrium: wide views at --wide-scale, an inset of the first --inset-degs, jittered over --jitter "
                 "phases; the compose pass and the passes after it per method (methods default fov,taau,wrs).");
    cli::listOption(app, "--cost-targets", costTargets, cli::list(cli::text("a target", "T")),
                "Devices the --cost-model compiles for: a RADV family (gfx1100, vangogh: Mesa's null device, no GPU "
                "needed) or device:NAME (a Vulkan device whose name contains NAME); each needs an entry with public "
                "figures in the model's GPU table.")
        ->type_name("T,...")
        ->default_str("gfx1100,vangogh");
    cli::option(app, "--sequence", o.sequenceDir, cli::text("a directory name", "DIR"),
                "Evaluate the frames of a sequence directory (docs/sequence.md) as scene `sequence` (alone unless "
                "--scenes is given); size, frames and fps come from its sequence.json, gaze from its gaze.csv "
                "(synthetic free viewing without one).");
    app.add_flag("--flicker", flicker,
                 "Where wrs's output changes more than fov's from frame to frame (the temporal instability's "
                 "pixels, split by what wrs showed: its candidate or a kept sample by quality, and state changes), "
                 "for the first scene, mode and fovea: flicker.md, flicker.csv and flicker.png in --out.");
    app.add_flag("--saving", saving,
                 "What rendering foveated saves (docs/metrics.md, \"Rendering saved\"): the first scene (atrium, dynamic, text or photo) "
                 "rendered at full resolution, as quad views with an inset on the gaze (--inset-degs, wide views at "
                 "--wide-scale of the display's density) and at gaze-centred shading rates, each composed with fov, wrs, "
                 "the oracle and the retention oracle oracle-q (--methods, unless given), against the full-resolution render: pixels rendered, render "
                 "and composition time, JOD, near-gaze PSNR, eta. Writes saving.csv, saving.md and saving.png in --out.");
    cli::listOption(app, "--inset-degs", savingOptions.insetDegs, cli::list(cli::number<float>(0, 170, cli::Ends::OpenLow)),
                "--saving: inset sizes across in degrees (quad views), and the 1x1 region's diameter (rate maps).")
        ->type_name("DEG,...")
        ->default_str("5,10,15,20,30");
    cli::option(app, "--wide-scale", savingOptions.wideScale, cli::number<float>(0, 1, cli::Ends::OpenLow),
                "--saving: the wide views' pixel density relative to the display's (default 0.4, i.e. 1/2.5).");
    cli::option(app, "--jitter", savingOptions.jitterPhases, cli::integer<uint32_t>(0, 64),
                "--saving: render the wide views jittered for temporal upsampling: each frame's projection shifted by "
                "a sub-pixel offset, Halton (2, 3) over N phases (0: none), the atrium's textures sampled at the "
                "display's density; the compositor places each sample where it was taken.")
        ->type_name("N");
    app.add_flag("--no-rate", noRate, "--saving: quad views only, no shading-rate rows.");
    cli::listOption(app, "--saving-plot", savingPlot, cli::list(cli::text("a saving.csv path", "CSV")),
                "Instead of a study: JOD against the share of full resolution's pixels from saving.csv files of "
                "--saving studies of one scene and size, one curve per method and input (jittered quad views "
                "apart), and the fewest pixels at which each curve reaches --saving-target. Writes "
                "jod_vs_pixels.png and jod_vs_pixels.md in --out; needs no device.")
        ->type_name("CSV,...");
    cli::listOption(app, "--study", studyFiles, cli::list(cli::text("a saving.csv path", "CSV")),
                "Instead of a study: the moving-content study's summary from the saving.csv files of its runs (one "
                "a cell, seed and configuration; tools/run-study.sh): cells by scene, head path and split, wrs "
                "against taau, fov and taau-simple paired over seeds with 95 % intervals, the pixels each needs to "
                "reach the cell's target, the goals on the test cells. Writes study.md, study.csv and study.png in "
                "--out; needs no device.")
        ->type_name("CSV,...");
    cli::option(app, "--saving-target", savingTarget, cli::text("a target", "METHOD,DENSITY,INSET[,JITTER]"),
                "--saving-plot: the row whose JOD the curves must reach, e.g. fov,0.4,30 (fov on unjittered quad "
                "views at wide density 0.4 with a 30-degree inset; JITTER > 1: the jittered views' row).");
    app.add_flag("--outcomes", savingOptions.outcomes,
                 "--saving: count what the retention rule did at each pixel (kept, changed, merged, ...) for wrs and "
                 "the oracle on quad views, by whether the history was sharper than the floor: the CPU reference steps "
                 "beside each composition (as costly again as the study). outcomes.csv and a table in saving.md.");
    cli::option(app, "--split", savingOptions.split,
                cli::oneOf(std::vector<std::pair<std::string, std::string>>{{"train", "train"}, {"test", "test"}}),
                "--saving: the part of a study this run is, written to saving.csv's split column: train (where "
                "parameters are chosen) or test (where figures are reported; the default).")
        ->type_name("SPLIT");
    cli::listOption(app, "--rate-degs", savingOptions.rateDegs, cli::list(cli::number<float>(0, 170, cli::Ends::OpenLow)),
                "--saving: the shading-rate rows' 1x1-region diameters in degrees (default: --inset-degs).")
        ->type_name("DEG,...");
    cli::option(app, "--write-sequence", writeDir, cli::text("a directory name", "DIR"),
                "Write one scene (frames, depth, motion, the sweep's gaze) as a sequence directory and exit; "
                "give the scene with --scenes NAME.");
    cli::addConfig(app);
    if (auto rc = cli::parseOrExit(app, argc, argv)) return *rc;

    auto given = [&](const char* name) { return app.count(name) > 0; };
    const bool scenesGiven = given("--scenes"), sizeGiven = given("--size"), framesGiven = given("--frames"),
               warmupGiven = given("--warmup"), methodsGiven = given("--methods");
    o.width = size.width;
    o.height = size.height;
    o.staleStats = !noStale;
    o.skipTiles = !noSkip;
    o.sparseRetention = !dense;
    o.landedSamples = !noLanded;
    o.phaseMerge = !noPhaseMerge;
    if (!taauSimpleParams.empty()) {
        if (taauSimpleParams.size() != 3) {
            std::fprintf(stderr, "wrsfov-bench: --taau-simple takes three values: radius, weight cap, clip box\n");
            return 2;
        }
        o.taauSimple = {taauSimpleParams[0], taauSimpleParams[1], taauSimpleParams[2]};
    }
    if (!taauParams.empty()) {
        if (taauParams.size() != 7) {
            std::fprintf(stderr, "wrsfov-bench: --taau takes seven values: kernel scale, weight cap, still box, "
                                 "full velocity, lock frames, lock threshold, luma stability\n");
            return 2;
        }
        o.taau = {taauParams[0], taauParams[1], taauParams[2], taauParams[3],
                  taauParams[4], taauParams[5], taauParams[6]};
    }
    o.floorMerge = floorMerge;
    o.steadyFloor = steadyFloor;
    o.jod = !noJod;
    if (noJod && !o.worthFoveas.empty()) return cli::usageError(app, "--fovea-worth needs JOD: drop --no-jod");
    if (quick) {
        if (!scenesGiven) o.scenes = {eval::SceneKind::Text, eval::SceneKind::Atrium};
        if (!sizeGiven) o.width = 160, o.height = 144;
        if (!framesGiven) o.frames = 24;
        if (!warmupGiven) o.warmup = 4;
        if (!given("--fovea")) o.foveas = {5.0f, 10.0f};
        if (!given("--modes")) o.modes = {FoveationMode::Mip};
    }
    if (given("--scaling") && scaling.empty()) return cli::usageError(app, "--scaling needs at least one size");
    if (!o.outputsDir.empty() && (!scaling.empty() || costModel || flicker || !writeDir.empty()))
        return cli::usageError(app, "--write-outputs writes a sweep's outputs: not with --scaling, --cost-model, "
                                    "--flicker or --write-sequence");
    if (!o.sequenceDir.empty()) {
        // The sequence brings its own size and length.
        auto info = eval::readSequenceInfo(o.sequenceDir);
        if (!info) {
            std::fprintf(stderr, "wrsfov-bench: %s\n", info.error().message.c_str());
            return 1;
        }
        if (!scenesGiven) o.scenes.clear();
        if (std::find(o.scenes.begin(), o.scenes.end(), eval::SceneKind::Sequence) == o.scenes.end())
            o.scenes.push_back(eval::SceneKind::Sequence);
        if (!sizeGiven) o.width = info->width, o.height = info->height;
        if (!framesGiven) o.frames = int(info->frameCount);
        if (!warmupGiven) o.warmup = std::min(o.warmup, o.frames / 2);
    }
    if (std::find(o.scenes.begin(), o.scenes.end(), eval::SceneKind::Sequence) != o.scenes.end() &&
        o.sequenceDir.empty())
        return cli::usageError(app, "scene 'sequence' needs --sequence DIR");
    if (!writeDir.empty() && o.scenes.size() != 1)
        return cli::usageError(app, "--write-sequence writes one scene: give --scenes NAME (or --sequence DIR)");
    if (o.scenes.empty() || o.methods.empty() || o.foveas.empty() || o.modes.empty())
        return cli::usageError(app, "scenes, methods, fovea sizes and modes must not be empty");
    if (writeDir.empty() && o.frames <= o.warmup) return cli::usageError(app, "--frames must exceed --warmup");
    if (!savingPlot.empty()) return runSavingPlot(savingPlot, savingTarget, out);
    if (!studyFiles.empty()) return runStudy(studyFiles, out);
    if (!savingTarget.empty()) return cli::usageError(app, "--saving-target is --saving-plot's: give the files to plot");
    // --write-sequence, --flicker and --saving: one Vulkan context, progress lines on stdout.
    std::unique_ptr<vk::Context> toolCtx;
    if (!writeDir.empty() || flicker || saving) {
        auto ctx = vk::Context::create();
        if (!ctx) {
            std::fprintf(stderr, "wrsfov-bench: %s\n", ctx.error().message.c_str());
            return 1;
        }
        toolCtx = std::move(*ctx);
        o.progress = [](const std::string& s) {
            std::printf("%s\n", s.c_str());
            std::fflush(stdout);
        };
    }
    if (!writeDir.empty()) {
        std::printf("wrsfov-bench: writing %s, %ux%u per eye, %d frames -> %s\n",
                    std::string(eval::toString(o.scenes[0])).c_str(), o.width, o.height, o.frames, writeDir.c_str());
        if (Status s = eval::writeSceneSequence(*toolCtx, o.scenes[0], o, writeDir); !s) {
            std::fprintf(stderr, "wrsfov-bench: %s\n", s.message().c_str());
            return 1;
        }
        std::printf("wrsfov-bench: sequence in %s (sequence.json, NNNNNN_{L,R}_*, gaze.csv)\n", writeDir.c_str());
        return 0;
    }
    if (saving) {
        if (!scenesGiven) o.scenes = {eval::SceneKind::Atrium};
        if (!methodsGiven) o.methods = {Method::Fov, Method::Wrs, Method::Oracle, Method::OracleQ};
        savingOptions.bench = o;
        savingOptions.methods = o.methods;
        savingOptions.rate = !noRate;
        savingOptions.jod = !noJod;
        std::printf("wrsfov-bench: rendering saved, %s, %ux%u per eye, %d frames -> %s\n",
                    std::string(eval::toString(o.scenes[0])).c_str(), o.width, o.height, o.frames, out.c_str());
        auto rows = eval::runSaving(*toolCtx, o.scenes[0], savingOptions);
        if (!rows) {
            std::fprintf(stderr, "wrsfov-bench: %s\n", rows.error().message.c_str());
            return 1;
        }
        return printReport(eval::writeSavingReport(*rows, savingOptions, out, toolCtx->deviceName()), out + "/saving.md",
                           "rendering saved in " + out + " (saving.md, saving.csv, saving.png)");
    }
    if (flicker) {
        auto r = eval::analyseFlicker(*toolCtx, o, out);
        if (!r) {
            std::fprintf(stderr, "wrsfov-bench: %s\n", r.error().message.c_str());
            return 1;
        }
        std::printf("wrsfov-bench: temporal instability wrs %.6f, fov %.6f over %llu stable pixel pairs; %s/flicker.md\n",
                    r->wrsInstability, r->fovInstability, (unsigned long long)r->stablePairs, out.c_str());
        return 0;
    }
    if (costQuad && savingOptions.insetDegs.empty()) return cli::usageError(app, "--cost-quad needs an --inset-degs size");
    if (costQuad && (!costModel || !scaling.empty()))
        return cli::usageError(app, "--cost-quad is a --cost-model cell of its own: not without --cost-model, not with --scaling");
    if (costModel) {
        if (!scenesGiven) o.scenes = {eval::SceneKind::Atrium};
        if (!methodsGiven)
            o.methods = costQuad ? std::vector<Method>{Method::Fov, Method::Taau, Method::Wrs}
                                 : std::vector<Method>{Method::Fov, Method::FovTaa, Method::WrsPaper, Method::Wrs};
        if (!given("--modes")) o.modes = {FoveationMode::Mip};
    } else {
        costTargets.clear();
    }
    if (!makeOutDir(out)) return 1;
    if (costModel && scaling.empty()) {
        // Nothing runs on this machine's device: the pipelines compile on the targets'.
        std::vector<std::pair<uint32_t, uint32_t>> sizes;
        if (sizeGiven) sizes.emplace_back(o.width, o.height);
        // A device of this machine only to measure sparse retention's share of retention tiles.
        auto ctx = vk::Context::create();
        std::optional<QuadCostCell> quad;
        if (costQuad)
            quad = QuadCostCell{savingOptions.wideScale, savingOptions.insetDegs.front(), savingOptions.jitterPhases};
        return runCostModel(o, costTargets, sizes, out, ctx ? ctx->get() : nullptr, quad).exitCode;
    }
    auto ctx = vk::Context::create();
    if (!ctx) {
        std::fprintf(stderr, "wrsfov-bench: %s\n", ctx.error().message.c_str());
        return 1;
    }
    const auto t0 = std::chrono::steady_clock::now();
    o.progress = [&](const std::string& s) {
        double el = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        std::printf("[%6.1f s] %s\n", el, s.c_str());
        std::fflush(stdout);
    };
    if (!scaling.empty())
        return runScaling(**ctx, o, scaling, out, framesGiven, warmupGiven, scenesGiven, methodsGiven, costTargets);
    o.cropDir = out;
    std::printf("wrsfov-bench: device %s, %ux%u per eye, %d frames per cell -> %s\n", (*ctx)->deviceName().c_str(),
                o.width, o.height, o.frames, out.c_str());
    auto results = eval::runBench(**ctx, o);
    if (!results) {
        std::fprintf(stderr, "wrsfov-bench: %s\n", results.error().message.c_str());
        return 1;
    }
    return printReport(eval::writeReport(*results, o, out, (*ctx)->deviceName()), out + "/table.md",
                       "report in " + out + " (results.csv, table.md, error_vs_*.png, crops_*.png)");
}
