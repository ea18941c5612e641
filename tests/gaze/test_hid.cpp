#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <deque>
#include <fstream>
#include <opencv2/core.hpp>
#include <sstream>

#include "gaze/angles.h"
#include "gaze/hid_descriptor.h"
#include "gaze/hid_device.h"
#include "gaze/hid_eyetracker.h"

namespace wg = wrsfov::gaze;
namespace hid = wrsfov::gaze::hid;
using Bytes = std::vector<uint8_t>;

namespace {

const std::string kData = WRSFOV_GAZE_TEST_DATA;

// Descriptor building blocks: short items with the smallest data size that holds the value.
struct Desc {
    Bytes b;
    Desc& item(uint8_t tag_type, int64_t v, int size = -1) {
        if (size < 0) size = (v >= -128 && v <= 127) ? 1 : (v >= -32768 && v <= 32767) ? 2 : 4;
        const uint8_t code = size == 0 ? 0 : size == 1 ? 1 : size == 2 ? 2 : 3;
        b.push_back(static_cast<uint8_t>(tag_type | code));
        for (int i = 0; i < size; ++i) b.push_back(static_cast<uint8_t>((static_cast<uint64_t>(v) >> (8 * i)) & 0xFF));
        return *this;
    }
    Desc& page(int v) { return item(0x04, v); }
    Desc& usage(int v) { return item(0x08, v, v > 0xFF ? 2 : 1); }
    Desc& lmin(int64_t v) { return item(0x14, v); }
    Desc& lmax(int64_t v) { return item(0x24, v); }
    Desc& pmin(int64_t v) { return item(0x34, v); }
    Desc& pmax(int64_t v) { return item(0x44, v); }
    Desc& exponent(int v, int size = 1) { return item(0x54, v, size); }
    Desc& unit(uint32_t v) { return item(0x64, v, v > 0xFF ? 2 : 1); }
    Desc& size(int v) { return item(0x74, v); }
    Desc& id(int v) { return item(0x84, v); }
    Desc& count(int v) { return item(0x94, v); }
    Desc& input(int flags = 0x02) { return item(0x80, flags); }
    Desc& feature(int flags = 0x02) { return item(0xB0, flags); }
    Desc& collection(int kind) { return item(0xA0, kind); }
    Desc& end() {
        b.push_back(0xC0);
        return *this;
    }
};

struct Report {
    Bytes b;
    Report& u8(uint8_t v) {
        b.push_back(v);
        return *this;
    }
    Report& le(uint64_t v, int bytes) {
        for (int i = 0; i < bytes; ++i) b.push_back(static_cast<uint8_t>(v >> (8 * i)));
        return *this;
    }
};

constexpr uint32_t kCm = 0x11, kInch = 0x13, kSeconds = 0x1001;

// The standard layout: ID 1 = timestamp (64-bit us), gaze point X/Y (32-bit, cm e-4 = um),
// left and right eye X/Y/Z; ID 3 = calibrated screen width/height feature.
Bytes standard_descriptor() {
    Desc d;
    d.page(0x12).usage(hid::eye::kEyeTracker).collection(1);
    d.id(1).usage(hid::eye::kTrackingData).collection(2);
    d.usage(hid::eye::kSensorTimestamp).lmin(0).item(0x24, 0, 1).size(64).count(1).unit(kSeconds).exponent(0xA).input();
    d.usage(hid::eye::kGazePoint).collection(0);
    d.usage(hid::eye::kPositionX).usage(hid::eye::kPositionY).item(0x14, INT32_MIN, 4).item(0x24, INT32_MAX, 4);
    d.size(32).count(2).unit(kCm).exponent(0xC).input().end();
    for (int e : {hid::eye::kLeftEyePosition, hid::eye::kRightEyePosition}) {
        d.usage(e).collection(0).usage(hid::eye::kPositionX).usage(hid::eye::kPositionY).usage(hid::eye::kPositionZ);
        d.count(3).input().end();
    }
    d.end();
    d.id(3).usage(hid::eye::kConfiguration).collection(2);
    d.usage(hid::eye::kCalibratedScreenWidth).usage(hid::eye::kCalibratedScreenHeight).lmin(0).item(0x24, INT32_MAX, 4);
    d.size(32).count(2).unit(kCm).exponent(0xC).feature().end();
    d.end();
    return d.b;
}

Bytes standard_report(uint64_t ts, int32_t gx, int32_t gy) {
    Report r;
    r.u8(1).le(ts, 8).le(static_cast<uint32_t>(gx), 4).le(static_cast<uint32_t>(gy), 4);
    for (int32_t v : {270000, 150000, 600000, 330000, 150000, 600000}) r.le(static_cast<uint32_t>(v), 4);
    return r.b;
}

Bytes read_hex(const std::string& path) {
    std::ifstream in(path);
    Bytes out;
    std::string tok;
    while (in >> tok) out.push_back(static_cast<uint8_t>(std::stoul(tok, nullptr, 16)));
    return out;
}

bool contains(const std::string& s, const std::string& what) { return s.find(what) != std::string::npos; }

}  // namespace

