#include "cli/cli.h"

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <regex>
#include <sstream>

#ifndef WRSFOV_VERSION
#error "WRSFOV_VERSION (the CMake project version) must be defined"
#endif

namespace wrsfov::cli {

namespace {

constexpr size_t kHelpWidth = 100;
constexpr size_t kOptionColumn = 30;

// Breaks `text` into lines of at most `width` characters at spaces; newlines in it stay.
std::string wrap(const std::string& text, size_t width) {
    std::string out;
    std::istringstream lines(text);
    bool firstLine = true;
    for (std::string line; std::getline(lines, line);) {
        if (!firstLine) out += '\n';
        firstLine = false;
        std::istringstream words(line);
        size_t col = 0;
        for (std::string w; words >> w;) {
            if (col > 0 && col + 1 + w.size() > width) {
                out += '\n';
                col = 0;
            } else if (col > 0) {
                out += ' ';
                ++col;
            }
            out += w;
            col += w.size();
        }
    }
    return out;
}

// Option, placeholder, then the sentence with the default at its end.
class Formatter : public CLI::Formatter {
  public:
    Formatter() { column_width(kOptionColumn); }

    std::string make_option_opts(const CLI::Option* opt) const override {
        std::string out;
        if (opt->get_type_size() == 0) return out;
        if (!opt->get_positional() && !opt->get_type_name().empty()) out += " " + opt->get_type_name();
        if (opt->get_expected_max() == CLI::detail::expected_max_vector_size) out += " ...";
        if (opt->get_required()) out += " (required)";
        return out;
    }

    std::string make_option_desc(const CLI::Option* opt) const override {
        std::string d = opt->get_description();
        if (opt->get_type_size() != 0 && !opt->get_default_str().empty())
            d += " Default: " + opt->get_default_str() + ".";
        return wrap(d, kHelpWidth - kOptionColumn);
    }

    std::string make_description(const CLI::App* app) const override {
        const std::string d = app->get_description();
        return d.empty() ? std::string() : wrap(d, kHelpWidth) + "\n\n";
    }

    std::string make_footer(const CLI::App* app) const override {
        const std::string f = app->get_footer();
        return f.empty() ? std::string() : f + "\n";
    }

