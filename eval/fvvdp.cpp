#include "eval/fvvdp.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <utility>

namespace wrsfov::eval::fvvdp {

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kDeg = 180.0 / kPi;

Error error(FvvdpError code, std::string message) { return Error{int(code), "fvvdp: " + std::move(message)}; }

std::string sizeText(int w, int h) { return std::to_string(w) + "x" + std::to_string(h); }

// First non-finite value of a CV_32FC3 image as "(x, y)", empty when all are finite.
std::string firstNonFinite(const cv::Mat& m) {
    for (int y = 0; y < m.rows; ++y) {
        const float* p = m.ptr<float>(y);
        uint32_t any = 0;
        for (int i = 0; i < m.cols * 3; ++i) {
            uint32_t bits;
            std::memcpy(&bits, p + i, 4);
            any |= uint32_t((bits & 0x7f800000u) == 0x7f800000u);
        }
        if (!any) continue;
        for (int i = 0; i < m.cols * 3; ++i)
            if (!std::isfinite(p[i])) return "(" + std::to_string(i / 3) + ", " + std::to_string(y) + ")";
    }
    return {};
}


// The CSF table's axes, as the values the interpolation works in.
struct CsfAxes {
    double y0 = std::log2(detail::kCsfYMin), y1 = std::log2(detail::kCsfYMax);
    double r0 = std::log2(detail::kCsfRhoMin), r1 = std::log2(detail::kCsfRhoMax);
    double e1 = std::sqrt(detail::kCsfEccMax);
};

// Position of q on a uniform axis [a, b] of n samples: the lower index and the fraction.
inline void axisPos(float q, float a, float b, int n, int& i, float& f) {
    float t = (std::clamp(q, a, b) - a) / (b - a) * float(n - 1);
    i = std::min(int(t), n - 2);
    f = t - float(i);
}

}  // namespace

// ---------------------------------------------------------------------------------------------
// Display model and geometry
// ---------------------------------------------------------------------------------------------

double DisplayPhotometry::black() const { return peak / contrast + ambient_lux * reflectivity / kPi; }

ViewGeometry ViewGeometry::view(uint32_t width, uint32_t height, glm::vec4 fov_tan) {
    return ViewGeometry{width, height, fov_tan, Model::View};
}

ViewGeometry ViewGeometry::symmetric(uint32_t width, uint32_t height, double fov_h_deg, Model model) {
    const float th = float(std::tan(fov_h_deg * 0.5 / kDeg));
    const float tv = th * float(height) / float(width);
    return ViewGeometry{width, height, {-th, th, tv, -tv}, model};
}

ViewGeometry ViewGeometry::flatScreen(uint32_t width, uint32_t height, double width_m, double height_m,
                                      double distance_m) {
    const float th = float(0.5 * width_m / distance_m), tv = float(0.5 * height_m / distance_m);
    return ViewGeometry{width, height, {-th, th, tv, -tv}, Model::FlatScreen};
}

ViewGeometry ViewGeometry::flatScreenPpd(uint32_t width, uint32_t height, double ppd) {
    // ppd = 1 / (2 atan(pitch / 2)) in degrees  =>  pitch = 2 tan(1 / (2 ppd) degrees).
    const double pitch = 2.0 * std::tan(0.5 / ppd / kDeg);
    const float th = float(0.5 * pitch * width), tv = float(0.5 * pitch * height);
    return ViewGeometry{width, height, {-th, th, tv, -tv}, Model::FlatScreen};
}

double ViewGeometry::ppdCentre() const {
    const double pitch = (double(fov_tan.y) - double(fov_tan.x)) / double(width);
    return 1.0 / (2.0 * std::atan(0.5 * pitch) * kDeg);
}