TEST(HidDescriptor, StandardEyeTrackerParses) {
    const Bytes bytes = standard_descriptor();
    EXPECT_EQ(bytes, read_hex(kData + "/eyetracker_descriptor.hex"));  // the CLI test's file is the same
    auto d = hid::parse_descriptor(bytes);
    ASSERT_TRUE(d.ok()) << d.error().message;
    EXPECT_TRUE(d->uses_report_ids);
    EXPECT_EQ(d->collections.size(), 6u);
    ASSERT_EQ(d->fields.size(), 5u);
    EXPECT_EQ(d->report_bytes(hid::ReportType::Input, 1), 41u);
    EXPECT_EQ(d->report_bytes(hid::ReportType::Feature, 3), 9u);
    EXPECT_EQ(d->fields[0].unit_exponent, -6);
    EXPECT_EQ(d->fields[1].unit_exponent, -4);
    EXPECT_EQ(d->fields[1].logical_min, INT32_MIN);
    EXPECT_EQ(d->fields[1].usage_at(1), hid::make_usage(0x12, hid::eye::kPositionY));
    EXPECT_EQ(d->fields[4].usage_at(0), hid::make_usage(0x12, hid::eye::kCalibratedScreenWidth));
    EXPECT_EQ(d->collection_path(d->fields[2]).front(), hid::make_usage(0x12, hid::eye::kLeftEyePosition));
}

TEST(HidDescriptor, StandardReportDecodesToMicrometresAndMicroseconds) {
    auto d = hid::parse_descriptor(standard_descriptor());
    ASSERT_TRUE(d.ok());
    auto layout = hid::find_eye_tracker(*d);
    ASSERT_TRUE(layout.ok()) << layout.error().message;
    EXPECT_EQ(layout->tracking_report_id, 1);
    const Bytes report = standard_report(123456789, 250000, -140000);
    auto t = hid::decode_tracking(*d, *layout, report);
    ASSERT_TRUE(t.ok()) << t.error().message;
    EXPECT_DOUBLE_EQ(*t->timestamp_us, 123456789);
    EXPECT_DOUBLE_EQ(t->gaze_um.x, 250000);
    EXPECT_DOUBLE_EQ(t->gaze_um.y, -140000);
    ASSERT_TRUE(t->eye_um[0] && t->eye_um[1]);
    EXPECT_DOUBLE_EQ(t->eye_um[1]->x, 330000);
    EXPECT_DOUBLE_EQ(t->eye_um[0]->z, 600000);
    auto s = hid::decode_screen(*d, *layout, read_hex(kData + "/eyetracker_feature.hex"));
    ASSERT_TRUE(s.ok()) << s.error().message;
    EXPECT_DOUBLE_EQ(s->width_um, 600000);
    EXPECT_DOUBLE_EQ(s->height_um, 340000);
    EXPECT_EQ(read_hex(kData + "/eyetracker_report.hex"), standard_report(123456789, 250000, 140000));
}

