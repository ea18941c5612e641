// docs/bad-input.md, "Images" and "Gaze": values that are not refused but sanitized, one named row
// each. Three groups:
//   Substitute – the bad value must act exactly like the documented substitute: the main compositor
//                gets the bad frame, its twin the substitute, and both must stay bit-identical.
//   Sanitize   – no exact substitute exists (e.g. a NaN colour has weight 0): the GPU must agree with
//                the CPU reference started from the GPU's own history, every reservoir stays finite,
//                the row's documented fallback holds pixel by pixel, and the next good frame keeps
//                the history (M continues).
//   Accepted   – unusual but valid submissions (frame index jumps, equal times, mixed formats).
#include <cmath>
#include <cstring>
#include <functional>
#include <limits>
#include <map>
#include <string>
#include <vector>

#include "robust_rig.h"

namespace wrsfov::test {
namespace {

using layers::Format;
using Eyes = std::array<EyeFrame, 2>;
using F = layers::FrameEndInfo;

const float kNaN = std::numeric_limits<float>::quiet_NaN();
const float kInf = std::numeric_limits<float>::infinity();
const float kDeg = 3.14159265f / 180.0f;

// The poisoned patch of every eye image.
bool inPatch(uint32_t x, uint32_t y) { return x >= 4 && x < 20 && y >= 4 && y < 14; }

template <typename Fn>
void forPatch(HostImage& img, Fn&& fn) {
    for (uint32_t y = 0; y < img.height; ++y)
        for (uint32_t x = 0; x < img.width; ++x)
            if (inPatch(x, y)) fn(x, y);
}
void setColor(Eyes& eyes, glm::vec4 v) {
    for (auto& e : eyes) forPatch(e.color, [&](uint32_t x, uint32_t y) { e.color.store(x, y, v); });
}
// Sets channel `c` of the colour in the patch, keeping the others.
void setColorChannel(Eyes& eyes, int c, float v) {
    for (auto& e : eyes)
        forPatch(e.color, [&](uint32_t x, uint32_t y) {
            glm::vec4 t = e.color.fetch(x, y);
            t[c] = v;
            e.color.store(x, y, t);
        });
}
void setDepth(Eyes& eyes, float v) {
    for (auto& e : eyes) forPatch(*e.depth, [&](uint32_t x, uint32_t y) { e.depth->store(x, y, glm::vec4(v)); });
}
void setMotion(Eyes& eyes, glm::vec4 v) {
    for (auto& e : eyes) forPatch(*e.motion, [&](uint32_t x, uint32_t y) { e.motion->store(x, y, v); });
}

// The view centre and fallback fovea radius the compositor must use for an eye whose gaze is unusable.
void expectFallback(Compositor& comp, int eye, bool fallback) {
    EXPECT_EQ(comp.stats().gazeFallback[eye], fallback) << "eye " << eye;
    const gpu::EyeParams& ep = comp.lastParams().eye[eye];
    if (fallback) {
        const glm::vec4 t = ep.fov_tan;
        const glm::vec3 centre = glm::normalize(glm::vec3((t.x + t.y) * 0.5f, (t.z + t.w) * 0.5f, -1.0f));
        EXPECT_EQ(glm::vec3(ep.gaze), centre) << "eye " << eye << ": fallback gaze is not the view centre";
        EXPECT_EQ(ep.gaze.w, comp.config().fallbackFoveaDeg * 0.5f) << "eye " << eye;
    } else {
        EXPECT_EQ(ep.gaze.w, comp.config().foveaDeg * 0.5f) << "eye " << eye;
    }
}

// ---- Substitute ---------------------------------------------------------------------------------

struct SubstituteRow {
    std::string name;
    bool rg16fMotion = false;               ///< on the lane with RG16F motion and D32F depth
    std::function<void(Eyes&)> bad;         ///< what the main compositor gets
    std::function<void(Eyes&)> substitute;  ///< what the documentation says it is taken as (twin)
    std::function<void(Compositor&)> check = nullptr;
};
void PrintTo(const SubstituteRow& r, std::ostream* os) { *os << r.name; }

std::function<void(Eyes&)> gazeOf(int eye, layers::EyeGaze g) {
    return [eye, g](Eyes& e) {
        for (int i = 0; i < 2; ++i)
            if (eye < 0 || eye == i) e[i].gaze = g;
    };
}
std::function<void(Eyes&)> scaleGaze(float s) {
    return [s](Eyes& e) {
        for (auto& x : e) x.gaze.dir *= s;
    };
}
std::function<void(Compositor&)> fallbackOn(bool left, bool right) {
    return [left, right](Compositor& c) {
        expectFallback(c, 0, left);
        expectFallback(c, 1, right);
    };
}

std::vector<SubstituteRow> substituteRows() {
    const layers::EyeGaze invalid{};
    std::vector<SubstituteRow> r;
    // Gaze: unusable directions act as invalid gaze (view centre, fallback fovea).
    r.push_back(
        {"gaze_left_nan", false, gazeOf(0, {{kNaN, 0, -1}, true, 1}), gazeOf(0, invalid), fallbackOn(true, false)});
    r.push_back({"gaze_right_pos_inf", false, gazeOf(1, {{kInf, 0, -1}, true, 1}), gazeOf(1, invalid),
                 fallbackOn(false, true)});
    r.push_back({"gaze_left_neg_inf", false, gazeOf(0, {{0, -kInf, -1}, true, 1}), gazeOf(0, invalid),
                 fallbackOn(true, false)});
    r.push_back({"gaze_both_zero_length", false, gazeOf(-1, {{0, 0, 0}, true, 1}), gazeOf(-1, invalid),
                 fallbackOn(true, true)});
    r.push_back({"gaze_right_length_overflows", false, gazeOf(1, {{1e30f, 1e30f, -1e30f}, true, 1}), gazeOf(1, invalid),
                 fallbackOn(false, true)});
    r.push_back({"gaze_left_length_below_1e-6", false, gazeOf(0, {{3e-7f, 0, -3e-7f}, true, 1}), gazeOf(0, invalid),
                 fallbackOn(true, false)});
    r.push_back({"gaze_invalid_with_nan_direction", false, gazeOf(-1, {{kNaN, kNaN, kNaN}, false, kNaN}),
                 gazeOf(-1, invalid), fallbackOn(true, true)});
    r.push_back({"gaze_invalid_with_good_direction", false, gazeOf(1, {gazeDir(1, 1), false, 1}), gazeOf(1, invalid),
                 fallbackOn(false, true)});
    // Gaze: a direction of any finite length is normalised (scaled by powers of two: exact).
    r.push_back({"gaze_length_4", false, scaleGaze(4.0f), [](Eyes&) {}, fallbackOn(false, false)});
    r.push_back({"gaze_length_1_over_1024", false, scaleGaze(1.0f / 1024.0f), [](Eyes&) {}, fallbackOn(false, false)});
    // Gaze confidence is not used by the compositor.
    for (auto [kind, v] : {std::pair{"nan", kNaN}, std::pair{"negative", -5.0f}, std::pair{"above_one", 7.0f},
                           std::pair{"pos_inf", kInf}})
        r.push_back({std::string("gaze_confidence_") + kind, false,
                     [v = v](Eyes& e) { e[0].gaze.confidence = e[1].gaze.confidence = v; }, [](Eyes&) {},
                     fallbackOn(false, false)});
    // Motion: non-finite x/y is zero motion, non-finite dz is 0.
    r.push_back({"motion_xy_nan", false,
                 [](Eyes& e) {
                     setMotion(e, {kNaN, 0, 0, 0});
                 },
                 [](Eyes& e) {
                     setMotion(e, {0, 0, 0, 0});
                 }});
    r.push_back({"motion_xy_pos_inf", false,
                 [](Eyes& e) {
                     setMotion(e, {0, kInf, 0, 0});
                 },
                 [](Eyes& e) {
                     setMotion(e, {0, 0, 0, 0});
                 }});
    r.push_back({"motion_xy_neg_inf", false,
                 [](Eyes& e) {
                     setMotion(e, {-kInf, -kInf, 0, 0});
                 },
                 [](Eyes& e) {
                     setMotion(e, {0, 0, 0, 0});
                 }});
    r.push_back({"motion_x_nan_y_finite", false,
                 [](Eyes& e) {
                     setMotion(e, {kNaN, 3, 0, 0});
                 },
                 [](Eyes& e) {
                     setMotion(e, {0, 0, 0, 0});
                 }});
    r.push_back({"motion_dz_nan", false,
                 [](Eyes& e) {
                     setMotion(e, {0, 0, kNaN, 0});
                 },
                 [](Eyes& e) {
                     setMotion(e, {0, 0, 0, 0});
                 }});
    r.push_back({"motion_dz_neg_inf", false,
                 [](Eyes& e) {
                     setMotion(e, {0, 0, -kInf, 0});
                 },
                 [](Eyes& e) {
                     setMotion(e, {0, 0, 0, 0});
                 }});
    r.push_back({"motion_alpha_nan", false,
                 [](Eyes& e) {
                     setMotion(e, {0, 0, 0, kNaN});
                 },
                 [](Eyes& e) {
                     setMotion(e, {0, 0, 0, 0});
                 }});
    r.push_back({"motion_rg16f_nan", true,
                 [](Eyes& e) {
                     setMotion(e, {kNaN, kNaN, 0, 0});
                 },
                 [](Eyes& e) {
                     setMotion(e, {0, 0, 0, 0});
                 }});
    r.push_back({"motion_rg16f_pos_inf", true,
                 [](Eyes& e) {
                     setMotion(e, {kInf, 0, 0, 0});
                 },
                 [](Eyes& e) {
                     setMotion(e, {0, 0, 0, 0});
                 }});
    // Colour: negative channels are 0; alpha is not used.
    r.push_back({"color_negative", false, [](Eyes& e) { setColorChannel(e, 1, -3.0f); },
                 [](Eyes& e) { setColorChannel(e, 1, 0.0f); }});
    r.push_back({"color_negative_max", false,
                 [](Eyes& e) {
                     setColor(e, {-65504.0f, -65504.0f, -65504.0f, 1});
                 },
                 [](Eyes& e) {
                     setColor(e, {0, 0, 0, 1});
                 }});
    r.push_back({"color_alpha_nan", false, [](Eyes& e) { setColorChannel(e, 3, kNaN); },
                 [](Eyes& e) { setColorChannel(e, 3, 1.0f); }});
    r.push_back({"color_alpha_neg_inf", false, [](Eyes& e) { setColorChannel(e, 3, -kInf); },
                 [](Eyes& e) { setColorChannel(e, 3, 1.0f); }});
    // Depth: every value outside [0, 1] is "unknown", whatever it is.
    r.push_back(
        {"depth_nan_as_out_of_range", false, [](Eyes& e) { setDepth(e, kNaN); }, [](Eyes& e) { setDepth(e, 2.0f); }});
    r.push_back({"depth_pos_inf_as_out_of_range", false, [](Eyes& e) { setDepth(e, kInf); },
                 [](Eyes& e) { setDepth(e, 2.0f); }});
    r.push_back({"depth_neg_inf_as_out_of_range", false, [](Eyes& e) { setDepth(e, -kInf); },
                 [](Eyes& e) { setDepth(e, -1.0f); }});
    r.push_back(
        {"depth_huge_as_out_of_range", false, [](Eyes& e) { setDepth(e, 3e38f); }, [](Eyes& e) { setDepth(e, 2.0f); }});
    return r;
}

LaneFormats rg16fLane() { return LaneFormats{Format::RGBA16F, Format::D32F, Format::RG16F}; }

TwinChain& substituteChain(bool rg16f) {
    const CompositorConfig cfg{.foveaDeg = 10.0f, .seed = 9};
    static TwinChain a(cfg, LaneFormats{});
    static TwinChain b(cfg, rg16fLane());
    return rg16f ? b : a;
}

class Substitute : public GpuTest, public ::testing::WithParamInterface<SubstituteRow> {};

TEST_P(Substitute, Row) {
    const SubstituteRow& row = GetParam();
    TwinChain& c = substituteChain(row.rg16fMotion);
    const int warmUp = c.next() == 1 ? 3 : 1;  // some history first
    for (int i = 0; i < warmUp; ++i) ASSERT_NO_FATAL_FAILURE(c.stepBoth("before"));
    Eyes bad = goodFrame(c.next(), c.main.formats), substitute = bad;
    row.bad(bad);
    row.substitute(substitute);
    ASSERT_NO_FATAL_FAILURE(c.stepPair(row.name, bad, substitute));
    if (row.check) row.check(*c.main.comp);
    expectSane(*c.main.comp, row.name);
    ASSERT_NO_FATAL_FAILURE(c.stepBoth("the good frame after"));
}

INSTANTIATE_TEST_SUITE_P(BadValue, Substitute, ::testing::ValuesIn(substituteRows()),
                         [](const ::testing::TestParamInfo<SubstituteRow>& i) {
                             std::string n = i.param.name;
                             for (char& ch : n)
                                 if (!std::isalnum(static_cast<unsigned char>(ch))) ch = '_';
                             return n;
                         });

// ---- Sanitize -----------------------------------------------------------------------------------

struct Ctx {
    Compositor& comp;
    const Reservoirs& prev;  // before the bad frame
    const Reservoirs& now;   // after it
};

struct SanitizeRow {
    std::string name;
    std::function<void(Eyes&)> bad;
    std::function<void(F&)> edit = nullptr;  ///< changes the frame end (depth range, fov)
    std::function<void(const Ctx&)> check = nullptr;
    bool compareWithCpu = true;    ///< false where tangents near 90° make rounding, not logic, decide
    bool historyContinues = true;  ///< M continues at every pixel through the bad frame
};
void PrintTo(const SanitizeRow& r, std::ostream* os) { *os << r.name; }

// Pixels whose colour was not finite keep their history sample (weight 0 never wins) and show it.
void historyKeptInPatch(const Ctx& c) {
    for (uint32_t e = 0; e < 2; ++e) {
        auto out = c.comp.readOutput(e);
        ASSERT_TRUE(out.ok());
        uint64_t lost = 0;
        for (uint32_t y = 0; y < kH; ++y)
            for (uint32_t x = 0; x < kW; ++x) {
                if (!inPatch(x, y)) continue;
                const std::size_t i = std::size_t(y) * kW + x;
                const gpu::Reservoir r = gpu::wrs_unpack(c.now[e][i]), h = gpu::wrs_unpack(c.prev[e][i]);
                lost += c.now[e][i].x != c.prev[e][i].x || (c.now[e][i].y & 0xffffu) != (c.prev[e][i].y & 0xffffu);
                lost += r.w != h.w;
                const glm::u8vec4 o = encodeOutput(h.color);
                for (int ch = 0; ch < 3; ++ch) lost += std::abs(int(uint8_t(out->data[i * 4 + ch])) - int(o[ch])) > 1;
            }
        EXPECT_EQ(lost, 0u) << "eye " << e << ": an invalid colour replaced or changed the history sample";
    }
}
// Depth that gives no positive finite linear depth is stored as unknown (z = 0) in the patch, and
// everywhere else z stays positive and finite (at most the fp16 maximum).
void unknownZInPatch(const Ctx& c) {
    for (uint32_t e = 0; e < 2; ++e) {
        uint64_t wrong = 0;
        for (uint32_t y = 0; y < kH; ++y)
            for (uint32_t x = 0; x < kW; ++x) {
                const float z = gpu::wrs_unpack(c.now[e][std::size_t(y) * kW + x]).z;
                wrong += inPatch(x, y) ? z != 0.0f : !(z > 0.0f && z <= 65504.0f);
            }
        EXPECT_EQ(wrong, 0u) << "eye " << e;
    }
}
// History dropped (M = 1) exactly in the patch.
void noHistoryInPatch(const Ctx& c) {
    for (uint32_t e = 0; e < 2; ++e) {
        uint64_t wrong = 0;
        for (uint32_t y = 0; y < kH; ++y)
            for (uint32_t x = 0; x < kW; ++x) {
                const std::size_t i = std::size_t(y) * kW + x;
                const uint32_t m = gpu::wrs_unpack(c.now[e][i]).M, h = gpu::wrs_unpack(c.prev[e][i]).M;
                wrong += inPatch(x, y) ? m != 1u : m != std::min(h + 1u, WRS_M_MAX);
            }
        EXPECT_EQ(wrong, 0u) << "eye " << e;
    }
}
void allZ(const Ctx& c, float z) {
    for (uint32_t e = 0; e < 2; ++e) {
        uint64_t wrong = 0;
        for (const glm::uvec4& p : c.now[e]) wrong += gpu::wrs_unpack(p).z != z;
        EXPECT_EQ(wrong, 0u) << "eye " << e << ": z is not " << z << " everywhere";
    }
}
std::function<void(F&)> depthRange(float nearZ, float farZ, bool reversed) {
    return [=](F& f) {
        for (auto& v : f.layers[0].views) {
            v.depth->nearZ = nearZ;
            v.depth->farZ = farZ;
            v.depth->reversedZ = reversed;
        }
    };
}
std::function<void(F&)> allFov(layers::Fov fov) {
    return [fov](F& f) {
        for (auto& v : f.layers[0].views) v.fov = fov;
    };
}

std::vector<SanitizeRow> sanitizeRows() {
    const float below90 = std::nextafter(1.5707963f, 0.0f);  // the widest angle the validator takes
    std::vector<SanitizeRow> r;
    auto color = [](glm::vec4 v) { return [v](Eyes& e) { setColor(e, v); }; };
    r.push_back({"color_nan", color({kNaN, kNaN, kNaN, 1}), nullptr, historyKeptInPatch});
    r.push_back({"color_red_pos_inf", color({kInf, 0.5f, 0.5f, 1}), nullptr, historyKeptInPatch});
    r.push_back({"color_green_neg_inf", color({0.5f, -kInf, 0.5f, 1}), nullptr, historyKeptInPatch});
    r.push_back({"color_signalling_nan",
                 [](Eyes& e) {
                     for (auto& x : e)
                         forPatch(x.color, [&](uint32_t px, uint32_t py) {
                             const uint16_t snan = 0x7d01;
                             std::memcpy(x.color.data.data() + (std::size_t(py) * kW + px) * 8 + 4, &snan, 2);
                         });
                 },
                 nullptr, historyKeptInPatch});
    // The fp16 maximum is a valid colour: stored as is (the reference comparison checks every pixel).
    r.push_back({"color_fp16_max", color({65504.0f, 65504.0f, 65504.0f, 1})});
    r.push_back({"depth_nan", [](Eyes& e) { setDepth(e, kNaN); }, nullptr, unknownZInPatch});
    r.push_back({"depth_pos_inf", [](Eyes& e) { setDepth(e, kInf); }, nullptr, unknownZInPatch});
    r.push_back({"depth_neg_inf", [](Eyes& e) { setDepth(e, -kInf); }, nullptr, unknownZInPatch});
    r.push_back({"depth_negative", [](Eyes& e) { setDepth(e, -0.5f); }, nullptr, unknownZInPatch});
    r.push_back({"depth_negative_tiny", [](Eyes& e) { setDepth(e, -1e-30f); }, nullptr, unknownZInPatch});
    r.push_back(
        {"depth_above_one", [](Eyes& e) { setDepth(e, std::nextafter(1.0f, 2.0f)); }, nullptr, unknownZInPatch});
    r.push_back({"depth_huge", [](Eyes& e) { setDepth(e, 1e30f); }, nullptr, unknownZInPatch});
    r.push_back({"depth_at_infinite_far_plane", [](Eyes& e) { setDepth(e, 1.0f); }, depthRange(0.1f, kInf, false),
                 unknownZInPatch, true, false});
    r.push_back({"depth_reversed_zero_infinite_far", [](Eyes& e) { setDepth(e, 0.0f); }, depthRange(0.1f, kInf, true),
                 unknownZInPatch, true, false});
    // Linear depth of about 1e-30 is below the smallest fp16 value: stored as 0, i.e. unknown.
    r.push_back({"depth_range_tiny_near_huge_far", [](Eyes&) {}, depthRange(1e-30f, 3e38f, false),
                 [](const Ctx& c) { allZ(c, 0.0f); }, true, false});
    r.push_back({"depth_range_huge_near_infinite_far", [](Eyes&) {}, depthRange(1e30f, kInf, false),
                 [](const Ctx& c) { allZ(c, 65504.0f); }, true, false});
    r.push_back({"motion_huge_off_screen",
                 [](Eyes& e) {
                     setMotion(e, {65504.0f, 0, 0, 0});
                 },
                 nullptr, noHistoryInPatch, true, false});
    r.push_back({"motion_negative_huge_off_screen",
                 [](Eyes& e) {
                     setMotion(e, {0, -65504.0f, 0, 0});
                 },
                 nullptr, noHistoryInPatch, true, false});
    // Each patch pixel's previous position lands just left of the image (fp16 keeps the 0.1 margin).
    r.push_back({"motion_just_off_screen",
                 [](Eyes& e) {
                     for (auto& x : e)
                         forPatch(*x.motion, [&](uint32_t px, uint32_t py) {
                             x.motion->store(px, py, glm::vec4(-float(px) - 0.6f, 0, 0, 0));
                         });
                 },
                 nullptr, noHistoryInPatch, true, false});
    r.push_back({"gaze_behind_the_viewer",
                 [](Eyes& e) {
                     e[0].gaze = e[1].gaze = {{0, 0, 1}, true, 1};
                 },
                 nullptr,
                 [](const Ctx& c) {
                     expectFallback(c.comp, 0, false);
                     expectFallback(c.comp, 1, false);
                     EXPECT_EQ(glm::vec3(c.comp.lastParams().eye[0].gaze), glm::vec3(0, 0, 1));
                 }});
    r.push_back({"gaze_sideways_90_degrees",
                 [](Eyes& e) {
                     e[0].gaze = e[1].gaze = {{1, 0, 0}, true, 1};
                 },
                 nullptr, [](const Ctx& c) { expectFallback(c.comp, 0, false); }});
    r.push_back({"fov_just_below_90_degrees", [](Eyes&) {}, allFov({-below90, below90, below90, -below90}), nullptr,
                 false, false});
    r.push_back({"fov_tiny", [](Eyes&) {}, allFov({-1e-4f, 1e-4f, 1e-4f, -1e-4f}), nullptr, true, false});
    r.push_back({"fov_one_sided", [](Eyes&) {}, allFov({-60.0f * kDeg, -5.0f * kDeg, 10.0f * kDeg, 2.0f * kDeg}),
                 [](const Ctx& c) { expectFallback(c.comp, 0, false); }, true, false});
    return r;
}

struct SanitizeLane {
    SanitizeLane() : lane(context(), config(), LaneFormats{}), ref(config()) {}
    static CompositorConfig config() { return CompositorConfig{.method = Method::WrsPaper, .foveaDeg = 10.0f, .seed = 13}; }
    Lane lane;
    Reference ref;
    uint64_t next = 1;
    StepTally tally;