namespace detail {

float srgbToLinear(float v) { return v > 0.04045f ? std::pow((v + 0.055f) / 1.055f, 2.4f) : v / 12.92f; }

float displayLuminance(float r, float g, float b, float peak, float black) {
    auto channel = [&](float v) { return (peak - black) * srgbToLinear(std::clamp(v, 0.0f, 1.0f)) + black; };
    return 0.2126729f * channel(r) + 0.7151522f * channel(g) + 0.0721750f * channel(b);
}

std::array<std::vector<float>, 2> temporalFilters(double fps, const Parameters& p) {
    // 250 ms of frames, computed as the reference does so that the length agrees at every rate.
    const int n = int(std::ceil(250.0 / (1000.0 / fps)));
    std::array<std::vector<float>, 2> f{std::vector<float>(size_t(n)), std::vector<float>(size_t(n), 0.0f)};
    if (n < 2) {
        f[0].assign(size_t(n), 1.0f);
        return f;
    }
    const double span = double(n) / fps;  // t from 0 to n / fps in n samples
    const double dt = span / double(n - 1);
    std::vector<double> s(static_cast<size_t>(n));
    double sum = 0.0;
    for (int k = 0; k < n; ++k) {
        const double t = dt * k;
        const double d = std::log(t + 1e-4) - std::log(p.sustained_beta);
        s[size_t(k)] = std::exp(-d * d / (2.0 * p.sustained_sigma * p.sustained_sigma));
        sum += s[size_t(k)];
    }
    for (auto& v : s) v /= sum;
    constexpr double k2 = 0.062170507756932;  // the reference's gain of the transient channel
    for (int k = 0; k < n; ++k) {
        f[0][size_t(k)] = float(s[size_t(k)]);
        if (k + 1 < n) f[1][size_t(k)] = float(k2 * (s[size_t(k) + 1] - s[size_t(k)]) / dt);
    }
    return f;
}

double corticalMagnificationRel(double ecc_deg, double k_cm) {
    constexpr double e2 = 3.67;  // Dougherty et al. 2003: M(e) = 29.2 mm / (e + 3.67°)
    return std::pow(e2 / (ecc_deg + e2), k_cm);
}

double csfSpatioVelocity(double rho, double velocity) {
    constexpr double s1 = 6.1, s2 = 7.3, p1 = 45.9;
    constexpr double c0 = 0.6329, c1 = 0.8404, c2 = 0.7986;
    const double v = std::max(velocity, 0.1);
    const double l = std::abs(std::log10(c2 * v / 3.0));
    const double k = s1 + s2 * l * l * l;
    const double rho_max = p1 / (c2 * v + 2.0);
    const double w = c1 * 2.0 * kPi * rho;
    return k * c0 * c1 * c2 * v * w * w * std::exp(-(c1 * 4.0 * kPi * rho) / rho_max);
}

namespace {

// Mantiuk et al. 2020, cone-contrast CSF: the luminance dependence of one mechanism's parameter
// (1, 3 or 5 coefficients).
double lumDep(const double* c, int n, double lum) {
    switch (n) {
        case 1:
            return c[0];
        case 3:
            return c[0] * std::pow(1.0 + c[1] / lum, -c[2]);
        default:
            return c[0] * std::pow(1.0 + c[1] / lum, -c[2]) * (1.0 - std::pow(1.0 + c[3] / lum, -c[4]));
    }
}

struct Mechanism {
    double s_max[5];
    int n_s_max;
    double f_max[3];
    int n_f_max;
    double bw, gamma, ac_prime;
};

// Fitted parameters of the model (achromatic, red-green, yellow-violet mechanisms).
constexpr Mechanism kMechanisms[3] = {
    {{356404, 6.2726, 0.320031, 895943, 7.77919e-05}, 5, {2.3021, 3317.45, 0.186215}, 3, 1.07516, 1.1107, 52.9768},
    {{423.978, 15.4032, 0.50343}, 3, {0.122699}, 1, 2.70669, 1.72903, 1.38437},
    {{11811.9, 196.342, 0.339396}, 3, {7.1099e-08}, 1, 5.3416, 1.47263, 0.282573},
};
// Off-unit entries of the matrix from cone contrast to mechanism contrast.
constexpr double kColmat[6] = {0.00130319, 0.256197, 0.933541, 1.1504, 6.42477e-07, 0.00373304};

// Sensitivity of mechanism m to a Gabor: log-parabola around f_max, Rovamo's area summation.
double mechanismSensitivity(int m, double freq, double area, double lum) {
    const Mechanism& c = kMechanisms[m];
    const double s_max = lumDep(c.s_max, c.n_s_max, lum);
    const double f_max = lumDep(c.f_max, c.n_f_max, lum);
    double s_peak =
        s_max / std::pow(10.0, std::pow(std::log10(freq) - std::log10(f_max), 2.0) / (0.5 * std::pow(2.0, c.bw)));
    if (m > 0 && freq < f_max) s_peak = s_max;  // chromatic mechanisms are low-pass
    constexpr double f0 = 0.65;
    const double k = c.ac_prime + area * f0;
    const double a = std::pow(area, c.gamma) * freq * freq;
    return s_peak * std::sqrt(a / (k + a));
}

}  // namespace

double csfAchromatic(double rho, double area, double luminance) {
    // D65 white (CIE 1931 XYZ, Y = 1) in CIE 2006 LMS (the model's transform for an LED LCD).
    constexpr double xyz[3] = {0.95047, 1.0, 1.08883};
    constexpr double m[3][3] = {{0.187596268556126, 0.585168649077728, -0.026384263306304},
                                {-0.133397430663221, 0.405505777260049, 0.034502127690364},
                                {0.000244379021663, -0.000542995890619, 0.019406849066323}};
    double lms_mean[3];
    for (int i = 0; i < 3; ++i) lms_mean[i] = luminance * (m[i][0] * xyz[0] + m[i][1] * xyz[1] + m[i][2] * xyz[2]);
    constexpr double lms_delta[3] = {0.698, 0.302, 0.019613};  // the achromatic direction
    double cc[3], cc_norm2 = 0.0;
    for (int i = 0; i < 3; ++i) {
        cc[i] = lms_delta[i] / lms_mean[i];
        cc_norm2 += cc[i] * cc[i];
    }
    const double mech[3][3] = {
        {1.0, kColmat[1], kColmat[4]}, {1.0, -kColmat[2], kColmat[5]}, {-kColmat[0], -kColmat[3], 1.0}};
    const double lum = lms_mean[0] + lms_mean[1];
    double c2 = 0.0;
    for (int i = 0; i < 3; ++i) {
        const double acc = std::abs(mech[i][0] * cc[0] + mech[i][1] * cc[1] + mech[i][2] * cc[2]);
        const double cn = acc * mechanismSensitivity(i, rho, area, lum);
        c2 += cn * cn;
    }
    // Detection at normalised contrast 1: the threshold cone contrast is cc / C, its RMS over the
    // three cones the inverse sensitivity.
    return std::sqrt(c2) * std::sqrt(3.0) / std::sqrt(cc_norm2);
}

double csfSensitivity(double rho, double omega, double luminance, double ecc, const Parameters& p) {
    const double sigma = p.csf_sigma < 0 ? -p.csf_sigma / rho : p.csf_sigma;  // stimulus radius, deg
    const double m_rel = corticalMagnificationRel(ecc, p.k_cm);
    const double area = kPi * (sigma * m_rel) * (sigma * m_rel);
    const double rho_cm = rho / m_rel;
    const double s_st = csfSpatioVelocity(rho_cm, omega / rho_cm) / (csfSpatioVelocity(rho_cm, 0.0) + 1e-5);
    return std::max(csfAchromatic(rho_cm, area, luminance) * s_st, 1e-4);
}

std::vector<float> csfTable(double omega, const Parameters& p) {
    constexpr int n = kCsfN;
    std::vector<float> t(size_t(n * n * n));
    const CsfAxes ax;
    for (int iy = 0; iy < n; ++iy) {
        const double y = std::exp2(ax.y0 + (ax.y1 - ax.y0) * iy / (n - 1));
        for (int ir = 0; ir < n; ++ir) {
            const double rho = std::exp2(ax.r0 + (ax.r1 - ax.r0) * ir / (n - 1));
            for (int ie = 0; ie < n; ++ie) {
                const double se = ax.e1 * ie / (n - 1);
                t[size_t((iy * n + ir) * n + ie)] = float(std::log2(csfSensitivity(rho, omega, y, se * se, p)));
            }
        }
    }
    return t;
}

float csfLookup(const std::vector<float>& table, float rho, float luminance, float ecc) {
    constexpr int n = kCsfN;
    static const CsfAxes ax;
    int iy, ir, ie;
    float fy, fr, fe;
    axisPos(std::log2(std::max(luminance, float(kCsfYMin))), float(ax.y0), float(ax.y1), n, iy, fy);
    axisPos(std::log2(std::max(rho, float(kCsfRhoMin))), float(ax.r0), float(ax.r1), n, ir, fr);
    axisPos(std::sqrt(std::max(ecc, 0.0f)), 0.0f, float(ax.e1), n, ie, fe);
    auto at = [&](int y, int r, int e) { return table[size_t(((iy + y) * n + ir + r) * n + ie + e)]; };
    auto lerp = [](float a, float b, float f) { return a + (b - a) * f; };
    const float v = lerp(lerp(lerp(at(0, 0, 0), at(0, 1, 0), fr), lerp(at(1, 0, 0), at(1, 1, 0), fr), fy),
                         lerp(lerp(at(0, 0, 1), at(0, 1, 1), fr), lerp(at(1, 0, 1), at(1, 1, 1), fr), fy), fe);
    return std::exp2(v);
}

float maskedDifference(float t, float r, float p, float q, float mask_gain) {
    if (t == r) return 0.0f;
    const float m = mask_gain * std::min(std::abs(t), std::abs(r));
    const float d = std::pow(std::abs(t - r), p) / (1.0f + std::pow(m, q));
    return std::min(d, 1e4f);
}

double eccentricityDeg(ViewGeometry::Model model, double tx, double ty, double gtx, double gty) {
    if (model == ViewGeometry::Model::View) {
        // The angle between (tx, ty, -1) and (gtx, gty, -1): atan2 of |cross| and dot, accurate
        // near 0 where acos is not.
        const double cx = ty - gty, cy = gtx - tx, cz = tx * gty - ty * gtx;
        return std::atan2(std::sqrt(cx * cx + cy * cy + cz * cz), tx * gtx + ty * gty + 1.0) * kDeg;
    }
    const double dx = (std::atan(tx) - std::atan(gtx)) * kDeg, dy = (std::atan(ty) - std::atan(gty)) * kDeg;
    return std::sqrt(dx * dx + dy * dy);
}

double resolutionMagnification(double angle_deg, double ppd_centre) {
    const double a = std::min(angle_deg, 89.9) / kDeg;
    const double delta = 0.5 / ppd_centre / kDeg;
    return (std::tan(a + delta) - std::tan(a)) / std::tan(delta);
}

std::array<double, 2> poolFrame(const FrameQuality& f, const Parameters& p) {
    // Bands (beta_sch) with the channels' weights, then the two channels (beta_tch).
    double q_ch[2] = {0.0, 0.0};
    for (const auto& b : f.band)
        for (int cc = 0; cc < 2; ++cc)
            q_ch[cc] += std::pow((cc == 0 ? 1.0 : p.w_transient) * b[size_t(cc)], p.beta_sch);
    for (double& v : q_ch) v = std::pow(v, 1.0 / p.beta_sch);
    return {q_ch[0], std::pow(std::pow(q_ch[0], p.beta_tch) + std::pow(q_ch[1], p.beta_tch), 1.0 / p.beta_tch)};
}

double jodFromQuality(double q, const Parameters& p) {
    return 10.0 - std::abs(p.jod_a) * std::pow(q, std::pow(10.0, p.log_jod_exp));
}

namespace {

constexpr float kA = 0.4f;
constexpr float kKernel[5] = {0.25f - kA / 2, 0.25f, kA, 0.25f, 0.25f - kA / 2};

// A 1-D resampling as taps: output i = sum of weight · input[index] over taps[i].
struct Taps {
    std::vector<int> first;  ///< taps of output i: [first[i], first[i + 1])
    std::vector<int> index;
    std::vector<float> weight;
    void add(int i, float w) {
        for (size_t t = size_t(first.back()); t < index.size(); ++t)
            if (index[t] == i) {
                weight[t] += w;
                return;
            }
        index.push_back(i);
        weight.push_back(w);
    }
    void close() { first.push_back(int(index.size())); }
};

// Reduction of n samples into ceil(n / 2): the kernel at every second sample, the borders mirrored
// (x[-1] = x[0], x[-2] = x[1], x[n] = x[n-1], x[n+1] = x[n-2]).
Taps reduceTaps(int n) {
    Taps t;
    t.first.push_back(0);
    for (int i = 0; i < (n + 1) / 2; ++i) {
        for (int k = 0; k < 5; ++k) {
            int j = 2 * i + k - 2;
            if (j < 0) j = -j - 1;
            if (j >= n) j = 2 * n - 1 - j;
            t.add(std::clamp(j, 0, n - 1), kKernel[k]);
        }
        t.close();
    }
    return t;
}

// Expansion of m samples to n: the samples at even positions, zeros between, the kernel times 2;
// beyond the ends u[-2] = x[0] and u[n] (n even) or u[n + 1] (n odd) = the last sample.
Taps expandTaps(int m, int n) {
    Taps t;
    t.first.push_back(0);
    for (int i = 0; i < n; ++i) {
        for (int k = 0; k < 5; ++k) {
            const int j = i + k - 2;
            int src = -1;
            if (j == -2)
                src = 0;
            else if (j >= n)
                src = (j == n + (n & 1)) ? m - 1 : -1;
            else if (j >= 0 && !(j & 1))
                src = j / 2;
            if (src >= 0) t.add(src, 2.0f * kKernel[k]);
        }
        t.close();
    }
    return t;
}

// Applies `rows` taps between rows (whole rows at once) and `cols` taps within each row.
void resample(const float* src, int sw, float* dst, int w, int h, const Taps& rows, const Taps& cols) {
    thread_local std::vector<float> tmp;  // kept per thread: no allocation per call after the first
    tmp.assign(size_t(sw) * size_t(h), 0.0f);
    for (int y = 0; y < h; ++y) {
        float* o = tmp.data() + size_t(y) * sw;
        for (int t = rows.first[size_t(y)]; t < rows.first[size_t(y) + 1]; ++t) {
            const float wt = rows.weight[size_t(t)];
            const float* in = src + size_t(rows.index[size_t(t)]) * sw;
            for (int x = 0; x < sw; ++x) o[x] += wt * in[x];
        }
    }
    for (int y = 0; y < h; ++y) {
        const float* in = tmp.data() + size_t(y) * sw;
        float* o = dst + size_t(y) * w;
        for (int x = 0; x < w; ++x) {
            float v = 0.0f;
            for (int t = cols.first[size_t(x)]; t < cols.first[size_t(x) + 1]; ++t)
                v += cols.weight[size_t(t)] * in[cols.index[size_t(t)]];
            o[x] = v;
        }
    }
}

}  // namespace

void pyramidReduce(const float* src, int w, int h, float* dst) {
    resample(src, w, dst, (w + 1) / 2, (h + 1) / 2, reduceTaps(h), reduceTaps(w));
}

void pyramidExpand(const float* src, int sw, int sh, float* dst, int w, int h) {
    resample(src, sw, dst, w, h, expandTaps(sh, h), expandTaps(sw, w));
}

}  // namespace detail