TEST(HidDescriptor, OtherOrderSizesAndExponents) {
    // No report IDs; right eye first in millimetres (cm, exponent -1) as 16-bit with a physical
    // range; the gaze point as one Gaze Point usage of two 24-bit values in mils (inch e-3); the
    // timestamp last, as eight one-byte elements in milliseconds (s, exponent -3 as a signed byte).
    Desc d;
    d.page(0x12).usage(hid::eye::kEyeTracker).collection(1);
    d.usage(hid::eye::kRightEyePosition).collection(0);
    d.usage(hid::eye::kPositionX).usage(hid::eye::kPositionY).usage(hid::eye::kPositionZ);
    d.lmin(-32768).lmax(32767).pmin(-65536).pmax(65534).size(16).count(3).unit(kCm).exponent(-1, 1).input().end();
    d.item(0x74, 4).count(1).input(0x03);  // 4 bits of constant padding
    d.item(0x74, 4).count(1).input(0x03);
    d.usage(hid::eye::kGazePoint)
        .lmin(-8388608)
        .lmax(8388607)
        .pmin(0)
        .pmax(0)
        .size(24)
        .count(2)
        .unit(kInch)
        .exponent(0xD);
    d.input();
    d.usage(hid::eye::kSensorTimestamp).lmin(0).lmax(255).size(8).count(8).unit(kSeconds).exponent(-3, 1).input();
    d.end();
    auto desc = hid::parse_descriptor(d.b);
    ASSERT_TRUE(desc.ok()) << desc.error().message;
    EXPECT_FALSE(desc->uses_report_ids);
    auto layout = hid::find_eye_tracker(*desc);
    ASSERT_TRUE(layout.ok()) << layout.error().message;
    EXPECT_EQ(layout->timestamp.elements, 8u);
    EXPECT_FALSE(layout->eye_pos[0][0].found());
    EXPECT_TRUE(layout->eye_pos[1][0].found());

    Report r;
    r.le(static_cast<uint16_t>(1500), 2).le(static_cast<uint16_t>(-200), 2).le(static_cast<uint16_t>(3000), 2);
    r.u8(0x00);  // padding
    r.le(10000, 3).le(static_cast<uint32_t>(-2000) & 0xFFFFFF, 3);
    r.le(987654321ull, 8);
    ASSERT_EQ(r.b.size(), desc->report_bytes(hid::ReportType::Input, 0));
    auto t = hid::decode_tracking(*desc, *layout, r.b);
    ASSERT_TRUE(t.ok()) << t.error().message;
    // 1500 logical -> 3000 physical (x2) mm -> 3 000 000 um.
    EXPECT_NEAR(t->eye_um[1]->x, 3000.0 * 1000, 1e-3 * 1000);
    EXPECT_NEAR(t->eye_um[1]->y, -400.0 * 1000, 1e-3 * 1000);
    EXPECT_NEAR(t->gaze_um.x, 10000 * 25.4, 1e-6);  // 10000 mil = 10 in
    EXPECT_NEAR(t->gaze_um.y, -2000 * 25.4, 1e-6);
    EXPECT_DOUBLE_EQ(*t->timestamp_us, 987654321.0 * 1000);
    EXPECT_FALSE(t->eye_um[0].has_value());
}

TEST(HidDescriptor, GazePointOutsideLogicalRangeIsNull) {
    Desc d;
    d.page(0x12).usage(hid::eye::kEyeTracker).collection(1).usage(hid::eye::kGazePoint).collection(0);
    d.usage(hid::eye::kPositionX).usage(hid::eye::kPositionY).lmin(0).lmax(30000).size(16).count(2).input(0x42);
    d.end().end();
    auto desc = hid::parse_descriptor(d.b);
    ASSERT_TRUE(desc.ok()) << desc.error().message;
    auto layout = hid::find_eye_tracker(*desc);
    ASSERT_TRUE(layout.ok());
    auto t = hid::decode_tracking(*desc, *layout, Report().le(0xFFFF, 2).le(100, 2).b);
    ASSERT_TRUE(t.ok());
    EXPECT_FALSE(t->gaze_valid);
    EXPECT_FALSE(hid::eyes_from_gaze_point(*t, {600000, 340000})[0].valid);
}

