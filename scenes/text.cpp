#include "scenes/text.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <memory>

#include <opencv2/freetype.hpp>
#include <opencv2/imgproc.hpp>

#include "scenes/atrium.h"
#include "shaders/wrs_common.h"

namespace wrsfov::scenes {

namespace {
constexpr double kDeg = 3.14159265358979 / 180.0;
const char* kFont = "/usr/share/fonts/truetype/dejavu/DejaVuSansMono.ttf";
// Horizontal / vertical extent of the page texture, as tangents from the cyclopean eye (±60°, ±55°).
constexpr double kTanX = 1.7320508, kTanY = 1.4281480;

const char* kWords[] = {"the", "reservoir", "keeps", "samples", "that", "were", "seen", "sharply", "while", "gaze",
                        "moves", "across", "a", "line", "of", "text", "and", "every", "pixel", "weighs", "what",
                        "it", "saw", "before", "reading", "fovea", "periphery", "detail", "frame", "history",
                        "quality", "words", "light", "page", "eye", "view"};
}  // namespace

layers::Fov textFov(const TextOptions& o, int eye) {
    return o.monitor ? monitorFov() : atriumFov(eye);
}

TextScene::TextScene(const TextOptions& o) : options_(o) {
    // Texture density: at least twice the eye's density at the centre, and enough for legible
    // glyphs (a character cell of about 10 texels).
    const layers::Fov f0 = textFov(o, 0);
    const double eyePpt = o.width / (std::tan(f0.angleRight) - std::tan(f0.angleLeft));
    const TextLayout& L = o.layout;
    const double cellPpt = 10.0 / std::tan(L.charDeg * kDeg);
    const double ppt = std::max(2.0 * eyePpt, cellPpt);
    const int TW = int(std::ceil(2 * kTanX * ppt)), TH = int(std::ceil(2 * kTanY * ppt));
    cv::Mat page(TH, TW, CV_8UC3, cv::Scalar(238, 238, 238));

    cv::Ptr<cv::freetype::FreeType2> ft;
    if (std::filesystem::exists(kFont)) {
        try {
            ft = cv::freetype::createFreeType2();
            ft->loadFontData(kFont, 0);
            freetype_ = true;
        } catch (const cv::Exception&) {
            ft.release();
        }
    }
    const double advance = std::tan(L.charDeg * kDeg) * ppt;  // texels per character
    // Font height so that 40 characters span 40 advances.
    int fontPx = 12;
    double hersheyScale = 0.5;
    {
        std::string probe(40, 'm');
        if (freetype_) {
            int base = 0;
            cv::Size s = ft->getTextSize(probe, 100, -1, &base);
            fontPx = std::max(6, int(std::lround(100.0 * advance * 40 / s.width)));
        } else {
            int base = 0;
            cv::Size s = cv::getTextSize(probe, cv::FONT_HERSHEY_SIMPLEX, 1.0, 1, &base);
            hersheyScale = advance * 40 / s.width;
        }
    }
    auto put = [&](const std::string& text, double tanX, double tanY, cv::Scalar colour) {
        cv::Point org(int((tanX + kTanX) * ppt), int((kTanY - tanY) * ppt));
        if (freetype_) ft->putText(page, text, org, fontPx, colour, -1, cv::LINE_AA, true);
        else cv::putText(page, text, org, cv::FONT_HERSHEY_SIMPLEX, hersheyScale, colour, 1, cv::LINE_AA);
    };
    cv::RNG rng(o.seed);
    // Central reading block.
    for (int line = 0; line < L.lines; ++line) {
        std::string s;
        while (int(s.size()) < L.lineChars) {
            std::string w = kWords[rng.uniform(0, int(std::size(kWords)))];
            if (int(s.size() + w.size()) > L.lineChars) break;
            s += w + " ";
        }
        // Baseline below the line centre by about half an x-height (0.45 advances for DejaVu Sans Mono).
        double baseline = L.lineCentreDeg(line) - 0.45 * L.charDeg;
        put(s, std::tan(L.leftEdgeAzimuthDeg() * kDeg), std::tan(baseline * kDeg), cv::Scalar(25, 25, 25));
    }
    // Peripheral nonsense text everywhere else, in grey.
    const double blockTop = L.lineCentreDeg(0) + L.lineSpacingDeg;
    const double blockBottom = L.lineCentreDeg(L.lines - 1) - L.lineSpacingDeg;
    const double rightEdge = L.leftEdgeAzimuthDeg() + L.lineChars * L.charDeg;
    for (double el = 54.0; el > -54.0; el -= L.lineSpacingDeg) {
        for (double az = -58.0; az < 58.0;) {
            std::string w;
            int n = rng.uniform(2, 9);
            for (int i = 0; i < n; ++i) w += char('a' + rng.uniform(0, 26));
            double wDeg = (n + 1) * L.charDeg;
            bool inBlock = el <= blockTop && el >= blockBottom && az + wDeg >= L.leftEdgeAzimuthDeg() - 1.0 &&
                           az <= rightEdge + 1.0;
            if (!inBlock) put(w, std::tan(az * kDeg), std::tan(el * kDeg), cv::Scalar(120, 120, 120));
            az += wDeg;
        }
    }

    // The page in linear colour, which every view of the scene samples.
    page.convertTo(page_, CV_32FC3, 1.0 / 255.0);
    for (int y = 0; y < page_.rows; ++y) {
        auto* p = page_.ptr<cv::Vec3f>(y);
        for (int x = 0; x < page_.cols; ++x)
            for (int c = 0; c < 3; ++c) p[x][c] = gpu::wrs_srgb_to_linear(p[x][c]);
    }
    ppt_ = ppt;
    renderViews({textFov(o, 0), textFov(o, 1)}, o.width, o.height, color_, depth_);
}

void TextScene::renderViews(const std::array<layers::Fov, 2>& fovs, uint32_t width, uint32_t height,
                            std::array<HostImage, 2>& color, std::array<HostImage, 2>& depth, float footprint) const {
    const float fp = std::isfinite(footprint) && footprint > 0.0f ? std::min(footprint, 1.0f) : 1.0f;
    // Per eye: rays through 2x2 subsamples of each pixel meet the plane z = -distance.
    const TextOptions& o = options_;
    const cv::Mat& lin = page_;
    const double ppt = ppt_;
    const float d = o.distance;
    const float n = o.nearZ, far = o.farZ;
    const float depthValue = far / (far - n) - far * n / ((far - n) * d);
    for (int eye = 0; eye < 2; ++eye) {
        const layers::Fov fov = fovs[eye];
        const float eyeX = o.monitor ? 0.0f : (eye == 0 ? -0.5f : 0.5f) * o.ipd;
        // Monitor mode: one view seen by both eyes, rendered once.
        if (eye == 1 && o.monitor && std::memcmp(&fovs[0], &fovs[1], sizeof(layers::Fov)) == 0) {
            color[1] = color[0];
            depth[1] = depth[0];
            break;
        }
        const float tl = std::tan(fov.angleLeft), tr = std::tan(fov.angleRight);
        const float tu = std::tan(fov.angleUp), td = std::tan(fov.angleDown);
        color[eye] = HostImage::make(layers::Format::RGBA8_SRGB, width, height);
        depth[eye] = HostImage::make(layers::Format::R32F, width, height);
        for (uint32_t y = 0; y < height; ++y)
            for (uint32_t x = 0; x < width; ++x) {
                cv::Vec3f acc(0, 0, 0);
                for (int s = 0; s < 4; ++s) {
                    float sx = float(x) + 0.5f + fp * (0.5f * float(s & 1) - 0.25f);
                    float sy = float(y) + 0.5f + fp * (0.5f * float(s >> 1) - 0.25f);
                    float tx = tl + sx / float(width) * (tr - tl);
                    float ty = tu - sy / float(height) * (tu - td);
                    double X = tx + eyeX / d, Y = ty;  // plane point in cyclopean tangent units
                    float u = float((X + kTanX) * ppt - 0.5), v = float((kTanY - Y) * ppt - 0.5);
                    cv::Vec3f c(0.93f, 0.93f, 0.93f);
                    if (u >= 0 && v >= 0 && u < lin.cols - 1 && v < lin.rows - 1) {
                        int u0 = int(u), v0 = int(v);
                        float fu = u - u0, fv = v - v0;
                        const cv::Vec3f* r0 = lin.ptr<cv::Vec3f>(v0);
                        const cv::Vec3f* r1 = lin.ptr<cv::Vec3f>(v0 + 1);
                        c = (r0[u0] * (1 - fu) + r0[u0 + 1] * fu) * (1 - fv) + (r1[u0] * (1 - fu) + r1[u0 + 1] * fu) * fv;
                    }
                    acc += c * 0.25f;
                }
                // page is BGR; the swapchain is RGBA
                glm::vec3 rgb(acc[2], acc[1], acc[0]);
                color[eye].store(x, y, glm::vec4(gpu::wrs_linear_to_srgb3(rgb), 1.0f));
                depth[eye].store(x, y, glm::vec4(depthValue));
            }
    }
}

}  // namespace wrsfov::scenes
