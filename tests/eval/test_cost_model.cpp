// The static cost model (eval/cost_model.h): the pipeline variants against what the compositor
// dispatches, the statistics read by name, the roofline arithmetic, cost_model.csv, and (suite
// CostModelDevice) the statistics process on lavapipe and on RADV's null device.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <optional>
#include <set>
#include <sstream>

#include <unistd.h>

#include "eval/bench.h"
#include "eval/cost_model.h"
#include "shaders/config.h"

using namespace wrsfov;
using namespace wrsfov::eval;

namespace {

VkPipelineExecutableStatisticKHR stat(const char* name, uint64_t v) {
    VkPipelineExecutableStatisticKHR s{VK_STRUCTURE_TYPE_PIPELINE_EXECUTABLE_STATISTIC_KHR};
    std::snprintf(s.name, sizeof(s.name), "%s", name);
    s.format = VK_PIPELINE_EXECUTABLE_STATISTIC_FORMAT_UINT64_KHR;
    s.value.u64 = v;
    return s;
}

// What RADV reports for a compute pipeline (names as Mesa 22.3 gives them), in its order.
std::vector<VkPipelineExecutableStatisticKHR> radvLike(uint64_t inv = 1500) {
    return {stat("Driver pipeline hash", 123),
            stat("SGPRs", 128),
            stat("VGPRs", 72),
            stat("Spilled SGPRs", 0),
            stat("Spilled VGPRs", 2),
            stat("Code size", 13544),
            stat("LDS size", 0),
            stat("Scratch size", 0),
            stat("Subgroups per SIMD", 20),
            stat("Hash", 1),
            stat("Instructions", 2561),
            stat("Copies", 305),
            stat("Branches", 85),
            stat("Latency", 5997),
            stat("Inverse Throughput", inv)};
}

const TrafficInputs kAtrium{512, 512, 4, 4, 8};  // RGBA8 colour, D32F depth, RGBA16F motion

CompositorConfig config(Method m) {
    CompositorConfig c;
    c.method = m;
    c.foveation = FoveationMode::Mip;
    return c;
}

// Made-up statistics for every variant of `methods`, inverse throughput `inv` cycles.
std::map<VariantKey, ExecutableStats> fakeStats(const std::vector<Method>& methods, double inv) {
    std::map<VariantKey, ExecutableStats> stats;
    for (Method m : methods)
        for (const PipelineVariant& v : pipelineVariants(config(m), kAtrium)) {
            ExecutableStats s;
            s.instructions = 100 + double(v.shader) * 10;
            s.vgprs = 32;
            s.wavesPerSimd = 16;
            s.latency = 50;
            s.invThroughput = inv;
            s.subgroupSize = 64;
            stats[{v.shader, v.constants}] = s;
        }
    return stats;
}

const GpuFigures kGpu{"test", "a test GPU", "", 10, 20, 1000.0, 100.0, 512, 512, "made up"};

std::vector<CostRow> rowsFor(const std::vector<Method>& methods, const GpuFigures& gpu = kGpu, double inv = 400) {
    const auto stats = fakeStats(methods, inv);
    std::vector<CostRow> rows;
    for (Method m : methods) {
        CostCell cell{
            &gpu, kAtrium.width, kAtrium.height, 2, m, pipelineVariants(config(m), kAtrium), {0.1, 0.05, 0.15, 0.7}};
        auto r = costRows(cell, stats);
        rows.insert(rows.end(), r.begin(), r.end());
    }
    return rows;
}

std::vector<std::string> split(const std::string& line) {
    std::vector<std::string> out;
    std::stringstream s(line);
    for (std::string f; std::getline(s, f, ',');) out.push_back(f);
    if (!line.empty() && line.back() == ',') out.push_back("");
    return out;
}

}  // namespace

TEST(CostModel, StatisticsAreReadByName) {
    auto s = parseStatistics(radvLike(), 64);
    ASSERT_TRUE(s) << s.error().message;
    EXPECT_EQ(s->instructions, 2561);
    EXPECT_EQ(s->vgprs, 72);
    EXPECT_EQ(s->sgprs, 128);
    EXPECT_EQ(s->wavesPerSimd, 20);
    EXPECT_EQ(s->latency, 5997);
    EXPECT_EQ(s->invThroughput, 1500);
    EXPECT_EQ(s->spilledVgprs, 2);
    EXPECT_EQ(s->subgroupSize, 64u);
    // Another order and other formats read the same.
    auto shuffled = radvLike();
    std::reverse(shuffled.begin(), shuffled.end());
    for (auto& st : shuffled)
        if (std::strcmp(st.name, "Latency") == 0) {
            st.format = VK_PIPELINE_EXECUTABLE_STATISTIC_FORMAT_FLOAT64_KHR;
            st.value.f64 = 5997.0;
        }
    auto t = parseStatistics(shuffled, 32);
    ASSERT_TRUE(t);
    EXPECT_EQ(t->latency, 5997);
    EXPECT_EQ(t->subgroupSize, 32u);
}

