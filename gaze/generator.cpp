#include "gaze/generator.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <opencv2/core.hpp>
#include <string>

#include "gaze/random.h"

namespace wrsfov::gaze {

namespace {

constexpr double kSimDt = 0.25e-3;  // 4 kHz: four grid points per sample at the fastest tracker rate
constexpr double kPi = std::numbers::pi;

uint64_t splitmix64(uint64_t x) {
    x += 0x9E3779B97F4A7C15ull;
    x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ull;
    x = (x ^ (x >> 27)) * 0x94D049BB133111EBull;
    return x ^ (x >> 31);
}

// One independent stream per component keeps, e.g., the trajectory unchanged when only the
// tracker noise changes.
cv::RNG make_stream(uint64_t seed, uint64_t stream) {
    uint64_t s = splitmix64(seed ^ splitmix64(stream));
    return cv::RNG(s == 0 ? 1 : s);
}

// Peak-to-mean velocity ratio of the profile v(s) ~ (s (1 - s))^k on s in [0, 1]:
// 4^-k / B(k + 1, k + 1).
double profile_ratio(double k) {
    return std::exp(-k * std::log(4.0) + std::lgamma(2 * k + 2) - 2 * std::lgamma(k + 1));
}

double solve_profile_exponent(double ratio) {
    double lo = 0.25, hi = 8.0;
    if (ratio <= profile_ratio(lo)) return lo;
    if (ratio >= profile_ratio(hi)) return hi;
    for (int i = 0; i < 60; ++i) {
        const double mid = 0.5 * (lo + hi);
        (profile_ratio(mid) < ratio ? lo : hi) = mid;
    }
    return 0.5 * (lo + hi);
}

struct Vec2 {
    double x = 0, y = 0;
};
Vec2 operator+(Vec2 a, Vec2 b) { return {a.x + b.x, a.y + b.y}; }
Vec2 operator-(Vec2 a, Vec2 b) { return {a.x - b.x, a.y - b.y}; }
Vec2 operator*(Vec2 a, double s) { return {a.x * s, a.y * s}; }
double norm(Vec2 a) { return std::hypot(a.x, a.y); }

// Simulates the cyclopean eye on a fine grid. Angles: x = azimuth, y = elevation, degrees.
class Simulator {
public:
    Simulator(const GeneratorConfig& cfg, cv::RNG& rng)
        : cfg_(cfg), rng_(rng), total_(static_cast<size_t>(std::ceil(cfg.seconds / kSimDt)) + 2) {
        x_.reserve(total_);
        y_.reserve(total_);
        label_.reserve(total_);
    }

    bool done() const { return x_.size() >= total_; }
    double now() const { return static_cast<double>(x_.size()) * kSimDt; }
    Vec2 pos() const { return pos_; }
    void set_anchor(Vec2 a) { anchor_ = a; }
    void restart_microsaccade_clock() { next_ms_ = now() + next_ms_interval(); }

    // Fixational eye movements (drift + microsaccades) around the anchor until `until`.
    void fixate(double until, Event drift_label) {
        while (!done() && now() < until) {
            if (now() >= next_ms_) {
                microsaccade();
                next_ms_ = now() + next_ms_interval();
                continue;
            }
            drift_step(true);
            record(drift_label);
        }
    }

    // A saccade executed from a planned vector, with landing gain and scatter along and across
    // the movement (`perp_sd_deg` < 0: the same relative scatter as along it).
    void planned_saccade(Vec2 planned, double perp_sd_deg = -1) {
        const double a = norm(planned);
        if (a < 1e-9) return;
        const Vec2 u = planned * (1.0 / a), perp{-u.y, u.x};
        const SaccadeModel& m = cfg_.saccade;
        const double perp_sd = perp_sd_deg < 0 ? m.landing_sd * a : perp_sd_deg;
        const Vec2 executed =
            planned * m.landing_gain + u * rng_.gaussian(m.landing_sd * a) + perp * rng_.gaussian(perp_sd);
        saccade(executed, Event::Saccade, {0, 0});
    }

