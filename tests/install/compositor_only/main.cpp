// Composites three frames of a flat grey stereo pair with the compositor-only library through its front
// class (wrsfov/stereo_compositor.h) and checks the output: the grey comes back (sRGB 128 in, 128 out)
// and the frame used no depth or motion.
#include <wrsfov/stereo_compositor.h>

#include <cstdio>

using namespace wrsfov;

int main() {
    auto comp = StereoCompositor::createOnOwnDevice();
    if (!comp) return std::fprintf(stderr, "%s\n", comp.error().message.c_str()), 1;
    constexpr uint32_t kW = 64, kH = 48;
    layers::SwapchainCreateInfo info;
    info.format = layers::Format::RGBA8_SRGB;
    info.width = kW;
    info.height = kH;
    info.arraySize = 2;
    auto color = (*comp)->createSwapchain(info);
    if (!color) return std::fprintf(stderr, "%s\n", color.error().message.c_str()), 1;
    HostImage grey = HostImage::make(layers::Format::RGBA8_SRGB, kW, kH);
    for (auto& b : grey.data) b = std::byte{128};
    for (uint64_t n = 1; n <= 3; ++n) {
        auto index = (*color)->acquire();
        if (!index) return std::fprintf(stderr, "%s\n", index.error().message.c_str()), 1;
        if (Status s = (*color)->wait(); !s) return std::fprintf(stderr, "%s\n", s.message().c_str()), 1;
        for (uint32_t eye = 0; eye < 2; ++eye)
            if (Status s = (*color)->write(*index, eye, grey.bytes()); !s)
                return std::fprintf(stderr, "%s\n", s.message().c_str()), 1;
        if (Status s = (*color)->release(); !s) return std::fprintf(stderr, "%s\n", s.message().c_str()), 1;
        layers::FrameEndInfo frame;
        frame.frameIndex = n;
        frame.time_s = double(n) / 90.0;
        layers::ProjectionLayer layer;
        for (uint32_t eye = 0; eye < 2; ++eye) {
            layers::ProjectionView v;
            v.fov = {-0.8f, 0.8f, 0.7f, -0.7f};
            v.color = {color->get(), {0, 0, kW, kH}, eye};
            layer.views.push_back(v);
        }
        frame.layers.push_back(layer);
        if (Status s = (*comp)->endFrame(frame); !s) return std::fprintf(stderr, "%s\n", s.message().c_str()), 1;
    }
    auto out = (*comp)->readOutput(1);
    if (!out) return std::fprintf(stderr, "%s\n", out.error().message.c_str()), 1;
    for (std::size_t i = 0; i < out->data.size(); i += 4)
        if (out->data[i] != std::byte{128}) return std::fprintf(stderr, "texel %zu is %d, not 128\n", i / 4, int(out->data[i])), 1;
    const FrameReport r = (*comp)->lastFrame();
    std::printf("compositor-only consumer: %s, %s, %u frames, output grey as submitted\n", (*comp)->deviceName().c_str(),
                std::string(toString((*comp)->settings().method)).c_str(), unsigned(r.frameIndex));
    return r.usedDepth || r.usedMotion ? 1 : 0;
}
