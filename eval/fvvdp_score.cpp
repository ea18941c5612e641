// wrsfov-fvvdp: FovVideoVDP (eval/fvvdp.h) of two PNG sequences, so that any pair of frame sets
// (the bench's outputs, another renderer's) can be scored from the command line.
//
//   wrsfov-fvvdp [options] TEST REFERENCE
//
// TEST and REFERENCE are a PNG file (an image) or a directory whose *.png files, in name order,
// are the frames. Prints the JOD. Exit status 0 on success, 1 on bad input, 2 on a usage error.
#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "eval/fvvdp.h"

namespace fs = std::filesystem;
using namespace wrsfov::eval;

namespace {

const char* kUsage =
    "usage: wrsfov-fvvdp [options] TEST REFERENCE\n"
    "  TEST, REFERENCE    a PNG image, or a directory of PNG frames (name order)\n"
    "  --display NAME     monitor (200 cd/m2, 1000:1, 250 lux; default) or hmd (100 cd/m2, black 0.1)\n"
    "  --fov-deg D        symmetric view D degrees wide (default 76, the bench's monitor view)\n"
    "  --fov-tan L,R,U,D  view by its tangents (XrFovf order)\n"
    "  --ppd P            the reference's flat screen with P pixels per degree at its centre\n"
    "  --flat             the reference's flat-screen model for --fov-deg (eccentricity per axis)\n"
    "  --fps F            frame rate (default 90)\n"
    "  --gaze X,Y         pixel looked at in every frame (default the image centre)\n"
    "  --gaze-csv FILE    per-frame gaze: lines 'frame,x,y' in pixels (a header line is skipped)\n"
    "  --no-foveated      foveal sensitivity everywhere\n"
    "  --frames N         score only the first N frames\n"
    "  --per-band         print each frame's pooled quality per band and channel\n";

[[noreturn]] void usage(const std::string& why) {
    std::cerr << "wrsfov-fvvdp: " << why << "\n" << kUsage;
    std::exit(2);
}

std::vector<double> numbers(const std::string& text, size_t n, const char* what) {
    std::vector<double> v;
    std::stringstream ss(text);
    std::string item;
    while (std::getline(ss, item, ',')) {
        char* end = nullptr;
        double d = std::strtod(item.c_str(), &end);
        if (end == item.c_str() || *end != '\0') usage(std::string(what) + ": '" + text + "' is not a number list");
        v.push_back(d);
    }
    if (v.size() != n) usage(std::string(what) + " needs " + std::to_string(n) + " comma-separated numbers");
    return v;
}

std::vector<std::string> frameFiles(const std::string& path) {
    std::vector<std::string> files;
    if (fs::is_directory(path)) {
        for (const auto& e : fs::directory_iterator(path))
            if (e.is_regular_file() && e.path().extension() == ".png") files.push_back(e.path().string());
        std::sort(files.begin(), files.end());
    } else {
        files.push_back(path);
    }
    return files;
}

// PNG -> CV_32FC3 R, G, B in [0, 1] (8 or 16 bits).
bool loadPng(const std::string& path, cv::Mat& out, std::string& why) {
    cv::Mat m = cv::imread(path, cv::IMREAD_ANYDEPTH | cv::IMREAD_COLOR);
    if (m.empty()) {
        why = "cannot read " + path;
        return false;
    }
    const double scale = m.depth() == CV_16U ? 1.0 / 65535.0 : 1.0 / 255.0;
    cv::cvtColor(m, m, cv::COLOR_BGR2RGB);
    m.convertTo(out, CV_32FC3, scale);
    return true;
}

}  // namespace

