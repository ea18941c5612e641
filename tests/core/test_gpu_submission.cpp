// FrameSubmission: a frame submitted with the caller's semaphores (not waited for) or recorded into
// the caller's command buffer composites exactly like a waited frame: the same outputs and
// reservoirs, frame after frame, with motion, depth and history; a submission that cannot be carried
// out is refused and changes nothing.
#include "gpu_checks.h"

namespace wrsfov::test {
namespace {

using Mode = FrameSubmission::Mode;

class Submission : public GpuTest {
protected:
    static constexpr uint32_t W = 40, H = 32;

    void SetUp() override {
        GpuTest::SetUp();
        VkDevice dev = context().device();
        VkCommandPoolCreateInfo pci{VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO};
        pci.flags = VK_COMMAND_POOL_CREATE_RESET_COMMAND_BUFFER_BIT;
        pci.queueFamilyIndex = context().queueFamily();
        ASSERT_EQ(vkCreateCommandPool(dev, &pci, nullptr, &pool_), VK_SUCCESS);
        VkCommandBufferAllocateInfo ai{VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO};
        ai.commandPool = pool_;
        ai.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
        ai.commandBufferCount = 1;
        ASSERT_EQ(vkAllocateCommandBuffers(dev, &ai, &cmd_), VK_SUCCESS);
        VkSemaphoreCreateInfo sci{VK_STRUCTURE_TYPE_SEMAPHORE_CREATE_INFO};
        ASSERT_EQ(vkCreateSemaphore(dev, &sci, nullptr, &composited_), VK_SUCCESS);
        ASSERT_EQ(vkCreateSemaphore(dev, &sci, nullptr, &rendered_), VK_SUCCESS);
        VkFenceCreateInfo fci{VK_STRUCTURE_TYPE_FENCE_CREATE_INFO};
        ASSERT_EQ(vkCreateFence(dev, &fci, nullptr, &fence_), VK_SUCCESS);
    }
    void TearDown() override {
        VkDevice dev = context().device();
        vkQueueWaitIdle(context().queue());
        vkDestroyFence(dev, fence_, nullptr);
        vkDestroySemaphore(dev, rendered_, nullptr);
        vkDestroySemaphore(dev, composited_, nullptr);
        vkDestroyCommandPool(dev, pool_, nullptr);
        GpuTest::TearDown();
    }

