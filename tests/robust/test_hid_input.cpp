// docs/bad-input.md, "HID descriptors and reports": what the HID tracker source does with a device
// that answers badly (descriptor, feature report, input reports). The parser and decoder on their
// own are covered by tests/gaze/test_hid.cpp; here the source, which must never block, crash or
// produce a non-finite direction, and must say what went wrong.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <deque>
#include <fstream>
#include <optional>
#include <string>
#include <vector>

#include "gaze/hid_device.h"

namespace wrsfov::gaze::hid {
namespace {

using Bytes = std::vector<uint8_t>;
const std::string kData = WRSFOV_GAZE_TEST_DATA;

Bytes readHex(const std::string& path) {
    std::ifstream in(path);
    Bytes out;
    std::string tok;
    while (in >> tok) out.push_back(static_cast<uint8_t>(std::stoul(tok, nullptr, 16)));
    return out;
}
Bytes standardDescriptor() { return readHex(kData + "/eyetracker_descriptor.hex"); }
Bytes standardFeature() { return readHex(kData + "/eyetracker_feature.hex"); }

// Report 1 of the standard descriptor: timestamp (µs), gaze point (µm), left and right eye (µm).
Bytes report(uint64_t ts, int32_t gx, int32_t gy, int32_t eyeZ = 600000) {
    Bytes r{1};
    auto le = [&](uint64_t v, int n) {
        for (int i = 0; i < n; ++i) r.push_back(static_cast<uint8_t>(v >> (8 * i)));
    };
    le(ts, 8);
    le(static_cast<uint32_t>(gx), 4);
    le(static_cast<uint32_t>(gy), 4);
    for (int32_t v : {270000, 170000, eyeZ, 330000, 170000, eyeZ}) le(static_cast<uint32_t>(v), 4);
    return r;
}

struct Device {
    Result<Bytes> descriptor = standardDescriptor();
    Result<Bytes> feature = standardFeature();
    std::deque<Bytes> reports;
    bool gone = false;
};

class Conn final : public Connection {
public:
    explicit Conn(Device& d) : d_(d) {}
    Result<Bytes> descriptor() override { return d_.descriptor; }
    int read(std::span<uint8_t> buf) override {
        if (d_.gone) return -1;
        if (d_.reports.empty()) return 0;
        const Bytes r = d_.reports.front();
        d_.reports.pop_front();
        const size_t n = std::min(r.size(), buf.size());
        std::memcpy(buf.data(), r.data(), n);
        return static_cast<int>(n);
    }
    Result<Bytes> get_feature(uint8_t, size_t) override { return d_.feature; }

private:
    Device& d_;
};

class Conner final : public Connector {
public:
    explicit Conner(Device& d) : d_(d) {}
    Result<std::unique_ptr<Connection>> open() override {
        return std::unique_ptr<Connection>(std::make_unique<Conn>(d_));
    }
    std::string name() const override { return "test device"; }

private:
    Device& d_;
};

struct Rig {
    explicit Rig(HidSourceOptions o = {}) : src(std::make_unique<Conner>(dev), o, [this] { return now; }) {}
    // Polls once per 10 ms for `seconds`, checking that every sample is finite.
    void run(double seconds) {
        for (double end = now + seconds; now < end; now += 0.01) {
            const GazeSample s = src.sample(now);
            for (const EyeGaze& e : s.eye)
                EXPECT_TRUE(std::isfinite(e.dir.x) && std::isfinite(e.dir.y) && std::isfinite(e.dir.z));
        }
    }
    Device dev;
    double now = 100.0;
    HidTrackerSource src;
};

bool contains(const std::string& s, const std::string& part) { return s.find(part) != std::string::npos; }

TEST(HidInput, DescriptorUnreadable) {
    Rig r;
    r.dev.descriptor = fail("cannot read /sys/class/hidraw/hidraw9/device/report_descriptor (device unplugged?)");
    r.run(0.1);
    EXPECT_FALSE(r.src.connected());
    EXPECT_TRUE(contains(r.src.last_error(), "cannot read")) << r.src.last_error();
    EXPECT_FALSE(r.src.sample(r.now).eye[0].valid);
}

TEST(HidInput, DescriptorEmptyTruncatedOrOversized) {
    for (const auto& [bytes, part] :
         {std::pair{Bytes{}, "empty"}, std::pair{Bytes{0x05, 0x12, 0x27, 0xFF}, "truncated"},
          std::pair{Bytes(5000, 0xC0), "4096"}}) {
        Rig r;
        r.dev.descriptor = bytes;
        r.run(0.05);
        EXPECT_FALSE(r.src.connected());
        EXPECT_TRUE(contains(r.src.last_error(), "report descriptor")) << r.src.last_error();
        EXPECT_TRUE(contains(r.src.last_error(), part)) << r.src.last_error();
    }
}

TEST(HidInput, DescriptorOfAMouse) {
    Rig r;
    r.dev.descriptor = Bytes{0x05, 0x01, 0x09, 0x02, 0xA1, 0x01, 0x09, 0x30, 0x09, 0x31, 0x15,
                             0x81, 0x25, 0x7F, 0x75, 0x08, 0x95, 0x02, 0x81, 0x06, 0xC0};
    r.run(0.05);
    EXPECT_FALSE(r.src.connected());
    EXPECT_TRUE(contains(r.src.last_error(), "not an eye tracker")) << r.src.last_error();
}

TEST(HidInput, NoScreenSizeAnywhere) {
    // An eye tracker without the Calibrated Screen feature, and no --screen-mm.
    Rig r;
    r.dev.descriptor = Bytes{0x05, 0x12, 0x09, 0x01, 0xA1, 0x01, 0x09, 0x24, 0xA1, 0x00, 0x09, 0x21, 0x09, 0x22,
                             0x15, 0x00, 0x26, 0x30, 0x75, 0x75, 0x10, 0x95, 0x02, 0x81, 0x02, 0xC0, 0xC0};
    r.run(0.05);
    EXPECT_FALSE(r.src.connected());
    EXPECT_TRUE(contains(r.src.last_error(), "no Calibrated Screen Width/Height feature")) << r.src.last_error();
    // The same device with the size given works.
    HidSourceOptions o;
    o.screen = ScreenSize{600000, 340000};
    Rig given(o);
    given.dev.descriptor = r.dev.descriptor;
    given.dev.reports.push_back(Bytes{0x10, 0x27, 0x10, 0x27});  // (10000, 10000) µm
    given.run(0.05);
    EXPECT_TRUE(given.src.connected()) << given.src.last_error();
    EXPECT_TRUE(given.src.sample(given.now - 0.02).eye[0].valid);
}

TEST(HidInput, FeatureReportFailsOrIsNonsense) {
    Rig r;
    r.dev.feature = fail("reading feature report 3 from /dev/hidraw9 failed");
    r.run(0.05);
    EXPECT_FALSE(r.src.connected());
    EXPECT_TRUE(contains(r.src.last_error(), "feature report 3")) << r.src.last_error();
    Rig zero;
    zero.dev.feature = Bytes{3, 0, 0, 0, 0, 0, 0, 0, 0};
    zero.run(0.05);
    EXPECT_FALSE(zero.src.connected());
    EXPECT_TRUE(contains(zero.src.last_error(), "not positive")) << zero.src.last_error();
    Rig shortFeature;
    shortFeature.dev.feature = Bytes{3, 1};
    shortFeature.run(0.05);
    EXPECT_FALSE(shortFeature.src.connected());
    EXPECT_FALSE(shortFeature.src.last_error().empty());
}

TEST(HidInput, BadReportsAreCountedAndSkipped) {
    Rig r;
    uint64_t ts = 1'000'000;
    auto good = [&] { return report(ts += 4000, 300000, 170000); };
    r.dev.reports = {good(), Bytes{1, 2, 3},
                     [&] {
                         Bytes b = good();
                         b.push_back(0);
                         return b;
                     }(),
                     Bytes(4096, 1), good()};
    r.run(0.05);
    EXPECT_TRUE(r.src.connected());
    EXPECT_EQ(r.src.decode_errors(), 3u);
    EXPECT_EQ(r.src.take_new_samples().size(), 2u);
    EXPECT_TRUE(r.src.sample(r.now - 0.02).eye[0].valid);
}

TEST(HidInput, OtherReportIdsAreIgnored) {
    Rig r;
    Bytes other = report(5000, 300000, 170000);
    other[0] = 2;
    r.dev.reports = {other, other};
    r.run(0.05);
    EXPECT_TRUE(r.src.connected());
    EXPECT_EQ(r.src.decode_errors(), 0u);
    EXPECT_TRUE(r.src.take_new_samples().empty());
}

TEST(HidInput, HugeNullAndImpossibleValues) {
    Rig r;
    uint64_t ts = 2'000'000;
    // Gaze point at INT32_MAX µm (2 km off the screen): a valid, finite direction, far to the side.
    r.dev.reports = {report(ts += 4000, INT32_MAX, 170000)};
    r.run(0.02);
    auto s = r.src.take_new_samples();
    ASSERT_EQ(s.size(), 1u);
    EXPECT_TRUE(s[0].eye[0].valid);
    EXPECT_GT(s[0].eye[0].dir.x, 0.99f);
    // Gaze point at INT32_MIN: the logical minimum, still in range.
    r.dev.reports = {report(ts += 4000, INT32_MIN, 0)};
    r.run(0.02);
    s = r.src.take_new_samples();
    ASSERT_EQ(s.size(), 1u);
    EXPECT_TRUE(s[0].eye[0].valid);
    // Eyes behind the screen plane (negative distance): impossible geometry, both eyes invalid.
    r.dev.reports = {report(ts += 4000, 300000, 170000, -600000)};
    r.run(0.02);
    s = r.src.take_new_samples();
    ASSERT_EQ(s.size(), 1u);
    EXPECT_FALSE(s[0].eye[0].valid || s[0].eye[1].valid);
    // Eyes on the screen plane (distance 0): invalid too.
    r.dev.reports = {report(ts += 4000, 300000, 170000, 0)};
    r.run(0.02);
    s = r.src.take_new_samples();
    ASSERT_EQ(s.size(), 1u);
    EXPECT_FALSE(s[0].eye[0].valid || s[0].eye[1].valid);
    EXPECT_EQ(r.src.decode_errors(), 0u);
}

TEST(HidInput, TimestampsBackwardsHugeOrJumping) {
    Rig r;
    r.dev.reports = {report(9'000'000, 300000, 170000), report(8'000'000, 300000, 170000),  // backwards
                     report(UINT64_MAX, 300000, 170000),                                    // huge
                     report(5, 300000, 170000)};                                            // device reset
    r.run(0.05);
    const auto s = r.src.take_new_samples();
    ASSERT_EQ(s.size(), 4u);
    for (size_t i = 0; i < s.size(); ++i) {
        EXPECT_TRUE(std::isfinite(s[i].t_s));
        if (i > 0) {
            EXPECT_GT(s[i].t_s, s[i - 1].t_s) << "sample times must increase";
        }
    }
    EXPECT_TRUE(r.src.sample(r.now - 0.02).eye[0].valid);
}

TEST(HidInput, DeviceGoneMidStreamIsInvalidAfterTheHold) {
    Rig r;
    uint64_t ts = 3'000'000;
    for (int i = 0; i < 20; ++i) r.dev.reports.push_back(report(ts += 4000, 300000, 170000));
    r.run(0.1);
    EXPECT_TRUE(r.src.sample(r.now - 0.05).eye[0].valid);
    r.dev.gone = true;
    r.run(0.05);
    EXPECT_FALSE(r.src.connected());
    EXPECT_TRUE(contains(r.src.last_error(), "read failed")) << r.src.last_error();
    r.run(0.2);
    EXPECT_FALSE(r.src.sample(r.now).eye[0].valid);
}

}  // namespace
}  // namespace wrsfov::gaze::hid