// ---------------------------------------------------------------------------------------------
// The metric
// ---------------------------------------------------------------------------------------------

Result<Metric> Metric::create(const Options& o) {
    const ViewGeometry& g = o.geometry;
    if (g.width < 8 || g.height < 8)
        return error(FvvdpError::InvalidOptions,
                     "geometry is " + sizeText(int(g.width), int(g.height)) + ", at least 8x8 pixels needed");
    const glm::vec4 t = g.fov_tan;
    if (!std::isfinite(t.x) || !std::isfinite(t.y) || !std::isfinite(t.z) || !std::isfinite(t.w) || !(t.y > t.x) ||
        !(t.z > t.w))
        return error(FvvdpError::InvalidOptions, "field of view tangents (left " + std::to_string(t.x) + ", right " +
                                                     std::to_string(t.y) + ", up " + std::to_string(t.z) + ", down " +
                                                     std::to_string(t.w) + ") span no area");
    if (!(o.fps > 0.0) || !std::isfinite(o.fps))
        return error(FvvdpError::InvalidOptions, "fps is " + std::to_string(o.fps) + ", must be finite and > 0");
    const DisplayPhotometry& d = o.photometry;
    if (!std::isfinite(d.peak) || !std::isfinite(d.contrast) || !std::isfinite(d.ambient_lux) ||
        !std::isfinite(d.reflectivity) || !(d.contrast > 1.0) || d.ambient_lux < 0 || d.reflectivity < 0 ||
        !(d.peak > d.black()))
        return error(FvvdpError::InvalidOptions, "display photometry (peak " + std::to_string(d.peak) +
                                                     " cd/m², contrast " + std::to_string(d.contrast) + ", ambient " +
                                                     std::to_string(d.ambient_lux) + " lux, reflectivity " +
                                                     std::to_string(d.reflectivity) + ") is not a display");

    Metric m;
    m.options_ = o;
    m.filters_ = detail::temporalFilters(o.fps);
    m.filter_len_ = int(m.filters_[0].size());

    // Bands: the reference's rule. Frequencies ppd/2, 0.3228 ppd/2 · 2^-k; the pyramid stops at the
    // first band at or below 0.5 cpd, and leaves at least a 4-pixel base.
    const double ppd = g.ppdCentre();
    const int w = int(g.width), h = int(g.height);
    const int max_levels = int(std::floor(std::log2(double(std::min(w, h))))) - 1;
    std::vector<double> freqs{ppd / 2.0};
    for (int k = 0; k < 14; ++k) freqs.push_back(0.3228 * std::pow(2.0, -k) * ppd / 2.0);
    int max_band = max_levels;
    for (size_t i = 0; i < freqs.size(); ++i)
        if (freqs[i] <= 0.5) {
            max_band = int(i);
            break;
        }
    const int nbands = std::clamp(max_band + 1, 0, max_levels);
    m.band_freq_.assign(freqs.begin(), freqs.begin() + nbands);

    // Per band: tangents of its pixel centres (the band covers the image) and the local resolution.
    int bw = w, bh = h;
    for (int b = 0; b < nbands; ++b) {
        BandGeometry bg;
        bg.w = bw;
        bg.h = bh;
        bg.tx.resize(size_t(bw));
        bg.ty.resize(size_t(bh));
        for (int x = 0; x < bw; ++x) bg.tx[size_t(x)] = t.x + (float(x) + 0.5f) / float(bw) * (t.y - t.x);
        for (int y = 0; y < bh; ++y) bg.ty[size_t(y)] = t.z - (float(y) + 0.5f) / float(bh) * (t.z - t.w);
        if (o.foveated) {
            bg.res_mag.resize(size_t(bw) * size_t(bh));
            for (int y = 0; y < bh; ++y)
                for (int x = 0; x < bw; ++x) {
                    const double angle = detail::eccentricityDeg(g.model, bg.tx[size_t(x)], bg.ty[size_t(y)], 0.0, 0.0);
                    bg.res_mag[size_t(y) * bw + x] = float(detail::resolutionMagnification(angle, ppd));
                }
        }
        m.bands_.push_back(std::move(bg));
        bw = (bw + 1) / 2;
        bh = (bh + 1) / 2;
    }
    for (int c = 0; c < 2; ++c) m.csf_table_[c] = detail::csfTable(detail::kChannelOmega[size_t(c)]);
    return m;
}

