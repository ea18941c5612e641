// Compositor::importSwapchain: images someone else made on the device (as an OpenXR runtime's images
// are, seen from an API layer), in an attachment layout between frames, give the same output and
// reservoirs as the compositor's own swapchains, and stay alive after the import is gone. sRGB images
// made without MUTABLE_FORMAT (as Monado 21 makes them, whatever the usage asked) are read through sRGB
// views and give the same bits as the compositor's own, read through UNORM views.
#include "compositor/swapchain_vk.h"
#include "gpu_checks.h"

namespace wrsfov::test {
namespace {

// Param: whether the owner made the sRGB images MUTABLE_FORMAT and says so (SwapchainImageOptions::flags).
class Import : public GpuTest, public ::testing::WithParamInterface<bool> {
protected:
    static constexpr uint32_t W = 48, H = 32;
    // Images as their owner would make them, initialised and moved to `layout`.
    std::vector<vk::Image> ownerImages(VkFormat format, VkImageUsageFlags usage, VkImageCreateFlags flags,
                                       VkImageLayout layout) {
        std::vector<vk::Image> images;
        for (int i = 0; i < 3; ++i) {
            vk::ImageCreateInfo ci;
            ci.format = format;
            ci.width = W;
            ci.height = H;
            ci.layers = 2;
            ci.usage = usage;
            ci.flags = flags;
            auto img = context().createImage(ci);
            EXPECT_TRUE(img.ok());
            images.push_back(std::move(*img));
        }
        Status s = context().submitAndWait([&](VkCommandBuffer cb) {
            for (auto& img : images) vk::layoutTransition(cb, img.handle(), img.aspect(), 2, VK_IMAGE_LAYOUT_UNDEFINED, layout);
        });
        EXPECT_TRUE(s.ok()) << s.message();
        return images;
    }
    static std::vector<VkImage> handles(const std::vector<vk::Image>& images) {
        std::vector<VkImage> h;
        for (auto& i : images) h.push_back(i.handle());
        return h;
    }
};

TEST_P(Import, ImportedImagesCompositeLikeOwnSwapchains) {
    const bool mutableFormat = GetParam();
    CompositorConfig cfg;
    cfg.seed = 9;
    auto own = Compositor::create(context(), cfg);
    auto imp = Compositor::create(context(), cfg);
    ASSERT_TRUE(own.ok() && imp.ok());
    StereoApp app(**own, W, H, layers::Format::RGBA8_SRGB, layers::Format::D32F, std::nullopt);

    const VkImageUsageFlags colorUse = VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_SAMPLED_BIT |
                                       VK_IMAGE_USAGE_TRANSFER_SRC_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT;
    const VkImageUsageFlags depthUse = VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT | VK_IMAGE_USAGE_SAMPLED_BIT |
                                       VK_IMAGE_USAGE_TRANSFER_SRC_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT;
    const VkImageCreateFlags colorFlags = mutableFormat ? VK_IMAGE_CREATE_MUTABLE_FORMAT_BIT : 0;
    auto colorImgs = ownerImages(VK_FORMAT_R8G8B8A8_SRGB, colorUse, colorFlags, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL);
    auto depthImgs = ownerImages(VK_FORMAT_D32_SFLOAT, depthUse, 0, VK_IMAGE_LAYOUT_DEPTH_STENCIL_ATTACHMENT_OPTIMAL);
    layers::SwapchainCreateInfo ci;
    ci.format = layers::Format::RGBA8_SRGB;
    ci.width = W;
    ci.height = H;
    ci.arraySize = 2;
    ci.imageCount = 3;
    SwapchainImageOptions colorOpt, depthOpt;
    colorOpt.restingLayout = VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL;
    colorOpt.flags = colorFlags;
    depthOpt.restingLayout = VK_IMAGE_LAYOUT_DEPTH_STENCIL_ATTACHMENT_OPTIMAL;
    const auto ch = handles(colorImgs), dh = handles(depthImgs);
    auto color = (*imp)->importSwapchain(ci, ch, colorOpt);
    ASSERT_TRUE(color.ok()) << color.error().message;
    // A UNORM view only of an image its owner made MUTABLE_FORMAT (VUID-VkImageViewCreateInfo-image-01019).
    EXPECT_EQ(dynamic_cast<const VulkanSwapchain&>(**color).colorEncoding(),
              mutableFormat ? gpu::WRS_INPUT_SRGB : gpu::WRS_INPUT_SRGB_VIEW);
    EXPECT_EQ(dynamic_cast<const VulkanSwapchain&>(app.color()).colorEncoding(), gpu::WRS_INPUT_SRGB);
    layers::SwapchainCreateInfo di = ci;
    di.usage = layers::Usage::Depth;
    di.format = layers::Format::D32F;
    auto depth = (*imp)->importSwapchain(di, dh, depthOpt);
    ASSERT_TRUE(depth.ok()) << depth.error().message;
    // The image count must match the images given.
    layers::SwapchainCreateInfo two = ci;
    two.imageCount = 2;
    auto bad = (*imp)->importSwapchain(two, ch, colorOpt);
    ASSERT_FALSE(bad.ok());
    EXPECT_EQ(bad.error().code, int(layers::SwapchainError::InvalidCreateInfo));

    RandomScene scene(21);
    for (uint64_t n = 1; n <= 3; ++n) {
        std::array<EyeFrame, 2> eyes;
        for (int e = 0; e < 2; ++e) {
            eyes[e].fov = hmdFov(e);
            eyes[e].color = scene.color(layers::Format::RGBA8_SRGB, W, H);
            eyes[e].depth = scene.depth(layers::Format::D32F, W, H);
            eyes[e].gaze = {scene.gaze(eyes[e].fov), true, 1.0f};
        }
        ASSERT_TRUE(app.submit(n, eyes).ok());
        for (auto* sc : {color->get(), depth->get()}) {
            auto idx = sc->acquire();
            ASSERT_TRUE(idx.ok());
            ASSERT_TRUE(sc->wait().ok());
            for (uint32_t e = 0; e < 2; ++e) {
                const HostImage& img = sc == color->get() ? eyes[e].color : *eyes[e].depth;
                ASSERT_TRUE(sc->write(*idx, e, img.bytes()).ok());
            }
            ASSERT_TRUE(sc->release().ok());
        }
        layers::FrameEndInfo fe = app.frameEnd(n, eyes);
        for (uint32_t e = 0; e < 2; ++e) {
            fe.layers[0].views[e].color.swapchain = color->get();
            fe.layers[0].views[e].depth->subImage.swapchain = depth->get();
        }
        Status s = (*imp)->endFrame(fe);
        ASSERT_TRUE(s.ok()) << s.message();
    }
    expectSameReservoirs(**own, **imp, "imported against owned");
    expectSameOutputs(**own, **imp, "imported against owned");
    // The import is gone; the owner's images are not (and stay in their resting layout).
    const int32_t last = (*color)->lastReleased();
    color->reset();
    depth->reset();
    auto bytes = context().readImageLayer(colorImgs[size_t(last)].handle(), VK_IMAGE_ASPECT_COLOR_BIT, 1, W, H,
                                          size_t(W) * H * 4, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL);
    ASSERT_TRUE(bytes.ok()) << bytes.error().message;
}

INSTANTIATE_TEST_SUITE_P(Owner, Import, ::testing::Values(false, true),
                         [](const ::testing::TestParamInfo<bool>& i) {
                             return i.param ? "MutableFormat" : "AsMonadoMakesThem";
                         });

}  // namespace
}  // namespace wrsfov::test