TEST(HidDescriptor, TruncatedOversizedAndNonsenseDescriptors) {
    const Bytes good = standard_descriptor();
    auto cut = hid::parse_descriptor(std::span(good).first(good.size() - 9));
    ASSERT_FALSE(cut.ok());
    EXPECT_TRUE(contains(cut.error().message, "not closed") || contains(cut.error().message, "truncated"))
        << cut.error().message;
    auto mid_item = hid::parse_descriptor(std::span(good).first(good.size() - 12));
    EXPECT_FALSE(mid_item.ok());
    Bytes trunc = {0x05, 0x12, 0x27, 0xFF, 0xFF};
    auto t = hid::parse_descriptor(trunc);
    ASSERT_FALSE(t.ok());
    EXPECT_TRUE(contains(t.error().message, "truncated")) << t.error().message;
    EXPECT_TRUE(contains(t.error().message, "byte 2")) << t.error().message;

    Bytes big(5000, 0xC0);
    auto b = hid::parse_descriptor(big);
    ASSERT_FALSE(b.ok());
    EXPECT_TRUE(contains(b.error().message, "4096")) << b.error().message;

    EXPECT_TRUE(contains(hid::parse_descriptor(Bytes{0xC0}).error().message, "End Collection"));
    EXPECT_TRUE(contains(hid::parse_descriptor(Bytes{}).error().message, "empty"));
    EXPECT_TRUE(contains(hid::parse_descriptor(Bytes{0xB4}).error().message, "Pop"));
    EXPECT_TRUE(contains(hid::parse_descriptor(Bytes{0x85, 0x00}).error().message, "Report ID"));
    EXPECT_TRUE(contains(hid::parse_descriptor(Bytes{0x95, 0x02, 0x81, 0x02}).error().message, "Report Size 0"));
    EXPECT_TRUE(contains(hid::parse_descriptor(Bytes{0x75, 0x08, 0x95, 0x01, 0x81, 0x02, 0x85, 0x01}).error().message,
                         "mixes"));
    EXPECT_TRUE(contains(hid::parse_descriptor(Bytes{0x0C}).error().message, "reserved"));  // type 3
    EXPECT_TRUE(contains(hid::parse_descriptor(Bytes{0x29, 0x05}).error().message, "Usage Maximum"));
    EXPECT_TRUE(contains(hid::parse_descriptor(Bytes{0x19, 0x05, 0x29, 0x01}).error().message, "range"));
    EXPECT_TRUE(
        contains(hid::parse_descriptor(Bytes{0x75, 0x08, 0x96, 0xFF, 0xFF, 0x81, 0x02, 0x81, 0x02}).error().message,
                 "4096 bytes"));

    // A mouse is a valid descriptor but not an eye tracker.
    Desc mouse;
    mouse.page(1).usage(2).collection(1).usage(0x30).usage(0x31).lmin(-127).lmax(127).size(8).count(2).item(0x80, 6);
    mouse.end();
    auto m = hid::parse_descriptor(mouse.b);
    ASSERT_TRUE(m.ok()) << m.error().message;
    auto ml = hid::find_eye_tracker(*m);
    ASSERT_FALSE(ml.ok());
    EXPECT_TRUE(contains(ml.error().message, "not an eye tracker"));

    // A gaze point in seconds is refused with the reason.
    Desc wrong;
    wrong.page(0x12).usage(1).collection(1).usage(hid::eye::kGazePoint).collection(0);
    wrong.usage(hid::eye::kPositionX).usage(hid::eye::kPositionY).size(16).count(2).unit(kSeconds).input().end().end();
    auto w = hid::parse_descriptor(wrong.b);
    ASSERT_TRUE(w.ok());
    auto wl = hid::find_eye_tracker(*w);
    ASSERT_FALSE(wl.ok());
    EXPECT_TRUE(contains(wl.error().message, "not a length")) << wl.error().message;

    // Random bytes: never a crash, and every failure says why.
    cv::RNG rng(77);
    size_t parsed = 0;
    for (int i = 0; i < 3000; ++i) {
        Bytes junk(static_cast<size_t>(rng.uniform(1, 200)));
        for (uint8_t& x : junk) x = static_cast<uint8_t>(rng.uniform(0, 256));
        auto r = hid::parse_descriptor(junk);
        if (r.ok()) {
            ++parsed;
            auto l = hid::find_eye_tracker(*r);
            if (l.ok()) (void)hid::decode_tracking(*r, *l, junk);
        } else {
            EXPECT_FALSE(r.error().message.empty());
        }
    }
    EXPECT_LT(parsed, 3000u);
}