TEST(CostModel, MissingStatisticsAreASkipNamingThem) {
    std::vector<VkPipelineExecutableStatisticKHR> other{stat("SGPRs", 10), stat("VGPRs", 20), stat("Instructions", 5)};
    auto s = parseStatistics(other, 64);
    ASSERT_FALSE(s);
    EXPECT_EQ(s.error().code, int(CostError::Unavailable));
    for (const char* name : {"Subgroups per SIMD", "Latency", "Inverse Throughput"})
        EXPECT_NE(s.error().message.find(name), std::string::npos) << s.error().message;
    EXPECT_EQ(s.error().message.find("\"VGPRs\""), std::string::npos) << s.error().message;
    auto none = parseStatistics({}, 64);
    ASSERT_FALSE(none);
    EXPECT_EQ(none.error().code, int(CostError::Unavailable));
}

TEST(CostModel, VariantsMirrorTheDispatches) {
    auto names = [](const std::vector<PipelineVariant>& vs) {
        std::vector<std::string> out;
        for (const PipelineVariant& v : vs) out.push_back(v.pass + "/" + tileClassName(v.tileClass));
        return out;
    };
    using V = std::vector<std::string>;
    EXPECT_EQ(names(pipelineVariants(config(Method::Fov), kAtrium)),
              (V{"classify/whole", "pyramid/whole", "foveate/any", "foveate/fovea", "foveate/mid", "foveate/far"}));
    EXPECT_EQ(names(pipelineVariants(config(Method::Wrs), kAtrium)),
              (V{"reach/whole", "classify/whole", "pyramid/whole", "retain/any", "retain/fovea", "retain/mid",
                 "retain/far", "skip/skip"}));
    CompositorConfig dense = config(Method::Wrs);
    dense.sparseRetention = false;
    EXPECT_EQ(names(pipelineVariants(dense, kAtrium)),
              (V{"classify/whole", "pyramid/whole", "retain/any", "retain/fovea", "retain/mid", "retain/far"}));
    EXPECT_EQ(names(pipelineVariants(config(Method::FovTaa), kAtrium)),
              (V{"pyramid/whole", "foveate/whole", "taa/whole"}));
    EXPECT_EQ(names(pipelineVariants(config(Method::WrsPaper), kAtrium)),
              (V{"pyramid/whole", "foveate/whole", "wrs-paper/whole"}));
    // Constants as endFrame binds them: retain {motion, depth, mode, rule, in place, 1 + class, sparse},
    // classify {mode, sparse, motion, phase} (phase 1: the superblocks of the motion reach), the skip
    // list's foveate {mode, output, -, -, -, 1 + skip}.
    const auto wrs = pipelineVariants(config(Method::Wrs), kAtrium);
    EXPECT_EQ(wrs[0].constants, (SpecConstants{1, 1, 1, 1, 0, 0, 0, 1, 0, 0}));
    EXPECT_EQ(wrs[1].constants, (SpecConstants{1, 1, 1, 0, 0, 0, 0, 1, 0, 0}));
    EXPECT_EQ(wrs[3].constants, (SpecConstants{1, 1, 1, 0, 0, 1, 1, 1, 0, 4}));
    EXPECT_EQ(wrs[6].constants, (SpecConstants{1, 1, 1, 0, 0, 4, 1, 1, 0, 4}));
    EXPECT_EQ(wrs[7].constants, (SpecConstants{1, 1, 0, 0, 0, 5, 0, 1, 0, 4}));
    // 64 x 64 tiles per eye at 512 px: 8 x 8 superblocks, one group of 8 x 8 tiles each.
    EXPECT_EQ(wrs[0].groups, 8u * 8u * 2u);
    const auto still = pipelineVariants(config(Method::Wrs), {512, 512, 4, 4, 0});
    EXPECT_EQ(still[2].constants, (SpecConstants{0, 1, 1, 0, 1, 1, 1, 1, 0, 4})) << "no motion: in place";
    EXPECT_EQ(pipelineVariants(config(Method::Fov), kAtrium)[2].constants,
              (SpecConstants{1, 1, 0, 0, 0, 1, 0, 1, 0, 4}));
    CompositorConfig noSkip = config(Method::Wrs);
    noSkip.skipTiles = false;
    EXPECT_EQ(names(pipelineVariants(noSkip, kAtrium)), (V{"pyramid/whole", "retain/whole"}));
    // Whole-image dispatch shapes: 8x8 groups per pixel pass, 32x32-pixel groups for the mip pyramid.
    EXPECT_EQ(pipelineVariants(noSkip, kAtrium)[1].groups, 64u * 64u * 2u);
    static_assert(WRS_MIP_TILE == 32);
    EXPECT_EQ(pipelineVariants(noSkip, kAtrium)[0].groups, 16u * 16u * 2u);
    // Every pass of traffic() has its variants and their bytes, and nothing else but the classification's.
    // A tile list's variant moves its own pixels' bytes: retention's as if every tile retained, the
    // skipped tiles' as if none did (traffic() weighs the two by the measured share).
    for (Method m : {Method::Fov, Method::FovTaa, Method::WrsPaper, Method::Wrs, Method::Oracle}) {
        TrafficInputs none = kAtrium;
        none.retainShare = 0.0;
        const Traffic t = traffic(config(m), kAtrium), tNone = traffic(config(m), none);
        const auto vs = pipelineVariants(config(m), kAtrium);
        for (const PassTraffic& p : t.passes) {
            int found = 0;
            for (const PipelineVariant& v : vs)
                if (v.pass == p.pass) {
                    ++found;
                    const PassTraffic* q = &p;
                    for (const PassTraffic& n : tNone.passes)
                        if (p.pass == "skip" && n.pass == p.pass) q = &n;
                    if (p.pass != "classify") {
                        EXPECT_DOUBLE_EQ(v.bytesPerPx, q->read + q->write) << p.pass;
                    }
                }
            EXPECT_GT(found, 0) << toString(m) << ": no variant for pass " << p.pass;
        }
        for (const PipelineVariant& v : vs)
            EXPECT_TRUE(
                v.pass == "classify" || v.pass == "reach" ||
                std::any_of(t.passes.begin(), t.passes.end(), [&](const PassTraffic& p) { return p.pass == v.pass; }))
                << v.pass;
    }
}