void Metric::reset() {
    window_test_.clear();
    window_ref_.clear();
    window_next_ = 0;
    frames_ = 0;
    sum_video_ = 0.0;
    q_image_ = 0.0;
    last_ = {};
    distortion_.release();
}

Status detail::checkInputImage(const cv::Mat& m, const char* what, const ViewGeometry& g) {
    if (m.empty()) return error(FvvdpError::InvalidInput, std::string(what) + " image is empty");
    if (m.type() != CV_32FC3)
        return error(FvvdpError::InvalidInput, std::string(what) +
                                                   " image must be CV_32FC3 (sRGB-encoded RGB in [0, 1]), got type " +
                                                   std::to_string(m.type()));
    if (m.cols != int(g.width) || m.rows != int(g.height))
        return error(FvvdpError::InvalidInput, std::string(what) + " image is " + sizeText(m.cols, m.rows) +
                                                   ", the geometry is " + sizeText(int(g.width), int(g.height)));
    if (std::string at = firstNonFinite(m); !at.empty())
        return error(FvvdpError::NonFinite, std::string(what) + " image has a non-finite value at pixel " + at);
    return Status::success();
}

Status detail::checkInputFrame(const cv::Mat& test, const cv::Mat& reference, glm::vec2 gaze_px, const ViewGeometry& g) {
    if (Status s = checkInputImage(test, "test", g); !s) return s;
    if (Status s = checkInputImage(reference, "reference", g); !s) return s;
    if (!std::isfinite(gaze_px.x) || !std::isfinite(gaze_px.y))
        return error(FvvdpError::InvalidInput,
                     "gaze (" + std::to_string(gaze_px.x) + ", " + std::to_string(gaze_px.y) + ") is not finite");
    return Status::success();
}

