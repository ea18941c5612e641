#include "layers/frame.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <utility>

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
    case SubmitError::InvalidInset: return "InvalidInset";
    case SubmitError::InvalidSampleOffset: return "InvalidSampleOffset";
    case SubmitError::InvalidRateMap: return "InvalidRateMap";
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

std::string sizeText(uint32_t w, uint32_t h) { return std::to_string(w) + "x" + std::to_string(h); }

// Depth and motion of a view or an inset (`where`: "left", "left inset"), against its colour rectangle.
Status checkDepthMotion(const std::optional<DepthInfo>& depth, const std::optional<MotionInfo>& motion,
                        const Rect& color, const std::string& where) {
    if (depth) {
        if (Status s = checkSubImage(depth->subImage, Usage::Depth, where + " depth"); !s) return s;
        if (!sameSize(depth->subImage.rect, color))
            return err(SubmitError::SizeMismatch, where + " depth rectangle size differs from its colour");
        const DepthInfo& d = *depth;
        bool farOk = std::isinf(d.farZ) ? d.farZ > 0 : std::isfinite(d.farZ) && d.farZ > d.nearZ;
        if (!std::isfinite(d.nearZ) || d.nearZ <= 0 || !farOk)
            return err(SubmitError::InvalidDepthRange, where + " depth range needs 0 < nearZ < farZ (farZ may be "
                                                               "+infinity), got near " + std::to_string(d.nearZ) +
                                                               " far " + std::to_string(d.farZ));
    }
    if (motion) {
        if (Status s = checkSubImage(motion->subImage, Usage::Motion, where + " motion"); !s) return s;
        if (!sameSize(motion->subImage.rect, color))
            return err(SubmitError::SizeMismatch, where + " motion rectangle size differs from its colour");
        const glm::vec3 k = motion->scale;
        if (!std::isfinite(k.x) || !std::isfinite(k.y) || !std::isfinite(k.z))
            return err(SubmitError::InvalidMotionScale, where + " motion scale must be finite");
    }
    return {};
}

// Pixels per tangent unit of an image of `size` over `fov`, per axis.
glm::dvec2 density(const Fov& f, uint32_t w, uint32_t h) {
    return {w / (std::tan(double(f.angleRight)) - std::tan(double(f.angleLeft))),
            h / (std::tan(double(f.angleUp)) - std::tan(double(f.angleDown)))};
}

// A sample offset inside its pixel (`where`: "left view", "left inset").
Status checkSampleOffset(glm::vec2 o, const std::string& where) {
    for (int i = 0; i < 2; ++i) {
        const char* axis = i == 0 ? "x" : "y";
        if (!std::isfinite(o[i]))
            return err(SubmitError::InvalidSampleOffset,
                       where + " sample offset " + axis + " is not finite (" + std::to_string(o[i]) + ")");
        if (o[i] < -0.5f || o[i] > 0.5f)
            return err(SubmitError::InvalidSampleOffset, where + " sample offset " + axis + " = " +
                                                             std::to_string(o[i]) +
                                                             " px is outside its pixel ([-0.5, 0.5])");
    }
    return {};
}

