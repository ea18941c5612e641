// Composites three frames of a flat grey stereo pair with the compositor-only library and checks
// the output: the grey comes back (sRGB 128 in, 128 out) and the frame used no depth or motion.
#include <wrsfov/compositor/compositor.h>
#include <wrsfov/compositor/host_app.h>

#include <cstdio>

using namespace wrsfov;

int main() {
    auto ctx = vk::Context::create();
    if (!ctx) return std::fprintf(stderr, "%s\n", ctx.error().message.c_str()), 1;
    auto comp = Compositor::create(**ctx);
    if (!comp) return std::fprintf(stderr, "%s\n", comp.error().message.c_str()), 1;
    HostStereoApp::Options o;
    o.width = 64;
    o.height = 48;
    auto app = HostStereoApp::create(**comp, o);
    if (!app) return std::fprintf(stderr, "%s\n", app.error().message.c_str()), 1;
    std::array<EyeSubmission, 2> eyes;
    for (int e = 0; e < 2; ++e) {
        eyes[e].color = HostImage::make(layers::Format::RGBA8_SRGB, o.width, o.height);
        for (auto& b : eyes[e].color.data) b = std::byte{128};
        eyes[e].fov = hmdFov(e);
    }
    for (uint64_t n = 1; n <= 3; ++n)
        if (Status s = (*app)->submit(n, n / 90.0, eyes); !s) return std::fprintf(stderr, "%s\n", s.message().c_str()), 1;
    auto out = (*comp)->readOutput(1);
    if (!out) return std::fprintf(stderr, "%s\n", out.error().message.c_str()), 1;
    for (std::size_t i = 0; i < out->data.size(); i += 4)
        if (out->data[i] != std::byte{128}) return std::fprintf(stderr, "texel %zu is %d, not 128\n", i / 4, int(out->data[i])), 1;
    std::printf("compositor-only consumer: %s, %s, 3 frames, output grey as submitted\n",
                (*ctx)->deviceName().c_str(), std::string(toString((*comp)->config().method)).c_str());
    return (*comp)->stats().usedDepth ? 1 : 0;
}