    std::string make_subcommand(const CLI::App* sub) const override {
        std::stringstream out;
        CLI::detail::format_help(out, sub->get_display_name(), wrap(sub->get_description(), kHelpWidth - kOptionColumn),
                                 get_column_width());
        return out.str();
    }
};

// "wrsfov-gaze generate": the program and the subcommands down to `app`.
std::string commandPath(const CLI::App* app) {
    std::string path = app->get_name();
    for (const CLI::App* p = app->get_parent(); p; p = p->get_parent()) path = p->get_name() + " " + path;
    return path;
}

// The deepest subcommand the command line selected.
const CLI::App* selected(const CLI::App* app) {
    for (;;) {
        auto subs = app->get_subcommands();
        if (subs.empty()) return app;
        app = subs.front();
    }
}

void printError(const CLI::App* app, const std::string& message) {
    printUsageError(commandPath(app), message);
}

// CLI11's messages where ours say more: the first leftover argument ("unknown option --bogus",
// "unknown command 'x'", not "The following arguments were not expected: 1 --bogus"), a missing
// value, an option given twice, an unknown --config key. The rest as CLI11 words them ("--mode is
// required"); the readers' messages are ours.
std::string message(const CLI::ParseError& e, const CLI::App& app) {
    const std::string what = e.what();
    if (dynamic_cast<const CLI::ExtrasError*>(&e)) {
        for (const CLI::App* a = selected(&app); a; a = a->get_parent()) {
            const std::vector<std::string> left = a->remaining(false);
            if (left.empty()) continue;
            if (left.front().rfind('-', 0) == 0) return "unknown option " + left.front();
            std::string commands;
            for (const CLI::App* sub : a->get_subcommands([](const CLI::App*) { return true; }))
                commands += (commands.empty() ? "" : ", ") + sub->get_name();
            if (!commands.empty()) return "unknown command '" + left.front() + "' (" + commands + ")";
            return "unexpected argument '" + left.front() + "'";
        }
        return what;
    }
    std::smatch m;
    static const std::regex missing("^(\\S+): ([0-9]+) required (.*) missing$");
    static const std::regex twice("^(\\S+): At Most 1 required but received ([0-9]+)$");
    static const std::regex configKey("^INI was not able to parse (.*)$");
    if (std::regex_match(what, m, missing))
        return m[1].str() + ": " + (m[2] == "1" ? "missing value (" : "missing values (") + m[3].str() + ")";
    if (std::regex_match(what, m, twice)) return m[1].str() + ": given " + m[2].str() + " times; give it once";
    if (std::regex_match(what, m, configKey)) return "--config: unknown key '" + m[1].str() + "'";
    return what;
}

}  // namespace

std::optional<long double> parseWhole(std::string_view text) {
    const std::string s(text);
    if (s.empty()) return std::nullopt;
    const size_t digits = (s[0] == '+' || s[0] == '-') ? 1 : 0;
    char* end = nullptr;
    errno = 0;
    if (digits < s.size() && s.find_first_not_of("0123456789", digits) == std::string::npos) {
        if (s[0] == '-') {
            const long long v = std::strtoll(s.c_str(), &end, 10);
            if (errno == ERANGE) return std::nullopt;
            return static_cast<long double>(v);
        }
        const unsigned long long v = std::strtoull(s.c_str(), &end, 10);
        if (errno == ERANGE) return std::nullopt;
        return static_cast<long double>(v);  // exact: long double holds 64 bits of mantissa
    }
    // 1e6, 2.0: a decimal number that is a whole one (no hex, inf or nan).
    if (s.find_first_not_of("0123456789.eE+-") != std::string::npos) return std::nullopt;
    const long double v = std::strtold(s.c_str(), &end);
    if (end == s.c_str() || *end != '\0' || !std::isfinite(v) || v != std::floor(v)) return std::nullopt;
    return v;
}

std::optional<double> parseFinite(std::string_view text) {
    const std::string s(text);
    char* end = nullptr;
    const double v = std::strtod(s.c_str(), &end);
    if (s.empty() || *end != '\0' || !std::isfinite(v)) return std::nullopt;
    return v;
}

std::string showNumber(double v) {
    char b[32];
    std::snprintf(b, sizeof b, "%g", v);
    return b;
}

std::string showWhole(long double v) {
    char b[32];
    std::snprintf(b, sizeof b, "%.0Lf", v);
    return b;
}

std::string rangeText(long double lo, long double hi) {
    return "an integer in " + showWhole(lo) + ".." + showWhole(hi);
}

std::string rangeText(double lo, double hi, Ends ends) {
    const bool openLo = ends == Ends::OpenLow || ends == Ends::Open;
    const bool openHi = ends == Ends::OpenHigh || ends == Ends::Open;
    const bool hasLo = std::isfinite(lo), hasHi = std::isfinite(hi);
    if (!hasLo && !hasHi) return "a finite number";
    if (!hasHi) return std::string("a number ") + (openLo ? "> " : ">= ") + showNumber(lo);
    if (!hasLo) return std::string("a number ") + (openHi ? "< " : "<= ") + showNumber(hi);
    return std::string("a number in ") + (openLo ? "(" : "[") + showNumber(lo) + ", " + showNumber(hi) +
           (openHi ? ")" : "]");
}

bool inRange(double v, double lo, double hi, Ends ends) {
    const bool openLo = ends == Ends::OpenLow || ends == Ends::Open;
    const bool openHi = ends == Ends::OpenHigh || ends == Ends::Open;
    return (openLo ? v > lo : v >= lo) && (openHi ? v < hi : v <= hi);
}

Reader<Size> size(uint32_t lo, uint32_t hi) {
    const std::string what = "WxH with W and H in " + std::to_string(lo) + ".." + std::to_string(hi);
    return {[lo, hi, what](std::string_view text, std::string& why) -> std::optional<Size> {
                const size_t x = text.find('x');
                auto side = [&](std::string_view d) -> std::optional<uint32_t> {
                    if (d.empty() || d.find_first_not_of("0123456789") != std::string_view::npos) return std::nullopt;
                    const auto v = parseWhole(d);
                    if (!v || *v < lo || *v > hi) return std::nullopt;
                    return static_cast<uint32_t>(*v);
                };
                if (x != std::string_view::npos) {
                    const auto w = side(text.substr(0, x)), h = side(text.substr(x + 1));
                    if (w && h) return Size{*w, *h};
                }
                why = "'" + std::string(text) + "' is not " + what;
                return std::nullopt;
            },
            [](const Size& s) { return std::to_string(s.width) + "x" + std::to_string(s.height); }, "WxH"};
}

Reader<Size> squareOrSize(uint32_t lo, uint32_t hi) {
    const std::string what = "S or WxH with each side in " + std::to_string(lo) + ".." + std::to_string(hi);
    const Reader<Size> pair = size(lo, hi);
    return {[lo, hi, what, pair](std::string_view text, std::string& why) -> std::optional<Size> {
                std::optional<Size> v;
                if (text.find('x') != std::string_view::npos) {
                    v = pair.read(text, why);
                } else if (!text.empty() && text.find_first_not_of("0123456789") == std::string_view::npos) {
                    const auto s = parseWhole(text);
                    if (s && *s >= lo && *s <= hi) v = Size{static_cast<uint32_t>(*s), static_cast<uint32_t>(*s)};
                }
                if (!v) why = "'" + std::string(text) + "' is not " + what;
                return v;
            },
            [](const Size& s) {
                return s.width == s.height ? std::to_string(s.width)
                                           : std::to_string(s.width) + "x" + std::to_string(s.height);
            },
            "S|WxH"};
}

Reader<std::string> text(std::string what, std::string type) {
    return {[what](std::string_view t, std::string& why) -> std::optional<std::string> {
                if (t.empty()) {
                    why = "'' is not " + what;
                    return std::nullopt;
                }
                return std::string(t);
            },
            [](const std::string& s) { return s; }, std::move(type)};
}

void setup(CLI::App& app) {
    app.set_help_flag("-h,--help", "Print this help and exit.");
    const std::string version = app.get_name() + " " + WRSFOV_VERSION;
    app.set_version_flag("--version", version, "Print \"" + version + "\" and exit.");
    app.formatter(std::make_shared<Formatter>());
    app.option_defaults()->multi_option_policy(CLI::MultiOptionPolicy::TakeLast);
}

CLI::Option* addConfig(CLI::App& app) {
    CLI::Option* o = app.set_config(
        "--config", "",
        "Read options from a TOML or INI file: one `key = value` per line, the key an option's long name "
        "without the dashes (frames = 50, fovea = \"5,10\", monitor = true). Options on the command line "
        "win over the file; an unknown key is a usage error.");
    o->type_name("FILE");
    app.allow_config_extras(CLI::config_extras_mode::error);
    return o;
}

Parsed parse(CLI::App& app, int argc, const char* const* argv) {
    try {
        app.parse(argc, argv);
        return {};
    } catch (const CLI::CallForHelp&) {
        return {Parsed::Kind::Help, app.help()};
    } catch (const CLI::CallForAllHelp&) {
        return {Parsed::Kind::Help, app.help("", CLI::AppFormatMode::All)};
    } catch (const CLI::CallForVersion& e) {
        return {Parsed::Kind::Version, e.what()};
    } catch (const CLI::FileError& e) {
        return {Parsed::Kind::FileError, e.what()};
    } catch (const CLI::ParseError& e) {
        return {Parsed::Kind::UsageError, message(e, app)};
    }
}

std::optional<int> parseOrExit(CLI::App& app, int argc, const char* const* argv) {
    const Parsed p = parse(app, argc, argv);
    switch (p.kind) {
        case Parsed::Kind::Run:
            return std::nullopt;
        case Parsed::Kind::Help:
            std::fputs(p.text.c_str(), stdout);
            return 0;
        case Parsed::Kind::Version:
            std::printf("%s\n", p.text.c_str());
            return 0;
        case Parsed::Kind::FileError:
            printError(selected(&app), p.text);
            return kExitRuntime;
        case Parsed::Kind::UsageError:
            break;
    }
    printError(selected(&app), p.text);
    return kExitUsage;
}

void printUsageError(const std::string& command, const std::string& message) {
    const std::string program = command.substr(0, command.find(' '));
    std::fprintf(stderr, "%s: %s\nRun '%s --help' for more information.\n", program.c_str(), message.c_str(),
                 command.c_str());
}

int usageError(const CLI::App& app, const std::string& message) {
    printError(&app, message);
    return kExitUsage;
}

}  // namespace wrsfov::cli
