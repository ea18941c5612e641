#include "gaze/stats.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace wrsfov::gaze {

double median(std::vector<double> v) {
    if (v.empty()) return 0;
    std::sort(v.begin(), v.end());
    const size_t m = v.size() / 2;
    return v.size() % 2 ? v[m] : 0.5 * (v[m - 1] + v[m]);
}

MainSequenceFit fit_main_sequence(std::span<const DetectedEvent> events, double ref_eta, double ref_c) {
    MainSequenceFit fit;
    std::vector<double> a, vp;
    for (const DetectedEvent& e : events) {
        if (!e.clean || !(e.amplitude_deg > 0) || !(e.peak_velocity_deg_s > 0)) continue;
        a.push_back(e.amplitude_deg);
        vp.push_back(e.peak_velocity_deg_s);
    }
    fit.n = a.size();
    if (fit.n < 3) return fit;
    std::vector<double> ratios;
    double sa = 0, sv = 0;
    for (size_t i = 0; i < fit.n; ++i) {
        ratios.push_back(vp[i] / (ref_eta * (1 - std::exp(-a[i] / ref_c))));
        sa += std::log(a[i]);
        sv += std::log(vp[i]);
    }
    fit.median_ratio_to_reference = median(ratios);
    const double ma = sa / fit.n, mv = sv / fit.n;
    double cov = 0, va = 0, vv = 0;
    for (size_t i = 0; i < fit.n; ++i) {
        const double da = std::log(a[i]) - ma, dv = std::log(vp[i]) - mv;
        cov += da * dv;
        va += da * da;
        vv += dv * dv;
    }
    fit.log_correlation = va > 0 && vv > 0 ? cov / std::sqrt(va * vv) : 0;
    // For a fixed c, the best log(eta) is the mean residual; search c on a log grid.
    double best = 1e300;
    for (double c = 0.2; c <= 40; c *= 1.01) {
        double s = 0;
        for (size_t i = 0; i < fit.n; ++i) s += std::log(vp[i]) - std::log(1 - std::exp(-a[i] / c));
        const double log_eta = s / fit.n;
        double sse = 0;
        for (size_t i = 0; i < fit.n; ++i) {
            const double r = std::log(vp[i]) - log_eta - std::log(1 - std::exp(-a[i] / c));
            sse += r * r;
        }
        if (sse < best) {
            best = sse;
            fit.c_deg = c;
            fit.eta_deg_s = std::exp(log_eta);
        }
    }
    fit.log_rmse = std::sqrt(best / fit.n);
    return fit;
}

ReadingStats analyse_reading(const IvtResult& ivt, const ReadingLayout& layout) {
    ReadingStats r;
    std::vector<double> fwd, reg;
    const double half_line = 0.5 * layout.line_spacing_deg;
    for (const DetectedEvent& s : ivt.saccades) {
        const double dx_chars = s.dx_deg / layout.char_deg;
        if (s.dy_deg < -half_line && s.dx_deg < 0) {
            ++r.return_sweeps;
        } else if (s.dy_deg > half_line) {
            ++r.page_turns;
        } else if (std::abs(s.dy_deg) <= half_line && dx_chars > 0) {
            ++r.forward;
            fwd.push_back(dx_chars);
        } else if (std::abs(s.dy_deg) <= half_line && dx_chars < 0) {
            ++r.regressions;
            reg.push_back(-dx_chars);
        }
    }
    r.median_forward_chars = median(fwd);
    r.median_regression_chars = median(reg);
    if (r.forward + r.regressions > 0)
        r.regression_fraction = static_cast<double>(r.regressions) / static_cast<double>(r.forward + r.regressions);
    // For every line change the tracker saw (consecutive fixations one line lower, no blink in
    // between), count the return sweeps between the two fixations: reading has exactly one.
    constexpr double kMaxSaccadeGap = 0.15;
    size_t sweeps_in_changes = 0;
    for (size_t i = 1; i < ivt.fixations.size(); ++i) {
        const DetectedEvent &a = ivt.fixations[i - 1], &b = ivt.fixations[i];
        const double dy = b.cy_deg - a.cy_deg;
        if (!(b.t0_s - a.t1_s < kMaxSaccadeGap && dy < -half_line && dy > -1.5 * layout.line_spacing_deg)) continue;
        ++r.line_changes;
        for (const DetectedEvent& s : ivt.saccades) {
            if (s.begin + 1 < a.end || s.end > b.begin + 1) continue;
            if (s.dy_deg < -half_line && s.dx_deg < 0) ++sweeps_in_changes;
        }
    }
    if (r.line_changes > 0)
        r.sweeps_per_line_change = static_cast<double>(sweeps_in_changes) / static_cast<double>(r.line_changes);
    return r;
}

