// wrsfov-demo: the built-in default job. A procedural stereo page of text and gratings is submitted
// per eye through the layers API while a scripted reading gaze path sweeps the lines; the same
// frames and gaze go to method fov, method wrs and the unfoveated reference (method fov with
// foveation none), each a Compositor of its own. Writes side-by-side images, per-frame stats (GPU
// time per pass, PSNR and near-gaze PSNR against the reference) and a summary table.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <optional>
#include <string>
#include <vector>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "compositor/compositor.h"
#include "compositor/host_app.h"
#include "compositor/vk_context.h"
#include "eval/metrics.h"
#include "cli/cli.h"

using namespace wrsfov;
namespace fs = std::filesystem;

namespace {

struct Options {
    std::string out = "out/demo";
    cli::Size size{320, 288};
    int frames = 120;
    float foveaDeg = 5.0f;
    FoveationMode mode = FoveationMode::Mip;
    uint32_t seed = 1;
    int saveEvery = 30;
};

// The command line; an exit status when the program should stop here.
std::optional<int> parse(int argc, char** argv, Options& o) {
    CLI::App app{
        "The built-in demo: a procedural stereo page of text and gratings with a scripted reading gaze, "
        "composited by method fov, method wrs and the unfoveated reference (method fov with foveation none), "
        "each a compositor of its own fed the same frames and gaze. Writes DIR/frame_NNNN.png (reference, fov "
        "and wrs rows, both eyes), DIR/stats.csv (GPU time per pass, PSNR and near-gaze PSNR per frame) and "
        "DIR/summary.md, and prints the summary table.",
        "wrsfov-demo"};
    cli::setup(app);
    cli::option(app, "--out", o.out, cli::text("a directory name", "DIR"), "Directory for the images and tables.");
    cli::option(app, "--size", o.size, cli::size(16, 4096), "Image size per eye, W and H in 16..4096.");
    cli::option(app, "--frames", o.frames, cli::integer(1, 100000),
                "Frames to composite at 90 Hz, 1..100000 (the summary averages frames 10 on).");
    cli::option(app, "--fovea", o.foveaDeg, cli::number<float>(0, 60, cli::Ends::OpenLow),
                "Fovea diameter in degrees, in (0, 60].")
        ->type_name("DEG");
    cli::option(app, "--mode", o.mode,
                cli::oneOf<FoveationMode>(
                    {{"mip", FoveationMode::Mip}, {"gauss", FoveationMode::Gauss}, {"none", FoveationMode::None}}),
                "Foveation of fov and wrs: mip, gauss or none.");
    cli::option(app, "--seed", o.seed, cli::integer<uint32_t>(0, 0xffffffffu),
                "Seed of the page's words and WRS's random numbers, 0..4294967295.");
    cli::option(app, "--save-every", o.saveEvery, cli::integer(1, 100000),
                "Write a side-by-side image every N frames (and after the last), 1..100000.");
    return cli::parseOrExit(app, argc, argv);
}

// The page: text lines in the middle, gratings and a checker around it. Disparity shifts the
// right eye's copy so that both eyes see the same page at a small depth.
cv::Mat drawPage(uint32_t w, uint32_t h, int shiftPx, uint32_t seed) {
    cv::Mat img(int(h), int(w), CV_8UC3, cv::Scalar(235, 235, 235));
    cv::RNG rng(seed);
    for (int y = 0; y < img.rows; ++y)
        for (int x = 0; x < img.cols; ++x) {
            int xs = x - shiftPx;
            bool border = y < img.rows / 8 || y > img.rows * 7 / 8;
            if (border) {
                bool c = ((xs / 4) + (y / 4)) % 2;
                img.at<cv::Vec3b>(y, x) = c ? cv::Vec3b(40, 90, 200) : cv::Vec3b(230, 200, 60);
            } else if (xs < img.cols / 10 || xs > img.cols * 9 / 10) {
                float g = 0.5f + 0.5f * std::sin(float(xs) * 1.3f + float(y) * 0.2f);
                img.at<cv::Vec3b>(y, x) = cv::Vec3b(uchar(60 + 160 * g), uchar(200 * g), uchar(90));
            }
        }
    const char* words[] = {"foveated", "reservoir", "weighted", "sample", "gaze", "stereo", "vulkan", "compute",
                           "pixel", "history", "acuity", "saccade", "periphery", "fixation", "display", "eye"};
    double scale = std::max(0.28, double(h) / 900.0);
    int lineH = int(28 * scale / 0.5);
    for (int y = img.rows / 8 + lineH; y < img.rows * 7 / 8 - lineH / 2; y += lineH) {
        std::string line;
        while (int(line.size()) * 9 * scale / 0.5 < img.cols * 0.7) line += std::string(words[rng.uniform(0, 16)]) + " ";
        cv::putText(img, line, cv::Point(img.cols / 8 + shiftPx, y), cv::FONT_HERSHEY_SIMPLEX, scale,
                    cv::Scalar(20, 20, 20), 1, cv::LINE_AA);
    }
    return img;
}

HostImage toHost(const cv::Mat& bgr) {
    HostImage h = HostImage::make(layers::Format::RGBA8_SRGB, uint32_t(bgr.cols), uint32_t(bgr.rows));
    cv::Mat rgba(bgr.rows, bgr.cols, CV_8UC4, h.data.data());
    cv::cvtColor(bgr, rgba, cv::COLOR_BGR2RGBA);
    return h;
}

cv::Mat toMat(const HostImage& h) {
    cv::Mat rgba(int(h.height), int(h.width), CV_8UC4, const_cast<std::byte*>(h.data.data()));
    cv::Mat bgr;
    cv::cvtColor(rgba, bgr, cv::COLOR_RGBA2BGR);
    return bgr;
}

// Scripted reading path over the page, in left-eye pixel coordinates: fixations of ~250 ms on
// points 7 characters apart along each line, a return sweep at the end of the line.
cv::Point2f gazePoint(double t, uint32_t w, uint32_t h) {
    const double fix = 0.25;
    const int perLine = 8;
    const int lines = 6;
    int k = int(t / fix);
    int line = (k / perLine) % lines;
    int step = k % perLine;
    float x = float(w) * (0.18f + 0.62f * float(step) / float(perLine - 1));
    float y = float(h) * (0.22f + 0.56f * float(line) / float(lines - 1));
    return {x, y};
}

struct Psnr {
    double full = 0, near = 0;
};

// PSNR on sRGB-encoded 8-bit output, over all pixels and over pixels within 10° of the gaze
// (eval/metrics). Identical images count as 99 dB so that means over frames stay finite.
Psnr psnr(const HostImage& a, const HostImage& ref, const gpu::EyeParams& ep) {
    cv::Mat ecc = eval::eccentricityMap(a.width, a.height, ep);
    double near = eval::nearGazePsnr(ref, a, ecc);
    return {std::min(eval::psnr(ref, a), 99.0), std::isnan(near) ? 0.0 : std::min(near, 99.0)};
}

}  // namespace

