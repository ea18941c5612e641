// wrsfov-stress: long runs of the reservoir update over adversarial streams, on the CPU reference
// (every storage format of the precision study) and on the GPU in lockstep with the reference.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <fstream>
#include <numeric>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "compositor/vk_context.h"
#include "stress/report.h"
#include "stress/retain_stress.h"
#include "cli/cli.h"

namespace st = wrsfov::stress;
namespace cli = wrsfov::cli;

namespace {

std::string join(const std::vector<std::string>& v, const char* sep = ", ") {
    std::string s;
    for (const auto& x : v) s += (s.empty() ? "" : sep) + x;
    return s;
}

// A list in which no item may come twice.
template <typename T>
cli::Reader<std::vector<T>> uniqueList(cli::Reader<T> item) {
    cli::Reader<std::vector<T>> r = cli::list(item);
    r.read = [read = r.read, show = item.show](std::string_view text, std::string& why) -> std::optional<std::vector<T>> {
        auto v = read(text, why);
        for (size_t i = 0; v && i < v->size(); ++i)
            if (std::find(v->begin(), v->begin() + i, (*v)[i]) != v->begin() + i) {
                why = "'" + show((*v)[i]) + "' is listed twice";
                return std::nullopt;
            }
        return v;
    };
    return r;
}

void progress(const st::Progress& p) {
    std::fprintf(stderr, "[%s] %3.0f %%  %7.1f s  %.3g frames/s\n", p.phase, p.fraction * 100.0, p.elapsed_s,
                 p.framesPerSecond);
}

}  // namespace

int main(int argc, char** argv) {
    uint64_t frames = 1000000, gpuFrames = 10000, pixels = 64, gpuWidth = 16, seed = 1, threads = 0;
    bool quick = false;
    std::string out;
    std::vector<std::string> streams;
    std::vector<st::FormatId> formats;
    // The command line as given, for the report.
    const std::string commandLine = std::accumulate(argv + std::min(argc, 1), argv + argc, std::string("wrsfov-stress"),
                                                    [](std::string s, const char* a) { return s + " " + a; });

    std::vector<std::pair<std::string, std::string>> streamNames;
    for (const std::string& s : st::streamNames()) streamNames.emplace_back(s, s);
    std::vector<std::pair<std::string, st::FormatId>> formatNames;
    for (const st::FormatInfo& f : st::formats()) formatNames.emplace_back(std::string(f.name), f.id);
    // 0 skips the CPU run; one frame has no history to test.
    cli::Reader<uint64_t> cpuFrames = cli::integer<uint64_t>(0, 0xffffffffu, "0 or an integer in 2..4294967295");
    cpuFrames.read = [read = cpuFrames.read](std::string_view text, std::string& why) -> std::optional<uint64_t> {
        auto v = read(text, why);
        if (v && *v == 1) {
            why = "'" + std::string(text) + "' is not 0 or an integer in 2..4294967295";
            return std::nullopt;
        }
        return v;
    };

    CLI::App app{
        "Runs the adversarial streams through the shared reservoir update (shaders/wrs_common.h) on the CPU for "
        "every storage format of the precision study, then through the compositor on the GPU in lockstep with "
        "the CPU reference, and the same streams through the retention rule of method wrs; prints a Markdown "
        "report to stdout (progress goes to stderr). Exits 0 when every check passes, 1 when one fails or the "
        "run cannot be done, 2 for bad arguments. Integers may be written as 1e6.",
        "wrsfov-stress"};
    cli::setup(app);
    app.option_defaults()->multi_option_policy(CLI::MultiOptionPolicy::Throw);  // an option given twice is refused
    cli::option(app, "--frames", frames, cpuFrames, "CPU frames per stream, 0 (skips the CPU run) or 2..4294967295.");
    cli::option(app, "--gpu-frames", gpuFrames, cli::integer<uint64_t>(0, 0xffffffffu),
                "GPU frames, 0..4294967295 (0 skips the GPU run).");
    cli::option(app, "--pixels", pixels, cli::integer<uint64_t>(1, 65536), "CPU pixels per stream, 1..65536.");
    cli::option(app, "--gpu-width", gpuWidth, cli::integer<uint64_t>(1, 1024),
                "GPU pixels per row, i.e. per stream and eye, 1..1024.");
    cli::option(app, "--streams", streams, uniqueList(cli::oneOf(streamNames)),
                "CPU streams, each at most once: " + join(st::streamNames()) + ".")
        ->default_str("all");
    std::vector<std::string> formatList;
    for (const auto& f : formatNames) formatList.push_back(f.first);
    cli::option(app, "--formats", formats, uniqueList(cli::oneOf(formatNames)),
                "Storage formats, each at most once (`chosen` is the shipping layout): " + join(formatList) + ".")
        ->default_str("all");
    cli::option(app, "--seed", seed, cli::integer<uint64_t>(0, 0xffffffffu),
                "Seed of the random numbers and of the stream content, 0..4294967295.");
    cli::option(app, "--threads", threads, cli::integer<uint64_t>(1, 256), "CPU threads, 1..256.")
        ->default_str("one per core");
    cli::option(app, "--out", out, cli::text("a directory name", "DIR"),
                "Also write report.md, report.csv, horizon.csv, gpu.csv, retain.csv and wsum_<stream>.png there.");
    app.add_flag("--quick", quick,
                 "100000 CPU frames, 16 pixels, 300 GPU frames, horizon study for w = 1 only (options given as "
                 "well win).");
    if (auto rc = cli::parseOrExit(app, argc, argv)) return *rc;

    if (quick) {
        if (!app.count("--frames")) frames = 100000;
        if (!app.count("--gpu-frames")) gpuFrames = 300;
        if (!app.count("--pixels")) pixels = 16;
    }
    if (app.count("--streams") && streams.empty()) return cli::usageError(app, "--streams needs at least one stream");
    if (app.count("--formats") && formats.empty()) return cli::usageError(app, "--formats needs at least one format");
    if (frames == 0 && gpuFrames == 0)
        return cli::usageError(app, "nothing to run: --frames and --gpu-frames are both 0");

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
    if (!out.empty()) {
        if (wrsfov::Status s = st::writeReport(in, out); !s) {
            std::fprintf(stderr, "wrsfov-stress: %s\n", s.message().c_str());
            return 1;
        }
        if (!retain.empty()) {
            std::ofstream(out + "/report.md", std::ios::app) << retainMd;
            std::ofstream(out + "/retain.csv") << st::retainCsv(retain);
        }
        std::fprintf(stderr, "report written to %s\n", out.c_str());
    }
    for (const st::Check& c : in.checks)
        if (!c.pass) return 1;
    for (const st::RetainStats& r : retain)
        if (!r.pass()) return 1;
    return 0;
}
