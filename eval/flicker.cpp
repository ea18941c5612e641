#include "eval/flicker.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <memory>
#include <string_view>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "compositor/reference.h"
#include "shaders/wrs_common.h"

namespace wrsfov::eval {

namespace {

// What `wrs` showed at a pixel: its candidate (the same output as `fov`), or something else with the
// stored sample of the candidate's quality (a merge of equals), or sharper than it, by its quality.
enum class Shown : uint8_t { Candidate, Equal, SharperFull, SharperBlend, SharperCoarse, Count };
const char* const kShownName[] = {"candidate", "equal quality", "sharper: full-rate", "sharper: blend",
                                  "sharper: level 3+"};

Shown classify(const uint8_t* wrs, const uint8_t* fov, const glm::uvec4& packed, float qCandidate) {
    if (wrs[0] == fov[0] && wrs[1] == fov[1] && wrs[2] == fov[2]) return Shown::Candidate;
    const float q = gpu::wrs_packed_quality(packed);
    if (q <= qCandidate * (1.0f + 1e-3f)) return Shown::Equal;
    if (q >= 1.0f - 1e-3f) return Shown::SharperFull;
    if (q > 1.0f / 64.0f + 1e-6f) return Shown::SharperBlend;
    return Shown::SharperCoarse;
}

constexpr std::size_t kPatchesShown = 3;  // the largest drop patches listed per reason

std::string fmtNum(double v, int prec) {
    char b[64];
    std::snprintf(b, sizeof b, "%.*f", prec, v);
    return b;
}

}  // namespace

Result<FlickerReport> analyseFlicker(vk::Context& ctx, const BenchOptions& o, const std::string& dir) {
    if (o.scenes.empty() || o.modes.empty() || o.foveas.empty()) return Error{1, "flicker: no scene, mode or fovea"};
    if (o.frames <= o.warmup + 1) return Error{1, "flicker: frames must exceed the warm-up frames by two"};
    struct Run {
        std::unique_ptr<Compositor> comp;
        std::unique_ptr<HostStereoApp> app;
        HostImage prev, cur;
    };
    Run runs[3];  // reference, fov, wrs
    std::vector<glm::uvec4> reservoirs;
    constexpr int kN = int(Shown::Count);
    FlickerClass cls[kN][kN];
    for (int a = 0; a < kN; ++a)
        for (int b = 0; b < kN; ++b) cls[a][b].name = std::string(kShownName[a]) + " → " + kShownName[b];
    std::vector<Shown> prevShown, curShown;
    std::vector<float> qCandidate;  // the candidate's quality at each pixel now
    // The CPU reference of `wrs`, stepped on the GPU's history each frame: why a kept sample went.
    std::unique_ptr<Reference> cpu;
    std::vector<float> heldPrev;
    std::map<std::string, uint64_t> drops;
    // Why a kept sample went: the retention outcome (WRS_OUT_*), or none where the lookup found nothing.
    const char* const outcomeName[] = {"no usable history", "change test", "candidate sharper", "kept", "merged",
                                       "outside the taps",  "floor rule",  "no tracked sample"};
    constexpr int kNoTrackedSample = 7;
    cv::Mat excess;  // per pixel: sum of |Δ wrs| - |Δ fov| over stable pairs
    FlickerReport rep;
    auto visit = [&](const SceneFrameInfo& si, int f, double t, std::array<EyeSubmission, 2>& eyes) -> Status {
        const HostStereoApp::Options& app = si.app;
        if (!runs[0].comp) {
            for (int r = 0; r < 3; ++r) {
                CompositorConfig cc = compositorConfig(o);
                cc.method = r == 2 ? Method::Wrs : Method::Fov;
                cc.foveation = r == 0 ? FoveationMode::None : o.modes.front();
                cc.foveaDeg = o.foveas.front();
                auto c = Compositor::create(ctx, cc);
                if (!c) return c.error();
                auto a = HostStereoApp::create(**c, app);
                if (!a) return a.error();
                runs[r].comp = std::move(*c);
                runs[r].app = std::move(*a);
            }
            excess = cv::Mat::zeros(int(app.height), int(app.width), CV_64F);
        }
        if (!cpu) cpu = std::make_unique<Reference>(runs[2].comp->config());
        if (f > 0) {
            for (uint32_t e = 0; e < 2; ++e) {
                auto g = runs[2].comp->readReservoirs(e);
                if (!g) return g.error();
                auto held = runs[2].comp->readTileHeld(e);
                cpu->setHistory(e, std::move(*g), held ? std::move(*held) : std::vector<float>{});
                auto steady = runs[2].comp->readSteadyFloor(e);
                if (!steady) return steady.error();
                cpu->setSteadyFloor(e, std::move(*steady));
            }
        }
        for (Run& r : runs) {
            if (Status s = r.app->submit(uint64_t(f + 1), t, eyes); !s) return s;
            auto out = r.comp->readOutput(0);
            if (!out) return out.error();
            r.prev = std::move(r.cur);
            r.cur = std::move(*out);
        }
        auto res = runs[2].comp->readReservoirs(0);
        if (!res) return res.error();
        std::array<Reference::EyeInput, 2> in;
        for (int e = 0; e < 2; ++e) in[e] = {eyes[e].color, eyes[e].depth, eyes[e].motion};
        cpu->step(runs[2].comp->lastParams(), in);
        const uint32_t W = app.width, H = app.height;
        curShown.assign(std::size_t(W) * H, Shown::Candidate);
        qCandidate.assign(std::size_t(W) * H, 0.0f);
        const auto* wrs = reinterpret_cast<const uint8_t*>(runs[2].cur.data.data());
        const auto* fov = reinterpret_cast<const uint8_t*>(runs[1].cur.data.data());
        const gpu::FrameParams& fp = runs[2].comp->lastParams();
        const gpu::EyeParams& ep = fp.eye[0];
        for (uint32_t y = 0; y < H; ++y)
            for (uint32_t x = 0; x < W; ++x) {
                const std::size_t i = std::size_t(y) * W + x;
                const float e =
                    gpu::wrs_eccentricity_deg(gpu::wrs_pixel_ray(x, y, W, H, ep.fov_tan), glm::vec3(ep.gaze));
                // The candidate's quality as the retain pass takes it (wrs_candidate_quality; a valid
                // candidate of a simulated mode).
                const uint32_t mode = uint32_t(o.modes.front());
                const float qc = gpu::wrs_candidate_quality(
                    mode, gpu::wrs_foveation_levels(mode, e, ep.gaze.w, fp.tuning.x), e, ep.gaze.w, 0.0f, true);
                curShown[i] = classify(wrs + 4 * i, fov + 4 * i, (*res)[i], qc);
                qCandidate[i] = qc;
            }
        if (f > o.warmup) {
            const auto& trace = cpu->trace(0);
            cv::Mat dropMask = cv::Mat::zeros(int(H), int(W), CV_8U);  // 1 + the reason of a loss, 0: none
            for (uint32_t y = 0; y < H; ++y)
                for (uint32_t x = 0; x < W; ++x) {
                    const std::size_t i = std::size_t(y) * W + x;
                    if (!(prevShown[i] >= Shown::SharperFull && curShown[i] == Shown::Candidate)) continue;
                    // Inside the kept region (its 8 neighbours showed a sharper sample too) or at its edge.
                    bool inside = x > 0 && y > 0 && x + 1 < W && y + 1 < H;
                    for (int dy = -1; dy <= 1 && inside; ++dy)
                        for (int dx = -1; dx <= 1; ++dx)
                            inside = inside && prevShown[i + dy * int(W) + dx] >= Shown::SharperFull;
                    const Reference::Trace& tr = trace[i];
                    const int why = tr.hadHistory || tr.outcome != gpu::WRS_OUT_FRESH ? int(std::min(tr.outcome, 6u))
                                                                                      : kNoTrackedSample;
                    drops[outcomeName[why] + std::string(inside ? ", inside the kept region" : ", at its edge")]++;
                    // A patch is a loss: the candidate now is less sharp than the sample stored there
                    // before (not the gaze arriving with sharper candidates).
                    if (qCandidate[i] < gpu::wrs_packed_quality(reservoirs[i]) * (1.0f - 1e-3f))
                        dropMask.at<uchar>(int(y), int(x)) = uchar(1 + why);
                }
            // The drops of this frame as 8-connected patches: a block lost at once shows as one.
            cv::Mat labels, stats, centroids;
            const int n = cv::connectedComponentsWithStats(dropMask, labels, stats, centroids, 8, CV_32S);
            for (int l = 1; l < n; ++l) {
                const int area = stats.at<int>(l, cv::CC_STAT_AREA);
                if (area < FlickerReport::kMinDropPatch) continue;
                DropPatch dp;
                dp.frame = f;
                dp.x = stats.at<int>(l, cv::CC_STAT_LEFT);
                dp.y = stats.at<int>(l, cv::CC_STAT_TOP);
                dp.width = stats.at<int>(l, cv::CC_STAT_WIDTH);
                dp.height = stats.at<int>(l, cv::CC_STAT_HEIGHT);
                dp.area = area;
                int count[std::size(outcomeName)] = {};
                for (int y = dp.y; y < dp.y + dp.height; ++y)
                    for (int x = dp.x; x < dp.x + dp.width; ++x)
                        if (labels.at<int>(y, x) == l) count[dropMask.at<uchar>(y, x) - 1]++;
                // The most frequent reason; of equally frequent ones, the first by name.
                int top = 0;
                for (int k = 1; k < int(std::size(count)); ++k)
                    if (count[k] > count[top] ||
                        (count[k] == count[top] && std::string_view(outcomeName[k]) < outcomeName[top]))
                        top = k;
                dp.reason = outcomeName[top];
                dp.reasonShare = double(count[top]) / area;
                rep.patches.push_back(dp);
            }
            const auto* ref = reinterpret_cast<const uint8_t*>(runs[0].cur.data.data());
            const auto* refP = reinterpret_cast<const uint8_t*>(runs[0].prev.data.data());
            const auto* wrsP = reinterpret_cast<const uint8_t*>(runs[2].prev.data.data());
            const auto* fovP = reinterpret_cast<const uint8_t*>(runs[1].prev.data.data());
            for (uint32_t y = 0; y < H; ++y) {
                double* ex = excess.ptr<double>(int(y));
                for (uint32_t x = 0; x < W; ++x) {
                    const std::size_t i = std::size_t(y) * W + x, k = 4 * i;
                    bool stable = true;
                    for (int c = 0; c < 3; ++c) stable = stable && std::abs(int(ref[k + c]) - int(refP[k + c])) <= 1;
                    if (!stable) continue;
                    double dw = 0, df = 0, dr = 0, ew = 0, ef = 0, aw = 0, af = 0, dx = 0, dxf = 0;
                    // A full-rate kept sample shown exactly: the reference wherever `wrs` showed one.
                    const bool exact1 = curShown[i] == Shown::SharperFull, exact0 = prevShown[i] == Shown::SharperFull;
                    for (int c = 0; c < 3; ++c) {
                        const int r1 = ref[k + c], r0 = refP[k + c];
                        dx += std::abs((exact1 ? r1 : int(wrs[k + c])) - (exact0 ? r0 : int(wrsP[k + c])));
                        dxf += std::abs((exact1 ? r1 : int(fov[k + c])) - (exact0 ? r0 : int(fovP[k + c])));
                        dw += std::abs(int(wrs[k + c]) - int(wrsP[k + c]));
                        df += std::abs(int(fov[k + c]) - int(fovP[k + c]));
                        dr += std::abs(r1 - r0);
                        ew += std::abs((int(wrs[k + c]) - r1) - (int(wrsP[k + c]) - r0));
                        ef += std::abs((int(fov[k + c]) - r1) - (int(fovP[k + c]) - r0));
                        aw += std::abs(int(wrs[k + c]) - r1);
                        af += std::abs(int(fov[k + c]) - r1);
                    }
                    aw /= 3 * 255.0, af /= 3 * 255.0;
                    dw /= 3 * 255.0, df /= 3 * 255.0, dr /= 3 * 255.0, dx /= 3 * 255.0, dxf /= 3 * 255.0,
                        ew /= 3 * 255.0, ef /= 3 * 255.0;
                    FlickerClass& c = cls[int(prevShown[i])][int(curShown[i])];
                    c.pairs++;
                    c.wrsChange += dw;
                    c.fovChange += df;
                    c.refChange += dr;
                    c.wrsErrorChange += ew;
                    c.fovErrorChange += ef;
                    c.wrsError += aw;
                    c.fovError += af;
                    c.exactKeptChange += dx;
                    c.exactKeptFovChange += dxf;
                    ex[x] += dw - df;
                    rep.stablePairs++;
                }
            }
        }
        prevShown.swap(curShown);
        reservoirs = std::move(*res);
        if (o.progress && ((f + 1) % 50 == 0 || f + 1 == o.frames))
            o.progress("flicker: frame " + std::to_string(f + 1) + "/" + std::to_string(o.frames));
        return {};
    };
    if (Status s = forEachSceneFrame(ctx, o.scenes.front(), o, visit); !s) return s.error();
    double sw = 0, sf = 0, sr = 0, sew = 0, sef = 0, sx = 0, sxf = 0;
    for (auto& row : cls)
        for (FlickerClass& c : row) {
            sw += c.wrsChange, sf += c.fovChange, sr += c.refChange, sew += c.wrsErrorChange, sef += c.fovErrorChange;
            sx += c.exactKeptChange, sxf += c.exactKeptFovChange;
            if (c.pairs) rep.classes.push_back(c);
        }
    const double n = double(std::max<uint64_t>(rep.stablePairs, 1));
    rep.wrsInstability = sw / n;
    rep.fovInstability = sf / n;
    rep.refInstability = sr / n;
    rep.wrsErrorInstability = sew / n;
    rep.fovErrorInstability = sef / n;
    rep.exactKeptInstability = sx / n;
    rep.exactKeptFovInstability = sxf / n;
    std::sort(rep.classes.begin(), rep.classes.end(), [](const FlickerClass& a, const FlickerClass& b) {
        return a.wrsChange - a.fovChange > b.wrsChange - b.fovChange;
    });
    for (const auto& [why, n] : drops) rep.drops.emplace_back(why, n);
    std::stable_sort(rep.patches.begin(), rep.patches.end(),
                     [](const DropPatch& a, const DropPatch& b) { return a.area > b.area; });
    if (dir.empty()) return rep;
    std::error_code ec;
    std::filesystem::create_directories(dir, ec);
    std::ofstream csv(dir + "/flicker.csv"), md(dir + "/flicker.md");
    if (!csv || !md) return Error{1, "flicker: cannot write " + dir + "/flicker.{csv,md}"};
    csv << "class,pairs,share,wrs_mean_change,fov_mean_change,ref_mean_change,wrs_error_change,fov_error_change,"
           "contribution,exact_kept_mean_change,exact_kept_fov_mean_change\n";
    md << "# Where `wrs` changes more than `fov` from frame to frame\n\nScene " << toString(o.scenes.front()) << ", "
       << toString(o.modes.front()) << ", fovea " << fmtNum(o.foveas.front(), 1) << "°, " << o.width << "x" << o.height
       << ", frames " << o.warmup + 1 << "–" << o.frames - 1 << " (left eye). Pixel pairs where the "
       << "reference changes by at most one 8-bit step (" << rep.stablePairs << " pairs), by what `wrs` showed "
       << "in the two frames: its candidate (the same output as `fov`) or something else: a merge of equal-quality "
          "samples, or a kept sample sharper than the candidate by its quality. "
       << "*Contribution*: the class's share of `wrs` − `fov` temporal instability.\n\n"
       << "Temporal instability over these pairs: `wrs` " << fmtNum(rep.wrsInstability, 6) << ", `fov` "
       << fmtNum(rep.fovInstability, 6) << " (" << fmtNum(100.0 * (rep.wrsInstability / rep.fovInstability - 1.0), 1)
       << " %); the reference itself " << fmtNum(rep.refInstability, 6) << ". The error's change, "
       << "mean |Δ(output − reference)|: `wrs` " << fmtNum(rep.wrsErrorInstability, 6) << ", `fov` "
       << fmtNum(rep.fovErrorInstability, 6) << ". With every full-rate kept sample shown exactly (the reference "
       << "where `wrs` showed one: a display of them without error; a steadier one must depart from the reference): "
       << fmtNum(rep.exactKeptInstability, 6) << " ("
       << fmtNum(100.0 * (rep.exactKeptInstability / rep.fovInstability - 1.0), 1)
       << " % against `fov`); the same with `fov`'s output everywhere else: "
       << fmtNum(rep.exactKeptFovInstability, 6) << " ("
       << fmtNum(100.0 * (rep.exactKeptFovInstability / rep.fovInstability - 1.0), 1)
       << " %).\n\n| previous → now | share of pairs | `wrs` mean change | "
       << "`fov` mean change | reference mean change | `wrs` error change | `fov` error change | `wrs` error | "
       << "`fov` error | contribution | full-rate kept shown exactly: mean change "
          "|\n|---|---|---|---|---|---|---|---|---|---|---|\n";
    for (const FlickerClass& c : rep.classes) {
        const double share = c.pairs / n, mw = c.wrsChange / c.pairs, mf = c.fovChange / c.pairs,
                     contrib = (c.wrsChange - c.fovChange) / n;
        const double mr = c.refChange / c.pairs, ew = c.wrsErrorChange / c.pairs, ef = c.fovErrorChange / c.pairs;
        csv << '"' << c.name << "\"," << c.pairs << ',' << share << ',' << mw << ',' << mf << ',' << mr << ',' << ew
            << ',' << ef << ',' << contrib << ',' << c.exactKeptChange / c.pairs << ','
            << c.exactKeptFovChange / c.pairs << '\n';
        md << "| " << c.name << " | " << fmtNum(100 * share, 2) << " % | " << fmtNum(mw, 6) << " | " << fmtNum(mf, 6)
           << " | " << fmtNum(mr, 6) << " | " << fmtNum(ew, 6) << " | " << fmtNum(ef, 6) << " | "
           << fmtNum(c.wrsError / c.pairs, 5) << " | " << fmtNum(c.fovError / c.pairs, 5) << " | " << fmtNum(contrib, 7)
           << " | " << fmtNum(c.exactKeptChange / c.pairs, 6) << " |\n";
    }
    // The map: red where wrs changed more than fov, blue where less, over the run.
    double lim = 1e-9;
    for (int y = 0; y < excess.rows; ++y)
        for (int x = 0; x < excess.cols; ++x) lim = std::max(lim, std::abs(excess.at<double>(y, x)));
    lim *= 0.25;
    cv::Mat map(excess.rows, excess.cols, CV_8UC3);
    for (int y = 0; y < excess.rows; ++y)
        for (int x = 0; x < excess.cols; ++x) {
            const double v = std::clamp(excess.at<double>(y, x) / lim, -1.0, 1.0);
            const uchar b = uchar(255 - 255 * std::abs(v));
            map.at<cv::Vec3b>(y, x) = v >= 0 ? cv::Vec3b(b, b, 255) : cv::Vec3b(255, b, b);
        }
    if (!cv::imwrite(dir + "/flicker.png", map)) return Error{1, "flicker: cannot write " + dir + "/flicker.png"};
    md << "\nPixels that showed a sharper kept sample and then their candidate, by what the retention rule "
          "decided (the CPU reference on the GPU's history):\n\n| outcome | pixels |\n|---|---|\n";
    for (const auto& [why, count] : rep.drops) md << "| " << why << " | " << count << " |\n";
    md << "\nThe losses among them (the candidate now less sharp than the sample stored there before, so not "
          "the gaze arriving with sharper candidates) as patches, 8-connected within a frame, of at least "
       << FlickerReport::kMinDropPatch << " pixels: " << rep.patches.size() << ". By the most frequent reason in "
       << "the patch, the count and the largest " << kPatchesShown << ":\n\n| most frequent reason | patches | "
       << "frame | x, y | width × height | pixels | the reason's share |\n|---|---|---|---|---|---|---|\n";
    std::map<std::string, std::vector<const DropPatch*>> byReason;
    for (const DropPatch& dp : rep.patches) byReason[dp.reason].push_back(&dp);
    for (const auto& [why, list] : byReason)
        for (std::size_t k = 0; k < std::min<std::size_t>(list.size(), kPatchesShown); ++k) {
            const DropPatch& dp = *list[k];
            md << "| " << (k ? "" : why) << " | " << (k ? "" : std::to_string(list.size())) << " | " << dp.frame
               << " | " << dp.x << ", " << dp.y << " | " << dp.width << " × " << dp.height << " | " << dp.area << " | "
               << fmtNum(100 * dp.reasonShare, 0) << " % |\n";
        }
    md << "\n![where wrs changes more (red) or less (blue) than fov, summed over the run](flicker.png)\n";
    return rep;
}

}  // namespace wrsfov::eval
