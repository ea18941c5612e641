// wrsfov-stress: long runs of the reservoir update over adversarial streams, on the CPU reference
// (every storage format of the precision study) and on the GPU in lockstep with the reference.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "compositor/vk_context.h"
#include "stress/report.h"
#include "stress/retain_stress.h"

namespace st = wrsfov::stress;

namespace {

constexpr const char* kUsage = R"(usage: wrsfov-stress [options]

Runs the adversarial streams through the shared reservoir update (shaders/wrs_common.h) on the CPU
for every storage format of the precision study, then through the compositor on the GPU in lockstep
with the CPU reference, and prints a Markdown report to stdout (progress goes to stderr). Exits 0
when every check passes, 1 when one fails or the run cannot be done, 2 for bad arguments.

options:
  --frames N        CPU frames per stream (default 1000000; 0 skips the CPU run)
  --gpu-frames N    GPU frames (default 10000; 0 skips the GPU run)
  --pixels N        CPU pixels per stream (default 64)
  --gpu-width N     GPU pixels per row, i.e. per stream and eye (default 16)
  --streams a,b     CPU streams (default all): )";

constexpr const char* kUsage2 = R"(
  --formats a,b     storage formats (default all; `chosen` is the shipping layout): )";

constexpr const char* kUsage3 = R"(
  --seed N          seed of the random numbers and of the stream content (default 1)
  --threads N       CPU threads (default: one per core)
  --out DIR         also write report.md, report.csv, horizon.csv, gpu.csv and wsum_<stream>.png
  --quick           100000 CPU frames, 16 pixels, 300 GPU frames, horizon study for w = 1 only
  --help            this text
)";

std::string join(const std::vector<std::string>& v) {
    std::string s;
    for (const auto& x : v) s += (s.empty() ? "" : ",") + x;
    return s;
}

void usage(FILE* f) {
    std::vector<std::string> fmts;
    for (const auto& x : st::formats()) fmts.emplace_back(x.name);
    std::fprintf(f, "%s%s%s%s%s", kUsage, join(st::streamNames()).c_str(), kUsage2, join(fmts).c_str(), kUsage3);
}

int usageError(const std::string& msg) {
    std::fprintf(stderr, "wrsfov-stress: %s (see wrsfov-stress --help)\n", msg.c_str());
    return 2;
}

// A non-negative integer, written plainly or as 1e6.
std::optional<uint64_t> parseCount(const std::string& s, uint64_t max) {
    if (s.empty() || s[0] == '-' || s[0] == '+') return std::nullopt;
    char* end = nullptr;
    const double v = std::strtod(s.c_str(), &end);
    if (*end != '\0' || !std::isfinite(v) || v < 0 || v != std::floor(v) || v > double(max)) return std::nullopt;
    return uint64_t(v);
}

std::vector<std::string> splitList(const std::string& s) {
    std::vector<std::string> out;
    size_t a = 0;
    for (;;) {
        const size_t b = s.find(',', a);
        out.push_back(s.substr(a, b == std::string::npos ? std::string::npos : b - a));
        if (b == std::string::npos) break;
        a = b + 1;
    }
    return out;
}

void progress(const st::Progress& p) {
    std::fprintf(stderr, "[%s] %3.0f %%  %7.1f s  %.3g frames/s\n", p.phase, p.fraction * 100.0, p.elapsed_s,
                 p.framesPerSecond);
}

}  // namespace

