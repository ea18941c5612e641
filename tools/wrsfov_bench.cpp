// wrsfov-bench: run time against error. Sweeps scenes x methods x fovea sizes x foveation modes
// with synthetic gaze, and writes results.csv, table.md, PNG plots and crops into --out.
// --sequence DIR evaluates external frames (docs/sequence.md); --write-sequence DIR writes a
// built-in scene out as such a directory.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "eval/bench.h"
#include "eval/sequence.h"

using namespace wrsfov;

namespace {

void usage() {
    std::printf(
        "usage: wrsfov-bench [--out DIR] [--scenes text,atrium,dynamic] [--methods fov,fov+taa,wrs-paper,wrs,oracle]\n"
        "                    [--fovea 5,7.5,10] [--modes mip,gauss] [--size WxH] [--frames N] [--warmup N]\n"
        "                    [--heavy-every N] [--copy-every N] [--path static|lateral|turn] [--change off|lstar|de94]\n"
        "                    [--seed N] [--monitor] [--hmd-fov DEG] [--quick] [--sequence DIR] [--no-stale]\n"
        "       wrsfov-bench --scaling 512,1024,2048 [--methods ...] [--scenes NAME] [--frames N] [--monitor] ...\n"
        "       wrsfov-bench --write-sequence DIR --scenes NAME [--size WxH] [--frames N] [--path P] [--seed N]\n"
        "--monitor: the built-in scenes in monitor mode (one symmetric 76x60 degree view as both eyes)\n"
        "  instead of the stereo HMD views.\n"
        "--hmd-fov DEG: HMD stereo (atrium, dynamic) with a symmetric DEG x DEG view per eye, the central part\n"
        "  of the HMD's, to reach a pixel density at a size the device can afford.\n"
        "Defaults: scenes text,atrium,dynamic; every method; fovea 5,7.5,10; modes mip,gauss; 320x288; 90 frames\n"
        "  (10 warm-up); path lateral (atrium, dynamic); change lstar (wrs-paper's eq. 7 term); seed 1.\n"
        "--heavy-every N: SSIM, FLIP and the stale-pixel count on every N-th counted frame (default 10).\n"
        "--copy-every N: the copy kernels (one moving the passes' bytes, one the method's floor) after every\n"
        "  N-th counted frame (default 1), each in a submission of its own.\n"
        "--no-stale: no stale-pixel statistics, so wrs-paper, wrs and the oracle run without the birth\n"
        "  buffers (32 B/px of evaluation-only traffic): the passes as an application gets them.\n"
        "--scaling S1,S2,...: time and bytes at square sizes S per eye (one scene, the first fovea and mode;\n"
        "  defaults: atrium, fov,fov+taa,wrs, 20 frames with 5 warm-up, --no-stale); writes scaling.md,\n"
        "  scaling.csv, scaling.png and each size's report in DIR/SxS.\n"
        "--change: the eq. 7 change term of wrs-paper (off, lstar, de94).\n"
        "--quick: a CI-sized sweep (text and atrium, 160x144, 24 frames, fovea 5 and 10, mip).\n"
        "--sequence DIR: evaluate the frames of a sequence directory (docs/sequence.md) as scene\n"
        "  `sequence` (alone unless --scenes is given); size, frames and fps come from its sequence.json,\n"
        "  gaze from its gaze.csv (synthetic free viewing without one).\n"
        "--write-sequence DIR: write one scene (frames, depth, motion, the sweep's gaze) as a sequence\n"
        "  directory and exit.\n");
}

std::vector<std::string> split(const std::string& s) {
    std::vector<std::string> out;
    std::stringstream ss(s);
    for (std::string item; std::getline(ss, item, ',');)
        if (!item.empty()) out.push_back(item);
    return out;
}

bool parseInt(const char* v, long lo, long hi, long& out) {
    char* end = nullptr;
    out = std::strtol(v, &end, 10);
    return *v && !*end && out >= lo && out <= hi;
}

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

// --scaling: the sweep at each size, stale tracking off, and a scaling table over all of them.
int runScaling(vk::Context& ctx, eval::BenchOptions o, const std::vector<uint32_t>& sizes, const std::string& out,
               bool framesGiven, bool warmupGiven, bool scenesGiven, bool methodsGiven) {
    if (!scenesGiven) o.scenes = {eval::SceneKind::Atrium};
    if (!methodsGiven) o.methods = {Method::Fov, Method::FovTaa, Method::Wrs};
    if (!framesGiven) o.frames = 20;
    if (!warmupGiven) o.warmup = 5;
    o.scenes.resize(1);
    o.foveas.resize(1);
    o.modes.resize(1);
    o.staleStats = false;
    o.heavyEvery = 1000000;  // no SSIM/FLIP: this sweep is about time
    std::vector<eval::ScalingStep> steps;
    for (uint32_t size : sizes) {
        eval::BenchOptions so = o;
        so.width = so.height = size;
        const std::string dir = out + "/" + std::to_string(size) + "x" + std::to_string(size);
        std::filesystem::create_directories(dir);
        so.cropDir = "";
        std::printf("wrsfov-bench: scaling %ux%u per eye, %d frames per cell -> %s\n", size, size, so.frames, dir.c_str());
        auto results = eval::runBench(ctx, so);
        if (!results) {
            std::fprintf(stderr, "wrsfov-bench: %s\n", results.error().message.c_str());
            return 1;
        }
        if (Status s = eval::writeReport(*results, so, dir, ctx.deviceName()); !s) {
            std::fprintf(stderr, "wrsfov-bench: %s\n", s.message().c_str());
            return 1;
        }
        steps.push_back({size, size, *results});
    }
    return printReport(eval::writeScalingReport(steps, o, out, ctx.deviceName()), out + "/scaling.md",
                       "scaling report in " + out + " (scaling.md, scaling.csv, scaling.png)");
}

}  // namespace

