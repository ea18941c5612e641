// wrsfov-gaze: generate synthetic gaze, analyse gaze files, inspect and record HID eye trackers.
#include <atomic>
#include <cctype>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iterator>
#include <map>
#include <optional>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "gaze/gaze_file.h"
#include "gaze/generator.h"
#include "gaze/hid_descriptor.h"
#include "gaze/hid_device.h"
#include "gaze/hid_eyetracker.h"
#include "gaze/plot.h"
#include "gaze/stats.h"

namespace g = wrsfov::gaze;
namespace hid = wrsfov::gaze::hid;

namespace {

constexpr const char* kUsage = R"(usage: wrsfov-gaze COMMAND [options]

commands:
  generate --mode fixation|scene|reading|pursuit --seconds S --rate HZ --seed N --out FILE [--plot PNG]
           [--latency-ms MS] [--noise-deg DEG] [--dropouts-per-s R] [--blinks-per-min B] [--no-blinks]
           [--char-deg D] [--line-spacing-deg D] [--line-chars N] [--pursuit-speed MIN MAX]
      Synthetic gaze as a project CSV with the true event in a `label` column. --plot writes the
      scanpath to PNG and the speed over the first 10 s to PNG's name with _velocity.
  stats FILE [--format auto|project|pupil|tobii] [--lambda L] [--ivt-deg-s V] [--pursuit-deg-s V]
           [--reading [--char-deg D] [--line-spacing-deg D]] [--plot PNG]
      Runs the Engbert & Kliegl and I-VT detectors and prints rates, amplitudes, durations and the
      main-sequence fit next to published values.
  list
      HID devices with their usage pages; eye trackers (usage page 0x12) are marked.
  hid-decode --descriptor FILE [--report FILE] [--feature FILE]
      Parses a report descriptor and decodes an input (and feature) report; prints JSON. Files are
      binary or hex text ("05 12 09 01 ...").
  record --device PATH|INDEX|VID:PID --out FILE [--seconds S] [--screen-mm W H]
      Records a HID eye tracker to a project CSV (S = 0: until Ctrl-C; default 10).
)";

struct Args {
    std::vector<std::string> positional;
    std::map<std::string, std::vector<std::string>> opts;
    std::string error;

    bool has(const std::string& k) const { return opts.count(k) > 0; }
    std::optional<std::string> get(const std::string& k, size_t i = 0) const {
        auto it = opts.find(k);
        if (it == opts.end() || it->second.size() <= i) return std::nullopt;
        return it->second[i];
    }
};

// Options and how many values each takes.
Args parse_args(int argc, char** argv, const std::map<std::string, int>& known) {
    Args a;
    for (int i = 2; i < argc; ++i) {
        const std::string s = argv[i];
        if (s.rfind("--", 0) == 0) {
            auto k = known.find(s);
            if (k == known.end()) {
                a.error = "unknown option " + s;
                return a;
            }
            std::vector<std::string> vals;
            for (int n = 0; n < k->second; ++n) {
                if (i + 1 >= argc) {
                    a.error = s + " needs " + std::to_string(k->second) + " value(s)";
                    return a;
                }
                vals.push_back(argv[++i]);
            }
            a.opts[s] = vals;
        } else {
            a.positional.push_back(s);
        }
    }
    return a;
}

bool to_double(const std::string& s, double& out) {
    char* end = nullptr;
    out = std::strtod(s.c_str(), &end);
    return !s.empty() && *end == '\0' && std::isfinite(out);
}

int usage_error(const std::string& msg) {
    std::fprintf(stderr, "wrsfov-gaze: %s\n\n%s", msg.c_str(), kUsage);
    return 2;
}

int runtime_error(const std::string& msg) {
    std::fprintf(stderr, "wrsfov-gaze: %s\n", msg.c_str());
    return 1;
}

// Reads a number option into `out`; false (with a message) if it is malformed.
bool number_opt(const Args& a, const std::string& k, double& out, std::string& err, size_t i = 0) {
    auto v = a.get(k, i);
    if (!v) return true;
    if (!to_double(*v, out)) {
        err = k + " '" + *v + "' is not a number";
        return false;
    }
    return true;
}

std::string velocity_png_name(const std::string& png) {
    const size_t dot = png.rfind('.');
    const size_t slash = png.rfind('/');
    if (dot == std::string::npos || (slash != std::string::npos && dot < slash)) return png + "_velocity.png";
    return png.substr(0, dot) + "_velocity" + png.substr(dot);
}

