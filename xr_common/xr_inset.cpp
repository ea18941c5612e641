#include "xr_common/xr_inset.h"

#include <algorithm>
#include <cmath>

namespace wrsfov::xr {

namespace {

constexpr float kDeg = 3.14159265358979f / 180.0f;

glm::vec4 tangents(const layers::Fov& f) {
    return {std::tan(f.angleLeft), std::tan(f.angleRight), std::tan(f.angleUp), std::tan(f.angleDown)};
}

uint32_t rounded(double v) { return uint32_t(std::max(1.0, std::round(v))); }

}  // namespace

glm::vec2 insetHalfTangent(const layers::Fov& view, float insetDeg) {
    const glm::vec4 t = tangents(view);
    const float h = std::tan(0.5f * insetDeg * kDeg);
    return {std::min(h, 0.5f * (t.y - t.x)), std::min(h, 0.5f * (t.z - t.w))};
}

QuadViewSizes quadViewSizes(const RuntimeConfig& c) {
    QuadViewSizes s;
    s.wide = {rounded(c.width * double(kWideDensity)), rounded(c.height * double(kWideDensity))};
    const glm::vec4 t = tangents(c.fov[0]);
    const glm::vec2 half = insetHalfTangent(c.fov[0], c.insetDeg);
    s.inset = {rounded(2.0 * half.x * c.width / (t.y - t.x)), rounded(2.0 * half.y * c.height / (t.z - t.w))};
    return s;
}

layers::Fov insetFov(const layers::Fov& view, float insetDeg, std::optional<glm::vec3> gaze) {
    const glm::vec4 t = tangents(view);
    const glm::vec2 half = insetHalfTangent(view, insetDeg);
    glm::vec2 c(0.5f * (t.x + t.y), 0.5f * (t.z + t.w));
    if (gaze && std::isfinite(gaze->x) && std::isfinite(gaze->y) && std::isfinite(gaze->z) && gaze->z < -1e-3f)
        c = glm::vec2(gaze->x, gaze->y) / -gaze->z;
    c.x = std::clamp(c.x, t.x + half.x, t.y - half.x);
    c.y = std::clamp(c.y, t.w + half.y, t.z - half.y);
    // The angles clamped too: atan(tan(a)) may round past the view's own angle.
    layers::Fov f;
    f.angleLeft = std::max(view.angleLeft, std::atan(c.x - half.x));
    f.angleRight = std::min(view.angleRight, std::atan(c.x + half.x));
    f.angleUp = std::min(view.angleUp, std::atan(c.y + half.y));
    f.angleDown = std::max(view.angleDown, std::atan(c.y - half.y));
    return f;
}

}  // namespace wrsfov::xr