    // Moves the eye by `vec` along the main sequence; `carry` is a pursuit velocity that keeps
    // acting underneath (catch-up saccades).
    void saccade(Vec2 vec, Event type, Vec2 carry) {
        const double a = norm(vec);
        if (a < 1e-9 || done()) return;
        const MainSequence& ms = cfg_.saccade.main;
        const double eta = ms.eta_deg_s * std::exp(rng_.gaussian(cfg_.saccade.velocity_jitter));
        const double vp = eta * (1 - std::exp(-a / ms.c_deg));
        // Keep the peak on the main sequence; the duration follows from the profile shape.
        const double k = solve_profile_exponent(vp * ms.duration_s(a) / a);
        const double dur = profile_ratio(k) * a / vp;
        build_profile(k);
        const int steps = std::max(1, static_cast<int>(std::lround(dur / kSimDt)));
        const Vec2 start = pos_;
        const double t0 = now();
        for (int i = 1; i <= steps && !done(); ++i) {
            const double f = profile_at(static_cast<double>(i) / steps);
            pos_ = start + vec * f + carry * (i * kSimDt);
            record(type);
        }
        anchor_ = pos_;
        TrueEvent ev;
        ev.type = type;
        ev.t0_s = t0;
        ev.t1_s = now();
        ev.amplitude_deg = a;
        ev.peak_velocity_deg_s = vp;
        ev.from = {start.x, start.y};
        ev.to = {pos_.x, pos_.y};
        events_.push_back(ev);
        if (type == Event::Saccade && a >= 1.0) {
            const double amp = std::min(cfg_.saccade.settle_fraction * a, cfg_.saccade.settle_max_deg);
            settle_dir_ = vec * (amp / a);
            settle_t0_ = now();
            settling_ = true;
        }
    }

    // One grid step of drift: Ornstein-Uhlenbeck velocity plus a weak pull to the anchor.
    void drift_step(bool restore) {
        const FixationalModel& f = cfg_.fixational;
        const double s = f.drift_speed_deg_s * std::sqrt(2 * kSimDt / f.drift_tau_s);
        drift_v_.x += -drift_v_.x / f.drift_tau_s * kSimDt + rng_.gaussian(s);
        drift_v_.y += -drift_v_.y / f.drift_tau_s * kSimDt + rng_.gaussian(s);
        Vec2 v = drift_v_;
        if (restore) v = v - (pos_ - anchor_) * f.drift_restore_per_s;
        pos_ = pos_ + v * kSimDt;
    }

    void move(Vec2 delta) { pos_ = pos_ + delta; }

    void record(Event label) {
        Vec2 p = pos_;
        if (settling_) {
            const double tt = now() - settle_t0_;
            const SaccadeModel& m = cfg_.saccade;
            if (tt > 5 * m.settle_tau_s) {
                settling_ = false;
            } else {
                p = p + settle_dir_ * (std::exp(-tt / m.settle_tau_s) * std::sin(2 * kPi * m.settle_freq_hz * tt));
            }
        }
        x_.push_back(p.x);
        y_.push_back(p.y);
        label_.push_back(label);
    }

    std::vector<double> x_, y_;
    std::vector<Event> label_;
    std::vector<TrueEvent> events_;

private:
    double next_ms_interval() {
        const FixationalModel& f = cfg_.fixational;
        return gamma_mean(rng_, f.microsaccade_interval_mean_s, f.microsaccade_interval_shape);
    }

    void microsaccade() {
        const FixationalModel& f = cfg_.fixational;
        double a = gamma_mean(rng_, f.microsaccade_amplitude_mean_arcmin / 60.0, f.microsaccade_amplitude_shape);
        a = std::min(a, f.microsaccade_amplitude_max_deg);
        // Microsaccades correct the position error that drift built up (Engbert & Kliegl 2004):
        // the larger the error, the more likely the direction points back to the anchor.
        const Vec2 err = anchor_ - pos_;
        const double e = norm(err);
        double theta = rng_.uniform(0.0, 2 * kPi);
        const double p_correct = e / (e + 5.0 / 60.0);
        if (e > 0 && rng_.uniform(0.0, 1.0) < p_correct) theta = std::atan2(err.y, err.x) + rng_.gaussian(0.35);
        const Vec2 anchor = anchor_;
        saccade({a * std::cos(theta), a * std::sin(theta)}, Event::Microsaccade, {0, 0});
        anchor_ = anchor;  // fixation stays on the same target
    }