Status Metric::push(const cv::Mat& test, const cv::Mat& reference) {
    return push(test, reference, glm::vec2(float(options_.geometry.width / 2), float(options_.geometry.height / 2)));
}

Status Metric::push(const cv::Mat& test, const cv::Mat& reference, glm::vec2 gaze_px) {
    const ViewGeometry& g = options_.geometry;
    if (Status s = detail::checkInputFrame(test, reference, gaze_px, g); !s) return s;

    const int w = int(g.width), h = int(g.height);
    const float peak = float(options_.photometry.peak), black = float(options_.photometry.black());
    // Each channel's emitted luminance as detail::displayLuminance computes it; for the 256 values an
    // 8-bit image gives (code / 255.0f) from a table of the same expression (the same floats, without
    // a pow per channel), any other value directly.
    auto channel = [&](float v) { return (peak - black) * detail::srgbToLinear(std::clamp(v, 0.0f, 1.0f)) + black; };
    std::array<float, 256> lin;
    for (int k = 0; k < 256; ++k) lin[size_t(k)] = channel(float(k) / 255.0f);
    auto emitted = [&](float v) {
        if (v >= 0.0f && v <= 1.0f) {
            const int k = int(v * 255.0f + 0.5f);
            if (float(k) / 255.0f == v) return lin[size_t(k)];
        }
        return channel(v);
    };
    auto toLuminance = [&](const cv::Mat& img, Plane& out) {
        out.w = w;
        out.h = h;
        out.v.resize(size_t(w) * size_t(h));
        for (int y = 0; y < h; ++y) {
            const float* p = img.ptr<float>(y);
            float* o = out.v.data() + size_t(y) * w;
            for (int x = 0; x < w; ++x)
                o[x] = 0.2126729f * emitted(p[3 * x]) + 0.7151522f * emitted(p[3 * x + 1]) +
                       0.0721750f * emitted(p[3 * x + 2]);
        }
    };
    if (window_test_.empty()) {
        // First frame: replicated into the filters' past.
        Plane t, r;
        toLuminance(test, t);
        toLuminance(reference, r);
        window_test_.assign(size_t(filter_len_), t);
        window_ref_.assign(size_t(filter_len_), r);
        window_next_ = 0;
    } else {
        toLuminance(test, window_test_[size_t(window_next_)]);
        toLuminance(reference, window_ref_[size_t(window_next_)]);
        window_next_ = (window_next_ + 1) % filter_len_;
    }
    processFrame(gaze_px);
    return Status::success();
}

