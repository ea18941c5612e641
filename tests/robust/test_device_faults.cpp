// docs/bad-input.md, "Device faults": out of device memory, device loss and a pipeline the driver
// cannot make, injected through vk::FaultInjection because a real device does not fail on demand.
// Out of memory and a failed pipeline are clear errors that change nothing (a twin that never saw
// them stays bit-identical); device loss makes the compositor refuse every later frame at once, and a
// new Context and Compositor run normally.
#include <algorithm>
#include <chrono>
#include <functional>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "robust_rig.h"

namespace wrsfov::test {
namespace {

using layers::Format;
using layers::SubmitError;
using layers::SwapchainError;
using layers::Usage;
using Clock = std::chrono::steady_clock;

constexpr uint32_t kW2 = 48, kH2 = 32;  // the size a resize goes to

const char* const kOom = "VK_ERROR_OUT_OF_DEVICE_MEMORY";
const char* const kLost = "VK_ERROR_DEVICE_LOST";

// Arms faults on a context for one scope.
struct Armed {
    Armed(vk::Context& c, vk::FaultInjection f) : ctx(c) { ctx.injectFaults(f); }
    ~Armed() { ctx.injectFaults({}); }
    vk::Context& ctx;
};
vk::FaultInjection allocFault(uint32_t n) { return vk::FaultInjection{.failAllocation = n}; }
vk::FaultInjection lossFault(uint32_t n) { return vk::FaultInjection{.loseDevice = n}; }

std::unique_ptr<vk::Context> freshContext() {
    auto r = vk::Context::create();
    EXPECT_TRUE(r.ok()) << (r.ok() ? "" : r.error().message);
    return r.ok() ? std::move(*r) : nullptr;
}

std::array<EyeFrame, 2> frameOfSize(uint64_t index, uint32_t w, uint32_t h) {
    RandomScene rs(uint32_t(500 + index)), fixed(8);
    std::array<EyeFrame, 2> eyes;
    for (int e = 0; e < 2; ++e) {
        eyes[e].fov = hmdFov(e);
        eyes[e].color = rs.color(Format::RGBA16F, w, h);
        eyes[e].depth = fixed.depth(Format::R32F, w, h);
        eyes[e].motion = HostImage::make(Format::RGBA16F, w, h);
        eyes[e].gaze = {gazeDir(2.0f, 1.0f), true, 1.0f};
    }
    return eyes;
}

// ---- Out of device memory -----------------------------------------------------------------------

struct OomRow {
    std::string name;
    uint32_t allocation;  ///< which allocation fails
    std::string what;     ///< what the message must name
};
void PrintTo(const OomRow& r, std::ostream* os) { *os << r.name; }

class OomAtCreate : public GpuTest, public ::testing::WithParamInterface<OomRow> {};

TEST_P(OomAtCreate, Row) {
    const OomRow& row = GetParam();
    {
        Armed a(context(), allocFault(row.allocation));
        auto comp = Compositor::create(context(), CompositorConfig{});
        ASSERT_FALSE(comp.ok()) << "allocation " << row.allocation << " did not fail Compositor::create";
        EXPECT_TRUE(contains(comp.error().message, row.what)) << comp.error().message;
        EXPECT_TRUE(contains(comp.error().message, kOom)) << comp.error().message;
    }
    // The same context makes compositors that run as if nothing had happened.
    TwinChain c(CompositorConfig{.seed = 4}, LaneFormats{});
    for (int i = 0; i < 2; ++i) ASSERT_NO_FATAL_FAILURE(c.stepBoth("after the failed create"));
    expectSane(*c.main.comp, row.name);
}

INSTANTIATE_TEST_SUITE_P(DeviceFault, OomAtCreate,
                         ::testing::Values(OomRow{"frame_parameters", 1, "compositor frame parameters"},
                                           OomRow{"srgb_table", 2, "sRGB decode table"},
                                           OomRow{"placeholder_image", 3, "compositor placeholder image"}),
                         [](const ::testing::TestParamInfo<OomRow>& i) { return i.param.name; });

// A chain at kW x kH whose lanes can also submit kW2 x kH2 frames.
struct ResizeChain {
    explicit ResizeChain(const CompositorConfig& cfg) : chain(cfg, LaneFormats{}) {
        for (Lane* lane : {&chain.main, &chain.twin})
            big[lane] =
                std::make_unique<StereoApp>(*lane->comp, kW2, kH2, Format::RGBA16F, Format::R32F, Format::RGBA16F);
    }
    // Both lanes take a kW2 x kH2 frame and must stay identical.
    void bigStepBoth(const std::string& what) {
        const auto eyes = frameOfSize(chain.next(), kW2, kH2);
        for (Lane* lane : {&chain.main, &chain.twin}) {
            const Status s = big[lane]->submit(chain.next(), eyes);
            ASSERT_TRUE(s.ok()) << what << ": " << s.message();
        }
        chain.jumpTo(chain.next() + 1);
        const std::string d = difference(snapshot(*chain.main.comp), snapshot(*chain.twin.comp));
        EXPECT_TRUE(d.empty()) << what << ": " << d;
    }
    TwinChain chain;
    std::map<Lane*, std::unique_ptr<StereoApp>> big;
};

class OomAtResize : public GpuTest, public ::testing::WithParamInterface<OomRow> {};

TEST_P(OomAtResize, Row) {
    const OomRow& row = GetParam();
    static ResizeChain rc(CompositorConfig{.foveaDeg = 10.0f, .seed = 6});
    TwinChain& c = rc.chain;
    for (int i = 0; i < 3; ++i) ASSERT_NO_FATAL_FAILURE(c.stepBoth("before"));
    const Snapshot before = snapshot(*c.main.comp);

    const auto eyes = frameOfSize(c.next(), kW2, kH2);
    StereoApp& big = *rc.big[&c.main];
    big.write(eyes);  // the upload allocates too: before the fault is armed
    Status s;
    {
        Armed a(context(), allocFault(row.allocation));
        s = c.main.comp->endFrame(big.frameEnd(c.next(), eyes));
    }
    ASSERT_FALSE(s.ok()) << "allocation " << row.allocation << " did not fail the resize";
    EXPECT_EQ(s.error().code, int(SubmitError::DeviceFailure)) << s.message();
    for (const std::string& part : {std::string("resizing to 48x32"), row.what, std::string(kOom)})
        EXPECT_TRUE(contains(s.message(), part)) << "'" << s.message() << "' lacks '" << part << "'";
    EXPECT_EQ(c.main.comp->width(), kW);
    EXPECT_EQ(c.main.comp->height(), kH);
    const std::string changed = difference(before, snapshot(*c.main.comp));
    EXPECT_TRUE(changed.empty()) << "the failed resize changed the compositor: " << changed;

    // The old size goes on as if the bad frame never happened; the new size works when memory is back.
    ASSERT_NO_FATAL_FAILURE(c.stepBoth("old size after the failed resize"));
    expectSane(*c.main.comp, row.name);
    ASSERT_NO_FATAL_FAILURE(rc.bigStepBoth("the new size once memory is back"));
    expectSane(*c.main.comp, row.name + " at the new size");
    ASSERT_NO_FATAL_FAILURE(c.stepBoth("back to the old size"));
}

INSTANTIATE_TEST_SUITE_P(
    DeviceFault, OomAtResize,
    ::testing::Values(OomRow{"colour_pyramid", 1, "colour pyramid"}, OomRow{"candidates", 2, "candidates"},
                      OomRow{"reservoirs_first", 3, "reservoirs"}, OomRow{"reservoirs_second", 4, "reservoirs"},
                      OomRow{"births_first", 5, "births"}, OomRow{"births_second", 6, "births"},
                      OomRow{"steady_display", 7, "steady display"}, OomRow{"tile_lists", 8, "tile lists"},
                      OomRow{"held_qualities", 9, "held qualities"}, OomRow{"tile_counts", 10, "tile counts"},
                      OomRow{"output_image", 11, "output image"}),
    [](const ::testing::TestParamInfo<OomRow>& i) { return i.param.name; });

class DeviceFaultOom : public GpuTest {};

TEST_F(DeviceFaultOom, CopyKernelBuffersAtResize) {
    ResizeChain rc(CompositorConfig{.foveaDeg = 10.0f, .seed = 8, .measureCopy = true});
    TwinChain& c = rc.chain;
    for (int i = 0; i < 2; ++i) ASSERT_NO_FATAL_FAILURE(c.stepBoth("before"));
    const Snapshot before = snapshot(*c.main.comp);
    const auto eyes = frameOfSize(c.next(), kW2, kH2);
    rc.big[&c.main]->write(eyes);
    Status s;
    {
        Armed a(context(), allocFault(2));
        s = c.main.comp->endFrame(rc.big[&c.main]->frameEnd(c.next(), eyes));
    }
    ASSERT_FALSE(s.ok());
    EXPECT_EQ(s.error().code, int(SubmitError::DeviceFailure));
    EXPECT_TRUE(contains(s.message(), "copy-kernel buffers")) << s.message();
    EXPECT_TRUE(contains(s.message(), kOom)) << s.message();
    EXPECT_TRUE(difference(before, snapshot(*c.main.comp)).empty());
    ASSERT_NO_FATAL_FAILURE(c.stepBoth("after"));
    ASSERT_NO_FATAL_FAILURE(rc.bigStepBoth("the new size once memory is back"));
}

TEST_F(DeviceFaultOom, SwapchainCreation) {
    TwinChain c(CompositorConfig{.seed = 10}, LaneFormats{});
    ASSERT_NO_FATAL_FAILURE(c.stepBoth("before"));
    for (uint32_t n : {1u, 2u}) {  // the first or the second image of the swapchain
        Armed a(context(), allocFault(n));
        auto sc = c.main.comp->createSwapchain(stereoInfo(Usage::Color, Format::RGBA8_SRGB));
        ASSERT_FALSE(sc.ok()) << "image " << n;
        EXPECT_EQ(sc.error().code, int(SwapchainError::DeviceFailure));
        EXPECT_TRUE(contains(sc.error().message, "vkAllocateMemory (image")) << sc.error().message;
        EXPECT_TRUE(contains(sc.error().message, kOom)) << sc.error().message;
    }
    ASSERT_NO_FATAL_FAILURE(c.stepBoth("after"));
    auto sc = c.main.comp->createSwapchain(stereoInfo(Usage::Color, Format::RGBA8_SRGB));
    EXPECT_TRUE(sc.ok()) << "a swapchain once memory is back";
}

TEST_F(DeviceFaultOom, SwapchainUpload) {
    TwinChain c(CompositorConfig{.seed = 12}, LaneFormats{});
    for (int i = 0; i < 2; ++i) ASSERT_NO_FATAL_FAILURE(c.stepBoth("before"));
    const Snapshot before = snapshot(*c.main.comp);
    Status s;
    {
        Armed a(context(), allocFault(1));  // the staging buffer of the first write
        s = c.main.app->submit(c.next(), goodFrame(c.next(), c.main.formats));
    }
    ASSERT_FALSE(s.ok());
    EXPECT_EQ(s.error().code, int(SwapchainError::DeviceFailure)) << s.message();
    EXPECT_TRUE(contains(s.message(), kOom)) << s.message();
    EXPECT_TRUE(difference(before, snapshot(*c.main.comp)).empty());
    ASSERT_NO_FATAL_FAILURE(c.stepBoth("after"));
}

TEST_F(DeviceFaultOom, Readback) {
    TwinChain c(CompositorConfig{.seed = 14}, LaneFormats{});
    for (int i = 0; i < 2; ++i) ASSERT_NO_FATAL_FAILURE(c.stepBoth("before"));
    const Snapshot before = snapshot(*c.main.comp);
    {
        Armed a(context(), allocFault(1));
        auto out = c.main.comp->readOutput(0);
        ASSERT_FALSE(out.ok());
        EXPECT_TRUE(contains(out.error().message, kOom)) << out.error().message;
    }
    {
        Armed a(context(), allocFault(1));
        auto res = c.main.comp->readReservoirs(1);
        ASSERT_FALSE(res.ok());
        EXPECT_TRUE(contains(res.error().message, kOom)) << res.error().message;
    }
    EXPECT_TRUE(difference(before, snapshot(*c.main.comp)).empty());
    ASSERT_NO_FATAL_FAILURE(c.stepBoth("after"));
}

// ---- A pipeline the driver cannot make ----------------------------------------------------------

const char* const kPipelineOom = "vkCreateComputePipelines failed: VK_ERROR_OUT_OF_DEVICE_MEMORY";

// Ends frame `n` of `lane` in Wait mode, or in Record mode into a command buffer of `ctx` that is then
// submitted and waited for; returns endFrame's status.
Status endFrameIn(vk::Context& ctx, Lane& lane, uint64_t n, const std::array<EyeFrame, 2>& eyes, bool record) {
    lane.app->write(eyes);
    if (!record) return lane.comp->endFrame(lane.app->frameEnd(n, eyes));
    auto allocated = ctx.allocateCommandBuffer();
    EXPECT_TRUE(allocated.ok());
    if (!allocated) return allocated.error();
    VkCommandBuffer cb = *allocated;
    VkCommandBufferBeginInfo bi{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
    bi.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
    EXPECT_EQ(vkBeginCommandBuffer(cb, &bi), VK_SUCCESS);
    FrameSubmission rec;
    rec.mode = FrameSubmission::Mode::Record;
    rec.commandBuffer = cb;
    const Status s = lane.comp->endFrame(lane.app->frameEnd(n, eyes), rec);
    // Submitted whatever endFrame did: after a failure the buffer must hold nothing of the frame.
    EXPECT_EQ(vkEndCommandBuffer(cb), VK_SUCCESS);
    VkFenceCreateInfo fci{VK_STRUCTURE_TYPE_FENCE_CREATE_INFO};
    VkFence fence = VK_NULL_HANDLE;
    EXPECT_EQ(vkCreateFence(ctx.device(), &fci, nullptr, &fence), VK_SUCCESS);
    VkSubmitInfo si{VK_STRUCTURE_TYPE_SUBMIT_INFO};
    si.commandBufferCount = 1;
    si.pCommandBuffers = &cb;
    EXPECT_EQ(ctx.submitBatch(si, fence), VK_SUCCESS);
    vkDestroyFence(ctx.device(), fence, nullptr);
    ctx.freeCommandBuffer(cb);
    return s;
}

// Main and twin, each on a context of its own (so that both make the same pipelines at the same
// frames), after frames 1 and 2 untiled.
struct FreshTwins {
    explicit FreshTwins(uint32_t seed) {
        CompositorConfig untiled{.seed = seed};
        untiled.skipTiles = false;
        mainCtx = freshContext();
        twinCtx = freshContext();
        if (!mainCtx || !twinCtx) return;
        main = std::make_unique<Lane>(*mainCtx, untiled, LaneFormats{});
        twin = std::make_unique<Lane>(*twinCtx, untiled, LaneFormats{});
        for (uint64_t n = 1; n <= 2; ++n)
            for (Lane* lane : {main.get(), twin.get()})
                EXPECT_TRUE(lane->app->submit(n, goodFrame(n, lane->formats)).ok()) << "frame " << n;
    }
    /// Both lanes: `edit` applied to their configuration from the next frame on.
    void set(const std::function<void(CompositorConfig&)>& edit) {
        CompositorConfig c = main->comp->config();
        edit(c);
        EXPECT_TRUE(main->comp->setConfig(c).ok());
        EXPECT_TRUE(twin->comp->setConfig(c).ok());
    }
    /// Has the twin end frame `n` (`eyes`, through `app` if given) and returns how many pipelines that
    /// made: main, whose context made the same ones so far, needs as many for it.
    uint32_t twinMakes(uint64_t n, const std::array<EyeFrame, 2>& eyes, StereoApp* app = nullptr) {
        const std::size_t before = twinCtx->sharedPipelineCount();
        EXPECT_TRUE((app ? app : twin->app.get())->submit(n, eyes).ok()) << "twin, frame " << n;
        return uint32_t(twinCtx->sharedPipelineCount() - before);
    }
    std::unique_ptr<vk::Context> mainCtx, twinCtx;
    std::unique_ptr<Lane> main, twin;
};

class DeviceFaultObject : public GpuTest {};

// Every object Compositor::create makes without device memory (layouts, descriptor pool and sets,
// sampler, timestamp queries, shader modules, command buffers, fence), failing in turn: a clear error
// naming it; once N passes them all the compositor is made and runs.
TEST_F(DeviceFaultObject, EveryObjectOfCompositorCreateFailsWithAnError) {
    auto ctx = freshContext();
    ASSERT_TRUE(ctx);
    std::vector<std::string> refusals;
    std::unique_ptr<Compositor> made;
    for (uint32_t n = 1; n <= 64 && !made; ++n) {
        Armed a(*ctx, vk::FaultInjection{.failObject = n});
        auto comp = Compositor::create(*ctx);
        if (comp.ok()) {
            made = std::move(*comp);
            break;
        }
        EXPECT_TRUE(contains(comp.error().message, "failed: VK_ERROR_OUT_OF_HOST_MEMORY")) << comp.error().message;
        refusals.push_back(comp.error().message);
    }
    ASSERT_TRUE(made) << "no compositor after 64 faults";
    for (const char* what :
         {"the passes' descriptor set layout: vkCreateDescriptorSetLayout", "the passes' pipeline layout",
          "the copy kernel's descriptor set layout", "the copy kernel's pipeline layout",
          "the compositor's descriptor pool", "the compositor's descriptor sets", "the compositor's sampler",
          "the compositor's timestamp queries", "the passes' shader modules: vkCreateShaderModule",
          "vkAllocateCommandBuffers", "the compositor's command buffer", "the compositor's frame fence"})
        EXPECT_TRUE(std::any_of(refusals.begin(), refusals.end(), [&](const std::string& m) { return contains(m, what); }))
            << "no refusal named " << what;
    StereoApp app(*made, kW, kH, Format::RGBA16F, Format::R32F, Format::RGBA16F);
    ASSERT_TRUE(app.submit(1, goodFrame(1, LaneFormats{})).ok());
    expectSane(*made, "the compositor made once no object failed");
    EXPECT_EQ(ctx->validationErrors(), 0u);
}

class DeviceFaultPipeline : public GpuTest {};

// Expects `s` to be the refusal of a frame whose pipeline could not be made.
void expectPipelineRefusal(const Status& s, const std::string& what) {
    ASSERT_FALSE(s.ok()) << what << ": the pipeline fault did not fail the frame";
    EXPECT_EQ(s.error().code, int(SubmitError::DeviceFailure)) << what << ": " << s.message();
    EXPECT_TRUE(contains(s.message(), kPipelineOom)) << what << ": " << s.message();
    EXPECT_TRUE(contains(s.message(), ".comp pipeline (constants ")) << what << ": " << s.message();
}

// One pair of twins through every case, main alone seeing the faults:
// - frame 3 switches tiles on (setConfig, no history reset), which needs the classification's, tiled
//   retention's and the skip list's pipelines. It fails at its first new pipeline, then at its last
//   (Wait), then in Record mode at the one still missing, after every other pass was recorded. Each
//   time nothing changes: not the history, the output, the stats, the parameters, and in Record mode
//   the caller's buffer, submitted as endFrame left it, writes nothing either. Then the same frame
//   goes through and matches the twin.
// - frame 5 comes at a new size with sparse retention off (new pipelines again) and fails after its
//   resize: the size is the one change, its output black and its reservoirs empty (a resize clears
//   them), until the same frame goes through and matches the twin.
TEST_F(DeviceFaultPipeline, AFrameWhosePipelineCannotBeMadeIsRefusedAndChangesNothing) {
    FreshTwins t(16);
    ASSERT_TRUE(t.main && t.twin);
    Lane &main = *t.main, &twin = *t.twin;
    vk::Context& mainCtx = *t.mainCtx;
    auto expectSameAsTwin = [&](const std::string& what) {
        const std::string d = difference(snapshot(*main.comp), snapshot(*twin.comp));
        EXPECT_TRUE(d.empty()) << what << ": " << d;
    };

    t.set([](CompositorConfig& c) { c.skipTiles = true; });
    const Snapshot before = snapshot(*main.comp);
    const uint32_t fresh = t.twinMakes(3, goodFrame(3, twin.formats));
    ASSERT_GE(fresh, 3u) << "frame 3 should need the classification's, tiled retention's and the skip list's";
    struct Attempt {
        const char* what;
        uint32_t failPipeline;
        bool record;
    };
    for (const Attempt& at : {Attempt{"its first new pipeline (Wait)", 1u, false},
                              Attempt{"its last new pipeline (Wait)", fresh, false},
                              Attempt{"the one still missing (Record)", 1u, true}}) {
        Status s;
        {
            Armed a(mainCtx, vk::FaultInjection{.failPipeline = at.failPipeline});
            s = endFrameIn(mainCtx, main, 3, goodFrame(3, main.formats), at.record);
        }
        ASSERT_NO_FATAL_FAILURE(expectPipelineRefusal(s, at.what));
        const std::string changed = difference(before, snapshot(*main.comp));
        EXPECT_TRUE(changed.empty()) << at.what << ": the refused frame changed the compositor: " << changed;
    }
    ASSERT_TRUE(endFrameIn(mainCtx, main, 3, goodFrame(3, main.formats), true).ok());
    expectSameAsTwin("frame 3 once its pipelines could be made");
    for (Lane* lane : {&main, &twin}) ASSERT_TRUE(lane->app->submit(4, goodFrame(4, lane->formats)).ok());
    expectSameAsTwin("frame 4");

    StereoApp bigMain(*main.comp, kW2, kH2, Format::RGBA16F, Format::R32F, Format::RGBA16F);
    StereoApp bigTwin(*twin.comp, kW2, kH2, Format::RGBA16F, Format::R32F, Format::RGBA16F);
    t.set([](CompositorConfig& c) { c.sparseRetention = false; });
    const auto eyes = frameOfSize(5, kW2, kH2);
    const uint32_t freshBig = t.twinMakes(5, eyes, &bigTwin);
    ASSERT_GE(freshBig, 1u);
    bigMain.write(eyes);
    Status s;
    {
        Armed a(mainCtx, vk::FaultInjection{.failPipeline = freshBig});
        s = main.comp->endFrame(bigMain.frameEnd(5, eyes));
    }
    ASSERT_NO_FATAL_FAILURE(expectPipelineRefusal(s, "frame 5"));
    ASSERT_EQ(main.comp->width(), kW2);
    for (uint32_t eye = 0; eye < 2; ++eye) {
        auto out = main.comp->readOutput(eye);
        ASSERT_TRUE(out.ok());
        EXPECT_TRUE(std::all_of(out->data.begin(), out->data.end(), [](std::byte b) { return b == std::byte{0}; }))
            << "eye " << eye << ": the new size's output is not black";
        auto res = main.comp->readReservoirs(eye);
        ASSERT_TRUE(res.ok());
        EXPECT_TRUE(std::all_of(res->begin(), res->end(), [](const glm::uvec4& r) { return r == glm::uvec4(0u); }))
            << "eye " << eye << ": the new size's reservoirs are not empty";
    }
    ASSERT_TRUE(main.comp->endFrame(bigMain.frameEnd(5, eyes)).ok());
    expectSameAsTwin("frame 5 once its pipeline could be made");
    const auto next = frameOfSize(6, kW2, kH2);
    ASSERT_TRUE(bigMain.submit(6, next).ok());
    ASSERT_TRUE(bigTwin.submit(6, next).ok());
    expectSameAsTwin("frame 6");
    EXPECT_EQ(mainCtx.validationErrors(), 0u);
}

// The fp16 probe at Compositor::create runs a pipeline of its own: where it cannot be made the passes
// convert by hand (the same bits), as where the probe has no memory.
TEST_F(DeviceFaultPipeline, TheHalfProbeFallsBackToTheHandConversion) {
    auto plain = Compositor::create(context());
    ASSERT_TRUE(plain.ok());
    if (!(*plain)->usesHardwareHalf()) GTEST_SKIP() << "this device's fp16 conversion is not used anyway";
    auto ctx = freshContext();
    ASSERT_TRUE(ctx);
    {
        Armed a(*ctx, vk::FaultInjection{.failPipeline = 1});
        auto comp = Compositor::create(*ctx);
        ASSERT_TRUE(comp.ok()) << comp.error().message;
        EXPECT_FALSE((*comp)->usesHardwareHalf());
        StereoApp app(**comp, kW, kH, Format::RGBA16F, Format::R32F, Format::RGBA16F);
        const Status first = app.submit(1, goodFrame(1, LaneFormats{}));
        ASSERT_TRUE(first.ok()) << first.message();
        expectSane(**comp, "after the probe's pipeline failed");
    }
    EXPECT_EQ(ctx->validationErrors(), 0u);
}

// ---- Device lost --------------------------------------------------------------------------------

class DeviceFaultLost : public GpuTest {
protected:
    // A refusal that names the loss and says what to do, and that comes at once (no wait, no hang).
    static void expectLostRefusal(const std::function<Status()>& call, const std::string& what) {
        const auto t0 = Clock::now();
        const Status s = call();
        const double ms = std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
        ASSERT_FALSE(s.ok()) << what << " was accepted on a lost device";
        EXPECT_EQ(s.error().code, int(SubmitError::DeviceFailure)) << what << ": " << s.message();
        EXPECT_TRUE(contains(s.message(), kLost)) << what << ": " << s.message();
        EXPECT_TRUE(contains(s.message(), "create a new vk::Context and Compositor")) << what << ": " << s.message();
        EXPECT_LT(ms, 1000.0) << what;
    }
};

TEST_F(DeviceFaultLost, WhileCompositingThenEveryLaterFrameIsRefusedAndANewContextWorks) {
    auto ctx = freshContext();
    ASSERT_TRUE(ctx);
    const CompositorConfig cfg{.foveaDeg = 10.0f, .seed = 31};
    {
        auto comp = Compositor::create(*ctx, cfg);
        ASSERT_TRUE(comp.ok());
        Compositor& c = **comp;
        StereoApp app(c, kW, kH, Format::RGBA16F, Format::R32F, Format::RGBA16F);
        for (uint64_t f = 1; f <= 2; ++f) ASSERT_TRUE(app.submit(f, goodFrame(f, LaneFormats{})).ok());
        const auto eyes = goodFrame(3, LaneFormats{});
        app.write(eyes);
        ctx->injectFaults(lossFault(1));
        expectLostRefusal([&] { return c.endFrame(app.frameEnd(3, eyes)); }, "the frame the device was lost in");
        EXPECT_TRUE(ctx->deviceLost());
        // Every later frame, good or bad, is refused the same way at once.
        expectLostRefusal([&] { return c.endFrame(app.frameEnd(4, eyes)); }, "the next good frame");
        expectLostRefusal(
            [&] {
                layers::FrameEndInfo f = app.frameEnd(5, eyes);
                f.layers.clear();
                return c.endFrame(f);
            },
            "a malformed frame");
        // Everything else that needs the device says so too.
        auto out = c.readOutput(0);
        ASSERT_FALSE(out.ok());
        EXPECT_TRUE(contains(out.error().message, kLost)) << out.error().message;
        auto res = c.readReservoirs(0);
        ASSERT_FALSE(res.ok());
        EXPECT_TRUE(contains(res.error().message, kLost)) << res.error().message;
        auto idx = app.color().acquire();
        ASSERT_TRUE(idx.ok());
        ASSERT_TRUE(app.color().wait().ok());
        const Status w = app.color().write(*idx, 0, eyes[0].color.bytes());
        EXPECT_FALSE(w.ok());
        EXPECT_EQ(w.error().code, int(SwapchainError::DeviceFailure));
        EXPECT_TRUE(contains(w.message(), kLost)) << w.message();
        EXPECT_TRUE(app.color().release().ok());
        auto sc = c.createSwapchain(stereoInfo(Usage::Color, Format::RGBA8));
        ASSERT_FALSE(sc.ok());
        EXPECT_TRUE(contains(sc.error().message, kLost)) << sc.error().message;
        auto another = Compositor::create(*ctx, cfg);
        ASSERT_FALSE(another.ok());
        EXPECT_TRUE(contains(another.error().message, kLost)) << another.error().message;
    }
    EXPECT_EQ(ctx->validationErrors(), 0u);
    ctx.reset();  // the lost context and everything on it go away without a crash

    // A new context and compositor run normally: the same frames as a compositor on the test's
    // own context, bit for bit.
    auto ctx2 = freshContext();
    ASSERT_TRUE(ctx2);
    Lane fresh(*ctx2, cfg, LaneFormats{});
    Lane twin(context(), cfg, LaneFormats{});
    for (uint64_t f = 1; f <= 3; ++f) {
        const auto eyes = goodFrame(f, LaneFormats{});
        ASSERT_TRUE(fresh.app->submit(f, eyes).ok());
        ASSERT_TRUE(twin.app->submit(f, eyes).ok());
        const std::string d = difference(snapshot(*fresh.comp), snapshot(*twin.comp));
        EXPECT_TRUE(d.empty()) << "frame " << f << " on the new context: " << d;
    }
    expectSane(*fresh.comp, "new context");
    EXPECT_FALSE(ctx2->deviceLost());
    EXPECT_EQ(ctx2->validationErrors(), 0u);
}

TEST_F(DeviceFaultLost, AtCompositorCreation) {
    auto ctx = freshContext();
    ASSERT_TRUE(ctx);
    ctx->injectFaults(lossFault(1));
    auto comp = Compositor::create(*ctx);
    ASSERT_FALSE(comp.ok());
    EXPECT_TRUE(contains(comp.error().message, kLost)) << comp.error().message;
    EXPECT_TRUE(ctx->deviceLost());
    EXPECT_EQ(ctx->validationErrors(), 0u);
}

TEST_F(DeviceFaultLost, AtTheFirstFrameResize) {
    auto ctx = freshContext();
    ASSERT_TRUE(ctx);
    auto comp = Compositor::create(*ctx);
    ASSERT_TRUE(comp.ok());
    StereoApp app(**comp, kW, kH, Format::RGBA16F, Format::R32F, Format::RGBA16F);
    const auto eyes = goodFrame(1, LaneFormats{});
    app.write(eyes);
    ctx->injectFaults(lossFault(1));  // the resize's submission
    expectLostRefusal([&] { return (*comp)->endFrame(app.frameEnd(1, eyes)); }, "the first frame");
    EXPECT_EQ((*comp)->width(), 0u);
    expectLostRefusal([&] { return (*comp)->endFrame(app.frameEnd(2, eyes)); }, "the second frame");
    EXPECT_EQ(ctx->validationErrors(), 0u);
}

TEST_F(DeviceFaultLost, DuringAnUpload) {
    auto ctx = freshContext();
    ASSERT_TRUE(ctx);
    auto comp = Compositor::create(*ctx);
    ASSERT_TRUE(comp.ok());
    StereoApp app(**comp, kW, kH, Format::RGBA16F, std::nullopt, std::nullopt);
    ASSERT_TRUE(app.submit(1, goodFrame(1, LaneFormats{Format::RGBA16F, std::nullopt, std::nullopt})).ok());
    ctx->injectFaults(lossFault(1));
    const Status s = app.submit(2, goodFrame(2, LaneFormats{Format::RGBA16F, std::nullopt, std::nullopt}));
    ASSERT_FALSE(s.ok());
    EXPECT_EQ(s.error().code, int(SwapchainError::DeviceFailure)) << s.message();
    EXPECT_TRUE(contains(s.message(), kLost)) << s.message();
    const auto eyes = goodFrame(3, LaneFormats{Format::RGBA16F, std::nullopt, std::nullopt});
    expectLostRefusal([&] { return (*comp)->endFrame(app.frameEnd(3, eyes)); }, "the frame after");
    EXPECT_EQ(ctx->validationErrors(), 0u);
}

}  // namespace
}  // namespace wrsfov::test
