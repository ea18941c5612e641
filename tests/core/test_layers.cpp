// The submission API without a device: frame-end validation (one refusal code per malformed frame,
// each with a message naming the eye and field), swapchain create-info checks and the
// acquire/wait/release state machine.
#include <cmath>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "layers/formats.h"
#include "layers/frame.h"
#include "layers/swapchain.h"

namespace wrsfov::layers {
namespace {

const float kNaN = std::numeric_limits<float>::quiet_NaN();
const float kInf = std::numeric_limits<float>::infinity();
const float kDeg = 3.14159265f / 180.0f;

// A swapchain with no images: only the state machine of the base class. Its constructor does not
// run validateCreateInfo, which lets a test hand the validator formats no real swapchain accepts.
class FakeSwapchain final : public Swapchain {
public:
    explicit FakeSwapchain(const SwapchainCreateInfo& info) : Swapchain(info) {}
    Status write(uint32_t, uint32_t, std::span<const std::byte>) override { return {}; }
    VkImage image(uint32_t) const override { return VK_NULL_HANDLE; }
};

std::unique_ptr<FakeSwapchain> makeReleased(Usage usage, Format format, uint32_t w, uint32_t h, uint32_t layers = 2) {
    SwapchainCreateInfo ci;
    ci.usage = usage;
    ci.format = format;
    ci.width = w;
    ci.height = h;
    ci.arraySize = layers;
    ci.imageCount = 2;
    auto sc = std::make_unique<FakeSwapchain>(ci);
    EXPECT_TRUE(sc->acquire().ok());
    EXPECT_TRUE(sc->wait().ok());
    EXPECT_TRUE(sc->release().ok());
    return sc;
}

bool contains(const std::string& s, const std::string& part) { return s.find(part) != std::string::npos; }

// One valid stereo frame: colour, depth and motion swapchains with two layers (layer = eye).
class FrameValidation : public ::testing::Test {
protected:
    static constexpr uint32_t W = 64, H = 48;
    void SetUp() override {
        color = makeReleased(Usage::Color, Format::RGBA8_SRGB, W, H);
        depth = makeReleased(Usage::Depth, Format::D32F, W, H);
        motion = makeReleased(Usage::Motion, Format::RGBA16F, W, H);
        frame = valid(10);
        Status s = validator.validate(frame);
        ASSERT_TRUE(s.ok()) << s.message();
        validator.accept(frame);
        frame = valid(11);
        s = validator.validate(frame);
        ASSERT_TRUE(s.ok()) << s.message();
    }
    FrameEndInfo valid(uint64_t index) {
        FrameEndInfo f;
        f.frameIndex = index;
        f.time_s = double(index) / 90.0;
        ProjectionLayer layer;
        for (uint32_t eye = 0; eye < 2; ++eye) {
            ProjectionView v;
            v.color = {color.get(), {0, 0, W, H}, eye};
            v.depth = DepthInfo{{depth.get(), {0, 0, W, H}, eye}, 0.1f, 100.0f, false};
            v.motion = MotionInfo{{motion.get(), {0, 0, W, H}, eye}};
            layer.views.push_back(v);
            f.gaze[eye] = {glm::vec3(0, 0, -1), true, 1.0f};
        }
        f.layers.push_back(layer);
        return f;
    }
    ProjectionView& view(int eye) { return frame.layers[0].views[eye]; }
    // Expects a refusal with `code` whose message contains every part.
    void expectRefused(SubmitError code, std::vector<std::string> parts) {
        Status s = validator.validate(frame);
        ASSERT_FALSE(s.ok()) << "expected " << toString(code);
        EXPECT_EQ(s.error().code, int(code)) << "got " << toString(SubmitError(s.error().code)) << ": " << s.message();
        for (const std::string& p : parts) EXPECT_TRUE(contains(s.message(), p)) << "'" << s.message() << "' lacks '" << p << "'";
    }