TEST(CostModel, VariantKeysRoundTrip) {
    for (Method m : {Method::Fov, Method::FovTaa, Method::WrsPaper, Method::Wrs})
        for (const PipelineVariant& v : pipelineVariants(config(m), kAtrium)) {
            const VariantKey k{v.shader, v.constants};
            auto back = parseVariantKey(toString(k));
            ASSERT_TRUE(back) << toString(k);
            EXPECT_EQ(*back, k);
        }
    const VariantKey compose{ShaderId::Compose, {1, 1, 1, 0, 1, 4, 0, 1, 0, 0, 0, 0}};
    EXPECT_EQ(parseVariantKey("compose:1,1,1,0,1,4,0,1,0,0,0,0"), compose);
    EXPECT_FALSE(parseVariantKey("retain:1,2"));
    EXPECT_FALSE(parseVariantKey("copy:0,0,0,0,0,0"));
    EXPECT_FALSE(parseVariantKey("retain:1,1,1,0,0,1,1,1,0,4,0,0,7"));
    EXPECT_FALSE(parseVariantKey("retain:1,1,1,0,0,1,1,1,0,4,0"));
    EXPECT_FALSE(parseStatsTarget("device:"));
    EXPECT_FALSE(parseStatsTarget("GFX 1100"));
    EXPECT_EQ(parseStatsTarget("vangogh")->family, "vangogh");
    EXPECT_EQ(parseStatsTarget("device:7900")->deviceName, "7900");
}

TEST(CostModel, RooflineArithmetic) {
    const auto rows = rowsFor({Method::Fov});
    // pyramid: whole image, 32x32-pixel groups: 16 x 16 x 2 groups of one wave64 each.
    const CostRow& pyr = rows[1];
    ASSERT_EQ(pyr.pass, "pyramid");
    EXPECT_DOUBLE_EQ(pyr.groups, 512);
    EXPECT_DOUBLE_EQ(pyr.aluUs, 512 * 400.0 / 20 / 1000.0);
    EXPECT_DOUBLE_EQ(pyr.memUs, 512.0 * 512 * 2 * pyr.bytesPerPx / (100.0 * 1e3));
    EXPECT_DOUBLE_EQ(pyr.predictedUs, std::max(pyr.aluUs, pyr.memUs));
    EXPECT_DOUBLE_EQ(pyr.cyclesPerPx, 400.0 / 1024);
    // A tile class: its share of the tiles, one group per tile; a dispatch lasts at least one wave's latency.
    const CostRow& fovea = rows[3];
    ASSERT_EQ(fovea.cls, "fovea");
    EXPECT_DOUBLE_EQ(fovea.groups, 0.05 * 64 * 64 * 2);
    EXPECT_NEAR(fovea.share, 0.05, 1e-12);
    EXPECT_DOUBLE_EQ(fovea.aluUs, std::max(409.6 * 400 / 20, 50.0) / 1000.0);
    // A class with no tiles costs nothing.
    CostCell empty{&kGpu, 512, 512, 2, Method::Fov, pipelineVariants(config(Method::Fov), kAtrium), {0, 0, 0, 1}};
    const auto er = costRows(empty, fakeStats({Method::Fov}, 400));
    EXPECT_EQ(er[3].aluUs, 0.0);
    EXPECT_EQ(er[3].memUs, 0.0);
}

