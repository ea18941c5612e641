// wrsfov-bench: run time against error. Sweeps scenes x methods x fovea sizes x foveation modes
// with synthetic gaze, and writes results.csv, table.md, PNG plots and crops into --out.
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "eval/bench.h"

using namespace wrsfov;

namespace {

void usage() {
    std::printf(
        "usage: wrsfov-bench [--out DIR] [--scenes text,atrium,dynamic] [--methods fov,fov+taa,wrs]\n"
        "                    [--fovea 5,7.5,10] [--modes mip,gauss] [--size WxH] [--frames N] [--warmup N]\n"
        "                    [--heavy-every N] [--path static|lateral|turn] [--change off|lstar|de94] [--seed N]\n"
        "                    [--quick]\n"
        "--quick: a CI-sized sweep (text and atrium, 160x144, 24 frames, fovea 5 and 10, mip).\n");
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

}  // namespace

int main(int argc, char** argv) {
    eval::BenchOptions o;
    std::string out = "out/bench";
    std::string err;
    for (int i = 1; i < argc && err.empty(); ++i) {
        std::string a = argv[i];
        if (a == "--help" || a == "-h") {
            usage();
            return 0;
        }
        if (a == "--quick") {
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
        } else if (a == "--scenes") {
            o.scenes.clear();
            for (auto& s : split(v)) {
                auto k = eval::parseScene(s);
                if (!k) err = "unknown scene '" + s + "' (text, atrium, dynamic)";
                else o.scenes.push_back(*k);
            }
        } else if (a == "--methods") {
            o.methods.clear();
            for (auto& s : split(v)) {
                if (s == "fov") o.methods.push_back(Method::Fov);
                else if (s == "fov+taa") o.methods.push_back(Method::FovTaa);
                else if (s == "wrs") o.methods.push_back(Method::Wrs);
                else err = "unknown method '" + s + "' (fov, fov+taa, wrs)";
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
            o.width = w;
            o.height = h;
        } else if (a == "--frames") {
            if (!parseInt(v, 2, 100000, n)) err = "--frames wants 2..100000";
            o.frames = int(n);
        } else if (a == "--warmup") {
            if (!parseInt(v, 0, 100000, n)) err = "--warmup wants a non-negative integer";
            o.warmup = int(n);
        } else if (a == "--heavy-every") {
            if (!parseInt(v, 1, 100000, n)) err = "--heavy-every wants a positive integer";
            o.heavyEvery = int(n);
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
            std::string p = v;
            if (p == "static") o.path = scenes::CameraPath::Static;
            else if (p == "lateral") o.path = scenes::CameraPath::Lateral;
            else if (p == "turn") o.path = scenes::CameraPath::Turn;
            else err = "unknown camera path '" + p + "' (static, lateral, turn)";
        } else {
            err = "unknown option " + a;
        }
    }
    if (err.empty() && (o.scenes.empty() || o.methods.empty() || o.foveas.empty() || o.modes.empty()))
        err = "scenes, methods, fovea sizes and modes must not be empty";
    if (err.empty() && o.frames <= o.warmup) err = "--frames must exceed --warmup";
    if (!err.empty()) {
        std::fprintf(stderr, "wrsfov-bench: %s\n", err.c_str());
        usage();
        return 2;
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
    o.cropDir = out;
    o.progress = [&](const std::string& s) {
        double el = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        std::printf("[%6.1f s] %s\n", el, s.c_str());
        std::fflush(stdout);
    };
    std::printf("wrsfov-bench: device %s, %ux%u per eye, %d frames per cell -> %s\n", (*ctx)->deviceName().c_str(),
                o.width, o.height, o.frames, out.c_str());
    auto results = eval::runBench(**ctx, o);
    if (!results) {
        std::fprintf(stderr, "wrsfov-bench: %s\n", results.error().message.c_str());
        return 1;
    }
    if (Status s = eval::writeReport(*results, o, out, (*ctx)->deviceName()); !s) {
        std::fprintf(stderr, "wrsfov-bench: %s\n", s.message().c_str());
        return 1;
    }
    std::ifstream table(out + "/table.md");
    std::printf("%s", std::string(std::istreambuf_iterator<char>(table), {}).c_str());
    std::printf("\nwrsfov-bench: report in %s (results.csv, table.md, error_vs_*.png, crops_*.png)\n", out.c_str());
    return 0;
}
