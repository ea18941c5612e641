// wrsfov-gaze: generate synthetic gaze, analyse gaze files, inspect and record HID eye trackers.
#include <array>
#include <atomic>
#include <cctype>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <fstream>
#include <iterator>
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
#include "cli/cli.h"

namespace g = wrsfov::gaze;
namespace hid = wrsfov::gaze::hid;
namespace cli = wrsfov::cli;

namespace {

// A usage error found after parsing; `cmd` is the subcommand (its --help is named).
int usage_error(const CLI::App& cmd, const std::string& msg) { return cli::usageError(cmd, msg); }

int runtime_error(const std::string& msg) {
    std::fprintf(stderr, "wrsfov-gaze: %s\n", msg.c_str());
    return 1;
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

struct GenerateArgs {
    g::GeneratorConfig c;
    std::string out, plot;
    double latency_ms = 0;
    bool no_blinks = false;
    std::array<double, 2> pursuit{};
};

int cmd_generate(const CLI::App& cmd, GenerateArgs& a) {
    g::GeneratorConfig& c = a.c;
    c.tracker.latency_s = a.latency_ms * 1e-3;
    c.pursuit.speed_min_deg_s = a.pursuit[0];
    c.pursuit.speed_max_deg_s = a.pursuit[1];
    c.blinks_enabled = !a.no_blinks;
    auto gen = g::generate(c);
    if (!gen) return usage_error(cmd, gen.error().message);
    if (auto s = g::write_gaze_csv(a.out, gen->samples, true); !s) return runtime_error(s.error().message);
    size_t valid = 0;
    for (const g::GazeSample& s : gen->samples) valid += s.eye[0].valid ? 1 : 0;
    std::printf("wrote %zu samples (%zu valid) of %s gaze at %g Hz, seed %llu, to %s\n", gen->samples.size(), valid,
                std::string(g::mode_name(c.mode)).c_str(), c.tracker.rate_hz, static_cast<unsigned long long>(c.seed),
                a.out.c_str());
    if (!a.plot.empty()) return write_plots(a.plot, gen->samples, 30);
    return 0;
}

struct StatsArgs {
    std::string file, plot;
    g::ReadOptions ro;
    g::StatsOptions so;
    g::ReadingLayout layout;
    bool reading = false;
};

int cmd_stats(StatsArgs& a) {
    g::StatsOptions& so = a.so;
    if (a.reading) so.reading = a.layout;
    auto rec = g::read_gaze_file(a.file, a.ro);
    if (!rec) return runtime_error(rec.error().message);
    for (size_t i = 0; i < rec->issues.size() && i < 20; ++i)
        std::fprintf(stderr, "%s:%zu: skipped: %s\n", a.file.c_str(), rec->issues[i].line,
                     rec->issues[i].message.c_str());
    if (rec->issues.size() > 20) std::fprintf(stderr, "... %zu bad rows in all\n", rec->issues.size());
    if (rec->samples.empty()) return runtime_error(a.file + ": no usable samples");
    const g::GazeStats s = g::compute_stats(rec->samples, so);
    std::printf("%s (%s), %zu bad rows skipped\n", a.file.c_str(),
                std::string(g::format_name(rec->format)).c_str(), rec->issues.size());
    std::printf("%s", g::format_stats(s).c_str());
    if (!a.plot.empty()) return write_plots(a.plot, rec->samples, so.ivt.saccade_threshold_deg_s);
    return 0;
}

int cmd_list() {
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

struct HidDecodeArgs {
    std::string descriptor, report, feature;
};

int cmd_hid_decode(const HidDecodeArgs& a) {
    auto bytes = read_bytes(a.descriptor);
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
    if (!a.report.empty()) {
        auto rb = read_bytes(a.report);
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
    if (!a.feature.empty()) {
        auto fb = read_bytes(a.feature);
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

struct RecordArgs {
    std::string device, out;
    double seconds = 10;
    std::array<double, 2> screen_mm{};
    bool screen_given = false;
};

int cmd_record(const RecordArgs& a) {
    const double seconds = a.seconds;
    hid::HidSourceOptions opts;
    if (a.screen_given) opts.screen = hid::ScreenSize{a.screen_mm[0] * 1000, a.screen_mm[1] * 1000};
    auto path = hid::resolve_device(a.device);
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
    if (auto s = g::write_gaze_csv(a.out, samples, false); !s) return runtime_error(s.error().message);
    std::printf("recorded %zu samples to %s\n", samples.size(), a.out.c_str());
    return 0;
}

// An option that takes any finite number (the generator and the detectors check their ranges).
template <typename T>
CLI::Option* finite(CLI::App& app, const std::string& name, T& target, const std::string& description) {
    return cli::option(app, name, target, cli::number<T>(-INFINITY, INFINITY), description);
}

}  // namespace

int main(int argc, char** argv) {
    CLI::App app{
        "Generate synthetic gaze, analyse gaze files, inspect and record HID eye trackers. Exit status: 0 "
        "success, 1 a run-time failure (unreadable file, device missing, undecodable report), 2 a usage error.",
        "wrsfov-gaze"};
    cli::setup(app);
    app.require_subcommand(0, 1);

    GenerateArgs ga;
    g::GeneratorConfig& c = ga.c;
    ga.pursuit = {c.pursuit.speed_min_deg_s, c.pursuit.speed_max_deg_s};
    CLI::App* gen = app.add_subcommand(
        "generate",
        "Synthetic gaze as a project CSV with the true event in a `label` column. The ranges are the "
        "generator's (a message names the field).");
    cli::option(*gen, "--mode", c.mode,
                cli::oneOf<g::Mode>({{"fixation", g::Mode::Fixation},
                                     {"scene", g::Mode::Scene},
                                     {"reading", g::Mode::Reading},
                                     {"pursuit", g::Mode::Pursuit}}),
                "What the simulated observer does: fixation (drift and microsaccades), scene (free viewing), "
                "reading (lines of text) or pursuit (step-ramp targets).")
        ->required()
        ->default_str("");
    cli::option(*gen, "--out", ga.out, cli::text("a file name", "FILE"), "The project CSV to write.")->required();
    finite(*gen, "--seconds", c.seconds, "Length in seconds, in (0, 3600].")->type_name("S");
    finite(*gen, "--rate", c.tracker.rate_hz, "Tracker rate in Hz, 90..1000.")->type_name("HZ");
    cli::option(*gen, "--seed", c.seed,
                cli::integer<uint64_t>(0, 18000000000000000000ull, "a non-negative integer below 1.8e19"),
                "Seed of the generator: the same seed and options give the same file.");
    cli::option(*gen, "--plot", ga.plot, cli::text("a file name", "PNG"),
                "Write the scanpath to PNG and the speed over the first 10 s to PNG's name with _velocity.");
    finite(*gen, "--latency-ms", ga.latency_ms, "Tracker latency in ms: a sample at t shows the eye at t - latency.")
        ->type_name("MS");
    finite(*gen, "--noise-deg", c.tracker.noise_deg, "RMS white noise of the tracker per axis, in degrees.")
        ->type_name("DEG");
    finite(*gen, "--dropouts-per-s", c.tracker.dropout_per_s, "Rate of tracking losses per second.")
        ->type_name("R");
    finite(*gen, "--blinks-per-min", c.blinks.per_minute, "Blinks per minute (samples invalid while the lid is closed).")
        ->type_name("B");
    gen->add_flag("--no-blinks", ga.no_blinks, "No blinks.");
    finite(*gen, "--char-deg", c.reading.char_deg, "Reading: width of one character in degrees.")->type_name("D");
    finite(*gen, "--line-spacing-deg", c.reading.line_spacing_deg, "Reading: distance between lines in degrees.")
        ->type_name("D");
    cli::option(*gen, "--line-chars", c.reading.line_chars, cli::integer(10, 1000),
                "Reading: characters per line, 10..1000.");
    gen->add_option("--pursuit-speed", ga.pursuit, "Pursuit: target speeds drawn between MIN and MAX deg/s.")
        ->check(cli::check(cli::number<double>(-INFINITY, INFINITY)))
        ->type_name("MIN MAX")
        ->default_str(cli::showNumber(ga.pursuit[0]) + " " + cli::showNumber(ga.pursuit[1]));

    StatsArgs sa;
    CLI::App* stats = app.add_subcommand(
        "stats",
        "Runs the Engbert & Kliegl and I-VT detectors on a gaze file and prints rates, amplitudes, durations and "
        "the main-sequence fit next to published values; rows that cannot be read are reported and skipped.");
    cli::option(*stats, "FILE", sa.file, cli::text("a file name", "FILE"),
                "Gaze file: project CSV, Pupil Labs export or Tobii Pro Lab TSV.")
        ->required();
    cli::option(*stats, "--format", sa.ro.format,
                cli::oneOf<g::GazeFormat>({{"auto", g::GazeFormat::Auto},
                                           {"project", g::GazeFormat::Project},
                                           {"pupil", g::GazeFormat::PupilLabs},
                                           {"tobii", g::GazeFormat::TobiiProLab}}),
                "File format: auto (from the header), project, pupil or tobii.");
    const cli::Reader<double> positive = cli::number<double>(0, INFINITY, cli::Ends::OpenLow);
    cli::option(*stats, "--lambda", sa.so.ek.lambda, positive,
                "Engbert & Kliegl threshold: this many median-based SDs of the velocity, > 0.")
        ->type_name("L");
    cli::option(*stats, "--ivt-deg-s", sa.so.ivt.saccade_threshold_deg_s, positive,
                "I-VT saccade threshold in deg/s, > 0.")
        ->type_name("V");
    finite(*stats, "--pursuit-deg-s", sa.so.ivt.pursuit_threshold_deg_s,
           "I-VT: slow segments moving faster than this (deg/s) are pursuit; 0: no pursuit.")
        ->type_name("V");
    stats->add_flag("--reading", sa.reading, "Reading measures (regressions, return sweeps) for the layout below.");
    cli::option(*stats, "--char-deg", sa.layout.char_deg, positive, "Reading: width of one character in degrees, > 0.")
        ->type_name("D");
    cli::option(*stats, "--line-spacing-deg", sa.layout.line_spacing_deg, positive,
                "Reading: distance between lines in degrees, > 0.")
        ->type_name("D");
    cli::option(*stats, "--plot", sa.plot, cli::text("a file name", "PNG"),
                "Write the scanpath to PNG and the speed over the first 10 s to PNG's name with _velocity.");

    CLI::App* list = app.add_subcommand("list", "HID devices with their usage pages; eye trackers (usage page 0x12) "
                                                "are marked.");

    HidDecodeArgs ha;
    CLI::App* hidDecode = app.add_subcommand(
        "hid-decode",
        "Parses a report descriptor and decodes an input (and feature) report; prints JSON. Files are binary or "
        "hex text (\"05 12 09 01 ...\", \"0x05,0x12\").");
    cli::option(*hidDecode, "--descriptor", ha.descriptor, cli::text("a file name", "FILE"), "The report descriptor.")
        ->required();
    cli::option(*hidDecode, "--report", ha.report, cli::text("a file name", "FILE"), "An input report to decode.");
    cli::option(*hidDecode, "--feature", ha.feature, cli::text("a file name", "FILE"),
                "A Calibrated Screen feature report to decode.");

    RecordArgs ra;
    CLI::App* record = app.add_subcommand("record", "Records a HID eye tracker to a project CSV.");
    cli::option(*record, "--device", ra.device, cli::text("a device", "ID"),
                "The tracker: a hidraw path, an index of `wrsfov-gaze list` or VID:PID in hex.")
        ->required();
    cli::option(*record, "--out", ra.out, cli::text("a file name", "FILE"), "The project CSV to write.")->required();
    cli::option(*record, "--seconds", ra.seconds, cli::number<double>(0, INFINITY),
                "How long to record, >= 0; 0: until Ctrl-C.")
        ->type_name("S");
    record
        ->add_option("--screen-mm", ra.screen_mm,
                     "Screen width and height in mm, > 0, where the tracker has no Calibrated Screen feature.")
        ->check(cli::check(cli::number<double>(0, INFINITY, cli::Ends::OpenLow)))
        ->type_name("W H");

    CLI::App* help = app.add_subcommand("help", "Print this help, or with a COMMAND that command's, and exit.");
    help->allow_extras();
    app.footer("Run 'wrsfov-gaze COMMAND --help' for the options of a command.");  // after the commands: theirs differ
    if (auto rc = cli::parseOrExit(app, argc, argv)) return *rc;
    if (help->parsed()) {
        const CLI::App* of = &app;
        std::string name = app.get_name();
        for (const CLI::App* sub : {gen, stats, list, hidDecode, record})
            if (!help->remaining().empty() && help->remaining().front() == sub->get_name()) {
                of = sub;
                name += " " + sub->get_name();
            }
        std::fputs(app.get_formatter()->make_help(of, name, CLI::AppFormatMode::Normal).c_str(), stdout);
        return 0;
    }
    if (gen->parsed()) return cmd_generate(*gen, ga);
    if (stats->parsed()) return cmd_stats(sa);
    if (list->parsed()) return cmd_list();
    if (hidDecode->parsed()) return cmd_hid_decode(ha);
    if (record->parsed()) {
        ra.screen_given = record->count("--screen-mm") > 0;
        return cmd_record(ra);
    }
    return cli::usageError(app, "no command: generate, stats, list, hid-decode or record");
}