    // One frame on the GPU and the reference from the GPU's own history; returns the history.
    Reservoirs step(const Eyes& eyes, const std::function<void(F&)>& edit, bool compare, const std::string& what) {
        Reservoirs prev;
        if (lane.comp->width() != 0) {
            prev = readReservoirs(*lane.comp);
            for (uint32_t e = 0; e < 2; ++e) {
                ref.setHistory(e, prev[e], *lane.comp->readTileHeld(e));
                ref.setSteadyFloor(e, *lane.comp->readSteadyFloor(e));
            }
        }
        lane.app->write(eyes);
        F f = lane.app->frameEnd(next, eyes);
        if (edit) edit(f);
        const Status s = lane.comp->endFrame(f);
        EXPECT_TRUE(s.ok()) << what << ": " << s.message();
        if (!s.ok()) return prev;
        ++next;
        if (prev[0].empty()) {
            ref.resetHistory();
            for (auto& p : prev) p.assign(std::size_t(kW) * kH, glm::uvec4(0u));
        }
        ref.step(lane.comp->lastParams(), referenceInputs(eyes));
        if (compare) compareWithReference(*lane.comp, ref, prev, tally, what);
        return prev;
    }
};

SanitizeLane& sanitizeLane() {
    static SanitizeLane l;
    return l;
}

void expectHistoryContinues(const Reservoirs& prev, const Reservoirs& now, const std::string& what) {
    for (uint32_t e = 0; e < 2; ++e) {
        uint64_t wrong = 0;
        for (std::size_t i = 0; i < now[e].size(); ++i)
            wrong += gpu::wrs_unpack(now[e][i]).M != std::min(gpu::wrs_unpack(prev[e][i]).M + 1u, WRS_M_MAX);
        EXPECT_EQ(wrong, 0u) << what << ": eye " << e << ": history lost at " << wrong << " pixels";
    }
}

class Sanitize : public GpuTest, public ::testing::WithParamInterface<SanitizeRow> {};

TEST_P(Sanitize, Row) {
    const SanitizeRow& row = GetParam();
    SanitizeLane& l = sanitizeLane();
    const int warmUp = l.next == 1 ? 3 : 1;  // some history first
    for (int i = 0; i < warmUp; ++i) {
        l.step(goodFrame(l.next, l.lane.formats), nullptr, true, "before");
        ASSERT_FALSE(HasFailure());
    }
    Eyes eyes = goodFrame(l.next, l.lane.formats);
    row.bad(eyes);
    const Reservoirs prev = l.step(eyes, row.edit, row.compareWithCpu, row.name);
    ASSERT_FALSE(HasFailure());
    const Reservoirs now = readReservoirs(*l.lane.comp);
    expectSane(*l.lane.comp, row.name);
    if (row.historyContinues) expectHistoryContinues(prev, now, row.name);
    if (row.check) row.check(Ctx{*l.lane.comp, prev, now});
    // The next good frame: still sane and in agreement with the reference; history continues
    // where the bad frame kept it.
    const Reservoirs before = l.step(goodFrame(l.next, l.lane.formats), nullptr, true, "the good frame after");
    expectSane(*l.lane.comp, "the good frame after " + row.name);
    if (row.historyContinues) expectHistoryContinues(before, readReservoirs(*l.lane.comp), "the good frame after");
    EXPECT_EQ(l.tally.mismatches, l.tally.nearThreshold);
    EXPECT_LE(l.tally.maxOutputDiff, 1);
}

INSTANTIATE_TEST_SUITE_P(BadValue, Sanitize, ::testing::ValuesIn(sanitizeRows()),
                         [](const ::testing::TestParamInfo<SanitizeRow>& i) { return i.param.name; });

// ---- Accepted -----------------------------------------------------------------------------------

TwinChain& acceptedChain() {
    static TwinChain c(CompositorConfig{.method = Method::WrsPaper, .foveaDeg = 7.5f, .seed = 17}, LaneFormats{});
    return c;
}

class BadValueAccepted : public GpuTest {};

TEST_F(BadValueAccepted, FrameIndexMayJump) {
    TwinChain& c = acceptedChain();
    ASSERT_NO_FATAL_FAILURE(c.stepBoth("first"));
    c.jumpTo(c.next() + 1'000'000'000'000ull);  // only the order is checked; the shader hash takes the low bits
    ASSERT_NO_FATAL_FAILURE(c.stepBoth("after a jump of 1e12"));
    expectSane(*c.main.comp, "frame index jump");
    EXPECT_EQ(c.main.comp->stats().frameIndex, c.next() - 1);
}

TEST_F(BadValueAccepted, FrameTimeMayRepeat) {
    TwinChain& c = acceptedChain();
    ASSERT_NO_FATAL_FAILURE(c.stepBoth("first"));
    const double t = double(c.next() - 1) / 90.0;  // the time of the frame just accepted
    ASSERT_NO_FATAL_FAILURE(c.stepEdited("same time as the previous frame", [t](Lane&, F& f) { f.time_s = t; }));
    expectSane(*c.main.comp, "repeated time");
}

TEST_F(BadValueAccepted, FrameTimeNegativeHugeAndTheLastFrameIndex) {
    // Only the order is checked: a negative first time, a huge time, and the largest index are taken,
    // after which nothing can follow (the index cannot grow, the time cannot go back).
    TwinChain c(CompositorConfig{.method = Method::WrsPaper, .seed = 19}, LaneFormats{});
    ASSERT_NO_FATAL_FAILURE(c.stepEdited("negative first time", [](Lane&, F& f) { f.time_s = -1e300; }));
    ASSERT_NO_FATAL_FAILURE(c.stepEdited("huge time", [](Lane&, F& f) { f.time_s = 1e300; }));
    c.jumpTo(std::numeric_limits<uint64_t>::max());
    ASSERT_NO_FATAL_FAILURE(c.stepEdited("the largest frame index", [](Lane&, F& f) { f.time_s = 1e300; }));
    expectSane(*c.main.comp, "after the largest frame index");
    const auto eyes = goodFrame(7, c.main.formats);
    c.main.app->write(eyes);
    F f = c.main.app->frameEnd(std::numeric_limits<uint64_t>::max(), eyes);
    f.time_s = 1e300;
    const Status s = c.main.comp->endFrame(f);
    ASSERT_FALSE(s.ok());
    EXPECT_EQ(s.error().code, int(layers::SubmitError::FrameOutOfOrder));
    EXPECT_TRUE(contains(s.message(), "does not follow 18446744073709551615")) << s.message();
}

TEST_F(BadValueAccepted, ViewsMayUseDifferentColourFormats) {
    // InconsistentViews is about depth or motion given for one view only; the two views' colour
    // (and depth, motion) formats may differ: each view is read in its own format.
    TwinChain& c = acceptedChain();
    ASSERT_NO_FATAL_FAILURE(c.stepBoth("first"));
    static std::map<const Lane*, std::unique_ptr<layers::Swapchain>> srgb;
    ASSERT_NO_FATAL_FAILURE(c.stepEdited("right colour in rgba8_srgb, left in rgba16f", [&](Lane& lane, F& f) {
        auto& sc = srgb[&lane];
        if (!sc) {
            auto r = lane.comp->createSwapchain(stereoInfo(layers::Usage::Color, Format::RGBA8_SRGB));
            ASSERT_TRUE(r.ok());
            sc = std::move(*r);
        }
        RandomScene rs(5);
        const HostImage img = rs.color(Format::RGBA8_SRGB, kW, kH);
        auto idx = sc->acquire();
        ASSERT_TRUE(idx.ok());
        ASSERT_TRUE(sc->wait().ok());
        ASSERT_TRUE(sc->write(*idx, 1, img.bytes()).ok());
        ASSERT_TRUE(sc->release().ok());
        f.layers[0].views[1].color.swapchain = sc.get();
    }));
    expectSane(*c.main.comp, "mixed colour formats");
}

}  // namespace
}  // namespace wrsfov::test