// Phases follow endFrame's barriers: the classification overlaps the `mip` pyramid; the tile classes
// of a pass that writes what it does not read run together, those of the in-place retain pass (no
// motion) one after another.
TEST(CostModel, PhasesFollowTheBarriers) {
    auto phases = [](const std::vector<PipelineVariant>& vs) {
        std::vector<int> out;
        for (const PipelineVariant& v : vs) out.push_back(v.phase);
        return out;
    };
    using P = std::vector<int>;
    // classify, pyramid | foveate any, fovea, mid, far
    EXPECT_EQ(phases(pipelineVariants(config(Method::Fov), kAtrium)), (P{0, 0, 1, 1, 1, 1}));
    // reach | classify, pyramid | retain any, fovea, mid, far, skip
    EXPECT_EQ(phases(pipelineVariants(config(Method::Wrs), kAtrium)), (P{0, 1, 1, 2, 2, 2, 2, 2}));
    // No motion: no reach, and the reservoirs are updated in place.
    EXPECT_EQ(phases(pipelineVariants(config(Method::Wrs), {512, 512, 4, 4, 0})), (P{0, 0, 1, 2, 3, 4, 5}));
    CompositorConfig gauss = config(Method::Fov);
    gauss.foveation = FoveationMode::Gauss;
    EXPECT_EQ(phases(pipelineVariants(gauss, kAtrium)), (P{0, 1, 2, 2, 2, 2}));
    // pyramid | foveate | taa
    EXPECT_EQ(phases(pipelineVariants(config(Method::FovTaa), kAtrium)), (P{0, 1, 2}));
}

// A dispatch lasts at least one wave's latency; dispatches with no barrier between them share that floor.
TEST(CostModel, ALatencyFloorPerPhase) {
    const uint64_t px = 512ull * 512 * 2;
    const VariantKey a{ShaderId::Foveate, {1, 1, 0, 0, 0, 2, 0, 1, 0}};
    const VariantKey b{ShaderId::Foveate, {1, 1, 0, 0, 0, 3, 0, 1, 0}};
    std::map<VariantKey, ExecutableStats> stats;
    stats[a].latency = 3000, stats[a].invThroughput = 100;
    stats[b].latency = 1000, stats[b].invThroughput = 100;
    auto cellOf = [&](int pa, int pb) {
        CostCell c{&kGpu, 512, 512, 2, Method::Fov, {}, {0, 0.01, 0.01, 0}};
        c.variants.push_back({"foveate", a.shader, a.constants, 1, 0, 64, 8.0, pa});
        c.variants.push_back({"foveate", b.shader, b.constants, 2, 0, 64, 8.0, pb});
        return c;
    };
    const double groups = 0.01 * px / 64, throughput = groups * 100 / 20;  // 81.92 groups: 409.6 cycles each
    ASSERT_LT(throughput, 1000.0);
    const auto apart = costRows(cellOf(kOwnPhase, kOwnPhase), stats);
    EXPECT_DOUBLE_EQ(apart[0].aluUs, 3000.0 / 1000);
    EXPECT_DOUBLE_EQ(apart[1].aluUs, 1000.0 / 1000);
    const auto together = costRows(cellOf(4, 4), stats);
    EXPECT_DOUBLE_EQ(together[0].aluUs, (3000.0 - throughput) / 1000);  // the slowest wave's row holds the floor
    EXPECT_DOUBLE_EQ(together[1].aluUs, throughput / 1000);
    EXPECT_DOUBLE_EQ(together[2].aluUs, 3.0) << "the phase: one latency";
    EXPECT_DOUBLE_EQ(apart[2].aluUs, 4.0);
    // Enough waves hide the latency: the phase costs its throughput.
    stats[a].invThroughput = stats[b].invThroughput = 10000;
    const auto busy = costRows(cellOf(4, 4), stats);
    EXPECT_DOUBLE_EQ(busy[2].aluUs, 2 * groups * 10000 / 20 / 1000);
}

TEST(CostModel, MemoryTimeScalesWithBytesAndBandwidth) {
    GpuFigures wide = kGpu;
    wide.bandwidthGBs = 2 * kGpu.bandwidthGBs;
    const auto a = rowsFor({Method::Wrs}), b = rowsFor({Method::Wrs}, wide);
    ASSERT_EQ(a.size(), b.size());
    for (std::size_t i = 0; i < a.size(); ++i) {
        EXPECT_NEAR(b[i].memUs, a[i].memUs / 2, 1e-9 * a[i].memUs) << a[i].pass << "/" << a[i].cls;
        EXPECT_DOUBLE_EQ(b[i].aluUs, a[i].aluUs);
    }
    // Twice the bytes of a variant, twice its memory time.
    auto variants = pipelineVariants(config(Method::Wrs), kAtrium);
    CostCell cell{&kGpu, 512, 512, 2, Method::Wrs, variants, {0.1, 0.05, 0.15, 0.7}};
    const auto stats = fakeStats({Method::Wrs}, 400);
    const auto base = costRows(cell, stats);
    for (PipelineVariant& v : cell.variants) v.bytesPerPx *= 2;
    const auto doubled = costRows(cell, stats);
    for (std::size_t i = 0; i < base.size(); ++i)
        EXPECT_NEAR(doubled[i].memUs, 2 * base[i].memUs, 1e-9 * base[i].memUs);
    // Less arithmetic per wave makes a pass memory-bound: predicted = max(alu, mem).
    const auto cheap = rowsFor({Method::Wrs}, kGpu, 1);
    for (const CostRow& r : cheap)
        if (!r.total) {
            EXPECT_DOUBLE_EQ(r.predictedUs, std::max(r.aluUs, r.memUs));
        }
}