GazeStats compute_stats(std::span<const GazeSample> samples, const StatsOptions& o) {
    GazeStats s;
    s.samples = samples.size();
    if (samples.empty()) return s;
    const AngleTrace tr = to_angle_trace(samples);
    s.duration_s = tr.t_s.back() - tr.t_s.front() + tr.dt_s;
    s.rate_hz = tr.dt_s > 0 ? 1.0 / tr.dt_s : 0;
    size_t nvalid = 0;
    for (uint8_t v : tr.valid) nvalid += v;
    s.valid_fraction = static_cast<double>(nvalid) / static_cast<double>(tr.size());
    s.valid_s = static_cast<double>(nvalid) * tr.dt_s;

    s.ivt = detect_ivt(tr, o.ivt);
    s.ek = detect_microsaccades(tr, o.ek);
    const double minutes = s.duration_s / 60.0;

    s.blinks = s.ivt.blinks.size();
    s.dropouts = s.ivt.dropouts;
    s.blinks_per_minute = minutes > 0 ? static_cast<double>(s.blinks) / minutes : 0;
    std::vector<double> v;
    for (const DetectedEvent& b : s.ivt.blinks) v.push_back(b.duration_s() * 1e3);
    s.median_blink_ms = median(v);

    // Microsaccades are the E&K events that lie inside fixations (not parts of saccades).
    std::vector<DetectedEvent> micro;
    double fix_time = 0;
    for (const DetectedEvent& f : s.ivt.fixations) fix_time += f.duration_s();
    {
        size_t fi = 0;
        for (const DetectedEvent& m : s.ek.microsaccades) {
            while (fi < s.ivt.fixations.size() && s.ivt.fixations[fi].end <= m.begin) ++fi;
            if (fi < s.ivt.fixations.size() && s.ivt.fixations[fi].begin <= m.begin && m.end <= s.ivt.fixations[fi].end)
                micro.push_back(m);
        }
    }
    s.microsaccades = micro.size();
    s.microsaccade_rate_hz = fix_time > 0 ? static_cast<double>(micro.size()) / fix_time : 0;
    v.clear();
    std::vector<double> d;
    for (const DetectedEvent& m : micro) {
        v.push_back(m.amplitude_deg * 60);
        d.push_back(m.duration_s() * 1e3);
    }
    s.median_microsaccade_arcmin = median(v);
    s.median_microsaccade_ms = median(d);
    s.ek_sigma_x = s.ek.sigma_x;
    s.ek_sigma_y = s.ek.sigma_y;
    s.microsaccade_fit = fit_main_sequence(micro);

    s.saccades = s.ivt.saccades.size();
    s.saccade_rate_hz = s.valid_s > 0 ? static_cast<double>(s.saccades) / s.valid_s : 0;
    v.clear();
    d.clear();
    size_t le15 = 0;
    for (const DetectedEvent& e : s.ivt.saccades) {
        v.push_back(e.amplitude_deg);
        d.push_back(e.duration_s() * 1e3);
        le15 += e.amplitude_deg <= 15 ? 1 : 0;
    }
    s.median_saccade_deg = median(v);
    s.median_saccade_ms = median(d);
    s.fraction_saccades_le_15 = s.saccades ? static_cast<double>(le15) / static_cast<double>(s.saccades) : 0;
    s.saccade_fit = fit_main_sequence(s.ivt.saccades);

    s.fixations = s.ivt.fixations.size();
    v.clear();
    double sum = 0;
    for (const DetectedEvent& f : s.ivt.fixations) {
        v.push_back(f.duration_s() * 1e3);
        sum += f.duration_s() * 1e3;
    }
    s.median_fixation_ms = median(v);
    s.mean_fixation_ms = s.fixations ? sum / static_cast<double>(s.fixations) : 0;
    s.pursuits = s.ivt.pursuits.size();
    v.clear();
    for (const DetectedEvent& p : s.ivt.pursuits) v.push_back(p.peak_velocity_deg_s);
    s.median_pursuit_speed_deg_s = median(v);
    if (o.reading) s.reading = analyse_reading(s.ivt, *o.reading);
    return s;
}