// One frame, in the order a compute version would run its passes: temporal filters (per pixel),
// pyramid reduction per level, then per band expansion, contrast, sensitivity, masking and a
// partial sum (per pixel, then reduced), the distortion map's collapse, and pooling (per frame).
void Metric::processFrame(glm::vec2 gaze_px) {
    const Parameters& p = kParameters;
    const ViewGeometry& g = options_.geometry;
    const int w = int(g.width), h = int(g.height);
    const size_t npix = size_t(w) * size_t(h);
    const int nb = int(bands_.size());

    // Temporal channels: 0 test sustained, 1 reference sustained, 2 test transient, 3 reference transient.
    // The newest frame sits just before window_next_ in the ring.
    Scratch& sc = scratch_;
    std::array<std::vector<float>, 4>& chan = sc.a;
    for (auto& c : chan) c.assign(npix, 0.0f);
    // In blocks of pixels that stay in cache over the window's frames (each pixel's sum still runs
    // from the newest frame to the oldest).
    std::vector<const float*> tvs(static_cast<size_t>(filter_len_)), rvs(static_cast<size_t>(filter_len_));
    for (int k = 0; k < filter_len_; ++k) {
        const int slot = ((window_next_ - 1 - k) % filter_len_ + filter_len_) % filter_len_;
        tvs[size_t(k)] = window_test_[size_t(slot)].v.data();
        rvs[size_t(k)] = window_ref_[size_t(slot)].v.data();
    }
    constexpr size_t kBlock = 2048;
    for (size_t i0 = 0; i0 < npix; i0 += kBlock) {
        const size_t i1 = std::min(npix, i0 + kBlock);
        float* c0 = chan[0].data();
        float* c1 = chan[1].data();
        float* c2 = chan[2].data();
        float* c3 = chan[3].data();
        for (int k = 0; k < filter_len_; ++k) {
            const float* tv = tvs[size_t(k)];
            const float* rv = rvs[size_t(k)];
            const float fs = filters_[0][size_t(k)], ft = filters_[1][size_t(k)];
            for (size_t i = i0; i < i1; ++i) {
                c0[i] += fs * tv[i];
                c1[i] += fs * rv[i];
                c2[i] += ft * tv[i];
                c3[i] += ft * rv[i];
            }
        }
    }

    // Gaze as tangents (the ray through the centre of the pixel looked at).
    const glm::vec4 t = g.fov_tan;
    const double gtx = t.x + (double(gaze_px.x) + 0.5) / w * (t.y - t.x);
    const double gty = t.z - (double(gaze_px.y) + 0.5) / h * (t.z - t.w);

    last_.band.assign(size_t(nb), {0.0, 0.0});
    // Gaussian level l of each channel; level l + 1 is made from it as the bands go down.
    std::array<std::vector<float>, 4>* cur = &sc.a;  // holds the temporal channels now
    std::array<std::vector<float>, 4>* next = &sc.b;
    std::vector<float>& expanded = sc.expanded;
    std::vector<float>& ecc = sc.ecc;
    std::vector<float>& rho = sc.rho;
    expanded.resize(npix);
    ecc.resize(npix);
    rho.resize(npix);
    std::array<std::vector<float>, 4>& band = sc.band;
    std::vector<std::vector<float>> dmap_bands(options_.distortion_map ? size_t(nb) : 0);
    for (int b = 0; b < nb; ++b) {
        const BandGeometry& bg = bands_[size_t(b)];
        const int bw = bg.w, bh = bg.h, nw = (bw + 1) / 2, nh = (bh + 1) / 2;
        const size_t n = size_t(bw) * size_t(bh);
        for (int c = 0; c < 4; ++c) {
            (*next)[size_t(c)].resize(size_t(nw) * size_t(nh));
            detail::pyramidReduce((*cur)[size_t(c)].data(), bw, bh, (*next)[size_t(c)].data());
        }
        // Laplacian bands; the background luminance is the expanded next level of the reference's
        // sustained channel.
        std::vector<float>& l_bkg = sc.l_bkg;
        l_bkg.resize(n);  // every value written by the expansion
        detail::pyramidExpand((*next)[1].data(), nw, nh, l_bkg.data(), bw, bh);
        for (int c = 0; c < 4; ++c) {
            band[size_t(c)].resize(n);
            if (c != 1) detail::pyramidExpand((*next)[size_t(c)].data(), nw, nh, expanded.data(), bw, bh);
            const float* e = c == 1 ? l_bkg.data() : expanded.data();
            const float* cv = (*cur)[size_t(c)].data();
            for (size_t i = 0; i < n; ++i) band[size_t(c)][i] = cv[i] - e[i];
        }
        // Contrast: band / max(background, 0.1), capped at 1000; bands between the finest and the
        // base are doubled (the decimated pyramid's gain).
        const float band_mul = b == 0 ? 1.0f : 2.0f;
        for (size_t i = 0; i < n; ++i) l_bkg[i] = std::max(l_bkg[i], 0.1f);
        for (int c = 0; c < 4; ++c)
            for (size_t i = 0; i < n; ++i)
                band[size_t(c)][i] = std::min(band[size_t(c)][i] / l_bkg[i], 1000.0f) * band_mul;

        // Eccentricity and local frequency of each pixel.
        const bool fov = options_.foveated;
        if (fov) {
            for (int y = 0; y < bh; ++y) {
                const double ty = bg.ty[size_t(y)];
                for (int x = 0; x < bw; ++x) {
                    ecc[size_t(y) * bw + x] = float(detail::eccentricityDeg(g.model, bg.tx[size_t(x)], ty, gtx, gty));
                    rho[size_t(y) * bw + x] = float(band_freq_[size_t(b)]) * bg.res_mag[size_t(y) * bw + x];
                }
            }
        }
        const float gain = float(std::pow(10.0, p.sensitivity_correction / 20.0));
        for (int cc = 0; cc < 2; ++cc) {
            const float q = float(cc == 0 ? p.mask_q_sust : p.mask_q_trans);
            const float mask_p = float(p.mask_p), mask_gain = float(std::pow(10.0, p.mask_c)), beta = float(p.beta);
            const float* tb = band[size_t(2 * cc)].data();
            const float* rb = band[size_t(2 * cc + 1)].data();
            double sum = 0.0;
            float* dmap = nullptr;
            if (options_.distortion_map) {
                // The map's band: the sustained D plus the weighted transient D, without the
                // pyramid's gain (the reference's raw heat map).
                auto& db = dmap_bands[size_t(b)];
                if (cc == 0) db.assign(n, 0.0f);
                dmap = db.data();
            }
            const float dmap_w = (cc == 0 ? 1.0f : float(p.w_transient)) / band_mul;
            for (size_t i = 0; i < n; ++i) {
                const float s = gain * detail::csfLookup(csf_table_[cc], fov ? rho[i] : float(band_freq_[size_t(b)]),
                                                         l_bkg[i], fov ? ecc[i] : 0.0f);
                const float d = detail::maskedDifference(tb[i] * s, rb[i] * s, mask_p, q, mask_gain);
                if (d > 0.0f) sum += double(std::pow(d, beta));
                if (dmap) dmap[i] += dmap_w * d;
            }
            last_.band[size_t(b)][size_t(cc)] = std::pow(sum / double(n), 1.0 / p.beta);
        }
        std::swap(cur, next);
    }

    if (options_.distortion_map) {
        // Collapse the map's pyramid (a zero base band), then to JOD units: |jod_a| · D^(10^log_jod_exp).
        std::vector<float> img, up;
        int iw = 0, ih = 0;
        if (nb > 0) {
            iw = (bands_.back().w + 1) / 2;
            ih = (bands_.back().h + 1) / 2;
            img.assign(size_t(iw) * size_t(ih), 0.0f);
        }
        for (int b = nb - 1; b >= 0; --b) {
            const BandGeometry& bg = bands_[size_t(b)];
            up.resize(size_t(bg.w) * size_t(bg.h));
            detail::pyramidExpand(img.data(), iw, ih, up.data(), bg.w, bg.h);
            for (size_t i = 0; i < up.size(); ++i) up[i] += dmap_bands[size_t(b)][i];
            std::swap(img, up);
            iw = bg.w;
            ih = bg.h;
        }
        distortion_.create(h, w, CV_32F);
        const float a = float(std::abs(p.jod_a)), e = float(std::pow(10.0, p.log_jod_exp));
        for (int y = 0; y < h; ++y)
            for (int x = 0; x < w; ++x)
                distortion_.at<float>(y, x) = nb > 0 ? a * std::pow(img[size_t(y) * w + x], e) : 0.0f;
    }

    const std::array<double, 2> q = detail::poolFrame(last_);
    if (frames_ == 0) q_image_ = q[0];
    const double q_frame = q[1];
    sum_video_ += std::pow(q_frame, p.beta_t);
    ++frames_;
}

