#include "stress/retain_stress.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <sstream>

#include "shaders/wrs_common.h"
#include "stress/streams.h"

namespace wrsfov::stress {

using namespace gpu;

std::vector<RetainStats> runRetainStress(uint64_t frames, uint32_t pixels, uint32_t seed) {
    std::vector<RetainStats> out;
    const std::vector<Stream> streams = makeStreams(frames, seed);
    for (uint32_t rule : {WRS_RULE_MERGE, WRS_RULE_RESERVOIR}) {
        for (std::size_t si = 0; si < streams.size(); ++si) {
            const Stream& s = streams[si];
            const auto t0 = std::chrono::steady_clock::now();
            RetainStats st;
            st.stream = s.name;
            st.domain = std::string(toString(s.domain));
            st.rule = rule == WRS_RULE_MERGE ? "merge" : "reservoir";
            st.mustHold = s.domain != Domain::Outside;
            for (uint32_t px = 0; px < pixels; ++px) {
                uvec4 stored(0u);
                for (uint64_t f = 1; f <= frames; ++f) {
                    const StreamSample in = s.sample(f, px);
                    bool valid;
                    RetainInput c;
                    c.color = wrs_sanitize_color(in.color, valid);
                    c.q = valid ? in.weight : 0.0f;
                    c.lo = c.color;
                    c.hi = c.color;
                    c.fp = wrs_linear_to_lab(c.color).x;
                    c.fp_range = 0.0f;
                    c.moved = false;
                    c.jittered = false;
                    c.flags = 0u;
                    c.weight = 1.0f;
                    c.z = wrs_linear_depth(in.depth, kNearZ, kFarZ, false);
                    c.q_floor = 0.0f;  // streams of arbitrary weights: no floor quality
                    const Tracked h = wrs_unpack_tracked(stored);
                    bool has = wrs_tracked_valid(h);
                    if (has && wrs_depth_flush(h.z, c.z, 0.0f, kDepthTau)) has = false;
                    uint32_t outcome;
                    float margin;
                    const Tracked r = wrs_retain(rule, has, h, vec2(0.0f), c, c.color, wrs_rand(px, 0u, 0u, uint32_t(f), seed),
                                                 outcome, margin);
                    stored = wrs_pack_tracked(r, wrs_offset_dither(uint32_t(f), seed));
                    const Tracked b = wrs_unpack_tracked(stored);
                    st.pixelFrames++;
                    st.outcomes[has ? outcome : WRS_OUT_FRESH]++;
                    st.nonFiniteStored += !(wrs_finite3(b.color) && wrs_finite(b.q) && wrs_finite(b.w_sum) && wrs_finite(b.z));
                    st.validWithoutQuality += wrs_tracked_valid(b) && !(b.q > 0.0f);
                    st.zeroQualityReplaced += has && c.q == 0.0f && outcome != WRS_OUT_KEPT && outcome != WRS_OUT_MERGED;
                    st.nonFiniteOutput += !wrs_finite3(r.color);
                    if (wrs_finite(b.w_sum)) st.wsumMax = std::max<double>(st.wsumMax, b.w_sum);
                    if (wrs_tracked_valid(b)) st.wsumOverQMax = std::max<double>(st.wsumOverQMax, b.w_sum / b.q);
                }
            }
            st.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
            std::fprintf(stderr, "[retain] %s, %s: %llu pixel-frames in %.1f s\n", st.rule.c_str(), st.stream.c_str(),
                         (unsigned long long)st.pixelFrames, st.wall_s);
            out.push_back(st);
        }
    }
    return out;
}

std::string retainMarkdown(const std::vector<RetainStats>& stats) {
    std::ostringstream md;
    md << "\n## Method wrs: tracked layout (quality-aware retention)\n\n"
          "Every stream through load, the depth test, `wrs_retain` and `wrs_pack_tracked` storage; the stream's "
          "weight is the candidate's quality. w_sum is bounded by construction (at most "
       << WRS_MERGE_CAP
       << " candidates' quality), so the fp16 field cannot saturate or freeze; there is no counter.\n\n"
          "| rule | stream | domain | pixel-frames | fresh | changed | better | kept | merged | outside | floor | non-finite "
          "stored | valid with q ≤ 0 | q = 0 replaced history | max w_sum | max w_sum / q | verdict |\n"
          "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n";
    bool all = true;
    for (const RetainStats& s : stats) {
        all = all && s.pass();
        md << "| " << s.rule << " | " << s.stream << " | " << s.domain << " | " << s.pixelFrames;
        for (uint64_t o : s.outcomes) md << " | " << o;
        md << " | " << s.nonFiniteStored << " | " << s.validWithoutQuality << " | " << s.zeroQualityReplaced << " | "
           << s.wsumMax << " | " << s.wsumOverQMax << " | "
           << (s.pass() ? (s.mustHold ? "pass" : "outside the promise") : "**FAIL**") << " |\n";
    }
    md << "\nVerdict (method wrs): " << (all ? "every invariant holds" : "**an invariant is violated**") << ".\n";
    return md.str();
}

std::string retainCsv(const std::vector<RetainStats>& stats) {
    std::ostringstream c;
    c << "rule,stream,domain,pixel_frames,fresh,changed,better,kept,merged,outside,floor,non_finite_stored,"
         "valid_without_quality,zero_quality_replaced,non_finite_output,wsum_max,wsum_over_q_max,pass\n";
    for (const RetainStats& s : stats) {
        c << s.rule << ',' << s.stream << ',' << s.domain << ',' << s.pixelFrames;
        for (uint64_t o : s.outcomes) c << ',' << o;
        c << ',' << s.nonFiniteStored << ',' << s.validWithoutQuality << ',' << s.zeroQualityReplaced << ','
          << s.nonFiniteOutput << ',' << s.wsumMax << ',' << s.wsumOverQMax << ',' << (s.pass() ? 1 : 0) << '\n';
    }
    return c.str();
}

}  // namespace wrsfov::stress