int write_plots(const std::string& png, const std::vector<g::GazeSample>& samples, double threshold) {
    g::PlotOptions po;
    po.threshold_deg_s = threshold;
    if (auto s = g::write_scanpath_png(png, samples, po); !s) return runtime_error(s.error().message);
    po.max_seconds = 10;
    const std::string vel = velocity_png_name(png);
    if (auto s = g::write_velocity_png(vel, samples, po); !s) return runtime_error(s.error().message);
    std::printf("wrote %s and %s\n", png.c_str(), vel.c_str());
    return 0;
}

int cmd_generate(int argc, char** argv) {
    const Args a = parse_args(argc, argv,
                              {{"--mode", 1},
                               {"--seconds", 1},
                               {"--rate", 1},
                               {"--seed", 1},
                               {"--out", 1},
                               {"--plot", 1},
                               {"--latency-ms", 1},
                               {"--noise-deg", 1},
                               {"--dropouts-per-s", 1},
                               {"--blinks-per-min", 1},
                               {"--no-blinks", 0},
                               {"--char-deg", 1},
                               {"--line-spacing-deg", 1},
                               {"--line-chars", 1},
                               {"--pursuit-speed", 2}});
    if (!a.error.empty()) return usage_error(a.error);
    if (!a.positional.empty()) return usage_error("unexpected argument " + a.positional[0]);
    g::GeneratorConfig c;
    const auto mode = a.get("--mode");
    if (!mode) return usage_error("generate needs --mode");
    const auto m = g::parse_mode(*mode);
    if (!m) return usage_error("--mode must be fixation, scene, reading or pursuit, not '" + *mode + "'");
    c.mode = *m;
    const auto out = a.get("--out");
    if (!out) return usage_error("generate needs --out FILE");
    std::string err;
    double seed = 1, latency_ms = 0, line_chars = c.reading.line_chars;
    if (!number_opt(a, "--seconds", c.seconds, err) || !number_opt(a, "--rate", c.tracker.rate_hz, err) ||
        !number_opt(a, "--seed", seed, err) || !number_opt(a, "--latency-ms", latency_ms, err) ||
        !number_opt(a, "--noise-deg", c.tracker.noise_deg, err) ||
        !number_opt(a, "--dropouts-per-s", c.tracker.dropout_per_s, err) ||
        !number_opt(a, "--blinks-per-min", c.blinks.per_minute, err) ||
        !number_opt(a, "--char-deg", c.reading.char_deg, err) ||
        !number_opt(a, "--line-spacing-deg", c.reading.line_spacing_deg, err) ||
        !number_opt(a, "--line-chars", line_chars, err) ||
        !number_opt(a, "--pursuit-speed", c.pursuit.speed_min_deg_s, err, 0) ||
        !number_opt(a, "--pursuit-speed", c.pursuit.speed_max_deg_s, err, 1))
        return usage_error(err);
    if (seed < 0 || seed != std::floor(seed) || seed > 1.8e19)
        return usage_error("--seed must be a non-negative integer");
    c.seed = static_cast<uint64_t>(seed);
    c.tracker.latency_s = latency_ms * 1e-3;
    if (!(line_chars >= 10 && line_chars <= 1000)) return usage_error("--line-chars must be 10..1000");
    c.reading.line_chars = static_cast<int>(line_chars);
    c.blinks_enabled = !a.has("--no-blinks");
    auto gen = g::generate(c);
    if (!gen) return usage_error(gen.error().message);
    if (auto s = g::write_gaze_csv(*out, gen->samples, true); !s) return runtime_error(s.error().message);
    size_t valid = 0;
    for (const g::GazeSample& s : gen->samples) valid += s.eye[0].valid ? 1 : 0;
    std::printf("wrote %zu samples (%zu valid) of %s gaze at %g Hz, seed %llu, to %s\n", gen->samples.size(), valid,
                std::string(g::mode_name(c.mode)).c_str(), c.tracker.rate_hz, static_cast<unsigned long long>(c.seed),
                out->c_str());
    if (auto png = a.get("--plot")) return write_plots(*png, gen->samples, 30);
    return 0;
}