int main(int argc, char** argv) {
    Options o;
    if (auto rc = parse(argc, argv, o)) return *rc;
    const uint32_t width = o.size.width, height = o.size.height;
    std::error_code ec;
    fs::create_directories(o.out, ec);
    if (ec) {
        std::fprintf(stderr, "wrsfov-demo: cannot create %s: %s\n", o.out.c_str(), ec.message().c_str());
        return 1;
    }
    auto ctx = vk::Context::create();
    if (!ctx) {
        std::fprintf(stderr, "wrsfov-demo: %s\n", ctx.error().message.c_str());
        return 1;
    }
    std::printf("wrsfov-demo: device %s, %ux%u per eye, %d frames, fovea %.1f°, mode %s -> %s\n",
                (*ctx)->deviceName().c_str(), width, height, o.frames, o.foveaDeg,
                std::string(toString(o.mode)).c_str(), o.out.c_str());

    const char* names[3] = {"reference", "fov", "wrs"};
    std::unique_ptr<Compositor> comps[3];
    std::unique_ptr<HostStereoApp> apps[3];
    for (int i = 0; i < 3; ++i) {
        CompositorConfig cfg;
        cfg.method = i == 2 ? Method::Wrs : Method::Fov;  // wrs: the default retention rule
        cfg.foveation = i == 0 ? FoveationMode::None : o.mode;
        cfg.foveaDeg = o.foveaDeg;
        cfg.seed = o.seed;
        auto c = Compositor::create(**ctx, cfg);
        if (!c) {
            std::fprintf(stderr, "wrsfov-demo: %s\n", c.error().message.c_str());
            return 1;
        }
        comps[i] = std::move(*c);
        HostStereoApp::Options ao;
        ao.width = width;
        ao.height = height;
        auto a = HostStereoApp::create(*comps[i], ao);
        if (!a) {
            std::fprintf(stderr, "wrsfov-demo: %s\n", a.error().message.c_str());
            return 1;
        }
        apps[i] = std::move(*a);
    }

    const int disparity = int(width / 80);
    std::array<HostImage, 2> pages = {toHost(drawPage(width, height, 0, o.seed)),
                                      toHost(drawPage(width, height, -disparity, o.seed))};
    std::ofstream csv(o.out + "/stats.csv");
    csv << "frame,t_s,gaze_x_px,gaze_y_px,method,pyramid_ms,foveate_ms,temporal_ms,total_ms,"
           "psnr_left,psnr_right,near_psnr_left,near_psnr_right\n";
    double sums[3][4] = {};
    int counted = 0;
    const double fps = 90.0;
    auto t0 = std::chrono::steady_clock::now();
    for (int f = 0; f < o.frames; ++f) {
        double t = f / fps;
        cv::Point2f g = gazePoint(t, width, height);
        std::array<EyeSubmission, 2> eyes;
        for (int e = 0; e < 2; ++e) {
            eyes[e].color = pages[e];
            eyes[e].fov = hmdFov(e);
            float gx = g.x - float(e == 1 ? disparity : 0);
            eyes[e].gaze = {pixelDirection(eyes[e].fov, width, height, gx, g.y), true, 1.0f};
        }
        HostImage outs[3][2];
        for (int i = 0; i < 3; ++i) {
            if (Status s = apps[i]->submit(uint64_t(f + 1), t, eyes); !s) {
                std::fprintf(stderr, "wrsfov-demo: frame %d (%s) refused: %s\n", f, names[i], s.message().c_str());
                return 1;
            }
            for (uint32_t e = 0; e < 2; ++e) {
                auto r = comps[i]->readOutput(e);
                if (!r) {
                    std::fprintf(stderr, "wrsfov-demo: %s\n", r.error().message.c_str());
                    return 1;
                }
                outs[i][e] = std::move(*r);
            }
        }
        for (int i = 1; i < 3; ++i) {
            const FrameStats& st = comps[i]->stats();
            Psnr pl = psnr(outs[i][0], outs[0][0], comps[i]->lastParams().eye[0]);
            Psnr pr = psnr(outs[i][1], outs[0][1], comps[i]->lastParams().eye[1]);
            csv << f << ',' << t << ',' << g.x << ',' << g.y << ',' << names[i] << ','
                << st.gpu.pyramid << ',' << st.gpu.foveate << ',' << st.gpu.temporal << ',' << st.gpu.total << ','
                << pl.full << ',' << pr.full << ',' << pl.near << ',' << pr.near << '\n';
            if (f >= 10) {
                sums[i][0] += (pl.full + pr.full) / 2;
                sums[i][1] += (pl.near + pr.near) / 2;
                sums[i][2] += st.gpu.total;
            }
        }
        if (f >= 10) counted++;
        if (f % o.saveEvery == o.saveEvery - 1 || f == o.frames - 1) {
            cv::Mat rows[3];
            for (int i = 0; i < 3; ++i) {
                cv::Mat l = toMat(outs[i][0]), r = toMat(outs[i][1]);
                for (int e = 0; e < 2; ++e) {
                    cv::Mat& m = e == 0 ? l : r;
                    cv::circle(m, cv::Point(int(g.x) - (e == 1 ? disparity : 0), int(g.y)), 3, cv::Scalar(0, 0, 255),
                               -1);
                    cv::putText(m, std::string(names[i]) + (e == 0 ? " L" : " R"), cv::Point(4, 14),
                                cv::FONT_HERSHEY_SIMPLEX, 0.45, cv::Scalar(0, 0, 255), 1, cv::LINE_AA);
                }
                cv::hconcat(l, r, rows[i]);
            }
            cv::Mat all;
            cv::vconcat(rows, 3, all);
            char name[64];
            std::snprintf(name, sizeof(name), "/frame_%04d.png", f);
            cv::imwrite(o.out + name, all);
        }
        if ((f + 1) % 20 == 0 || f + 1 == o.frames) {
            double el = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
            std::printf("  frame %d/%d  (%.1f s)\n", f + 1, o.frames, el);
            std::fflush(stdout);
        }
    }
    // The summary table, in summary.md and on the console, each with its header.
    const char* header =
        "| method | PSNR (dB) | near-gaze PSNR, e ≤ 10° (dB) | GPU ms / frame (both eyes) |\n|---|---|---|---|\n";
    std::ofstream md(o.out + "/summary.md");
    md << "# wrsfov-demo summary\n\n" << width << "x" << height << " per eye, " << o.frames << " frames, fovea "
       << o.foveaDeg << "°, foveation " << toString(o.mode) << ", device " << (*ctx)->deviceName()
       << ". Means over frames 10.. of both eyes, against the unfoveated reference.\n\n"
       << header;
    std::printf("wrsfov-demo: means over frames 10.. of both eyes, against the unfoveated reference\n%s", header);
    for (int i = 1; i < 3; ++i) {
        char row[200];
        std::snprintf(row, sizeof(row), "| %s | %.2f | %.2f | %.3f |\n", names[i], sums[i][0] / std::max(1, counted),
                      sums[i][1] / std::max(1, counted), sums[i][2] / std::max(1, counted));
        md << row;
        std::printf("%s", row);
    }
    md.close();
    std::printf("wrsfov-demo: wrote %s/summary.md, %s/stats.csv and frame images\n", o.out.c_str(), o.out.c_str());
    return 0;
}
