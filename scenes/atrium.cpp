#include "scenes/atrium.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <string>
#include <glm/gtc/matrix_transform.hpp>
#include <opencv2/imgproc.hpp>

#include "atrium_frag_spv.h"
#include "atrium_vert_spv.h"
#include "compositor/host_app.h"
#include "shaders/atrium_params.h"

namespace wrsfov::scenes {

namespace {
constexpr float kDeg = 3.14159265358979f / 180.0f;
constexpr double kTwoPi = 6.283185307179586;

Error err(const std::string& m) { return Error{static_cast<int>(layers::SwapchainError::DeviceFailure), m}; }

// Moving box i at time t (the `dynamic` scene).
glm::mat4 movingBox(int i, double t) {
    float x = 3.2f * float(std::sin(kTwoPi * t / 5.0 + 2.1 * i));
    glm::mat4 m = glm::translate(glm::mat4(1.0f), glm::vec3(x, 0.7f + 0.55f * i, -3.5f - 2.5f * i));
    m = glm::rotate(m, float(t * (0.5 + 0.3 * i)), glm::vec3(0, 1, 0));
    return glm::scale(m, glm::vec3(0.9f));
}
constexpr int kMovingBoxes = 3;
}  // namespace

float atriumLight(const AtriumOptions& o, double t) {
    if (!o.dynamic) return 1.0f;
    // The room light dims to 60 % over 0.1 s at t = 1 s and comes back over 0.1 s at t = 2.2 s
    // (and so on every 3 s): a scene change that neither depth nor motion vectors announce.
    const double c = std::fmod(t, 3.0);
    const double down = std::clamp((c - 1.0) / 0.1, 0.0, 1.0), up = std::clamp((c - 2.2) / 0.1, 0.0, 1.0);
    return float(1.0 - 0.4 * (down - up));
}

layers::Fov atriumFov(int eye) { return hmdFov(eye); }

layers::Fov atriumFov(const AtriumOptions& o, int eye) {
    if (o.monitor) return monitorFov();
    if (o.fovDeg > 0.0f) {
        const float h = 0.5f * o.fovDeg * kDeg;
        return layers::Fov{-h, h, h, -h};
    }
    return atriumFov(eye);
}

layers::Fov monitorFov() {
    layers::Fov f;
    f.angleLeft = -38.0f * kDeg;
    f.angleRight = 38.0f * kDeg;
    f.angleUp = 30.0f * kDeg;
    f.angleDown = -30.0f * kDeg;
    return f;
}

std::optional<CameraPath> parseCameraPath(std::string_view name) {
    for (CameraPath p : kCameraPaths)
        if (name == toString(p)) return p;
    return std::nullopt;
}

std::string_view toString(CameraPath path) {
    switch (path) {
        case CameraPath::Static:
            return "static";
        case CameraPath::Lateral:
            return "lateral";
        case CameraPath::Turn:
            return "turn";
        case CameraPath::Yaw30:
            return "yaw30";
        case CameraPath::Yaw60:
            return "yaw60";
        case CameraPath::Yaw120:
            return "yaw120";
        case CameraPath::LookAround:
            return "look-around";
    }
    return "?";
}

namespace {

// The look-around path (CameraPath::LookAround): gaze targets in the world (azimuth left-positive and
// elevation, degrees), one every kLookDwell seconds from kLookStart, cycled; the first holds until then.
struct LookTarget {
    float az, el;
};
constexpr LookTarget kLookTargets[] = {{0, 0}, {30, -4}, {-15, 4}, {25, -6}, {-25, 2}, {5, 6}, {-10, -5}};
constexpr int kLookCount = int(std::size(kLookTargets));
constexpr double kLookStart = 0.2, kLookDwell = 0.6;
constexpr double kHeadShare = 0.85;    // the head turns through this share of each gaze shift
constexpr double kHeadLatency = 0.02;  // the head starts this long after the saccade
constexpr double kEyeRange = 35.0;     // the eye's range in the head, degrees either way

// Minimum-jerk progress 0..1 of a movement over the unit interval.
double minJerk(double u) {
    u = std::clamp(u, 0.0, 1.0);
    return u * u * u * (10.0 + u * (-15.0 + 6.0 * u));
}
// The head's turn for a shift of A degrees: 0.15 s + A / 150 °/s, so a 40° turn takes 0.42 s and
// peaks at 1.875 A / D = 180 °/s (head movements of gaze shifts: Freedman 2008).
double headDuration(double a) { return 0.15 + std::abs(a) / 150.0; }
// Gaze saccade duration on the main sequence (gaze::MainSequence's 2.2 ms a degree + 21 ms).
double saccadeDuration(double a) { return 0.021 + 0.0022 * std::abs(a); }

const LookTarget& lookTarget(long k) { return kLookTargets[k <= 0 ? 0 : 1 + (k - 1) % (kLookCount - 1)]; }

// The index of the last shift at or before t (0: none yet).
long lookShift(double t) { return t < kLookStart ? 0 : 1 + long(std::floor((t - kLookStart) / kLookDwell)); }

// The head's yaw and the gaze's azimuth and elevation in the world at t, degrees.
struct LookState {
    double headYaw, gazeAz, gazeEl;
};
LookState lookState(double t) {
    const long k = lookShift(t);
    const LookTarget &from = lookTarget(k - 1), &to = lookTarget(k);
    if (k == 0) return {kHeadShare * to.az, to.az, to.el};
    const double t0 = kLookStart + double(k - 1) * kLookDwell;
    const double a = double(to.az) - from.az, ha = kHeadShare * a;
    const double gs = minJerk((t - t0) / saccadeDuration(std::hypot(a, double(to.el) - from.el)));
    LookState s;
    s.headYaw = kHeadShare * from.az + ha * minJerk((t - t0 - kHeadLatency) / headDuration(ha));
    s.gazeAz = from.az + a * gs;
    s.gazeEl = from.el + (double(to.el) - from.el) * gs;
    return s;
}

}  // namespace

GazeInHead lookAroundGaze(double t) {
    const LookState s = lookState(t);
    return {float(std::clamp(s.gazeAz - s.headYaw, -kEyeRange, kEyeRange)),
            float(std::clamp(s.gazeEl, -kEyeRange, kEyeRange))};
}

// The turn's peak speed: d/dt of 25° sin(2πt / 6 s) at t = 0.
double headDegPerS(CameraPath path) {
    if (path == CameraPath::LookAround) {
        // The fastest head turn of the cycle: minimum jerk peaks at 1.875 A / D.
        double peak = 0.0;
        for (long k = 1; k <= kLookCount; ++k) {
            const double ha = kHeadShare * std::abs(double(lookTarget(k).az) - lookTarget(k - 1).az);
            peak = std::max(peak, 1.875 * ha / headDuration(ha));
        }
        return peak;
    }
    switch (path) {
        case CameraPath::Turn:
            return 25.0 * kTwoPi / 6.0;
        case CameraPath::Yaw30:
            return 30.0;
        case CameraPath::Yaw60:
            return 60.0;
        case CameraPath::Yaw120:
            return 120.0;
        default:
            return 0.0;
    }
}

HeadPose headPose(CameraPath path, double t) {
    HeadPose h;
    if (path == CameraPath::Lateral) h.position.x = 0.5f * float(std::sin(kTwoPi * t / 4.0));
    if (path == CameraPath::Turn) h.yaw = 25.0f * kDeg * float(std::sin(kTwoPi * t / 6.0));
    if (path == CameraPath::Yaw30 || path == CameraPath::Yaw60 || path == CameraPath::Yaw120)
        h.yaw = float(std::fmod(headDegPerS(path) * t, 360.0)) * kDeg;
    if (path == CameraPath::LookAround) h.yaw = float(lookState(t).headYaw) * kDeg;
    return h;
}

glm::mat4 atriumView(const AtriumOptions& o, int eye, double t) {
    const HeadPose head = headPose(o.path, t);
    glm::mat4 headToWorld =
        glm::rotate(glm::translate(glm::mat4(1.0f), head.position), head.yaw, glm::vec3(0, 1, 0));
    glm::mat4 eyeToWorld = glm::translate(headToWorld, glm::vec3(o.monitor ? 0.0f : (eye == 0 ? -0.5f : 0.5f) * o.ipd, 0.0f, 0.0f));
    return glm::inverse(eyeToWorld);
}

glm::mat4 projection(const layers::Fov& fov, float n, float f, bool reversedZ) {
    const float l = std::tan(fov.angleLeft), r = std::tan(fov.angleRight);
    const float u = std::tan(fov.angleUp), d = std::tan(fov.angleDown);
    glm::mat4 p(0.0f);
    p[0][0] = 2.0f / (r - l);
    p[2][0] = (r + l) / (r - l);
    p[1][1] = -2.0f / (u - d);  // Vulkan clip y points down
    p[2][1] = -(u + d) / (u - d);
    if (reversedZ) {
        p[2][2] = n / (f - n);
        p[3][2] = n * f / (f - n);
    } else {
        p[2][2] = -f / (f - n);
        p[3][2] = -n * f / (f - n);
    }
    p[2][3] = -1.0f;
    return p;
}

Result<std::unique_ptr<AtriumRenderer>> AtriumRenderer::create(vk::Context& ctx, const AtriumOptions& options) {
    if (options.width == 0 || options.height == 0) return err("atrium: size must be positive");
    if (!(options.nearZ > 0 && options.farZ > options.nearZ)) return err("atrium: needs 0 < near < far");
    if (options.materialSamples != 1 && options.materialSamples != 4)
        return err("atrium: material samples must be 1 or 4, not " + std::to_string(options.materialSamples));
    std::unique_ptr<AtriumRenderer> r(new AtriumRenderer(ctx, options));
    if (Status s = r->init(); !s) return s.error();
    return r;
}

AtriumRenderer::~AtriumRenderer() {
    VkDevice dev = ctx_.device();
    vkDeviceWaitIdle(dev);
    for (auto& [k, fb] : framebuffers_) vkDestroyFramebuffer(dev, fb, nullptr);
    for (auto& [k, v] : views_) vkDestroyImageView(dev, v, nullptr);
    if (renderPass_) vkDestroyRenderPass(dev, renderPass_, nullptr);
}

Status AtriumRenderer::init() {
    // ---- geometry: room, columns, posters (static), unit cube (moving boxes)
    std::vector<Vertex> v;
    auto quad = [&](glm::vec3 a, glm::vec3 b, glm::vec3 c, glm::vec3 d, glm::vec2 uvMax, uint32_t mat) {
        glm::vec3 n = glm::normalize(glm::cross(b - a, d - a));
        Vertex q[4] = {{a, n, {0, 0}, mat}, {b, n, {uvMax.x, 0}, mat}, {c, n, uvMax, mat}, {d, n, {0, uvMax.y}, mat}};
        for (int i : {0, 1, 2, 0, 2, 3}) v.push_back(q[i]);
    };
    auto box = [&](glm::vec3 lo, glm::vec3 hi, uint32_t mat, float uvPerMetre) {
        glm::vec3 s = hi - lo;
        glm::vec3 p[8];
        for (int i = 0; i < 8; ++i) p[i] = glm::vec3(i & 1 ? hi.x : lo.x, i & 2 ? hi.y : lo.y, i & 4 ? hi.z : lo.z);
        float k = uvPerMetre;
        quad(p[4], p[5], p[7], p[6], {s.x * k, s.y * k}, mat);  // +z
        quad(p[1], p[0], p[2], p[3], {s.x * k, s.y * k}, mat);  // -z
        quad(p[0], p[4], p[6], p[2], {s.z * k, s.y * k}, mat);  // -x
        quad(p[5], p[1], p[3], p[7], {s.z * k, s.y * k}, mat);  // +x
        quad(p[2], p[6], p[7], p[3], {s.x * k, s.z * k}, mat);  // +y
        quad(p[0], p[1], p[5], p[4], {s.x * k, s.z * k}, mat);  // -y
    };
    const float X = 6.0f, Z0 = 2.0f, Z1 = -14.0f, Y = 4.0f;
    quad({-X, 0, Z0}, {X, 0, Z0}, {X, 0, Z1}, {-X, 0, Z1}, {2 * X / 2, (Z0 - Z1) / 2}, 0);  // floor
    quad({-X, Y, Z1}, {X, Y, Z1}, {X, Y, Z0}, {-X, Y, Z0}, {1, 1}, 5);                      // ceiling
    quad({-X, 0, Z1}, {X, 0, Z1}, {X, Y, Z1}, {-X, Y, Z1}, {2 * X / 4, Y / 4}, 1);          // back wall
    quad({-X, 0, Z0}, {-X, 0, Z1}, {-X, Y, Z1}, {-X, Y, Z0}, {(Z0 - Z1) / 4, Y / 4}, 1);    // left wall
    quad({X, 0, Z1}, {X, 0, Z0}, {X, Y, Z0}, {X, Y, Z1}, {(Z0 - Z1) / 4, Y / 4}, 1);        // right wall
    quad({-X, 0, Z0}, {-X, Y, Z0}, {X, Y, Z0}, {X, 0, Z0}, {2 * X / 4, Y / 4}, 1);          // wall behind
    for (float z : {-3.0f, -6.0f, -9.0f, -12.0f})
        for (float x : {-2.6f, 2.6f}) box({x - 0.3f, 0, z - 0.3f}, {x + 0.3f, Y, z + 0.3f}, 2, 1.0f);
    // Posters: text textures on the walls (uv flipped so that text reads left to right).
    quad({-2.0f, 1.0f, Z1 + 0.01f}, {2.0f, 1.0f, Z1 + 0.01f}, {2.0f, 3.0f, Z1 + 0.01f}, {-2.0f, 3.0f, Z1 + 0.01f},
         {1, 1}, 3);
    quad({-X + 0.01f, 1.0f, -4.0f}, {-X + 0.01f, 1.0f, -8.0f}, {-X + 0.01f, 3.0f, -8.0f}, {-X + 0.01f, 3.0f, -4.0f},
         {1, 1}, 3);
    quad({X - 0.01f, 1.0f, -8.0f}, {X - 0.01f, 1.0f, -4.0f}, {X - 0.01f, 3.0f, -4.0f}, {X - 0.01f, 3.0f, -8.0f}, {1, 1},
         3);
    for (Vertex& q : v)
        if (q.material == 3) q.uv.y = 1.0f - q.uv.y;
    if (options_.thin) {
        // A tube from a to b of radius r: `sides` faces with normals smooth around it (metal, material 6),
        // so its highlight is a thin line that slides along it as the eye moves.
        auto tube = [&](glm::vec3 a, glm::vec3 b, float r, int sides = 6) {
            const glm::vec3 axis = glm::normalize(b - a);
            const glm::vec3 side = glm::normalize(glm::cross(axis, std::abs(axis.y) < 0.9f ? glm::vec3(0, 1, 0)
                                                                                            : glm::vec3(1, 0, 0)));
            const glm::vec3 up = glm::cross(side, axis);
            const float len = glm::length(b - a);
            for (int i = 0; i < sides; ++i) {
                const float a0 = 6.2831853f * float(i) / float(sides), a1 = 6.2831853f * float(i + 1) / float(sides);
                const glm::vec3 n0 = std::cos(a0) * side + std::sin(a0) * up, n1 = std::cos(a1) * side + std::sin(a1) * up;
                const Vertex q[4] = {{a + r * n0, n0, {0, 0}, 6}, {b + r * n0, n0, {len, 0}, 6},
                                     {b + r * n1, n1, {len, 1}, 6}, {a + r * n1, n1, {0, 1}, 6}};
                for (int k : {0, 1, 2, 0, 2, 3}) v.push_back(q[k]);
            }
        };
        // A railing across the room 2.2 m ahead (top rail 5 cm, middle rail 2.4 cm, balusters 1.6 cm every
        // 10 cm) and one along the room on the left, 1.8 m out (balusters every 15 cm).
        tube({-4.5f, 1.0f, -2.2f}, {4.5f, 1.0f, -2.2f}, 0.025f, 8);
        tube({-4.5f, 0.55f, -2.2f}, {4.5f, 0.55f, -2.2f}, 0.012f);
        for (int i = 0; i <= 90; ++i) tube({-4.5f + 0.1f * i, 0.0f, -2.2f}, {-4.5f + 0.1f * i, 1.0f, -2.2f}, 0.008f);
        tube({-1.8f, 1.0f, -3.0f}, {-1.8f, 1.0f, -11.0f}, 0.025f, 8);
        for (int i = 0; i <= 53; ++i) tube({-1.8f, 0.0f, -3.0f - 0.15f * i}, {-1.8f, 1.0f, -3.0f - 0.15f * i}, 0.008f);
        // Cables of 8 mm from wall to wall at five depths, two heights each, and six from the ceiling to the
        // floor at a slant.
        for (float z : {-4.0f, -5.5f, -7.0f, -8.5f, -10.0f})
            for (float y : {2.7f, 3.3f}) tube({-X, y + 0.02f * z, z}, {X, y - 0.03f * z, z + 0.4f}, 0.004f, 4);
        for (int i = 0; i < 6; ++i) {
            const float x = -3.5f + 1.4f * i, z = -3.5f - 1.3f * i;
            tube({x, Y, z}, {x + 0.8f, 0.0f, z - 0.9f}, 0.004f, 4);
        }
        // Foliage: crossed cut-out panels (two quads at right angles, leaves alpha-tested, material 7).
        for (glm::vec3 p : {glm::vec3(1.3f, 0, -4.5f), glm::vec3(-0.9f, 0, -7.5f), glm::vec3(1.0f, 0, -10.5f),
                            glm::vec3(3.8f, 0, -6.0f)}) {
            const float w = 0.7f, h = 2.2f;
            quad(p + glm::vec3(-w, 0, 0), p + glm::vec3(w, 0, 0), p + glm::vec3(w, h, 0), p + glm::vec3(-w, h, 0),
                 {1, 1}, 7);
            quad(p + glm::vec3(0, 0, -w), p + glm::vec3(0, 0, w), p + glm::vec3(0, h, w), p + glm::vec3(0, h, -w),
                 {1, 1}, 7);
        }
    }
    room_ = {0, uint32_t(v.size())};
    box({-0.5f, -0.5f, -0.5f}, {0.5f, 0.5f, 0.5f}, 4, 2.0f);
    cube_ = {room_.count, uint32_t(v.size()) - room_.count};

    auto vb = ctx_.createBuffer(v.size() * sizeof(Vertex), VK_BUFFER_USAGE_VERTEX_BUFFER_BIT, true);
    if (!vb) return vb.error();
    vertices_ = std::move(*vb);
    std::memcpy(vertices_.mapped(), v.data(), v.size() * sizeof(Vertex));
    for (auto& c : cameras_) {
        auto b = ctx_.createBuffer(sizeof(gpu::AtriumCamera), VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT, true);
        if (!b) return b.error();
        c = std::move(*b);
    }

    // ---- poster texture: text drawn with OpenCV, mip chain by area averaging
    const int PW = 1024, PH = 512;
    cv::Mat page(PH, PW, CV_8UC4, cv::Scalar(245, 240, 230, 255));
    const char* words[] = {"reservoir", "foveated", "sample", "weight", "history", "gaze",   "saccade", "vision",
                           "acuity",    "pixel",    "stereo", "render", "compute", "atrium", "column",  "poster"};
    cv::RNG rng(7);
    for (int y = 40; y < PH - 10; y += 34) {
        std::string line;
        while (line.size() < 44) line += std::string(words[rng.uniform(0, 16)]) + " ";
        cv::putText(page, line, cv::Point(20, y), cv::FONT_HERSHEY_SIMPLEX, 0.85, cv::Scalar(20, 20, 30, 255), 2,
                    cv::LINE_AA);
    }
    cv::rectangle(page, cv::Rect(0, 0, PW, PH), cv::Scalar(30, 60, 160, 255), 12);
    std::vector<cv::Mat> mips{page};
    while (mips.back().cols > 1 && mips.back().rows > 1) {
        cv::Mat next;
        cv::resize(mips.back(), next, cv::Size(mips.back().cols / 2, mips.back().rows / 2), 0, 0, cv::INTER_AREA);
        mips.push_back(next);
    }
    vk::ImageCreateInfo pci;
    pci.format = VK_FORMAT_R8G8B8A8_SRGB;  // cv BGRA order is swizzled below in the upload
    pci.width = PW;
    pci.height = PH;
    pci.mipLevels = uint32_t(mips.size());
    pci.usage = VK_IMAGE_USAGE_SAMPLED_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT;
    auto poster = ctx_.createImage(pci);
    if (!poster) return poster.error();
    poster_ = std::move(*poster);
    size_t total = 0;
    for (auto& m : mips) total += m.total() * 4;
    auto staging = ctx_.createBuffer(total, VK_BUFFER_USAGE_TRANSFER_SRC_BIT, true);
    if (!staging) return staging.error();
    std::vector<VkBufferImageCopy> regions;
    size_t off = 0;
    for (uint32_t l = 0; l < mips.size(); ++l) {
        cv::Mat rgba;
        cv::cvtColor(mips[l], rgba, cv::COLOR_BGRA2RGBA);
        std::memcpy(static_cast<char*>(staging->mapped()) + off, rgba.data, rgba.total() * 4);
        VkBufferImageCopy r{};
        r.bufferOffset = off;
        r.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, l, 0, 1};
        r.imageExtent = {uint32_t(rgba.cols), uint32_t(rgba.rows), 1};
        regions.push_back(r);
        off += rgba.total() * 4;
    }
    Status st = ctx_.submitAndWait([&](VkCommandBuffer cb) {
        VkImageMemoryBarrier b{VK_STRUCTURE_TYPE_IMAGE_MEMORY_BARRIER};
        b.dstAccessMask = VK_ACCESS_TRANSFER_WRITE_BIT;
        b.oldLayout = VK_IMAGE_LAYOUT_UNDEFINED;
        b.newLayout = VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL;
        b.srcQueueFamilyIndex = b.dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
        b.image = poster_.handle();
        b.subresourceRange = {VK_IMAGE_ASPECT_COLOR_BIT, 0, uint32_t(mips.size()), 0, 1};
        vkCmdPipelineBarrier(cb, VK_PIPELINE_STAGE_TOP_OF_PIPE_BIT, VK_PIPELINE_STAGE_TRANSFER_BIT, 0, 0, nullptr, 0,
                             nullptr, 1, &b);
        vkCmdCopyBufferToImage(cb, staging->handle(), poster_.handle(), VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL,
                               uint32_t(regions.size()), regions.data());
        b.srcAccessMask = VK_ACCESS_TRANSFER_WRITE_BIT;
        b.dstAccessMask = VK_ACCESS_SHADER_READ_BIT;
        b.oldLayout = VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL;
        b.newLayout = VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL;
        vkCmdPipelineBarrier(cb, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_PIPELINE_STAGE_FRAGMENT_SHADER_BIT, 0, 0, nullptr,
                             0, nullptr, 1, &b);
    });
    if (!st) return st;