int main(int argc, char** argv) {
    uint64_t frames = 1000000, gpuFrames = 10000, pixels = 64, gpuWidth = 16, seed = 1, threads = 0;
    bool quick = false;
    std::optional<std::string> out;
    std::vector<std::string> streams;
    std::vector<st::FormatId> formats;
    std::set<std::string> given;
    std::string commandLine = "wrsfov-stress";

    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        commandLine += " " + a;
        if (a == "--help" || a == "-h") {
            usage(stdout);
            return 0;
        }
        if (a == "--quick") {
            quick = true;
            continue;
        }
        static const std::set<std::string> withValue = {"--frames",    "--gpu-frames", "--pixels",
                                                        "--gpu-width", "--streams",    "--formats",
                                                        "--seed",      "--threads",    "--out"};
        if (!withValue.count(a)) return usageError("unknown option '" + a + "'");
        if (i + 1 >= argc) return usageError(a + " needs a value");
        const std::string v = argv[++i];
        commandLine += " " + v;
        if (!given.insert(a).second) return usageError(a + " given twice");
        auto count = [&](uint64_t& dst, uint64_t lo, uint64_t hi) {
            auto c = parseCount(v, hi);
            if (!c || *c < lo) return false;
            dst = *c;
            return true;
        };
        const std::string range = " must be an integer";
        if (a == "--frames") {
            if (!count(frames, 0, 0xffffffffull) || frames == 1)
                return usageError("--frames '" + v + "'" + range + ", 0 or 2..4294967295");
        } else if (a == "--gpu-frames") {
            if (!count(gpuFrames, 0, 0xffffffffull)) return usageError("--gpu-frames '" + v + "'" + range + " >= 0");
        } else if (a == "--pixels") {
            if (!count(pixels, 1, 65536)) return usageError("--pixels '" + v + "'" + range + " in 1..65536");
        } else if (a == "--gpu-width") {
            if (!count(gpuWidth, 1, 1024)) return usageError("--gpu-width '" + v + "'" + range + " in 1..1024");
        } else if (a == "--seed") {
            if (!count(seed, 0, 0xffffffffull)) return usageError("--seed '" + v + "'" + range + " in 0..4294967295");
        } else if (a == "--threads") {
            if (!count(threads, 1, 256)) return usageError("--threads '" + v + "'" + range + " in 1..256");
        } else if (a == "--out") {
            if (v.empty()) return usageError("--out needs a directory");
            out = v;
        } else if (a == "--streams") {
            const std::vector<std::string> known = st::streamNames();
            for (const std::string& s : splitList(v)) {
                if (std::find(known.begin(), known.end(), s) == known.end())
                    return usageError("unknown stream '" + s + "' (known: " + join(known) + ")");
                if (std::find(streams.begin(), streams.end(), s) != streams.end())
                    return usageError("stream '" + s + "' listed twice");
                streams.push_back(s);
            }
        } else if (a == "--formats") {
            for (const std::string& s : splitList(v)) {
                auto f = st::parseFormat(s);
                if (!f) return usageError("unknown format '" + s + "'");
                if (std::find(formats.begin(), formats.end(), *f) != formats.end())
                    return usageError("format '" + s + "' listed twice");
                formats.push_back(*f);
            }
        }
    }
    if (quick) {
        if (!given.count("--frames")) frames = 100000;
        if (!given.count("--gpu-frames")) gpuFrames = 300;
        if (!given.count("--pixels")) pixels = 16;
    }
    if (frames == 0 && gpuFrames == 0) return usageError("nothing to run: --frames and --gpu-frames are both 0");

    const auto t0 = std::chrono::steady_clock::now();
    std::optional<st::HorizonStudy> horizon;
    std::optional<st::CpuResult> cpu;
    std::optional<st::GpuResult> gpu;

    if (frames > 0) {
        std::fprintf(stderr, "[horizon] constant-weight pixels until w_sum stops growing ...\n");
        const auto h0 = std::chrono::steady_clock::now();
        horizon = st::runHorizonStudy(quick);
        std::fprintf(stderr, "[horizon] done in %.1f s\n",
                     std::chrono::duration<double>(std::chrono::steady_clock::now() - h0).count());
        st::CpuOptions o;
        o.frames = frames;
        o.pixels = uint32_t(pixels);
        o.seed = uint32_t(seed);
        o.streams = streams;
        o.formats = formats;
        o.threads = unsigned(threads);
        o.progress = progress;
        std::fprintf(stderr, "[cpu] %llu frames x %llu pixels per stream\n", (unsigned long long)frames,
                     (unsigned long long)pixels);
        auto r = st::runCpu(o);
        if (!r) {
            std::fprintf(stderr, "wrsfov-stress: %s\n", r.error().message.c_str());
            return 1;
        }
        cpu = std::move(*r);
    }
    if (gpuFrames > 0) {
        auto ctx = wrsfov::vk::Context::create();
        if (!ctx) {
            std::fprintf(stderr,
                         "wrsfov-stress: no Vulkan device for the GPU run (%s); use --gpu-frames 0 to skip it\n",
                         ctx.error().message.c_str());
            return 1;
        }
        std::fprintf(stderr, "[gpu] %llu frames on %s\n", (unsigned long long)gpuFrames, (*ctx)->deviceName().c_str());
        st::GpuOptions o;
        o.frames = gpuFrames;
        o.width = uint32_t(gpuWidth);
        o.seed = uint32_t(seed);
        o.progress = progress;
        auto r = st::runGpu(**ctx, o);
        if (!r) {
            std::fprintf(stderr, "wrsfov-stress: GPU run: %s\n", r.error().message.c_str());
            return 1;
        }
        gpu = std::move(*r);
    }

    // Method wrs: the same streams through the tracked layout and the retention rule.
    std::vector<st::RetainStats> retain;
    if (frames > 0) {
        const uint64_t rf = std::min<uint64_t>(frames, quick ? 20000 : 200000);
        std::fprintf(stderr, "[retain] %llu frames x %llu pixels per stream and rule\n", (unsigned long long)rf,
                     (unsigned long long)pixels);
        retain = st::runRetainStress(rf, uint32_t(pixels), uint32_t(seed));
    }

    st::ReportInput in;
    in.cpu = cpu ? &*cpu : nullptr;
    in.gpu = gpu ? &*gpu : nullptr;
    in.horizon = horizon ? &*horizon : nullptr;
    in.checks = st::evaluate(in.cpu, in.gpu);
    in.commandLine = commandLine;
    in.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    const std::string retainMd = retain.empty() ? std::string() : st::retainMarkdown(retain);
    std::fputs((st::markdownReport(in) + retainMd).c_str(), stdout);
    if (out) {
        if (wrsfov::Status s = st::writeReport(in, *out); !s) {
            std::fprintf(stderr, "wrsfov-stress: %s\n", s.message().c_str());
            return 1;
        }
        if (!retain.empty()) {
            std::ofstream(*out + "/report.md", std::ios::app) << retainMd;
            std::ofstream(*out + "/retain.csv") << st::retainCsv(retain);
        }
        std::fprintf(stderr, "report written to %s\n", out->c_str());
    }
    for (const st::Check& c : in.checks)
        if (!c.pass) return 1;
    for (const st::RetainStats& r : retain)
        if (!r.pass()) return 1;
    return 0;
}
