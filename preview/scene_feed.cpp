#include "preview/scene_feed.h"

namespace wrsfov::preview {

namespace {
constexpr SceneKind kScenes[] = {SceneKind::Text, SceneKind::Atrium, SceneKind::Dynamic, SceneKind::Photo};
constexpr double kPhotoFps = 90.0;  // the rate the photo scene's speed is given at
}  // namespace

std::string_view toString(SceneKind s) {
    switch (s) {
        case SceneKind::Text:
            return "text";
        case SceneKind::Atrium:
            return "atrium";
        case SceneKind::Dynamic:
            return "dynamic";
        case SceneKind::Photo:
            return "photo";
    }
    return "?";
}

std::optional<SceneKind> parseScene(std::string_view name) {
    for (SceneKind s : kScenes)
        if (toString(s) == name) return s;
    return std::nullopt;
}

SceneKind nextScene(SceneKind s) {
    switch (s) {
        case SceneKind::Text: return SceneKind::Atrium;
        case SceneKind::Atrium: return SceneKind::Dynamic;
        case SceneKind::Dynamic: return SceneKind::Photo;
        case SceneKind::Photo: return SceneKind::Text;
    }
    return SceneKind::Text;
}

Result<std::unique_ptr<SceneFeed>> SceneFeed::create(vk::Context& ctx, const SceneFeedOptions& o) {
    if (o.width < 32 || o.height < 32) return Error{1, "scene: images must be at least 32x32 per eye"};
    std::unique_ptr<SceneFeed> f(new SceneFeed(o));
    if (o.scene == SceneKind::Text) {
        scenes::TextOptions to;
        to.width = o.width;
        to.height = o.height;
        to.seed = o.seed;
        f->text_ = std::make_unique<scenes::TextScene>(to);
    } else if (o.scene == SceneKind::Photo) {
        scenes::PhotoOptions po;
        po.width = o.width;
        po.height = o.height;
        po.monitor = false;  // the preview's views are an HMD's, as the atrium's
        po.image = o.photoImage;
        po.motion = o.photoMotion;
        po.speed = o.photoSpeed;
        po.frames = 3600;  // 40 s of generated texture before it repeats mirrored
        if (o.photoMotion == scenes::PhotoMotion::Turn) po.frames = 900;
        po.seed = o.seed;
        auto p = scenes::PhotoScene::create(po);
        if (!p) return p.error();
        f->photo_ = std::move(*p);
    } else {
        scenes::AtriumOptions ao;
        ao.width = o.width;
        ao.height = o.height;
        ao.dynamic = o.scene == SceneKind::Dynamic;
        ao.path = o.path;
        auto r = scenes::AtriumRenderer::create(ctx, ao);
        if (!r) return r.error();
        f->atrium_ = std::move(*r);
    }
    return f;
}

layers::Fov SceneFeed::fov(int eye) const {
    if (photo_) return scenes::photoFov(photo_->options(), eye);
    return text_ ? scenes::textFov(text_->options(), eye) : scenes::atriumFov(eye);
}

scenes::TextLayout SceneFeed::textLayout() const { return text_ ? text_->options().layout : scenes::TextLayout{}; }

Result<HostStereoApp*> SceneFeed::app(Compositor& target) {
    auto it = apps_.find(&target);
    if (it != apps_.end()) return it->second.get();
    HostStereoApp::Options a;
    a.width = options_.width;
    a.height = options_.height;
    if (text_) {
        a.depth = layers::Format::R32F;
        a.nearZ = text_->options().nearZ;
        a.farZ = text_->options().farZ;
    } else if (photo_) {
        a.depth = layers::Format::D32F;
        a.motion = layers::Format::RGBA16F;
        a.nearZ = photo_->options().nearZ;
        a.farZ = photo_->options().farZ;
    } else {
        const scenes::AtriumOptions& ao = atrium_->options();
        a.depth = layers::Format::D32F;
        a.motion = layers::Format::RGBA16F;
        a.nearZ = ao.nearZ;
        a.farZ = ao.farZ;
        a.reversedZ = ao.reversedZ;
    }
    auto made = HostStereoApp::create(target, a);
    if (!made) return made.error();
    HostStereoApp* p = made->get();
    apps_[&target] = std::move(*made);
    return p;
}

Status SceneFeed::submit(std::span<Compositor* const> targets, uint64_t frameIndex, double t, double prevT,
                         const std::array<layers::EyeGaze, 2>& gaze) {
    std::array<EyeSubmission, 2> eyes;
    for (int e = 0; e < 2; ++e) {
        eyes[e].fov = fov(e);
        eyes[e].gaze = gaze[e];
        if (text_) {
            eyes[e].color = text_->color(e);
            eyes[e].depth = text_->depth(e);
        }
        if (photo_) {
            HostImage c, d, m;
            if (Status s = photo_->renderAt(t * kPhotoFps, prevT * kPhotoFps, e, c, d, m); !s) return s;
            eyes[e].color = std::move(c);
            eyes[e].depth = std::move(d);
            eyes[e].motion = std::move(m);
        }
    }
    for (Compositor* target : targets) {
        auto a = app(*target);
        if (!a) return a.error();
        HostStereoApp& app = **a;
        if (text_ || photo_) {
            if (Status s = app.submit(frameIndex, t, eyes); !s) return s;
            continue;
        }
        // The atrium renders straight into this target's swapchain images (acquire, wait, render,
        // release), as a Vulkan application would.
        Status s = app.drawInPlace([&](const HostStereoApp::Images& im) {
            return atrium_->render(t, prevT, app.color(), im.color, *app.depth(), im.depth, *app.motion(), im.motion);
        });
        if (!s) return s;
        if (Status e = target->endFrame(app.frameEnd(frameIndex, t, eyes)); !e) return e;
    }
    return {};
}

}  // namespace wrsfov::preview