TEST(CostModel, CsvHasTheColumnsARowPerPassClassAndMethodAndTotalsThatSum) {
    const std::vector<Method> methods{Method::Fov, Method::FovTaa, Method::WrsPaper, Method::Wrs};
    const auto rows = rowsFor(methods);
    const std::string dir = testing::TempDir() + "/cost_model_csv";
    std::filesystem::create_directories(dir);
    ASSERT_TRUE(writeCostModel(rows, {"vangogh: a test skip"}, "a test cell", dir));
    std::ifstream csv(dir + "/cost_model.csv");
    std::string header;
    std::getline(csv, header);
    const auto cols = split(header);
    for (const char* c :
         {"gpu", "size", "method", "pass", "class", "instructions", "vgprs", "waves_per_simd", "subgroup_size",
          "inv_throughput", "cycles_per_px", "bytes_per_px", "share", "alu_us", "mem_us", "predicted_us"})
        EXPECT_NE(std::find(cols.begin(), cols.end(), c), cols.end()) << c;
    auto col = [&](const char* name) { return std::size_t(std::find(cols.begin(), cols.end(), name) - cols.begin()); };
    std::map<std::string, std::set<std::string>> seen;  // method -> pass/class
    std::map<std::string, std::array<double, 3>> sums, totals;
    for (std::string line; std::getline(csv, line);) {
        const auto f = split(line);
        ASSERT_EQ(f.size(), cols.size()) << line;
        const std::string method = f[col("method")];
        const std::array<double, 3> v{std::stod(f[col("alu_us")]), std::stod(f[col("mem_us")]),
                                      std::stod(f[col("predicted_us")])};
        if (f[col("pass")] == "total") {
            totals[method] = v;
            continue;
        }
        EXPECT_GT(std::stod(f[col("instructions")]), 0) << line;
        seen[method].insert(f[col("pass")] + "/" + f[col("class")]);
        for (int k = 0; k < 3; ++k) sums[method][k] += v[k];
    }
    using S = std::set<std::string>;
    EXPECT_EQ(seen["fov"],
              (S{"classify/whole", "pyramid/whole", "foveate/any", "foveate/fovea", "foveate/mid", "foveate/far"}));
    EXPECT_EQ(seen["wrs"], (S{"reach/whole", "classify/whole", "pyramid/whole", "retain/any", "retain/fovea",
                              "retain/mid", "retain/far", "skip/skip"}));
    EXPECT_EQ(seen["fov+taa"], (S{"pyramid/whole", "foveate/whole", "taa/whole"}));
    EXPECT_EQ(seen["wrs-paper"], (S{"pyramid/whole", "foveate/whole", "wrs-paper/whole"}));
    ASSERT_EQ(totals.size(), 4u);
    for (const auto& [method, t] : totals)
        for (int k = 0; k < 3; ++k)
            EXPECT_NEAR(t[k], sums[method][k], 1e-5 * std::max(1.0, t[k])) << method << " " << k;
    std::ifstream md(dir + "/cost_model.md");
    const std::string text((std::istreambuf_iterator<char>(md)), {});
    EXPECT_NE(text.find("wrs / retain: "), std::string::npos);
    EXPECT_NE(text.find("vangogh: a test skip"), std::string::npos);
}

TEST(CostModel, TileSharesFromTheSweepsGaze) {
    BenchOptions o;
    o.frames = 12;
    o.warmup = 2;
    auto g = cellGeometry(o, SceneKind::Atrium, FoveationMode::Mip, 5.0f, 512, 512);
    ASSERT_TRUE(g) << g.error().message;
    EXPECT_EQ(g->inputs.depthBytes, 4u);
    EXPECT_EQ(g->inputs.motionBytes, 8u);
    double sum = 0;
    for (double s : g->tileShare) sum += s;
    EXPECT_NEAR(sum, 1.0, 1e-12);
    EXPECT_GT(g->tileShare[gpu::WRS_TILE_FAR], 0.8) << "a 5° fovea in a wide HMD view: mostly far periphery";
    EXPECT_GT(g->tileShare[gpu::WRS_TILE_FOVEA], 0.0);
    auto none = cellGeometry(o, SceneKind::Atrium, FoveationMode::None, 5.0f, 256, 256);
    ASSERT_TRUE(none);
    EXPECT_EQ(none->tileShare[gpu::WRS_TILE_ANY], 1.0);
    EXPECT_FALSE(cellGeometry(o, SceneKind::Sequence, FoveationMode::Mip, 5.0f, 256, 256));
}

