// docs/bad-input.md, "Layer and views": every malformed field of a frame end, one named row each,
// through the real compositor. Each row proves the SubmitError code and message, that the refused
// frame left the compositor bit-identical (reservoirs, outputs, stats, parameters), and that the
// next good frame gives exactly what a twin compositor that never saw the bad frame gives.
#include <cmath>
#include <functional>
#include <limits>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "robust_rig.h"

namespace wrsfov::test {
namespace {

using layers::Format;
using layers::SubmitError;
using layers::Usage;
using F = layers::FrameEndInfo;

const float kNaN = std::numeric_limits<float>::quiet_NaN();
const float kInf = std::numeric_limits<float>::infinity();
const float kDeg = 3.14159265f / 180.0f;

struct RefusalRow {
    std::string name;
    SubmitError code;
    std::vector<std::string> message;  ///< parts the message must contain
    std::function<void(TwinChain&, F&)> edit;
    std::function<void(TwinChain&)> undo = nullptr;  ///< restores swapchain state the edit changed
};

void PrintTo(const RefusalRow& r, std::ostream* os) { *os << r.name; }

std::vector<layers::ProjectionView>& views(F& f) { return f.layers.at(0).views; }
layers::ProjectionView& left(F& f) { return views(f).at(0); }
layers::ProjectionView& right(F& f) { return views(f).at(1); }

// Swapchains no real compositor makes: formats validateCreateInfo refuses, or another implementation.
layers::Swapchain& fake(Usage u, Format f) {
    static std::map<int, std::unique_ptr<FakeSwapchain>> fakes;
    auto& p = fakes[int(u) * 16 + int(f)];
    if (!p) p = std::make_unique<FakeSwapchain>(u, f, kW, kH);
    return *p;
}

std::vector<RefusalRow> rows() {
    std::vector<RefusalRow> r;
    // Structure of the submission.
    r.push_back({"layers_none", SubmitError::LayerCount, {"one projection layer", "got 0"}, [](TwinChain&, F& f) {
                     f.layers.clear();
                 }});
    r.push_back(
        {"layers_two", SubmitError::LayerCount, {"got 2"}, [](TwinChain&, F& f) { f.layers.push_back(f.layers[0]); }});
    r.push_back(
        {"views_none", SubmitError::MissingEye, {"two views", "got 0"}, [](TwinChain&, F& f) { views(f).clear(); }});
    r.push_back({"views_one", SubmitError::MissingEye, {"got 1"}, [](TwinChain&, F& f) { views(f).pop_back(); }});
    r.push_back(
        {"views_three", SubmitError::MissingEye, {"got 3"}, [](TwinChain&, F& f) { views(f).push_back(left(f)); }});
    r.push_back(
        {"views_differ_in_size", SubmitError::SizeMismatch, {"left and right", "32x24 vs 16x24"}, [](TwinChain&, F& f) {
             right(f).color.rect.width = kW / 2;
             right(f).depth->subImage.rect.width = kW / 2;
             right(f).motion->subImage.rect.width = kW / 2;
         }});

    // Colour sub-image.
    r.push_back(
        {"color_swapchain_missing", SubmitError::NullSwapchain, {"left colour", "no swapchain"}, [](TwinChain&, F& f) {
             left(f).color.swapchain = nullptr;
         }});
    r.push_back({"color_swapchain_is_depth",
                 SubmitError::WrongUsage,
                 {"right colour", "depth swapchain"},
                 [](TwinChain& c, F& f) { right(f).color.swapchain = c.main.app->depth(); }});
    r.push_back({"color_format_d32f", SubmitError::UnsupportedFormat, {"left colour", "d32f"}, [](TwinChain&, F& f) {
                     left(f).color.swapchain = &fake(Usage::Color, Format::D32F);
                 }});
    r.push_back({"color_format_rg16f", SubmitError::UnsupportedFormat, {"right colour", "rg16f"}, [](TwinChain&, F& f) {
                     right(f).color.swapchain = &fake(Usage::Color, Format::RG16F);
                 }});
    r.push_back(
        {"color_rect_empty_width", SubmitError::RectOutOfBounds, {"left colour", "empty"}, [](TwinChain&, F& f) {
             left(f).color.rect.width = 0;
         }});
    r.push_back(
        {"color_rect_empty_height", SubmitError::RectOutOfBounds, {"right colour", "empty"}, [](TwinChain&, F& f) {
             right(f).color.rect.height = 0;
         }});
    r.push_back(
        {"color_rect_negative_x", SubmitError::RectOutOfBounds, {"left colour", "(-1,0 32x24)"}, [](TwinChain&, F& f) {
             left(f).color.rect.x = -1;
         }});
    r.push_back(
        {"color_rect_negative_y", SubmitError::RectOutOfBounds, {"right colour", "(0,-7 32x24)"}, [](TwinChain&, F& f) {
             right(f).color.rect.y = -7;
         }});
    r.push_back(
        {"color_rect_past_edge", SubmitError::RectOutOfBounds, {"left colour", "32x24 image"}, [](TwinChain&, F& f) {
             left(f).color.rect.x = 1;
         }});
    r.push_back(
        {"color_rect_huge_width", SubmitError::RectOutOfBounds, {"left colour", "4294967295x24"}, [](TwinChain&, F& f) {
             left(f).color.rect.width = 0xffffffffu;
         }});
    r.push_back(
        {"color_rect_huge_offset", SubmitError::RectOutOfBounds, {"right colour", "2147483647"}, [](TwinChain&, F& f) {
             right(f).color.rect.y = std::numeric_limits<int32_t>::max();
         }});
    r.push_back({"color_array_index_2",
                 SubmitError::ArrayIndexOutOfRange,
                 {"right colour", "array layer 2", "with 2"},
                 [](TwinChain&, F& f) { right(f).color.arrayIndex = 2; }});
    r.push_back({"color_array_index_huge",
                 SubmitError::ArrayIndexOutOfRange,
                 {"left colour", "4294967295"},
                 [](TwinChain&, F& f) { left(f).color.arrayIndex = 0xffffffffu; }});
    r.push_back({"color_never_released",
                 SubmitError::ImageNotReleased,
                 {"left colour", "no released image"},
                 [](TwinChain& c, F& f) {
                     left(f).color.swapchain = right(f).color.swapchain =
                         &c.neverReleased(Usage::Color, c.main.formats.color);
                 }});
    r.push_back(
        {"color_still_acquired",
         SubmitError::ImageNotReleased,
         {"left colour", "acquired"},
         [](TwinChain& c, F&) { ASSERT_TRUE(c.main.app->color().acquire().ok()); },
         [](TwinChain& c) { ASSERT_TRUE(c.main.app->color().wait().ok() && c.main.app->color().release().ok()); }});
    r.push_back(
        {"color_waited_not_released",
         SubmitError::ImageNotReleased,
         {"left colour", "release it first"},
         [](TwinChain& c, F&) { ASSERT_TRUE(c.main.app->color().acquire().ok() && c.main.app->color().wait().ok()); },
         [](TwinChain& c) { ASSERT_TRUE(c.main.app->color().release().ok()); }});
    r.push_back({"color_other_compositor",
                 SubmitError::ForeignSwapchain,
                 {"left colour", "not created by this compositor"},
                 [](TwinChain& c, F& f) { left(f).color.swapchain = &c.foreignColor(); }});
    r.push_back({"color_other_implementation", SubmitError::ForeignSwapchain, {"right colour"}, [](TwinChain& c, F& f) {
                     right(f).color.swapchain = &fake(Usage::Color, c.main.formats.color);
                 }});

    // Depth sub-image and range.
    r.push_back(
        {"depth_swapchain_missing", SubmitError::NullSwapchain, {"right depth", "no swapchain"}, [](TwinChain&, F& f) {
             right(f).depth->subImage.swapchain = nullptr;
         }});
    r.push_back({"depth_swapchain_is_motion",
                 SubmitError::WrongUsage,
                 {"left depth", "motion swapchain"},
                 [](TwinChain& c, F& f) { left(f).depth->subImage.swapchain = c.main.app->motion(); }});
    r.push_back({"depth_format_rgba8", SubmitError::UnsupportedFormat, {"left depth", "rgba8"}, [](TwinChain&, F& f) {
                     left(f).depth->subImage.swapchain = &fake(Usage::Depth, Format::RGBA8);
                 }});
    r.push_back({"depth_rect_size_differs",
                 SubmitError::SizeMismatch,
                 {"left depth", "differs from its colour"},
                 [](TwinChain&, F& f) { left(f).depth->subImage.rect.width = kW - 1; }});
    r.push_back({"depth_rect_negative_x", SubmitError::RectOutOfBounds, {"right depth"}, [](TwinChain&, F& f) {
                     right(f).depth->subImage.rect.x = -3;
                 }});
    r.push_back({"depth_rect_empty", SubmitError::RectOutOfBounds, {"left depth", "empty"}, [](TwinChain&, F& f) {
                     left(f).depth->subImage.rect.height = 0;
                 }});
    r.push_back({"depth_array_index_3",
                 SubmitError::ArrayIndexOutOfRange,
                 {"left depth", "array layer 3"},
                 [](TwinChain&, F& f) { left(f).depth->subImage.arrayIndex = 3; }});
    r.push_back({"depth_never_released",
                 SubmitError::ImageNotReleased,
                 {"left depth", "no released image"},
                 [](TwinChain& c, F& f) {
                     left(f).depth->subImage.swapchain = right(f).depth->subImage.swapchain =
                         &c.neverReleased(Usage::Depth, Format::R32F);
                 }});
    r.push_back({"depth_other_implementation", SubmitError::ForeignSwapchain, {"left depth"}, [](TwinChain&, F& f) {
                     left(f).depth->subImage.swapchain = &fake(Usage::Depth, Format::R32F);
                 }});
    r.push_back({"depth_one_view_only",
                 SubmitError::InconsistentViews,
                 {"depth is given for one view only"},
                 [](TwinChain&, F& f) { right(f).depth.reset(); }});
    const std::pair<const char*, float> nears[] = {{"nan", kNaN},  {"pos_inf", kInf},   {"neg_inf", -kInf},
                                                   {"zero", 0.0f}, {"negative", -0.1f}, {"neg_huge", -3e38f}};
    for (auto [kind, v] : nears)
        r.push_back({std::string("depth_near_") + kind,
                     SubmitError::InvalidDepthRange,
                     {"left depth range", "0 < nearZ < farZ"},
                     [v = v](TwinChain&, F& f) { left(f).depth->nearZ = v; }});
    const std::pair<const char*, float> fars[] = {{"nan", kNaN},         {"neg_inf", -kInf},   {"zero", 0.0f},
                                                  {"negative", -100.0f}, {"equal_near", 0.1f}, {"below_near", 0.05f}};
    for (auto [kind, v] : fars)
        r.push_back({std::string("depth_far_") + kind,
                     SubmitError::InvalidDepthRange,
                     {"right depth range"},
                     [v = v](TwinChain&, F& f) { right(f).depth->farZ = v; }});

    // Motion sub-image.
    r.push_back(
        {"motion_swapchain_missing", SubmitError::NullSwapchain, {"left motion", "no swapchain"}, [](TwinChain&, F& f) {
             left(f).motion->subImage.swapchain = nullptr;
         }});
    r.push_back({"motion_swapchain_is_color",
                 SubmitError::WrongUsage,
                 {"right motion", "color swapchain"},
                 [](TwinChain& c, F& f) { right(f).motion->subImage.swapchain = &c.main.app->color(); }});
    r.push_back({"motion_format_r32f", SubmitError::UnsupportedFormat, {"left motion", "r32f"}, [](TwinChain&, F& f) {
                     left(f).motion->subImage.swapchain = &fake(Usage::Motion, Format::R32F);
                 }});
    r.push_back(
        {"motion_format_rgba8", SubmitError::UnsupportedFormat, {"right motion", "rgba8"}, [](TwinChain&, F& f) {
             right(f).motion->subImage.swapchain = &fake(Usage::Motion, Format::RGBA8);
         }});
    r.push_back({"motion_rect_size_differs",
                 SubmitError::SizeMismatch,
                 {"right motion", "differs from its colour"},
                 [](TwinChain&, F& f) { right(f).motion->subImage.rect.height = kH / 2; }});
    r.push_back({"motion_rect_past_edge", SubmitError::RectOutOfBounds, {"left motion"}, [](TwinChain&, F& f) {
                     left(f).motion->subImage.rect.y = 1;
                 }});
    r.push_back({"motion_array_index_2",
                 SubmitError::ArrayIndexOutOfRange,
                 {"right motion", "array layer 2"},
                 [](TwinChain&, F& f) { right(f).motion->subImage.arrayIndex = 2; }});
    r.push_back(
        {"motion_still_acquired",
         SubmitError::ImageNotReleased,
         {"left motion", "acquired"},
         [](TwinChain& c, F&) { ASSERT_TRUE(c.main.app->motion()->acquire().ok()); },
         [](TwinChain& c) { ASSERT_TRUE(c.main.app->motion()->wait().ok() && c.main.app->motion()->release().ok()); }});
    r.push_back({"motion_other_implementation", SubmitError::ForeignSwapchain, {"right motion"}, [](TwinChain&, F& f) {
                     right(f).motion->subImage.swapchain = &fake(Usage::Motion, Format::RGBA16F);
                 }});
    r.push_back({"motion_one_view_only",
                 SubmitError::InconsistentViews,
                 {"motion is given for one view only"},
                 [](TwinChain&, F& f) { left(f).motion.reset(); }});

    // Field of view angles (radians).
    struct FovCase {
        const char* name;
        float layers::Fov::*field;
        float value;
        const char* part;
    };
    const FovCase fovs[] = {
        {"fov_left_nan", &layers::Fov::angleLeft, kNaN, "not finite"},
        {"fov_right_pos_inf", &layers::Fov::angleRight, kInf, "not finite"},
        {"fov_up_neg_inf", &layers::Fov::angleUp, -kInf, "not finite"},
        {"fov_down_nan", &layers::Fov::angleDown, kNaN, "not finite"},
        {"fov_left_minus_90", &layers::Fov::angleLeft, -90.0f * kDeg, "(-90°, 90°)"},
        {"fov_right_plus_90", &layers::Fov::angleRight, 90.0f * kDeg, "(-90°, 90°)"},
        {"fov_up_huge", &layers::Fov::angleUp, 1e30f, "(-90°, 90°)"},
        {"fov_down_huge_negative", &layers::Fov::angleDown, -1e30f, "(-90°, 90°)"},
        {"fov_left_positive_past_right", &layers::Fov::angleLeft, 60.0f * kDeg, "angleLeft < angleRight"},
        {"fov_right_negative_past_left", &layers::Fov::angleRight, -60.0f * kDeg, "angleLeft < angleRight"},
        {"fov_down_above_up", &layers::Fov::angleDown, 50.0f * kDeg, "angleDown < angleUp"},
        {"fov_up_equal_down", &layers::Fov::angleUp, -48.0f * kDeg, "angleDown < angleUp"},
    };
    for (const FovCase& k : fovs)
        r.push_back({k.name, SubmitError::InvalidFov, {"right view field of view", k.part}, [k](TwinChain&, F& f) {
                         right(f).fov.*k.field = k.value;
                     }});

    // Frame order and time.
    r.push_back({"frame_index_repeated", SubmitError::FrameOutOfOrder, {"does not follow"}, [](TwinChain& c, F& f) {
                     f.frameIndex = c.next() - 1;
                 }});
    r.push_back({"frame_index_backwards", SubmitError::FrameOutOfOrder, {"frame index 0"}, [](TwinChain&, F& f) {
                     f.frameIndex = 0;
                 }});
    r.push_back({"frame_time_backwards", SubmitError::FrameOutOfOrder, {"frame time", "before"}, [](TwinChain&, F& f) {
                     f.time_s = -1.0;
                 }});
    r.push_back({"frame_time_nan", SubmitError::FrameOutOfOrder, {"not finite"}, [](TwinChain&, F& f) {
                     f.time_s = std::numeric_limits<double>::quiet_NaN();
                 }});
    r.push_back({"frame_time_pos_inf", SubmitError::FrameOutOfOrder, {"not finite"}, [](TwinChain&, F& f) {
                     f.time_s = std::numeric_limits<double>::infinity();
                 }});
    r.push_back({"frame_time_neg_inf", SubmitError::FrameOutOfOrder, {"not finite"}, [](TwinChain&, F& f) {
                     f.time_s = -std::numeric_limits<double>::infinity();
                 }});
    return r;
}

TwinChain& chain() {
    static TwinChain c(CompositorConfig{.foveaDeg = 10.0f, .seed = 3}, LaneFormats{});
    return c;
}

class Refusal : public GpuTest, public ::testing::WithParamInterface<RefusalRow> {};

TEST_P(Refusal, Row) {
    const RefusalRow& row = GetParam();
    TwinChain& c = chain();
    // Some history first, then the state the bad frame must not touch.
    const int warmUp = c.next() == 1 ? 3 : 1;
    for (int i = 0; i < warmUp; ++i) ASSERT_NO_FATAL_FAILURE(c.stepBoth("before the bad frame"));
    const Snapshot before = snapshot(*c.main.comp);

    const std::array<EyeFrame, 2> eyes = goodFrame(c.next(), c.main.formats);
    c.main.app->write(eyes);
    F f = c.main.app->frameEnd(c.next(), eyes);
    row.edit(c, f);
    const Status s = c.main.comp->endFrame(f);
    if (row.undo) row.undo(c);
    ASSERT_FALSE(s.ok()) << row.name << " was accepted";
    EXPECT_EQ(s.error().code, int(row.code))
        << "got " << layers::toString(SubmitError(s.error().code)) << ": " << s.message();
    for (const std::string& part : row.message)
        EXPECT_TRUE(contains(s.message(), part)) << "'" << s.message() << "' lacks '" << part << "'";

    const std::string changed = difference(before, snapshot(*c.main.comp));
    EXPECT_TRUE(changed.empty()) << "the refused frame changed the compositor: " << changed;
    // The next good frame (same index: a refused frame does not count) matches the twin exactly.
    ASSERT_NO_FATAL_FAILURE(c.stepBoth("after the bad frame"));
    expectSane(*c.main.comp, row.name);
}

INSTANTIATE_TEST_SUITE_P(BadFrame, Refusal, ::testing::ValuesIn(rows()),
                         [](const ::testing::TestParamInfo<RefusalRow>& i) { return i.param.name; });

}  // namespace
}  // namespace wrsfov::test