Result<double> Metric::jod() const {
    if (frames_ == 0) return error(FvvdpError::NoFrames, "no frames pushed yet");
    const Parameters& p = kParameters;
    const double q = frames_ == 1 ? q_image_ : std::pow(sum_video_ / double(frames_), 1.0 / p.beta_t);
    return detail::jodFromQuality(q);
}

Result<double> score(const std::vector<cv::Mat>& test, const std::vector<cv::Mat>& reference,
                     const std::vector<glm::vec2>& gaze_px, const Options& options) {
    if (test.size() != reference.size())
        return error(FvvdpError::InvalidInput, std::to_string(test.size()) + " test frames, " +
                                                   std::to_string(reference.size()) + " reference frames");
    if (!gaze_px.empty() && gaze_px.size() != test.size())
        return error(FvvdpError::InvalidInput,
                     std::to_string(gaze_px.size()) + " gaze points for " + std::to_string(test.size()) + " frames");
    auto metric = Metric::create(options);
    if (!metric) return metric.error();
    for (size_t f = 0; f < test.size(); ++f)
        if (Status s =
                gaze_px.empty() ? metric->push(test[f], reference[f]) : metric->push(test[f], reference[f], gaze_px[f]);
            !s)
            return Error{s.error().code, s.error().message + " (frame " + std::to_string(f) + ")"};
    return metric->jod();
}

}  // namespace wrsfov::eval::fvvdp