int main(int argc, char** argv) {
    fvvdp::Options opt;
    double fov_deg = 76.0, ppd = 0.0;
    std::vector<double> fov_tan, gaze;
    std::string gaze_csv;
    bool flat = false, per_band = false;
    long max_frames = -1;
    std::vector<std::string> pos;
    for (int i = 1; i < argc; ++i) {
        std::string a = argv[i];
        auto value = [&]() -> std::string {
            if (i + 1 >= argc) usage(a + " needs a value");
            return argv[++i];
        };
        if (a == "--help" || a == "-h") {
            std::cout << kUsage;
            return 0;
        } else if (a == "--display") {
            std::string d = value();
            if (d == "monitor")
                opt.photometry = fvvdp::DisplayPhotometry::monitor();
            else if (d == "hmd")
                opt.photometry = fvvdp::DisplayPhotometry::hmd();
            else
                usage("--display: '" + d + "' is neither monitor nor hmd");
        } else if (a == "--fov-deg")
            fov_deg = numbers(value(), 1, "--fov-deg")[0];
        else if (a == "--fov-tan")
            fov_tan = numbers(value(), 4, "--fov-tan");
        else if (a == "--ppd")
            ppd = numbers(value(), 1, "--ppd")[0];
        else if (a == "--flat")
            flat = true;
        else if (a == "--fps")
            opt.fps = numbers(value(), 1, "--fps")[0];
        else if (a == "--gaze")
            gaze = numbers(value(), 2, "--gaze");
        else if (a == "--gaze-csv")
            gaze_csv = value();
        else if (a == "--no-foveated")
            opt.foveated = false;
        else if (a == "--frames")
            max_frames = long(numbers(value(), 1, "--frames")[0]);
        else if (a == "--per-band")
            per_band = true;
        else if (!a.empty() && a[0] == '-')
            usage("unknown option " + a);
        else
            pos.push_back(a);
    }
    if (pos.size() != 2) usage("TEST and REFERENCE are needed");

    std::vector<std::string> tf = frameFiles(pos[0]), rf = frameFiles(pos[1]);
    if (tf.empty() || tf.size() != rf.size()) {
        std::cerr << "wrsfov-fvvdp: " << tf.size() << " test frames, " << rf.size() << " reference frames\n";
        return 1;
    }
    size_t n = tf.size();
    if (max_frames > 0 && size_t(max_frames) < n) n = size_t(max_frames);

    std::vector<glm::vec2> gazes;
    if (!gaze_csv.empty()) {
        std::ifstream in(gaze_csv);
        if (!in) {
            std::cerr << "wrsfov-fvvdp: cannot read " << gaze_csv << "\n";
            return 1;
        }
        std::string line;
        while (std::getline(in, line)) {
            long f;
            double x, y;
            if (std::sscanf(line.c_str(), "%ld,%lf,%lf", &f, &x, &y) != 3) continue;  // header
            if (f >= 0 && size_t(f) < n) {
                if (gazes.size() <= size_t(f)) gazes.resize(size_t(f) + 1, glm::vec2(NAN, NAN));
                gazes[size_t(f)] = {float(x), float(y)};
            }
        }
        if (gazes.size() < n) {
            std::cerr << "wrsfov-fvvdp: " << gaze_csv << " has gaze for " << gazes.size() << " of " << n << " frames\n";
            return 1;
        }
    }

    cv::Mat t, r;
    std::string why;
    if (!loadPng(tf[0], t, why)) {
        std::cerr << "wrsfov-fvvdp: " << why << "\n";
        return 1;
    }
    const uint32_t w = uint32_t(t.cols), h = uint32_t(t.rows);
    if (ppd > 0)
        opt.geometry = fvvdp::ViewGeometry::flatScreenPpd(w, h, ppd);
    else if (!fov_tan.empty())
        opt.geometry = fvvdp::ViewGeometry::view(
            w, h, glm::vec4(float(fov_tan[0]), float(fov_tan[1]), float(fov_tan[2]), float(fov_tan[3])));
    else
        opt.geometry = fvvdp::ViewGeometry::symmetric(
            w, h, fov_deg, flat ? fvvdp::ViewGeometry::Model::FlatScreen : fvvdp::ViewGeometry::Model::View);
    if (!gaze.empty()) gazes.assign(n, glm::vec2(float(gaze[0]), float(gaze[1])));
    if (gazes.empty()) gazes.assign(n, glm::vec2(float(w / 2), float(h / 2)));

    auto metric = fvvdp::Metric::create(opt);
    if (!metric) {
        std::cerr << "wrsfov-fvvdp: " << metric.error().message << "\n";
        return 1;
    }
    for (size_t f = 0; f < n; ++f) {
        if ((f > 0 && !loadPng(tf[f], t, why)) || !loadPng(rf[f], r, why)) {
            std::cerr << "wrsfov-fvvdp: " << why << "\n";
            return 1;
        }
        if (wrsfov::Status s = metric->push(t, r, gazes[f]); !s) {
            std::cerr << "wrsfov-fvvdp: frame " << f << ": " << s.message() << "\n";
            return 1;
        }
        if (per_band) {
            const auto& q = metric->lastFrame().band;
            for (size_t b = 0; b < q.size(); ++b)
                std::printf("frame %zu band %zu (%.3g cpd): sustained %.6g transient %.6g\n", f, b,
                            metric->bandFrequencies()[b], q[b][0], q[b][1]);
        }
    }
    std::printf("%.4f\n", metric->jod().value());
    return 0;
}