    VkDevice dev = ctx_.device();
    VkSamplerCreateInfo sci{VK_STRUCTURE_TYPE_SAMPLER_CREATE_INFO};
    sci.magFilter = sci.minFilter = VK_FILTER_LINEAR;
    sci.mipmapMode = VK_SAMPLER_MIPMAP_MODE_LINEAR;
    sci.addressModeU = sci.addressModeV = sci.addressModeW = VK_SAMPLER_ADDRESS_MODE_CLAMP_TO_EDGE;
    sci.maxLod = float(mips.size());
    VkSampler smp;
    VK_CHECK(vkCreateSampler(dev, &sci, nullptr, &smp));
    sampler_ = vk::Sampler(dev, smp);

    auto setLayout = ctx_.createSetLayout(
        {{0, VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, 1, VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_FRAGMENT_BIT, nullptr},
         {1, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, 1, VK_SHADER_STAGE_FRAGMENT_BIT, nullptr}});
    if (!setLayout) return setLayout.error();
    setLayout_ = std::move(*setLayout);
    const VkDescriptorSetLayout sl = setLayout_.get();
    auto pipelineLayout = ctx_.createPipelineLayout(sl, sizeof(gpu::AtriumDraw), VK_SHADER_STAGE_VERTEX_BIT);
    if (!pipelineLayout) return pipelineLayout.error();
    pipelineLayout_ = std::move(*pipelineLayout);