int cmd_stats(int argc, char** argv) {
    const Args a = parse_args(argc, argv,
                              {{"--format", 1},
                               {"--lambda", 1},
                               {"--ivt-deg-s", 1},
                               {"--pursuit-deg-s", 1},
                               {"--reading", 0},
                               {"--char-deg", 1},
                               {"--line-spacing-deg", 1},
                               {"--plot", 1}});
    if (!a.error.empty()) return usage_error(a.error);
    if (a.positional.size() != 1) return usage_error("stats needs exactly one FILE");
    g::ReadOptions ro;
    if (auto f = a.get("--format")) {
        if (*f == "auto")
            ro.format = g::GazeFormat::Auto;
        else if (*f == "project")
            ro.format = g::GazeFormat::Project;
        else if (*f == "pupil")
            ro.format = g::GazeFormat::PupilLabs;
        else if (*f == "tobii")
            ro.format = g::GazeFormat::TobiiProLab;
        else
            return usage_error("--format must be auto, project, pupil or tobii");
    }
    g::StatsOptions so;
    g::ReadingLayout layout;
    std::string err;
    if (!number_opt(a, "--lambda", so.ek.lambda, err) ||
        !number_opt(a, "--ivt-deg-s", so.ivt.saccade_threshold_deg_s, err) ||
        !number_opt(a, "--pursuit-deg-s", so.ivt.pursuit_threshold_deg_s, err) ||
        !number_opt(a, "--char-deg", layout.char_deg, err) ||
        !number_opt(a, "--line-spacing-deg", layout.line_spacing_deg, err))
        return usage_error(err);
    if (!(so.ek.lambda > 0) || !(so.ivt.saccade_threshold_deg_s > 0) || !(layout.char_deg > 0) ||
        !(layout.line_spacing_deg > 0))
        return usage_error("--lambda, --ivt-deg-s, --char-deg and --line-spacing-deg must be > 0");
    if (a.has("--reading")) so.reading = layout;
    auto rec = g::read_gaze_file(a.positional[0], ro);
    if (!rec) return runtime_error(rec.error().message);
    for (size_t i = 0; i < rec->issues.size() && i < 20; ++i)
        std::fprintf(stderr, "%s:%zu: skipped: %s\n", a.positional[0].c_str(), rec->issues[i].line,
                     rec->issues[i].message.c_str());
    if (rec->issues.size() > 20) std::fprintf(stderr, "... %zu bad rows in all\n", rec->issues.size());
    if (rec->samples.empty()) return runtime_error(a.positional[0] + ": no usable samples");
    const g::GazeStats s = g::compute_stats(rec->samples, so);
    std::printf("%s (%s), %zu bad rows skipped\n", a.positional[0].c_str(),
                std::string(g::format_name(rec->format)).c_str(), rec->issues.size());
    std::printf("%s", g::format_stats(s).c_str());
    if (auto png = a.get("--plot")) return write_plots(*png, rec->samples, so.ivt.saccade_threshold_deg_s);
    return 0;
}

int cmd_list(int argc, char**) {
    if (argc > 2) return usage_error("list takes no arguments");
    auto devices = hid::enumerate_devices();
    if (!devices) return runtime_error(devices.error().message);
    if (devices->empty()) {
        std::printf("no HID devices found (hidraw nodes need read permission)\n");
        return 0;
    }
    size_t i = 0;
    for (const hid::DeviceInfo& d : *devices) {
        std::printf("%2zu  %-14s %04x:%04x  usage page 0x%04x usage 0x%04x  %s%s %s\n", i++, d.path.c_str(),
                    d.vendor_id, d.product_id, d.usage_page, d.usage, d.is_eye_tracker() ? "[eye tracker] " : "",
                    d.manufacturer.c_str(), d.product.c_str());
    }
    return 0;
}