// Frames submitted as quad views (wrsfov-bench --cost-model --cost-quad): the layer's bytes, the tiles
// the inset covers, and the compose pass first, then each method's passes on the composed images.
TEST(CostModel, QuadViewsComposeFirstWithTheLayersBytes) {
    BenchOptions o;
    o.hmdFovDeg = 100.0f;
    auto g = quadCellGeometry(o, SceneKind::Atrium, 768, 768, 0.3f, 10.0f, false);
    ASSERT_TRUE(g) << g.error().message;
    // The composed images: RGBA16F colour (the rendered quality in its alpha), R32F depth, RGBA16F motion.
    EXPECT_EQ(g->inputs.colorBytes, 8u);
    EXPECT_EQ(g->inputs.depthBytes, 4u);
    EXPECT_EQ(g->inputs.motionBytes, 8u);
    EXPECT_DOUBLE_EQ(g->inputs.composeWrite, 20.0);
    // Read: the wide view's 230^2 texels and the inset's of RGBA8, D32F and RGBA16F (16 B), per output pixel.
    // The inset: 10° across at 768 px over 100°: 2 tan 5° x 768 / (2 tan 50°) = 56 px.
    const double wide = 230.0 * 230.0 / (768.0 * 768.0), inset = 56.0 * 56.0 / (768.0 * 768.0);
    EXPECT_NEAR(g->inputs.composeRead, 16.0 * (wide + inset), 1e-9);
    // 56 px centred in 768: pixels 356..411, tiles 22..25 of 48 per axis.
    EXPECT_DOUBLE_EQ(g->tileShare[gpu::WRS_TILE_ANY], 16.0 / (48.0 * 48.0));
    EXPECT_DOUBLE_EQ(g->tileShare[gpu::WRS_TILE_FAR], 1.0 - 16.0 / (48.0 * 48.0));
    auto merged = quadCellGeometry(o, SceneKind::Atrium, 768, 768, 0.3f, 10.0f, true);
    ASSERT_TRUE(merged);
    EXPECT_EQ(merged->tileShare[gpu::WRS_TILE_ANY], 1.0);
    EXPECT_EQ(merged->tileShare[gpu::WRS_TILE_FAR], 0.0);
    EXPECT_FALSE(quadCellGeometry(o, SceneKind::Text, 768, 768, 0.3f, 10.0f, false));
    EXPECT_FALSE(quadCellGeometry(o, SceneKind::Atrium, 768, 768, 0.0f, 10.0f, false));
    EXPECT_FALSE(quadCellGeometry(o, SceneKind::Atrium, 768, 768, 0.3f, 0.0f, false));

    auto names = [](const std::vector<PipelineVariant>& vs) {
        std::vector<std::string> out;
        for (const PipelineVariant& v : vs) out.push_back(v.pass + "/" + tileClassName(v.tileClass));
        return out;
    };
    using V = std::vector<std::string>;
    auto quadConfig = [](Method m) {
        CompositorConfig c = config(m);
        c.foveation = FoveationMode::Submitted;
        return c;
    };
    const auto wrs = pipelineVariants(quadConfig(Method::Wrs), g->inputs);
    // The steady display runs in the retain pass (constant 10), which then retains in every pixel: no
    // classification, no tile lists.
    EXPECT_EQ(names(wrs), (V{"compose/outside", "compose/inset", "pyramid/whole", "retain/whole"}));
    EXPECT_EQ(wrs[3].constants[10], 1u);
    EXPECT_EQ(wrs[3].constants[11], 1u) << "the wide views' encoding, from which it takes the landed samples";
    CompositorConfig undisplayed = quadConfig(Method::Wrs);
    undisplayed.steadyDisplay = 0.0f;
    EXPECT_EQ(names(pipelineVariants(undisplayed, g->inputs)),
              (V{"compose/outside", "compose/inset", "reach/whole", "classify/whole", "pyramid/whole", "retain/any",
                 "retain/fovea", "retain/mid", "retain/far", "skip/skip"}));
    // compose.comp's constants as ComposePass binds them: quad views (1), depth, motion, the method's
    // wide samples (composeLanded: `wrs` its landed ones, `taau-simple` the gathered ones, `taau` their
    // Lanczos-2 gather, `fov` none), the wide
    // views' and the insets' encodings (RGBA8 sRGB: 1), the inset's groups, and `fov`'s output; nothing else.
    EXPECT_EQ(wrs[0].shader, ShaderId::Compose);
    EXPECT_EQ(wrs[0].constants, (SpecConstants{1, 1, 1, 1, 1, 1, 0, 0, 0, 0}));
    EXPECT_EQ(wrs[1].constants, (SpecConstants{1, 1, 1, 1, 1, 1, 1, 0, 0, 0}));
    EXPECT_EQ(pipelineVariants(quadConfig(Method::Taau), g->inputs)[0].constants,
              (SpecConstants{1, 1, 1, 3, 1, 1, 0, 0, 0, 0}));
    EXPECT_EQ(pipelineVariants(quadConfig(Method::TaauSimple), g->inputs)[0].constants,
              (SpecConstants{1, 1, 1, 2, 1, 1, 0, 0, 0, 0}));
    EXPECT_EQ(pipelineVariants(quadConfig(Method::Fov), g->inputs)[0].constants,
              (SpecConstants{1, 0, 0, 0, 1, 1, 0, 1, 0, 0}));
    CompositorConfig unlanded = quadConfig(Method::Wrs);
    unlanded.landedSamples = false;
    EXPECT_EQ(pipelineVariants(unlanded, g->inputs)[0].constants[3], 0u);
    // The inset's groups (56 px at the centre of 768: pixels 354..413 with a pixel to spare each side,
    // groups 44..51 of 96 per axis) and the others, side by side; then a barrier.
    EXPECT_DOUBLE_EQ(g->inputs.insetShare, 64.0 / (96.0 * 96.0));
    EXPECT_EQ(wrs[0].groups + wrs[1].groups, 96u * 96u * 2u);
    EXPECT_EQ(wrs[1].groups, 2u * 64u);
    EXPECT_EQ(wrs[0].phase, wrs[1].phase);
    EXPECT_LT(wrs[1].phase, wrs[2].phase) << "a barrier after the compose pass";
    // `fov` composes into the output; `taau`'s pass reads the composed colour: no foveating pass.
    EXPECT_EQ(names(pipelineVariants(quadConfig(Method::Fov), g->inputs)), (V{"compose/outside", "compose/inset"}));
    EXPECT_EQ(names(pipelineVariants(quadConfig(Method::Taau), g->inputs)),
              (V{"compose/outside", "compose/inset", "taa/whole"}));
    // Every pass of traffic() on these views has its variant with its bytes (the compose pass's among them).
    for (Method m : {Method::Fov, Method::Taau, Method::TaauSimple, Method::Wrs}) {
        const Traffic t = traffic(quadConfig(m), g->inputs);
        const auto vs = pipelineVariants(quadConfig(m), g->inputs);
        for (const PassTraffic& p : t.passes) {
            // The skip list moves the bytes of no retaining tile, the classification adds its list entries
            // (VariantsMirrorTheDispatches).
            if (p.pass == "skip" || p.pass == "classify") continue;
            bool found = false;
            for (const PipelineVariant& v : vs)
                if (v.pass == p.pass) {
                    found = true;
                    EXPECT_DOUBLE_EQ(v.bytesPerPx, p.read + p.write) << toString(m) << " " << p.pass;
                }
            EXPECT_TRUE(found) << toString(m) << ": no variant for pass " << p.pass;
        }
    }
    // A rate map's compose pass: kind 2, no depth or motion of its own.
    TrafficInputs rate = kAtrium;
    rate.composeRead = 1.0 / 256.0;
    rate.composeWrite = 4;
    const auto fovRate = pipelineVariants(quadConfig(Method::Fov), rate);
    ASSERT_FALSE(fovRate.empty());
    EXPECT_EQ(fovRate[0].constants, (SpecConstants{2, 0, 0, 0, 4, 4, 0, 0, 0, 0}));
}

