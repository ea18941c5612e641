#include "layers/frame.h"

#include <cmath>
#include <string>

namespace wrsfov::layers {

std::string_view toString(SubmitError e) {
    switch (e) {
    case SubmitError::LayerCount: return "LayerCount";
    case SubmitError::MissingEye: return "MissingEye";
    case SubmitError::NullSwapchain: return "NullSwapchain";
    case SubmitError::WrongUsage: return "WrongUsage";
    case SubmitError::UnsupportedFormat: return "UnsupportedFormat";
    case SubmitError::SizeMismatch: return "SizeMismatch";
    case SubmitError::RectOutOfBounds: return "RectOutOfBounds";
    case SubmitError::ArrayIndexOutOfRange: return "ArrayIndexOutOfRange";
    case SubmitError::ImageNotReleased: return "ImageNotReleased";
    case SubmitError::FrameOutOfOrder: return "FrameOutOfOrder";
    case SubmitError::InvalidFov: return "InvalidFov";
    case SubmitError::InvalidDepthRange: return "InvalidDepthRange";
    case SubmitError::InconsistentViews: return "InconsistentViews";
    case SubmitError::ForeignSwapchain: return "ForeignSwapchain";
    case SubmitError::DeviceFailure: return "DeviceFailure";
    case SubmitError::InvalidMotionScale: return "InvalidMotionScale";
    case SubmitError::InvalidSubmission: return "InvalidSubmission";
    }
    return "?";
}

namespace {

Error err(SubmitError code, std::string msg) { return Error{static_cast<int>(code), std::move(msg)}; }

const char* eyeName(std::size_t i) { return i == 0 ? "left" : "right"; }

Status checkFov(const Fov& f, const std::string& where) {
    const float kLimit = 1.5707963f;  // 90°: tan() must stay finite
    float a[4] = {f.angleLeft, f.angleRight, f.angleUp, f.angleDown};
    for (float v : a)
        if (!std::isfinite(v) || std::fabs(v) >= kLimit)
            return err(SubmitError::InvalidFov, where + " field of view has an angle that is not finite or not inside "
                                                        "(-90°, 90°)");
    if (!(f.angleLeft < f.angleRight) || !(f.angleDown < f.angleUp))
        return err(SubmitError::InvalidFov, where + " field of view needs angleLeft < angleRight and angleDown < angleUp");
    return {};
}

Status checkSubImage(const SubImage& s, Usage usage, const std::string& where) {
    if (!s.swapchain) return err(SubmitError::NullSwapchain, where + " has no swapchain");
    const SwapchainCreateInfo& info = s.swapchain->info();
    if (info.usage != usage && !(info.anyUse && isSupported(usage, info.format)))
        return err(SubmitError::WrongUsage, where + " uses a " + std::string(toString(info.usage)) +
                                                " swapchain where a " + std::string(toString(usage)) + " one is needed");
    if (!isSupported(usage, info.format))
        return err(SubmitError::UnsupportedFormat,
                   where + " has format " + std::string(toString(info.format)) + ", not readable as " +
                       std::string(toString(usage)));
    if (s.arrayIndex >= info.arraySize)
        return err(SubmitError::ArrayIndexOutOfRange, where + " uses array layer " + std::to_string(s.arrayIndex) +
                                                          " of a swapchain with " + std::to_string(info.arraySize));
    const Rect& r = s.rect;
    if (r.width == 0 || r.height == 0 || r.x < 0 || r.y < 0 || uint64_t(r.x) + r.width > info.width ||
        uint64_t(r.y) + r.height > info.height)
        return err(SubmitError::RectOutOfBounds, where + " rectangle (" + std::to_string(r.x) + "," +
                                                     std::to_string(r.y) + " " + std::to_string(r.width) + "x" +
                                                     std::to_string(r.height) + ") is empty or outside the " +
                                                     std::to_string(info.width) + "x" + std::to_string(info.height) +
                                                     " image");
    if (s.swapchain->lastReleased() < 0)
        return err(SubmitError::ImageNotReleased, where + " swapchain has no released image");
    if (s.swapchain->busy())
        return err(SubmitError::ImageNotReleased, where + " swapchain still has an acquired image; release it first");
    return {};
}

bool sameSize(const Rect& a, const Rect& b) { return a.width == b.width && a.height == b.height; }

}  // namespace

Status FrameValidator::validate(const FrameEndInfo& frame) const {
    if (!std::isfinite(frame.time_s))
        return err(SubmitError::FrameOutOfOrder, "frame time is not finite");
    if (have_ && frame.frameIndex <= lastIndex_)
        return err(SubmitError::FrameOutOfOrder, "frame index " + std::to_string(frame.frameIndex) +
                                                     " does not follow " + std::to_string(lastIndex_));
    if (have_ && frame.time_s < lastTime_)
        return err(SubmitError::FrameOutOfOrder, "frame time " + std::to_string(frame.time_s) + " s is before " +
                                                     std::to_string(lastTime_) + " s");
    if (frame.layers.size() != 1)
        return err(SubmitError::LayerCount,
                   "expected exactly one projection layer, got " + std::to_string(frame.layers.size()));
    const ProjectionLayer& layer = frame.layers[0];
    if (layer.views.size() != 2)
        return err(SubmitError::MissingEye,
                   "a projection layer needs two views (left, right), got " + std::to_string(layer.views.size()));
    for (std::size_t i = 0; i < 2; ++i) {
        const ProjectionView& v = layer.views[i];
        std::string eye = eyeName(i);
        if (Status s = checkFov(v.fov, eye + " view"); !s) return s;
        if (Status s = checkSubImage(v.color, Usage::Color, eye + " colour"); !s) return s;
        if (v.depth) {
            if (Status s = checkSubImage(v.depth->subImage, Usage::Depth, eye + " depth"); !s) return s;
            if (!sameSize(v.depth->subImage.rect, v.color.rect))
                return err(SubmitError::SizeMismatch, eye + " depth rectangle size differs from its colour");
            const DepthInfo& d = *v.depth;
            bool farOk = std::isinf(d.farZ) ? d.farZ > 0 : std::isfinite(d.farZ) && d.farZ > d.nearZ;
            if (!std::isfinite(d.nearZ) || d.nearZ <= 0 || !farOk)
                return err(SubmitError::InvalidDepthRange, eye + " depth range needs 0 < nearZ < farZ (farZ may be "
                                                                 "+infinity), got near " + std::to_string(d.nearZ) +
                                                                 " far " + std::to_string(d.farZ));
        }
        if (v.motion) {
            if (Status s = checkSubImage(v.motion->subImage, Usage::Motion, eye + " motion"); !s) return s;
            if (!sameSize(v.motion->subImage.rect, v.color.rect))
                return err(SubmitError::SizeMismatch, eye + " motion rectangle size differs from its colour");
            const glm::vec3 k = v.motion->scale;
            if (!std::isfinite(k.x) || !std::isfinite(k.y) || !std::isfinite(k.z))
                return err(SubmitError::InvalidMotionScale, eye + " motion scale must be finite");
        }
    }
    const ProjectionView& l = layer.views[0];
    const ProjectionView& r = layer.views[1];
    if (!sameSize(l.color.rect, r.color.rect))
        return err(SubmitError::SizeMismatch, "left and right views differ in size (" + std::to_string(l.color.rect.width) +
                                                  "x" + std::to_string(l.color.rect.height) + " vs " +
                                                  std::to_string(r.color.rect.width) + "x" +
                                                  std::to_string(r.color.rect.height) + ")");
    if (l.depth.has_value() != r.depth.has_value())
        return err(SubmitError::InconsistentViews, "depth is given for one view only; give it for both or neither");
    if (l.motion.has_value() != r.motion.has_value())
        return err(SubmitError::InconsistentViews, "motion is given for one view only; give it for both or neither");
    return {};
}

void FrameValidator::accept(const FrameEndInfo& frame) {
    have_ = true;
    lastIndex_ = frame.frameIndex;
    lastTime_ = frame.time_s;
}

}  // namespace wrsfov::layers
