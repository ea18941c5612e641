#include "scenes/photo.h"

#include <algorithm>
#include <cmath>
#include <filesystem>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "scenes/atrium.h"
#include "shaders/wrs_common.h"

namespace wrsfov::scenes {

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr int kMargin = 8;         // texels beyond the views' reach: the Lanczos kernel's radius and more
constexpr int kMaxTexture = 8192;  // texels per side of a generated texture

// Zero-mean, unit-variance noise whose amplitude spectrum falls as 1/f (natural images' statistics).
// `stretch` > 1 lengthens its structures along x (wood grain).
cv::Mat oneOverF(int w, int h, cv::RNG& rng, double stretch) {
    const int W = cv::getOptimalDFTSize(w), H = cv::getOptimalDFTSize(h);
    cv::Mat n(H, W, CV_32F);
    rng.fill(n, cv::RNG::NORMAL, 0.0, 1.0);
    cv::Mat f;
    cv::dft(n, f, cv::DFT_COMPLEX_OUTPUT);
    const double fMin = 1.0 / std::max(W, H);
    for (int y = 0; y < H; ++y) {
        auto* row = f.ptr<cv::Vec2f>(y);
        const double fy = double(y <= H / 2 ? y : y - H) / H;
        for (int x = 0; x < W; ++x) {
            const double fx = double(x <= W / 2 ? x : x - W) / W * stretch;
            const double r = std::sqrt(fx * fx + fy * fy);
            row[x] *= float(x == 0 && y == 0 ? 0.0 : 1.0 / std::max(r, fMin));
        }
    }
    cv::Mat out;
    cv::idft(f, out, cv::DFT_REAL_OUTPUT | cv::DFT_SCALE);
    out = out(cv::Rect(0, 0, w, h)).clone();
    cv::Scalar mean, sd;
    cv::meanStdDev(out, mean, sd);
    out = (out - mean[0]) / std::max(sd[0], 1e-12);
    return out;
}

float smooth01(float x) { return 1.0f / (1.0f + std::exp(-x)); }

cv::Mat grass(int w, int h, cv::RNG& rng) {
    // Soil and undergrowth: 1/f noise between dark brown and green, drawn at twice the resolution in
    // 8-bit sRGB (OpenCV's antialiased lines), then averaged down in linear light.
    const int W = 2 * w, H = 2 * h;
    cv::Mat base = oneOverF(w, h, rng, 1.0);
    cv::Mat canvas(H, W, CV_8UC3);
    const cv::Vec3f soil(0.09f, 0.07f, 0.04f), leaf(0.10f, 0.32f, 0.06f);  // linear RGB
    for (int y = 0; y < H; ++y) {
        const float* b = base.ptr<float>(y / 2);
        auto* c = canvas.ptr<cv::Vec3b>(y);
        for (int x = 0; x < W; ++x) {
            const float t = smooth01(1.5f * b[x / 2]), lum = std::exp(0.35f * b[x / 2]);
            const cv::Vec3f lin = (soil * (1.0f - t) + leaf * t) * lum;
            for (int k = 0; k < 3; ++k) c[x][2 - k] = uchar(std::lround(255.0f * gpu::wrs_linear_to_srgb(std::min(lin[k], 1.0f))));
        }
    }
    // Strands: thin curved blades, mostly upright, 1-2 canvas pixels wide (under a pixel to a few),
    // light and dark, some dry.
    const int blades = w * h / 24;
    for (int i = 0; i < blades; ++i) {
        const cv::Point2f root(float(rng.uniform(0.0, double(W))), float(rng.uniform(0.0, double(H) + 60.0)));
        const double len = rng.uniform(16.0, 90.0), lean = rng.gaussian(0.35), bend = rng.gaussian(0.5);
        std::vector<cv::Point> pts;
        for (int k = 0; k <= 6; ++k) {
            const double s = k / 6.0, a = lean + bend * s;
            pts.emplace_back(int(std::lround((root.x + std::sin(a) * len * s) * 16)),
                             int(std::lround((root.y - std::cos(a) * len * s) * 16)));
        }
        const double g = rng.uniform(0.35, 1.0), dry = rng.uniform(0.0, 1.0) < 0.15 ? 1.0 : 0.0;
        const cv::Vec3f lin = dry ? cv::Vec3f(0.55f, 0.45f, 0.18f) * float(g) : cv::Vec3f(0.16f, 0.55f, 0.08f) * float(g);
        cv::Scalar bgr;
        for (int k = 0; k < 3; ++k) bgr[2 - k] = 255.0 * gpu::wrs_linear_to_srgb(lin[k]);
        cv::polylines(canvas, pts, false, bgr, rng.uniform(0.0, 1.0) < 0.7 ? 1 : 2, cv::LINE_AA, 4);
    }
    cv::Mat lin(H, W, CV_32FC3);
    for (int y = 0; y < H; ++y) {
        const auto* c = canvas.ptr<cv::Vec3b>(y);
        auto* l = lin.ptr<cv::Vec3f>(y);
        for (int x = 0; x < W; ++x)
            for (int k = 0; k < 3; ++k) l[x][k] = gpu::wrs_srgb_to_linear(c[x][2 - k] / 255.0f);
    }
    cv::Mat out;
    cv::resize(lin, out, cv::Size(w, h), 0, 0, cv::INTER_AREA);
    return out;
}

cv::Mat wood(int w, int h, cv::RNG& rng) {
    // Grain along x: 1/f noise stretched eightfold, rings whose phase the coarse noise bends, pores.
    cv::Mat grain = oneOverF(w, h, rng, 8.0), bendNoise = oneOverF(w, h, rng, 4.0), pores = oneOverF(w, h, rng, 2.0);
    cv::GaussianBlur(bendNoise, bendNoise, cv::Size(0, 0), 6.0);
    cv::Scalar m, sd;
    cv::meanStdDev(bendNoise, m, sd);
    bendNoise = (bendNoise - m[0]) / std::max(sd[0], 1e-12);
    const cv::Vec3f light(0.55f, 0.33f, 0.15f), dark(0.22f, 0.11f, 0.04f);
    const double period = 11.0;
    cv::Mat out(h, w, CV_32FC3);
    for (int y = 0; y < h; ++y) {
        const float *g = grain.ptr<float>(y), *b = bendNoise.ptr<float>(y), *p = pores.ptr<float>(y);
        auto* o = out.ptr<cv::Vec3f>(y);
        for (int x = 0; x < w; ++x) {
            const double phase = 2.0 * kPi * (y + 9.0 * b[x]) / period;
            const float ring = float(std::pow(0.5 + 0.5 * std::sin(phase), 3.0));
            const float t = std::clamp(0.55f * ring + 0.12f * g[x] + 0.2f, 0.0f, 1.0f);
            const float lum = std::exp(0.08f * p[x]);
            o[x] = (light * (1.0f - t) + dark * t) * lum;
        }
    }
    return out;
}

}  // namespace