// A statistics process that dies of a signal after offering its device (a driver's crash while compiling)
// is run once more; dying again is CostError::Crashed. A stand-in script: its first `crashes` runs kill
// themselves with SIGSEGV, the next prints one key's statistics as the child does.
TEST(CostModel, ACrashedStatisticsProcessIsRunOnceMore) {
    const std::filesystem::path dir = std::filesystem::temp_directory_path() /
                                      ("wrsfov_cost_crash_" + std::to_string(::getpid()));
    std::filesystem::create_directories(dir);
    const VariantKey key{ShaderId::Classify, {1, 0, 0, 0, 0, 0}};
    auto script = [&](int crashes) {
        const std::filesystem::path exe = dir / ("child" + std::to_string(crashes) + ".sh");
        std::ofstream f(exe);
        f << "#!/bin/sh\n"
          << "n=$(cat '" << (dir / "runs").string() << "' 2>/dev/null || echo 0)\n"
          << "echo $((n + 1)) > '" << (dir / "runs").string() << "'\n"
          << "printf 'device\\tstand-in\\n'\n"
          << "if [ \"$n\" -lt " << crashes << " ]; then kill -SEGV $$; fi\n"
          << "printf 'executable\\t%s\\t64\\n' \"$3\"\n";
        for (const char* stat :
             {"Instructions", "VGPRs", "SGPRs", "Subgroups per SIMD", "Latency", "Inverse Throughput"})
            f << "printf 'stat\\t" << stat << "\\t3\\t10\\n'\n";
        f.close();
        std::filesystem::permissions(exe, std::filesystem::perms::owner_all);
        std::filesystem::remove(dir / "runs");
        return exe.string();
    };
    auto runs = [&] {
        std::ifstream f(dir / "runs");
        int n = 0;
        f >> n;
        return n;
    };
    auto once = collectStatistics(script(1), *parseStatsTarget("device:stand-in"), {key});
    ASSERT_TRUE(once) << once.error().message;
    EXPECT_EQ(runs(), 2);
    EXPECT_EQ(once->at(key).instructions, 10.0);
    auto twice = collectStatistics(script(2), *parseStatsTarget("device:stand-in"), {key});
    ASSERT_FALSE(twice);
    EXPECT_EQ(runs(), 2) << "not a third time";
    EXPECT_EQ(twice.error().code, int(CostError::Crashed));
    EXPECT_NE(twice.error().message.find("died of signal 11"), std::string::npos) << twice.error().message;
    auto fine = collectStatistics(script(0), *parseStatsTarget("device:stand-in"), {key});
    ASSERT_TRUE(fine) << fine.error().message;
    EXPECT_EQ(runs(), 1) << "a child that does not crash runs once";
    std::filesystem::remove_all(dir);
}