    VkDescriptorPoolSize ps[2] = {{VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, 2},
                                  {VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, 2}};
    VkDescriptorPoolCreateInfo dpci{VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO};
    dpci.maxSets = 2;
    dpci.poolSizeCount = 2;
    dpci.pPoolSizes = ps;
    VkDescriptorPool dp;
    VK_CHECK(vkCreateDescriptorPool(dev, &dpci, nullptr, &dp));
    pool_ = vk::DescriptorPool(dev, dp);
    VkDescriptorSetLayout layouts[2] = {sl, sl};
    VkDescriptorSetAllocateInfo ai{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_ALLOCATE_INFO};
    ai.descriptorPool = dp;
    ai.descriptorSetCount = 2;
    ai.pSetLayouts = layouts;
    VK_CHECK(vkAllocateDescriptorSets(dev, &ai, sets_));
    for (int e = 0; e < 2; ++e) {
        VkDescriptorBufferInfo bi{cameras_[e].handle(), 0, VK_WHOLE_SIZE};
        VkDescriptorImageInfo ii{sampler_.get(), poster_.layerView(0), VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL};
        VkWriteDescriptorSet w[2] = {vk::bufferWrite(sets_[e], 0, VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, &bi),
                                     vk::imageWrite(sets_[e], 1, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, &ii)};
        vkUpdateDescriptorSets(dev, 2, w, 0, nullptr);
    }
    return {};
}