    void build_profile(double k) {
        constexpr int n = kProfileSize - 1;
        profile_[0] = 0;
        double acc = 0;
        auto v = [k](double s) { return std::pow(std::max(0.0, s * (1 - s)), k); };
        for (int i = 1; i <= n; ++i) {
            const double s0 = static_cast<double>(i - 1) / n, s1 = static_cast<double>(i) / n;
            acc += (v(s0) + 4 * v(0.5 * (s0 + s1)) + v(s1)) / 6.0;  // Simpson per segment
            profile_[i] = acc;
        }
        for (double& p : profile_) p /= acc;
    }

    double profile_at(double s) const {
        constexpr int n = kProfileSize - 1;
        const double f = std::clamp(s, 0.0, 1.0) * n;
        const int i = std::min(static_cast<int>(f), n - 1);
        return profile_[i] + (profile_[i + 1] - profile_[i]) * (f - i);
    }

    const GeneratorConfig& cfg_;
    cv::RNG& rng_;
    size_t total_;
    Vec2 pos_, anchor_, drift_v_;
    double next_ms_ = 0;
    bool settling_ = false;
    Vec2 settle_dir_;
    double settle_t0_ = 0;
    static constexpr int kProfileSize = 513;
    std::array<double, kProfileSize> profile_{};
};

void run_fixation(Simulator& sim, const GeneratorConfig&) {
    sim.restart_microsaccade_clock();
    sim.fixate(1e300, Event::Drift);
}

void run_scene(Simulator& sim, const GeneratorConfig& cfg, cv::RNG& rng) {
    const SceneModel& m = cfg.scene;
    while (!sim.done()) {
        sim.restart_microsaccade_clock();
        const double dur = std::max(m.fixation_min_s, gamma_mean(rng, m.fixation_mean_s, m.fixation_shape));
        sim.fixate(sim.now() + dur, Event::Fixation);
        const double a =
            std::clamp(gamma_mean(rng, m.saccade_mean_deg, m.saccade_shape), m.saccade_min_deg, m.saccade_max_deg);
        const double theta = rng.uniform(0.0, 2 * kPi);
        Vec2 v{a * std::cos(theta), a * std::sin(theta)};
        const Vec2 p = sim.pos();
        // Stay inside the scene: mirror a component that would leave it.
        if (std::abs(p.x + v.x) > m.half_width_deg) v.x = -v.x;
        if (std::abs(p.y + v.y) > m.half_height_deg) v.y = -v.y;
        sim.planned_saccade(v);
    }
}

struct ReadingCounts {
    int line_changes = 0;
    int pages = 0;
};

ReadingCounts run_reading(Simulator& sim, const GeneratorConfig& cfg, cv::RNG& rng) {
    const ReadingModel& m = cfg.reading;
    ReadingCounts counts;
    const double x0 = -0.5 * m.line_chars * m.char_deg;
    const double y0 = 0.5 * (m.lines_per_page - 1) * m.line_spacing_deg;
    auto char_x = [&](double c) { return x0 + c * m.char_deg; };
    auto line_y = [&](int l) { return y0 - l * m.line_spacing_deg; };
    auto line_start = [&] { return std::clamp(gamma_mean(rng, m.line_start_mean_chars, 4), 1.0, 12.0); };

    int line = 0;
    double c = line_start();
    // Start on the first word with no saccade: the eye is simply there.
    sim.move(Vec2{char_x(c), line_y(line)} - sim.pos());
    sim.set_anchor(sim.pos());
    while (!sim.done()) {
        sim.restart_microsaccade_clock();
        const double dur =
            std::clamp(gamma_mean(rng, m.fixation_mean_s, m.fixation_shape), m.fixation_min_s, m.fixation_max_s);
        sim.fixate(sim.now() + dur, Event::Fixation);
        double target_c;
        int target_line = line;
        if (c > 3 && rng.uniform(0.0, 1.0) < m.regression_prob) {
            target_c = std::max(0.5, c - std::max(2.0, gamma_mean(rng, m.regression_mean_chars, 4)));
        } else {
            target_c = c + std::max(2.0, gamma_mean(rng, m.forward_mean_chars, m.forward_shape));
            if (target_c > m.line_chars - 1) {
                target_line = line + 1;
                if (target_line >= m.lines_per_page) {
                    target_line = 0;
                    ++counts.pages;
                } else {
                    ++counts.line_changes;
                }
                target_c = line_start();
            }
        }
        const Vec2 from = sim.pos();
        const Vec2 to{char_x(target_c), line_y(target_line)};
        // Readers keep to the line: the scatter across a saccade is a fraction of a line, not of
        // the (long, for return sweeps) amplitude.
        sim.planned_saccade(to - from, 0.08 * m.line_spacing_deg);
        line = target_line;
        c = (sim.pos().x - x0) / m.char_deg;
        // The eye fixates the line it aimed at, wherever it landed.
        sim.set_anchor(sim.pos());
    }
    return counts;
}

void run_pursuit(Simulator& sim, const GeneratorConfig& cfg, cv::RNG& rng) {
    const PursuitModel& m = cfg.pursuit;
    const FixationalModel& f = cfg.fixational;
    while (!sim.done()) {
        if (norm(sim.pos()) > 0.5) sim.planned_saccade(Vec2{0, 0} - sim.pos());
        sim.set_anchor({0, 0});
        sim.restart_microsaccade_clock();
        sim.fixate(sim.now() + m.rest_s, Event::Fixation);
        if (sim.done()) break;

        const double speed = rng.uniform(m.speed_min_deg_s, m.speed_max_deg_s);
        const double theta = rng.uniform(0, 8) * (kPi / 4);  // one of eight directions
        const Vec2 u{std::cos(theta), std::sin(theta)};
        // Rashbass step: the target steps back so that it crosses the fixation point when
        // pursuit starts, and no initial saccade is needed.
        const Vec2 target0 = u * (-speed * m.latency_s);
        const double t0 = sim.now();
        Vec2 ve{0, 0};
        double last_catchup = -1;
        TrueEvent ramp;
        ramp.type = Event::Pursuit;
        ramp.t0_s = t0 + m.latency_s;
        ramp.peak_velocity_deg_s = speed;
        ramp.from = {sim.pos().x, sim.pos().y};
        while (!sim.done() && sim.now() < t0 + m.ramp_s) {
            const double tt = sim.now() - t0;
            const Vec2 target = target0 + u * (speed * tt);
            const bool tracking = tt >= m.latency_s;
            if (!tracking) {
                sim.drift_step(true);
                sim.record(Event::Fixation);
                continue;
            }
            ve = ve + (u * (m.gain * speed) - ve) * (kSimDt / m.tau_s);
            sim.drift_step(false);
            sim.move(ve * kSimDt);
            const Vec2 err = target - sim.pos();
            if (norm(err) > m.catchup_error_deg && sim.now() - last_catchup > 0.2) {
                // Aim where the target will be when the saccade ends (about 30 ms later).
                const Vec2 aim = err + (u * speed - ve) * 0.03;
                sim.saccade(aim * cfg.saccade.landing_gain, Event::Saccade, ve);
                last_catchup = sim.now();
                continue;
            }
            sim.record(Event::Pursuit);
        }
        ramp.t1_s = sim.now();
        ramp.to = {sim.pos().x, sim.pos().y};
        ramp.amplitude_deg = norm(Vec2{ramp.to.az_deg, ramp.to.el_deg} - Vec2{ramp.from.az_deg, ramp.from.el_deg});
        sim.events_.push_back(ramp);
        // The target stops; pursuit decays with the same lag.
        const double t_stop = sim.now();
        while (!sim.done() && sim.now() < t_stop + 3 * m.tau_s) {
            ve = ve * (1 - kSimDt / m.tau_s);
            sim.drift_step(false);
            sim.move(ve * kSimDt);
            sim.record(norm(ve) > f.drift_speed_deg_s ? Event::Pursuit : Event::Fixation);
        }
        sim.set_anchor(sim.pos());
    }
}

struct Interval {
    double t0, t1;
};

std::vector<Interval> poisson_intervals(cv::RNG& rng, double seconds, double per_s, double min_len, double max_len,
                                        bool uniform_len, double mean_len) {
    std::vector<Interval> out;
    if (!(per_s > 0)) return out;
    double t = exponential_sample(rng, 1.0 / per_s);
    while (t < seconds) {
        const double len = uniform_len ? rng.uniform(min_len, max_len) : exponential_sample(rng, mean_len);
        out.push_back({t, t + len});
        t += len + exponential_sample(rng, 1.0 / per_s);
    }
    return out;
}

bool inside(const std::vector<Interval>& v, size_t& cursor, double t) {
    while (cursor < v.size() && v[cursor].t1 <= t) ++cursor;
    return cursor < v.size() && v[cursor].t0 <= t;
}

}  // namespace

std::string_view mode_name(Mode m) {
    switch (m) {
        case Mode::Fixation:
            return "fixation";
        case Mode::Scene:
            return "scene";
        case Mode::Reading:
            return "reading";
        case Mode::Pursuit:
            return "pursuit";
    }
    return "fixation";
}

std::optional<Mode> parse_mode(std::string_view name) {
    for (Mode m : {Mode::Fixation, Mode::Scene, Mode::Reading, Mode::Pursuit})
        if (mode_name(m) == name) return m;
    return std::nullopt;
}

double MainSequence::peak_velocity(double a) const { return eta_deg_s * (1 - std::exp(-a / c_deg)); }
double MainSequence::duration_s(double a) const { return (duration_slope_ms * a + duration_intercept_ms) * 1e-3; }

Status GeneratorConfig::validate() const {
    auto bad = [](const std::string& what) { return Status(fail(what)); };
    // An hour at 1 kHz is 3.6 M samples and a 14 M-point simulation grid: a few hundred MB.
    if (!(seconds > 0) || seconds > 3600) return bad("seconds must be in (0, 3600], got " + std::to_string(seconds));
    if (!(tracker.rate_hz >= 90 && tracker.rate_hz <= 1000))
        return bad("tracker rate must be 90..1000 Hz, got " + std::to_string(tracker.rate_hz));
    if (!(tracker.latency_s >= 0 && tracker.latency_s < 1)) return bad("tracker latency must be in [0, 1) s");
    if (!(tracker.noise_deg >= 0 && tracker.noise_deg < 10)) return bad("tracker noise must be in [0, 10) degrees");
    if (!(tracker.dropout_per_s >= 0 && tracker.dropout_per_s <= 100) || !(tracker.dropout_mean_s > 0))
        return bad("dropouts need a rate in [0, 100] per second and a mean length > 0");
    if (!(tracker.loss_probability >= 0 && tracker.loss_probability <= 1)) return bad("loss probability must be 0..1");
    if (!(saccade.main.eta_deg_s > 0 && saccade.main.c_deg > 0)) return bad("main sequence eta and c must be > 0");
    if (!(blinks.per_minute >= 0 && blinks.per_minute <= 120 && blinks.min_s > 0 && blinks.max_s >= blinks.min_s))
        return bad("blinks need 0 <= per_minute <= 120 and 0 < min_s <= max_s");
    if (!(reading.char_deg > 0 && reading.line_spacing_deg > 0 && reading.line_chars >= 10 &&
          reading.lines_per_page >= 1 && reading.lines_per_page <= 200 &&
          reading.char_deg * reading.line_chars <= 120 && reading.line_spacing_deg * reading.lines_per_page <= 120))
        return bad(
            "reading needs char_deg > 0, line_spacing_deg > 0, line_chars >= 10, 1..200 lines per page, and "
            "a page no larger than 120 x 120 degrees");
    if (!(pursuit.speed_min_deg_s > 0 && pursuit.speed_max_deg_s <= 100 &&
          pursuit.speed_max_deg_s >= pursuit.speed_min_deg_s && pursuit.ramp_s > 0 && pursuit.tau_s > 0))
        return bad("pursuit needs 0 < speed_min <= speed_max <= 100 deg/s, ramp_s > 0, tau_s > 0");
    if (!(fixational.drift_tau_s > 0 && fixational.microsaccade_interval_mean_s > 0))
        return bad("fixational model out of range");
    return Ok{};
}

Result<GeneratedGaze> generate(const GeneratorConfig& cfg) {
    if (Status st = cfg.validate(); !st) return st.error();
    cv::RNG traj_rng = make_stream(cfg.seed, 1);
    cv::RNG plan_rng = make_stream(cfg.seed, 2);
    cv::RNG blink_rng = make_stream(cfg.seed, 3);
    cv::RNG tracker_rng = make_stream(cfg.seed, 4);

    GeneratedGaze out;
    Simulator sim(cfg, traj_rng);
    switch (cfg.mode) {
        case Mode::Fixation:
            run_fixation(sim, cfg);
            break;
        case Mode::Scene:
            run_scene(sim, cfg, plan_rng);
            break;
        case Mode::Reading: {
            const ReadingCounts rc = run_reading(sim, cfg, plan_rng);
            out.line_changes = rc.line_changes;
            out.pages = rc.pages;
            break;
        }
        case Mode::Pursuit:
            run_pursuit(sim, cfg, plan_rng);
            break;
    }
    out.events = std::move(sim.events_);

    std::vector<Interval> blinks;
    if (cfg.blinks_enabled)
        blinks = poisson_intervals(blink_rng, cfg.seconds, cfg.blinks.per_minute / 60.0, cfg.blinks.min_s,
                                   cfg.blinks.max_s, true, 0);
    for (const Interval& b : blinks) {
        TrueEvent ev;
        ev.type = Event::Blink;
        ev.t0_s = b.t0;
        ev.t1_s = b.t1;
        out.events.push_back(ev);
    }
    std::stable_sort(out.events.begin(), out.events.end(),
                     [](const TrueEvent& a, const TrueEvent& b) { return a.t0_s < b.t0_s; });
    const TrackerModel& tr = cfg.tracker;
    const std::vector<Interval> losses =
        poisson_intervals(tracker_rng, cfg.seconds, tr.dropout_per_s, 0, 0, false, tr.dropout_mean_s);

    const size_t n = static_cast<size_t>(std::floor(cfg.seconds * tr.rate_hz));
    out.samples.reserve(n);
    size_t blink_cursor = 0, loss_cursor = 0;
    const size_t last = sim.x_.size() - 1;
    for (size_t k = 0; k < n; ++k) {
        const double t = static_cast<double>(k) / tr.rate_hz;
        const double te = std::max(0.0, t - tr.latency_s);  // the eye state the tracker shows
        const double fi = te / kSimDt;
        const size_t i0 = std::min(static_cast<size_t>(fi), last - 1);
        const double w = std::clamp(fi - static_cast<double>(i0), 0.0, 1.0);
        GazeAngle a{sim.x_[i0] + (sim.x_[i0 + 1] - sim.x_[i0]) * w, sim.y_[i0] + (sim.y_[i0 + 1] - sim.y_[i0]) * w};
        Event label = sim.label_[w < 0.5 ? i0 : i0 + 1];
        // Draw the noise for every sample, valid or not, so that dropouts do not shift it.
        a.az_deg += tracker_rng.gaussian(tr.noise_deg);
        a.el_deg += tracker_rng.gaussian(tr.noise_deg);
        const bool lost_sample = tr.loss_probability > 0 && tracker_rng.uniform(0.0, 1.0) < tr.loss_probability;
        const bool blink = inside(blinks, blink_cursor, te);
        const bool lost = lost_sample || inside(losses, loss_cursor, t);
        if (blink) label = Event::Blink;
        out.samples.push_back(sample_from_angle(t, a, !(blink || lost), label));
    }
    return out;
}

}  // namespace wrsfov::gaze
