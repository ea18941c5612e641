// JOD against pixels across saving studies (wrsfov-bench --saving-plot, docs/metrics.md "Rendering saved"):
// the rows of one or more saving.csv files of one scene and size, one curve per method and kind of input,
// the fewest pixels at which each curve reaches a target row's JOD, and the curves side by side at equal
// pixels.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <map>
#include <set>
#include <sstream>

#include <opencv2/imgcodecs.hpp>

#include "eval/chart.h"
#include "eval/saving.h"

namespace wrsfov::eval {

namespace {

Error plotError(const std::string& msg) { return Error{1, "saving plot: " + msg}; }

std::string fmt(const char* f, double v) { return savingNumber(f, v); }

std::vector<std::string> splitCsv(const std::string& line) {
    std::vector<std::string> out;
    std::stringstream ss(line);
    std::string cell;
    while (std::getline(ss, cell, ',')) out.push_back(cell);
    if (!line.empty() && line.back() == ',') out.emplace_back();
    return out;
}

// A number of the file: strtod's whole text ("inf", "nan" and "-nan" as writeSavingReport prints them).
std::optional<double> number(const std::string& text) {
    if (text.empty()) return std::nullopt;
    char* end = nullptr;
    const double v = std::strtod(text.c_str(), &end);
    if (end != text.c_str() + text.size()) return std::nullopt;
    return v;
}

}  // namespace

std::string curveName(const SavingRow& r) {
    std::string name(toString(r.method));
    if (r.input == SavingInput::Rate) return name + " (rate)";
    if (r.input == SavingInput::Quad && r.jitterPhases > 1) name += " (jittered)";
    return name;
}

Result<std::vector<SavingRow>> readSavingCsv(const std::string& path) {
    std::ifstream in(path);
    if (!in) return plotError("cannot read " + path);
    std::string line;
    if (!std::getline(in, line)) return plotError(path + " is empty");
    const std::vector<std::string> header = splitCsv(line);
    std::map<std::string, std::size_t> col;
    for (std::size_t i = 0; i < header.size(); ++i) col[header[i]] = i;
    // The columns every saving.csv has had; the jittered study's three are read where present.
    for (const char* need : {"scene", "input", "method", "inset_deg", "pixels_rendered", "render_ms", "compose_ms", "jod",
                             "near_gaze_psnr"})
        if (!col.count(need)) return plotError(path + ": no column \"" + need + "\" (not a saving.csv)");
    std::vector<SavingRow> rows;
    int lineNo = 1;
    while (std::getline(in, line)) {
        ++lineNo;
        if (line.empty()) continue;
        const std::vector<std::string> cells = splitCsv(line);
        const std::string where = path + ":" + std::to_string(lineNo);
        if (cells.size() != header.size())
            return plotError(where + ": " + std::to_string(cells.size()) + " fields where the header has " +
                             std::to_string(header.size()));
        auto cell = [&](const char* name) -> const std::string& { return cells[col.at(name)]; };
        SavingRow r;
        const auto scene = parseScene(cell("scene"));
        const auto method = parseMethod(cell("method"));
        if (!scene) return plotError(where + ": unknown scene \"" + cell("scene") + "\"");
        if (!method) return plotError(where + ": unknown method \"" + cell("method") + "\"");
        r.scene = *scene;
        r.method = *method;
        const std::string& input = cell("input");
        if (input == "full") r.input = SavingInput::Full;
        else if (input == "quad") r.input = SavingInput::Quad;
        else if (input == "rate") r.input = SavingInput::Rate;
        else return plotError(where + ": unknown input \"" + input + "\"");
        // Numbers: the pixels must be a positive count; the scores may be n/a (NaN) but not absent.
        struct Field {
            const char* name;
            double* to;
        };
        double inset = 0, jitter = 0, wide = 0;
        Field fields[] = {{"inset_deg", &inset},     {"pixels_rendered", &r.pixelsRendered}, {"render_ms", &r.renderMs},
                          {"compose_ms", &r.composeMs}, {"jod", &r.jod},                        {"near_gaze_psnr", &r.nearGazePsnr},
                          {"wide_density", &wide},   {"jitter", &jitter},                    {"temporal_instability", &r.temporalInstability}};
        for (const Field& f : fields) {
            if (!col.count(f.name)) continue;
            const auto v = number(cell(f.name));
            if (!v) return plotError(where + ": column " + f.name + " is not a number: \"" + cell(f.name) + "\"");
            *f.to = *v;
        }
        if (!(r.pixelsRendered > 0) || !std::isfinite(r.pixelsRendered))
            return plotError(where + ": pixels_rendered must be a positive count, not " + cell("pixels_rendered"));
        if (!std::isfinite(inset) || inset < 0 || !std::isfinite(wide) || wide < 0 || wide > 1 || !std::isfinite(jitter) ||
            jitter < 0 || jitter > 1024 || jitter != std::floor(jitter))
            return plotError(where + ": inset, wide density or jitter out of range");
        r.insetDeg = float(inset);
        r.wideScale = float(wide);
        r.jitterPhases = uint32_t(jitter);
        // The cell's columns (SavingRow::headPath ...), where the file has them.
        if (col.count("head_path")) r.headPath = cell("head_path");
        if (col.count("split")) {
            r.split = cell("split");
            if (r.split != "train" && r.split != "test")
                return plotError(where + ": split must be train or test, not \"" + r.split + "\"");
        }
        if (col.count("head_deg_per_s")) {
            const auto v = number(cell("head_deg_per_s"));
            if (!v) return plotError(where + ": column head_deg_per_s is not a number: \"" + cell("head_deg_per_s") + "\"");
            r.headDegPerS = *v;
        }
        if (col.count("seed")) {
            const auto v = number(cell("seed"));
            if (!v || !(*v >= 1 && *v <= 4294967295.0) || *v != std::floor(*v))
                return plotError(where + ": seed must be a whole number from 1, not \"" + cell("seed") + "\"");
            r.seed = uint32_t(*v);
        }
        rows.push_back(r);
    }
    return rows;
}

Result<SavingTarget> parseSavingTarget(std::string_view text) {
    // METHOD,DENSITY,INSET[,JITTER]
    std::vector<std::string> parts = splitCsv(std::string(text));
    if (parts.size() < 3 || parts.size() > 4)
        return plotError("a target is METHOD,DENSITY,INSET[,JITTER] (e.g. fov,0.4,30), not \"" + std::string(text) + "\"");
    SavingTarget t;
    const auto m = parseMethod(parts[0]);
    if (!m) return plotError("unknown method \"" + parts[0] + "\" in the target");
    t.method = *m;
    const auto d = number(parts[1]), i = number(parts[2]);
    const auto j = parts.size() == 4 ? number(parts[3]) : std::optional<double>(0.0);
    if (!d || !(*d > 0 && *d <= 1)) return plotError("the target's wide density must be in (0, 1], not \"" + parts[1] + "\"");
    if (!i || !(*i > 0 && *i < 180)) return plotError("the target's inset must be in (0, 180) degrees, not \"" + parts[2] + "\"");
    if (!j || *j < 0 || *j > 1024 || *j != std::floor(*j))
        return plotError("the target's jitter must be a count of phases, not \"" + parts.back() + "\"");
    t.wideScale = float(*d);
    t.insetDeg = float(*i);
    t.jitterPhases = uint32_t(*j);
    return t;
}

std::vector<SavingFrontPoint> savingFront(const std::vector<SavingRow>& curve) {
    std::vector<const SavingRow*> sorted;
    for (const SavingRow& r : curve)
        if (std::isfinite(r.jod)) sorted.push_back(&r);
    std::sort(sorted.begin(), sorted.end(), [](auto* a, auto* b) {
        return a->pixelsRendered != b->pixelsRendered ? a->pixelsRendered < b->pixelsRendered : a->jod > b->jod;
    });
    std::vector<SavingFrontPoint> front;
    for (const SavingRow* r : sorted)
        if (front.empty() || r->jod > front.back().jod) front.push_back({r->pixelsRendered, r->renderMs, r->jod});
    return front;
}

SavingReach savingReach(const std::vector<SavingFrontPoint>& front, double targetJod) {
    SavingReach out;
    if (front.empty() || !std::isfinite(targetJod)) return out;
    std::vector<std::pair<double, double>> curve;
    for (const SavingFrontPoint& p : front) curve.push_back({p.pixels, p.jod});
    const FoveaWorth w = foveaWorth(curve, targetJod);
    out.bound = w.bound;
    out.pixels = w.deg;
    // The render time linearly in the pixels between the two front points around them.
    for (std::size_t i = 0; i < front.size(); ++i) {
        if (front[i].pixels == out.pixels) {
            out.renderMs = front[i].renderMs;
            break;
        }
        if (i > 0 && front[i - 1].pixels < out.pixels && out.pixels < front[i].pixels) {
            const double f = (out.pixels - front[i - 1].pixels) / (front[i].pixels - front[i - 1].pixels);
            out.renderMs = front[i - 1].renderMs + (front[i].renderMs - front[i - 1].renderMs) * f;
            break;
        }
    }
    return out;
}

Status writeJodAgainstPixels(const std::vector<SavingRow>& rows, const std::optional<SavingTarget>& target,
                             const std::string& dir, std::string* summary) {
    // One scene at one size: every file's full-resolution row the same.
    const SavingRow* full = nullptr;
    for (const SavingRow& r : rows) {
        if (r.input != SavingInput::Full) continue;
        if (full && (full->scene != r.scene || full->pixelsRendered != r.pixelsRendered))
            return plotError("the studies are of different cells: full resolution renders " +
                             fmt("%.0f", full->pixelsRendered) + " pixels of the " + std::string(toString(full->scene)) +
                             " in one and " + fmt("%.0f", r.pixelsRendered) + " of the " +
                             std::string(toString(r.scene)) + " in another");
        full = &r;
    }
    if (!full) return plotError("no full-resolution row: the pixels need its count");
    for (const SavingRow& r : rows)
        if (r.scene != full->scene) return plotError("the studies are of different scenes");
    const double fullPx = full->pixelsRendered;
    const bool hasRender = std::isfinite(full->renderMs);

    // The curves, in the order their first row comes.
    std::vector<std::string> names;
    std::map<std::string, std::vector<SavingRow>> curves;
    std::map<std::string, Method> methodOf;
    for (const SavingRow& r : rows) {
        if (r.input == SavingInput::Full) continue;
        const std::string n = curveName(r);
        if (!curves.count(n)) names.push_back(n);
        curves[n].push_back(r);
        methodOf[n] = r.method;
    }
    if (names.empty()) return plotError("no foveated rows to plot");

    const SavingRow* targetRow = nullptr;
    if (target) {
        for (const SavingRow& r : rows)
            if (r.input == SavingInput::Quad && r.method == target->method &&
                std::fabs(r.wideScale - target->wideScale) < 1e-4f && std::fabs(r.insetDeg - target->insetDeg) < 1e-3f &&
                (r.jitterPhases > 1) == (target->jitterPhases > 1))
                targetRow = &r;
        if (!targetRow)
            return plotError("no row of " + std::string(toString(target->method)) + " at wide density " +
                             fmt("%.2f", target->wideScale) + ", inset " + fmt("%.0f°", target->insetDeg) +
                             (target->jitterPhases > 1 ? ", jittered" : ", unjittered") + " for the target");
        if (!std::isfinite(targetRow->jod)) return plotError("the target row has no JOD (a --no-jod study?)");
    }

    std::ostringstream md;
    md << "# JOD against pixels: " << toString(full->scene) << "\n\n";
    md << "Full resolution renders " << fmt("%.0f", fullPx) << " pixels per frame (both eyes)"
       << (hasRender ? ", in " + fmt("%.2f", full->renderMs) + " ms" : std::string()) << ". One curve per method and kind "
       << "of input (jittered: the wide views rendered over several sub-pixel phases); each point a wide density and "
          "inset. ![JOD against pixels](jod_vs_pixels.png)\n\n";
    std::ostringstream head;
    if (targetRow) {
        head << "The target: " << toString(targetRow->method) << " at wide density " << fmt("%.2f", targetRow->wideScale)
             << " with a " << fmt("%.0f°", targetRow->insetDeg) << " inset"
             << (targetRow->jitterPhases > 1 ? ", jittered" : ", unjittered") << ", JOD **" << fmt("%.2f", targetRow->jod)
             << "** with " << fmt("%.1f %%", 100.0 * targetRow->pixelsRendered / fullPx)
             << " of full resolution's pixels. The fewest pixels at which each curve reaches it (interpolated along the "
                "curve's best points, those no cheaper point beats):\n\n";
        head << "| curve | pixels × full | render ms | measured point that reaches it |\n|---|---|---|---|\n";
        for (const std::string& n : names) {
            const SavingReach reach = savingReach(savingFront(curves[n]), targetRow->jod);
            const SavingRow* first = nullptr;  // the cheapest measured point at or above the target
            for (const SavingRow& r : curves[n])
                if (r.jod >= targetRow->jod && (!first || r.pixelsRendered < first->pixelsRendered)) first = &r;
            std::string where;
            switch (reach.bound) {
            case FoveaWorth::Bound::Exact: where = fmt("%.1f %%", 100.0 * reach.pixels / fullPx); break;
            case FoveaWorth::Bound::AtMost: where = fmt("%.1f %% or less", 100.0 * reach.pixels / fullPx); break;
            case FoveaWorth::Bound::MoreThan: where = "not reached (" + fmt("%.1f %%", 100.0 * reach.pixels / fullPx) + " measured)"; break;
            case FoveaWorth::Bound::Unknown: where = "n/a"; break;
            }
            head << "| " << n << " | " << where << " | "
                 << (reach.bound == FoveaWorth::Bound::MoreThan ? "n/a" : fmt("%.2f", reach.renderMs)) << " | "
                 << (first ? fmt("%.2f", first->wideScale) + " / " + fmt("%.0f°", first->insetDeg) + ": " +
                                 fmt("%.1f %%", 100.0 * first->pixelsRendered / fullPx) + ", JOD " + fmt("%.2f", first->jod)
                           : std::string("none")) << " |\n";
        }
        head << "\n";
    }
    // At equal pixels: the rows of each (density, inset, jitter) side by side.
    struct Key {
        float wide, inset;
        bool jittered;
        SavingInput input;
        auto operator<=>(const Key&) const = default;
    };
    std::map<Key, std::map<std::string, const SavingRow*>> byInput;
    for (const SavingRow& r : rows)
        if (r.input != SavingInput::Full) byInput[{r.wideScale, r.insetDeg, r.jitterPhases > 1, r.input}][curveName(r)] = &r;
    std::vector<std::string> shared;  // curves with a row at a configuration another curve shares
    for (const std::string& n : names)
        for (const auto& [k, m] : byInput)
            if (m.size() > 1 && m.count(n)) {
                shared.push_back(n);
                break;
            }
    if (!shared.empty()) {
        head << "At equal pixels (the same views composed by each method), JOD and temporal instability:\n\n| views | pixels × full |";
        for (const std::string& n : shared) head << ' ' << n << " |";
        head << "\n|---|---|";
        for (std::size_t i = 0; i < shared.size(); ++i) head << "---|";
        head << '\n';
        for (const auto& [k, m] : byInput) {
            if (m.size() < 2) continue;
            head << "| " << (k.input == SavingInput::Rate ? "rate " + fmt("%.0f°", k.inset)
                                                          : fmt("%.2f", k.wide) + " / " + fmt("%.0f°", k.inset) +
                                                                (k.jittered ? ", jittered" : ""))
                 << " | " << fmt("%.1f %%", 100.0 * m.begin()->second->pixelsRendered / fullPx) << " |";
            for (const std::string& n : shared) {
                auto it = m.find(n);
                head << ' ' << (it == m.end() ? std::string("–")
                                              : fmt("%.2f", it->second->jod) + " / " + fmt("%.4f", it->second->temporalInstability))
                     << " |";
            }
            head << '\n';
        }
        head << '\n';
    }
    md << head.str();
    md << "## Every row\n\n| curve | wide density | inset | jitter | pixels × full | render ms | compose ms | JOD | near-gaze PSNR "
          "| temporal instability |\n|---|---|---|---|---|---|---|---|---|---|\n";
    for (const std::string& n : names) {
        std::vector<SavingRow> c = curves[n];
        std::sort(c.begin(), c.end(), [](const SavingRow& a, const SavingRow& b) { return a.pixelsRendered < b.pixelsRendered; });
        for (const SavingRow& r : c)
            md << "| " << n << " | " << fmt("%.2f", r.wideScale) << " | " << fmt("%.0f°", r.insetDeg) << " | " << r.jitterPhases
               << " | " << fmt("%.1f %%", 100.0 * r.pixelsRendered / fullPx) << " | " << fmt("%.2f", r.renderMs) << " | "
               << fmt("%.2f", r.composeMs) << " | " << fmt("%.2f", r.jod) << " | " << fmt("%.2f", r.nearGazePsnr) << " | "
               << fmt("%.4f", r.temporalInstability) << " |\n";
    }
    {
        std::ofstream f(dir + "/jod_vs_pixels.md");
        if (!f || !(f << md.str())) return plotError("cannot write " + dir + "/jod_vs_pixels.md");
    }

    // The target's level first, under the curves, as a line without dots (its own row is a curve's point).
    std::vector<Series> series;
    if (targetRow) series.push_back({"target", {150, 150, 150}, {}, {}, true, false});
    for (const std::string& n : names) {
        std::vector<SavingRow> c = curves[n];
        std::sort(c.begin(), c.end(), [](const SavingRow& a, const SavingRow& b) { return a.pixelsRendered < b.pixelsRendered; });
        Series s;
        s.name = n;
        s.colour = methodColour(methodOf[n]);
        if (n.find("(jittered)") == std::string::npos && methodOf[n] == Method::Fov && curves.count("fov (jittered)"))
            s.colour *= 0.55;  // fov on unjittered views beside fov on jittered ones
        s.line = true;
        for (const SavingRow& r : c) {
            s.points.push_back({100.0 * r.pixelsRendered / fullPx, r.jod});
            s.labels.push_back(fmt("%.2f", r.wideScale) + "/" + fmt("%.0f", r.insetDeg));
        }
        series.push_back(std::move(s));
    }
    if (targetRow) {
        double lo = 1e300, hi = -1e300;
        for (const Series& s : series)
            for (const auto& p : s.points) lo = std::min(lo, p.x), hi = std::max(hi, p.x);
        series.front().points = {{lo, targetRow->jod}, {hi, targetRow->jod}};
    }
    const std::string title = std::string(toString(full->scene)) + ": FovVideoVDP JOD against the pixels rendered";
    if (!cv::imwrite(dir + "/jod_vs_pixels.png", chart(title, "% of full resolution's pixels per frame", "JOD", series)))
        return plotError("cannot write " + dir + "/jod_vs_pixels.png");
    if (summary) *summary = head.str();
    return {};
}

}  // namespace wrsfov::eval