VkImageView AtriumRenderer::view(VkImage image, VkFormat format, VkImageAspectFlags aspect, uint32_t layer) {
    auto key = std::make_tuple(image, format, layer);
    if (auto it = views_.find(key); it != views_.end()) return it->second;
    VkImageViewCreateInfo vci{VK_STRUCTURE_TYPE_IMAGE_VIEW_CREATE_INFO};
    vci.image = image;
    vci.viewType = VK_IMAGE_VIEW_TYPE_2D;
    vci.format = format;
    vci.subresourceRange = {aspect, 0, 1, layer, 1};
    VkImageView v;
    VK_CHECK(vkCreateImageView(ctx_.device(), &vci, nullptr, &v));
    views_[key] = v;
    return v;
}

VkFramebuffer AtriumRenderer::framebuffer(VkImageView color, VkImageView motion, VkImageView depth, uint32_t width,
                                          uint32_t height) {
    auto key = std::make_tuple(color, motion, depth);
    if (auto it = framebuffers_.find(key); it != framebuffers_.end()) return it->second;
    VkImageView att[3] = {color, motion, depth};
    VkFramebufferCreateInfo fci{VK_STRUCTURE_TYPE_FRAMEBUFFER_CREATE_INFO};
    fci.renderPass = renderPass_;
    fci.attachmentCount = 3;
    fci.pAttachments = att;
    fci.width = width;
    fci.height = height;
    fci.layers = 1;
    VkFramebuffer fb;
    VK_CHECK(vkCreateFramebuffer(ctx_.device(), &fci, nullptr, &fb));
    framebuffers_[key] = fb;
    return fb;
}

