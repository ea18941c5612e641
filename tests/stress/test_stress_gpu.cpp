// A short GPU stress run: every GPU row (stream x motion x aged history) through the compositor
// against the CPU reference in lockstep, and a run with a wrong reference seed showing that the
// comparison can fail.
#include <cstdio>

#include "stress/gpu_stress.h"
#include "stress/report.h"
#include "tests/core/gpu_rig.h"

namespace wrsfov::stress {
namespace {

class StressGpu : public test::GpuTest {};

TEST_F(StressGpu, ThreeHundredFramesAgreeWithTheLockstepReference) {
    GpuOptions o;
    o.frames = 300;
    o.width = 16;
    auto r = runGpu(test::context(), o);
    ASSERT_TRUE(r.ok()) << r.error().message;
    EXPECT_EQ(r->height, uint32_t(defaultGpuRows().size()));
    uint64_t decisions = 0, kept = 0;
    for (const GpuRowStats& s : r->rows) {
        SCOPED_TRACE(s.row.stream);
        EXPECT_EQ(s.pixelFrames, 300u * 2 * 16);
        EXPECT_EQ(s.selectionMismatch, s.nearThreshold);
        EXPECT_EQ(s.zmMismatch, 0u);
        EXPECT_LE(s.wsumMaxRel, kWsumTolerance);
        EXPECT_EQ(s.nonFinite, 0u);
        EXPECT_EQ(s.stepMismatch, 0u);
        EXPECT_LE(s.outputMaxDiff, 1) << "sRGB encode of the same colour";
        if (s.row.aged) {
            EXPECT_EQ(s.mMax, 65535u) << "aged rows saturate M on the GPU";
        }
        decisions += s.decisions;
        kept += s.kept;
    }
    EXPECT_EQ(r->resyncs, 0u) << "full lockstep: the reference never needed the GPU's history";
    EXPECT_EQ(r->finalAgree, r->finalPixels);
    EXPECT_EQ(r->validationErrors, 0u);
    // Both outcomes of the combine are well represented.
    EXPECT_GT(decisions, 100000u);
    EXPECT_GT(kept, decisions / 10);
    EXPECT_GT(decisions - kept, decisions / 20);
    for (const Check& c : evaluate(nullptr, &*r)) EXPECT_TRUE(c.pass) << c.what << ": " << c.detail;
    std::printf("  %llu decisions, %llu kept; %llu of %llu final reservoirs bit-identical; %.1f s\n",
                (unsigned long long)decisions, (unsigned long long)kept, (unsigned long long)r->finalIdentical,
                (unsigned long long)r->finalPixels, r->wall_s);
}

TEST_F(StressGpu, WrongReferenceSeedIsCaught) {
    GpuOptions o;
    o.frames = 20;
    o.width = 8;
    o.referenceSeedOffset = 1;
    auto r = runGpu(test::context(), o);
    ASSERT_TRUE(r.ok()) << r.error().message;
    uint64_t mismatches = 0, near = 0;
    for (const GpuRowStats& s : r->rows) {
        mismatches += s.selectionMismatch;
        near += s.nearThreshold;
    }
    EXPECT_GT(mismatches - near, 100u);
    EXPECT_GT(r->resyncs, 0u);
    bool failed = false;
    for (const Check& c : evaluate(nullptr, &*r)) failed |= !c.pass;
    EXPECT_TRUE(failed);
}

TEST_F(StressGpu, RefusesRowsTheGpuCannotRun) {
    GpuOptions o;
    o.frames = 2;
    o.rows = {{"unbiased"}};
    EXPECT_FALSE(runGpu(test::context(), o).ok());
    o.rows = {{"out-of-range"}};
    EXPECT_FALSE(runGpu(test::context(), o).ok());
    o.rows = {{"nope"}};
    EXPECT_FALSE(runGpu(test::context(), o).ok());
}

}  // namespace
}  // namespace wrsfov::stress
