#include "stress/report.h"

#include <algorithm>
#include <cmath>
#include <cstdarg>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <sstream>

namespace wrsfov::stress {

namespace {

std::string fmt(const char* f, ...) {
    va_list ap, copy;
    va_start(ap, f);
    va_copy(copy, ap);
    const int n = std::vsnprintf(nullptr, 0, f, copy);
    va_end(copy);
    std::string b(size_t(std::max(n, 0)) + 1, '\0');
    std::vsnprintf(b.data(), b.size(), f, ap);
    va_end(ap);
    b.resize(size_t(std::max(n, 0)));
    return b;
}
std::string num(double v) {
    if (std::isnan(v)) return "nan";
    if (std::isinf(v)) return v > 0 ? "inf" : "-inf";
    return fmt("%.4g", v);
}
std::string zs(const ZTest& t) { return t.variance > 0 || t.observed > 0 ? fmt("%+.2f", t.z()) : "–"; }
std::string chis(const ChiSquare& c) { return c.valid ? fmt("%.3g (%d) p=%.2g", c.chi2, c.dof, c.p) : "–"; }
std::string count(uint64_t v) { return std::to_string(v); }
double hours90(uint64_t frames) { return double(frames) / 90.0 / 3600.0; }

const FormatStats* statsOf(const StreamResult& s, FormatId f) {
    for (const FormatStats& x : s.formats)
        if (x.format == f) return &x;
    return nullptr;
}

}  // namespace

bool selectionAsserted(const Stream& stream) {
    return stream.domain != Domain::Outside && stream.knownDeviation.empty();
}

HorizonStudy runHorizonStudy(bool quick) {
    HorizonStudy h;
    const float wMin = minPipelineWeight();
    const uint64_t limit = uint64_t(1) << 26;
    // The shipping layout takes ~10^7 frames per weight to freeze; quick runs keep w = 1 only.
    std::vector<float> weights{1.0f, wMin};
    if (!quick) {
        // 0.995: the largest overshoot of the exact-math bound found on a 0.0025 grid over [0.9, 1];
        // 0.9975: the earliest 1 % drift from the exact model found there (about 10^6 frames).
        for (float w : {0.9975f, 0.995f, 0.5f, 0.1f, 1e-6f}) weights.push_back(w);
        for (int k = 1; k < 12; ++k) weights.push_back(std::pow(wMin, float(k) / 12.0f));
    }
    std::sort(weights.begin(), weights.end(), std::greater<>());
    for (float w : weights) {
        if (!quick || w == 1.0f) h.runs.push_back(horizon(FormatId::Chosen, w, true, limit));
        h.runs.push_back(horizon(FormatId::WsumF16, w, true, limit));
    }
    for (float w : {1.0f, wMin}) {
        if (!quick) h.runs.push_back(horizon(FormatId::Chosen, w, false, limit));
        h.runs.push_back(horizon(FormatId::WsumF16, w, false, limit));
    }
    const int binadeSteps = quick ? 0 : 256;
    for (int k = 0; k < binadeSteps; ++k)
        h.binade.push_back(horizon(FormatId::Chosen, 0.5f + 0.5f * float(k) / float(binadeSteps), true, limit));
    std::vector<double> ceilings;
    for (int v = 0; v < 256; ++v) {
        const float lin = gpu::wrs_srgb_to_linear(float(v) / 255.0f);
        const gpu::vec3 c(lin), r(gpu::wrs_round_f16(lin));
        const double d = gpu::wrs_change(gpu::WRS_CHANGE_LSTAR, c, r);
        h.greyLevels++;
        if (d == 0.0)
            h.greyLevelsExact++;
        else
            ceilings.push_back(1.0 / std::sqrt(d));
    }
    std::sort(ceilings.begin(), ceilings.end());
    if (!ceilings.empty()) {
        h.ceilingMin = ceilings.front();
        h.ceilingMax = ceilings.back();
        h.ceilingMedian = ceilings[ceilings.size() / 2];
    }
    return h;
}

std::vector<Check> evaluate(const CpuResult* cpu, const GpuResult* gpu) {
    std::vector<Check> checks;
    if (cpu) {
        for (const StreamResult& s : cpu->streams) {
            const FormatStats* f = statsOf(s, FormatId::Chosen);
            if (!f || s.stream.domain == Domain::Outside) continue;
            const std::string name = "cpu " + s.stream.name + ": ";
            auto add = [&](const std::string& what, bool pass, const std::string& detail) {
                checks.push_back({name + what, pass, detail});
            };
            add("no NaN/Inf or w_sum <= 0 stored, no NaN/Inf output",
                f->nonFiniteStored == 0 && f->nonFiniteOutput == 0,
                fmt("stored %llu, output %llu", (unsigned long long)f->nonFiniteStored,
                    (unsigned long long)f->nonFiniteOutput));
            add("w_sum within its bound", f->boundRatioMax <= kBoundSlack,
                fmt("max w_sum / bound = %.4f (limit %.2f)", f->boundRatioMax, kBoundSlack));
            add("M never wraps, history never lost to storage", f->mWraps == 0 && f->lost == 0,
                fmt("wraps %llu, lost %llu", (unsigned long long)f->mWraps, (unsigned long long)f->lost));
            add("kept sample is its candidate, weight-0 candidates never selected",
                f->identityViolations == 0 && f->zeroWeightSelected == 0,
                fmt("identity %llu, weight-0 selected %llu", (unsigned long long)f->identityViolations,
                    (unsigned long long)f->zeroWeightSelected));
            if (!selectionAsserted(s.stream)) continue;
            const bool condOk =
                !(std::fabs(f->conditional.z()) >= kZLimit) && !(std::fabs(f->conditionalAfterCap.z()) >= kZLimit);
            add("replacements match eq. 7 given the loaded history", condOk,
                fmt("z = %+.2f, after M cap z = %+.2f", f->conditional.z(), f->conditionalAfterCap.z()));
            if (!s.modelWsum.empty()) {
                add("new-candidate frames match the exact model", !(std::fabs(f->unconditional.z()) >= kZLimit),
                    fmt("z = %+.2f (%.0f observed, %.1f expected)", f->unconditional.z(), f->unconditional.observed,
                        f->unconditional.expected));
                const bool chiOk =
                    (!f->chiMid.valid || f->chiMid.p > kChiLimit) && (!f->chiFinal.valid || f->chiFinal.p > kChiLimit);
                add("kept sample's (class, age) matches the exact model", chiOk,
                    fmt("N/2: %s; N: %s", chis(f->chiMid).c_str(), chis(f->chiFinal).c_str()));
            }
        }
    }
    if (gpu) {
        uint64_t selection = 0, near = 0, rounding = 0, zm = 0, nonFinite = 0, step = 0, wsum = 0, pf = 0;
        uint32_t ulp = 0;
        double rel = 0;
        for (const GpuRowStats& r : gpu->rows) {
            selection += r.selectionMismatch;
            near += r.nearThreshold;
            rounding += r.weightRounding;
            zm += r.zmMismatch;
            nonFinite += r.nonFinite;
            step += r.stepMismatch;
            wsum += r.wsumMismatch;
            pf += r.pixelFrames;
            ulp = std::max(ulp, r.wsumMaxUlp);
            rel = std::max(rel, r.wsumMaxRel);
        }
        checks.push_back({"gpu: same selections as the lockstep reference (except within 1e-5 of the threshold)",
                          selection == near,
                          fmt("%llu differ, %llu of them near the threshold; %llu w-field roundings; %llu resyncs",
                              (unsigned long long)selection, (unsigned long long)near, (unsigned long long)rounding,
                              (unsigned long long)gpu->resyncs)});
        checks.push_back({"gpu: z and M identical", zm == 0, fmt("%llu differ", (unsigned long long)zm)});
        checks.push_back({"gpu: w_sum within the tolerance", rel <= kWsumTolerance,
                          fmt("%llu of %llu pixel-frames not bit-identical, max %u ulp, max relative %.2g (limit %.0e)",
                              (unsigned long long)wsum, (unsigned long long)pf, ulp, rel, kWsumTolerance)});
        checks.push_back({"gpu: final reservoirs agree", gpu->finalAgree == gpu->finalPixels,
                          fmt("%llu of %llu agree, %llu bit-identical", (unsigned long long)gpu->finalAgree,
                              (unsigned long long)gpu->finalPixels, (unsigned long long)gpu->finalIdentical)});
        checks.push_back({"gpu: no NaN/Inf or w_sum <= 0 in reservoirs", nonFinite == 0,
                          fmt("%llu", (unsigned long long)nonFinite)});
        checks.push_back(
            {"gpu: stress step equals the reference step", step == 0, fmt("%llu", (unsigned long long)step)});
        checks.push_back({"gpu: no validation errors", gpu->validationErrors == 0,
                          gpu->validation ? fmt("%u", gpu->validationErrors) : std::string("validation layer off")});
    }
    return checks;
}

std::string markdownReport(const ReportInput& in) {
    std::ostringstream o;
    o << "# wrsfov-stress report\n\n";
    if (!in.commandLine.empty()) o << "`" << in.commandLine << "`\n\n";
    if (in.cpu) {
        const CpuOptions& c = in.cpu->options;
        o << fmt("CPU reference: %llu frames x %u pixels per stream, %zu streams, %zu formats, seed %u: %.1f s.\n",
                 (unsigned long long)c.frames, c.pixels, in.cpu->streams.size(), c.formats.size(), c.seed,
                 in.cpu->wall_s);
    }
    if (in.gpu)
        o << fmt("GPU: %llu frames of %ux%u per eye on %s%s: %.1f s (%.0f frames/s).\n",
                 (unsigned long long)in.gpu->frames, in.gpu->width, in.gpu->height, in.gpu->device.c_str(),
                 in.gpu->validation ? " (Khronos validation on)" : "", in.gpu->wall_s,
                 in.gpu->wall_s > 0 ? double(in.gpu->frames) / in.gpu->wall_s : 0.0);
    o << fmt("Wall time %.1f s.\n\n", in.wall_s);

    int failed = 0;
    for (const Check& c : in.checks) failed += !c.pass;
    o << "## Verdict\n\n"
      << (failed ? fmt("**%d of %zu checks failed.**\n\n", failed, in.checks.size())
                 : fmt("All %zu checks pass.\n\n", in.checks.size()));
    for (const Check& c : in.checks)
        if (!c.pass) o << "- FAIL " << c.what << ": " << c.detail << "\n";
    if (failed) o << "\n";

    if (in.cpu) {
        const uint64_t N = in.cpu->options.frames;
        o << "## CPU reference, shipping layout\n\n"
          << "Per stream, over all pixels and frames. z: replacements against eq. 7 / Alg. 2 given the loaded "
             "history (cond), after M reached 65535 (cap), and new-candidate frames against the exact model "
             "(exact); χ²: kept sample's (class, age) against the exact model at N/2 and N (value, dof, upper tail). "
             "Pass: |z| < "
          << kZLimit << ", p > " << kChiLimit << ".\n\n";
        o << "| stream | domain | w_sum min | w_sum max | w_sum at N | exact at N | max w_sum/bound | M max | "
             "pixel-frames at M cap | first cap | NaN/Inf stored | NaN/Inf out | flushes | replaced / decisions | "
             "z cond | z cap | z exact | χ² N/2 | χ² N |\n";
        o << "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n";
        for (const StreamResult& s : in.cpu->streams) {
            const FormatStats* f = statsOf(s, FormatId::Chosen);
            if (!f) continue;
            o << "| " << s.stream.name << " | " << toString(s.stream.domain) << " | " << num(f->wsumMin) << " | "
              << num(f->wsumMax) << " | " << num(f->wsumFinalMean) << " | "
              << (s.modelWsum.empty() ? "–" : num(s.modelWsum.back())) << " | "
              << (s.stream.domain == Domain::Outside ? "–" : fmt("%.3f", f->boundRatioMax)) << " | " << f->mMax << " | "
              << count(f->mAtCap) << " | " << count(f->firstCapFrame) << " | " << count(f->nonFiniteStored) << " | "
              << count(f->nonFiniteOutput) << " | " << count(f->flushes) << " | " << count(f->replaced) << " / "
              << count(f->decisions) << " | " << zs(f->conditional) << " | " << zs(f->conditionalAfterCap) << " | "
              << zs(f->unconditional) << " | " << chis(f->chiMid) << " | " << chis(f->chiFinal) << " |\n";
        }
        o << "\n";
        for (const StreamResult& s : in.cpu->streams)
            if (!s.stream.knownDeviation.empty())
                o << "- `" << s.stream.name << "` (known deviation): " << s.stream.knownDeviation << ".\n";
        o << "\nStreams:\n\n";
        for (const StreamResult& s : in.cpu->streams)
            o << "- `" << s.stream.name << "`: " << s.stream.description << ".\n";
        o << "\n";

        if (in.cpu->options.formats.size() > 1) {
            o << "## Precision study: stream x storage format\n\n"
              << "Formats other than `chosen` are study variants (stress/formats.h). frozen: pixel 0's stored "
                 "w_sum never changes again from that frame; lost: the reservoir stored last frame loads as invalid; "
                 "invalid stored: a non-finite field or w_sum <= 0; kept ≠ f32: pixel-frames whose kept sample "
                 "differs from the fp32 baseline's (same random numbers).\n\n";
            o << "| stream | format | w_sum min | w_sum max | w_sum at N | frozen from | M max | lost | invalid stored "
                 "| "
                 "kept ≠ f32 | z exact | χ² N |\n";
            o << "|---|---|---|---|---|---|---|---|---|---|---|---|\n";
            for (const StreamResult& s : in.cpu->streams)
                for (const FormatStats& f : s.formats) {
                    const double pf = double(N) * double(in.cpu->options.pixels);
                    o << "| " << s.stream.name << " | " << formatInfo(f.format).name << " | " << num(f.wsumMin) << " | "
                      << num(f.wsumMax) << " | " << num(f.wsumFinalMean) << " | "
                      << (f.wsumFrozenFrom ? count(f.wsumFrozenFrom) : "–") << " | " << f.mMax << " | " << count(f.lost)
                      << " | " << count(f.nonFiniteStored) << " | "
                      << fmt("%.3g %%", 100.0 * double(f.divergentFrames) / pf) << " | " << zs(f.unconditional) << " | "
                      << chis(f.chiFinal) << " |\n";
                }
            o << "\n";
        }
    }

    if (in.horizon) {
        const HorizonStudy& h = *in.horizon;
        o << "## Safe horizon\n\n"
          << "A pixel given the same weight w every frame, identical colour (|ΔL| = 0), no flush: the frame from "
             "which its stored w_sum no longer changes (the increment is below half an ulp), in frames and hours "
             "at 90 Hz, with the stored and the exact w_sum there.\n\n";
        o << "| format | bias | w | frozen at frame | hours @ 90 Hz | stored w_sum | exact w_sum | > 1 % off exact "
             "from | max w_sum / (w bound) | note |\n"
             "|---|---|---|---|---|---|---|---|---|---|\n";
        for (const Horizon& r : h.runs)
            o << "| " << formatInfo(r.format).name << " | " << (r.bernoulli ? "eq. 6" : "off") << " | " << num(r.weight)
              << " | " << (r.frame ? count(r.frame) : "> 2^26") << " | "
              << (r.frame ? fmt("%.3g", hours90(r.frame)) : "–") << " | " << num(r.wsum) << " | " << num(r.exactWsum)
              << " | " << (r.drift1 ? count(r.drift1) : "–") << " | " << fmt("%.4f", r.maxBoundRatio) << " | "
              << (r.lost ? "stored w_sum rounds to 0: history dropped every frame" : "") << " |\n";
        if (!h.binade.empty()) {
            std::vector<double> frozen, drift;
            double boundMax = 0, ratioLo = INFINITY, ratioHi = 0;
            size_t over = 0;
            for (const Horizon& r : h.binade) {
                frozen.push_back(double(r.frame));
                if (r.drift1) drift.push_back(double(r.drift1));
                ratioLo = std::min(ratioLo, r.wsum / r.weight);
                ratioHi = std::max(ratioHi, r.wsum / r.weight);
                boundMax = std::max(boundMax, r.maxBoundRatio);
                over += r.maxBoundRatio > 1.0;
            }
            std::sort(frozen.begin(), frozen.end());
            std::sort(drift.begin(), drift.end());
            const size_t drifted = drift.size();
            if (drift.empty()) drift.push_back(0);
            o << fmt(
                "\nShipping layout over one binade of weights (%zu weights in [0.5, 1); by scale invariance every "
                "weight from ~1e-26 to 1): w_sum freezes between frame %.0f and %.0f (median %.0f; %.1f to %.1f h "
                "at 90 Hz) at %.0f w to %.0f w. %zu of them drift more than 1 %% from the exact model before they "
                "freeze, from frame %.0f to %.0f on (median %.0f). Largest stored w_sum / (w sqrt(1 + 2.25 (n - "
                "1))) on the way: %.4f (above 1 for %zu weights).\n",
                h.binade.size(), frozen.front(), frozen.back(), frozen[frozen.size() / 2],
                hours90(uint64_t(frozen.front())), hours90(uint64_t(frozen.back())), ratioLo, ratioHi, drifted,
                drift.front(), drift.back(), drift[drift.size() / 2], boundMax, over);
        }
        o << fmt(
            "\nfp16 colour against the change term, over the %d grey levels of an sRGB8 image: %d round-trip "
            "exactly (|ΔL| = 0); for the others w_sum (w = 1) settles at 1/sqrt(|ΔL|): min %.4g, median %.4g, "
            "max %.4g.\n\n",
            h.greyLevels, h.greyLevelsExact, h.ceilingMin, h.ceilingMedian, h.ceilingMax);
    }

    if (in.gpu) {
        const GpuResult& g = *in.gpu;
        o << "## GPU against the lockstep CPU reference\n\n"
          << "Per row (stream) both eyes; every frame both eyes' packed reservoirs and outputs are compared word "
             "by word. step ≠ ref: the stress step (stress/step.h) on the reference's own inputs differs from "
             "the reference.\n\n";
        o << "| row | stream | motion | aged | pixel-frames | decisions (kept) | selection ≠ (near thr.) | "
             "w rounding ≠ | z/M ≠ | w_sum ≠ | max ulp | max rel. | output bytes ≠ (max) | step ≠ ref | NaN/Inf | "
             "w_sum max | M max |\n"
             "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n";
        for (size_t r = 0; r < g.rows.size(); ++r) {
            const GpuRowStats& s = g.rows[r];
            const char* motion = s.row.motion == RowMotion::Zero        ? "zero"
                                 : s.row.motion == RowMotion::NonFinite ? "non-finite"
                                                                        : "off-screen";
            o << "| " << r << " | " << s.row.stream << " | " << motion << " | " << (s.row.aged ? "yes" : "") << " | "
              << count(s.pixelFrames) << " | " << count(s.decisions) << " (" << count(s.kept) << ") | "
              << count(s.selectionMismatch) << " (" << count(s.nearThreshold) << ") | " << count(s.weightRounding)
              << " | " << count(s.zmMismatch) << " | " << count(s.wsumMismatch) << " | " << s.wsumMaxUlp << " | "
              << fmt("%.2g", s.wsumMaxRel) << " | " << count(s.outputDiffs) << " (" << s.outputMaxDiff << ") | "
              << count(s.stepMismatch) << " | " << count(s.nonFinite) << " | " << num(s.wsumMax) << " | " << s.mMax
              << " |\n";
        }
        o << fmt(
            "\nResyncs of the reference from the GPU: %llu. Final reservoirs: %llu of %llu agree (colour, z, M "
            "identical, w within one fp16 step, w_sum within %.0e relative), %llu bit-identical. Validation errors: "
            "%s.\n\n",
            (unsigned long long)g.resyncs, (unsigned long long)g.finalAgree, (unsigned long long)g.finalPixels,
            kWsumTolerance, (unsigned long long)g.finalIdentical,
            g.validation ? std::to_string(g.validationErrors).c_str() : "layer off");
    }
    return o.str();
}

namespace {

cv::Scalar formatColour(FormatId f) {  // BGR
    switch (f) {
        case FormatId::Chosen:
            return {180, 110, 30};
        case FormatId::F32:
            return {60, 170, 60};
        case FormatId::WsumF16:
            return {40, 40, 220};
        case FormatId::MU8:
            return {0, 160, 255};
        case FormatId::MU8Wrap:
            return {160, 60, 160};
        case FormatId::MF16:
            return {140, 140, 40};
    }
    return {90, 90, 90};
}

// w_sum (mean over the stream's pixels) against the frame, both axes logarithmic.
Status plotSeries(const StreamResult& s, const std::string& path) {
    const int W = 1080, H = 640;
    const cv::Rect area(90, 50, W - 380, H - 120);
    double y0 = INFINITY, y1 = -INFINITY;
    auto take = [&](double v) {
        if (v > 0 && std::isfinite(v)) {
            y0 = std::min(y0, v);
            y1 = std::max(y1, v);
        }
    };
    for (const FormatStats& f : s.formats)
        for (double v : f.series.mean) take(v);
    for (double v : s.modelWsum) take(v);
    if (!(y0 <= y1) || s.formats.empty()) return {};
    double ly0 = std::floor(std::log10(y0)), ly1 = std::ceil(std::log10(y1));
    if (ly1 - ly0 < 1) ly1 = ly0 + 1;
    const std::vector<uint64_t>& fr = s.formats[0].series.frames;
    const double lx0 = 0, lx1 = std::max(1.0, std::ceil(std::log10(double(fr.back()))));
    auto map = [&](double x, double y) {
        const double fx = (std::log10(x) - lx0) / (lx1 - lx0), fy = (std::log10(y) - ly0) / (ly1 - ly0);
        return cv::Point(area.x + int(std::lround(fx * area.width)),
                         area.y + area.height - int(std::lround(fy * area.height)));
    };
    cv::Mat img(H, W, CV_8UC3, cv::Scalar(255, 255, 255));
    const cv::Scalar grid(225, 225, 225), ink(40, 40, 40);
    const int yStep = std::max(1, int((ly1 - ly0) / 10));
    for (double e = lx0; e <= lx1 + 1e-9; e += 1) {
        cv::line(img, map(std::pow(10, e), std::pow(10, ly0)), map(std::pow(10, e), std::pow(10, ly1)), grid);
        cv::putText(img, fmt("1e%d", int(e)), map(std::pow(10, e), std::pow(10, ly0)) + cv::Point(-14, 20),
                    cv::FONT_HERSHEY_SIMPLEX, 0.4, ink, 1, cv::LINE_AA);
    }
    for (double e = ly0; e <= ly1 + 1e-9; e += yStep) {
        cv::line(img, map(1, std::pow(10, e)), map(std::pow(10, lx1), std::pow(10, e)), grid);
        cv::putText(img, fmt("1e%d", int(e)), map(1, std::pow(10, e)) + cv::Point(-60, 4), cv::FONT_HERSHEY_SIMPLEX,
                    0.4, ink, 1, cv::LINE_AA);
    }
    cv::rectangle(img, area, ink);
    cv::putText(img, "w_sum (mean over pixels): " + s.stream.name, {area.x, 30}, cv::FONT_HERSHEY_SIMPLEX, 0.6, ink, 1,
                cv::LINE_AA);
    cv::putText(img, "frame", {area.x + area.width / 2 - 20, area.y + area.height + 45}, cv::FONT_HERSHEY_SIMPLEX, 0.5,
                ink, 1, cv::LINE_AA);
    auto polyline = [&](const std::vector<double>& ys, cv::Scalar c, int thick) {
        cv::Point last;
        bool have = false;
        for (size_t k = 0; k < ys.size() && k < fr.size(); ++k) {
            if (!(ys[k] > 0) || !std::isfinite(ys[k])) {
                have = false;
                continue;
            }
            const cv::Point p = map(double(fr[k]), ys[k]);
            if (have) cv::line(img, last, p, c, thick, cv::LINE_AA);
            last = p;
            have = true;
        }
    };
    cv::Point legend(area.x + area.width + 20, area.y + 10);
    auto label = [&](const std::string& t, cv::Scalar c) {
        cv::line(img, legend, legend + cv::Point(24, 0), c, 3);
        cv::putText(img, t, legend + cv::Point(32, 5), cv::FONT_HERSHEY_SIMPLEX, 0.45, ink, 1, cv::LINE_AA);
        legend.y += 24;
    };
    if (!s.modelWsum.empty()) {
        polyline(s.modelWsum, cv::Scalar(150, 150, 150), 5);
        label("exact model (fp16 colour)", cv::Scalar(150, 150, 150));
    }
    for (const FormatStats& f : s.formats) {
        polyline(f.series.mean, formatColour(f.format), 2);
        label(std::string(formatInfo(f.format).name), formatColour(f.format));
    }
    try {
        if (!cv::imwrite(path, img)) return Error{1, "cannot write '" + path + "'"};
    } catch (const cv::Exception& e) {
        return Error{1, "cannot write '" + path + "': " + e.what()};
    }
    return {};
}

Status writeText(const std::string& path, const std::string& text) {
    std::ofstream f(path);
    if (!f) return Error{1, "cannot write '" + path + "'"};
    f << text;
    if (!f) return Error{1, "cannot write '" + path + "'"};
    return {};
}

}  // namespace

Status writeReport(const ReportInput& in, const std::string& dir) {
    std::error_code ec;
    std::filesystem::create_directories(dir, ec);
    if (ec) return Error{1, "cannot create '" + dir + "': " + ec.message()};
    if (Status s = writeText(dir + "/report.md", markdownReport(in)); !s) return s;

    if (in.cpu) {
        std::ostringstream c;
        c << "stream,domain,format,frames,pixels,wsum_min,wsum_max,wsum_final_mean,model_wsum_final,bound_ratio_max,"
             "wsum_frozen_from,m_max,m_at_cap,first_cap_frame,m_wraps,decisions,replaced,fresh,flushes,lost,"
             "nonfinite_stored,nonfinite_output,zero_weight_selected,identity_violations,divergent_frames,"
             "z_conditional,z_conditional_after_cap,z_exact,chi2_mid,dof_mid,p_mid,chi2_final,dof_final,p_final\n";
        for (const StreamResult& s : in.cpu->streams)
            for (const FormatStats& f : s.formats)
                c << s.stream.name << ',' << toString(s.stream.domain) << ',' << formatInfo(f.format).name << ','
                  << in.cpu->options.frames << ',' << in.cpu->options.pixels << ',' << num(f.wsumMin) << ','
                  << num(f.wsumMax) << ',' << num(f.wsumFinalMean) << ','
                  << (s.modelWsum.empty() ? "" : num(s.modelWsum.back())) << ',' << num(f.boundRatioMax) << ','
                  << f.wsumFrozenFrom << ',' << f.mMax << ',' << f.mAtCap << ',' << f.firstCapFrame << ',' << f.mWraps
                  << ',' << f.decisions << ',' << f.replaced << ',' << f.fresh << ',' << f.flushes << ',' << f.lost
                  << ',' << f.nonFiniteStored << ',' << f.nonFiniteOutput << ',' << f.zeroWeightSelected << ','
                  << f.identityViolations << ',' << f.divergentFrames << ',' << num(f.conditional.z()) << ','
                  << num(f.conditionalAfterCap.z()) << ',' << num(f.unconditional.z()) << ',' << num(f.chiMid.chi2)
                  << ',' << f.chiMid.dof << ',' << num(f.chiMid.p) << ',' << num(f.chiFinal.chi2) << ','
                  << f.chiFinal.dof << ',' << num(f.chiFinal.p) << '\n';
        if (Status s = writeText(dir + "/report.csv", c.str()); !s) return s;
        for (const StreamResult& s : in.cpu->streams)
            if (Status st = plotSeries(s, dir + "/wsum_" + s.stream.name + ".png"); !st) return st;
    }
    if (in.horizon) {
        std::ostringstream c;
        c << "set,format,bernoulli,weight,frozen_frame,hours_at_90hz,stored_wsum,exact_wsum,lost,drift_1pct_frame,"
             "max_bound_ratio\n";
        auto row = [&](const char* set, const Horizon& h) {
            c << set << ',' << formatInfo(h.format).name << ',' << h.bernoulli << ',' << fmt("%.9g", h.weight) << ','
              << h.frame << ',' << num(hours90(h.frame)) << ',' << fmt("%.9g", h.wsum) << ','
              << fmt("%.9g", h.exactWsum) << ',' << h.lost << ',' << h.drift1 << ',' << num(h.maxBoundRatio) << '\n';
        };
        for (const Horizon& h : in.horizon->runs) row("weights", h);
        for (const Horizon& h : in.horizon->binade) row("binade", h);
        if (Status s = writeText(dir + "/horizon.csv", c.str()); !s) return s;
    }
    if (in.gpu) {
        std::ostringstream c;
        c << "row,stream,motion,aged,pixel_frames,decisions,kept,selection_mismatch,near_threshold,weight_rounding,"
             "zm_mismatch,wsum_mismatch,wsum_max_ulp,wsum_max_rel,output_diffs,output_max_diff,step_mismatch,nonfinite,"
             "wsum_max,m_max\n";
        for (size_t r = 0; r < in.gpu->rows.size(); ++r) {
            const GpuRowStats& s = in.gpu->rows[r];
            c << r << ',' << s.row.stream << ',' << int(s.row.motion) << ',' << s.row.aged << ',' << s.pixelFrames
              << ',' << s.decisions << ',' << s.kept << ',' << s.selectionMismatch << ',' << s.nearThreshold << ','
              << s.weightRounding << ',' << s.zmMismatch << ',' << s.wsumMismatch << ',' << s.wsumMaxUlp << ','
              << num(s.wsumMaxRel) << ',' << s.outputDiffs << ',' << s.outputMaxDiff << ',' << s.stepMismatch << ','
              << s.nonFinite << ',' << num(s.wsumMax) << ',' << s.mMax << '\n';
        }
        if (Status s = writeText(dir + "/gpu.csv", c.str()); !s) return s;
    }
    return {};
}

}  // namespace wrsfov::stress
