#include "gpu_rig.h"

#include <cmath>
#include <cstdio>
#include <cstring>

namespace wrsfov::test {

vk::Context& context() {
    static std::unique_ptr<vk::Context> ctx = [] {
        auto r = vk::Context::create();
        if (!r) {
            std::fprintf(stderr, "no Vulkan device: %s\n", r.error().message.c_str());
            std::abort();
        }
        std::fprintf(stderr, "[wrsfov] device: %s%s\n", (*r)->deviceName().c_str(),
                     (*r)->validationEnabled() ? " (Khronos validation on)" : "");
        return std::move(*r);
    }();
    return *ctx;
}

void GpuTest::SetUp() { errorsBefore_ = context().validationErrors(); }

void GpuTest::TearDown() {
    uint32_t errors = context().validationErrors() - errorsBefore_;
    EXPECT_EQ(errors, 0u) << "Khronos validation reported errors during this test";
}

StereoApp::StereoApp(Compositor& compositor, uint32_t width, uint32_t height, layers::Format colorFormat,
                     std::optional<layers::Format> depthFormat, std::optional<layers::Format> motionFormat)
    : comp_(compositor) {
    HostStereoApp::Options o;
    o.width = width;
    o.height = height;
    o.color = colorFormat;
    o.depth = depthFormat;
    o.motion = motionFormat;
    o.nearZ = nearZ;
    o.farZ = farZ;
    auto app = HostStereoApp::create(compositor, o);
    EXPECT_TRUE(app.ok()) << (app.ok() ? "" : app.error().message);
    if (app.ok()) app_ = std::move(*app);
}

void StereoApp::write(const std::array<EyeFrame, 2>& eyes) {
    Status s = app_->write(eyes);
    ASSERT_TRUE(s.ok()) << s.message();
}

layers::FrameEndInfo StereoApp::frameEnd(uint64_t frameIndex, const std::array<EyeFrame, 2>& eyes, bool reversed) {
    layers::FrameEndInfo f = app_->frameEnd(frameIndex, double(frameIndex) / 90.0, eyes);
    for (auto& v : f.layers[0].views)
        if (v.depth) v.depth->reversedZ = reversed;
    return f;
}

Status StereoApp::submit(uint64_t frameIndex, const std::array<EyeFrame, 2>& eyes, bool reversed) {
    if (Status s = app_->write(eyes); !s) return s;
    return comp_.endFrame(frameEnd(frameIndex, eyes, reversed));
}

std::array<Reference::EyeInput, 2> referenceInputs(const std::array<EyeFrame, 2>& eyes) {
    std::array<Reference::EyeInput, 2> in;
    for (int i = 0; i < 2; ++i) {
        in[i].color = eyes[i].color;
        in[i].depth = eyes[i].depth;
        in[i].motion = eyes[i].motion;
    }
    return in;
}

glm::vec3 gazeAtPixel(double x, double y, uint32_t w, uint32_t h, const layers::Fov& fov) {
    const double l = std::tan(double(fov.angleLeft)), r = std::tan(double(fov.angleRight));
    const double u = std::tan(double(fov.angleUp)), d = std::tan(double(fov.angleDown));
    const double tx = l + (x + 0.5) / w * (r - l), ty = u - (y + 0.5) / h * (u - d);
    return glm::vec3(glm::normalize(glm::dvec3(tx, ty, -1.0)));
}

HostImage fineTexture(uint32_t w, uint32_t h, float sx, float sy, float brightness) {
    HostImage img = HostImage::make(layers::Format::RGBA16F, w, h);
    for (uint32_t y = 0; y < h; ++y)
        for (uint32_t x = 0; x < w; ++x) {
            const float u = float(x) + 0.5f - sx, v = float(y) + 0.5f - sy;
            const float c = 0.5f + 0.35f * std::sin(u * 2.1f) * std::sin(v * 1.7f) + 0.1f * std::sin(u * 0.05f);
            img.store(x, y, glm::vec4(c * brightness, (1.0f - c) * 0.8f * brightness, 0.3f * brightness, 1.0f));
        }
    return img;
}

HostImage uniformMotion(uint32_t w, uint32_t h, float mx, float my) {
    HostImage img = HostImage::make(layers::Format::RG16F, w, h);
    for (uint32_t y = 0; y < h; ++y)
        for (uint32_t x = 0; x < w; ++x) img.store(x, y, glm::vec4(mx, my, 0, 0));
    return img;
}

glm::vec3 gazeDir(float azimuthDeg, float elevationDeg) {
    const float d = 3.14159265f / 180.0f;
    float az = azimuthDeg * d, el = elevationDeg * d;
    return glm::vec3(std::sin(az) * std::cos(el), std::sin(el), -std::cos(az) * std::cos(el));
}

HostImage RandomScene::color(layers::Format f, uint32_t w, uint32_t h) {
    HostImage img = HostImage::make(f, w, h);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    const uint32_t block = 4 + rng() % 12;
    std::vector<glm::vec3> blocks((w / block + 1) * (h / block + 1));
    for (auto& b : blocks) b = glm::vec3(u(rng), u(rng), u(rng));
    for (uint32_t y = 0; y < h; ++y)
        for (uint32_t x = 0; x < w; ++x) {
            glm::vec3 c = blocks[(y / block) * (w / block + 1) + x / block];
            c = glm::clamp(c + 0.15f * glm::vec3(u(rng) - 0.5f, u(rng) - 0.5f, u(rng) - 0.5f), 0.0f, 1.0f);
            img.store(x, y, glm::vec4(c, 1.0f));
        }
    return img;
}

HostImage RandomScene::depth(layers::Format f, uint32_t w, uint32_t h) {
    HostImage img = HostImage::make(f, w, h);
    std::uniform_real_distribution<float> u(0.3f, 0.99f);
    const uint32_t block = 8 + rng() % 16;
    std::vector<float> blocks((w / block + 1) * (h / block + 1));
    for (auto& b : blocks) b = u(rng);
    for (uint32_t y = 0; y < h; ++y)
        for (uint32_t x = 0; x < w; ++x) img.store(x, y, glm::vec4(blocks[(y / block) * (w / block + 1) + x / block]));
    return img;
}

HostImage RandomScene::motion(layers::Format f, uint32_t w, uint32_t h) {
    HostImage img = HostImage::make(f, w, h);
    std::uniform_real_distribution<float> shift(-6.0f, 6.0f), jitter(-0.75f, 0.75f), dz(-0.01f, 0.01f);
    glm::vec2 g(std::round(shift(rng)), shift(rng));
    const uint32_t block = 8 + rng() % 8;
    std::vector<glm::vec3> blocks((w / block + 1) * (h / block + 1));
    for (auto& b : blocks) b = glm::vec3(jitter(rng), jitter(rng), dz(rng));
    for (uint32_t y = 0; y < h; ++y)
        for (uint32_t x = 0; x < w; ++x) {
            glm::vec3 b = blocks[(y / block) * (w / block + 1) + x / block];
            img.store(x, y, glm::vec4(g.x + b.x, g.y + b.y, b.z, 0.0f));
        }
    return img;
}

glm::vec3 RandomScene::gaze(const layers::Fov& fov) {
    std::uniform_real_distribution<float> ux(std::tan(fov.angleLeft) * 0.8f, std::tan(fov.angleRight) * 0.8f);
    std::uniform_real_distribution<float> uy(std::tan(fov.angleDown) * 0.8f, std::tan(fov.angleUp) * 0.8f);
    return glm::normalize(glm::vec3(ux(rng), uy(rng), -1.0f));
}

}  // namespace wrsfov::test

