// docs/bad-input.md, "Gaze sources": a source that dies mid-run makes the compositor fall back to
// fixed foveation (view centre, fallback fovea) once the dropout hold has run out, and foveation
// follows gaze again as soon as the source returns. Gaze goes from the source to the frame end
// through gaze::frame_gaze, the one shared conversion.
#include <cmath>
#include <cstring>
#include <deque>
#include <fstream>
#include <string>
#include <vector>

#include "gaze/angles.h"
#include "gaze/frame_gaze.h"
#include "gaze/hid_device.h"
#include "robust_rig.h"

namespace wrsfov::test {
namespace {

namespace g = gaze;
namespace hid = gaze::hid;
using layers::Format;
using Bytes = std::vector<uint8_t>;

const LaneFormats kColourOnly{Format::RGBA16F, std::nullopt, std::nullopt};

double angleDeg(glm::vec3 a, glm::vec3 b) {
    const glm::dvec3 x = glm::normalize(glm::dvec3(a)), y = glm::normalize(glm::dvec3(b));
    return std::acos(std::clamp(glm::dot(x, y), -1.0, 1.0)) * 180.0 / 3.14159265358979323846;
}

// Fallback flags as the compositor reports them, and the gaze it used.
void expectGaze(Compositor& comp, const std::optional<glm::vec3>& expected, const std::string& what) {
    for (int e = 0; e < 2; ++e) {
        const gpu::EyeParams& ep = comp.lastParams().eye[e];
        if (!expected) {
            EXPECT_TRUE(comp.stats().gazeFallback[e]) << what << ": eye " << e << " should fall back";
            const glm::vec4 t = ep.fov_tan;
            const glm::vec3 centre = glm::normalize(glm::vec3((t.x + t.y) * 0.5f, (t.z + t.w) * 0.5f, -1.0f));
            EXPECT_EQ(glm::vec3(ep.gaze), centre) << what;
            EXPECT_EQ(ep.gaze.w, comp.config().fallbackFoveaDeg * 0.5f) << what;
        } else {
            EXPECT_FALSE(comp.stats().gazeFallback[e]) << what << ": eye " << e << " should follow gaze";
            EXPECT_LT(angleDeg(glm::vec3(ep.gaze), *expected), 1e-3) << what << ": eye " << e;
            EXPECT_EQ(ep.gaze.w, comp.config().foveaDeg * 0.5f) << what;
        }
    }
}

class GazeLoss : public GpuTest {};

TEST_F(GazeLoss, ReplayWithAGapFallsBackAfterTheHoldAndFollowsGazeWhenItReturns) {
    // A 1 kHz recording: gaze A for 0.3 s, then nothing for 0.3 s (the tracker stopped), then gaze B.
    const glm::vec3 A = g::direction_from_angle({8, 3}), B = g::direction_from_angle({-12, -6});
    std::vector<g::GazeSample> samples;
    for (int i = 0; i <= 1000; ++i) {
        if (i >= 300 && i < 600) continue;
        g::GazeSample s;
        s.t_s = i / 1000.0;
        for (auto& e : s.eye) e = {i < 300 ? A : B, true, 1.0f};
        samples.push_back(s);
    }
    g::ReplaySource src(samples);
    const g::DropoutPolicy policy;  // 100 ms hold
    Lane lane(context(), CompositorConfig{.foveaDeg = 5.0f, .fallbackFoveaDeg = 20.0f}, kColourOnly);
    int fellBack = 0;
    for (uint64_t f = 1; f <= 90; ++f) {
        const double t = double(f) / 90.0;  // StereoApp's frame time
        std::array<EyeFrame, 2> eyes = goodFrame(f, kColourOnly);
        const auto gz = g::frame_gaze(&src, t, policy);
        for (int e = 0; e < 2; ++e) eyes[e].gaze = gz[e];
        ASSERT_TRUE(lane.app->submit(f, eyes).ok());
        // The documented policy: held up to 100 ms after the last sample at 0.299 s, fallback until the
        // source returns at 0.6 s, then B.
        std::optional<glm::vec3> expected;
        if (t <= 0.299 + policy.hold_s)
            expected = A;
        else if (t >= 0.6)
            expected = B;
        expectGaze(*lane.comp, expected, "frame at " + std::to_string(t) + " s");
        fellBack += !expected;
        if (f % 15 == 0) expectSane(*lane.comp, "gaze replay");
    }
    EXPECT_EQ(fellBack, 18);  // frames 36..53
}

TEST_F(GazeLoss, ReplayEndsThenFixedFoveation) {
    // A recording that simply stops (a dead source): the last gaze is held 100 ms, then fallback for good.
    std::vector<g::GazeSample> samples;
    for (int i = 0; i < 200; ++i) samples.push_back(g::sample_from_angle(i / 1000.0, {5, 2}, true));
    g::ReplaySource src(samples);
    Lane lane(context(), CompositorConfig{}, kColourOnly);
    for (uint64_t f = 1; f <= 40; ++f) {
        const double t = double(f) / 90.0;
        std::array<EyeFrame, 2> eyes = goodFrame(f, kColourOnly);
        const auto gz = g::frame_gaze(&src, t);
        for (int e = 0; e < 2; ++e) eyes[e].gaze = gz[e];
        ASSERT_TRUE(lane.app->submit(f, eyes).ok());
        std::optional<glm::vec3> expected;
        if (t <= 0.199 + 0.1) expected = g::direction_from_angle({5, 2});
        expectGaze(*lane.comp, expected, "frame at " + std::to_string(t) + " s");
    }
    expectSane(*lane.comp, "after the recording ended");
}

TEST_F(GazeLoss, NoSourceOrAStaleSampleIsTheFallback) {
    Lane lane(context(), CompositorConfig{}, kColourOnly);
    const glm::vec3 dir = g::direction_from_angle({-4, 6});
    g::GazeSample held;
    held.t_s = 0.5;
    held.eye[0] = held.eye[1] = {dir, true, 1.0f};
    struct Step {
        const char* what;
        std::array<layers::EyeGaze, 2> gaze;
        bool fallback;
    };
    const Step steps[] = {
        {"fresh sample", g::to_frame_gaze(held, 0.5), false},
        {"sample 100 ms old", g::to_frame_gaze(held, 0.6), false},
        {"sample 150 ms old (source stopped answering)", g::to_frame_gaze(held, 0.65), true},
        {"no source at all", g::frame_gaze(nullptr, 0.7), true},
        {"source back", g::to_frame_gaze(held, 0.45), false},
    };
    uint64_t f = 1;
    for (const Step& s : steps) {
        std::array<EyeFrame, 2> eyes = goodFrame(f, kColourOnly);
        for (int e = 0; e < 2; ++e) eyes[e].gaze = s.gaze[e];
        ASSERT_TRUE(lane.app->submit(f++, eyes).ok());
        expectGaze(*lane.comp, s.fallback ? std::nullopt : std::optional<glm::vec3>(dir), s.what);
    }
    expectSane(*lane.comp, "stale gaze");
}

// ---- A HID eye tracker that is unplugged and plugged in again ------------------------------------

Bytes readHex(const std::string& path) {
    std::ifstream in(path);
    Bytes out;
    std::string tok;
    while (in >> tok) out.push_back(static_cast<uint8_t>(std::stoul(tok, nullptr, 16)));
    return out;
}

// Report 1 of tests/gaze/data/eyetracker_descriptor.hex: timestamp (µs), gaze point (µm), eyes (µm).
Bytes trackingReport(uint64_t ts_us, int32_t gx, int32_t gy) {
    Bytes r{1};
    auto le = [&](uint64_t v, int n) {
        for (int i = 0; i < n; ++i) r.push_back(static_cast<uint8_t>(v >> (8 * i)));
    };
    le(ts_us, 8);
    le(static_cast<uint32_t>(gx), 4);
    le(static_cast<uint32_t>(gy), 4);
    for (int32_t v : {270000, 170000, 600000, 330000, 170000, 600000}) le(static_cast<uint32_t>(v), 4);
    return r;
}

struct FakeTracker {
    bool plugged = true;
    std::deque<Bytes> pending;
};

class FakeConnection final : public hid::Connection {
public:
    explicit FakeConnection(FakeTracker& t) : t_(t) {}
    g::Result<Bytes> descriptor() override {
        return readHex(WRSFOV_GAZE_TEST_DATA "/eyetracker_descriptor.hex");
    }
    int read(std::span<uint8_t> buf) override {
        if (!t_.plugged) return -1;  // hidapi's answer for a device that went away
        if (t_.pending.empty()) return 0;
        const Bytes r = t_.pending.front();
        t_.pending.pop_front();
        std::memcpy(buf.data(), r.data(), r.size());
        return static_cast<int>(r.size());
    }
    g::Result<Bytes> get_feature(uint8_t, size_t) override {
        return readHex(WRSFOV_GAZE_TEST_DATA "/eyetracker_feature.hex");
    }

private:
    FakeTracker& t_;
};

class FakeConnector final : public hid::Connector {
public:
    explicit FakeConnector(FakeTracker& t) : t_(t) {}
    g::Result<std::unique_ptr<hid::Connection>> open() override {
        if (!t_.plugged) return g::fail("no such device");
        return std::unique_ptr<hid::Connection>(std::make_unique<FakeConnection>(t_));
    }
    std::string name() const override { return "fake tracker"; }

private:
    FakeTracker& t_;
};

TEST_F(GazeLoss, HidTrackerUnpluggedFallsBackAndRecoversWhenPluggedIn) {
    FakeTracker tracker;
    double now = 1000.0;
    hid::HidTrackerSource src(std::make_unique<FakeConnector>(tracker), {}, [&] { return now; });
    Lane lane(context(), CompositorConfig{}, kColourOnly);
    // The gaze point: before the unplug 10 cm right of the screen centre, after it 10 cm left.
    const int32_t before = 400000, after = 200000;
    uint64_t ts = 7'000'000;
    const double unplugAt = 1000.0 + 0.5, replugAt = 1000.0 + 1.5;
    double lastReport = 0, reconnectedAt = -1;
    int heldFrames = 0, fallbackFrames = 0, followedAfter = 0;
    std::optional<glm::vec3> dirBefore, dirAfter;
    for (uint64_t f = 1; f <= 240; ++f) {
        const double frameStart = now;
        now = 1000.0 + double(f) / 90.0;
        tracker.plugged = now < unplugAt || now >= replugAt;
        // Reports at 250 Hz while plugged in.
        if (tracker.plugged)
            for (double t = std::ceil(frameStart * 250) / 250; t < now; t += 1.0 / 250) {
                ts += 4000;
                tracker.pending.push_back(trackingReport(ts, now < unplugAt ? before : after, 170000));
                lastReport = t;
            }
        const auto gz = g::frame_gaze(&src, now);
        if (src.connected() && now >= replugAt && reconnectedAt < 0) reconnectedAt = now;
        std::array<EyeFrame, 2> eyes = goodFrame(f, kColourOnly);
        for (int e = 0; e < 2; ++e) eyes[e].gaze = gz[e];
        ASSERT_TRUE(lane.app->submit(f, eyes).ok());
        const bool fallback = lane.comp->stats().gazeFallback[0];
        EXPECT_EQ(fallback, lane.comp->stats().gazeFallback[1]);
        if (now < unplugAt) {
            EXPECT_FALSE(fallback) << "plugged in at " << now - 1000;
            if (!fallback) dirBefore = glm::vec3(lane.comp->lastParams().eye[0].gaze);
        } else if (now < replugAt) {
            // Held for up to 100 ms after the last sample, then fixed foveation.
            const double age = now - lastReport;
            if (age < 0.09) {
                EXPECT_FALSE(fallback) << "just unplugged, " << age << " s after the last report";
                heldFrames += !fallback;
            } else if (age > 0.11) {
                EXPECT_TRUE(fallback) << "unplugged " << age << " s after the last report";
                fallbackFrames += fallback;
            }
        } else if (reconnectedAt >= 0 && now > reconnectedAt + 0.02) {
            EXPECT_FALSE(fallback) << "reconnected at " << reconnectedAt - 1000 << ", now " << now - 1000;
            if (!fallback) {
                dirAfter = glm::vec3(lane.comp->lastParams().eye[0].gaze);
                ++followedAfter;
            }
        }
    }
    EXPECT_GT(heldFrames, 0);
    EXPECT_GT(fallbackFrames, 60);
    ASSERT_GE(reconnectedAt, replugAt) << "the source never reconnected: " << src.last_error();
    EXPECT_LT(reconnectedAt, replugAt + 4.1) << "reconnection is bounded by the 4 s back-off";
    EXPECT_GT(followedAfter, 10);
    ASSERT_TRUE(dirBefore && dirAfter);
    // Foveation follows the new gaze: the left eye now looks left of where it looked before.
    EXPECT_LT(dirAfter->x, dirBefore->x - 0.1f);
    expectSane(*lane.comp, "after the tracker came back");
}

}  // namespace
}  // namespace wrsfov::test
