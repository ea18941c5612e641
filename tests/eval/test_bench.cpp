// Regression guard of the benchmark's headline: at a 5° fovea, WRS keeps more near-gaze quality
// than FOV on the reading page (reading gaze) and in the atrium (free viewing, static camera).
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "../core/gpu_rig.h"
#include "eval/bench.h"
#include "eval/flicker.h"

namespace wrsfov::test {
namespace {

class Bench : public GpuTest {};

TEST_F(Bench, WrsBeatsFovNearGazeAtFiveDegrees) {
    eval::BenchOptions o;
    o.scenes = {eval::SceneKind::Text, eval::SceneKind::Atrium};
    o.methods = {Method::Fov, Method::WrsPaper};
    o.foveas = {5.0f};
    o.modes = {FoveationMode::Mip};
    o.width = 160;
    o.height = 144;
    o.frames = 120;  // long enough for the reading gaze to revisit words
    o.warmup = 10;
    o.heavyEvery = 1000;
    o.path = scenes::CameraPath::Static;
    auto r = eval::runBench(context(), o);
    ASSERT_TRUE(r.ok()) << r.error().message;
    ASSERT_EQ(r->size(), 4u);
    for (eval::SceneKind scene : o.scenes) {
        double fov = NAN, wrs = NAN;
        for (const auto& c : *r) {
            if (c.scene != scene) continue;
            (c.method == Method::Fov ? fov : wrs) = c.nearPsnr;
            EXPECT_TRUE(c.gpu.valid);
            EXPECT_GT(c.copyMs, 0.0);
            EXPECT_GT(c.shadingFraction, 0.0);
            EXPECT_LT(c.shadingFraction, 0.2);  // a 5° fovea shades a small part of a 92° view at full rate
            // The eccentricity bands partition the pixels: their shares sum to 1 and their MSEs,
            // weighted by the shares, give the whole image's MSE.
            double share = 0.0, mse = 0.0;
            for (std::size_t b = 0; b < c.bandMse.size(); ++b) {
                share += c.bandShare[b];
                mse += c.bandShare[b] * c.bandMse[b];
            }
            EXPECT_NEAR(share, 1.0, 1e-12);
            EXPECT_NEAR(mse, c.mse, 1e-9 * c.mse);
            EXPECT_GT(c.bandShare.back(), 0.3);  // most of a 92° view lies beyond 30° of a gaze near its centre
        }
        std::printf("%s: near-gaze PSNR fov %.3f dB, wrs %.3f dB\n", std::string(eval::toString(scene)).c_str(), fov,
                    wrs);
        EXPECT_GT(wrs, fov) << eval::toString(scene);
    }
}

TEST_F(Bench, FlickerAnalysisAccountsForEveryStablePixelPair) {
    // wrsfov-bench --flicker on the photo scene: its classes partition the stable pixel pairs and
    // their sums are the methods' temporal instabilities; a still head gives `wrs` nothing to flicker
    // with (kept samples do not move: steadier than fov, and none is lost to a blurrier candidate), a
    // slow pan does (and loses kept samples in patches), the exact display of full-rate kept samples
    // differs from `wrs` only in the pairs that show one, and the files are written.
    eval::BenchOptions o;
    o.scenes = {eval::SceneKind::Photo};
    o.monitor = true;
    o.foveas = {5.0f};
    o.modes = {FoveationMode::Mip};
    o.width = 128;
    o.height = 96;
    o.frames = 24;
    o.warmup = 4;
    // Under the sanitizers (tools/run-tests.sh, stage 2), which check the host paths, the pan alone: it
    // takes every path the still head does, and the loss patches' too.
    std::vector<scenes::PhotoMotion> motions{scenes::PhotoMotion::Static, scenes::PhotoMotion::Pan};
    if (kSanitized) motions.erase(motions.begin());
    for (scenes::PhotoMotion m : motions) {
        SCOPED_TRACE(std::string(scenes::toString(m)));
        o.photoMotion = m;
        if (m == scenes::PhotoMotion::Pan) {  // large and long enough for the fovea's blend band to lose patches
            o.width = 256;
            o.height = 192;
            o.frames = 40;
        }
        const std::string dir = ::testing::TempDir() + "flicker_" + std::string(scenes::toString(m));
        auto r = eval::analyseFlicker(context(), o, dir);
        ASSERT_TRUE(r.ok()) << r.error().message;
        uint64_t pairs = 0;
        double w = 0, f = 0;
        for (const eval::FlickerClass& c : r->classes) {
            pairs += c.pairs;
            w += c.wrsChange;
            f += c.fovChange;
            EXPECT_GT(c.pairs, 0u) << c.name;
        }
        ASSERT_GT(r->stablePairs, 1000u);
        EXPECT_EQ(pairs, r->stablePairs);
        EXPECT_NEAR(r->wrsInstability, w / double(pairs), 1e-12);
        EXPECT_NEAR(r->fovInstability, f / double(pairs), 1e-12);
        // The exact display of full-rate kept samples changes what `wrs` shows only where it showed one:
        // classes with none in either frame change as `wrs` does (as `fov` does with `fov`'s output
        // elsewhere), those with one in both frames as the reference does.
        double x = 0, xf = 0;
        for (const eval::FlickerClass& c : r->classes) {
            x += c.exactKeptChange;
            xf += c.exactKeptFovChange;
            const std::size_t arrow = c.name.find(" → ");
            ASSERT_NE(arrow, std::string::npos) << c.name;
            const std::string full = "sharper: full-rate";
            const bool before = c.name.rfind(full, 0) == 0, after = c.name.compare(arrow + 5, full.size(), full) == 0;
            if (!before && !after) {
                EXPECT_NEAR(c.exactKeptChange, c.wrsChange, 1e-9) << c.name;
                EXPECT_NEAR(c.exactKeptFovChange, c.fovChange, 1e-9) << c.name;
            }
            if (before && after) {
                EXPECT_NEAR(c.exactKeptChange, c.refChange, 1e-9) << c.name;
                EXPECT_NEAR(c.exactKeptFovChange, c.refChange, 1e-9) << c.name;
            }
        }
        EXPECT_NEAR(r->exactKeptInstability, x / double(pairs), 1e-12);
        EXPECT_NEAR(r->exactKeptFovInstability, xf / double(pairs), 1e-12);
        // Loss patches: largest first, each a connected set within its bounding box.
        for (std::size_t k = 0; k < r->patches.size(); ++k) {
            const eval::DropPatch& p = r->patches[k];
            EXPECT_GE(p.area, eval::FlickerReport::kMinDropPatch);
            EXPECT_LE(p.area, p.width * p.height);
            EXPECT_GE(p.area, std::max(p.width, p.height));  // 8-connected across its whole box
            EXPECT_GT(p.reasonShare, 0.0);
            EXPECT_LE(p.reasonShare, 1.0);
            EXPECT_GT(p.frame, int(o.warmup));
            if (k) {
                EXPECT_LE(p.area, r->patches[k - 1].area);
            }
        }
        std::printf("%zu loss patches\n", r->patches.size());
        std::printf("%s: wrs %.6f fov %.6f reference %.6f over %llu pairs, %zu classes\n",
                    std::string(scenes::toString(m)).c_str(), r->wrsInstability, r->fovInstability, r->refInstability,
                    (unsigned long long)r->stablePairs, r->classes.size());
        if (m == scenes::PhotoMotion::Static) {
            EXPECT_LE(r->wrsInstability, r->fovInstability);
            EXPECT_EQ(r->refInstability, 0.0) << "a still scene: the reference never changes";
            EXPECT_TRUE(r->patches.empty()) << "a still scene loses no kept sample to a blurrier candidate";
        } else {
            EXPECT_GT(r->refInstability, 0.0);
            EXPECT_FALSE(r->patches.empty()) << "under a pan the fovea's blend band loses kept samples in patches";
        }
        for (const char* file : {"/flicker.md", "/flicker.csv", "/flicker.png"})
            EXPECT_TRUE(std::filesystem::exists(dir + file)) << file;
    }
}

// A small text page in HMD stereo: fov without foveation (the reference itself) and with it.
eval::BenchOptions smallJodSweep() {
    eval::BenchOptions o;
    o.scenes = {eval::SceneKind::Text};
    o.methods = {Method::Fov, Method::Wrs};
    o.foveas = {5.0f};
    o.width = 96;
    o.height = 80;
    o.frames = 14;
    o.warmup = 4;
    o.heavyEvery = 1000;
    o.jodFrames = 6;
    return o;
}

const eval::CellResult* cell(const std::vector<eval::CellResult>& r, Method m, FoveationMode mode, float fovea) {
    for (const auto& c : r)
        if (c.method == m && c.mode == mode && c.foveaDeg == fovea) return &c;
    return nullptr;
}

TEST_F(Bench, JodIsTenForTheReferenceAndLowerForFoveation) {
    eval::BenchOptions o = smallJodSweep();
    o.modes = {FoveationMode::None, FoveationMode::Mip};
    o.worthFoveas = {5.0f, 10.0f};  // 5° is a cell already: only 10° is added
    auto r = eval::runBench(context(), o);
    ASSERT_TRUE(r.ok()) << r.error().message;
    const eval::CellResult* same = cell(*r, Method::Fov, FoveationMode::None, 5.0f);
    const eval::CellResult* fov = cell(*r, Method::Fov, FoveationMode::Mip, 5.0f);
    const eval::CellResult* fov10 = cell(*r, Method::Fov, FoveationMode::Mip, 10.0f);
    ASSERT_TRUE(same && fov && fov10);
    EXPECT_EQ(same->jod, 10.0);  // no foveation: the output is the reference
    EXPECT_EQ(same->jodFrames, 6);
    EXPECT_LT(fov->jod, 9.99);
    EXPECT_GT(fov->jod, 0.0);
    EXPECT_FALSE(fov->worthSweep);
    EXPECT_TRUE(fov10->worthSweep);
    EXPECT_EQ(fov10->frames, 6);
    EXPECT_TRUE(std::isfinite(fov10->jod));
    EXPECT_TRUE(std::isfinite(fov10->jodNearPsnr));
    EXPECT_GE(fov10->jodNearPsnr, fov->jodNearPsnr);  // a larger fovea loses less near the gaze
    EXPECT_EQ(r->size(), 2u /* none */ + 3u /* mip: fov, wrs, fov at 10° */);

    const std::string dir = ::testing::TempDir() + "/bench_jod_report";
    std::filesystem::remove_all(dir);
    std::filesystem::create_directories(dir);
    ASSERT_TRUE(eval::writeReport(*r, o, dir, "test").ok());
    std::ifstream csv(dir + "/results.csv");
    std::string header;
    std::getline(csv, header);
    EXPECT_NE(header.find(",psnr,jod,ssim,"), std::string::npos) << header;
    EXPECT_NE(header.find(",jod_frames,jod_near_gaze_psnr,worth_sweep"), std::string::npos) << header;
    EXPECT_TRUE(std::filesystem::exists(dir + "/fovea_worth.csv"));
    EXPECT_TRUE(std::filesystem::exists(dir + "/jod_vs_time_text_mip.png"));
    std::ifstream md(dir + "/table.md");
    const std::string table((std::istreambuf_iterator<char>(md)), {});
    EXPECT_NE(table.find("| JOD |"), std::string::npos);
    EXPECT_NE(table.find("The fovea `wrs` at 5.0° is worth"), std::string::npos);
    EXPECT_NE(table.find("| fov (sweep) | 10.0°"), std::string::npos);
}

// Splits one CSV line.
std::vector<std::string> fields(const std::string& line) {
    std::vector<std::string> out;
    std::stringstream ss(line);
    for (std::string f; std::getline(ss, f, ',');) out.push_back(f);
    return out;
}

TEST_F(Bench, WriteOutputsWritesWhatTheMetricsScored) {
    eval::BenchOptions o = smallJodSweep();
    o.modes = {FoveationMode::Mip};
    const std::string dir = ::testing::TempDir() + "/bench_outputs";
    std::filesystem::remove_all(dir);
    o.outputsDir = dir;
    auto r = eval::runBench(context(), o);
    ASSERT_TRUE(r.ok()) << r.error().message;
    const std::string cellDir = dir + "/text_mip_5";
    const int counted = o.frames - o.warmup;
    for (const char* who : {"reference", "fov", "wrs"})
        for (const char* eye : {"L", "R"}) {
            for (int k = 0; k < counted; ++k) {
                char name[16];
                std::snprintf(name, sizeof name, "%06d.png", k);
                const std::string path = cellDir + "/" + who + "/" + eye + "/" + name;
                ASSERT_TRUE(std::filesystem::exists(path)) << path;
            }
            char extra[16];
            std::snprintf(extra, sizeof extra, "%06d.png", counted);
            EXPECT_FALSE(std::filesystem::exists(cellDir + "/" + who + "/" + eye + "/" + extra));
        }
    // gaze.csv: a header and one line per counted frame with both eyes' gaze in pixels.
    std::ifstream gaze(cellDir + "/gaze.csv");
    std::string line;
    std::getline(gaze, line);
    EXPECT_EQ(line, "frame,left_x,left_y,right_x,right_y,bench_frame,t_s");
    std::vector<std::array<float, 4>> gazePx;
    while (std::getline(gaze, line)) {
        const auto f = fields(line);
        ASSERT_EQ(f.size(), 7u) << line;
        EXPECT_EQ(std::stoi(f[0]), int(gazePx.size()));
        EXPECT_EQ(std::stoi(f[5]), int(gazePx.size()) + o.warmup);
        gazePx.push_back({std::stof(f[1]), std::stof(f[2]), std::stof(f[3]), std::stof(f[4])});
    }
    ASSERT_EQ(int(gazePx.size()), counted);
    // view.csv: each eye's tangents; scoring the written frames with them and the gaze gives the
    // bench's JOD (mean of the eyes).
    std::ifstream view(cellDir + "/view.csv");
    std::getline(view, line);
    std::vector<glm::vec4> tan;
    int jodFirst = -1;
    while (std::getline(view, line)) {
        const auto f = fields(line);
        ASSERT_EQ(f.size(), 11u) << line;
        tan.emplace_back(std::stof(f[1]), std::stof(f[2]), std::stof(f[3]), std::stof(f[4]));
        EXPECT_EQ(f[8], "hmd");
        jodFirst = std::stoi(f[10]);
    }
    ASSERT_EQ(tan.size(), 2u);
    EXPECT_EQ(jodFirst, counted - o.jodFrames);
    const eval::CellResult* wrs = cell(*r, Method::Wrs, FoveationMode::Mip, 5.0f);
    ASSERT_TRUE(wrs);
    double sum = 0;
    for (int e = 0; e < 2; ++e) {
        auto metric = eval::makeJodMetric(context(), eval::jodOptions(o, eval::SceneKind::Text, o.width, o.height,
                                                                      tan[size_t(e)], 90.0));
        ASSERT_TRUE(metric.ok()) << metric.error().message;
        for (int k = jodFirst; k < counted; ++k) {
            char name[16];
            std::snprintf(name, sizeof name, "%06d.png", k);
            auto load = [&](const char* who) {
                cv::Mat bgr = cv::imread(cellDir + "/" + who + "/" + (e == 0 ? "L/" : "R/") + name), rgb, f;
                cv::cvtColor(bgr, rgb, cv::COLOR_BGR2RGB);
                rgb.convertTo(f, CV_32FC3, 1.0 / 255.0);
                return f;
            };
            const glm::vec2 g(gazePx[size_t(k)][2 * e], gazePx[size_t(k)][2 * e + 1]);
            ASSERT_TRUE((*metric)->push(load("wrs"), load("reference"), g).ok());
        }
        sum += *(*metric)->jod();
    }
    EXPECT_NEAR(sum / 2, wrs->jod, 1e-4);
}

// The scaling sweep's run keeps a scene's frames on the device: the atrium is rendered into the
// compositors' inputs every frame and never uploaded, a still page is uploaded once, and every
// method is timed against its copy kernels with no metric computed.
TEST_F(Bench, DeviceSweepUploadsAStillImageOnceAndRendersTheAtriumInPlace) {
    eval::BenchOptions o;
    o.scenes = {eval::SceneKind::Text};
    o.methods = {Method::Fov, Method::Wrs};
    o.foveas = {5.0f};
    o.modes = {FoveationMode::Mip};
    o.width = 128;
    o.height = 96;
    o.frames = 6;
    o.warmup = 2;
    o.staleStats = false;
    o.qualityMetrics = false;
    eval::DeviceSweepStats stats;
    auto r = eval::runDeviceSweep(context(), o, &stats);
    ASSERT_TRUE(r.ok()) << r.error().message;
    EXPECT_EQ(stats.uploads, 1);
    EXPECT_EQ(stats.rendered, 0);
    EXPECT_EQ(stats.submitted, 12);
    ASSERT_EQ(r->size(), 2u);
    for (const eval::CellResult& c : *r) {
        EXPECT_TRUE(c.gpu.valid);
        EXPECT_GT(c.gpu.total, 0.0);
        EXPECT_GT(c.copyMs, 0.0);
        EXPECT_GT(c.copyFloorMs, 0.0);
        EXPECT_EQ(c.frames, 4);
        EXPECT_TRUE(std::isnan(c.psnr));
        EXPECT_GT(c.fovTotalMs, 0.0);
    }
    EXPECT_TRUE(std::isfinite((*r)[1].retainShare));

    o.scenes = {eval::SceneKind::Atrium};
    o.width = 96;
    o.height = 128;
    r = eval::runDeviceSweep(context(), o, &stats);
    ASSERT_TRUE(r.ok()) << r.error().message;
    EXPECT_EQ(stats.rendered, 6);
    EXPECT_EQ(stats.uploads, 0);
    EXPECT_EQ(stats.submitted, 12);
    ASSERT_EQ(r->size(), 2u);
    EXPECT_GT((*r)[1].gpu.total, 0.0);
}

// A compositor fed another app's images through HostStereoApp::share composites exactly what one
// fed the same pixels by upload does, frame after frame (history included).
TEST_F(Bench, SharedImagesCompositeAsUploadedOnes) {
    CompositorConfig cc;
    cc.method = Method::Wrs;
    cc.foveation = FoveationMode::Mip;
    auto uploaded = Compositor::create(context(), cc);
    auto shared = Compositor::create(context(), cc);
    auto owner = Compositor::create(context());
    ASSERT_TRUE(uploaded.ok() && shared.ok() && owner.ok());
    HostStereoApp::Options ao;
    ao.width = 80;
    ao.height = 64;
    ao.depth = layers::Format::D32F;
    auto upApp = HostStereoApp::create(**uploaded, ao);
    ao.imageCount = 1;
    auto source = HostStereoApp::create(**owner, ao);
    ASSERT_TRUE(upApp.ok() && source.ok());
    auto sharedApp = HostStereoApp::share(**shared, **source);
    ASSERT_TRUE(sharedApp.ok()) << sharedApp.error().message;
    std::array<EyeSubmission, 2> eyes;
    EXPECT_FALSE((*upApp)->submitShared(1, 0.0, eyes).ok());  // not made by share()
    uint32_t state = 12345;
    for (int f = 0; f < 3; ++f) {
        for (int e = 0; e < 2; ++e) {
            eyes[e].color = HostImage::make(layers::Format::RGBA8_SRGB, ao.width, ao.height);
            for (std::byte& b : eyes[e].color.data) b = std::byte((state = state * 1664525u + 1013904223u) >> 24);
            eyes[e].depth = HostImage::make(layers::Format::D32F, ao.width, ao.height);
            auto* z = reinterpret_cast<float*>(eyes[e].depth->data.data());
            for (uint32_t i = 0; i < ao.width * ao.height; ++i) z[i] = 0.5f + 0.001f * float((i + f) % 7);
            eyes[e].fov = hmdFov(e);
            eyes[e].gaze = {glm::normalize(glm::vec3(0.05f * f, 0.0f, -1.0f)), true, 1.0f};
        }
        ASSERT_TRUE((*upApp)->submit(uint64_t(f + 1), f / 90.0, eyes).ok());
        ASSERT_TRUE((*source)->write(eyes).ok());
        ASSERT_TRUE((*sharedApp)->submitShared(uint64_t(f + 1), f / 90.0, eyes).ok());
        for (uint32_t e = 0; e < 2; ++e) {
            auto a = (*uploaded)->readOutput(e);
            auto b = (*shared)->readOutput(e);
            ASSERT_TRUE(a.ok() && b.ok());
            EXPECT_TRUE(a->data == b->data) << "frame " << f << ", eye " << e;
        }
    }
}

TEST(BenchOptions, RefusesBadSweeps) {
    eval::BenchOptions o;
    o.frames = 5;
    o.warmup = 10;
    auto r = eval::runBench(context(), o);
    ASSERT_FALSE(r.ok());
    EXPECT_NE(r.error().message.find("warm-up"), std::string::npos) << r.error().message;
    o = {};
    o.width = 8;
    r = eval::runBench(context(), o);
    ASSERT_FALSE(r.ok());
}

}  // namespace
}  // namespace wrsfov::test