TEST(HidDescriptor, TruncatedOversizedAndUnknownReports) {
    auto d = hid::parse_descriptor(standard_descriptor());
    ASSERT_TRUE(d.ok());
    auto layout = hid::find_eye_tracker(*d);
    ASSERT_TRUE(layout.ok());
    Bytes r = standard_report(1, 2, 3);
    auto shortr = hid::decode_tracking(*d, *layout, std::span(r).first(20));
    ASSERT_FALSE(shortr.ok());
    EXPECT_TRUE(contains(shortr.error().message, "truncated")) << shortr.error().message;
    EXPECT_TRUE(contains(shortr.error().message, "41")) << shortr.error().message;
    Bytes longr = r;
    longr.push_back(0);
    auto lr = hid::decode_tracking(*d, *layout, longr);
    ASSERT_FALSE(lr.ok());
    EXPECT_TRUE(contains(lr.error().message, "oversized"));
    Bytes other = r;
    other[0] = 9;
    EXPECT_TRUE(contains(hid::decode_tracking(*d, *layout, other).error().message, "report ID 9"));
    EXPECT_TRUE(contains(hid::decode_tracking(*d, *layout, Bytes{}).error().message, "empty"));
    EXPECT_FALSE(hid::decode_screen(*d, *layout, Bytes{3, 1, 2}).ok());
    EXPECT_FALSE(hid::decode_screen(*d, *layout, Bytes{3, 0, 0, 0, 0, 0, 0, 0, 0}).ok());  // zero size
}

TEST(HidEyeTracker, GazePointToEyeDirections) {
    hid::TrackingData t;
    t.gaze_um = {400000, 150000};  // 10 cm right of the left eye, at its height
    t.eye_um[0] = glm::dvec3(300000, 150000, 600000);
    t.eye_um[1] = glm::dvec3(400000, 50000, 600000);
    const auto eyes = hid::eyes_from_gaze_point(t, {600000, 340000});
    ASSERT_TRUE(eyes[0].valid && eyes[1].valid);
    const wg::GazeAngle l = wg::angle_from_direction(eyes[0].dir), r = wg::angle_from_direction(eyes[1].dir);
    EXPECT_NEAR(l.az_deg, std::atan(0.1 / 0.6) * 180 / M_PI, 1e-4);
    EXPECT_NEAR(l.el_deg, 0, 1e-4);
    EXPECT_NEAR(r.az_deg, 0, 1e-4);
    EXPECT_NEAR(r.el_deg, -std::atan(0.1 / 0.6) * 180 / M_PI, 1e-4);  // point is 10 cm lower (y down)
    // No eye positions: centred viewer at 65 cm.
    hid::TrackingData c;
    c.gaze_um = {300000, 170000};
    const auto ce = hid::eyes_from_gaze_point(c, {600000, 340000});
    EXPECT_NEAR(wg::angle_from_direction(ce[0].dir).az_deg, std::atan(31.5 / 650) * 180 / M_PI, 1e-4);
    EXPECT_NEAR(wg::angle_from_direction(ce[1].dir).az_deg, -std::atan(31.5 / 650) * 180 / M_PI, 1e-4);
    // An eye behind the screen plane is impossible.
    t.eye_um[0]->z = -5;
    EXPECT_FALSE(hid::eyes_from_gaze_point(t, {600000, 340000})[0].valid);
}

namespace {

// A scripted device: reports to hand out, and whether it is plugged in.
struct FakeDevice {
    bool plugged = true;
    bool unplug_on_read = false;
    std::deque<Bytes> pending;
    int opens = 0;
};

class FakeConnection final : public hid::Connection {
public:
    explicit FakeConnection(FakeDevice& d) : d_(d) {}
    wg::Result<Bytes> descriptor() override { return standard_descriptor(); }
    int read(std::span<uint8_t> buf) override {
        if (!d_.plugged || d_.unplug_on_read) return -1;
        if (d_.pending.empty()) return 0;
        const Bytes r = d_.pending.front();
        d_.pending.pop_front();
        std::memcpy(buf.data(), r.data(), r.size());
        return static_cast<int>(r.size());
    }
    wg::Result<Bytes> get_feature(uint8_t, size_t) override { return read_hex(kData + "/eyetracker_feature.hex"); }

private:
    FakeDevice& d_;
};

class FakeConnector final : public hid::Connector {
public:
    explicit FakeConnector(FakeDevice& d) : d_(d) {}
    wg::Result<std::unique_ptr<hid::Connection>> open() override {
        ++d_.opens;
        if (!d_.plugged) return wg::fail("fake device unplugged");
        return std::unique_ptr<hid::Connection>(std::make_unique<FakeConnection>(d_));
    }
    std::string name() const override { return "fake"; }

private:
    FakeDevice& d_;
};

}  // namespace