Status AtriumRenderer::render(double t, double prevT, layers::Swapchain& color, uint32_t colorIndex,
                              layers::Swapchain& depth, uint32_t depthIndex, layers::Swapchain& motion,
                              uint32_t motionIndex) {
    const auto &ci = color.info(), &di = depth.info(), &mi = motion.info();
    for (const auto* i : {&ci, &di, &mi})
        if (i->width != options_.width || i->height != options_.height)
            return err("atrium: swapchains must be " + std::to_string(options_.width) + "x" +
                       std::to_string(options_.height) + " with 2 array layers");
    return renderViews(t, prevT, {atriumFov(options_, 0), atriumFov(options_, 1)}, color, colorIndex, depth, depthIndex,
                       motion, motionIndex);
}

Status AtriumRenderer::renderViews(double t, double prevT, const std::array<layers::Fov, 2>& fovs,
                                   layers::Swapchain& color, uint32_t colorIndex, layers::Swapchain& depth,
                                   uint32_t depthIndex, layers::Swapchain& motion, uint32_t motionIndex,
                                   float footprint) {
    const auto &ci = color.info(), &di = depth.info(), &mi = motion.info();
    if (ci.usage != layers::Usage::Color || di.usage != layers::Usage::Depth || mi.usage != layers::Usage::Motion)
        return err("atrium: needs a colour, a depth and a motion swapchain");
    if (di.format != layers::Format::D32F || mi.format != layers::Format::RGBA16F)
        return err("atrium: renders depth into D32F and motion into RGBA16F swapchains");
    const uint32_t width = ci.width, height = ci.height;
    for (const auto* i : {&ci, &di, &mi})
        if (i->width != width || i->height != height || i->arraySize < 2)
            return err("atrium: the colour, depth and motion swapchains must be of one size with 2 array layers");
    VkFormat cf = layers::toVkFormat(ci.format);
    VkDevice dev = ctx_.device();
    if (!renderPass_ || cf != colorFormat_) {
        if (renderPass_) return err("atrium: the colour format cannot change between frames");
        colorFormat_ = cf;
        VkAttachmentDescription a[3] = {};
        VkFormat formats[3] = {cf, VK_FORMAT_R16G16B16A16_SFLOAT, VK_FORMAT_D32_SFLOAT};
        for (int i = 0; i < 3; ++i) {
            a[i].format = formats[i];
            a[i].samples = VK_SAMPLE_COUNT_1_BIT;
            a[i].loadOp = VK_ATTACHMENT_LOAD_OP_CLEAR;
            a[i].storeOp = VK_ATTACHMENT_STORE_OP_STORE;
            a[i].stencilLoadOp = VK_ATTACHMENT_LOAD_OP_DONT_CARE;
            a[i].stencilStoreOp = VK_ATTACHMENT_STORE_OP_DONT_CARE;
            a[i].initialLayout = VK_IMAGE_LAYOUT_GENERAL;
            a[i].finalLayout = VK_IMAGE_LAYOUT_GENERAL;
        }
        VkAttachmentReference cr[2] = {{0, VK_IMAGE_LAYOUT_GENERAL}, {1, VK_IMAGE_LAYOUT_GENERAL}};
        VkAttachmentReference dr{2, VK_IMAGE_LAYOUT_GENERAL};
        VkSubpassDescription sp{};
        sp.pipelineBindPoint = VK_PIPELINE_BIND_POINT_GRAPHICS;
        sp.colorAttachmentCount = 2;
        sp.pColorAttachments = cr;
        sp.pDepthStencilAttachment = &dr;
        VkSubpassDependency dep[2] = {};
        dep[0].srcSubpass = VK_SUBPASS_EXTERNAL;
        dep[0].dstSubpass = 0;
        dep[0].srcStageMask = VK_PIPELINE_STAGE_ALL_COMMANDS_BIT;
        dep[0].dstStageMask =
            VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT | VK_PIPELINE_STAGE_EARLY_FRAGMENT_TESTS_BIT;
        dep[0].srcAccessMask = VK_ACCESS_MEMORY_READ_BIT | VK_ACCESS_MEMORY_WRITE_BIT;
        dep[0].dstAccessMask = VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT | VK_ACCESS_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT;
        dep[1].srcSubpass = 0;
        dep[1].dstSubpass = VK_SUBPASS_EXTERNAL;
        dep[1].srcStageMask = VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT | VK_PIPELINE_STAGE_LATE_FRAGMENT_TESTS_BIT;
        dep[1].dstStageMask = VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_TRANSFER_BIT;
        dep[1].srcAccessMask = VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT | VK_ACCESS_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT;
        dep[1].dstAccessMask = VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_TRANSFER_READ_BIT;
        VkRenderPassCreateInfo rpci{VK_STRUCTURE_TYPE_RENDER_PASS_CREATE_INFO};
        rpci.attachmentCount = 3;
        rpci.pAttachments = a;
        rpci.subpassCount = 1;
        rpci.pSubpasses = &sp;
        rpci.dependencyCount = 2;
        rpci.pDependencies = dep;
        VK_CHECK(vkCreateRenderPass(dev, &rpci, nullptr, &renderPass_));

        auto vs = ctx_.createShaderModule(atrium_vert_spv, sizeof(atrium_vert_spv));
        if (!vs) return vs.error();
        auto fs = ctx_.createShaderModule(atrium_frag_spv, sizeof(atrium_frag_spv));
        if (!fs) return fs.error();
        VkPipelineShaderStageCreateInfo stages[2] = {};
        stages[0].sType = stages[1].sType = VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO;
        stages[0].stage = VK_SHADER_STAGE_VERTEX_BIT;
        stages[0].module = vs->get();
        stages[0].pName = "main";
        stages[1].stage = VK_SHADER_STAGE_FRAGMENT_BIT;
        stages[1].module = fs->get();
        stages[1].pName = "main";
        VkVertexInputBindingDescription vb{0, sizeof(Vertex), VK_VERTEX_INPUT_RATE_VERTEX};
        VkVertexInputAttributeDescription va[4] = {{0, 0, VK_FORMAT_R32G32B32_SFLOAT, offsetof(Vertex, pos)},
                                                   {1, 0, VK_FORMAT_R32G32B32_SFLOAT, offsetof(Vertex, normal)},
                                                   {2, 0, VK_FORMAT_R32G32_SFLOAT, offsetof(Vertex, uv)},
                                                   {3, 0, VK_FORMAT_R32_UINT, offsetof(Vertex, material)}};
        VkPipelineVertexInputStateCreateInfo vi{VK_STRUCTURE_TYPE_PIPELINE_VERTEX_INPUT_STATE_CREATE_INFO};
        vi.vertexBindingDescriptionCount = 1;
        vi.pVertexBindingDescriptions = &vb;
        vi.vertexAttributeDescriptionCount = 4;
        vi.pVertexAttributeDescriptions = va;
        VkPipelineInputAssemblyStateCreateInfo ia{VK_STRUCTURE_TYPE_PIPELINE_INPUT_ASSEMBLY_STATE_CREATE_INFO};
        ia.topology = VK_PRIMITIVE_TOPOLOGY_TRIANGLE_LIST;
        VkPipelineViewportStateCreateInfo vp{VK_STRUCTURE_TYPE_PIPELINE_VIEWPORT_STATE_CREATE_INFO};
        vp.viewportCount = 1;
        vp.scissorCount = 1;
        VkPipelineRasterizationStateCreateInfo rs{VK_STRUCTURE_TYPE_PIPELINE_RASTERIZATION_STATE_CREATE_INFO};
        rs.polygonMode = VK_POLYGON_MODE_FILL;
        rs.cullMode = VK_CULL_MODE_NONE;
        rs.lineWidth = 1.0f;
        VkPipelineMultisampleStateCreateInfo ms{VK_STRUCTURE_TYPE_PIPELINE_MULTISAMPLE_STATE_CREATE_INFO};
        ms.rasterizationSamples = VK_SAMPLE_COUNT_1_BIT;
        VkPipelineDepthStencilStateCreateInfo ds{VK_STRUCTURE_TYPE_PIPELINE_DEPTH_STENCIL_STATE_CREATE_INFO};
        ds.depthTestEnable = VK_TRUE;
        ds.depthWriteEnable = VK_TRUE;
        ds.depthCompareOp = options_.reversedZ ? VK_COMPARE_OP_GREATER : VK_COMPARE_OP_LESS;
        VkPipelineColorBlendAttachmentState cb[2] = {};
        cb[0].colorWriteMask = cb[1].colorWriteMask = 0xf;
        VkPipelineColorBlendStateCreateInfo cbs{VK_STRUCTURE_TYPE_PIPELINE_COLOR_BLEND_STATE_CREATE_INFO};
        cbs.attachmentCount = 2;
        cbs.pAttachments = cb;
        VkDynamicState dyn[2] = {VK_DYNAMIC_STATE_VIEWPORT, VK_DYNAMIC_STATE_SCISSOR};
        VkPipelineDynamicStateCreateInfo dys{VK_STRUCTURE_TYPE_PIPELINE_DYNAMIC_STATE_CREATE_INFO};
        dys.dynamicStateCount = 2;
        dys.pDynamicStates = dyn;
        VkGraphicsPipelineCreateInfo gp{VK_STRUCTURE_TYPE_GRAPHICS_PIPELINE_CREATE_INFO};
        gp.stageCount = 2;
        gp.pStages = stages;
        gp.pVertexInputState = &vi;
        gp.pInputAssemblyState = &ia;
        gp.pViewportState = &vp;
        gp.pRasterizationState = &rs;
        gp.pMultisampleState = &ms;
        gp.pDepthStencilState = &ds;
        gp.pColorBlendState = &cbs;
        gp.pDynamicState = &dys;
        gp.layout = pipelineLayout_.get();
        gp.renderPass = renderPass_;
        VkPipeline p;
        VK_CHECK(vkCreateGraphicsPipelines(dev, VK_NULL_HANDLE, 1, &gp, nullptr, &p));
        pipeline_ = vk::Pipeline(dev, p);
    }

    const float W = float(width), H = float(height);
    for (int e = 0; e < 2; ++e) {
        glm::mat4 proj = projection(fovs[e], options_.nearZ, options_.farZ, options_.reversedZ);
        gpu::AtriumCamera cam{};
        cam.view = atriumView(options_, e, t);
        cam.prev_view = atriumView(options_, e, prevT);
        cam.view_proj = proj * cam.view;
        cam.prev_view_proj = proj * cam.prev_view;
        cam.viewport = glm::vec4(W, H, options_.nearZ, options_.farZ);
        cam.eye_pos = glm::vec4(glm::vec3(glm::inverse(cam.view)[3]), options_.reversedZ ? 1.0f : 0.0f);
        cam.light = glm::vec4(atriumLight(options_, t), float(options_.materialSamples),
                              std::isfinite(footprint) && footprint > 0.0f ? std::min(footprint, 1.0f) : 1.0f,
                              options_.thin ? 1.0f : 0.0f);
        std::memcpy(cameras_[e].mapped(), &cam, sizeof(cam));
    }
    VkFormat colorViewFormat = cf;
    const bool timing = ctx_.timestampPeriodNs() > 0;
    if (timing && !queries_) {
        VkQueryPoolCreateInfo qci{VK_STRUCTURE_TYPE_QUERY_POOL_CREATE_INFO};
        qci.queryType = VK_QUERY_TYPE_TIMESTAMP;
        qci.queryCount = 2;
        VkQueryPool qp;
        VK_CHECK(vkCreateQueryPool(dev, &qci, nullptr, &qp));
        queries_ = vk::QueryPool(dev, qp);
    }
    lastGpuMs_ = std::numeric_limits<double>::quiet_NaN();
    Status s = ctx_.submitAndWait([&](VkCommandBuffer cb) {
        if (timing) {
            vkCmdResetQueryPool(cb, queries_.get(), 0, 2);
            vkCmdWriteTimestamp(cb, VK_PIPELINE_STAGE_TOP_OF_PIPE_BIT, queries_.get(), 0);
        }
        for (uint32_t e = 0; e < 2; ++e) {
            VkImageView cv = view(color.image(colorIndex), colorViewFormat, VK_IMAGE_ASPECT_COLOR_BIT, e);
            VkImageView mv =
                view(motion.image(motionIndex), VK_FORMAT_R16G16B16A16_SFLOAT, VK_IMAGE_ASPECT_COLOR_BIT, e);
            VkImageView dv = view(depth.image(depthIndex), VK_FORMAT_D32_SFLOAT, VK_IMAGE_ASPECT_DEPTH_BIT, e);
            VkClearValue clear[3] = {};
            clear[0].color = {{0.02f, 0.02f, 0.03f, 1.0f}};
            clear[1].color = {{0.0f, 0.0f, 0.0f, 0.0f}};
            clear[2].depthStencil = {options_.reversedZ ? 0.0f : 1.0f, 0};
            VkRenderPassBeginInfo rb{VK_STRUCTURE_TYPE_RENDER_PASS_BEGIN_INFO};
            rb.renderPass = renderPass_;
            rb.framebuffer = framebuffer(cv, mv, dv, width, height);
            rb.renderArea = {{0, 0}, {width, height}};
            rb.clearValueCount = 3;
            rb.pClearValues = clear;
            vkCmdBeginRenderPass(cb, &rb, VK_SUBPASS_CONTENTS_INLINE);
            vkCmdBindPipeline(cb, VK_PIPELINE_BIND_POINT_GRAPHICS, pipeline_.get());
            VkViewport viewport{0, 0, W, H, 0.0f, 1.0f};
            VkRect2D scissor{{0, 0}, {width, height}};
            vkCmdSetViewport(cb, 0, 1, &viewport);
            vkCmdSetScissor(cb, 0, 1, &scissor);
            vkCmdBindDescriptorSets(cb, VK_PIPELINE_BIND_POINT_GRAPHICS, pipelineLayout_.get(), 0, 1, &sets_[e], 0,
                                    nullptr);
            VkDeviceSize zero = 0;
            VkBuffer vbuf = vertices_.handle();
            vkCmdBindVertexBuffers(cb, 0, 1, &vbuf, &zero);
            gpu::AtriumDraw d{glm::mat4(1.0f), glm::mat4(1.0f)};
            vkCmdPushConstants(cb, pipelineLayout_.get(), VK_SHADER_STAGE_VERTEX_BIT, 0, sizeof(d), &d);
            vkCmdDraw(cb, room_.count, 1, room_.first, 0);
            if (options_.dynamic) {
                for (int i = 0; i < kMovingBoxes; ++i) {
                    d.model = movingBox(i, t);
                    d.prev_model = movingBox(i, prevT);
                    vkCmdPushConstants(cb, pipelineLayout_.get(), VK_SHADER_STAGE_VERTEX_BIT, 0, sizeof(d), &d);
                    vkCmdDraw(cb, cube_.count, 1, cube_.first, 0);
                }
            }
            vkCmdEndRenderPass(cb);
        }
        if (timing) vkCmdWriteTimestamp(cb, VK_PIPELINE_STAGE_BOTTOM_OF_PIPE_BIT, queries_.get(), 1);
    });
    uint64_t ts[2] = {};
    if (s && timing &&
        vkGetQueryPoolResults(dev, queries_.get(), 0, 2, sizeof(ts), ts, sizeof(uint64_t), VK_QUERY_RESULT_64_BIT) ==
            VK_SUCCESS &&
        ts[1] >= ts[0])
        lastGpuMs_ = double(ts[1] - ts[0]) * ctx_.timestampPeriodNs() * 1e-6;
    return s;
}

}  // namespace wrsfov::scenes