std::optional<PhotoMotion> parsePhotoMotion(std::string_view name) {
    if (name == "static") return PhotoMotion::Static;
    if (name == "pan") return PhotoMotion::Pan;
    if (name == "turn") return PhotoMotion::Turn;
    return std::nullopt;
}

std::string_view toString(PhotoMotion m) {
    switch (m) {
        case PhotoMotion::Static: return "static";
        case PhotoMotion::Pan: return "pan";
        case PhotoMotion::Turn: return "turn";
    }
    return "?";
}

Result<cv::Mat> generatePhotoTexture(std::string_view kind, int w, int h, uint32_t seed) {
    if (w < 8 || h < 8 || w > kMaxTexture || h > kMaxTexture)
        return Error{1, "photo: a generated texture must be 8.." + std::to_string(kMaxTexture) + " texels per side, not " +
                            std::to_string(w) + "x" + std::to_string(h)};
    cv::RNG rng(seed);
    cv::Mat t;
    if (kind == "grass") t = grass(w, h, rng);
    else if (kind == "wood") t = wood(w, h, rng);
    else return Error{1, "photo: no generated texture '" + std::string(kind) + "' (grass, wood)"};
    cv::min(cv::max(t, 0.0), 1.0, t);
    return t;
}

layers::Fov photoFov(const PhotoOptions& o, int eye) {
    AtriumOptions a;
    a.monitor = o.monitor;
    a.fovDeg = o.fovDeg;
    return atriumFov(a, eye);
}

PhotoScene::Pose PhotoScene::pose(double frame) const {
    Pose p;
    const double travel = options_.speed * frame / ppt_;  // tangent units at the centre
    if (options_.motion == PhotoMotion::Pan) p.x = travel * options_.distance;
    if (options_.motion == PhotoMotion::Turn) p.yaw = travel;  // d tan / d angle = 1 at the centre
    return p;
}

