// The GPU pipeline against the CPU reference built from the same shared header, over many frames of
// random colour, depth, motion and gaze. Each frame the reference starts from the GPU's own history,
// so every frame checks one step of every pixel: the selection must be identical except where the
// random number lies within 1e-6 of the keep threshold, output colours within 1/255 (vs_cpu.cpp).
#include <cstdio>

#include "vs_cpu.h"

namespace wrsfov::test {
namespace {

class GpuVsCpu : public GpuTest, public ::testing::WithParamInterface<Case> {};

// Runs `frames` random frames of case `c` at W x H and checks every decision and output against the
// reference. `counts`: also require every branch of the rule to be exercised (the full-length run).
void runAgainstReference(const Case& c, uint32_t W, uint32_t H, int frames, bool counts) {
    std::vector<Variant> v{Variant{""}};
    runAgainstReferences(c, W, H, frames, v);
    if (::testing::Test::HasFatalFailure()) return;
    expectAgreement(c, v[0]);
    const RetainTally& rt = v[0].rt;
    const Tally& t = v[0].t;
    if (!counts) return;
    if (usesRetainPass(c.method)) {
        EXPECT_GT(rt.decisions, 50000u);
        // Every branch of the rule must be exercised for the comparison to mean anything.
        const std::vector<uint32_t> branches = isOracle(c.method)
                                                   ? std::vector<uint32_t>{gpu::WRS_OUT_KEPT, gpu::WRS_OUT_BETTER}
                                                   : std::vector<uint32_t>{gpu::WRS_OUT_CHANGED, gpu::WRS_OUT_BETTER,
                                                                           gpu::WRS_OUT_KEPT, gpu::WRS_OUT_KEPT};
        for (uint32_t b : branches) EXPECT_GT(rt.outcomes[b], rt.decisions / 200) << "outcome " << b;
        // The floor rule takes the far periphery's equal-quality decisions (mip and gauss), so merges
        // happen only above it (the fovea and the mid-periphery): fewer, but still exercised.
        if (!isOracle(c.method) && c.mode != FoveationMode::None) {
            EXPECT_GT(rt.outcomes[gpu::WRS_OUT_FLOOR], rt.decisions / 200) << "floor rule";
            if (c.rule == EqualQuality::Merge) {
                // One merge per three frames (20 over the sixty).
                EXPECT_GE(rt.outcomes[gpu::WRS_OUT_MERGED], uint64_t(frames) / 3) << "merges above the floor";
            }
        }
    }
    if (c.method == Method::WrsPaper) {
        // Both outcomes of the combine must be well represented for the comparison to mean anything.
        EXPECT_GT(t.decisions, 100000u);
        EXPECT_GT(t.kept, t.decisions / 20);
        EXPECT_GT(t.decisions - t.kept, t.decisions / 20);
    }
}

TEST_P(GpuVsCpu, SixtyRandomFramesMatchReference) {
    // 88 x 72: not multiples of the 8x8 workgroup: exercises bounds checks. Under the sanitizers, which
    // check the host code, 20 frames: four colour and two depth changes (the content's periods, vs_cpu.cpp)
    // take every host path the sixty take, at a third of the instrumented reference's time.
    runAgainstReference(GetParam(), 88, 72, kSanitized ? 20 : 60, true);
}

// Sizes whose levels are odd where the mip pyramid's groups clamp their taps: level 0 (87, 69, 33),
// level 1 (45, 37, 35, 17, 9), and images narrower than one 32x32 group (17, 9).
TEST_P(GpuVsCpu, OddSizesMatchReference) {
    for (auto [w, h] : {std::pair{87u, 69u}, std::pair{90u, 74u}, std::pair{33u, 17u}}) {
        runAgainstReference(GetParam(), w, h, 6, false);
        if (HasFailure()) break;
    }
}

INSTANTIATE_TEST_SUITE_P(Pipelines, GpuVsCpu, ::testing::ValuesIn(comparedPipelines()),
                         [](const ::testing::TestParamInfo<Case>& i) { return std::string(i.param.name); });

}  // namespace
}  // namespace wrsfov::test