Status checkInset(const ProjectionView& v, const std::string& eye) {
    const InsetView& in = *v.inset;
    const std::string where = eye + " inset";
    if (Status s = checkFov(in.fov, where); !s) return s;
    // Inside the wide view (a few micro-radians of slack for angles that went through tan and atan).
    const float slack = 1e-5f;
    const std::pair<const char*, bool> sides[] = {{"angleLeft", in.fov.angleLeft < v.fov.angleLeft - slack},
                                                  {"angleRight", in.fov.angleRight > v.fov.angleRight + slack},
                                                  {"angleUp", in.fov.angleUp > v.fov.angleUp + slack},
                                                  {"angleDown", in.fov.angleDown < v.fov.angleDown - slack}};
    const float inner[] = {in.fov.angleLeft, in.fov.angleRight, in.fov.angleUp, in.fov.angleDown};
    const float outer[] = {v.fov.angleLeft, v.fov.angleRight, v.fov.angleUp, v.fov.angleDown};
    for (int i = 0; i < 4; ++i)
        if (sides[i].second)
            return err(SubmitError::InvalidInset, where + " field of view " + sides[i].first + " " +
                                                      std::to_string(inner[i]) + " rad is outside its view's " +
                                                      std::to_string(outer[i]) + " rad");
    if (Status s = checkSubImage(in.color, Usage::Color, where + " colour"); !s) return s;
    if (in.depth.has_value() != v.depth.has_value())
        return err(SubmitError::InconsistentViews, where + (in.depth ? " has depth and its view has none"
                                                                     : " has no depth and its view has"));
    if (in.motion.has_value() != v.motion.has_value())
        return err(SubmitError::InconsistentViews, where + (in.motion ? " has motion and its view has none"
                                                                      : " has no motion and its view has"));
    if (in.depth && (in.depth->nearZ != v.depth->nearZ || !(in.depth->farZ == v.depth->farZ) ||
                     in.depth->reversedZ != v.depth->reversedZ))
        return err(SubmitError::InconsistentViews,
                   where + " depth range (near " + std::to_string(in.depth->nearZ) + ", far " +
                       std::to_string(in.depth->farZ) + (in.depth->reversedZ ? ", reversed" : "") +
                       ") differs from its view's (near " + std::to_string(v.depth->nearZ) + ", far " +
                       std::to_string(v.depth->farZ) + (v.depth->reversedZ ? ", reversed" : "") + ")");
    if (Status s = checkDepthMotion(in.depth, in.motion, in.color.rect, where); !s) return s;
    const glm::dvec2 wide = density(v.fov, v.color.rect.width, v.color.rect.height);
    const glm::dvec2 inset = density(in.fov, in.color.rect.width, in.color.rect.height);
    if (inset.x < wide.x * 0.999 || inset.y < wide.y * 0.999)
        return err(SubmitError::InvalidInset, where + " is less dense than its view (" + std::to_string(inset.x) +
                                                  " x " + std::to_string(inset.y) + " against " +
                                                  std::to_string(wide.x) + " x " + std::to_string(wide.y) +
                                                  " pixels per tangent unit)");
    return {};
}

bool powerOfTwoUpTo64(uint32_t v) { return v >= 1 && v <= 64 && (v & (v - 1)) == 0; }

Status checkRateMap(const RateMapInfo& m, const Rect& color, const std::string& eye) {
    const std::string where = eye + " rate map";
    if (!powerOfTwoUpTo64(m.texelWidth) || !powerOfTwoUpTo64(m.texelHeight))
        return err(SubmitError::InvalidRateMap, where + " texel size " + sizeText(m.texelWidth, m.texelHeight) +
                                                    " is not a power of two from 1 to 64 on each axis");
    if (Status s = checkSubImage(m.subImage, Usage::ShadingRate, where); !s) return s;
    const uint32_t needW = (color.width + m.texelWidth - 1) / m.texelWidth;
    const uint32_t needH = (color.height + m.texelHeight - 1) / m.texelHeight;
    if (m.subImage.rect.width != needW || m.subImage.rect.height != needH)
        return err(SubmitError::InvalidRateMap,
                   where + " is " + sizeText(m.subImage.rect.width, m.subImage.rect.height) + " texels; a " +
                       sizeText(color.width, color.height) + " view at " + sizeText(m.texelWidth, m.texelHeight) +
                       " pixels per texel needs " + sizeText(needW, needH));
    return {};
}

constexpr uint32_t kMaxOutput = 16384;

}  // namespace

ProjectionLayer quadLayer(const std::array<ProjectionView, 4>& v, uint32_t outWidth, uint32_t outHeight,
                          bool* dropped) {
    auto sameDepth = [](const ProjectionView& a, const ProjectionView& b) {
        return a.depth->nearZ == b.depth->nearZ && a.depth->farZ == b.depth->farZ && a.depth->reversedZ == b.depth->reversedZ;
    };
    const bool depth = std::all_of(v.begin(), v.end(), [](const auto& x) { return x.depth.has_value(); }) &&
                       sameDepth(v[0], v[2]) && sameDepth(v[1], v[3]);
    const bool motion = std::all_of(v.begin(), v.end(), [](const auto& x) { return x.motion.has_value(); });
    const bool anyDepth = std::any_of(v.begin(), v.end(), [](const auto& x) { return x.depth.has_value(); });
    const bool anyMotion = std::any_of(v.begin(), v.end(), [](const auto& x) { return x.motion.has_value(); });
    if (dropped) *dropped = (anyDepth && !depth) || (anyMotion && !motion);
    ProjectionLayer layer;
    for (uint32_t e = 0; e < 2; ++e) {
        ProjectionView pv = v[e];
        InsetView in{v[e + 2].fov, v[e + 2].color, std::nullopt, std::nullopt, v[e + 2].sampleOffset};
        if (depth)
            in.depth = v[e + 2].depth;
        else
            pv.depth.reset();
        if (motion)
            in.motion = v[e + 2].motion;
        else
            pv.motion.reset();
        pv.inset = in;
        layer.views.push_back(pv);
    }
    layer.outputWidth = std::max(outWidth, layer.views[0].color.rect.width);
    layer.outputHeight = std::max(outHeight, layer.views[0].color.rect.height);
    return layer;
}