namespace wrsfov::test {

std::vector<std::byte> runBufferKernel(const uint32_t* spirv, size_t spirvBytes, std::span<const std::byte> input,
                                       size_t outputBytes, uint32_t count) {
    vk::Context& ctx = context();
    VkDevice dev = ctx.device();
    auto in = ctx.createBuffer(input.size(), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, true);
    auto out = ctx.createBuffer(outputBytes, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, true);
    EXPECT_TRUE(in.ok() && out.ok());
    std::memcpy(in->mapped(), input.data(), input.size());
    auto setLayout = ctx.createSetLayout({{0, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 1, VK_SHADER_STAGE_COMPUTE_BIT, nullptr},
                                          {1, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 1, VK_SHADER_STAGE_COMPUTE_BIT, nullptr}});
    EXPECT_TRUE(setLayout.ok());
    if (!setLayout) return {};
    const VkDescriptorSetLayout sl = setLayout->get();
    auto layout = ctx.createPipelineLayout(sl, 4, VK_SHADER_STAGE_COMPUTE_BIT);
    auto module = ctx.createShaderModule(spirv, spirvBytes);
    EXPECT_TRUE(layout.ok() && module.ok());
    if (!layout || !module) return {};
    const VkPipelineLayout pl = layout->get();
    VkComputePipelineCreateInfo ci{VK_STRUCTURE_TYPE_COMPUTE_PIPELINE_CREATE_INFO};
    ci.stage.sType = VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO;
    ci.stage.stage = VK_SHADER_STAGE_COMPUTE_BIT;
    ci.stage.module = module->get();
    ci.stage.pName = "main";
    ci.layout = pl;
    VkPipeline p;
    VK_CHECK(vkCreateComputePipelines(dev, VK_NULL_HANDLE, 1, &ci, nullptr, &p));
    vk::Pipeline pipeline(dev, p);
    VkDescriptorPoolSize ps{VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 2};
    VkDescriptorPoolCreateInfo dpci{VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO};
    dpci.maxSets = 1;
    dpci.poolSizeCount = 1;
    dpci.pPoolSizes = &ps;
    VkDescriptorPool dp;
    VK_CHECK(vkCreateDescriptorPool(dev, &dpci, nullptr, &dp));
    vk::DescriptorPool pool(dev, dp);
    VkDescriptorSetAllocateInfo ai{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_ALLOCATE_INFO};
    ai.descriptorPool = dp;
    ai.descriptorSetCount = 1;
    ai.pSetLayouts = &sl;
    VkDescriptorSet set;
    VK_CHECK(vkAllocateDescriptorSets(dev, &ai, &set));
    VkDescriptorBufferInfo bi[2] = {{in->handle(), 0, VK_WHOLE_SIZE}, {out->handle(), 0, VK_WHOLE_SIZE}};
    VkWriteDescriptorSet w[2] = {vk::bufferWrite(set, 0, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, &bi[0]),
                                 vk::bufferWrite(set, 1, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, &bi[1])};
    vkUpdateDescriptorSets(dev, 2, w, 0, nullptr);
    Status s = ctx.submitAndWait([&](VkCommandBuffer cb) {
        vkCmdBindPipeline(cb, VK_PIPELINE_BIND_POINT_COMPUTE, p);
        vkCmdBindDescriptorSets(cb, VK_PIPELINE_BIND_POINT_COMPUTE, pl, 0, 1, &set, 0, nullptr);
        vkCmdPushConstants(cb, pl, VK_SHADER_STAGE_COMPUTE_BIT, 0, 4, &count);
        vkCmdDispatch(cb, (count + 63) / 64, 1, 1);
        vk::memoryBarrier(cb, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_ACCESS_SHADER_WRITE_BIT,
                          VK_PIPELINE_STAGE_HOST_BIT, VK_ACCESS_HOST_READ_BIT);
    });
    EXPECT_TRUE(s.ok()) << s.message();
    std::vector<std::byte> result(outputBytes);
    std::memcpy(result.data(), out->mapped(), outputBytes);
    return result;
}

}  // namespace wrsfov::test