    std::unique_ptr<FakeSwapchain> color, depth, motion;
    FrameValidator validator;
    FrameEndInfo frame;
};

TEST_F(FrameValidation, LayerCount) {
    frame.layers.clear();
    expectRefused(SubmitError::LayerCount, {"one projection layer", "got 0"});
    frame = valid(11);
    frame.layers.push_back(frame.layers[0]);
    expectRefused(SubmitError::LayerCount, {"got 2"});
}

TEST_F(FrameValidation, MissingEye) {
    frame.layers[0].views.pop_back();
    expectRefused(SubmitError::MissingEye, {"two views", "got 1"});
    frame = valid(11);
    frame.layers[0].views.push_back(frame.layers[0].views[0]);
    expectRefused(SubmitError::MissingEye, {"got 3"});
}

TEST_F(FrameValidation, NullSwapchain) {
    view(0).color.swapchain = nullptr;
    expectRefused(SubmitError::NullSwapchain, {"left colour"});
    frame = valid(11);
    view(1).depth->subImage.swapchain = nullptr;
    expectRefused(SubmitError::NullSwapchain, {"right depth"});
    frame = valid(11);
    view(1).motion->subImage.swapchain = nullptr;
    expectRefused(SubmitError::NullSwapchain, {"right motion"});
}

TEST_F(FrameValidation, WrongUsage) {
    view(0).color.swapchain = depth.get();
    expectRefused(SubmitError::WrongUsage, {"left colour", "depth swapchain", "color one"});
    frame = valid(11);
    view(1).motion->subImage.swapchain = color.get();
    expectRefused(SubmitError::WrongUsage, {"right motion", "color swapchain"});
}

TEST_F(FrameValidation, UnsupportedFormat) {
    // A colour swapchain holding a depth format, and a motion swapchain holding R32F: formats that
    // validateCreateInfo refuses, reaching the frame through another implementation of Swapchain.
    auto badColor = makeReleased(Usage::Color, Format::D32F, W, H);
    view(1).color.swapchain = badColor.get();
    expectRefused(SubmitError::UnsupportedFormat, {"right colour", "d32f"});
    frame = valid(11);
    auto badMotion = makeReleased(Usage::Motion, Format::R32F, W, H);
    view(0).motion->subImage.swapchain = badMotion.get();
    expectRefused(SubmitError::UnsupportedFormat, {"left motion", "r32f"});
    frame = valid(11);
    auto badDepth = makeReleased(Usage::Depth, Format::RGBA8, W, H);
    view(0).depth->subImage.swapchain = badDepth.get();
    expectRefused(SubmitError::UnsupportedFormat, {"left depth", "rgba8"});
}

TEST_F(FrameValidation, SizeMismatch) {
    view(0).depth->subImage.rect.width = W - 1;
    expectRefused(SubmitError::SizeMismatch, {"left depth", "colour"});
    frame = valid(11);
    view(1).motion->subImage.rect.height = H / 2;
    expectRefused(SubmitError::SizeMismatch, {"right motion", "colour"});
    frame = valid(11);
    // left vs right: the right view uses a 32x48 part of its images (depth and motion alike).
    view(1).color.rect.width = 32;
    view(1).depth->subImage.rect.width = 32;
    view(1).motion->subImage.rect.width = 32;
    expectRefused(SubmitError::SizeMismatch, {"left and right", "64x48 vs 32x48"});
}

TEST_F(FrameValidation, RectOutOfBounds) {
    view(0).color.rect = {8, 0, W, H};  // 8 + 64 > 64
    expectRefused(SubmitError::RectOutOfBounds, {"left colour", "(8,0 64x48)", "64x48 image"});
    frame = valid(11);
    view(1).depth->subImage.rect.x = -1;
    expectRefused(SubmitError::RectOutOfBounds, {"right depth"});
    frame = valid(11);
    view(1).motion->subImage.rect.height = 0;
    expectRefused(SubmitError::RectOutOfBounds, {"right motion", "empty"});
    frame = valid(11);
    view(0).color.rect = {0, 1, W, H};
    expectRefused(SubmitError::RectOutOfBounds, {"left colour"});
}

TEST_F(FrameValidation, ArrayIndexOutOfRange) {
    view(1).color.arrayIndex = 2;
    expectRefused(SubmitError::ArrayIndexOutOfRange, {"right colour", "array layer 2", "with 2"});
    frame = valid(11);
    auto single = makeReleased(Usage::Depth, Format::R32F, W, H, 1);
    view(1).depth->subImage.swapchain = single.get();  // arrayIndex 1 of a one-layer swapchain
    expectRefused(SubmitError::ArrayIndexOutOfRange, {"right depth", "array layer 1", "with 1"});
}

TEST_F(FrameValidation, ImageNotReleased) {
    SwapchainCreateInfo ci;
    ci.usage = Usage::Motion;
    ci.format = Format::RG16F;
    ci.width = W;
    ci.height = H;
    ci.arraySize = 2;
    FakeSwapchain never(ci);  // no image was ever released
    view(0).motion->subImage.swapchain = &never;
    view(1).motion->subImage.swapchain = &never;
    expectRefused(SubmitError::ImageNotReleased, {"left motion", "no released image"});
    // Acquired (and waited) but not released: the application is still writing it.
    frame = valid(11);
    ASSERT_TRUE(color->acquire().ok());
    expectRefused(SubmitError::ImageNotReleased, {"left colour", "acquired"});
    ASSERT_TRUE(color->wait().ok());
    expectRefused(SubmitError::ImageNotReleased, {"left colour", "acquired"});
    ASSERT_TRUE(color->release().ok());
    EXPECT_TRUE(validator.validate(frame).ok());
}

TEST_F(FrameValidation, FrameOutOfOrder) {
    frame.frameIndex = 10;  // the accepted one was 10
    expectRefused(SubmitError::FrameOutOfOrder, {"frame index 10", "does not follow 10"});
    frame.frameIndex = 3;
    expectRefused(SubmitError::FrameOutOfOrder, {"frame index 3"});
    frame = valid(11);
    frame.time_s = 10.0 / 90.0 - 0.001;  // time going back
    expectRefused(SubmitError::FrameOutOfOrder, {"frame time", "before"});
    frame.time_s = std::numeric_limits<double>::quiet_NaN();
    expectRefused(SubmitError::FrameOutOfOrder, {"not finite"});
    frame.time_s = std::numeric_limits<double>::infinity();
    expectRefused(SubmitError::FrameOutOfOrder, {"not finite"});
    // Equal time with a larger index is allowed (non-decreasing time).
    frame = valid(11);
    frame.time_s = 10.0 / 90.0;
    EXPECT_TRUE(validator.validate(frame).ok());
    // A fresh validator takes any first frame, and a refused frame is never accepted as "previous".
    FrameValidator fresh;
    frame = valid(1);
    EXPECT_TRUE(fresh.validate(frame).ok());
}

TEST_F(FrameValidation, InvalidFov) {
    view(0).fov.angleUp = kNaN;
    expectRefused(SubmitError::InvalidFov, {"left view field of view", "not finite"});
    frame = valid(11);
    view(1).fov.angleRight = 90.0f * kDeg;
    expectRefused(SubmitError::InvalidFov, {"right view field of view", "90"});
    frame = valid(11);
    view(1).fov.angleDown = -kInf;
    expectRefused(SubmitError::InvalidFov, {"right view field of view"});
    frame = valid(11);
    view(0).fov.angleLeft = 10.0f * kDeg;
    view(0).fov.angleRight = 10.0f * kDeg;  // left == right
    expectRefused(SubmitError::InvalidFov, {"left view field of view", "angleLeft < angleRight"});
    frame = valid(11);
    view(1).fov.angleUp = -0.2f;
    view(1).fov.angleDown = 0.1f;  // down > up
    expectRefused(SubmitError::InvalidFov, {"right view field of view", "angleDown < angleUp"});
    // Asymmetric and one-sided views are fine as long as left < right and down < up.
    frame = valid(11);
    view(0).fov = {-60.0f * kDeg, -5.0f * kDeg, 89.0f * kDeg, 20.0f * kDeg};
    EXPECT_TRUE(validator.validate(frame).ok());
}

TEST_F(FrameValidation, InvalidDepthRange) {
    view(0).depth->nearZ = 0.0f;
    expectRefused(SubmitError::InvalidDepthRange, {"left depth range", "near 0"});
    frame = valid(11);
    view(1).depth->nearZ = kNaN;
    expectRefused(SubmitError::InvalidDepthRange, {"right depth range"});
    frame = valid(11);
    view(1).depth->farZ = 0.05f;  // far < near
    expectRefused(SubmitError::InvalidDepthRange, {"right depth range", "far 0.05"});
    frame = valid(11);
    view(0).depth->farZ = view(0).depth->nearZ;
    expectRefused(SubmitError::InvalidDepthRange, {"left depth range"});
    frame = valid(11);
    view(0).depth->farZ = -kInf;
    expectRefused(SubmitError::InvalidDepthRange, {"left depth range"});
    frame = valid(11);
    view(0).depth->farZ = kNaN;
    expectRefused(SubmitError::InvalidDepthRange, {"left depth range"});
    frame = valid(11);
    view(1).depth->nearZ = -1.0f;
    expectRefused(SubmitError::InvalidDepthRange, {"right depth range"});
    // An infinite far plane is allowed.
    frame = valid(11);
    view(0).depth->farZ = kInf;
    view(1).depth->farZ = kInf;
    EXPECT_TRUE(validator.validate(frame).ok());
}

TEST_F(FrameValidation, InconsistentViews) {
    view(1).depth.reset();
    expectRefused(SubmitError::InconsistentViews, {"depth", "one view"});
    frame = valid(11);
    view(0).motion.reset();
    expectRefused(SubmitError::InconsistentViews, {"motion", "one view"});
    // Neither view with depth or motion is consistent.
    frame = valid(11);
    for (int e = 0; e < 2; ++e) view(e).depth.reset(), view(e).motion.reset();
    EXPECT_TRUE(validator.validate(frame).ok());
}

TEST_F(FrameValidation, EveryCodeHasItsOwnName) {
    std::vector<std::string> names;
    for (int c = int(SubmitError::LayerCount); c <= int(SubmitError::InvalidSampleOffset); ++c) {
        std::string n(toString(SubmitError(c)));
        EXPECT_NE(n, "?") << c;
        for (const std::string& m : names) EXPECT_NE(n, m);
        names.push_back(n);
    }
}

// Quad views: the valid frame's views become wide views (64x48 over 90° x 74°) with a 40x40 inset
// over +-12° (denser: about 89 against 32 pixels per tangent unit), depth and motion on both.
class QuadValidation : public FrameValidation {
protected:
    void SetUp() override {
        FrameValidation::SetUp();
        insetColor = makeReleased(Usage::Color, Format::RGBA16F, 40, 40);
        insetDepth = makeReleased(Usage::Depth, Format::R32F, 40, 40);
        insetMotion = makeReleased(Usage::Motion, Format::RG16F, 40, 40);
        frame = quad(11);
        Status s = validator.validate(frame);
        ASSERT_TRUE(s.ok()) << s.message();
    }
    FrameEndInfo quad(uint64_t index) {
        FrameEndInfo f = valid(index);
        for (uint32_t eye = 0; eye < 2; ++eye) {
            ProjectionView& v = f.layers[0].views[eye];
            v.fov = Fov{-45 * kDeg, 45 * kDeg, 37 * kDeg, -37 * kDeg};
            InsetView in;
            in.fov = Fov{-12 * kDeg, 12 * kDeg, 12 * kDeg, -12 * kDeg};
            in.color = {insetColor.get(), {0, 0, 40, 40}, eye};
            in.depth = DepthInfo{{insetDepth.get(), {0, 0, 40, 40}, eye}, 0.1f, 100.0f, false};
            in.motion = MotionInfo{{insetMotion.get(), {0, 0, 40, 40}, eye}};
            v.inset = in;
        }
        return f;
    }
    std::unique_ptr<FakeSwapchain> insetColor, insetDepth, insetMotion;
};

TEST_F(QuadValidation, TheOutputIsTheInsetsDensityOverTheWideView) {
    EXPECT_EQ(submittedFoveation(frame.layers[0]), SubmittedFoveation::Quad);
    // 40 px over 2 tan(12°) = 94.1 px per tangent unit; the wide view spans 2 tan(45°) x 2 tan(37°).
    const glm::uvec2 out = outputSize(frame.layers[0]);
    EXPECT_EQ(out.x, uint32_t(std::lround(40 / (2 * std::tan(12 * kDeg)) * 2 * std::tan(45 * kDeg))));
    EXPECT_EQ(out.y, uint32_t(std::lround(40 / (2 * std::tan(12 * kDeg)) * 2 * std::tan(37 * kDeg))));
    frame.layers[0].outputWidth = 300;
    frame.layers[0].outputHeight = 200;
    EXPECT_TRUE(validator.validate(frame).ok());
    EXPECT_EQ(outputSize(frame.layers[0]), glm::uvec2(300, 200));
}

TEST_F(QuadValidation, EveryRefusalNamesEyeFieldAndValue) {
    view(1).inset->fov.angleLeft = -50 * kDeg;  // past the wide view's -45°
    expectRefused(SubmitError::InvalidInset, {"right inset", "angleLeft", "-0.872", "outside", "-0.785"});
    frame = quad(11);
    view(0).inset->fov.angleUp = 40 * kDeg;
    expectRefused(SubmitError::InvalidInset, {"left inset", "angleUp"});
    frame = quad(11);
    view(0).inset->fov.angleDown = kNaN;
    expectRefused(SubmitError::InvalidFov, {"left inset"});
    frame = quad(11);
    // 10 px over 2 tan(12°): 23.5 px per tangent unit, sparser than the wide view's 32.
    view(1).inset->color.rect = view(1).inset->depth->subImage.rect = view(1).inset->motion->subImage.rect = {0, 0, 10, 10};
    expectRefused(SubmitError::InvalidInset, {"right inset", "less dense"});
    frame = quad(11);
    view(0).inset->color.rect = {0, 0, 41, 40};
    expectRefused(SubmitError::RectOutOfBounds, {"left inset colour", "41x40"});
    frame = quad(11);
    view(1).inset->depth.reset();
    expectRefused(SubmitError::InconsistentViews, {"right inset", "no depth"});
    frame = quad(11);
    view(0).inset->depth->farZ = 50.0f;
    expectRefused(SubmitError::InconsistentViews, {"left inset depth range", "far 50", "far 100"});
    frame = quad(11);
    view(0).inset->motion->subImage.rect = {0, 0, 20, 20};
    expectRefused(SubmitError::SizeMismatch, {"left inset motion"});
    frame = quad(11);
    view(1).inset->motion->scale.x = kInf;
    expectRefused(SubmitError::InvalidMotionScale, {"right inset motion"});
    frame = quad(11);
    view(0).inset->color.swapchain = insetDepth.get();
    expectRefused(SubmitError::WrongUsage, {"left inset colour"});
    frame = quad(11);
    view(1).inset.reset();
    expectRefused(SubmitError::InconsistentViews, {"inset", "one view"});
    frame = quad(11);
    frame.layers[0].outputWidth = 100;
    expectRefused(SubmitError::SizeMismatch, {"output size 100x0"});
    frame.layers[0].outputHeight = 20;  // smaller than the 64x48 wide view
    expectRefused(SubmitError::InvalidInset, {"output size 100x20", "smaller", "64x48"});
    frame.layers[0].outputWidth = 20000;
    frame.layers[0].outputHeight = 200;
    expectRefused(SubmitError::InvalidInset, {"20000x200", "larger"});
    // The oracles' reference must cover the output.
    frame = quad(11);
    view(0).reference = SubImage{color.get(), {0, 0, W, H}, 0};
    expectRefused(SubmitError::SizeMismatch, {"left reference is 64x48", "the output"});
    // A full-resolution frame may name its own size only.
    frame = valid(11);
    frame.layers[0].outputWidth = 128;
    frame.layers[0].outputHeight = 96;
    expectRefused(SubmitError::SizeMismatch, {"128x96", "64x48", "only quad views"});
}

// Jittered views (ProjectionView::sampleOffset, InsetView::sampleOffset): inside the pixel, finite,
// each refusal naming the eye, the view, the axis and the value.
TEST_F(QuadValidation, SampleOffsetsInsideThePixelOnly) {
    view(0).sampleOffset = {0.5f, -0.5f};  // the pixel's edges are inside
    view(1).inset->sampleOffset = {-0.25f, 0.125f};
    EXPECT_TRUE(validator.validate(frame).ok());
    view(1).sampleOffset.y = 0.75f;
    expectRefused(SubmitError::InvalidSampleOffset, {"right view", "offset y", "0.75", "outside its pixel"});
    frame = quad(11);
    view(0).inset->sampleOffset.x = -0.51f;
    expectRefused(SubmitError::InvalidSampleOffset, {"left inset", "offset x", "-0.51"});
    frame = quad(11);
    view(0).sampleOffset.x = kNaN;
    expectRefused(SubmitError::InvalidSampleOffset, {"left view", "offset x", "not finite"});
    frame = quad(11);
    view(1).inset->sampleOffset.y = kInf;
    expectRefused(SubmitError::InvalidSampleOffset, {"right inset", "offset y", "not finite"});
    // A full-resolution frame's offset is checked the same way (it is not used).
    frame = valid(11);
    view(0).sampleOffset.x = 2.0f;
    expectRefused(SubmitError::InvalidSampleOffset, {"left view", "offset x"});
}

class RateValidation : public FrameValidation {
protected:
    void SetUp() override {
        FrameValidation::SetUp();
        map = makeReleased(Usage::ShadingRate, Format::R8UI, 4, 3);  // 64x48 at 16x16 px per texel
        frame = rated(11);
        Status s = validator.validate(frame);
        ASSERT_TRUE(s.ok()) << s.message();
    }
    FrameEndInfo rated(uint64_t index) {
        FrameEndInfo f = valid(index);
        for (uint32_t eye = 0; eye < 2; ++eye) f.layers[0].views[eye].rateMap = RateMapInfo{{map.get(), {0, 0, 4, 3}, eye}};
        return f;
    }
    std::unique_ptr<FakeSwapchain> map;
};

TEST_F(RateValidation, WrongSizesFormatsAndMixturesAreRefused) {
    EXPECT_EQ(submittedFoveation(frame.layers[0]), SubmittedFoveation::Rate);
    view(0).rateMap->texelWidth = 12;
    expectRefused(SubmitError::InvalidRateMap, {"left rate map", "12x16", "power of two"});
    frame = rated(11);
    view(1).rateMap->texelHeight = 128;
    expectRefused(SubmitError::InvalidRateMap, {"right rate map", "16x128"});
    frame = rated(11);
    view(1).rateMap->subImage.rect = {0, 0, 4, 2};
    expectRefused(SubmitError::InvalidRateMap, {"right rate map is 4x2 texels", "64x48 view", "needs 4x3"});
    frame = rated(11);
    // 8x8 px per texel needs 8x6 texels; the 4x3 map is the wrong size (and outside no image).
    view(0).rateMap->texelWidth = view(0).rateMap->texelHeight = 8;
    expectRefused(SubmitError::InvalidRateMap, {"needs 8x6"});
    frame = rated(11);
    view(0).rateMap->subImage.swapchain = color.get();
    expectRefused(SubmitError::WrongUsage, {"left rate map", "color swapchain", "shading-rate one"});
    frame = rated(11);
    auto floatMap = makeReleased(Usage::ShadingRate, Format::R32F, 4, 3);
    view(0).rateMap->subImage.swapchain = floatMap.get();
    expectRefused(SubmitError::UnsupportedFormat, {"left rate map", "r32f"});
    frame = rated(11);
    view(0).rateMap.reset();
    expectRefused(SubmitError::InconsistentViews, {"rate map", "one view"});
    frame = rated(11);
    auto insetColor = makeReleased(Usage::Color, Format::RGBA16F, 40, 40);
    for (int e = 0; e < 2; ++e) {
        InsetView in;
        in.fov = Fov{-10 * kDeg, 10 * kDeg, 10 * kDeg, -10 * kDeg};
        in.color = {insetColor.get(), {0, 0, 40, 40}, uint32_t(e)};
        view(e).inset = in;
        view(e).depth.reset();
        view(e).motion.reset();
    }
    expectRefused(SubmitError::InconsistentViews, {"left view", "both an inset and a rate map"});
}

TEST(SwapchainCreateInfo, SizesAndFormatsAreChecked) {
    SwapchainCreateInfo ci;
    ci.usage = Usage::Color;
    ci.format = Format::RGBA16F;
    ci.width = 64;
    ci.height = 48;
    ci.arraySize = 2;
    EXPECT_TRUE(validateCreateInfo(ci).ok());
    auto refused = [](SwapchainCreateInfo c, SwapchainError code, std::vector<std::string> parts) {
        Status s = validateCreateInfo(c);
        ASSERT_FALSE(s.ok());
        EXPECT_EQ(s.error().code, int(code)) << s.message();
        for (const std::string& p : parts) EXPECT_TRUE(contains(s.message(), p)) << s.message() << " / " << p;
    };
    SwapchainCreateInfo c = ci;
    c.format = Format::D32F;
    refused(c, SwapchainError::UnsupportedFormat, {"d32f", "color"});
    c = ci;
    c.usage = Usage::Motion;
    c.format = Format::R32F;
    refused(c, SwapchainError::UnsupportedFormat, {"r32f", "motion"});
    c = ci;
    c.usage = Usage::Depth;
    c.format = Format::RGBA8_SRGB;
    refused(c, SwapchainError::UnsupportedFormat, {"rgba8_srgb", "depth"});
    c = ci;
    c.width = 0;
    refused(c, SwapchainError::InvalidCreateInfo, {"0x48"});
    c = ci;
    c.height = 16385;
    refused(c, SwapchainError::InvalidCreateInfo, {"64x16385"});
    c = ci;
    c.arraySize = 3;
    refused(c, SwapchainError::InvalidCreateInfo, {"array size 3"});
    c = ci;
    c.imageCount = 9;
    refused(c, SwapchainError::InvalidCreateInfo, {"image count 9"});
    c = ci;
    c.imageCount = 0;
    refused(c, SwapchainError::InvalidCreateInfo, {"image count 0"});
    // The full table of what is allowed.
    for (Format f : {Format::RGBA8, Format::RGBA8_SRGB, Format::RGBA16F, Format::D32F, Format::R32F, Format::RG16F}) {
        EXPECT_EQ(isSupported(Usage::Color, f), f == Format::RGBA8 || f == Format::RGBA8_SRGB || f == Format::RGBA16F);
        EXPECT_EQ(isSupported(Usage::Depth, f), f == Format::D32F || f == Format::R32F);
        EXPECT_EQ(isSupported(Usage::Motion, f), f == Format::RG16F || f == Format::RGBA16F);
        EXPECT_EQ(parseFormat(toString(f)), f);
    }
}

TEST(SwapchainStateMachine, AcquireWaitReleaseInOrder) {
    SwapchainCreateInfo ci;
    ci.usage = Usage::Color;
    ci.format = Format::RGBA8;
    ci.width = ci.height = 4;
    ci.imageCount = 2;
    FakeSwapchain sc(ci);
    EXPECT_EQ(sc.lastReleased(), -1);
    EXPECT_FALSE(sc.busy());
    // wait / release with nothing acquired
    Status s = sc.wait();
    ASSERT_FALSE(s.ok());
    EXPECT_EQ(s.error().code, int(SwapchainError::CallOrder));
    EXPECT_TRUE(contains(s.message(), "wait called with no acquired image")) << s.message();
    s = sc.release();
    ASSERT_FALSE(s.ok());
    EXPECT_EQ(s.error().code, int(SwapchainError::CallOrder));
    EXPECT_TRUE(contains(s.message(), "no acquired image")) << s.message();

    auto a = sc.acquire();
    ASSERT_TRUE(a.ok());
    EXPECT_EQ(*a, 0u);
    EXPECT_TRUE(sc.busy());
    EXPECT_FALSE(sc.isWaited(0));
    // release before wait
    s = sc.release();
    ASSERT_FALSE(s.ok());
    EXPECT_EQ(s.error().code, int(SwapchainError::CallOrder));
    EXPECT_TRUE(contains(s.message(), "before wait")) << s.message();
    auto b = sc.acquire();
    ASSERT_TRUE(b.ok());
    EXPECT_EQ(*b, 1u);
    // both images acquired: no image available
    auto c = sc.acquire();
    ASSERT_FALSE(c.ok());
    EXPECT_EQ(c.error().code, int(SwapchainError::NoImageAvailable));
    EXPECT_TRUE(contains(c.error().message, "all 2 swapchain images")) << c.error().message;
    // wait and release take the oldest first
    ASSERT_TRUE(sc.wait().ok());
    EXPECT_TRUE(sc.isWaited(0));
    EXPECT_FALSE(sc.isWaited(1));
    // still full: a waited image is not available either
    EXPECT_FALSE(sc.acquire().ok());
    ASSERT_TRUE(sc.release().ok());
    EXPECT_EQ(sc.lastReleased(), 0);
    EXPECT_TRUE(sc.busy());  // image 1 still acquired
    s = sc.release();        // image 1 was not waited
    ASSERT_FALSE(s.ok());
    EXPECT_EQ(s.error().code, int(SwapchainError::CallOrder));
    ASSERT_TRUE(sc.wait().ok());
    ASSERT_TRUE(sc.release().ok());
    EXPECT_EQ(sc.lastReleased(), 1);
    EXPECT_FALSE(sc.busy());
    // round robin continues
    auto d = sc.acquire();
    ASSERT_TRUE(d.ok());
    EXPECT_EQ(*d, 0u);
    EXPECT_EQ(sc.lastReleased(), 1);  // acquiring does not change what the compositor reads
}

}  // namespace
}  // namespace wrsfov::layers
