// Quad layers drawn over the compositor's output (internal to runtime/): one compute dispatch per
// quad and eye on the application's device, blending in linear colour (runtime/shaders/quad.comp).
#pragma once

#include <vector>

#include <glm/glm.hpp>

#include "compositor/compositor.h"
#include "compositor/swapchain_vk.h"

namespace wrsfov::xr {

struct QuadDraw {
    uint32_t eye = 0;
    glm::mat4 quadFromEye{1.0f};  // eye space -> quad space (quad in z = 0, centred, x right, y up)
    glm::vec4 fovTan{0.0f};       // the eye's view, XrFovf tangents
    glm::vec4 uvRect{0, 0, 1, 1};  // sub-image in the quad's image: uv offset, uv scale
    glm::vec2 size{1.0f};         // metres
    bool blendAlpha = false, unpremultiplied = false;
    const VulkanSwapchain* swapchain = nullptr;
    uint32_t arrayIndex = 0;
};

class QuadPass {
public:
    static Result<std::unique_ptr<QuadPass>> create(vk::Context& ctx);
    ~QuadPass();
    /// Draws `quads` in order over `compositor`'s output image, in one submission after the
    /// compositor's on the same queue; returns without waiting for it (the next draw, or the
    /// destructor, does). Its writes are visible to all later work on the queue.
    Status draw(Compositor& compositor, const std::vector<QuadDraw>& quads);

private:
    explicit QuadPass(vk::Context& ctx) : ctx_(ctx) {}
    /// The last draw's submission is complete (its command buffer and descriptor sets are free).
    void waitIdle();
    vk::Context& ctx_;
    VkCommandBuffer cb_ = VK_NULL_HANDLE;
    vk::Fence fence_;
    bool pending_ = false;
    vk::DescriptorSetLayout setLayout_;
    vk::PipelineLayout pipelineLayout_;
    vk::DescriptorPool pool_;
    vk::Sampler sampler_;
    vk::ShaderModule module_;
    vk::Pipeline pipeline_;
};

}  // namespace wrsfov::xr