std::string format_stats(const GazeStats& s) {
    std::string out;
    char buf[256];
    auto line = [&](const char* name, const std::string& measured, const char* published) {
        std::snprintf(buf, sizeof buf, "  %-38s %-18s %s\n", name, measured.c_str(), published);
        out += buf;
    };
    auto num = [](double x, int prec = 2) {
        char b[64];
        std::snprintf(b, sizeof b, "%.*f", prec, x);
        return std::string(b);
    };
    std::snprintf(buf, sizeof buf,
                  "samples %zu, %.2f s at %.0f Hz, %.1f %% valid, %zu blinks (%.1f /min), %zu dropouts\n", s.samples,
                  s.duration_s, s.rate_hz, 100 * s.valid_fraction, s.blinks, s.blinks_per_minute, s.dropouts);
    out += buf;
    std::snprintf(buf, sizeof buf, "  %-38s %-18s %s\n", "quantity", "measured", "published");
    out += buf;
    line("blink rate (/min)", num(s.blinks_per_minute, 1), "15-20 (approximate)");
    line("median blink (ms)", num(s.median_blink_ms, 0), "100-400");
    line("microsaccades (E&K lambda=6)", std::to_string(s.microsaccades), "");
    line("microsaccade rate (/s of fixation)", num(s.microsaccade_rate_hz), "1-3 (Engbert; Martinez-Conde 2009)");
    line("median microsaccade amplitude (')", num(s.median_microsaccade_arcmin, 1), "5-20, Gamma mean 8' (<= 1 deg)");
    line("median microsaccade duration (ms)", num(s.median_microsaccade_ms, 1), "6-30");
    line("microsaccade main-seq r (log-log)", num(s.microsaccade_fit.log_correlation), ">= 0.8 (main sequence)");
    line("E&K velocity SD x/y (deg/s)", num(s.ek_sigma_x) + "/" + num(s.ek_sigma_y), "");
    line("saccades (I-VT 30 deg/s)", std::to_string(s.saccades), "");
    line("saccade rate (/s)", num(s.saccade_rate_hz), "~3 in scene viewing");
    line("median saccade amplitude (deg)", num(s.median_saccade_deg), "~4, most <= 15 (Bahill 1975)");
    line("saccades <= 15 deg (%)", num(100 * s.fraction_saccades_le_15, 1), "most");
    line("median saccade duration (ms)", num(s.median_saccade_ms, 1), "2.2 A + 21");
    line("main sequence fit eta (deg/s)", num(s.saccade_fit.eta_deg_s, 0), "300-900, ~600 (Dai 2016)");
    line("main sequence fit c (deg)", num(s.saccade_fit.c_deg, 2), "4.5-7.5, ~6 (Dai 2016)");
    line("median Vp / Dai(600, 6)", num(s.saccade_fit.median_ratio_to_reference, 3), "1 +- 0.2");
    line("fixations", std::to_string(s.fixations), "");
    line("median fixation (ms)", num(s.median_fixation_ms, 0), "scene ~330; reading 225-250 (Rayner 1998)");
    line("mean fixation (ms)", num(s.mean_fixation_ms, 0), "");
    if (s.pursuits) {
        line("pursuit segments (I-VVT)", std::to_string(s.pursuits), "");
        line("median pursuit speed (deg/s)", num(s.median_pursuit_speed_deg_s, 1), "gain 0.8-1.0 x target speed");
    }
    if (s.reading) {
        const ReadingStats& r = *s.reading;
        line("forward saccades", std::to_string(r.forward), "");
        line("median forward saccade (chars)", num(r.median_forward_chars, 1), "7-9 (Rayner 1998)");
        line("regressions (%)", num(100 * r.regression_fraction, 1), "10-15 (Rayner 1998)");
        line("median regression (chars)", num(r.median_regression_chars, 1), "");
        line("return sweeps", std::to_string(r.return_sweeps), "one per line");
        line("return sweeps per line change", num(r.sweeps_per_line_change, 2), "1");
        line("page turns", std::to_string(r.page_turns), "");
    }
    return out;
}

}  // namespace wrsfov::gaze