// Binary, or hex text such as "05 12 09 01" / "0x05,0x12".
g::Result<std::vector<uint8_t>> read_bytes(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) return g::fail("cannot open '" + path + "'");
    std::string data((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    bool text = !data.empty();
    for (char c : data)
        if (!(std::isxdigit(static_cast<unsigned char>(c)) || c == ' ' || c == '\n' || c == '\r' || c == '\t' ||
              c == ',' || c == 'x' || c == 'X'))
            text = false;
    if (!text) return std::vector<uint8_t>(data.begin(), data.end());
    std::vector<uint8_t> out;
    std::string tok;
    for (char& c : data)
        if (c == ',') c = ' ';
    std::istringstream words(data);
    while (words >> tok) {
        if (tok.size() > 2 && tok[0] == '0' && (tok[1] == 'x' || tok[1] == 'X')) tok = tok.substr(2);
        if (tok.find_first_of("xX") != std::string::npos || tok.size() % 2 != 0)
            return g::fail("'" + path + "': hex token '" + tok + "' is not whole bytes");
        for (size_t i = 0; i < tok.size(); i += 2)
            out.push_back(static_cast<uint8_t>(std::stoul(tok.substr(i, 2), nullptr, 16)));
    }
    return out;
}

std::string json_str(const std::string& s) {
    std::string o = "\"";
    for (char c : s) {
        if (c == '"' || c == '\\')
            o += '\\', o += c;
        else if (static_cast<unsigned char>(c) < 0x20) {
            char b[8];
            std::snprintf(b, sizeof b, "\\u%04x", c);
            o += b;
        } else
            o += c;
    }
    return o + "\"";
}

std::string json_num(double v) {
    if (!std::isfinite(v)) return "null";
    char b[64];
    std::snprintf(b, sizeof b, "%.10g", v);
    return b;
}

std::string hex32(uint32_t v) {
    char b[16];
    std::snprintf(b, sizeof b, "\"0x%08X\"", v);
    return b;
}

int cmd_hid_decode(int argc, char** argv) {
    const Args a = parse_args(argc, argv, {{"--descriptor", 1}, {"--report", 1}, {"--feature", 1}});
    if (!a.error.empty()) return usage_error(a.error);
    if (!a.positional.empty()) return usage_error("unexpected argument " + a.positional[0]);
    const auto dpath = a.get("--descriptor");
    if (!dpath) return usage_error("hid-decode needs --descriptor FILE");
    auto bytes = read_bytes(*dpath);
    if (!bytes) return runtime_error(bytes.error().message);
    auto desc = hid::parse_descriptor(*bytes);
    if (!desc) {
        std::printf("{\"descriptor\": {\"error\": %s}}\n", json_str(desc.error().message).c_str());
        return runtime_error("descriptor: " + desc.error().message);
    }
    static const char* kinds[] = {"physical",    "application",  "logical",       "report",
                                  "named array", "usage switch", "usage modifier"};
    std::string o = "{\n  \"descriptor\": {\n    \"bytes\": " + std::to_string(bytes->size()) +
                    ",\n    \"uses_report_ids\": " + (desc->uses_report_ids ? "true" : "false") +
                    ",\n    \"collections\": [";
    for (size_t i = 0; i < desc->collections.size(); ++i) {
        const hid::Collection& c = desc->collections[i];
        o += i ? ",\n      " : "\n      ";
        o += "{\"index\": " + std::to_string(i) +
             ", \"kind\": " + json_str(c.kind < 7 ? kinds[c.kind] : "vendor " + std::to_string(c.kind)) +
             ", \"usage\": " + json_str(hid::usage_name(c.usage)) + ", \"usage_code\": " + hex32(c.usage) +
             ", \"parent\": " + std::to_string(c.parent) + "}";
    }
    o += "\n    ],\n    \"fields\": [";
    for (size_t i = 0; i < desc->fields.size(); ++i) {
        const hid::Field& f = desc->fields[i];
        o += i ? ",\n      " : "\n      ";
        o += "{\"index\": " + std::to_string(i) +
             ", \"type\": " + json_str(std::string(hid::report_type_name(f.type))) +
             ", \"report_id\": " + std::to_string(f.report_id) + ", \"bit_offset\": " + std::to_string(f.bit_offset) +
             ", \"bit_size\": " + std::to_string(f.bit_size) + ", \"count\": " + std::to_string(f.count) +
             ", \"constant\": " + (f.is_constant() ? "true" : "false") +
             ", \"variable\": " + (f.is_variable() ? "true" : "false") + ", \"usages\": [";
        for (size_t k = 0; k < f.usages.size(); ++k) {
            const hid::UsageRange& r = f.usages[k];
            o += k ? ", " : "";
            o += r.min == r.max ? json_str(hid::usage_name(r.min))
                                : json_str(hid::usage_name(r.min) + " .. " + hid::usage_name(r.max));
        }
        o += "], \"logical\": [" + std::to_string(f.logical_min) + ", " + std::to_string(f.logical_max) +
             "], \"physical\": [" + std::to_string(f.physical_min) + ", " + std::to_string(f.physical_max) +
             "], \"unit\": " + json_str(hid::unit_name(f.unit)) + ", \"unit_code\": " + hex32(f.unit) +
             ", \"unit_exponent\": " + std::to_string(f.unit_exponent) +
             ", \"collection\": " + std::to_string(f.collection) + "}";
    }
    o += "\n    ],\n    \"reports\": [";
    bool first = true;
    for (hid::ReportType t : {hid::ReportType::Input, hid::ReportType::Output, hid::ReportType::Feature})
        for (uint8_t id : desc->report_ids(t)) {
            o += first ? "\n      " : ",\n      ";
            first = false;
            o += "{\"type\": " + json_str(std::string(hid::report_type_name(t))) + ", \"id\": " + std::to_string(id) +
                 ", \"bytes\": " + std::to_string(desc->report_bytes(t, id)) + "}";
        }
    o += "\n    ]\n  }";
    int rc = 0;
    auto layout = hid::find_eye_tracker(*desc);
    if (!layout) {
        o += ",\n  \"eye_tracker\": {\"error\": " + json_str(layout.error().message) + "}";
    } else {
        o += ",\n  \"eye_tracker\": {\"tracking_report_id\": " + std::to_string(layout->tracking_report_id) +
             ", \"timestamp\": " + (layout->timestamp.found() ? "true" : "false") +
             ", \"left_eye_position\": " + (layout->eye_pos[0][0].found() ? "true" : "false") +
             ", \"right_eye_position\": " + (layout->eye_pos[1][0].found() ? "true" : "false") +
             ", \"screen_feature_report_id\": " +
             (layout->screen_width.found() ? std::to_string(layout->screen_report_id) : "null") + "}";
    }
    if (auto rpath = a.get("--report")) {
        auto rb = read_bytes(*rpath);
        if (!rb) return runtime_error(rb.error().message);
        auto view = hid::view_report(*desc, hid::ReportType::Input, *rb);
        if (!view) {
            o += ",\n  \"report\": {\"error\": " + json_str(view.error().message) + "}";
            std::fprintf(stderr, "wrsfov-gaze: report: %s\n", view.error().message.c_str());
            rc = 1;
        } else {
            o += ",\n  \"report\": {\n    \"id\": " + std::to_string(view->id) + ",\n    \"fields\": [";
            bool f1 = true;
            for (size_t i = 0; i < desc->fields.size(); ++i) {
                const hid::Field& f = desc->fields[i];
                if (f.type != hid::ReportType::Input || f.report_id != view->id || f.is_constant()) continue;
                o += f1 ? "\n      " : ",\n      ";
                f1 = false;
                o += "{\"field\": " + std::to_string(i) + ", \"values\": [";
                for (uint32_t k = 0; k < f.count && k < 64; ++k) {
                    auto raw = hid::read_raw(f, k, view->payload);
                    o += k ? ", " : "";
                    o += raw ? "{\"usage\": " + json_str(hid::usage_name(f.usage_at(k))) +
                                   ", \"raw\": " + std::to_string(*raw) +
                                   ", \"physical\": " + json_num(hid::to_physical(f, *raw)) + "}"
                             : "{\"error\": " + json_str(raw.error().message) + "}";
                }
                o += "]}";
            }
            o += "\n    ]";
            if (layout) {
                auto t = hid::decode_tracking(*desc, *layout, *rb);
                if (!t) {
                    o += ",\n    \"tracking\": {\"error\": " + json_str(t.error().message) + "}";
                    rc = 1;
                } else {
                    o += ",\n    \"tracking\": {\"timestamp_us\": " +
                         (t->timestamp_us ? json_num(*t->timestamp_us) : std::string("null")) +
                         ", \"gaze_point_um\": [" + json_num(t->gaze_um.x) + ", " + json_num(t->gaze_um.y) +
                         "], \"gaze_valid\": " + (t->gaze_valid ? "true" : "false");
                    const char* names[2] = {"left_eye_um", "right_eye_um"};
                    for (int e = 0; e < 2; ++e) {
                        o += std::string(", \"") + names[e] + "\": ";
                        o += t->eye_um[e] ? "[" + json_num(t->eye_um[e]->x) + ", " + json_num(t->eye_um[e]->y) + ", " +
                                                json_num(t->eye_um[e]->z) + "]"
                                          : "null";
                    }
                    o += "}";
                }
            }
            o += "\n  }";
        }
    }
    if (auto fpath = a.get("--feature")) {
        auto fb = read_bytes(*fpath);
        if (!fb) return runtime_error(fb.error().message);
        if (!layout) {
            o += ",\n  \"feature\": {\"error\": \"no eye tracker layout\"}";
            rc = 1;
        } else if (auto s = hid::decode_screen(*desc, *layout, *fb); !s) {
            o += ",\n  \"feature\": {\"error\": " + json_str(s.error().message) + "}";
            rc = 1;
        } else {
            o += ",\n  \"feature\": {\"screen_um\": [" + json_num(s->width_um) + ", " + json_num(s->height_um) + "]}";
        }
    }
    o += "\n}\n";
    std::fputs(o.c_str(), stdout);
    return rc;
}

std::atomic<bool> g_stop{false};

int cmd_record(int argc, char** argv) {
    const Args a = parse_args(argc, argv, {{"--device", 1}, {"--out", 1}, {"--seconds", 1}, {"--screen-mm", 2}});
    if (!a.error.empty()) return usage_error(a.error);
    const auto dev = a.get("--device");
    const auto out = a.get("--out");
    if (!dev || !out) return usage_error("record needs --device ID and --out FILE");
    double seconds = 10;
    std::string err;
    hid::HidSourceOptions opts;
    double w = 0, h = 0;
    if (!number_opt(a, "--seconds", seconds, err) || !number_opt(a, "--screen-mm", w, err, 0) ||
        !number_opt(a, "--screen-mm", h, err, 1))
        return usage_error(err);
    if (seconds < 0) return usage_error("--seconds must be >= 0");
    if (a.has("--screen-mm")) {
        if (!(w > 0 && h > 0)) return usage_error("--screen-mm needs a positive width and height");
        opts.screen = hid::ScreenSize{w * 1000, h * 1000};
    }
    auto path = hid::resolve_device(*dev);
    if (!path) return runtime_error(path.error().message);
    std::signal(SIGINT, [](int) { g_stop = true; });
    hid::HidTrackerSource src(hid::hidapi_connector(*path), opts);
    std::vector<g::GazeSample> samples;
    const double t0 = hid::HidTrackerSource::steady_seconds();
    bool was_connected = false;
    std::string last_reported;
    while (!g_stop && (seconds == 0 || hid::HidTrackerSource::steady_seconds() - t0 < seconds)) {
        src.poll();
        for (g::GazeSample& s : src.take_new_samples()) samples.push_back(s);
        if (src.connected() != was_connected) {
            was_connected = src.connected();
            std::fprintf(stderr, "%s %s\n", path->c_str(), was_connected ? "connected" : "lost");
        }
        if (!src.connected() && src.last_error() != last_reported) {
            last_reported = src.last_error();
            std::fprintf(stderr, "wrsfov-gaze: %s (retrying)\n", last_reported.c_str());
        }
        std::this_thread::sleep_for(std::chrono::milliseconds(1));
    }
    if (samples.empty())
        return runtime_error("recorded no samples from " + *path +
                             (src.last_error().empty() ? std::string() : ": " + src.last_error()));
    const double first = samples.front().t_s;
    for (g::GazeSample& s : samples) s.t_s -= first;
    if (auto s = g::write_gaze_csv(*out, samples, false); !s) return runtime_error(s.error().message);
    std::printf("recorded %zu samples to %s\n", samples.size(), out->c_str());
    return 0;
}

}  // namespace

int main(int argc, char** argv) {
    if (argc < 2) return usage_error("no command");
    const std::string cmd = argv[1];
    if (cmd == "-h" || cmd == "--help" || cmd == "help") {
        std::fputs(kUsage, stdout);
        return 0;
    }
    if (cmd == "generate") return cmd_generate(argc, argv);
    if (cmd == "stats") return cmd_stats(argc, argv);
    if (cmd == "list") return cmd_list(argc, argv);
    if (cmd == "hid-decode") return cmd_hid_decode(argc, argv);
    if (cmd == "record") return cmd_record(argc, argv);
    return usage_error("unknown command '" + cmd + "'");
}
