// Sequence directories from the built-in scenes: the atrium written out reads back bit for bit,
// and the benchmark gives the same metrics on the written sequences as on the scenes themselves.
#include <cmath>
#include <filesystem>
#include <string>

#include <gtest/gtest.h>

#include "../core/gpu_rig.h"
#include "eval/bench.h"
#include "eval/sequence.h"
#include "scenes/atrium.h"

namespace wrsfov::test {
namespace {

namespace fs = std::filesystem;

std::string tempDir(const std::string& name) {
    fs::path p = fs::path(::testing::TempDir()) / ("wrsfov_seqgpu_" + name + "_" + std::to_string(::getpid()));
    fs::remove_all(p);
    return p.string();
}

eval::BenchOptions smallSweep() {
    eval::BenchOptions o;
    o.width = 96;  // at least ~0.65 pixels per degree over the 92° view, where FLIP is defined
    o.height = 64;
    o.frames = 4;
    o.warmup = 1;
    o.heavyEvery = 1;
    o.seed = 3;
    o.methods = {Method::Fov, Method::FovTaa, Method::WrsPaper};
    o.foveas = {5.0f};
    o.modes = {FoveationMode::Mip};
    o.path = scenes::CameraPath::Lateral;
    return o;
}

class SequenceGpu : public GpuTest {};

TEST_F(SequenceGpu, AtriumWrittenOutReadsBackBitExact) {
    const eval::BenchOptions o = smallSweep();
    const std::string dir = tempDir("atrium");
    Status s = eval::writeSceneSequence(context(), eval::SceneKind::Atrium, o, dir);
    ASSERT_TRUE(s.ok()) << s.message();
    auto reader = eval::SequenceReader::open(dir);
    ASSERT_TRUE(reader.ok()) << reader.error().message;
    const eval::SequenceInfo& info = (*reader)->info();
    EXPECT_EQ(info.width, 96u);
    EXPECT_EQ(info.height, 64u);
    EXPECT_EQ(info.frameCount, 4u);
    EXPECT_EQ(info.fps, 90.0);
    EXPECT_EQ(info.color, eval::ColorFile::Png);
    ASSERT_TRUE(info.depth && info.motion);
    EXPECT_EQ(*info.motion, eval::MotionUnits::Pixels);
    EXPECT_TRUE((*reader)->hasGaze());

    // The same frames rendered here, the way an application would.
    scenes::AtriumOptions ao;
    ao.width = o.width;
    ao.height = o.height;
    ao.path = o.path;
    EXPECT_EQ(info.depth->nearZ, ao.nearZ);
    EXPECT_EQ(info.depth->farZ, ao.farZ);
    EXPECT_EQ(info.depth->reversedZ, ao.reversedZ);
    auto comp = Compositor::create(context());
    ASSERT_TRUE(comp.ok());
    HostStereoApp::Options appOpt;
    appOpt.width = ao.width;
    appOpt.height = ao.height;
    appOpt.depth = layers::Format::D32F;
    appOpt.motion = layers::Format::RGBA16F;
    auto app = HostStereoApp::create(**comp, appOpt);
    ASSERT_TRUE(app.ok());
    auto renderer = scenes::AtriumRenderer::create(context(), ao);
    ASSERT_TRUE(renderer.ok()) << renderer.error().message;
    double prevT = 0;
    for (uint32_t f = 0; f < info.frameCount; ++f) {
        const double t = f / 90.0;
        layers::Swapchain* sc[3] = {&(*app)->color(), (*app)->depth(), (*app)->motion()};
        uint32_t idx[3];
        for (int i = 0; i < 3; ++i) {
            idx[i] = *sc[i]->acquire();
            ASSERT_TRUE(sc[i]->wait().ok());
        }
        ASSERT_TRUE((*renderer)->render(t, f == 0 ? t : prevT, *sc[0], idx[0], *sc[1], idx[1], *sc[2], idx[2]).ok());
        prevT = t;
        auto frame = (*reader)->frame(f);
        ASSERT_TRUE(frame.ok()) << frame.error().message;
        for (uint32_t e = 0; e < 2; ++e) {
            const EyeSubmission& got = frame->eyes[e];
            auto color = sc[0]->read(idx[0], e);
            auto depth = sc[1]->read(idx[1], e);
            auto motion = sc[2]->read(idx[2], e);
            ASSERT_TRUE(color.ok() && depth.ok() && motion.ok());
            EXPECT_EQ(got.color.data, *color) << "colour, frame " << f << " eye " << e;
            EXPECT_EQ(got.depth->data, *depth) << "depth, frame " << f << " eye " << e;
            HostImage m = HostImage::make(layers::Format::RGBA16F, ao.width, ao.height);
            m.data = *motion;
            uint32_t differing = 0;
            for (uint32_t y = 0; y < ao.height; ++y)
                for (uint32_t x = 0; x < ao.width; ++x) {
                    glm::vec4 a = m.fetch(x, y), b = got.motion->fetch(x, y);
                    differing += a.x != b.x || a.y != b.y || a.z != b.z;
                }
            EXPECT_EQ(differing, 0u) << "motion, frame " << f << " eye " << e;
            EXPECT_EQ(got.fov.angleLeft, scenes::atriumFov(int(e)).angleLeft);
        }
        for (int i = 0; i < 3; ++i) ASSERT_TRUE(sc[i]->release().ok());
    }
    fs::remove_all(dir);
}

TEST_F(SequenceGpu, BenchOnWrittenSequencesEqualsBenchOnScenes) {
    eval::BenchOptions o = smallSweep();
    for (eval::SceneKind scene : {eval::SceneKind::Atrium, eval::SceneKind::Text}) {
        const std::string dir = tempDir(std::string(eval::toString(scene)));
        Status s = eval::writeSceneSequence(context(), scene, o, dir);
        ASSERT_TRUE(s.ok()) << s.message();
        o.scenes = {scene};
        auto direct = eval::runBench(context(), o);
        ASSERT_TRUE(direct.ok()) << direct.error().message;
        eval::BenchOptions so = o;
        so.scenes = {eval::SceneKind::Sequence};
        so.sequenceDir = dir;
        auto viaFiles = eval::runBench(context(), so);
        ASSERT_TRUE(viaFiles.ok()) << viaFiles.error().message;
        ASSERT_EQ(direct->size(), 3u);
        ASSERT_EQ(viaFiles->size(), 3u);
        for (std::size_t i = 0; i < 3; ++i) {
            const eval::CellResult &a = (*direct)[i], &b = (*viaFiles)[i];
            SCOPED_TRACE(std::string(eval::toString(scene)) + " " + std::string(toString(a.method)));
            EXPECT_EQ(b.scene, eval::SceneKind::Sequence);
            EXPECT_EQ(a.method, b.method);
            EXPECT_EQ(a.frames, b.frames);
            EXPECT_TRUE(std::isfinite(a.flip) && std::isfinite(a.ssim) && std::isfinite(a.nearPsnr));
            EXPECT_EQ(a.psnr, b.psnr);
            EXPECT_EQ(a.nearPsnr, b.nearPsnr);
            EXPECT_EQ(a.ssim, b.ssim);
            EXPECT_EQ(a.flip, b.flip);
            EXPECT_EQ(a.eccMse, b.eccMse);
            EXPECT_EQ(a.temporal, b.temporal);
            EXPECT_EQ(a.shadingFraction, b.shadingFraction);
            EXPECT_EQ(a.trafficBytes, b.trafficBytes);
            EXPECT_TRUE(b.gpu.valid);
        }
        // WRS differs from FOV at all: the comparison above is not between empty results.
        EXPECT_NE((*viaFiles)[0].psnr, (*viaFiles)[2].psnr);
        fs::remove_all(dir);
    }
}

TEST_F(SequenceGpu, BenchRefusesAMismatchedSweep) {
    eval::BenchOptions o = smallSweep();
    const std::string dir = tempDir("mismatch");
    ASSERT_TRUE(eval::writeSceneSequence(context(), eval::SceneKind::Text, o, dir).ok());
    o.scenes = {eval::SceneKind::Sequence};
    o.sequenceDir = dir;
    o.frames = 5;
    auto r = eval::runBench(context(), o);
    ASSERT_FALSE(r.ok());
    EXPECT_NE(r.error().message.find("has 4 frames"), std::string::npos) << r.error().message;
    o.frames = 4;
    o.width = 128;
    r = eval::runBench(context(), o);
    ASSERT_FALSE(r.ok());
    EXPECT_NE(r.error().message.find("is 96x64 per eye"), std::string::npos) << r.error().message;
    o.width = 96;
    o.sequenceDir.clear();
    r = eval::runBench(context(), o);
    ASSERT_FALSE(r.ok());
    EXPECT_NE(r.error().message.find("needs a sequence directory"), std::string::npos) << r.error().message;
    fs::remove_all(dir);
}

}  // namespace
}  // namespace wrsfov::test
