#include "gaze/detect.h"

#include <algorithm>
#include <cmath>

#include "gaze/angles.h"

namespace wrsfov::gaze {

namespace {

double median_of(std::vector<double> v) {
    if (v.empty()) return 0;
    const size_t mid = v.size() / 2;
    std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(mid), v.end());
    double m = v[mid];
    if (v.size() % 2 == 0) m = 0.5 * (m + *std::max_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(mid)));
    return m;
}

struct Run {
    size_t begin, end;
};

std::vector<Run> runs_of(const std::vector<uint8_t>& flag) {
    std::vector<Run> out;
    size_t i = 0;
    while (i < flag.size()) {
        if (!flag[i]) {
            ++i;
            continue;
        }
        size_t j = i;
        while (j < flag.size() && flag[j]) ++j;
        out.push_back({i, j});
        i = j;
    }
    return out;
}

bool window_valid(const AngleTrace& tr, size_t begin, size_t end, size_t margin) {
    const size_t b = begin >= margin ? begin - margin : 0;
    const size_t e = std::min(tr.size(), end + margin);
    if (begin < margin || end + margin > tr.size()) return false;
    for (size_t i = b; i < e; ++i)
        if (!tr.valid[i]) return false;
    return true;
}

void fill_geometry(const AngleTrace& tr, const Velocity& v, DetectedEvent& ev) {
    ev.t0_s = tr.t_s[ev.begin];
    ev.t1_s = tr.t_s[ev.end - 1] + tr.dt_s;
    ev.dx_deg = tr.az_deg[ev.end - 1] - tr.az_deg[ev.begin];
    ev.dy_deg = tr.el_deg[ev.end - 1] - tr.el_deg[ev.begin];
    double peak = 0, sx = 0, sy = 0;
    size_t n = 0;
    for (size_t i = ev.begin; i < ev.end; ++i) {
        if (v.vvalid[i]) peak = std::max(peak, std::hypot(v.vx[i], v.vy[i]));
        if (tr.valid[i]) {
            sx += tr.az_deg[i];
            sy += tr.el_deg[i];
            ++n;
        }
    }
    ev.peak_velocity_deg_s = peak;
    if (n > 0) {
        ev.cx_deg = sx / static_cast<double>(n);
        ev.cy_deg = sy / static_cast<double>(n);
    }
}

}  // namespace

AngleTrace to_angle_trace(std::span<const GazeSample> samples) {
    AngleTrace tr;
    tr.t_s.reserve(samples.size());
    tr.az_deg.reserve(samples.size());
    tr.el_deg.reserve(samples.size());
    tr.valid.reserve(samples.size());
    for (const GazeSample& s : samples) {
        glm::vec3 d;
        const bool ok = cyclopean_direction(s, d);
        const GazeAngle a = ok ? angle_from_direction(d) : GazeAngle{};
        tr.t_s.push_back(s.t_s);
        tr.az_deg.push_back(a.az_deg);
        tr.el_deg.push_back(a.el_deg);
        tr.valid.push_back(ok ? 1 : 0);
    }
    std::vector<double> dts;
    for (size_t i = 1; i < tr.size(); ++i)
        if (tr.t_s[i] > tr.t_s[i - 1]) dts.push_back(tr.t_s[i] - tr.t_s[i - 1]);
    tr.dt_s = median_of(std::move(dts));
    return tr;
}

Velocity velocity_5pt(const AngleTrace& tr) {
    const size_t n = tr.size();
    Velocity v;
    v.vx.assign(n, 0);
    v.vy.assign(n, 0);
    v.vvalid.assign(n, 0);
    if (n < 5 || !(tr.dt_s > 0)) return v;
    for (size_t i = 2; i + 2 < n; ++i) {
        if (!(tr.valid[i - 2] && tr.valid[i - 1] && tr.valid[i + 1] && tr.valid[i + 2])) continue;
        // The time sum is 6 dt for uniform sampling; using it handles jitter, and a window that
        // spans a gap in the recording is not a velocity.
        const double tsum = tr.t_s[i + 2] + tr.t_s[i + 1] - tr.t_s[i - 1] - tr.t_s[i - 2];
        if (!(tsum > 0) || tsum > 9 * tr.dt_s) continue;
        v.vx[i] = (tr.az_deg[i + 2] + tr.az_deg[i + 1] - tr.az_deg[i - 1] - tr.az_deg[i - 2]) / tsum;
        v.vy[i] = (tr.el_deg[i + 2] + tr.el_deg[i + 1] - tr.el_deg[i - 1] - tr.el_deg[i - 2]) / tsum;
        v.vvalid[i] = 1;
    }
    return v;
}

