// The tools' command lines, read with CLI11: readers that turn an option's text into a value and
// say what is wrong with a bad one, one --help style (every option with a sentence and its
// default), --version, and the exit codes of docs/bad-input.md: 0 after --help and --version, 2 for
// a usage error (unknown option, missing or bad value, bad combination), 1 for a run-time error.
#pragma once

#include <CLI/CLI.hpp>

#include <functional>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace wrsfov::cli {

inline constexpr int kExitUsage = 2;
inline constexpr int kExitRuntime = 1;

/// Turns an option's text into a T, or says why it cannot ("'2.5' is not an integer in 2..100000";
/// CLI11 puts the option's name in front).
template <typename T>
struct Reader {
    std::function<std::optional<T>(std::string_view text, std::string& why)> read;
    std::function<std::string(const T&)> show;  ///< a value as the option would take it (defaults in --help)
    std::string type;                           ///< the value's placeholder in --help ("N", "WxH")
};

// The parsing cores of the readers below. Whole numbers: decimal digits with an optional sign, or
// a decimal form of an integer such as 1e6; never octal or hex.
std::optional<long double> parseWhole(std::string_view text);
std::optional<double> parseFinite(std::string_view text);  ///< strtod, all of it, finite
std::string showNumber(double v);                          ///< %g
std::string showWhole(long double v);

/// Which ends of a number range belong to it.
enum class Ends { Closed, OpenLow, OpenHigh, Open };
/// "an integer in 2..100000", "a number in (0, 60]", "a number > 0", "a finite number".
std::string rangeText(long double lo, long double hi);
std::string rangeText(double lo, double hi, Ends ends);
bool inRange(double v, double lo, double hi, Ends ends);

/// An integer in lo..hi (1e6 forms too). `what` replaces "an integer in lo..hi" in messages.
template <typename T>
Reader<T> integer(T lo, T hi, std::string what = {}) {
    if (what.empty()) what = rangeText(static_cast<long double>(lo), static_cast<long double>(hi));
    return {[lo, hi, what](std::string_view text, std::string& why) -> std::optional<T> {
                const auto v = parseWhole(text);
                if (!v || *v < static_cast<long double>(lo) || *v > static_cast<long double>(hi)) {
                    why = "'" + std::string(text) + "' is not " + what;
                    return std::nullopt;
                }
                return static_cast<T>(*v);
            },
            [](const T& v) { return showWhole(static_cast<long double>(v)); }, "N"};
}

/// A finite number between lo and hi (either may be infinite: no bound on that side).
template <typename T>
Reader<T> number(double lo, double hi, Ends ends = Ends::Closed, std::string what = {}) {
    if (what.empty()) what = rangeText(lo, hi, ends);
    return {[lo, hi, ends, what](std::string_view text, std::string& why) -> std::optional<T> {
                const auto v = parseFinite(text);
                if (!v || !inRange(*v, lo, hi, ends)) {
                    why = "'" + std::string(text) + "' is not " + what;
                    return std::nullopt;
                }
                return static_cast<T>(*v);
            },
            [](const T& v) { return showNumber(double(v)); }, "X"};
}

/// Width and height, "WxH", each in lo..hi.
struct Size {
    uint32_t width = 0, height = 0;
};
Reader<Size> size(uint32_t lo, uint32_t hi);
/// A size given as "S" (square, S x S) or "WxH", each side in lo..hi.
Reader<Size> squareOrSize(uint32_t lo, uint32_t hi);

/// A non-empty text (a file or directory name); `what` is its noun: "'' is not a file name".
Reader<std::string> text(std::string what, std::string type);

/// One of the named values.
template <typename T>
Reader<T> oneOf(std::vector<std::pair<std::string, T>> names) {
    std::string list;
    for (const auto& n : names) list += (list.empty() ? "" : ", ") + n.first;
    return {[names, list](std::string_view text, std::string& why) -> std::optional<T> {
                for (const auto& n : names)
                    if (n.first == text) return n.second;
                why = "'" + std::string(text) + "' is not one of " + list;
                return std::nullopt;
            },
            [names](const T& v) {
                for (const auto& n : names)
                    if (n.second == v) return n.first;
                return std::string("?");
            },
            "NAME"};
}