    // The caller's own submission on the compositor's queue: `cmd_` (recorded by `record`) waiting
    // for `wait` (if any), signalling `signal` (if any) and fence_, then waited for on the CPU.
    void submitOwn(const std::function<void(VkCommandBuffer)>& record, VkSemaphore wait, VkSemaphore signal) {
        VkCommandBufferBeginInfo bi{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
        bi.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
        ASSERT_EQ(vkResetCommandBuffer(cmd_, 0), VK_SUCCESS);
        ASSERT_EQ(vkBeginCommandBuffer(cmd_, &bi), VK_SUCCESS);
        if (record) record(cmd_);
        ASSERT_EQ(vkEndCommandBuffer(cmd_), VK_SUCCESS);
        const VkPipelineStageFlags stage = VK_PIPELINE_STAGE_ALL_COMMANDS_BIT;
        VkSubmitInfo si{VK_STRUCTURE_TYPE_SUBMIT_INFO};
        si.commandBufferCount = 1;
        si.pCommandBuffers = &cmd_;
        si.waitSemaphoreCount = wait ? 1 : 0;
        si.pWaitSemaphores = &wait;
        si.pWaitDstStageMask = &stage;
        si.signalSemaphoreCount = signal ? 1 : 0;
        si.pSignalSemaphores = &signal;
        ASSERT_EQ(vkQueueSubmit(context().queue(), 1, &si, fence_), VK_SUCCESS);
        ASSERT_EQ(vkWaitForFences(context().device(), 1, &fence_, VK_TRUE, UINT64_MAX), VK_SUCCESS);
        ASSERT_EQ(vkResetFences(context().device(), 1, &fence_), VK_SUCCESS);
    }

    static std::array<EyeFrame, 2> frame(RandomScene& scene) { return scene.stereoFrame(W, H); }

    static void expectSame(Compositor& a, Compositor& b, const std::string& what) {
        expectSameOutputs(a, b, what);
        expectSameReservoirs(a, b, what);
    }

    VkCommandPool pool_ = VK_NULL_HANDLE;
    VkCommandBuffer cmd_ = VK_NULL_HANDLE;
    VkSemaphore composited_ = VK_NULL_HANDLE, rendered_ = VK_NULL_HANDLE;
    VkFence fence_ = VK_NULL_HANDLE;
};

TEST_F(Submission, SubmitAndRecordCompositeExactlyLikeWait) {
    for (Method method : {Method::Wrs, Method::WrsPaper, Method::FovTaa}) {
        SCOPED_TRACE(std::string(toString(method)));
        CompositorConfig cfg;
        cfg.method = method;
        cfg.seed = 5;
        auto waited = Compositor::create(context(), cfg);
        auto submitted = Compositor::create(context(), cfg);
        auto recorded = Compositor::create(context(), cfg);
        ASSERT_TRUE(waited.ok() && submitted.ok() && recorded.ok());
        StereoApp appW(**waited, W, H, layers::Format::RGBA8_SRGB, layers::Format::R32F, layers::Format::RGBA16F);
        StereoApp appS(**submitted, W, H, layers::Format::RGBA8_SRGB, layers::Format::R32F, layers::Format::RGBA16F);
        StereoApp appR(**recorded, W, H, layers::Format::RGBA8_SRGB, layers::Format::R32F, layers::Format::RGBA16F);
        RandomScene scene(31);
        for (uint64_t n = 1; n <= 5; ++n) {
            const auto eyes = frame(scene);
            ASSERT_TRUE(appW.submit(n, eyes).ok());

            // Submit: the caller's "rendering" signals `rendered_`, the compositor waits for it and
            // signals `composited_`, which the caller's "present" waits for. endFrame returns
            // without waiting; the present submission's fence is all the CPU waits on.
            appS.write(eyes);
            submitOwn(nullptr, VK_NULL_HANDLE, rendered_);
            const VkSemaphore waitFor[] = {rendered_};
            const VkPipelineStageFlags stages[] = {VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT};
            const VkSemaphore signal[] = {composited_};
            FrameSubmission sub;
            sub.mode = Mode::Submit;
            sub.waitSemaphores = waitFor;
            sub.waitStages = stages;
            sub.signalSemaphores = signal;
            Status s = (*submitted)->endFrame(appS.frameEnd(n, eyes), sub);
            ASSERT_TRUE(s.ok()) << s.message();
            EXPECT_FALSE((*submitted)->stats().gpu.valid) << "no GPU times before waitFrame()";
            submitOwn(nullptr, composited_, VK_NULL_HANDLE);
            s = (*submitted)->waitFrame();
            ASSERT_TRUE(s.ok()) << s.message();
            EXPECT_EQ((*submitted)->stats().gpu.valid, context().timestampPeriodNs() > 0);
            EXPECT_EQ((*submitted)->stats().frameIndex, n);
            EXPECT_TRUE((*submitted)->waitFrame().ok()) << "a second wait has nothing to do";

            // Record: into the caller's command buffer, which the caller submits and waits for.
            appR.write(eyes);
            Status recordedStatus;
            submitOwn([&](VkCommandBuffer cb) {
                FrameSubmission rec;
                rec.mode = Mode::Record;
                rec.commandBuffer = cb;
                recordedStatus = (*recorded)->endFrame(appR.frameEnd(n, eyes), rec);
            }, VK_NULL_HANDLE, VK_NULL_HANDLE);
            ASSERT_TRUE(recordedStatus.ok()) << recordedStatus.message();
            EXPECT_FALSE((*recorded)->stats().gpu.valid) << "recorded frames carry no GPU times";

            expectSame(**waited, **submitted, "Submit, frame " + std::to_string(n));
            expectSame(**waited, **recorded, "Record, frame " + std::to_string(n));
        }
        EXPECT_FALSE((*waited)->stats().historyReset);
        EXPECT_TRUE((*waited)->stats().usedMotion);
    }
}

TEST_F(Submission, BackToBackSubmitFramesWaitForEachOther) {
    // Frames submitted without the caller ever waiting: each endFrame waits for the previous frame
    // before it reuses the command buffer and parameters, and reads are ordered after the frame.
    CompositorConfig cfg;
    auto waited = Compositor::create(context(), cfg);
    auto submitted = Compositor::create(context(), cfg);
    ASSERT_TRUE(waited.ok() && submitted.ok());
    StereoApp appW(**waited, W, H, layers::Format::RGBA8_SRGB, layers::Format::R32F, layers::Format::RGBA16F);
    StereoApp appS(**submitted, W, H, layers::Format::RGBA8_SRGB, layers::Format::R32F, layers::Format::RGBA16F);
    RandomScene scene(32);
    for (uint64_t n = 1; n <= 6; ++n) {
        const auto eyes = frame(scene);
        ASSERT_TRUE(appW.submit(n, eyes).ok());
        appS.write(eyes);
        FrameSubmission sub;
        sub.mode = Mode::Submit;
        Status s = (*submitted)->endFrame(appS.frameEnd(n, eyes), sub);
        ASSERT_TRUE(s.ok()) << s.message();
    }
    expectSame(**waited, **submitted, "after 6 frames never waited for");
    EXPECT_TRUE((*submitted)->waitFrame().ok());
}

TEST_F(Submission, RefusedSubmissionsChangeNothing) {
    CompositorConfig cfg;
    auto twin = Compositor::create(context(), cfg);
    auto comp = Compositor::create(context(), cfg);
    ASSERT_TRUE(twin.ok() && comp.ok());
    StereoApp appT(**twin, W, H, layers::Format::RGBA8_SRGB, layers::Format::R32F, layers::Format::RGBA16F);
    StereoApp appC(**comp, W, H, layers::Format::RGBA8_SRGB, layers::Format::R32F, layers::Format::RGBA16F);
    RandomScene scene(33);
    auto eyes = frame(scene);
    ASSERT_TRUE(appT.submit(1, eyes).ok());
    ASSERT_TRUE(appC.submit(1, eyes).ok());

    const VkSemaphore one[] = {rendered_};
    const VkSemaphore none[] = {VK_NULL_HANDLE};
    const VkPipelineStageFlags stage[] = {VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT};
    const VkPipelineStageFlags emptyStage[] = {0};
    struct Case {
        const char* name;
        FrameSubmission sub;
        const char* message;
    };
    std::vector<Case> cases;
    {
        FrameSubmission s;
        s.mode = Mode::Record;
        cases.push_back({"record_without_command_buffer", s, "Record needs the caller's command buffer"});
        s.commandBuffer = cmd_;
        s.signalSemaphores = one;
        cases.push_back({"record_with_semaphores", s, "semaphores go with Submit or Wait"});
    }
    {
        FrameSubmission s;
        s.commandBuffer = cmd_;
        cases.push_back({"wait_with_command_buffer", s, "a command buffer goes with Record only"});
        s.mode = Mode::Submit;
        cases.push_back({"submit_with_command_buffer", s, "a command buffer goes with Record only"});
    }
    {
        FrameSubmission s;
        s.mode = Mode::Submit;
        s.waitSemaphores = one;
        cases.push_back({"wait_semaphore_without_stage", s, "1 wait semaphores need as many stage masks, got 0"});
        s.waitStages = emptyStage;
        cases.push_back({"wait_stage_empty", s, "wait stage mask 0 is empty"});
        s.waitSemaphores = none;
        s.waitStages = stage;
        cases.push_back({"null_wait_semaphore", s, "a semaphore is VK_NULL_HANDLE"});
    }
    {
        FrameSubmission s;
        s.signalSemaphores = none;
        cases.push_back({"null_signal_semaphore", s, "a semaphore is VK_NULL_HANDLE"});
        s = {};
        s.mode = Mode(7);
        cases.push_back({"unknown_mode", s, "frame submission mode 7 is not Wait, Submit or Record"});
    }
    eyes = frame(scene);
    appC.write(eyes);
    for (const Case& c : cases) {
        SCOPED_TRACE(c.name);
        Status s = (*comp)->endFrame(appC.frameEnd(2, eyes), c.sub);
        ASSERT_FALSE(s.ok());
        EXPECT_EQ(s.error().code, int(layers::SubmitError::InvalidSubmission));
        EXPECT_NE(s.message().find(c.message), std::string::npos) << s.message();
        EXPECT_EQ((*comp)->stats().frameIndex, 1u) << "the refused frame changed the statistics";
    }
    expectSame(**twin, **comp, "after the refusals");
    // The same frame (same index) goes through afterwards, identical to the twin that never saw them.
    ASSERT_TRUE(appT.submit(2, eyes).ok());
    Status s = (*comp)->endFrame(appC.frameEnd(2, eyes));
    ASSERT_TRUE(s.ok()) << s.message();
    expectSame(**twin, **comp, "the next good frame");
}

}  // namespace
}  // namespace wrsfov::test