EngbertKlieglResult detect_microsaccades(const AngleTrace& tr, const EngbertKlieglParams& p) {
    EngbertKlieglResult out;
    const Velocity v = velocity_5pt(tr);
    std::vector<double> vx, vy, vx2, vy2;
    for (size_t i = 0; i < tr.size(); ++i) {
        if (!v.vvalid[i]) continue;
        vx.push_back(v.vx[i]);
        vy.push_back(v.vy[i]);
        vx2.push_back(v.vx[i] * v.vx[i]);
        vy2.push_back(v.vy[i] * v.vy[i]);
    }
    if (vx.size() < 10) return out;
    const double mx = median_of(vx), my = median_of(vy);
    out.sigma_x = std::sqrt(std::max(0.0, median_of(vx2) - mx * mx));
    out.sigma_y = std::sqrt(std::max(0.0, median_of(vy2) - my * my));
    // A noiseless signal would make every movement a detection; keep a floor far below real noise.
    constexpr double kMinSigma = 1e-3;
    out.eta_x = p.lambda * std::max(out.sigma_x, kMinSigma);
    out.eta_y = p.lambda * std::max(out.sigma_y, kMinSigma);

    std::vector<uint8_t> above(tr.size(), 0);
    for (size_t i = 0; i < tr.size(); ++i) {
        if (!v.vvalid[i]) continue;
        const double ex = v.vx[i] / out.eta_x, ey = v.vy[i] / out.eta_y;
        above[i] = ex * ex + ey * ey > 1 ? 1 : 0;
    }
    std::vector<Run> runs = runs_of(above);
    // Merge runs separated by a short, fully valid gap (overshoot of one movement).
    std::vector<Run> merged;
    for (const Run& r : runs) {
        if (!merged.empty()) {
            Run& last = merged.back();
            const bool gap_valid =
                std::all_of(v.vvalid.begin() + static_cast<std::ptrdiff_t>(last.end),
                            v.vvalid.begin() + static_cast<std::ptrdiff_t>(r.begin), [](uint8_t f) { return f != 0; });
            if (gap_valid && tr.t_s[r.begin] - tr.t_s[last.end - 1] <= p.merge_gap_s) {
                last.end = r.end;
                continue;
            }
        }
        merged.push_back(r);
    }
    const size_t min_n = std::max<size_t>(
        p.min_samples, static_cast<size_t>(std::ceil(p.min_duration_s / std::max(tr.dt_s, 1e-9) - 1e-9)));
    for (const Run& r : merged) {
        if (r.end - r.begin < min_n) continue;
        DetectedEvent ev;
        ev.type = Event::Microsaccade;
        ev.begin = r.begin;
        ev.end = r.end;
        fill_geometry(tr, v, ev);
        // Amplitude as in Engbert & Kliegl: the extent of the movement along each axis, signed by
        // the order of its extremes.
        size_t ixmin = r.begin, ixmax = r.begin, iymin = r.begin, iymax = r.begin;
        for (size_t i = r.begin; i < r.end; ++i) {
            if (tr.az_deg[i] < tr.az_deg[ixmin]) ixmin = i;
            if (tr.az_deg[i] > tr.az_deg[ixmax]) ixmax = i;
            if (tr.el_deg[i] < tr.el_deg[iymin]) iymin = i;
            if (tr.el_deg[i] > tr.el_deg[iymax]) iymax = i;
        }
        const double ax = tr.az_deg[ixmax] - tr.az_deg[ixmin];
        const double ay = tr.el_deg[iymax] - tr.el_deg[iymin];
        ev.amplitude_deg = std::hypot(ax, ay);
        if (ev.amplitude_deg > p.max_amplitude_deg) continue;
        ev.clean = window_valid(tr, r.begin, r.end, 3);
        out.microsaccades.push_back(ev);
    }
    return out;
}

