// The integrator's front class (wrsfov/stereo_compositor.h): on the application's device it composites
// exactly as the compositor it runs does with compositorConfig(settings), frame after frame with depth,
// motion, history and the gaze; what it reports of a frame is what the compositor's statistics say; and it
// refuses, changing nothing, the settings it cannot run (the evaluation-only oracles, out-of-range
// values, the foveation mode that only a submitted frame has).
#include "gpu_checks.h"
#include "wrsfov/stereo_compositor.h"

namespace wrsfov::test {
namespace {

constexpr uint32_t W = 64, H = 48;

class Front : public GpuTest {
protected:
    VulkanDevice device() {
        return {context().instance(), context().physicalDevice(), context().device(), context().queueFamily(), 0};
    }
};

layers::Fov frontFov() { return layers::Fov{-0.8f, 0.8f, 0.6f, -0.6f}; }

// The application's side of the front class: one two-layer swapchain per kind, written from the CPU.
struct FrontApp {
    std::unique_ptr<layers::Swapchain> color, depth, motion;

    explicit FrontApp(StereoCompositor& comp) {
        auto make = [&](layers::Usage usage, layers::Format format) {
            layers::SwapchainCreateInfo info;
            info.usage = usage;
            info.format = format;
            info.width = W;
            info.height = H;
            info.arraySize = 2;
            auto sc = comp.createSwapchain(info);
            EXPECT_TRUE(sc.ok());
            return sc.ok() ? std::move(*sc) : nullptr;
        };
        color = make(layers::Usage::Color, layers::Format::RGBA16F);
        depth = make(layers::Usage::Depth, layers::Format::D32F);
        motion = make(layers::Usage::Motion, layers::Format::RGBA16F);
    }
    static Status upload(layers::Swapchain& sc, const HostImage& left, const HostImage& right) {
        auto index = sc.acquire();
        if (!index) return index.error();
        if (Status s = sc.wait(); !s) return s;
        if (Status s = sc.write(*index, 0, left.bytes()); !s) return s;
        if (Status s = sc.write(*index, 1, right.bytes()); !s) return s;
        return sc.release();
    }
    Status submit(StereoCompositor& comp, uint64_t n, const std::array<EyeFrame, 2>& eyes) {
        if (Status s = upload(*color, eyes[0].color, eyes[1].color); !s) return s;
        if (Status s = upload(*depth, *eyes[0].depth, *eyes[1].depth); !s) return s;
        if (Status s = upload(*motion, *eyes[0].motion, *eyes[1].motion); !s) return s;
        layers::FrameEndInfo f;
        f.frameIndex = n;
        f.time_s = double(n) / 90.0;
        layers::ProjectionLayer layer;
        for (uint32_t eye = 0; eye < 2; ++eye) {
            layers::ProjectionView v;
            v.fov = eyes[eye].fov;
            v.color = {color.get(), {0, 0, W, H}, eye};
            v.depth = layers::DepthInfo{{depth.get(), {0, 0, W, H}, eye}, 0.1f, 100.0f, false};
            v.motion = layers::MotionInfo{{motion.get(), {0, 0, W, H}, eye}};
            layer.views.push_back(v);
            f.gaze[eye] = eyes[eye].gaze;
        }
        f.layers.push_back(std::move(layer));
        return comp.endFrame(f);
    }
};

// A drifting texture with depth and motion, the gaze on a path with one invalid sample.
std::array<EyeFrame, 2> frontFrame(uint64_t f) {
    std::array<EyeFrame, 2> eyes;
    const glm::vec2 s = glm::vec2(0.41f, 0.17f) * float(f);
    for (int e = 0; e < 2; ++e) {
        eyes[e].fov = frontFov();
        eyes[e].color = fineTexture(W, H, s.x + 0.5f * float(e), s.y, f == 9 ? 0.8f : 1.0f);
        HostImage depth = HostImage::make(layers::Format::D32F, W, H);
        HostImage motion = HostImage::make(layers::Format::RGBA16F, W, H);
        for (uint32_t y = 0; y < H; ++y)
            for (uint32_t x = 0; x < W; ++x) {
                depth.store(x, y, glm::vec4(0.9f + 0.05f * float(x) / W));
                motion.store(x, y, {-0.41f, -0.17f, 0.0f, 0.0f});
            }
        eyes[e].depth = depth;
        eyes[e].motion = motion;
        eyes[e].gaze = {gazeAtPixel(20.0 + 2.0 * double(f), 24.0, W, H, frontFov()), f != 6, 1.0f};
    }
    return eyes;
}

TEST_F(Front, SameOutputAsTheCompositorItRuns) {
    for (Method method : sanitizedSweep({Method::Wrs, Method::Fov, Method::Taau})) {
        SCOPED_TRACE(std::string(toString(method)));
        Settings settings;
        settings.method = method;
        settings.foveaDeg = 7.0f;
        settings.seed = 3;
        auto front = StereoCompositor::create(device(), settings);
        ASSERT_TRUE(front.ok()) << front.error().message;
        EXPECT_EQ((*front)->outputImage(), VK_NULL_HANDLE);  // no frame yet
        auto config = compositorConfig(settings);
        ASSERT_TRUE(config.ok());
        auto comp = Compositor::create(context(), *config);
        ASSERT_TRUE(comp.ok());
        FrontApp app(**front);
        ASSERT_TRUE(app.color && app.depth && app.motion);
        StereoApp reference(**comp, W, H, layers::Format::RGBA16F, layers::Format::D32F, layers::Format::RGBA16F);
        for (uint64_t f = 1; f <= 12; ++f) {
            const std::string what = "frame " + std::to_string(f);
            const auto eyes = frontFrame(f);
            ASSERT_TRUE(app.submit(**front, f, eyes).ok()) << what;
            ASSERT_TRUE(reference.submit(f, eyes).ok()) << what;
            for (uint32_t eye = 0; eye < 2; ++eye) {
                auto a = (*front)->readOutput(eye);
                auto b = (*comp)->readOutput(eye);
                ASSERT_TRUE(a.ok() && b.ok());
                EXPECT_TRUE(a->data == b->data) << what << " eye " << eye;
            }
            const FrameReport r = (*front)->lastFrame();
            const FrameStats& st = (*comp)->stats();
            EXPECT_EQ(r.frameIndex, f);
            EXPECT_EQ(r.historyReset, f == 1 && method != Method::Fov) << what;  // fov keeps no history
            EXPECT_EQ(r.historyReset, st.historyReset);
            EXPECT_EQ(r.usedDepth, st.usedDepth);
            EXPECT_EQ(r.usedMotion, st.usedMotion);
            EXPECT_EQ(r.gazeFallback[0], f == 6) << what;
            EXPECT_EQ(r.gazeFallback[1], st.gazeFallback[1]);
            EXPECT_TRUE(r.gpuTimed);
            EXPECT_EQ(r.submitted, layers::SubmittedFoveation::Full);
            if (HasFailure()) return;
        }
        EXPECT_NE((*front)->outputImage(), VK_NULL_HANDLE);
        EXPECT_EQ((*front)->width(), W);
        EXPECT_EQ((*front)->height(), H);
        EXPECT_EQ((*front)->deviceName(), context().deviceName());
    }
}

TEST_F(Front, RefusesWhatItCannotRunAndChangesNothing) {
    const auto invalid = static_cast<int>(ConfigError::InvalidValue);
    for (Method oracle : {Method::Oracle, Method::OracleQ}) {
        Settings s;
        s.method = oracle;
        auto front = StereoCompositor::create(device(), s);
        ASSERT_FALSE(front.ok());
        EXPECT_EQ(front.error().code, invalid);
        EXPECT_NE(front.error().message.find("evaluation only"), std::string::npos) << front.error().message;
    }
    Settings nan;
    nan.foveaDeg = std::nanf("");
    EXPECT_FALSE(StereoCompositor::create(device(), nan).ok());
    Settings submitted;
    submitted.foveation = FoveationMode::Submitted;
    EXPECT_FALSE(StereoCompositor::create(device(), submitted).ok());

    auto front = StereoCompositor::create(device());
    ASSERT_TRUE(front.ok());
    FrontApp app(**front);
    ASSERT_TRUE(app.submit(**front, 1, frontFrame(1)).ok());
    ASSERT_TRUE(app.submit(**front, 2, frontFrame(2)).ok());
    EXPECT_FALSE((*front)->lastFrame().historyReset);
    Settings bad;
    bad.foveaDeg = -1.0f;
    const Status refused = (*front)->setSettings(bad);
    ASSERT_FALSE(refused.ok());
    EXPECT_EQ(refused.error().code, invalid);
    EXPECT_EQ((*front)->settings().foveaDeg, Settings{}.foveaDeg);
    ASSERT_TRUE(app.submit(**front, 3, frontFrame(3)).ok());
    EXPECT_FALSE((*front)->lastFrame().historyReset);  // the refusal changed nothing
    Settings taau;
    taau.method = Method::Taau;
    ASSERT_TRUE((*front)->setSettings(taau).ok());
    EXPECT_EQ((*front)->settings().method, Method::Taau);
    ASSERT_TRUE(app.submit(**front, 4, frontFrame(4)).ok());
    EXPECT_TRUE((*front)->lastFrame().historyReset);  // a new method starts without history
    ASSERT_TRUE((*front)->setSettings(Settings{}).ok());
    ASSERT_TRUE(app.submit(**front, 5, frontFrame(5)).ok());
    EXPECT_TRUE((*front)->lastFrame().historyReset);
    ASSERT_TRUE(app.submit(**front, 6, frontFrame(6)).ok());
    EXPECT_FALSE((*front)->lastFrame().historyReset);
    (*front)->resetHistory();
    ASSERT_TRUE(app.submit(**front, 7, frontFrame(7)).ok());
    EXPECT_TRUE((*front)->lastFrame().historyReset);
}

}  // namespace
}  // namespace wrsfov::test