TEST(HidSource, MissingDeviceIsInvalidAndRetriedWithBackoff) {
    FakeDevice dev;
    dev.plugged = false;
    double now = 100;
    hid::HidTrackerSource src(std::make_unique<FakeConnector>(dev), {}, [&] { return now; });
    for (int i = 0; i < 100; ++i, now += 0.1) {  // 10 s of frames
        const wg::GazeSample s = src.sample(now);
        EXPECT_FALSE(s.eye[0].valid);
    }
    // Delays 0.25, 0.5, 1, 2, 4, 4: about 7 attempts in 10 s, not one per frame.
    EXPECT_GE(dev.opens, 5);
    EXPECT_LE(dev.opens, 8);
    EXPECT_TRUE(contains(src.last_error(), "unplugged"));
    // Plugged in: the next retry connects.
    dev.plugged = true;
    for (int i = 0; i < 50 && !src.connected(); ++i, now += 0.1) src.poll();
    EXPECT_TRUE(src.connected());
    ASSERT_TRUE(src.screen().has_value());
    EXPECT_DOUBLE_EQ(src.screen()->width_um, 600000);
}

TEST(HidSource, DecodesReportsHoldsThenInvalidOnSilenceAndUnplug) {
    FakeDevice dev;
    double now = 50;
    hid::HidSourceOptions o;
    o.policy.hold_s = 0.1;
    hid::HidTrackerSource src(std::make_unique<FakeConnector>(dev), o, [&] { return now; });
    // 120 Hz for 0.5 s, gaze 10 cm right of the left eye.
    uint64_t ts = 5'000'000;
    for (int i = 0; i < 60; ++i) {
        dev.pending.push_back(standard_report(ts, 370000, 150000));
        ts += 8333;
        now += 1.0 / 120;
        src.poll();
    }
    EXPECT_TRUE(src.connected());
    EXPECT_EQ(src.decode_errors(), 0u);
    const auto fresh = src.take_new_samples();
    EXPECT_EQ(fresh.size(), 60u);
    const wg::GazeSample s = src.sample(now - 0.02);
    ASSERT_TRUE(s.eye[0].valid);
    EXPECT_NEAR(wg::angle_from_direction(s.eye[0].dir).az_deg, std::atan(0.1 / 0.6) * 180 / M_PI, 1e-3);
    // Bad report in the stream: counted, not fatal.
    dev.pending.push_back(Bytes{1, 2, 3});
    src.poll();
    EXPECT_EQ(src.decode_errors(), 1u);
    EXPECT_TRUE(src.connected());
    // Silence: held for 0.1 s, then invalid; after 1 s the device is reopened.
    now += 0.05;
    EXPECT_TRUE(src.sample(now).eye[0].valid);
    now += 0.1;
    EXPECT_FALSE(src.sample(now).eye[0].valid);
    const int opens = dev.opens;
    now += 1.0;
    src.poll();
    EXPECT_FALSE(src.connected());
    now += 0.3;
    src.poll();
    EXPECT_GT(dev.opens, opens);
    // Unplugged mid-stream: the read fails, samples go invalid, nothing blocks.
    dev.unplug_on_read = true;
    now += 0.5;
    for (int i = 0; i < 10; ++i, now += 0.01) EXPECT_FALSE(src.sample(now).eye[0].valid);
    EXPECT_FALSE(src.connected());
}

TEST(HidDevice, RealHidapiPathsFailCleanly) {
    auto desc = hid::read_sysfs_descriptor("/dev/hidraw-does-not-exist99");
    EXPECT_FALSE(desc.ok());
    EXPECT_FALSE(hid::read_sysfs_descriptor("/dev/null").ok());
    hid::HidTrackerSource src(hid::hidapi_connector("/dev/hidraw-does-not-exist99"));
    const wg::GazeSample s = src.sample(hid::HidTrackerSource::steady_seconds());
    EXPECT_FALSE(s.eye[0].valid);
    EXPECT_FALSE(src.connected());
    EXPECT_FALSE(src.last_error().empty());
    auto list = hid::enumerate_devices();  // may be empty here; must not fail or crash
    EXPECT_TRUE(list.ok());
    EXPECT_FALSE(hid::resolve_device("banana").ok());
    EXPECT_FALSE(hid::resolve_device("9999").ok());
}