int main(int argc, char** argv) {
    eval::BenchOptions o;
    std::string out = "out/bench";
    std::string writeDir;
    std::vector<uint32_t> scaling;  // --scaling: square sizes per eye
    bool methodsGiven = false, scenesGiven = false, sizeGiven = false, framesGiven = false, warmupGiven = false, quick = false;
    std::string err;
    for (int i = 1; i < argc && err.empty(); ++i) {
        std::string a = argv[i];
        if (a == "--help" || a == "-h") {
            usage();
            return 0;
        }
        if (a == "--monitor") {
            o.monitor = true;
            continue;
        }
        if (a == "--no-stale") {
            o.staleStats = false;
            continue;
        }
        if (a == "--quick") {
            quick = true;
            o.width = 160;
            o.height = 144;
            o.frames = 24;
            o.warmup = 4;
            o.heavyEvery = 10;
            o.foveas = {5.0f, 10.0f};
            o.modes = {FoveationMode::Mip};
            continue;
        }
        if (i + 1 >= argc) {
            err = "missing value after " + a;
            break;
        }
        const char* v = argv[++i];
        long n = 0;
        if (a == "--out") {
            out = v;
        } else if (a == "--sequence") {
            o.sequenceDir = v;
        } else if (a == "--write-sequence") {
            writeDir = v;
        } else if (a == "--scenes") {
            scenesGiven = true;
            o.scenes.clear();
            for (auto& s : split(v)) {
                auto k = eval::parseScene(s);
                if (!k) err = "unknown scene '" + s + "' (text, atrium, dynamic, sequence)";
                else o.scenes.push_back(*k);
            }
        } else if (a == "--methods") {
            methodsGiven = true;
            o.methods.clear();
            for (auto& s : split(v)) {
                auto m = parseMethod(s);
                if (!m) err = "unknown method '" + s + "' (fov, fov+taa, wrs-paper, wrs, oracle)";
                else o.methods.push_back(*m);
            }
        } else if (a == "--fovea") {
            o.foveas.clear();
            for (auto& s : split(v)) {
                char* end = nullptr;
                float f = std::strtof(s.c_str(), &end);
                if (*end || !std::isfinite(f) || f <= 0 || f > 60) err = "fovea '" + s + "' is not in (0, 60] degrees";
                else o.foveas.push_back(f);
            }
        } else if (a == "--modes") {
            o.modes.clear();
            for (auto& s : split(v)) {
                if (s == "mip") o.modes.push_back(FoveationMode::Mip);
                else if (s == "gauss") o.modes.push_back(FoveationMode::Gauss);
                else if (s == "none") o.modes.push_back(FoveationMode::None);
                else err = "unknown foveation mode '" + s + "' (mip, gauss, none)";
            }
        } else if (a == "--size") {
            unsigned w = 0, h = 0;
            if (std::sscanf(v, "%ux%u", &w, &h) != 2 || w < 32 || h < 32 || w > 4096 || h > 4096)
                err = "--size wants WxH with 32..4096";
            sizeGiven = true;
            o.width = w;
            o.height = h;
        } else if (a == "--frames") {
            if (!parseInt(v, 2, 100000, n)) err = "--frames wants 2..100000";
            framesGiven = true;
            o.frames = int(n);
        } else if (a == "--warmup") {
            if (!parseInt(v, 0, 100000, n)) err = "--warmup wants a non-negative integer";
            warmupGiven = true;
            o.warmup = int(n);
        } else if (a == "--heavy-every") {
            if (!parseInt(v, 1, 100000, n)) err = "--heavy-every wants a positive integer";
            o.heavyEvery = int(n);
        } else if (a == "--hmd-fov") {
            char* end = nullptr;
            const float d = std::strtof(v, &end);
            if (*end || !std::isfinite(d) || d < 10 || d > 120) err = "--hmd-fov wants degrees in 10..120";
            o.hmdFovDeg = d;
        } else if (a == "--copy-every") {
            if (!parseInt(v, 1, 100000, n)) err = "--copy-every wants a positive integer";
            o.copyEvery = int(n);
        } else if (a == "--scaling") {
            if (split(v).empty()) err = "--scaling wants sizes in 64..4096 (pixels per side, per eye), e.g. 512,1024,2048";
            for (auto& s : split(v)) {
                if (!parseInt(s.c_str(), 64, 4096, n)) {
                    err = "--scaling wants sizes in 64..4096 (pixels per side, per eye), e.g. 512,1024,2048";
                    break;
                }
                scaling.push_back(uint32_t(n));
            }
        } else if (a == "--seed") {
            if (!parseInt(v, 0, 0xffffffffL, n)) err = "--seed wants a non-negative integer";
            o.seed = uint32_t(n);
        } else if (a == "--change") {
            std::string c = v;
            if (c == "off") o.change = ChangeMetric::Off;
            else if (c == "lstar") o.change = ChangeMetric::LStar;
            else if (c == "de94") o.change = ChangeMetric::DeltaE94;
            else err = "unknown change metric '" + c + "' (off, lstar, de94)";
        } else if (a == "--path") {
            if (auto p = scenes::parseCameraPath(v)) o.path = *p;
            else err = "unknown camera path '" + std::string(v) + "' (static, lateral, turn)";
        } else {
            err = "unknown option " + a;
        }
    }
    if (quick && !scenesGiven) o.scenes = {eval::SceneKind::Text, eval::SceneKind::Atrium};
    if (err.empty() && !o.sequenceDir.empty()) {
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
    if (err.empty() && std::find(o.scenes.begin(), o.scenes.end(), eval::SceneKind::Sequence) != o.scenes.end() &&
        o.sequenceDir.empty())
        err = "scene 'sequence' needs --sequence DIR";
    if (err.empty() && !writeDir.empty() && o.scenes.size() != 1)
        err = "--write-sequence writes one scene: give --scenes NAME (or --sequence DIR)";
    if (err.empty() && (o.scenes.empty() || o.methods.empty() || o.foveas.empty() || o.modes.empty()))
        err = "scenes, methods, fovea sizes and modes must not be empty";
    if (err.empty() && writeDir.empty() && o.frames <= o.warmup) err = "--frames must exceed --warmup";
    if (!err.empty()) {
        std::fprintf(stderr, "wrsfov-bench: %s\n", err.c_str());
        usage();
        return 2;
    }
    if (!writeDir.empty()) {
        auto ctx = vk::Context::create();
        if (!ctx) {
            std::fprintf(stderr, "wrsfov-bench: %s\n", ctx.error().message.c_str());
            return 1;
        }
        o.progress = [](const std::string& s) {
            std::printf("%s\n", s.c_str());
            std::fflush(stdout);
        };
        std::printf("wrsfov-bench: writing %s, %ux%u per eye, %d frames -> %s\n",
                    std::string(eval::toString(o.scenes[0])).c_str(), o.width, o.height, o.frames, writeDir.c_str());
        if (Status s = eval::writeSceneSequence(**ctx, o.scenes[0], o, writeDir); !s) {
            std::fprintf(stderr, "wrsfov-bench: %s\n", s.message().c_str());
            return 1;
        }
        std::printf("wrsfov-bench: sequence in %s (sequence.json, NNNNNN_{L,R}_*, gaze.csv)\n", writeDir.c_str());
        return 0;
    }
    std::error_code ec;
    std::filesystem::create_directories(out, ec);
    if (ec) {
        std::fprintf(stderr, "wrsfov-bench: cannot create %s: %s\n", out.c_str(), ec.message().c_str());
        return 1;
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
    if (!scaling.empty()) return runScaling(**ctx, o, scaling, out, framesGiven, warmupGiven, scenesGiven, methodsGiven);
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
