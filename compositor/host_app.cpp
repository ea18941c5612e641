#include "compositor/host_app.h"

#include <cmath>
#include <vector>

namespace wrsfov {

Result<std::unique_ptr<HostStereoApp>> HostStereoApp::create(Compositor& compositor, const Options& o) {
    std::unique_ptr<HostStereoApp> app(new HostStereoApp(compositor, o));
    auto make = [&](layers::Usage usage, layers::Format format) -> Result<std::unique_ptr<layers::Swapchain>> {
        layers::SwapchainCreateInfo ci;
        ci.usage = usage;
        ci.format = format;
        ci.width = o.width;
        ci.height = o.height;
        ci.arraySize = 2;
        ci.imageCount = o.imageCount;
        return compositor.createSwapchain(ci);
    };
    auto c = make(layers::Usage::Color, o.color);
    if (!c) return c.error();
    app->color_ = std::move(*c);
    if (o.depth) {
        auto d = make(layers::Usage::Depth, *o.depth);
        if (!d) return d.error();
        app->depth_ = std::move(*d);
    }
    if (o.motion) {
        auto m = make(layers::Usage::Motion, *o.motion);
        if (!m) return m.error();
        app->motion_ = std::move(*m);
    }
    return app;
}

Result<std::unique_ptr<HostStereoApp>> HostStereoApp::share(Compositor& compositor, HostStereoApp& source) {
    std::unique_ptr<HostStereoApp> app(new HostStereoApp(compositor, source.options_));
    app->source_ = &source;
    auto import = [&](layers::Swapchain* sc, std::unique_ptr<layers::Swapchain>& mine) -> Status {
        if (!sc) return {};
        std::vector<VkImage> images;
        for (uint32_t i = 0; i < sc->info().imageCount; ++i) images.push_back(sc->image(i));
        auto imported = compositor.importSwapchain(sc->info(), images);
        if (!imported) return imported.error();
        mine = std::move(*imported);
        return {};
    };
    if (Status s = import(source.color_.get(), app->color_); !s) return s.error();
    if (Status s = import(source.depth_.get(), app->depth_); !s) return s.error();
    if (Status s = import(source.motion_.get(), app->motion_); !s) return s.error();
    return app;
}

Status HostStereoApp::drawInPlace(const std::function<Status(const Images&)>& draw) {
    layers::Swapchain* sc[3] = {color_.get(), depth_.get(), motion_.get()};
    uint32_t idx[3] = {0, 0, 0};
    bool acquired[3] = {false, false, false};
    Status s;
    for (int i = 0; i < 3 && s; ++i) {
        if (!sc[i]) continue;
        auto a = sc[i]->acquire();
        if (!a) {
            s = a.error();
            break;
        }
        idx[i] = *a;
        acquired[i] = true;
        s = sc[i]->wait();
    }
    if (s) s = draw(Images{idx[0], idx[1], idx[2]});
    for (int i = 0; i < 3; ++i)
        if (acquired[i]) (void)sc[i]->release();
    return s;
}

Status HostStereoApp::readBack(const Images& im, uint32_t eye, HostImage& color, HostImage* depth, HostImage* motion) {
    struct Part {
        layers::Swapchain* swapchain;
        uint32_t index;
        HostImage* out;
    } parts[3] = {{color_.get(), im.color, &color}, {depth_.get(), im.depth, depth}, {motion_.get(), im.motion, motion}};
    for (const Part& p : parts) {
        if (!p.swapchain || !p.out) continue;
        auto bytes = p.swapchain->read(p.index, eye);
        if (!bytes) return bytes.error();
        const layers::SwapchainCreateInfo& ci = p.swapchain->info();
        *p.out = HostImage::make(ci.format, ci.width, ci.height);
        p.out->data = std::move(*bytes);
    }
    return {};
}

Status HostStereoApp::write(const std::array<EyeSubmission, 2>& eyes) {
    auto put = [&](layers::Swapchain* sc, auto get) -> Status {
        if (!sc) return {};
        auto idx = sc->acquire();
        if (!idx) return idx.error();
        if (Status s = sc->wait(); !s) return s;
        for (uint32_t eye = 0; eye < (options_.monoView ? 1u : 2u); ++eye) {
            const HostImage* img = get(eyes[eye]);
            if (!img) return Error{static_cast<int>(layers::SwapchainError::WriteOutOfRange),
                                   "eye " + std::to_string(eye) + " has no image for a swapchain the app created"};
            if (Status s = sc->write(*idx, eye, img->bytes()); !s) {
                (void)sc->release();
                return s;
            }
        }
        return sc->release();
    };
    if (Status s = put(color_.get(), [](const EyeSubmission& e) { return &e.color; }); !s) return s;
    if (Status s = put(depth_.get(), [](const EyeSubmission& e) { return e.depth ? &*e.depth : nullptr; }); !s)
        return s;
    return put(motion_.get(), [](const EyeSubmission& e) { return e.motion ? &*e.motion : nullptr; });
}

layers::FrameEndInfo HostStereoApp::frameEnd(uint64_t frameIndex, double time_s,
                                             const std::array<EyeSubmission, 2>& eyes) const {
    const uint32_t w = options_.width, h = options_.height;
    layers::FrameEndInfo f;
    f.frameIndex = frameIndex;
    f.time_s = time_s;
    layers::ProjectionLayer layer;
    for (uint32_t eye = 0; eye < 2; ++eye) {
        const uint32_t src = options_.monoView ? 0u : eye;
        layers::ProjectionView v;
        v.fov = eyes[src].fov;
        v.color = {color_.get(), {0, 0, w, h}, src};
        if (depth_)
            v.depth = layers::DepthInfo{{depth_.get(), {0, 0, w, h}, src}, options_.nearZ, options_.farZ,
                                        options_.reversedZ};
        if (motion_) v.motion = layers::MotionInfo{{motion_.get(), {0, 0, w, h}, src}};
        layer.views.push_back(v);
        f.gaze[eye] = eyes[src].gaze;
    }
    f.layers.push_back(std::move(layer));
    return f;
}

Status HostStereoApp::submit(uint64_t frameIndex, double time_s, const std::array<EyeSubmission, 2>& eyes) {
    if (Status s = write(eyes); !s) return s;
    return comp_.endFrame(frameEnd(frameIndex, time_s, eyes));
}

Status HostStereoApp::submitShared(uint64_t frameIndex, double time_s, const std::array<EyeSubmission, 2>& eyes) {
    if (!source_)
        return Error{static_cast<int>(layers::SwapchainError::CallOrder), "submitShared needs an app made by share()"};
    auto mark = [](layers::Swapchain* mine, layers::Swapchain* theirs) -> Status {
        if (!mine) return {};
        if (theirs->lastReleased() < 0)
            return Error{static_cast<int>(layers::SwapchainError::CallOrder), "the source has released no image yet"};
        return mine->releasedElsewhere(uint32_t(theirs->lastReleased()));
    };
    if (Status s = mark(color_.get(), source_->color_.get()); !s) return s;
    if (Status s = mark(depth_.get(), source_->depth_.get()); !s) return s;
    if (Status s = mark(motion_.get(), source_->motion_.get()); !s) return s;
    return comp_.endFrame(frameEnd(frameIndex, time_s, eyes));
}

layers::Fov hmdFov(int eye) {
    const float d = 3.14159265f / 180.0f;
    layers::Fov f;
    f.angleLeft = (eye == 0 ? -50.0f : -42.0f) * d;
    f.angleRight = (eye == 0 ? 42.0f : 50.0f) * d;
    f.angleUp = 45.0f * d;
    f.angleDown = -48.0f * d;
    return f;
}

glm::vec3 pixelDirection(const layers::Fov& fov, uint32_t width, uint32_t height, float x, float y) {
    float tl = std::tan(fov.angleLeft), tr = std::tan(fov.angleRight);
    float tu = std::tan(fov.angleUp), td = std::tan(fov.angleDown);
    float tx = tl + (x + 0.5f) / float(width) * (tr - tl);
    float ty = tu - (y + 0.5f) / float(height) * (tu - td);
    return glm::normalize(glm::vec3(tx, ty, -1.0f));
}

}  // namespace wrsfov