Result<std::unique_ptr<PhotoScene>> PhotoScene::create(const PhotoOptions& o) {
    if (o.width < 8 || o.height < 8) return Error{1, "photo: the views must be at least 8x8 pixels"};
    if (!(o.distance > 0.0f) || !std::isfinite(o.distance)) return Error{1, "photo: the plane's distance must be positive"};
    if (!std::isfinite(o.speed) || std::abs(o.speed) > 64.0f) return Error{1, "photo: speed must be within ±64 px per frame"};
    if (!(o.imageScale > 0.0f) || o.imageScale > 16.0f) return Error{1, "photo: the image scale must be in (0, 16]"};
    std::unique_ptr<PhotoScene> s(new PhotoScene());
    s->options_ = o;
    const layers::Fov f0 = photoFov(o, 0);
    s->ppt_ = o.width / (std::tan(f0.angleRight) - std::tan(f0.angleLeft));
    const double ppt = s->ppt_;
    if (o.motion == PhotoMotion::Turn) {
        // Every ray of every frame must meet the plane in front: the largest yaw plus the view's widest
        // half-angle stays below 85°.
        const double yawMax = std::abs(double(o.speed)) * o.frames / ppt;
        double half = 0;
        for (int eye = 0; eye < (o.monitor ? 1 : 2); ++eye) {
            const layers::Fov f = photoFov(o, eye);
            half = std::max({half, std::abs(double(f.angleLeft)), std::abs(double(f.angleRight))});
        }
        if (yawMax + half >= 85.0 * kPi / 180.0)
            return Error{1, "photo: a turn of " + std::to_string(yawMax * 180.0 / kPi).substr(0, 5) + "° over " +
                                std::to_string(o.frames) + " frames looks away from the plane"};
    }
    if (o.image == "grass" || o.image == "wood") {
        // The region of the plane any view sees over the frames (corners and edge midpoints of both
        // eyes at the first, middle and last frame), in tangent units, plus the kernel's margin.
        double x0 = 1e30, x1 = -1e30, y0 = 1e30, y1 = -1e30;
        for (double frame : {0.0, 0.5 * o.frames, double(o.frames)})
            for (int eye = 0; eye < (o.monitor ? 1 : 2); ++eye) {
                const layers::Fov f = photoFov(o, eye);
                const double eyeX = o.monitor ? 0.0 : (eye == 0 ? -0.5 : 0.5) * o.ipd;
                const Pose p = s->pose(frame);
                for (double a : {0.0, 0.5, 1.0})
                    for (double b : {0.0, 0.5, 1.0}) {
                        const double tx = std::tan(f.angleLeft) + a * (std::tan(f.angleRight) - std::tan(f.angleLeft));
                        const double ty = std::tan(f.angleDown) + b * (std::tan(f.angleUp) - std::tan(f.angleDown));
                        const double dx = std::cos(p.yaw) * tx - std::sin(p.yaw), dz = -std::sin(p.yaw) * tx - std::cos(p.yaw);
                        if (!(dz < 0.0)) return Error{1, "photo: the turn looks away from the plane"};
                        const double t = o.distance / -dz;
                        const double X = (p.x + eyeX + t * dx) / o.distance, Y = t * ty / o.distance;
                        x0 = std::min(x0, X), x1 = std::max(x1, X), y0 = std::min(y0, Y), y1 = std::max(y1, Y);
                    }
            }
        const int w = int(std::ceil((x1 - x0) * ppt)) + 2 * kMargin, h = int(std::ceil((y1 - y0) * ppt)) + 2 * kMargin;
        auto t = generatePhotoTexture(o.image, w, h, o.seed);
        if (!t) return t.error();
        s->texture_ = std::move(*t);
        s->originX_ = x0 - kMargin / ppt;
        s->originY_ = y1 + kMargin / ppt;
    } else {
        std::error_code ec;
        if (!std::filesystem::is_regular_file(o.image, ec))
            return Error{1, "photo: cannot read an image from " + o.image + " (no such file; a PNG or JPEG file, or grass / wood)"};
        cv::Mat img = cv::imread(o.image, cv::IMREAD_COLOR);
        if (img.empty()) return Error{1, "photo: cannot read an image from " + o.image + " (a PNG or JPEG file, or grass / wood)"};
        cv::Mat lin(img.rows, img.cols, CV_32FC3);
        for (int y = 0; y < img.rows; ++y) {
            const auto* c = img.ptr<cv::Vec3b>(y);
            auto* l = lin.ptr<cv::Vec3f>(y);
            for (int x = 0; x < img.cols; ++x)
                for (int k = 0; k < 3; ++k) l[x][k] = gpu::wrs_srgb_to_linear(c[x][2 - k] / 255.0f);
        }
        if (o.imageScale != 1.0f) {
            // Texels per pixel s: the image shrinks by s (area average) or grows (Lanczos).
            const cv::Size sz(std::max(1, int(std::lround(img.cols / o.imageScale))),
                              std::max(1, int(std::lround(img.rows / o.imageScale))));
            cv::resize(lin, lin, sz, 0, 0, o.imageScale > 1.0f ? cv::INTER_AREA : cv::INTER_LANCZOS4);
            cv::min(cv::max(lin, 0.0), 1.0, lin);
        }
        s->texture_ = lin;
        // Centred on the view at the first frame; repeated mirrored beyond its edges.
        s->originX_ = -0.5 * lin.cols / ppt;
        s->originY_ = 0.5 * lin.rows / ppt;
    }
    return s;
}