SubmittedFoveation submittedFoveation(const ProjectionLayer& layer) {
    if (layer.views.empty()) return SubmittedFoveation::Full;
    if (layer.views[0].inset) return SubmittedFoveation::Quad;
    if (layer.views[0].rateMap) return SubmittedFoveation::Rate;
    return SubmittedFoveation::Full;
}

glm::uvec2 outputSize(const ProjectionLayer& layer) {
    const ProjectionView& v = layer.views.at(0);
    if (!v.inset) return {v.color.rect.width, v.color.rect.height};
    if (layer.outputWidth != 0) return {layer.outputWidth, layer.outputHeight};
    const glm::dvec2 d = density(v.inset->fov, v.inset->color.rect.width, v.inset->color.rect.height);
    const double w = std::round(d.x * (std::tan(double(v.fov.angleRight)) - std::tan(double(v.fov.angleLeft))));
    const double h = std::round(d.y * (std::tan(double(v.fov.angleUp)) - std::tan(double(v.fov.angleDown))));
    return {uint32_t(std::clamp(w, 1.0, double(kMaxOutput))), uint32_t(std::clamp(h, 1.0, double(kMaxOutput)))};
}


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
        if (Status s = checkSampleOffset(v.sampleOffset, eye + " view"); !s) return s;
        if (v.inset)
            if (Status s = checkSampleOffset(v.inset->sampleOffset, eye + " inset"); !s) return s;
        if (Status s = checkSubImage(v.color, Usage::Color, eye + " colour"); !s) return s;
        if (Status s = checkDepthMotion(v.depth, v.motion, v.color.rect, eye); !s) return s;
        if (v.inset) {
            if (v.rateMap)
                return err(SubmitError::InconsistentViews,
                           eye + " view has both an inset and a rate map; submit quad views or a rate map, not both");
            if (Status s = checkInset(v, eye); !s) return s;
        }
        if (v.rateMap)
            if (Status s = checkRateMap(*v.rateMap, v.color.rect, eye); !s) return s;
        if (v.reference) {
            if (Status s = checkSubImage(*v.reference, Usage::Color, eye + " reference"); !s) return s;
            const glm::uvec2 out = outputSize(layer);
            if (v.reference->rect.width != out.x || v.reference->rect.height != out.y)
                return err(SubmitError::SizeMismatch, eye + " reference is " +
                                                          sizeText(v.reference->rect.width, v.reference->rect.height) +
                                                          ", the output " + sizeText(out.x, out.y));
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
    if (l.inset.has_value() != r.inset.has_value())
        return err(SubmitError::InconsistentViews, "an inset is given for one view only; give it for both or neither");
    if (l.rateMap.has_value() != r.rateMap.has_value())
        return err(SubmitError::InconsistentViews, "a rate map is given for one view only; give it for both or neither");
    if ((layer.outputWidth == 0) != (layer.outputHeight == 0))
        return err(SubmitError::SizeMismatch, "output size " + sizeText(layer.outputWidth, layer.outputHeight) +
                                                  ": give both sides or neither");
    if (l.inset) {
        if (layer.outputWidth > kMaxOutput || layer.outputHeight > kMaxOutput)
            return err(SubmitError::InvalidInset, "output size " + sizeText(layer.outputWidth, layer.outputHeight) +
                                                      " is larger than " + sizeText(kMaxOutput, kMaxOutput));
        const glm::uvec2 out = outputSize(layer);
        // The output at least as dense as the wide view: composing never throws a wide pixel away.
        if (out.x < l.color.rect.width || out.y < l.color.rect.height)
            return err(SubmitError::InvalidInset, "output size " + sizeText(out.x, out.y) +
                                                      " is smaller than the wide views (" +
                                                      sizeText(l.color.rect.width, l.color.rect.height) + ")");
    } else if (layer.outputWidth != 0 && (layer.outputWidth != l.color.rect.width || layer.outputHeight != l.color.rect.height)) {
        return err(SubmitError::SizeMismatch, "output size " + sizeText(layer.outputWidth, layer.outputHeight) +
                                                  " differs from the views' " +
                                                  sizeText(l.color.rect.width, l.color.rect.height) +
                                                  " (only quad views are resampled)");
    }
    return {};
}

void FrameValidator::accept(const FrameEndInfo& frame) {
    have_ = true;
    lastIndex_ = frame.frameIndex;
    lastTime_ = frame.time_s;
}

}  // namespace wrsfov::layers