#ifdef WRSFOV_BENCH_EXE
// The statistics process, which the bench re-executes per target.
TEST(CostModelDevice, ADeviceWithoutStatisticsIsASkipWithItsReason) {
    // Mesa's lavapipe has no VK_KHR_pipeline_executable_properties; an absent device is a skip too.
    const std::vector<VariantKey> keys{{ShaderId::Classify, {1, 0, 0, 0, 0, 0}}};
    auto lvp = collectStatistics(WRSFOV_BENCH_EXE, *parseStatsTarget("device:llvmpipe"), keys);
    ASSERT_FALSE(lvp);
    EXPECT_EQ(lvp.error().code, int(CostError::Unavailable)) << lvp.error().message;
    std::printf("lavapipe: %s\n", lvp.error().message.c_str());
    auto absent = collectStatistics(WRSFOV_BENCH_EXE, *parseStatsTarget("device:no such device"), keys);
    ASSERT_FALSE(absent);
    EXPECT_EQ(absent.error().code, int(CostError::Unavailable)) << absent.error().message;
    EXPECT_NE(absent.error().message.find("no Vulkan device's name contains 'no such device'"), std::string::npos)
        << absent.error().message;
    auto family = collectStatistics(WRSFOV_BENCH_EXE, *parseStatsTarget("gfx9999"), keys);
    ASSERT_FALSE(family);
    EXPECT_EQ(family.error().code, int(CostError::Unavailable)) << family.error().message;
    std::printf("gfx9999: %s\n", family.error().message.c_str());
}

TEST(CostModelDevice, RadvNullDeviceGivesAcoStatistics) {
    std::vector<VariantKey> keys;
    std::optional<VariantKey> retainAny, retainFar;
    for (const PipelineVariant& v : pipelineVariants(config(Method::Wrs), kAtrium)) {
        keys.push_back({v.shader, v.constants});
        if (v.pass == "retain" && v.tileClass == gpu::WRS_TILE_ANY) retainAny = keys.back();
        if (v.pass == "retain" && v.tileClass == gpu::WRS_TILE_FAR) retainFar = keys.back();
    }
    ASSERT_TRUE(retainAny && retainFar);
    auto stats = collectStatistics(WRSFOV_BENCH_EXE, *parseStatsTarget("gfx1100"), keys);
    if (!stats && stats.error().code == int(CostError::Unavailable))
        GTEST_SKIP() << "RADV's null device is unavailable here: " << stats.error().message;
    ASSERT_TRUE(stats) << stats.error().message;
    ASSERT_EQ(stats->size(), keys.size());
    for (const auto& [k, s] : *stats) {
        EXPECT_GT(s.instructions, 0) << toString(k);
        EXPECT_GT(s.vgprs, 0) << toString(k);
        EXPECT_GT(s.invThroughput, 0) << toString(k);
        EXPECT_GE(s.latency, s.invThroughput) << toString(k);
        EXPECT_TRUE(s.subgroupSize == 32 || s.subgroupSize == 64) << toString(k);
    }
    // The retain pass of the far class computes no eccentricity: fewer instructions than per pixel.
    EXPECT_LT((*stats)[*retainFar].instructions, (*stats)[*retainAny].instructions);
}

// The compose pass (frames submitted foveated) compiles with its own layout: quad views with depth and
// motion (two bilinear colour sources, the blend, nearest depth and motion) cost more than a rate map
// (one texel's rate per pixel).
TEST(CostModelDevice, ComposePassCompilesWithItsOwnLayout) {
    const VariantKey quad{ShaderId::Compose, {1, 1, 1, 0, 0, 0, 0, 1, 0}};
    const VariantKey rate{ShaderId::Compose, {2, 0, 0, 0, 0, 0, 0, 1, 0}};
    auto stats = collectStatistics(WRSFOV_BENCH_EXE, *parseStatsTarget("gfx1100"), {quad, rate});
    if (!stats && stats.error().code == int(CostError::Unavailable))
        GTEST_SKIP() << "RADV's null device is unavailable here: " << stats.error().message;
    ASSERT_TRUE(stats) << stats.error().message;
    std::printf("compose on gfx1100: quad %.0f instructions, %.0f cycles per wave; rate %.0f, %.0f\n",
                (*stats)[quad].instructions, (*stats)[quad].invThroughput, (*stats)[rate].instructions,
                (*stats)[rate].invThroughput);
    EXPECT_GT((*stats)[quad].instructions, 4 * (*stats)[rate].instructions);
    EXPECT_GT((*stats)[rate].instructions, 0);
}
#endif
