// XR_APILAYER_WRSFOV_foveation: the state its API areas share, and the helpers they all use.
#include "openxr_layer/layer_state.h"

namespace wrsfov::xrlayer {

std::mutex g_mutex;
std::map<XrInstance, InstanceState> g_instances;
std::map<XrSession, SessionState> g_sessions;
std::map<XrSwapchain, SwapchainState> g_swapchains;
std::map<XrActionSet, XrInstance> g_actionSets;  // the application's, for the checks of xrCreateAction
std::map<XrSpace, CombinedEye> g_combinedEye;

void logLine(const std::string& s) { std::fprintf(stderr, "[wrsfov-layer] %s\n", s.c_str()); }

bool isQuadExtension(const char* e) {
    return std::strcmp(e, XR_VARJO_QUAD_VIEWS_EXTENSION_NAME) == 0 ||
           std::strcmp(e, XR_VARJO_FOVEATED_RENDERING_EXTENSION_NAME) == 0;
}

void disable(SessionState& s, const std::string& why) {
    if (s.disabled) return;
    s.disabled = true;
    s.why = why;
    logLine("disabled for this session: " + why + " (frames pass through untouched)");
}

/// Waits for the compositor's last frame (its reads of the application's swapchains, its output) and
/// counts its GPU times, which the compositor fills in when it waits.
void waitComposited(SessionState& s) {
    if (!s.comp) return;
    if (Status st = s.comp->waitFrame(); !st) disable(s, st.message());
    if (!s.statsPending) return;
    s.statsPending = false;
    const FrameStats& stats = s.comp->stats();
    if (stats.gpu.valid) s.gpuMs += stats.gpu.total, ++s.gpuFrames;
}

/// Waits for the last copy into the output swapchain.
void waitCopied(SessionState& s) {
    if (!s.copyInFlight) return;
    s.copyInFlight = false;
    const VkResult r = s.ctx->waitSubmission(s.copied.get());
    VkFence f = s.copied.get();
    vkResetFences(s.ctx->device(), 1, &f);
    if (r != VK_SUCCESS) disable(s, std::string("copying the output: ") + vk::resultString(r));
}

/// Everything the layer submitted has finished: before a swapchain it used is destroyed, and at the
/// end of the session.
void settle(SessionState& s) {
    waitComposited(s);
    waitCopied(s);
}

std::optional<layers::Format> colorFormat(int64_t f) {
    switch (f) {
        case VK_FORMAT_R8G8B8A8_SRGB:
            return layers::Format::RGBA8_SRGB;
        case VK_FORMAT_R8G8B8A8_UNORM:
            return layers::Format::RGBA8;
        case VK_FORMAT_R16G16B16A16_SFLOAT:
            return layers::Format::RGBA16F;
        case VK_FORMAT_D32_SFLOAT:
            return layers::Format::D32F;
        default:
            return std::nullopt;  // e.g. BGRA, depth-stencil: passed through
    }
}

}  // namespace wrsfov::xrlayer