Status PhotoScene::render(uint32_t index, int eye, HostImage& color, HostImage& depth, HostImage& motion) const {
    return renderAt(index, index > 0 ? index - 1.0 : 0.0, eye, color, depth, motion);
}

Status PhotoScene::renderAt(double frame, double prevFrame, int eye, HostImage& color, HostImage& depth,
                            HostImage& motion) const {
    return renderViewAt(frame, prevFrame, eye, photoFov(options_, eye), options_.width, options_.height, color, depth,
                        motion);
}

Status PhotoScene::renderViewAt(double frame, double prevFrame, int eye, const layers::Fov& f, uint32_t W,
                                uint32_t H, HostImage& color, HostImage& depth, HostImage& motion) const {
    const PhotoOptions& o = options_;
    if (W == 0 || H == 0) return Error{1, "photo: a view needs a size"};
    const double tl = std::tan(f.angleLeft), tr = std::tan(f.angleRight), tu = std::tan(f.angleUp),
                 td = std::tan(f.angleDown);
    const double eyeX = o.monitor ? 0.0 : (eye == 0 ? -0.5 : 0.5) * o.ipd, D = o.distance;
    const Pose cur = pose(frame), prev = pose(prevFrame);
    cv::Mat mapX(int(H), int(W), CV_32F), mapY(int(H), int(W), CV_32F);
    color = HostImage::make(layers::Format::RGBA8_SRGB, W, H);
    depth = HostImage::make(layers::Format::D32F, W, H);
    motion = HostImage::make(layers::Format::RGBA16F, W, H);
    const double cc = std::cos(cur.yaw), sc = std::sin(cur.yaw), cp = std::cos(prev.yaw), sp = std::sin(prev.yaw);
    for (uint32_t y = 0; y < H; ++y) {
        float* mx = mapX.ptr<float>(int(y));
        float* my = mapY.ptr<float>(int(y));
        const double ty = tu - (y + 0.5) / H * (tu - td);
        for (uint32_t x = 0; x < W; ++x) {
            const double tx = tl + (x + 0.5) / W * (tr - tl);
            // The pixel's ray, turned by the head's yaw, meets the plane z = -D.
            const double dx = cc * tx - sc, dz = -sc * tx - cc;
            if (!(dz < 0.0)) return Error{1, "photo: a pixel's ray misses the plane"};
            const double t = D / -dz;  // view depth: the ray's z in eye space is -1
            const double hx = cur.x + eyeX + t * dx, hy = t * ty;
            mx[x] = float((hx / D - originX_) * ppt_ - 0.5);
            my[x] = float((originY_ - hy / D) * ppt_ - 0.5);
            depth.store(x, y, glm::vec4(gpu::wrs_depth_from_linear(float(t), o.nearZ, o.farZ, false)));
            // Where that point was in the previous frame's view of this eye.
            const double rx = hx - (prev.x + eyeX), ry = hy, rz = -D;
            const double qx = cp * rx - sp * rz, qz = sp * rx + cp * rz;  // R(-yaw) (r)
            const double ptx = qx / -qz, pty = ry / -qz;
            const double px = (ptx - tl) / (tr - tl) * W, py = (tu - pty) / (tu - td) * H;
            motion.store(x, y, glm::vec4(float(px - (x + 0.5)), float(py - (y + 0.5)), float(-qz - t), 0.0f));
        }
    }
    cv::Mat out;
    cv::remap(texture_, out, mapX, mapY, cv::INTER_LANCZOS4, cv::BORDER_REFLECT_101);
    for (uint32_t y = 0; y < H; ++y) {
        const auto* r = out.ptr<cv::Vec3f>(int(y));
        for (uint32_t x = 0; x < W; ++x) {
            const glm::vec3 lin(std::clamp(r[x][0], 0.0f, 1.0f), std::clamp(r[x][1], 0.0f, 1.0f), std::clamp(r[x][2], 0.0f, 1.0f));
            color.store(x, y, glm::vec4(gpu::wrs_linear_to_srgb3(lin), 1.0f));
        }
    }
    return {};
}

}  // namespace wrsfov::scenes