IvtResult detect_ivt(const AngleTrace& tr, const IvtParams& p) {
    IvtResult out;
    const size_t n = tr.size();
    if (n == 0) return out;
    const Velocity v = velocity_5pt(tr);
    std::vector<double> speed(n, 0);
    std::vector<uint8_t> fast(n, 0);
    for (size_t i = 0; i < n; ++i) {
        if (!v.vvalid[i]) continue;
        speed[i] = std::hypot(v.vx[i], v.vy[i]);
        fast[i] = speed[i] > p.saccade_threshold_deg_s ? 1 : 0;
    }
    const double floor_speed = 0.25 * p.saccade_threshold_deg_s;
    std::vector<Run> sacc;
    for (Run r : runs_of(fast)) {
        while (r.begin > 0 && v.vvalid[r.begin - 1] && speed[r.begin - 1] < speed[r.begin] &&
               speed[r.begin - 1] > floor_speed)
            --r.begin;
        while (r.end < n && v.vvalid[r.end] && speed[r.end] < speed[r.end - 1] && speed[r.end] > floor_speed) ++r.end;
        if (!sacc.empty() && r.begin <= sacc.back().end) {
            sacc.back().end = std::max(sacc.back().end, r.end);
            continue;
        }
        sacc.push_back(r);
    }
    std::vector<uint8_t> in_saccade(n, 0);
    for (const Run& r : sacc) {
        DetectedEvent ev;
        ev.type = Event::Saccade;
        ev.begin = r.begin;
        ev.end = r.end;
        fill_geometry(tr, v, ev);
        ev.amplitude_deg = std::hypot(ev.dx_deg, ev.dy_deg);
        ev.clean = window_valid(tr, r.begin, r.end, 3);
        out.saccades.push_back(ev);
        std::fill(in_saccade.begin() + static_cast<std::ptrdiff_t>(r.begin),
                  in_saccade.begin() + static_cast<std::ptrdiff_t>(r.end), 1);
    }

    // Inter-saccadic segments of valid samples.
    std::vector<uint8_t> slow(n, 0);
    for (size_t i = 0; i < n; ++i) slow[i] = tr.valid[i] && !in_saccade[i] ? 1 : 0;
    for (const Run& r : runs_of(slow)) {
        DetectedEvent ev;
        ev.begin = r.begin;
        ev.end = r.end;
        fill_geometry(tr, v, ev);
        if (ev.duration_s() < p.min_fixation_s) continue;
        ev.amplitude_deg = std::hypot(ev.dx_deg, ev.dy_deg);
        ev.clean = r.begin > 0 && r.end < n && in_saccade[r.begin - 1] && in_saccade[r.end];
        std::vector<double> sp;
        for (size_t i = r.begin; i < r.end; ++i)
            if (v.vvalid[i]) sp.push_back(speed[i]);
        const double med = median_of(std::move(sp));
        if (p.pursuit_threshold_deg_s > 0 && med > p.pursuit_threshold_deg_s) {
            ev.type = Event::Pursuit;
            ev.peak_velocity_deg_s = med;  // for pursuit, the typical speed is what matters
            out.pursuits.push_back(ev);
        } else {
            ev.type = Event::Fixation;
            out.fixations.push_back(ev);
        }
    }

    std::vector<uint8_t> invalid(n, 0);
    for (size_t i = 0; i < n; ++i) invalid[i] = tr.valid[i] ? 0 : 1;
    for (const Run& r : runs_of(invalid)) {
        const double t1 = r.end < n ? tr.t_s[r.end] : tr.t_s[r.end - 1] + tr.dt_s;
        const double t0 = r.begin > 0 ? tr.t_s[r.begin - 1] + tr.dt_s : tr.t_s[r.begin];
        const double len = t1 - t0;
        if (len >= p.blink_min_s && len <= p.blink_max_s) {
            DetectedEvent ev;
            ev.type = Event::Blink;
            ev.begin = r.begin;
            ev.end = r.end;
            ev.t0_s = t0;
            ev.t1_s = t1;
            out.blinks.push_back(ev);
        } else {
            ++out.dropouts;
        }
    }
    return out;
}

}  // namespace wrsfov::gaze
