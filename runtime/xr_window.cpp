#include "runtime/xr_window.h"

#define GLFW_INCLUDE_VULKAN
#include <GLFW/glfw3.h>

#include "preview/strip.h"

namespace wrsfov::xr {

namespace {
std::string g_error;
void onError(int code, const char* text) {
    g_error = std::string(text ? text : "unknown") + " (GLFW error " + std::to_string(code) + ")";
}
bool glfwReady() {
    static const bool ok = [] {
        glfwSetErrorCallback(onError);
        return glfwInit() == GLFW_TRUE;
    }();
    return ok;
}
void onResize(GLFWwindow* w, int, int) {
    if (auto* p = static_cast<preview::Presenter*>(glfwGetWindowUserPointer(w))) p->framebufferResized();
}
}  // namespace

Result<std::vector<std::string>> XrWindow::instanceExtensions() {
    if (!glfwReady()) return Error{1, "no display for a window: " + g_error};
    if (glfwVulkanSupported() != GLFW_TRUE) return Error{1, "GLFW finds no Vulkan surface support: " + g_error};
    uint32_t n = 0;
    const char** exts = glfwGetRequiredInstanceExtensions(&n);
    if (!exts) return Error{1, "the Vulkan loader lacks the window-surface extensions: " + g_error};
    return std::vector<std::string>(exts, exts + n);
}

bool XrWindow::canPresent(VkInstance instance, VkPhysicalDevice device, uint32_t queueFamily) {
    return glfwReady() && glfwGetPhysicalDevicePresentationSupport(instance, device, queueFamily) == GLFW_TRUE;
}

Result<std::unique_ptr<XrWindow>> XrWindow::create(vk::Context& ctx, uint32_t eyeWidth, uint32_t eyeHeight,
                                                   const std::string& title) {
    if (!glfwReady()) return Error{1, "no display for a window: " + g_error};
    std::unique_ptr<XrWindow> w(new XrWindow());
    w->eyeWidth_ = eyeWidth;
    w->eyeHeight_ = eyeHeight;
    w->layout_ = preview::makeLayout(preview::View::Stereo, eyeWidth, eyeHeight, 1);
    // Large eyes: a window that fits a desktop (the presenter scales the image to the window).
    const double fit = std::min({1.0, 1600.0 / w->layout_.width, 900.0 / w->layout_.height});
    glfwWindowHint(GLFW_CLIENT_API, GLFW_NO_API);
    w->window_ = glfwCreateWindow(std::max(1, int(w->layout_.width * fit)), std::max(1, int(w->layout_.height * fit)),
                                  title.c_str(), nullptr, nullptr);
    if (!w->window_) return Error{1, "cannot create a window: " + g_error};
    auto p = preview::Presenter::create(ctx, w->window_);
    if (!p) return p.error();
    w->presenter_ = std::move(*p);
    glfwSetWindowUserPointer(w->window_, w->presenter_.get());
    glfwSetFramebufferSizeCallback(w->window_, &onResize);
    return w;
}

XrWindow::~XrWindow() {
    presenter_.reset();
    if (window_) glfwDestroyWindow(window_);
}

Status XrWindow::present(const Compositor& compositor, const std::vector<std::string>& stats) {
    glfwPollEvents();
    const uint32_t lines = preview::stripLinesNeeded(layout_.width, stats);
    if (lines > layout_.stripLines) layout_ = preview::makeLayout(preview::View::Stereo, eyeWidth_, eyeHeight_, lines);
    const cv::Mat strip = preview::drawStrip(layout_, stats);
    preview::ComposeFrame f;
    f.layout = &layout_;
    f.output = &compositor.outputImage();
    f.eyes = preview::eyeOverlays(compositor);
    f.strip = &strip;
    auto r = presenter_->present(f);
    if (!r) return r.error();
    return {};
}

bool XrWindow::closeRequested() const { return glfwWindowShouldClose(window_) == GLFW_TRUE; }

std::optional<std::array<float, 2>> XrWindow::cursor() const {
    double cx = 0, cy = 0;
    glfwGetCursorPos(window_, &cx, &cy);
    int ww = 0, wh = 0, fw = 0, fh = 0;
    glfwGetWindowSize(window_, &ww, &wh);
    glfwGetFramebufferSize(window_, &fw, &fh);
    if (ww <= 0 || wh <= 0) return std::nullopt;
    const preview::Placement& p = presenter_->placement().width
                                      ? presenter_->placement()
                                      : preview::placeInWindow(layout_.width, layout_.height, uint32_t(fw), uint32_t(fh));
    auto hit = preview::hitTest(layout_, p, cx * fw / ww, cy * fh / wh);
    if (!hit) return std::nullopt;
    return std::array<float, 2>{hit->x, hit->y};
}

}  // namespace wrsfov::xr