/// A value the project reads itself: `parse` gives it or nullopt ("'TEXT' is not WHAT").
template <typename T>
Reader<T> parsedBy(std::function<std::optional<T>(std::string_view)> parse, std::function<std::string(const T&)> show,
                   std::string what, std::string type = "NAME") {
    return {[parse, what](std::string_view text, std::string& why) -> std::optional<T> {
                auto v = parse(text);
                if (!v) why = "'" + std::string(text) + "' is not " + what;
                return v;
            },
            std::move(show), std::move(type)};
}

/// A comma-separated list of items (empty items are skipped, so "," is an empty list); a bad item
/// is named alone.
template <typename T>
Reader<std::vector<T>> list(Reader<T> item) {
    return {[item](std::string_view text, std::string& why) -> std::optional<std::vector<T>> {
                std::vector<T> out;
                size_t start = 0;
                while (start <= text.size()) {
                    const size_t end = std::min(text.find(',', start), text.size());
                    const std::string_view part = text.substr(start, end - start);
                    if (!part.empty()) {
                        auto v = item.read(part, why);
                        if (!v) return std::nullopt;
                        out.push_back(std::move(*v));
                    }
                    start = end + 1;
                }
                return out;
            },
            [item](const std::vector<T>& v) {
                std::string s;
                for (const T& x : v) s += (s.empty() ? "" : ",") + item.show(x);
                return s;
            },
            item.type + ",..."};
}

/// A CLI11 check that refuses what `reader` cannot read (for CLI11's own typed options, such as
/// two-value ones); the text is left as it is.
template <typename T>
CLI::Validator check(Reader<T> reader) {
    return CLI::Validator(
        [read = reader.read](std::string& s) {
            std::string why;
            return read(s, why) ? std::string() : why;
        },
        "");
}

/// An option that takes one value, read by `reader` into `target` (whose value is the default
/// shown in --help). Given more than once, the last one counts.
template <typename T>
CLI::Option* option(CLI::App& app, const std::string& name, T& target, Reader<T> reader,
                    const std::string& description) {
    CLI::Option* o = app.add_option_function<std::string>(
        name,
        [&target, read = reader.read](const std::string& s) {
            std::string why;
            if (auto v = read(s, why)) target = std::move(*v);
        },
        description);
    o->check(check(reader));
    o->type_name(reader.type);
    o->default_str(reader.show(target));
    return o;
}

/// A list option: one value split at commas on the command line ("5,7.5,10"), or a TOML/INI array
/// in a --config file (`fovea = [5, 7.5, 10]`); every item goes through `reader`'s item check. Given
/// more than once, the items of all of them count, in order.
template <typename T>
CLI::Option* listOption(CLI::App& app, const std::string& name, std::vector<T>& target, Reader<std::vector<T>> reader,
                        const std::string& description) {
    CLI::Option* o = option(app, name, target, reader, description);
    o->expected(1, CLI::detail::expected_max_vector_size);
    o->delimiter(',');
    o->multi_option_policy(CLI::MultiOptionPolicy::Join);
    return o;
}

/// The common parts of every tool's command line: --help and --version ("NAME 0.1.0", the CMake
/// project version), the help layout (option, placeholder, sentence, default), and repeated options
/// taking the last value.
void setup(CLI::App& app);

/// --config FILE: the tool's options from a TOML or INI file (`key = value`, keys the long option
/// names without the dashes); unknown keys are a usage error, the command line wins over the file.
CLI::Option* addConfig(CLI::App& app);

/// What parsing came to.
struct Parsed {
    enum class Kind { Run, Help, Version, UsageError, FileError } kind = Kind::Run;
    std::string text;  ///< the help text, the version line or the error message
};
Parsed parse(CLI::App& app, int argc, const char* const* argv);

/// Parses and, where the program should stop, prints (help and version to stdout, errors to
/// stderr as "NAME: message" with a pointer to --help) and returns the exit status: 0 after --help
/// and --version, 2 for a usage error, 1 for an unreadable --config file. nullopt: run.
std::optional<int> parseOrExit(CLI::App& app, int argc, const char* const* argv);

/// A usage error found after parsing (a bad combination of options), printed like the others; 2.
int usageError(const CLI::App& app, const std::string& message);
/// Prints "PROGRAM: message" and "Run 'COMMAND --help' for more information." to stderr;
/// `command` is the program and its subcommand ("wrsfov-gaze generate").
void printUsageError(const std::string& command, const std::string& message);

}  // namespace wrsfov::cli
