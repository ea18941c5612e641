// The shared per-pixel math (shaders/wrs_common.h) compiled as C++: A-Chao selection statistics,
// the temporal biases on hand-computed cases, sample weights, eccentricity with asymmetric fields
// of view, fp16 packing, reservoir validity and the per-pixel hash.
#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <limits>
#include <random>
#include <set>
#include <vector>

#include <gtest/gtest.h>

#include "shaders/wrs_common.h"
#include "shaders/wrs_input.h"
#include "shaders/wrs_submitted.h"

namespace wrsfov::gpu {
namespace {

const float kNaN = std::numeric_limits<float>::quiet_NaN();
const float kInf = std::numeric_limits<float>::infinity();

// ---------------------------------------------------------------------------------------------
// Statistics helpers
// ---------------------------------------------------------------------------------------------

// Upper regularized incomplete gamma Q(k, x) for integer k: e^-x * sum_{j<k} x^j / j!.
// With k = df / 2 this is the chi-square survival function for even degrees of freedom.
double gammaQInt(int k, double x) {
    double term = 1.0, sum = 1.0;
    for (int j = 1; j < k; ++j) {
        term *= x / j;
        sum += term;
    }
    return std::exp(-x) * sum;
}

double chiSquarePValue(double chi2, int df) {
    EXPECT_EQ(df % 2, 0) << "closed form needs an even number of degrees of freedom";
    return gammaQInt(df / 2, chi2 / 2.0);
}

TEST(Statistics, ChiSquareSurvivalMatchesTables) {
    // Tabulated critical values: df 6 at p = 0.001 is 22.458, df 2 at p = 0.05 is 5.991.
    EXPECT_NEAR(chiSquarePValue(22.458, 6), 0.001, 2e-6);
    EXPECT_NEAR(chiSquarePValue(5.991, 2), 0.05, 1e-4);
    EXPECT_NEAR(chiSquarePValue(0.0, 6), 1.0, 1e-15);
}

// ---------------------------------------------------------------------------------------------
// 1. A-Chao selection frequencies
// ---------------------------------------------------------------------------------------------

struct StreamResult {
    std::vector<uint64_t> counts;
    uint64_t wrongM = 0, unidentified = 0;
};

// Streams the candidates into one reservoir per trial, packing and unpacking between steps as the
// GPU does (the reservoir travels through storage). Candidate i is the colour (i + 1, 0.25, 0.5),
// exact in fp16, so the final colour names the selected candidate.
StreamResult streamTrials(const std::vector<float>& weights, uint32_t trials, uint32_t seed, uint32_t change,
                          bool bernoulli) {
    const uint32_t width = 256;  // trial t is "pixel" (t % width, t / width); step i is "frame" i
    StreamResult out;
    out.counts.assign(weights.size(), 0);
    for (uint32_t t = 0; t < trials; ++t) {
        const uint32_t x = t % width, y = t / width;
        Reservoir r;
        bool has = false;
        for (uint32_t i = 0; i < weights.size(); ++i) {
            vec3 color(float(i + 1), 0.25f, 0.5f);
            float rnd = wrs_rand(x, y, 0u, i, seed);
            bool keep;
            Reservoir n = wrs_combine(has, r, color, weights[i], 1.0f, rnd, change, bernoulli, keep);
            r = wrs_unpack(wrs_pack(n));
            has = true;
        }
        if (r.M != weights.size()) out.wrongM++;
        const float id = r.color.x - 1.0f;
        if (id >= 0.0f && id < float(weights.size()) && id == std::floor(id) && r.color.y == 0.25f &&
            r.color.z == 0.5f)
            out.counts[uint32_t(id)]++;
        else
            out.unidentified++;
    }
    return out;
}

struct Fit {
    double chi2 = 0, p = 0, worstSigma = 0;
};

Fit fitFrequencies(const std::vector<uint64_t>& counts, const std::vector<float>& weights, uint64_t n) {
    double total = 0;
    for (float w : weights) total += w;
    Fit f;
    for (std::size_t i = 0; i < weights.size(); ++i) {
        const double p = weights[i] / total, expect = double(n) * p;
        const double d = double(counts[i]) - expect;
        f.chi2 += d * d / expect;
        f.worstSigma = std::max(f.worstSigma, std::fabs(d) / std::sqrt(double(n) * p * (1.0 - p)));
    }
    f.p = chiSquarePValue(f.chi2, int(weights.size()) - 1);
    return f;
}

// 7 weights spanning 2.5 decades, in an order that puts large ones both early and late.
const std::vector<float> kStreamWeights = {0.25f, 0.005f, 1.0f, 0.061f, 0.8f, 0.02f, 0.39f};

TEST(AChao, SelectionFrequenciesMatchWeightsWithoutBias) {
    const uint32_t trials = 60000;
    StreamResult r = streamTrials(kStreamWeights, trials, 20240611u, WRS_CHANGE_OFF, false);
    EXPECT_EQ(r.wrongM, 0u) << "every final reservoir has seen all candidates";
    ASSERT_EQ(r.unidentified, 0u) << "the kept colour must be one of the candidates";
    Fit f = fitFrequencies(r.counts, kStreamWeights, trials);
    double total = 0;
    for (float w : kStreamWeights) total += w;
    for (std::size_t i = 0; i < kStreamWeights.size(); ++i)
        std::printf("  candidate %zu: w = %.3f, expected %.1f, got %llu\n", i, kStreamWeights[i],
                    trials * kStreamWeights[i] / total, (unsigned long long)r.counts[i]);
    std::printf("  chi-square = %.3f (df %zu), p = %.4f, worst bin %.2f sigma\n", f.chi2, kStreamWeights.size() - 1,
                f.p, f.worstSigma);
    // 99.9 % confidence: refuse only when the frequencies are this unlikely under w_i / sum w.
    EXPECT_GT(f.p, 0.001);
    EXPECT_LT(f.worstSigma, 4.0);
}

TEST(AChao, SelectionIsIndependentOfStreamOrder) {
    std::vector<float> reversed(kStreamWeights.rbegin(), kStreamWeights.rend());
    const uint32_t trials = 40000;
    StreamResult r = streamTrials(reversed, trials, 77u, WRS_CHANGE_OFF, false);
    ASSERT_EQ(r.unidentified, 0u);
    Fit f = fitFrequencies(r.counts, reversed, trials);
    EXPECT_GT(f.p, 0.001);
    EXPECT_LT(f.worstSigma, 4.0);
}

TEST(AChao, TheTestDetectsABiasedStream) {
    // The Bernoulli bias (eq. 6) favours late candidates: the same test must reject it, which shows
    // it has the power to fail.
    const uint32_t trials = 60000;
    StreamResult r = streamTrials(kStreamWeights, trials, 20240611u, WRS_CHANGE_OFF, true);
    ASSERT_EQ(r.unidentified, 0u);
    Fit f = fitFrequencies(r.counts, kStreamWeights, trials);
    std::printf("  with the Bernoulli bias: chi-square = %.1f, p = %.3g\n", f.chi2, f.p);
    EXPECT_LT(f.p, 1e-6);
}

// ---------------------------------------------------------------------------------------------
// 2. Biases (eq. 6 / 7) and combine on hand-computed cases
// ---------------------------------------------------------------------------------------------

TEST(Bias, BiasedHistoryWeightFollowsEquationSevenExactly) {
    // w_sum1 = w_sum * (1 - |dL|) * (1 - w_cur / (w_sum + w_cur)); all values below are exact in float.
    // 3 * (1 - 0.25) * (1 - 1 / (3 + 1)) = 3 * 0.75 * 0.75 = 1.6875
    EXPECT_EQ(wrs_biased_history_weight(3.0f, 1.0f, 0.25f, true), 1.6875f);
    // without the Bernoulli factor: 3 * 0.75 = 2.25
    EXPECT_EQ(wrs_biased_history_weight(3.0f, 1.0f, 0.25f, false), 2.25f);
    // without the change term: 3 * (1 - 1/4) = 2.25
    EXPECT_EQ(wrs_biased_history_weight(3.0f, 1.0f, 0.0f, true), 2.25f);
    // eq. 6 on its own: 1 * (1 - 1 / (1 + 1)) = 0.5
    EXPECT_EQ(wrs_biased_history_weight(1.0f, 1.0f, 0.0f, true), 0.5f);
    // 6 * (1 - 0.5) * (1 - 2 / (6 + 2)) = 6 * 0.5 * 0.75 = 2.25
    EXPECT_EQ(wrs_biased_history_weight(6.0f, 2.0f, 0.5f, true), 2.25f);
    // a full change wipes the history: 5 * (1 - 1) * ... = 0
    EXPECT_EQ(wrs_biased_history_weight(5.0f, 0.5f, 1.0f, true), 0.0f);
    // nothing biased: the history weight passes unchanged
    EXPECT_EQ(wrs_biased_history_weight(7.5f, 0.3f, 0.0f, false), 7.5f);
    // a zero-weight candidate does not discount the history: 4 * (1 - 0 / 4) = 4
    EXPECT_EQ(wrs_biased_history_weight(4.0f, 0.0f, 0.0f, true), 4.0f);
    // non-exact case: 0.7 * (1 - 0.1) * (1 - 0.2 / 0.9) = 0.63 * 0.777... = 0.49
    EXPECT_NEAR(wrs_biased_history_weight(0.7f, 0.2f, 0.1f, true), 0.49f, 1e-7f);
}

TEST(Bias, LStarChangeOfGreyAgainstWhite) {
    // Linear grey 0.18: Y = 0.18 (the Rec. 709 Y row sums to 1), L* = 116 * 0.18^(1/3) - 16
    //   = 116 * 0.5646216 - 16 = 49.49611; white: L* = 116 * 1 - 16 = 100.
    // |dL| = (100 - 49.49611) / 100 = 0.5050389.
    const vec3 grey(0.18f), white(1.0f), black(0.0f);
    EXPECT_NEAR(wrs_linear_to_lab(grey).x, 49.49611f, 2e-4f);
    EXPECT_NEAR(wrs_linear_to_lab(white).x, 100.0f, 2e-4f);
    EXPECT_NEAR(wrs_change(WRS_CHANGE_LSTAR, grey, white), 0.5050389f, 2e-6f);
    EXPECT_NEAR(wrs_change(WRS_CHANGE_LSTAR, white, grey), 0.5050389f, 2e-6f);  // |.|: symmetric
    // white against black: (100 - 0) / 100 = 1, the clamp's upper end
    EXPECT_NEAR(wrs_change(WRS_CHANGE_LSTAR, white, black), 1.0f, 1e-6f);
    // beyond white (linear 8: L* = 116 * 2 - 16 = 216) the change is clamped to 1
    EXPECT_EQ(wrs_change(WRS_CHANGE_LSTAR, vec3(8.0f), black), 1.0f);
    // identical colours: no change; metric off: always 0
    EXPECT_EQ(wrs_change(WRS_CHANGE_LSTAR, grey, grey), 0.0f);
    EXPECT_EQ(wrs_change(WRS_CHANGE_OFF, white, black), 0.0f);
    // a chroma-only change (equal-luminance colours) is invisible to L*, seen by dE94
    const vec3 a(0.3f, 0.2f, 0.1f);
    const float y = 0.2126729f * a.x + 0.7151522f * a.y + 0.0721750f * a.z;
    const vec3 b(y, y, y);  // same Y, no chroma
    EXPECT_LT(wrs_change(WRS_CHANGE_LSTAR, a, b), 1e-5f);
    EXPECT_GT(wrs_change(WRS_CHANGE_DE94, a, b), 0.1f);
}

TEST(Bias, DeltaE94OnHandComputedColours) {
    // Red (1,0,0): L* 53.24079, a* 80.09246, b* 67.20320, C1 = sqrt(80.09246^2 + 67.20320^2) = 104.55177.
    // Against black (L* = a* = b* = 0): dL = 53.24079, dC = 104.55177, dH^2 = da^2 + db^2 - dC^2 = 0,
    //   S_C = 1 + 0.045 * 104.55177 = 5.704829, S_H = 1 + 0.015 * 104.55177 = 2.568276,
    //   dE94 = sqrt(53.24079^2 + (104.55177 / 5.704829)^2) = sqrt(2834.582 + 335.881) = 56.30681.
    EXPECT_NEAR(wrs_change(WRS_CHANGE_DE94, vec3(1, 0, 0), vec3(0)), 0.5630681f, 5e-6f);
    // Red against green (0,1,0): green L* 87.73472, a* -86.18272, b* 83.17932, C2 = 119.77587;
    //   dL = -34.49393, dC = 104.55177 - 119.77587 = -15.22411,
    //   dH^2 = (80.09246 + 86.18272)^2 + (67.20320 - 83.17932)^2 - 15.22411^2 = 27670.90,
    //   dE94 = sqrt(34.49393^2 + (15.22411 / 5.704829)^2 + 27670.90 / 2.568276^2)
    //        = sqrt(1189.831 + 7.121802 + 4195.086) = 73.43043.
    EXPECT_NEAR(wrs_change(WRS_CHANGE_DE94, vec3(1, 0, 0), vec3(0, 1, 0)), 0.7343043f, 1e-5f);
    // Greys have no chroma: dE94 reduces to |dL| = 0.5050389 (grey 0.18 vs white).
    EXPECT_NEAR(wrs_change(WRS_CHANGE_DE94, vec3(0.18f), vec3(1.0f)), 0.5050389f, 2e-6f);
    // Non-finite inputs never produce a non-finite change: treated as a full change.
    EXPECT_EQ(wrs_change(WRS_CHANGE_DE94, vec3(kNaN, 0, 0), vec3(0)), 1.0f);
    EXPECT_EQ(wrs_change(WRS_CHANGE_LSTAR, vec3(kInf), vec3(0)), 1.0f);
}

TEST(Combine, HandComputedBernoulliCase) {
    // History {A, w 0.5, w_sum 3, M 4, z 2}; candidate B with w_cur = 1, z_cur = 5; change off.
    // w_sum1 = 3 * (1 - 1/(3+1)) = 2.25; total = 3.25; keep iff rand * 3.25 <= 2.25, i.e. rand <= 0.6923077.
    const vec3 A(0.1f, 0.2f, 0.3f), B(0.9f, 0.8f, 0.7f);
    const Reservoir hist = wrs_reservoir(A, 0.5f, 3.0f, 4u, 2.0f);
    bool keep;
    Reservoir r = wrs_combine(true, hist, B, 1.0f, 5.0f, 0.69f, WRS_CHANGE_OFF, true, keep);
    EXPECT_TRUE(keep);
    EXPECT_EQ(r.color, A);
    EXPECT_EQ(r.w, 0.5f);      // the kept sample keeps its own weight
    EXPECT_EQ(r.w_sum, 3.25f);  // w_sum1 + w_cur = 2.25 + 1
    EXPECT_EQ(r.M, 5u);         // M1 + 1
    EXPECT_EQ(r.z, 5.0f);       // z of this frame, whichever sample is kept
    r = wrs_combine(true, hist, B, 1.0f, 5.0f, 0.70f, WRS_CHANGE_OFF, true, keep);
    EXPECT_FALSE(keep);
    EXPECT_EQ(r.color, B);
    EXPECT_EQ(r.w, 1.0f);
    EXPECT_EQ(r.w_sum, 3.25f);
    EXPECT_EQ(r.M, 5u);
    EXPECT_EQ(r.z, 5.0f);
    EXPECT_NEAR(wrs_keep_threshold(2.25f, 1.0f), 0.6923077f, 1e-7f);  // 2.25 / 3.25
}

TEST(Combine, ThresholdIsInclusiveAndExact) {
    // No bias: w_sum1 = 3, total = 3 + 1 = 4, keep iff rand * 4 <= 3. rand = 0.75 gives exactly 3.
    const Reservoir hist = wrs_reservoir(vec3(0.25f), 1.0f, 3.0f, 3u, 0.0f);
    bool keep;
    wrs_combine(true, hist, vec3(0.5f), 1.0f, 0.0f, 0.75f, WRS_CHANGE_OFF, false, keep);
    EXPECT_TRUE(keep);
    wrs_combine(true, hist, vec3(0.5f), 1.0f, 0.0f, 0.75f + 1.0f / 16777216.0f, WRS_CHANGE_OFF, false, keep);
    EXPECT_FALSE(keep);
    // With the Bernoulli factor the same history becomes 3 * (1 - 1/4) = 2.25: rand 0.75 now replaces.
    Reservoir r = wrs_combine(true, hist, vec3(0.5f), 1.0f, 0.0f, 0.75f, WRS_CHANGE_OFF, true, keep);
    EXPECT_FALSE(keep);
    EXPECT_EQ(r.w_sum, 3.25f);
    // rand = 0 always keeps a history with positive weight, rand just below 1 keeps only if the
    // candidate weighs nothing.
    wrs_combine(true, hist, vec3(0.5f), 1.0f, 0.0f, 0.0f, WRS_CHANGE_LSTAR, true, keep);
    EXPECT_TRUE(keep);
    wrs_combine(true, hist, vec3(0.5f), 0.0f, 0.0f, 1.0f - 1.0f / 16777216.0f, WRS_CHANGE_LSTAR, true, keep);
    EXPECT_TRUE(keep);
}

TEST(Combine, HandComputedLStarCase) {
    // History white {w_sum 2, M 7}; candidate grey 0.18 with w_cur = 1.
    // w_sum1 = 2 * (1 - 0.5050389) * (1 - 1/(2+1)) = 2 * 0.4949611 * 0.6666667 = 0.6599481;
    // total = 1.6599481; threshold = 0.6599481 / 1.6599481 = 0.3975715.
    const Reservoir hist = wrs_reservoir(vec3(1.0f), 0.25f, 2.0f, 7u, 0.0f);
    bool keep;
    Reservoir r = wrs_combine(true, hist, vec3(0.18f), 1.0f, 0.0f, 0.397f, WRS_CHANGE_LSTAR, true, keep);
    EXPECT_TRUE(keep);
    EXPECT_EQ(r.color, vec3(1.0f));
    EXPECT_NEAR(r.w_sum, 1.6599481f, 3e-6f);
    EXPECT_EQ(r.M, 8u);
    r = wrs_combine(true, hist, vec3(0.18f), 1.0f, 0.0f, 0.3985f, WRS_CHANGE_LSTAR, true, keep);
    EXPECT_FALSE(keep);
    EXPECT_EQ(r.color, vec3(0.18f));
    EXPECT_NEAR(r.w_sum, 1.6599481f, 3e-6f);
    // Same with dE94 (greys: equal to dL) and without Bernoulli: w_sum1 = 2 * 0.4949611 = 0.9899222,
    // threshold = 0.9899222 / 1.9899222 = 0.4974678.
    r = wrs_combine(true, hist, vec3(0.18f), 1.0f, 0.0f, 0.497f, WRS_CHANGE_DE94, false, keep);
    EXPECT_TRUE(keep);
    EXPECT_NEAR(r.w_sum, 1.9899222f, 3e-6f);
    wrs_combine(true, hist, vec3(0.18f), 1.0f, 0.0f, 0.498f, WRS_CHANGE_DE94, false, keep);
    EXPECT_FALSE(keep);
}

TEST(Combine, FullChangeAlwaysReplacesAndNoHistoryInitialises) {
    // History black, candidate white: |dL| = 1, w_sum1 = 0: the candidate replaces for every rand > 0.
    const Reservoir hist = wrs_reservoir(vec3(0.0f), 1.0f, 10.0f, 9u, 0.0f);
    bool keep;
    Reservoir r = wrs_combine(true, hist, vec3(1.0f), 0.5f, 0.0f, 1.0f / 16777216.0f, WRS_CHANGE_LSTAR, true, keep);
    EXPECT_FALSE(keep);
    EXPECT_EQ(r.color, vec3(1.0f));
    EXPECT_NEAR(r.w_sum, 0.5f, 1e-6f);  // 0 + w_cur
    EXPECT_EQ(r.M, 10u);
    // No history: {candidate, w, w_sum = w, M = 1, z}.
    r = wrs_combine(false, hist, vec3(0.5f, 0.25f, 0.125f), 0.39f, 3.0f, 0.5f, WRS_CHANGE_LSTAR, true, keep);
    EXPECT_FALSE(keep);
    EXPECT_EQ(r.color, vec3(0.5f, 0.25f, 0.125f));
    EXPECT_EQ(r.w, 0.39f);
    EXPECT_EQ(r.w_sum, 0.39f);
    EXPECT_EQ(r.M, 1u);
    EXPECT_EQ(r.z, 3.0f);
    // An invalid candidate (w = 0) starts a reservoir with the floor weight, never w_sum = 0.
    r = wrs_combine(false, hist, vec3(0.0f), 0.0f, 0.0f, 0.5f, WRS_CHANGE_OFF, false, keep);
    EXPECT_GT(r.w_sum, 0.0f);
    EXPECT_TRUE(wrs_reservoir_valid(r));
    // ...and never replaces history.
    r = wrs_combine(true, hist, vec3(0.3f), 0.0f, 0.0f, 0.999f, WRS_CHANGE_OFF, true, keep);
    EXPECT_TRUE(keep);
    EXPECT_EQ(r.color, vec3(0.0f));
    // M saturates at WRS_M_MAX.
    r = wrs_combine(true, wrs_reservoir(vec3(0.2f), 1.0f, 1.0f, WRS_M_MAX, 0.0f), vec3(0.2f), 1.0f, 0.0f, 0.1f,
                    WRS_CHANGE_OFF, false, keep);
    EXPECT_EQ(r.M, WRS_M_MAX);
    EXPECT_EQ(wrs_unpack(wrs_pack(r)).M, WRS_M_MAX);
}

// ---------------------------------------------------------------------------------------------
// Sample weights (eq. 3-4)
// ---------------------------------------------------------------------------------------------

// Watson 2014 in double, written out independently of the header.
double watsonDensity(double e) {
    const double a = 0.9851, r2 = 1.058, re = 22.14, dc0 = 14804.6, rm = 41.03;
    return 2.0 * dc0 / (1.0 + e / rm) * (a / ((1.0 + e / r2) * (1.0 + e / r2)) + (1.0 - a) * std::exp(-e / re));
}

TEST(Weights, FoveaWeighsOneAndPeripheryMatchesWatson) {
    // d(2.5) = 2 * 14804.6 / 1.0609310 * (0.9851 / 11.309426 + 0.0149 * 0.8932241) = 2802.4062
    // d(5)   = 2 * 14804.6 / 1.1218621 * (0.9851 / 32.785907 + 0.0149 * 0.7978493) = 1106.7707
    // d(20)  = 2 * 14804.6 / 1.4874482 * (0.9851 / 396.15296 + 0.0149 * 0.4052130) = 169.68583
    EXPECT_NEAR(watsonDensity(2.5), 2802.4062, 1e-3);
    EXPECT_NEAR(watsonDensity(5.0), 1106.7707, 1e-3);
    EXPECT_NEAR(watsonDensity(20.0), 169.68583, 1e-4);
    // w(5) = 1106.7707 / 2802.4062 = 0.3949359 (docs/conventions.md: ~0.39); w(20) = 169.68583 / 2802.4062 = 0.0605500 (~0.061)
    EXPECT_NEAR(wrs_sample_weight(5.0f, 2.5f), 0.3949359f, 1e-5f);
    EXPECT_NEAR(wrs_sample_weight(20.0f, 2.5f), 0.0605500f, 1e-5f);
    EXPECT_NEAR(wrs_sample_weight(10.0f, 2.5f), watsonDensity(10.0) / watsonDensity(2.5), 1e-5);
    // Fovea pixels weigh exactly 1, the edge included.
    for (float e : {0.0f, 0.5f, 1.0f, 2.0f, 2.4999f, 2.5f}) EXPECT_EQ(wrs_sample_weight(e, 2.5f), 1.0f) << e;
    EXPECT_LT(wrs_sample_weight(2.5001f, 2.5f), 1.0f);
    EXPECT_GT(wrs_sample_weight(2.5001f, 2.5f), 0.999f);  // continuous at the edge
    // Decreasing outside and relative to the fovea edge for other sizes.
    float last = 1.0f;
    for (float e = 3.0f; e < 120.0f; e += 0.5f) {
        float w = wrs_sample_weight(e, 2.5f);
        EXPECT_LT(w, last) << e;
        EXPECT_GT(w, 0.0f) << e;
        EXPECT_NEAR(w, watsonDensity(e) / watsonDensity(2.5), 1e-5 * std::max(1.0, double(w)) + 1e-7) << e;
        last = w;
    }
    EXPECT_NEAR(wrs_sample_weight(20.0f, 5.0f), watsonDensity(20.0) / watsonDensity(5.0), 1e-5);
}

// ---------------------------------------------------------------------------------------------
// 3. Eccentricity with an asymmetric field of view
// ---------------------------------------------------------------------------------------------

double eccentricityDouble(double tx, double ty, glm::dvec3 gaze) {
    glm::dvec3 ray = glm::normalize(glm::dvec3(tx, ty, -1.0));
    gaze = glm::normalize(gaze);
    return std::acos(std::clamp(glm::dot(ray, gaze), -1.0, 1.0)) * 180.0 / 3.14159265358979323846;
}

TEST(Foveation, LevelsBelowTheFirstStoredOneAreNeverSampled) {
    // The pyramid pass stores only levels >= wrs_first_stored_level(mode): every level a mode blends
    // must be 0 or one of those, for any eccentricity, fovea and mid-periphery.
    for (uint mode : {uint(WRS_FOV_NONE), uint(WRS_FOV_MIP), uint(WRS_FOV_GAUSS)}) {
        const uint first = wrs_first_stored_level(mode);
        std::set<uint> seen;
        for (float r_f : {0.5f, 2.5f, 5.0f, 10.0f, 30.0f})
            for (float r_m : {2.0f, 7.5f, 20.0f})
                for (float e = 0.0f; e < 90.0f; e += 0.05f) {
                    const vec3 lv = wrs_foveation_levels(mode, e, r_f, r_m);
                    for (float l : {lv.x, lv.y}) {
                        const uint level = uint(l);
                        ASSERT_TRUE(level == 0u || (level >= first && level < uint(WRS_LEVELS)))
                            << "mode " << mode << " e " << e << " r_f " << r_f << " samples level " << level;
                        if (lv.z > 0.0f || l == lv.x) seen.insert(level);
                    }
                }
        // The bound is tight: each mode reaches its first stored level (none samples only level 0).
        if (mode != WRS_FOV_NONE) EXPECT_TRUE(seen.count(first)) << "mode " << mode;
        else EXPECT_EQ(seen, std::set<uint>{0u});
    }
}

TEST(Eccentricity, KnownPixelsOfAnAsymmetricView) {
    // tan angles: left -1.5, right 0.5, up 1.0, down -0.6 (an asymmetric view looking left and up).
    const vec4 fov(-1.5f, 0.5f, 1.0f, -0.6f);
    // 8x8: pixel (2, 3): tx = -1.5 + 2.5/8 * 2 = -0.875, ty = 1 - 3.5/8 * 1.6 = 0.3;
    // from straight ahead: e = atan(sqrt(0.875^2 + 0.3^2)) = atan(sqrt(0.855625)) = atan(0.925) = 42.768825°.
    vec3 ray = wrs_pixel_ray(2, 3, 8, 8, fov);
    EXPECT_NEAR(ray.x / -ray.z, -0.875f, 1e-6f);
    EXPECT_NEAR(ray.y / -ray.z, 0.3f, 1e-6f);
    EXPECT_NEAR(wrs_eccentricity_deg(ray, vec3(0, 0, -1)), 42.768825f, 2e-4f);
    // 9x9: the centre pixel (4, 4) looks along the view's centre, tx = -1.5 + 0.5 * 2 = -0.5,
    // ty = 1 - 0.5 * 1.6 = 0.2: off-axis by atan(sqrt(0.25 + 0.04)) = atan(0.5385165) = 28.303196°.
    vec3 centre = wrs_pixel_ray(4, 4, 9, 9, fov);
    EXPECT_NEAR(wrs_eccentricity_deg(centre, vec3(0, 0, -1)), 28.303196f, 2e-4f);
    // ...and exactly on a gaze towards (-0.5, 0.2, -1).
    vec3 g = normalize(vec3(-0.5f, 0.2f, -1.0f));
    EXPECT_LT(wrs_eccentricity_deg(centre, g), 1e-3f);
    // Every pixel of a 37x29 view against a few gazes, versus acos in double.
    const glm::dvec3 gazes[] = {{0, 0, -1}, {-0.5, 0.2, -1}, {0.3, -0.45, -1}, {-1.2, 0.9, -1}};
    const uint32_t W = 37, H = 29;
    double worst = 0;
    for (const glm::dvec3& gd : gazes) {
        vec3 gf = vec3(glm::normalize(gd));
        for (uint32_t y = 0; y < H; ++y)
            for (uint32_t x = 0; x < W; ++x) {
                double tx = -1.5 + (x + 0.5) / W * 2.0;
                double ty = 1.0 - (y + 0.5) / H * 1.6;
                double expect = eccentricityDouble(tx, ty, gd);
                double got = wrs_eccentricity_deg(wrs_pixel_ray(x, y, W, H, fov), gf);
                worst = std::max(worst, std::fabs(got - expect));
                ASSERT_NEAR(got, expect, 2e-4 + 1e-5 * expect) << "pixel " << x << "," << y;
            }
    }
    std::printf("  worst eccentricity error against acos in double: %.3g°\n", worst);
}

TEST(Eccentricity, SmallAnglesKeepTheirPrecision) {
    // 2 atan2 keeps digits where acos(dot) would lose them: 0.01° and 0.001° between two rays.
    for (double deg : {0.001, 0.01, 0.1, 1.0, 45.0, 89.0, 135.0, 179.0}) {
        double r = deg * 3.14159265358979323846 / 180.0;
        vec3 a(0, 0, -1), b(float(std::sin(r)), 0.0f, float(-std::cos(r)));
        EXPECT_NEAR(wrs_eccentricity_deg(a, b), deg, 1e-5 * deg + 2e-5) << deg;
    }
}

// ---------------------------------------------------------------------------------------------
// Depth conventions
// ---------------------------------------------------------------------------------------------

TEST(Depth, LinearAndSubmittedDepthAreInverses) {
    // Hand-computed points: near 0.1, far 100. Standard: d = f (z - n) / (z (f - n)); reversed:
    // d = n (f - z) / (z (f - n)); infinite far: 1 - n / z and n / z.
    EXPECT_FLOAT_EQ(wrs_depth_from_linear(0.1f, 0.1f, 100.0f, false), 0.0f);
    EXPECT_FLOAT_EQ(wrs_depth_from_linear(100.0f, 0.1f, 100.0f, false), 1.0f);
    EXPECT_NEAR(wrs_depth_from_linear(1.0f, 0.1f, 100.0f, false), 100.0 * 0.9 / 99.9, 1e-6);
    EXPECT_NEAR(wrs_depth_from_linear(1.0f, 0.1f, 100.0f, true), 0.1 * 99.0 / 99.9, 1e-6);
    EXPECT_FLOAT_EQ(wrs_depth_from_linear(0.4f, 0.1f, kInf, false), 0.75f);
    EXPECT_FLOAT_EQ(wrs_depth_from_linear(0.4f, 0.1f, kInf, true), 0.25f);
    // Round trips over four decades in all four conventions.
    std::mt19937 rng(11);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    for (float far_z : {100.0f, kInf})
        for (bool rev : {false, true})
            for (int i = 0; i < 2000; ++i) {
                const float z = 0.1f * std::pow(10.0f, 3.0f * u(rng));  // 0.1 .. 100
                const float d = wrs_depth_from_linear(z, 0.1f, far_z, rev);
                ASSERT_GE(d, 0.0f) << z;
                ASSERT_LE(d, 1.0f) << z;
                EXPECT_NEAR(wrs_linear_depth(d, 0.1f, far_z, rev), z, 2e-3f * z) << z << " far " << far_z << " rev " << rev;
            }
    // Outside [near, far], not positive or NaN: -1, which reads back as unknown (0).
    for (float far_z : {100.0f, kInf})
        for (bool rev : {false, true})
            for (float z : {0.05f, 0.0f, -1.0f, kNaN, -kInf}) {
                EXPECT_EQ(wrs_depth_from_linear(z, 0.1f, far_z, rev), -1.0f) << z;
                EXPECT_EQ(wrs_linear_depth(wrs_depth_from_linear(z, 0.1f, far_z, rev), 0.1f, far_z, rev), 0.0f);
            }
    EXPECT_EQ(wrs_depth_from_linear(150.0f, 0.1f, 100.0f, false), -1.0f);
    EXPECT_EQ(wrs_depth_from_linear(150.0f, 0.1f, 100.0f, true), -1.0f);
    EXPECT_EQ(wrs_depth_from_linear(kInf, 0.1f, 100.0f, false), -1.0f);
    // +inf is the far plane of an infinite projection.
    EXPECT_EQ(wrs_depth_from_linear(kInf, 0.1f, kInf, false), 1.0f);
    EXPECT_EQ(wrs_depth_from_linear(kInf, 0.1f, kInf, true), 0.0f);
}

// ---------------------------------------------------------------------------------------------
// fp16 packing, reservoir layout and validity
// ---------------------------------------------------------------------------------------------

TEST(Fp16, RoundToNearestEvenSubnormalsAndLimits) {
    auto h = [](float f) { return wrs_f32_to_f16(f); };
    EXPECT_EQ(h(1.0f), 0x3c00u);
    EXPECT_EQ(h(-2.0f), 0xc000u);
    EXPECT_EQ(h(0.0f), 0x0000u);
    EXPECT_EQ(h(-0.0f), 0x8000u);
    // 1 + 2^-11 lies halfway between 1 and 1 + 2^-10: ties to even (down).
    EXPECT_EQ(h(1.0f + std::ldexp(1.0f, -11)), 0x3c00u);
    // 1 + 3 * 2^-11 lies halfway between 0x3c01 and 0x3c02: ties to even (up).
    EXPECT_EQ(h(1.0f + 3.0f * std::ldexp(1.0f, -11)), 0x3c02u);
    // just above halfway rounds up
    EXPECT_EQ(h(1.0f + std::ldexp(1.0f, -11) + std::ldexp(1.0f, -20)), 0x3c01u);
    // max: 65504 = 0x7bff; 65519 rounds down to it; 65520 (halfway to 65536) rounds to even = inf.
    EXPECT_EQ(h(65504.0f), 0x7bffu);
    EXPECT_EQ(h(65519.0f), 0x7bffu);
    EXPECT_EQ(h(65520.0f), 0x7c00u);
    EXPECT_EQ(h(-1e10f), 0xfc00u);
    EXPECT_EQ(h(kInf), 0x7c00u);
    EXPECT_EQ(h(-kInf), 0xfc00u);
    EXPECT_EQ(h(kNaN) & 0x7e00u, 0x7e00u);  // quiet NaN
    // subnormals: 2^-24 is the smallest; 2^-25 is halfway to 0 (ties to even: 0); 3 * 2^-25 is 1.5 ulp
    // (ties to even: 2); 1023 * 2^-24 the largest; 2^-14 the smallest normal.
    EXPECT_EQ(h(std::ldexp(1.0f, -24)), 0x0001u);
    EXPECT_EQ(h(std::ldexp(1.0f, -25)), 0x0000u);
    EXPECT_EQ(h(std::ldexp(1.0f, -25) * 1.0001f), 0x0001u);
    EXPECT_EQ(h(3.0f * std::ldexp(1.0f, -25)), 0x0002u);
    EXPECT_EQ(h(1023.0f * std::ldexp(1.0f, -24)), 0x03ffu);
    EXPECT_EQ(h(std::ldexp(1.0f, -14)), 0x0400u);
    EXPECT_EQ(h(-std::ldexp(1.0f, -24)), 0x8001u);
    EXPECT_EQ(h(1e-10f), 0x0000u);
    EXPECT_EQ(wrs_f16_to_f32(0x0001u), std::ldexp(1.0f, -24));
    EXPECT_EQ(wrs_f16_to_f32(0x7bffu), 65504.0f);
    EXPECT_EQ(wrs_f16_to_f32(0x7c00u), kInf);
    EXPECT_EQ(wrs_f16_to_f32(0xfc00u), -kInf);
    EXPECT_TRUE(std::isnan(wrs_f16_to_f32(0x7e00u)));
}

TEST(Fp16, EveryHalfRoundTripsAndRandomFloatsRoundToTheNearest) {
    // All 65536 bit patterns: finite and infinite ones survive f16 -> f32 -> f16 unchanged, NaNs stay NaN.
    std::vector<std::pair<double, uint32_t>> finite;  // value, bits (non-negative finite halves)
    for (uint32_t b = 0; b < 65536u; ++b) {
        float f = wrs_f16_to_f32(b);
        if ((b & 0x7c00u) == 0x7c00u && (b & 0x3ffu) != 0u) {
            EXPECT_TRUE(std::isnan(f)) << b;
            EXPECT_TRUE(std::isnan(wrs_f16_to_f32(wrs_f32_to_f16(f)))) << b;
            continue;
        }
        ASSERT_EQ(wrs_f32_to_f16(f), b) << "half 0x" << std::hex << b;
        if (b < 0x7c00u) finite.emplace_back(double(f), b);
    }
    // Independent oracle: nearest of the sorted non-negative halves, ties to the even pattern.
    std::sort(finite.begin(), finite.end());
    std::mt19937 rng(4242);
    std::uniform_int_distribution<uint32_t> bits(0u, 0x477fefffu);  // non-negative, below the overflow point
    for (int i = 0; i < 200000; ++i) {
        uint32_t u = bits(rng);
        float f = std::bit_cast<float>(u);
        double v = f;
        auto it = std::lower_bound(finite.begin(), finite.end(), std::pair<double, uint32_t>(v, 0u));
        uint32_t expect;
        if (it == finite.end()) {
            expect = finite.back().second;
        } else if (it->first == v || it == finite.begin()) {
            expect = it->second;
        } else {
            auto lo = std::prev(it);
            double dl = v - lo->first, dh = it->first - v;
            expect = dl < dh ? lo->second : dh < dl ? it->second : ((lo->second & 1u) == 0u ? lo->second : it->second);
        }
        ASSERT_EQ(wrs_f32_to_f16(f), expect) << "float " << f;
        ASSERT_EQ(wrs_f32_to_f16(-f), expect | 0x8000u) << "float " << -f;
    }
}

TEST(Reservoir, PackUnpackRoundTripAndLayout) {
    Reservoir r = wrs_reservoir(vec3(0.5f, 0.25f, 65504.0f), 0.39453125f, 123.456f, 4242u, 7.5f);
    uvec4 p = wrs_pack(r);
    EXPECT_EQ(p.x, 0x3800u | (0x3400u << 16u));  // R 0.5 | G 0.25
    EXPECT_EQ(p.y & 0xffffu, 0x7bffu);           // B 65504
    EXPECT_EQ(p.z, std::bit_cast<uint32_t>(123.456f));  // w_sum stays fp32
    EXPECT_EQ(p.w >> 16u, 4242u);
    Reservoir u = wrs_unpack(p);
    EXPECT_EQ(u.color, r.color);
    EXPECT_EQ(u.w, r.w);  // 0.39453125 is exact in fp16
    EXPECT_EQ(u.w_sum, r.w_sum);
    EXPECT_EQ(u.M, r.M);
    EXPECT_EQ(u.z, r.z);
    // Values that are not fp16 round to nearest even; M above 16 bits saturates.
    Reservoir s = wrs_reservoir(vec3(0.1f), 0.061f, 1e-30f, 70000u, 1000.3f);
    Reservoir t = wrs_unpack(wrs_pack(s));
    EXPECT_EQ(t.color.x, wrs_round_f16(0.1f));
    EXPECT_NEAR(t.color.x, 0.1f, 0.1f / 2048.0f);
    EXPECT_EQ(t.w_sum, 1e-30f);
    EXPECT_EQ(t.M, WRS_M_MAX);
    EXPECT_EQ(t.z, 1000.5f);  // 1000.3 -> 1000.5, the nearer fp16 (step 0.5 in [512, 1024))
}

TEST(Reservoir, ValidityRejectsNonFiniteAndEmpty) {
    const Reservoir ok = wrs_reservoir(vec3(0.2f), 0.5f, 1.0f, 3u, 2.0f);
    EXPECT_TRUE(wrs_reservoir_valid(ok));
    EXPECT_TRUE(wrs_reservoir_valid(wrs_unpack(wrs_pack(ok))));
    auto with = [&](auto edit) {
        Reservoir r = ok;
        edit(r);
        return wrs_reservoir_valid(r);
    };
    EXPECT_FALSE(with([](Reservoir& r) { r.color.x = kNaN; }));
    EXPECT_FALSE(with([](Reservoir& r) { r.color.y = kInf; }));
    EXPECT_FALSE(with([](Reservoir& r) { r.color.z = -kInf; }));
    EXPECT_FALSE(with([](Reservoir& r) { r.w = kNaN; }));
    EXPECT_FALSE(with([](Reservoir& r) { r.w_sum = kNaN; }));
    EXPECT_FALSE(with([](Reservoir& r) { r.w_sum = kInf; }));
    EXPECT_FALSE(with([](Reservoir& r) { r.w_sum = 0.0f; }));
    EXPECT_FALSE(with([](Reservoir& r) { r.w_sum = -0.0f; }));
    EXPECT_FALSE(with([](Reservoir& r) { r.w_sum = -1.0f; }));
    EXPECT_FALSE(with([](Reservoir& r) { r.z = kNaN; }));
    EXPECT_FALSE(with([](Reservoir& r) { r.M = 0u; }));
    EXPECT_TRUE(with([](Reservoir& r) { r.w_sum = 1e-30f; }));
    // Never-written (all zero) storage and packed NaN/Inf bit patterns are rejected on load.
    EXPECT_FALSE(wrs_reservoir_valid(wrs_unpack(uvec4(0u))));
    uvec4 p = wrs_pack(ok);
    EXPECT_FALSE(wrs_reservoir_valid(wrs_unpack(uvec4((p.x & 0xffff0000u) | 0x7e00u, p.y, p.z, p.w))));
    EXPECT_FALSE(wrs_reservoir_valid(wrs_unpack(uvec4(p.x, (p.y & 0xffffu) | (0x7c00u << 16u), p.z, p.w))));
    EXPECT_FALSE(wrs_reservoir_valid(wrs_unpack(uvec4(p.x, p.y, 0x7fc00000u, p.w))));
    EXPECT_FALSE(wrs_reservoir_valid(wrs_unpack(uvec4(p.x, p.y, p.z, (p.w & 0xffff0000u) | 0xfc00u))));
    EXPECT_TRUE(wrs_finite(65504.0f));
    EXPECT_FALSE(wrs_finite(kNaN));
    EXPECT_FALSE(wrs_finite(-kInf));
}

// ---------------------------------------------------------------------------------------------
// Hash
// ---------------------------------------------------------------------------------------------

TEST(Hash, DeterministicSensitiveToEveryInputAndUniform) {
    const uint32_t h0 = wrs_hash(3, 5, 1, 42, 7);
    EXPECT_EQ(wrs_hash(3, 5, 1, 42, 7), h0);
    EXPECT_NE(wrs_hash(4, 5, 1, 42, 7), h0);
    EXPECT_NE(wrs_hash(3, 6, 1, 42, 7), h0);
    EXPECT_NE(wrs_hash(3, 5, 0, 42, 7), h0);
    EXPECT_NE(wrs_hash(3, 5, 1, 43, 7), h0);
    EXPECT_NE(wrs_hash(3, 5, 1, 42, 8), h0);
    // x and y are not interchangeable.
    EXPECT_NE(wrs_hash(5, 3, 1, 42, 7), h0);

    // 128 x 128 pixels x 2 eyes x 8 frames into 64 bins of rand; chi-square with 63 df compared with
    // its normal approximation (mean df, sd sqrt(2 df)), mean, balance of each of the 24 bits.
    const int bins = 64;
    std::vector<uint64_t> count(bins, 0);
    std::vector<uint64_t> bitOnes(24, 0);
    uint64_t n = 0, collisionsWithNeighbour = 0;
    double sum = 0;
    for (uint32_t f = 0; f < 8; ++f)
        for (uint32_t e = 0; e < 2; ++e)
            for (uint32_t y = 0; y < 128; ++y)
                for (uint32_t x = 0; x < 128; ++x) {
                    float r = wrs_rand(x, y, e, f, 1u);
                    ASSERT_GE(r, 0.0f);
                    ASSERT_LT(r, 1.0f);
                    const uint32_t q = uint32_t(r * 16777216.0f);
                    ASSERT_EQ(float(q), r * 16777216.0f) << "24 bits exactly";
                    count[q >> 18]++;
                    for (int b = 0; b < 24; ++b) bitOnes[b] += (q >> b) & 1u;
                    if (x > 0 && wrs_rand(x - 1, y, e, f, 1u) == r) collisionsWithNeighbour++;
                    sum += r;
                    n++;
                }
    double chi2 = 0, expect = double(n) / bins;
    for (uint64_t c : count) chi2 += (c - expect) * (c - expect) / expect;
    const double df = bins - 1;
    std::printf("  rand: mean %.5f, chi-square over %d bins %.1f (df %.0f)\n", sum / n, bins, chi2, df);
    EXPECT_LT(std::fabs(chi2 - df) / std::sqrt(2 * df), 4.0);
    EXPECT_NEAR(sum / n, 0.5, 4.0 * std::sqrt(1.0 / 12.0 / n));
    for (int b = 0; b < 24; ++b) EXPECT_NEAR(double(bitOnes[b]) / n, 0.5, 4.0 * 0.5 / std::sqrt(double(n))) << "bit " << b;
    EXPECT_LT(collisionsWithNeighbour, 5u);
    // Neighbouring seeds give unrelated streams: correlation of rand over the same pixels.
    double sxy = 0, sx = 0, sy = 0, sxx = 0, syy = 0;
    const int m = 65536;
    for (int i = 0; i < m; ++i) {
        double a = wrs_rand(i & 255, i >> 8, 0, 0, 1u), b = wrs_rand(i & 255, i >> 8, 0, 0, 2u);
        sx += a, sy += b, sxy += a * b, sxx += a * a, syy += b * b;
    }
    double corr = (sxy / m - sx / m * sy / m) / std::sqrt((sxx / m - sx * sx / m / m) * (syy / m - sy * sy / m / m));
    EXPECT_LT(std::fabs(corr), 4.0 / std::sqrt(double(m)));
}

// ---- Quality-aware retention (method wrs) ----

RetainInput retainInput(vec3 c, float q, float fp, float range = 0.0f, bool moved = false) {
    RetainInput in;
    in.color = c;
    in.q = q;
    in.lo = c - vec3(0.05f);
    in.hi = c + vec3(0.05f);
    in.fp = fp;
    in.fp_range = range;
    in.moved = moved;
    in.jittered = false;
    in.flags = 0u;
    in.weight = 1.0f;
    in.d = vec2(0.0f);
    in.z = 0.0f;
    in.q_floor = 0.0f;  // no floor rule unless a test asks for it
    return in;
}

Tracked tracked(vec3 c, float q, float fp) {
    Tracked t;
    t.color = c;
    t.q = q;
    t.w_sum = q;
    t.fp = wrs_fp_value(wrs_fp_code(fp));
    t.flags = 0u;
    t.z = 0.0f;
    t.d = vec2(0.0f);
    return t;
}

TEST(Retention, PackedValidityIsTheUnpackedValidity) {
    // The tracked lookup tests validity on the packed reservoir (wrs_packed_tracked_valid); it must
    // agree with wrs_tracked_valid on the unpacked fields for every bit pattern of the fp16 fields.
    const uint specials[] = {0x0000u, 0x8000u, 0x0001u, 0x8001u, 0x03ffu, 0x0400u, 0x3c00u, 0xbc00u,
                             0x7bffu, 0xfbffu, 0x7c00u, 0xfc00u, 0x7c01u, 0x7e00u, 0xfe00u, 0x7fffu};
    std::mt19937 rng(77);
    uint64_t checked = 0, valid = 0;
    auto check = [&](uvec4 p) {
        const bool expect = wrs_tracked_valid(wrs_unpack_tracked(p));
        ASSERT_EQ(wrs_packed_tracked_valid(p), expect) << std::hex << p.x << " " << p.y << " " << p.z << " " << p.w;
        checked++;
        valid += expect;
    };
    for (uint field = 0; field < 6; ++field)  // R, G, B, q, w_sum, z: each special under valid others
        for (uint h : specials) {
            uint f[6] = {0x3800u, 0x3800u, 0x3800u, 0x3c00u, 0x4000u, 0x4100u};
            f[field] = h;
            ASSERT_NO_FATAL_FAILURE(check(uvec4(f[0] | (f[1] << 16u), f[2] | (f[3] << 16u),
                                                f[4] | (0x7fu << 16u) | (1u << 24u), f[5] | (0x12u << 16u) | (0xf0u << 24u))));
        }
    for (int i = 0; i < 200000; ++i) ASSERT_NO_FATAL_FAILURE(check(uvec4(rng(), rng(), rng(), rng())));
    EXPECT_GT(valid, checked / 20);  // both outcomes well represented
    EXPECT_LT(valid, checked - checked / 20);
}

TEST(Retention, PackedLayoutRoundTrips) {
    Tracked t = tracked(vec3(0.25f, 0.5f, 0.75f), 1.0f / 64.0f, 53.3f);
    t.w_sum = 0.125f;
    t.flags = WRS_FLAG_MOVED;
    t.z = 3.5f;
    t.d = vec2(-0.5f, 0.25f);
    const Tracked u = wrs_unpack_tracked(wrs_pack_tracked(t, vec2(0.5f)));
    EXPECT_EQ(u.color, t.color);
    EXPECT_EQ(u.q, t.q);
    EXPECT_EQ(u.w_sum, t.w_sum);
    EXPECT_NEAR(u.fp, 53.3f, 0.5f / WRS_FP_SCALE);
    EXPECT_EQ(u.flags, WRS_FLAG_MOVED);
    EXPECT_EQ(u.z, 3.5f);
    EXPECT_EQ(u.d.x, -0.5f);
    EXPECT_NEAR(u.d.y, 0.25f, 1.0f / WRS_OFFSET_SCALE);
    // Offsets stay inside the half-open footprint whatever the dither: -127..126 codes.
    for (float d : {-0.5f, -0.2f, 0.0f, 0.49999f})
        for (float u0 : {0.0f, 0.5f, 0.999f}) {
            const float back = wrs_offset_value(wrs_offset_code(d, u0));
            EXPECT_TRUE(back >= -0.5f && back < 0.5f) << d << " " << u0;
            EXPECT_LE(std::fabs(back - d), 1.0f / WRS_OFFSET_SCALE);
        }
    // All-zero storage is "no history".
    EXPECT_FALSE(wrs_tracked_valid(wrs_unpack_tracked(uvec4(0u))));
}

// A kept sample under motion shows the tent-weighted mean of the tracked samples of its quality
// (wrs_shown_add): bilinear weights on the samples' lattice; other qualities, depth failures and
// empty storage take no part; nothing usable leaves the kept colour.
TEST(Retention, ShownColourIsTheTentMeanOfSameQualitySamples) {
    const float q = 1.0f;
    // Samples stored at pixels (4..5, 6..7), all at offset 0; the centre's previous position is
    // (5.25, 7.0) in pixel units, so the samples at x = 4.5 and 5.5 are 0.75 and 0.25 away in x,
    // and those at y = 6.5 and 7.5 both 0.5 away in y.
    auto packed = [&](vec3 col, float quality, float z) {
        Tracked t = tracked(col, quality, 50.0f);
        t.z = z;
        t.d = vec2(0.0f);
        return wrs_pack_tracked(t, vec2(0.5f));
    };
    const vec2 pos(5.25f, 7.0f);
    const uvec2 qs[4] = {uvec2(4, 6), uvec2(5, 6), uvec2(4, 7), uvec2(5, 7)};
    const vec3 cols[4] = {vec3(0.0f), vec3(1.0f), vec3(0.0f), vec3(1.0f)};
    vec4 acc(0.0f);
    for (int k = 0; k < 4; ++k) wrs_shown_add(acc, packed(cols[k], q, 2.0f), qs[k], pos, q, 2.0f, 0.0f, 0.1f);
    // x weights 0.25 (left) and 0.75 (right), y 0.5 and 0.5: 0.75 of the right column's colour.
    EXPECT_NEAR(acc.w, 1.0f, 1e-6f);
    EXPECT_NEAR(wrs_shown_end(acc, vec3(9.0f)).x, 0.75f, 1e-3f);
    // A sample of another quality, one behind another surface, and empty storage take no part.
    acc = vec4(0.0f);
    wrs_shown_add(acc, packed(vec3(1.0f), q, 2.0f), qs[1], pos, q, 2.0f, 0.0f, 0.1f);
    wrs_shown_add(acc, packed(vec3(0.0f), q / 64.0f, 2.0f), qs[0], pos, q, 2.0f, 0.0f, 0.1f);
    wrs_shown_add(acc, packed(vec3(0.0f), q, 3.0f), qs[2], pos, q, 2.0f, 0.0f, 0.1f);
    wrs_shown_add(acc, uvec4(0u), qs[3], pos, q, 2.0f, 0.0f, 0.1f);
    EXPECT_NEAR(acc.w, 0.375f, 1e-6f);
    EXPECT_NEAR(wrs_shown_end(acc, vec3(9.0f)).x, 1.0f, 1e-3f);
    // Unknown depth on either side is no depth failure; a sample a pixel or more away weighs 0.
    acc = vec4(0.0f);
    wrs_shown_add(acc, packed(vec3(0.5f), q, 0.0f), qs[1], pos, q, 2.0f, 0.0f, 0.1f);
    EXPECT_NEAR(acc.w, 0.375f, 1e-6f);
    wrs_shown_add(acc, packed(vec3(0.5f), q, 2.0f), uvec2(7, 7), pos, q, 2.0f, 0.0f, 0.1f);
    EXPECT_NEAR(acc.w, 0.375f, 1e-6f);
    // Nothing usable: the kept colour.
    EXPECT_EQ(wrs_shown_end(vec4(0.0f), vec3(0.25f, 0.5f, 0.75f)), vec3(0.25f, 0.5f, 0.75f));
}

// A kept sample shown against a candidate that blends in level 0 (its box holds the true colour) is
// clipped to that box when more than one 8-bit step outside, and so never moves away from any colour
// inside the box; otherwise (inside, within the slack, or no level 0) it is shown as it is.
TEST(Retention, KeptSampleIsClippedToABoxHoldingTheTruth) {
    const vec3 lo(0.2f, 0.3f, 0.4f), hi(0.5f, 0.6f, 0.7f);
    EXPECT_EQ(wrs_kept_shown(vec3(0.9f, 0.45f, 0.1f), lo, hi, true), vec3(0.5f, 0.45f, 0.4f));
    EXPECT_EQ(wrs_kept_shown(vec3(0.9f, 0.45f, 0.1f), lo, hi, false), vec3(0.9f, 0.45f, 0.1f));
    EXPECT_EQ(wrs_kept_shown(vec3(0.3f, 0.4f, 0.5f), lo, hi, true), vec3(0.3f, 0.4f, 0.5f));
    const vec3 justOut = hi + vec3(0.5f / 255.0f);  // within the slack: fp16 rounding, not a change
    EXPECT_EQ(wrs_kept_shown(justOut, lo, hi, true), justOut);
    // Per channel never farther from a truth inside the box (fixed seed, 100 000 cases).
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    for (int i = 0; i < 100000; ++i) {
        vec3 a(u(rng), u(rng), u(rng)), b(u(rng), u(rng), u(rng));
        vec3 l = min(a, b), h = max(a, b);
        vec3 truth = l + (h - l) * vec3(u(rng), u(rng), u(rng));
        vec3 shown(u(rng), u(rng), u(rng));
        vec3 s = wrs_kept_shown(shown, l, h, true);
        for (int c = 0; c < 3; ++c) ASSERT_LE(std::fabs(s[c] - truth[c]), std::fabs(shown[c] - truth[c])) << i;
    }
}

TEST(Retention, DitheredOffsetsFollowASlowDriftInExpectation) {
    // A sample drifting 0.001 px per frame (a quarter of a code) for 1000 frames ends 1 px away
    // (wrapped into the footprint by the tracking, here just accumulated) with a frame-varying dither.
    float d = -0.5f;
    for (uint f = 0; f < 900; ++f) d = wrs_offset_value(wrs_offset_code(d + 0.001f, wrs_offset_dither(f, 1u).x));
    EXPECT_NEAR(d, 0.4f, 0.05f);
}

TEST(Retention, RuleOutcomes) {
    const vec3 grey(0.3f);
    uint outcome;
    float margin;
    Tracked h = tracked(grey, 1.0f, 50.0f);
    // Lower-quality candidate: the sharp sample is kept (and moves with its offset).
    Tracked r = wrs_retain(WRS_RULE_MERGE, true, h, vec2(0.1f, 0.0f), retainInput(vec3(0.31f), 1.0f / 256.0f, 50.1f), grey, 0.5f,
                           outcome, margin);
    EXPECT_EQ(outcome, WRS_OUT_KEPT);
    EXPECT_EQ(r.color, grey);
    EXPECT_EQ(r.d.x, 0.1f);
    // The scene changed beyond the noise model: the candidate, whatever the qualities.
    r = wrs_retain(WRS_RULE_MERGE, true, h, vec2(0.0f), retainInput(vec3(0.31f), 1.0f / 256.0f, 50.0f + WRS_FP_TOL + 0.2f), grey,
                   0.5f, outcome, margin);
    EXPECT_EQ(outcome, WRS_OUT_CHANGED);
    // ... but a moved sample gets the fingerprint taps' range on top.
    r = wrs_retain(WRS_RULE_MERGE, true, h, vec2(0.0f),
                   retainInput(vec3(0.31f), 1.0f / 256.0f, 50.0f + WRS_FP_TOL + 0.2f, 1.0f, true), grey, 0.5f, outcome, margin);
    EXPECT_EQ(outcome, WRS_OUT_KEPT);
    // Higher quality replaces.
    Tracked low = tracked(grey, 1.0f / 64.0f, 50.0f);
    r = wrs_retain(WRS_RULE_MERGE, true, low, vec2(0.0f), retainInput(vec3(0.32f), 1.0f, 50.0f), grey, 0.5f, outcome, margin);
    EXPECT_EQ(outcome, WRS_OUT_BETTER);
    EXPECT_EQ(r.color, vec3(0.32f));
    // Equal quality merges: running mean, offset towards the centre, weight capped at 16 candidates.
    r = wrs_retain(WRS_RULE_MERGE, true, h, vec2(0.2f, 0.0f), retainInput(vec3(0.32f), 1.0f, 50.0f), grey, 0.5f, outcome, margin);
    EXPECT_EQ(outcome, WRS_OUT_MERGED);
    EXPECT_NEAR(r.color.x, 0.31f, 1e-6f);
    EXPECT_NEAR(r.d.x, 0.1f, 1e-6f);
    EXPECT_EQ(r.w_sum, 2.0f);
    for (int i = 0; i < 40; ++i)
        r = wrs_retain(WRS_RULE_MERGE, true, r, vec2(0.0f), retainInput(vec3(0.32f), 1.0f, 50.0f), grey, 0.5f, outcome, margin);
    EXPECT_EQ(r.w_sum, WRS_MERGE_CAP);
    // A history outside what the candidate's taps allow is clipped to their box, then merged: half
    // way (w_sum 1, q 1) from the box's edge (0.45) to the candidate (0.5), and nowhere outside the box;
    // the offset moves like a merge's.
    r = wrs_retain(WRS_RULE_MERGE, true, h, vec2(0.2f, 0.0f), retainInput(vec3(0.5f), 1.0f, 50.4f), grey, 0.5f, outcome,
                   margin);
    EXPECT_EQ(outcome, WRS_OUT_OUTSIDE);
    EXPECT_NEAR(r.color.x, 0.475f, 1e-6f);
    EXPECT_NEAR(r.d.x, 0.1f, 1e-6f);
    EXPECT_EQ(r.w_sum, 2.0f);
    // A sharp candidate (its taps are itself) is taken as a fresh sample: the output is exact.
    RetainInput sharp = retainInput(vec3(0.5f, 0.02f, 0.9f), 1.0f, 50.4f);
    sharp.lo = sharp.hi = sharp.color;
    r = wrs_retain(WRS_RULE_MERGE, true, h, vec2(0.2f, 0.0f), sharp, grey, 0.5f, outcome, margin);
    EXPECT_EQ(outcome, WRS_OUT_OUTSIDE);
    EXPECT_EQ(r.color, sharp.color);
    EXPECT_EQ(r.d, vec2(0.0f));
    EXPECT_EQ(r.fp, wrs_fp_value(wrs_fp_code(50.4f)));
    EXPECT_EQ(r.w_sum, 1.0f);
    // Reservoir option: A-Chao with the eq. 6 bias among equals.
    r = wrs_retain(WRS_RULE_RESERVOIR, true, h, vec2(0.0f), retainInput(vec3(0.32f), 1.0f, 50.0f), grey, 0.2f, outcome, margin);
    EXPECT_EQ(outcome, WRS_OUT_KEPT);  // keep iff rnd <= w1 / (w1 + q) = (1/2) / (3/2) = 1/3
    r = wrs_retain(WRS_RULE_RESERVOIR, true, h, vec2(0.0f), retainInput(vec3(0.32f), 1.0f, 50.0f), grey, 0.4f, outcome, margin);
    EXPECT_EQ(outcome, WRS_OUT_BETTER);
    // Oracle: whichever is closer to the reference.
    r = wrs_retain(WRS_RULE_ORACLE, true, h, vec2(0.0f), retainInput(vec3(0.6f), 1.0f, 50.0f), vec3(0.32f), 0.5f, outcome, margin);
    EXPECT_EQ(outcome, WRS_OUT_KEPT);
    // Retention oracle: the closer history only when it is of higher quality than the candidate. The
    // fingerprint, far beyond the change test's tolerance, plays no part in either oracle.
    const vec3 ref(0.32f);
    for (float fp : {50.0f, 90.0f}) {
        r = wrs_retain(WRS_RULE_ORACLE_Q, true, h, vec2(0.0f), retainInput(vec3(0.6f), 1.0f, fp), ref, 0.5f, outcome, margin);
        EXPECT_EQ(outcome, WRS_OUT_BETTER) << "equal quality: the candidate, however much farther";
        EXPECT_EQ(r.color, vec3(0.6f));
        r = wrs_retain(WRS_RULE_ORACLE_Q, true, low, vec2(0.0f), retainInput(vec3(0.6f), 1.0f / 16.0f, fp), ref, 0.5f, outcome,
                       margin);
        EXPECT_EQ(outcome, WRS_OUT_BETTER) << "lower quality: the candidate";
        r = wrs_retain(WRS_RULE_ORACLE_Q, true, h, vec2(0.1f, 0.0f), retainInput(vec3(0.6f), 1.0f / 64.0f, fp), ref, 0.5f,
                       outcome, margin);
        EXPECT_EQ(outcome, WRS_OUT_KEPT) << "higher quality and closer: kept";
        EXPECT_EQ(r.color, grey);
        EXPECT_EQ(r.d.x, 0.1f);
        r = wrs_retain(WRS_RULE_ORACLE_Q, true, h, vec2(0.0f), retainInput(vec3(0.33f), 1.0f / 64.0f, fp), ref, 0.5f,
                       outcome, margin);
        EXPECT_EQ(outcome, WRS_OUT_BETTER) << "higher quality but farther: the candidate";
    }
    // Within 2^-10 the qualities are equal, and the margin says how close the quality test was.
    r = wrs_retain(WRS_RULE_ORACLE_Q, true, h, vec2(0.0f), retainInput(vec3(0.6f), 1.0f - 1.0f / 2048.0f, 50.0f), ref, 0.5f,
                   outcome, margin);
    EXPECT_EQ(outcome, WRS_OUT_BETTER);
    EXPECT_LT(margin, 1e-3f);
    // An invalid candidate (q = 0) never replaces history.
    r = wrs_retain(WRS_RULE_MERGE, true, h, vec2(0.0f), retainInput(vec3(0.0f), 0.0f, 50.0f), grey, 0.5f, outcome, margin);
    EXPECT_EQ(outcome, WRS_OUT_KEPT);
    // ... not even when the poisoned patch moved the fingerprint (wrsfov-stress, streams invalid/nonfinite).
    for (uint rule : {WRS_RULE_MERGE, WRS_RULE_RESERVOIR, WRS_RULE_ORACLE, WRS_RULE_ORACLE_Q}) {
        r = wrs_retain(rule, true, h, vec2(0.0f), retainInput(vec3(0.0f), 0.0f, 0.0f), grey, 0.5f, outcome, margin);
        EXPECT_EQ(outcome, WRS_OUT_KEPT) << rule;
        EXPECT_EQ(r.color, grey);
    }
}

TEST(Retention, MillionAdversarialStepsKeepTheInvariants) {
    // Stability of the new layout (docs/stability.md): w_sum is bounded by construction (<= 16 q <= 16,
    // fp16-safe), there is no counter to saturate; adversarial candidates (qualities from 1 to 0 and
    // denormal, colours 0 to 65504, fingerprints jumping) must never make a stored reservoir
    // non-finite, give it q <= 0 while valid, or w_sum above the cap. Seeded, 10^6 steps per rule.
    std::mt19937 rng(4242);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    const float qs[] = {1.0f, 1.0f / 64.0f, 1.0f / 256.0f, 0.0f, 1e-40f, 0.37f};
    const float cs[] = {0.0f, 0.3f, 1.0f, 65504.0f, 1e-8f};
    for (uint rule : {WRS_RULE_MERGE, WRS_RULE_RESERVOIR, WRS_RULE_ORACLE, WRS_RULE_ORACLE_Q}) {
        uvec4 stored(0u);
        uint64_t bad = 0, valid = 0;
        for (uint f = 0; f < 1000000u; ++f) {
            const Tracked h = wrs_unpack_tracked(stored);
            const bool has = wrs_tracked_valid(h);
            valid += has;
            const float q = qs[rng() % 6], c = cs[rng() % 5];
            RetainInput in = retainInput(vec3(c, c * 0.5f, 0.2f), q, u(rng) < 0.01f ? 100.0f * u(rng) : 50.0f, u(rng), u(rng) < 0.5f);
            in.lo = min(in.lo, in.color);
            in.hi = max(in.hi, in.color);
            uint outcome;
            float margin;
            const vec2 d(u(rng) - 0.5f, u(rng) - 0.5f);
            const Tracked r = wrs_retain(rule, has, h, d, in, vec3(0.3f), u(rng), outcome, margin);
            stored = wrs_pack_tracked(r, wrs_offset_dither(f, 1u));
            const Tracked back = wrs_unpack_tracked(stored);
            bad += !(wrs_finite3(back.color) && std::isfinite(back.q) && std::isfinite(back.w_sum) && back.q >= 0.0f &&
                     back.w_sum >= 0.0f && back.w_sum <= WRS_MERGE_CAP * std::max(back.q, 1.0f) * 1.001f);
        }
        std::printf("rule %u: 10^6 steps, %llu with usable history, %llu invariant violations\n", rule,
                    (unsigned long long)valid, (unsigned long long)bad);
        EXPECT_EQ(bad, 0u);
        EXPECT_GT(valid, 500000u);
    }
}

// ---------------------------------------------------------------------------------------------
// Sparse retention (docs/retention.md "Sparse retention")
// ---------------------------------------------------------------------------------------------

TEST(SparseRetention, FloorRuleTakesTheCandidateOnlyAtTheFloor) {
    const float floorQ = wrs_floor_quality(WRS_FOV_MIP);
    EXPECT_EQ(floorQ, 1.0f / 256.0f);
    EXPECT_EQ(wrs_floor_quality(WRS_FOV_GAUSS), 1.0f / 256.0f);
    EXPECT_EQ(wrs_floor_quality(WRS_FOV_NONE), 0.0f);
    EXPECT_EQ(wrs_rule_floor(WRS_RULE_ORACLE, WRS_FOV_MIP), 0.0f);
    EXPECT_EQ(wrs_rule_floor(WRS_RULE_ORACLE_Q, WRS_FOV_MIP), floorQ);
    const vec3 grey(0.3f);
    uint outcome;
    float margin;
    auto in = [&](float q, float qFloor) {
        RetainInput c = retainInput(vec3(0.31f), q, 50.0f);
        c.q_floor = qFloor;
        return c;
    };
    for (uint rule : {WRS_RULE_MERGE, WRS_RULE_RESERVOIR}) {
        // Equal quality at the floor: the candidate, fresh (no merge, no random combine).
        Tracked r = wrs_retain(rule, true, tracked(vec3(0.3f), floorQ, 50.0f), vec2(0.2f, 0.0f), in(floorQ, floorQ), grey,
                               0.0f, outcome, margin);
        EXPECT_EQ(outcome, WRS_OUT_FLOOR);
        EXPECT_EQ(r.color, vec3(0.31f));
        EXPECT_EQ(r.w_sum, floorQ);
        EXPECT_EQ(r.d, vec2(0.0f));
        // Without a floor (foveation none, or q_floor 0) the same decision merges or combines as before.
        wrs_retain(rule, true, tracked(vec3(0.3f), floorQ, 50.0f), vec2(0.2f, 0.0f), in(floorQ, 0.0f), grey, 0.0f,
                   outcome, margin);
        EXPECT_NE(outcome, WRS_OUT_FLOOR);
        // Above the floor equal quality still merges (rule merge) or combines.
        wrs_retain(rule, true, tracked(vec3(0.3f), 1.0f / 64.0f, 50.0f), vec2(0.0f), in(1.0f / 64.0f, floorQ), grey,
                   0.0f, outcome, margin);
        EXPECT_TRUE(outcome == WRS_OUT_MERGED || outcome == WRS_OUT_KEPT) << outcome;
        // A sharper history is kept against a floor candidate.
        wrs_retain(rule, true, tracked(vec3(0.3f), 1.0f, 50.0f), vec2(0.0f), in(floorQ, floorQ), grey, 0.0f, outcome,
                   margin);
        EXPECT_EQ(outcome, WRS_OUT_KEPT);
    }
    // An invalid candidate (q = 0) keeps a history sharper than the floor, not one at the floor: that
    // pixel stores the invalid candidate (read as no history later) and shows what fov shows.
    Tracked r = wrs_retain(WRS_RULE_MERGE, true, tracked(vec3(0.3f), 1.0f / 64.0f, 50.0f), vec2(0.0f), in(0.0f, floorQ),
                           grey, 0.0f, outcome, margin);
    EXPECT_EQ(outcome, WRS_OUT_KEPT);
    r = wrs_retain(WRS_RULE_MERGE, true, tracked(vec3(0.3f), floorQ, 50.0f), vec2(0.0f), in(0.0f, floorQ), grey, 0.0f,
                   outcome, margin);
    EXPECT_EQ(outcome, WRS_OUT_FLOOR);
    EXPECT_FALSE(wrs_tracked_valid(wrs_unpack_tracked(wrs_pack_tracked(r, vec2(0.5f)))));
    // The retention oracle keeps only sharper samples, so the floor changes nothing but the invalid case.
    wrs_retain(WRS_RULE_ORACLE_Q, true, tracked(vec3(0.3f), floorQ, 50.0f), vec2(0.0f), in(floorQ, floorQ), vec3(0.3f),
               0.0f, outcome, margin);
    EXPECT_EQ(outcome, WRS_OUT_BETTER);
}

TEST(TrackedLookup, AGapBetweenUnevenlyDriftedSamplesShowsTheNearest) {
    // Under a slow pan, kept samples taken in different frames drift at different sub-pixel phases, so
    // neighbouring samples can sit up to two pixels apart. A pixel whose centre fell in such a gap
    // found no sample in its 2x2 lookup and showed its blurred candidate for a frame: isolated-pixel
    // speckle inside kept regions (docs/retention.md "Natural texture in motion"). The offsets below
    // are those wrsfov-bench --flicker found at such a pixel of the photo scene (mandrill, 0.37 px per
    // frame): the centre lies 0.87 px from one sample and 0.76 px from the next, both beyond the
    // fallback's 0.75. The lookup still finds nothing to store (a sample moved a whole pixel would be
    // misplaced from then on), but wrs_track_gap finds the nearest one to show (wrs_shown_color).
    const uvec2 p(246u, 178u), size(512u, 384u);
    const vec3 mv(0.3701172f, 0.0f, 0.0f);
    vec2 pos;
    ivec2 base;
    ASSERT_TRUE(wrs_track_start(p, size, mv, kInf, pos, base));
    const vec2 offsets[4] = {vec2(-0.5f, 0.0f), vec2(0.1299f, 0.0f), vec2(0.0157f, 0.0f), vec2(0.4961f, 0.0f)};
    TrackState ts = wrs_track_begin(p);
    uvec4 taps[4];
    for (uint k = 0; k < 4u; ++k) {
        uvec2 q;
        ASSERT_TRUE(wrs_track_tap(base, k, size, q));
        Tracked t = tracked(vec3(0.1f * float(k + 1)), 1.0f, 40.0f);
        t.d = offsets[k];
        taps[k] = wrs_pack_tracked(t, vec2(0.5f));
        wrs_track_consider(ts, taps[k], q, pos);
    }
    Tracked h;
    vec2 d;
    uvec2 q;
    EXPECT_FALSE(wrs_track_end(ts, h, d, q)) << "nothing within the fallback's reach to store";
    ASSERT_TRUE(wrs_track_gap(ts, h, d, q)) << "a sample to show";
    EXPECT_EQ(q, uvec2(247u, 178u)) << "the nearest: 0.76 px to the right";
    EXPECT_NEAR(h.color.x, 0.2f, 1e-3f);
    EXPECT_TRUE(wrs_track_inside(d));
    // What is shown: the tent mean of the samples of its quality around the centre, here the two on
    // either side of the gap (weights 1 - 0.76 and 1 - 0.87, the lower row a pixel down: weight 0).
    const vec3 shown = wrs_shown_color(taps[0], taps[1], taps[2], taps[3], base, pos, h, 0.0f, 0.0f, 0.05f);
    const float w0 = 1.0f - 0.8701172f, w1 = 1.0f - 0.7598f;
    EXPECT_NEAR(shown.x, (0.1f * w0 + 0.2f * w1) / (w0 + w1), 2e-3f);
    // Nothing from farther than a pixel on either axis.
    Tracked t = tracked(vec3(0.5f), 1.0f, 40.0f);
    t.d = vec2(0.49f, 0.49f);
    const uvec4 far = wrs_pack_tracked(t, vec2(0.5f));  // at tap 3: 1.12 px right, 1.49 px down
    TrackState lone = wrs_track_begin(p);
    for (uint k = 0; k < 4u; ++k) {
        uvec2 qk;
        ASSERT_TRUE(wrs_track_tap(base, k, size, qk));
        wrs_track_consider(lone, k == 3u ? far : uvec4(0u), qk, pos);
    }
    EXPECT_FALSE(wrs_track_end(lone, h, d, q));
    EXPECT_FALSE(wrs_track_gap(lone, h, d, q));
}

TEST(Retention, LandedDisplayIsContinuousAsASampleCrossesIntoTheNextPixel) {
    // wrs_landed_shown: under motion a landed sample A drifts from pixel p's footprint into the next
    // one's. Inside, p keeps it; just outside, p's history is its wide sample. Either way p shows the
    // quality-weighted tent mean of the landed taps of its 2x2 lookup, so its colour moves with A's
    // weight (1 - |dx|) instead of jumping to the wide view's colour.
    const uvec2 p(10u, 10u), size(64u, 64u);
    vec2 pos;
    ivec2 base;
    ASSERT_TRUE(wrs_track_start(p, size, vec3(0.3f, 0.0f, 0.0f), kInf, pos, base));
    ASSERT_EQ(base, ivec2(10, 10));
    const float qWide = 0.0625f;
    auto landed = [](float colour, float dx) {
        Tracked t = tracked(vec3(colour), 0.5f, 50.0f);
        t.flags = WRS_FLAG_LANDED;
        t.d = vec2(dx, 0.0f);
        return wrs_pack_tracked(t, vec2(0.5f));
    };
    // Tap 0 (pixel 10,10) holds B, 0.7 px left of p's centre; tap 1 (11,10) holds A; the row below none.
    const uvec4 B = landed(0.2f, -0.4f);
    const Tracked wide = tracked(vec3(0.5f), qWide, 50.0f);
    RetainInput c = retainInput(vec3(0.5f), qWide, 50.0f, 0.0f, true);
    auto shownWith = [&](float dA, bool inside) {
        const uvec4 A = landed(0.8f, dA);
        const uvec4 taps[4] = {B, A, uvec4(0u), uvec4(0u)};
        vec4 w;
        for (uint k = 0; k < 4u; ++k)
            w[int(k)] = wrs_shown_weight(taps[k], uvec2(base) + uvec2(k & 1u, k >> 1u), pos, 0.0f, 0.0f, 0.05f);
        const Tracked h = wrs_unpack_tracked(A);
        EXPECT_EQ(wrs_track_inside(wrs_track_offset(uvec2(11u, 10u), h.d, pos)), inside);
        // Inside: the rule keeps A (stored as it is). Outside: p holds its wide sample, shown as it is.
        return inside ? wrs_landed_shown(taps[0], taps[1], taps[2], taps[3], w, true, h, h, qWide, c, h.color)
                      : wrs_landed_shown(taps[0], taps[1], taps[2], taps[3], w, false, wide, wide, qWide, c, wide.color);
    };
    const vec3 in = shownWith(-0.21f, true), out = shownWith(-0.19f, false);  // A 0.49 px, then 0.51 px right
    const float wB = 0.3f, wIn = 0.51f, wOut = 0.49f;
    EXPECT_NEAR(in.x, (0.2f * wB + 0.8f * wIn) / (wB + wIn), 2e-3f);
    EXPECT_NEAR(out.x, (0.2f * wB + 0.8f * wOut) / (wB + wOut), 2e-3f);
    EXPECT_LT(std::abs(in.x - out.x), 0.01f) << "a step of 0.02 px moves the colour a little";
    EXPECT_GT(std::abs(out.x - 0.5f), 0.05f) << "not the wide view's colour";
    // A landed tap that fails the change test against the candidate is not shown at a wide pixel.
    RetainInput other = retainInput(vec3(0.5f), qWide, 80.0f, 0.0f, true);
    const uvec4 A = landed(0.8f, -0.19f);
    const vec4 w(wrs_shown_weight(B, uvec2(base), pos, 0.0f, 0.0f, 0.05f),
                 wrs_shown_weight(A, uvec2(base) + uvec2(1u, 0u), pos, 0.0f, 0.0f, 0.05f), 0.0f, 0.0f);
    EXPECT_EQ(wrs_landed_shown(B, A, uvec4(0u), uvec4(0u), w, false, wide, wide, qWide, other, wide.color), wide.color);
    // Nor where none of the taps is landed: an inset sample (quality 1, not flagged) leaves the pixel as it was.
    Tracked inset = tracked(vec3(0.9f), 1.0f, 50.0f);
    const uvec4 I = wrs_pack_tracked(inset, vec2(0.5f));
    const vec4 wi(0.0f, wrs_shown_weight(I, uvec2(base) + uvec2(1u, 0u), pos, 0.0f, 0.0f, 0.05f), 0.0f, 0.0f);
    EXPECT_EQ(wrs_landed_shown(uvec4(0u), I, uvec4(0u), uvec4(0u), wi, false, wide, wide, qWide, c, wide.color),
              wide.color);
}

TEST(SparseRetention, FloorSampleIsAFloorQualitySampleAtThePixelCentre) {
    // What a lookup reads from a tile that stored nothing: valid, of the floor quality, at offset 0,
    // exactly as a fresh floor-quality candidate is stored (the lookup's preference uses only these).
    const float floorQ = wrs_floor_quality(WRS_FOV_MIP);
    const uvec4 p = wrs_floor_sample(floorQ);
    ASSERT_TRUE(wrs_packed_tracked_valid(p));
    EXPECT_EQ(wrs_packed_quality(p), floorQ);
    EXPECT_EQ(wrs_packed_offset(p), vec2(0.0f));
    RetainInput c = retainInput(vec3(0.7f, 0.2f, 0.1f), floorQ, 61.0f);
    const uvec4 fresh = wrs_pack_tracked(wrs_tracked_from(c, floorQ), vec2(0.99f, 0.0f));
    EXPECT_EQ(wrs_packed_quality(fresh), wrs_packed_quality(p));
    EXPECT_EQ(wrs_packed_offset(fresh), wrs_packed_offset(p));
    // Both steer the 2x2 lookup alike from every position.
    std::mt19937 rng(17);
    std::uniform_real_distribution<float> u(-1.2f, 1.2f);
    for (int i = 0; i < 10000; ++i) {
        const vec2 pos(5.5f + u(rng), 5.5f + u(rng));
        TrackState a = wrs_track_begin(uvec2(5u)), b = wrs_track_begin(uvec2(5u));
        const uvec2 q(5u + uint(i & 1), 5u + uint((i >> 1) & 1));
        wrs_track_consider(a, p, q, pos);
        wrs_track_consider(b, fresh, q, pos);
        EXPECT_EQ(a.has_inside, b.has_inside);
        EXPECT_EQ(a.has_outer, b.has_outer);
        EXPECT_EQ(a.has_near, b.has_near);
        EXPECT_EQ(a.d, b.d);
        EXPECT_EQ(a.dn, b.dn);
    }
}

TEST(SparseRetention, TileSourcesHoldEveryTapALookupReads) {
    // For random tiles, sizes, motion reaches and per-pixel motion (zero, sub-pixel, large, beyond the
    // reach, off-screen, non-finite), every pixel a tracked lookup of the tile reads (wrs_track_start /
    // wrs_track_tap) lies in a source tile, computed from the motion range as classify.comp and the
    // reference do, and in a superblock of the tile's reach (wrs_reach_blocks), which the
    // classification reads instead of the motion. 20 000 tiles.
    std::mt19937 rng(2024);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    uint64_t taps = 0, wide = 0, offScreen = 0, beyond = 0;
    for (int n = 0; n < 20000; ++n) {
        const uvec2 size(1u + uint(u(rng) * 90.0f), 1u + uint(u(rng) * 70.0f));
        const uvec2 tiles((size + uvec2(WRS_TILE - 1u)) / WRS_TILE);
        const uvec2 t(uint(u(rng) * float(tiles.x)) % tiles.x, uint(u(rng) * float(tiles.y)) % tiles.y);
        const float scale = n % 4 == 0 ? 0.0f : (n % 4 == 1 ? 1.5f : (n % 4 == 2 ? 12.0f : 200.0f));
        const float reach = n % 3 == 0 ? kInf : (n % 3 == 1 ? 0.5f + u(rng) * 8.0f : 1.0f + u(rng) * 60.0f);
        const vec2 shift((u(rng) - 0.5f) * scale, (u(rng) - 0.5f) * scale);
        std::vector<std::pair<uvec2, vec3>> px;
        vec2 lo(0.0f), hi(0.0f);
        for (uint y = t.y * WRS_TILE; y < std::min((t.y + 1u) * WRS_TILE, size.y); ++y)
            for (uint x = t.x * WRS_TILE; x < std::min((t.x + 1u) * WRS_TILE, size.x); ++x) {
                vec3 mv(shift + vec2(u(rng) - 0.5f, u(rng) - 0.5f) * (scale > 0.0f ? 2.0f : 0.0f), 0.0f);
                if (u(rng) < 0.1f) mv = vec3(0.0f);
                if (u(rng) < 0.05f) mv.x = u(rng) < 0.5f ? reach : -reach;  // exactly at the reach
                if (u(rng) < 0.02f) mv.x = kNaN;
                if (u(rng) < 0.01f) mv.y = kInf;
                px.push_back({uvec2(x, y), mv});
                if (!wrs_finite(mv.x) || !wrs_finite(mv.y) || !wrs_within_reach(vec2(mv), reach)) continue;
                lo = min(lo, vec2(mv));
                hi = max(hi, vec2(mv));
            }
        uvec2 s0, s1, b0, b1;
        const bool any = wrs_tile_sources(t, size, lo, hi, s0, s1);
        const bool anyInReach = wrs_reach_blocks(t, size, reach, b0, b1);
        const bool narrow = (s1.x - s0.x + 1u) * (s1.y - s0.y + 1u) <= WRS_SOURCE_TILES_MAX;
        if (!narrow) ++wide;  // classified as holding anything: only the reach to check
        for (auto [p, mv] : px) {
            const bool moved = wrs_finite(mv.x) && wrs_finite(mv.y) && (mv.x != 0.0f || mv.y != 0.0f);
            vec2 pos;
            ivec2 base;
            if (!wrs_track_start(p, size, mv, reach, pos, base)) {
                const bool far = wrs_finite(mv.x) && wrs_finite(mv.y) && !wrs_within_reach(vec2(mv), reach);
                ++(far ? beyond : offScreen);
                continue;
            }
            for (uint k = 0; k < (moved ? 4u : 1u); ++k) {
                uvec2 q;
                if (!wrs_track_tap(base, k, size, q)) continue;
                ++taps;
                const uvec2 qt = q / WRS_TILE, qb = qt / WRS_SUPERBLOCK;
                ASSERT_TRUE(anyInReach) << "tile " << t.x << "," << t.y << ": a tap on screen, the reach said none";
                ASSERT_TRUE(qb.x >= b0.x && qb.x <= b1.x && qb.y >= b0.y && qb.y <= b1.y)
                    << "tile " << t.x << "," << t.y << " pixel " << p.x << "," << p.y << " reads " << q.x << "," << q.y
                    << " outside the superblocks of its reach " << reach;
                if (!narrow) continue;
                ASSERT_TRUE(any) << "tile " << t.x << "," << t.y << ": a tap on screen, sources said none";
                ASSERT_TRUE(qt.x >= s0.x && qt.x <= s1.x && qt.y >= s0.y && qt.y <= s1.y)
                    << "tile " << t.x << "," << t.y << " pixel " << p.x << "," << p.y << " reads " << q.x << "," << q.y
                    << " outside source tiles " << s0.x << "," << s0.y << " .. " << s1.x << "," << s1.y;
            }
        }
    }
    std::printf("taps checked %llu, tiles too wide %llu, off-screen lookups %llu, beyond the reach %llu\n",
                (unsigned long long)taps, (unsigned long long)wide, (unsigned long long)offScreen,
                (unsigned long long)beyond);
    EXPECT_GT(beyond, 10000u);
    EXPECT_GT(taps, 1000000u);
    EXPECT_GT(wide, 1000u);
    EXPECT_GT(offScreen, 1000u);
}

TEST(SparseRetention, OnlyFarTilesWithNothingSharperSkip) {
    const float floorQ = wrs_floor_quality(WRS_FOV_MIP);
    EXPECT_TRUE(wrs_tile_skips(WRS_TILE_FAR, 0.0f, floorQ));
    EXPECT_TRUE(wrs_tile_skips(WRS_TILE_FAR, floorQ, floorQ));
    EXPECT_FALSE(wrs_tile_skips(WRS_TILE_FAR, std::nextafter(floorQ, 1.0f), floorQ));
    EXPECT_FALSE(wrs_tile_skips(WRS_TILE_FAR, 0.0f, 0.0f));  // no floor (none, the oracle): never
    for (uint cls : {WRS_TILE_ANY, WRS_TILE_FOVEA, WRS_TILE_MID}) EXPECT_FALSE(wrs_tile_skips(cls, 0.0f, floorQ));
    // A skipped tile is foveated with the far tiles' levels.
    EXPECT_TRUE(wrs_tile_levels(WRS_TILE_SKIP) == wrs_tile_levels(WRS_TILE_FAR));
    EXPECT_EQ(wrs_level_quality(wrs_tile_levels(WRS_TILE_FAR)), floorQ);
}

// ---- Landed wide samples (shaders/wrs_submitted.h) ----

// How much of a pixel a landed sample tells is the overlap of its footprint, one output pixel wide,
// with the pixel: 1 on the centre, falling linearly per axis, 0 a pixel or more out, 0 for a
// non-finite offset. Its quality is WRS_LANDED_Q where the overlap is WRS_LANDED_MIN_OVERLAP (a
// quarter) or more, and 0 (not offered) below.
TEST(Landed, OneQualityWhereTheFootprintCoversAQuarterOfThePixel) {
    EXPECT_EQ(wrs_landed_overlap(vec2(0.0f)), 1.0f);
    EXPECT_EQ(wrs_landed_overlap(vec2(0.25f, 0.0f)), 0.75f);
    // The footprint, one pixel wide, reaches into the neighbouring pixels: next door it still overlaps.
    EXPECT_EQ(wrs_landed_overlap(vec2(-0.25f, 0.5f)), 0.375f);
    EXPECT_FLOAT_EQ(wrs_landed_overlap(vec2(-0.3f, 0.2f)), 0.7f * 0.8f);
    EXPECT_FLOAT_EQ(wrs_landed_overlap(vec2(0.49f, -0.49f)), 0.51f * 0.51f);
    EXPECT_EQ(wrs_landed_overlap(vec2(0.5f, 0.0f)), 0.5f);
    EXPECT_FLOAT_EQ(wrs_landed_overlap(vec2(0.8f, -0.1f)), 0.2f * 0.9f);
    EXPECT_EQ(wrs_landed_overlap(vec2(1.0f, 0.0f)), 0.0f);
    EXPECT_EQ(wrs_landed_overlap(vec2(0.0f, -1.5f)), 0.0f);
    EXPECT_EQ(wrs_landed_overlap(vec2(std::nanf(""), 0.0f)), 0.0f);
    EXPECT_EQ(wrs_landed_overlap(vec2(0.0f, std::numeric_limits<float>::infinity())), 0.0f);
    // One class: every sample whose footprint covers a quarter of the pixel or more has WRS_LANDED_Q,
    // whether it landed on the centre or next door; below a quarter it is not offered.
    EXPECT_EQ(wrs_landed_quality(vec2(0.0f)), WRS_LANDED_Q);
    EXPECT_EQ(wrs_landed_quality(vec2(0.25f, 0.0f)), WRS_LANDED_Q);
    EXPECT_EQ(wrs_landed_quality(vec2(0.49f, -0.49f)), WRS_LANDED_Q);  // 0.26
    EXPECT_EQ(wrs_landed_quality(vec2(0.7f, 0.0f)), WRS_LANDED_Q);    // 0.3, next door
    EXPECT_EQ(wrs_landed_quality(vec2(0.5f, 0.5f)), WRS_LANDED_Q);    // exactly a quarter
    EXPECT_EQ(wrs_landed_quality(vec2(0.8f, -0.1f)), 0.0f);           // 0.18: under a quarter, not offered
    EXPECT_EQ(wrs_landed_quality(vec2(std::nanf(""), 0.0f)), 0.0f);
    EXPECT_EQ(wrs_landed_quality(vec2(0.0f, std::numeric_limits<float>::infinity())), 0.0f);
    // Above the bilinear wide view's quality (density squared) at every density below sqrt(0.75), and
    // below the inset's (1), which a landed sample never replaces.
    EXPECT_GT(WRS_LANDED_Q, 0.4f * 0.4f);
    EXPECT_LT(WRS_LANDED_Q, 1.0f);
    // Inside the pixel always offered; beyond it, offered exactly where the footprint covers a quarter.
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> u(-0.4999f, 0.4999f);
    for (int i = 0; i < 1000; ++i) {
        const vec2 d(u(rng), u(rng));
        EXPECT_GT(wrs_landed_overlap(d), 0.25f);
        EXPECT_EQ(wrs_landed_quality(d), WRS_LANDED_Q);
    }
    std::uniform_real_distribution<float> v(-1.2f, 1.2f);
    for (int i = 0; i < 1000; ++i) {
        const vec2 d(v(rng), v(rng));
        const float q = wrs_landed_quality(d), o = wrs_landed_overlap(d);
        EXPECT_EQ(o, std::abs(d.x) < 1.0f && std::abs(d.y) < 1.0f ? (1 - std::abs(d.x)) * (1 - std::abs(d.y)) : 0.0f);
        EXPECT_EQ(q, o >= 0.25f ? WRS_LANDED_Q : 0.0f);
    }
}

// The offset of sample k from the centre of the output pixel that maps to `pos`, in output pixels.
TEST(Landed, OffsetIsTheSamplesCentreLessThePositionInOutputPixels) {
    const vec2 d = wrs_landed_offset(vec2(3.7f, 10.1f), uvec2(3u, 10u), vec2(2.5f, 2.0f));
    EXPECT_NEAR(d.x, (3.5f - 3.7f) * 2.5f, 1e-6f);
    EXPECT_NEAR(d.y, (10.5f - 10.1f) * 2.0f, 1e-6f);
    EXPECT_EQ(wrs_landed_offset(vec2(0.5f, 7.5f), uvec2(0u, 7u), vec2(2.5f)), vec2(0.0f));
}

// The landed footprint (wrs_landed_scale): half-width max(1, k s) output pixels per axis, so the offset's
// scale is s where the wide pixel is small and 1 / k (the half-width in wide pixels) where it is large.
TEST(Landed, FootprintGrowsWithTheWidePixelFromOneOutputPixel) {
    // 0.2 of the density (5 output pixels a wide pixel), k 0.3: a half-width of 1.5 output pixels.
    vec2 s = wrs_landed_scale(vec4(5.0f, 5.0f, 1.0f, 0.3f));
    EXPECT_NEAR(s.x, 5.0f / 1.5f, 1e-5f);
    EXPECT_NEAR(s.y, 5.0f / 1.5f, 1e-5f);
    // 0.3 and 0.4 of it (10/3 and 2.5): one output pixel, the offset in output pixels as before.
    EXPECT_EQ(wrs_landed_scale(vec4(2.5f, 2.5f, 1.0f, 0.3f)), vec2(2.5f));
    EXPECT_NEAR(wrs_landed_scale(vec4(10.0f / 3.0f, 10.0f / 3.0f, 1.0f, 0.3f)).x, 10.0f / 3.0f, 1e-5f);
    // Per axis; k = 0 is one output pixel at every density.
    s = wrs_landed_scale(vec4(8.0f, 2.0f, 1.0f, 0.25f));
    EXPECT_NEAR(s.x, 4.0f, 1e-6f);
    EXPECT_EQ(s.y, 2.0f);
    EXPECT_EQ(wrs_landed_scale(vec4(8.0f, 5.0f, 1.0f, 0.0f)), vec2(8.0f, 5.0f));
    // A sample 0.9 output pixels from the centre at 0.2: offered with the grown footprint (an overlap of
    // 0.4), not with one output pixel (0.1).
    const vec2 pos(3.5f + 0.9f / 5.0f, 7.5f);
    EXPECT_EQ(wrs_landed_quality(wrs_landed_offset(pos, uvec2(3u, 7u), wrs_landed_scale(vec4(5.0f, 5.0f, 1.0f, 0.3f)))),
              WRS_LANDED_Q);
    EXPECT_EQ(wrs_landed_quality(wrs_landed_offset(pos, uvec2(3u, 7u), wrs_landed_scale(vec4(5.0f, 5.0f, 1.0f, 0.0f)))),
              0.0f);
}

// Packed as the compose pass stores it: the colour and quality to fp16, and no sample as zeros.
TEST(Landed, PackedSamplesRoundTripAndNoneReadsAsNone) {
    const vec3 c(0.123456f, 2.5f, 0.0f);
    const vec4 r = wrs_unpack_landed(wrs_pack_landed(c, 0.6543f));
    EXPECT_EQ(r, vec4(wrs_round_f16(c.x), wrs_round_f16(c.y), 0.0f, wrs_round_f16(0.6543f)));
    EXPECT_EQ(wrs_pack_landed(c, 0.0f), uvec2(0u));
    EXPECT_EQ(wrs_unpack_landed(uvec2(0u)), vec4(0.0f));
}

// Retention is offered a landed sample only where it tells more than the composed candidate; then as a
// sample of its own (its box the composed candidate's, widened by it), stored fresh with its flag, so that the flag and the quality
// follow it while it is kept.
TEST(Landed, OfferedWhereSharperAndStoredWithItsFlag) {
    RetainInput c = retainInput(vec3(0.3f), 0.16f, 50.0f);
    // Not offered: none landed (weight 0), or a composed candidate as sharp as a landed sample or more
    // (the inset's).
    RetainInput none = c, inset = retainInput(vec3(0.3f), 1.0f, 50.0f);
    wrs_offer_landed(none, vec4(0.9f, 0.1f, 0.2f, 0.0f), vec2(0.0f));
    wrs_offer_landed(inset, vec4(0.9f, 0.1f, 0.2f, 1.0f), vec2(0.0f));
    EXPECT_EQ(none.color, c.color);
    EXPECT_EQ(none.flags, 0u);
    EXPECT_EQ(inset.color, vec3(0.3f));
    EXPECT_EQ(inset.q, 1.0f);
    const vec3 lo = c.lo, hi = c.hi;  // the composed candidate's box (its taps, or the wide box)
    ASSERT_LT(lo.x, 0.3f);
    wrs_offer_landed(c, vec4(0.9f, 0.1f, 0.2f, 1.0f), vec2(0.0f));
    EXPECT_EQ(c.color, vec3(0.9f, 0.1f, 0.2f));
    EXPECT_EQ(c.q, WRS_LANDED_Q);
    EXPECT_EQ(c.weight, 1.0f);
    EXPECT_EQ(c.lo, vec3(lo.x, 0.1f, 0.2f)) << "the box spans the landed sample and the composed candidate's box";
    EXPECT_EQ(c.hi, vec3(0.9f, hi.y, hi.z));
    EXPECT_EQ(c.flags, WRS_FLAG_LANDED);
    EXPECT_EQ(c.fp, 50.0f) << "the fingerprint stays the composed frame's";
    uint outcome;
    float margin;
    // Against a history of the wide views' quality: taken, flagged, and the flag survives packing.
    Tracked h = tracked(vec3(0.3f), 0.16f, 50.0f);
    Tracked r = wrs_retain(WRS_RULE_MERGE, true, h, vec2(0.0f), c, vec3(0.0f), 0.5f, outcome, margin);
    EXPECT_EQ(outcome, WRS_OUT_BETTER);
    EXPECT_EQ(wrs_unpack_tracked(wrs_pack_tracked(r, vec2(0.5f))).flags, WRS_FLAG_LANDED);
    // The next frame's composed candidate (0.16) keeps it.
    r = wrs_retain(WRS_RULE_MERGE, true, r, vec2(0.0f), retainInput(vec3(0.3f), 0.16f, 50.0f), vec3(0.0f), 0.5f,
                   outcome, margin);
    EXPECT_EQ(outcome, WRS_OUT_KEPT);
    EXPECT_EQ(r.flags, WRS_FLAG_LANDED);
}

// Where a landed sample is stored (wrs_landed_position): its offset in output pixels where it lies within
// the pixel's footprint, moved onto the footprint's edge where it landed next door, so that the tracked
// lookup carries it from where it was seen; a merge of the class sits at its samples' weighted position,
// and a composed candidate is stored at the centre as before.
TEST(Landed, StoredWhereItLandedAndAMergeWhereItsSamplesLie) {
    const vec4 landed(10.0f / 3.0f, 10.0f / 3.0f, 1.0f, 0.3f);  // 0.3 of the density
    // 0.06 wide pixels left of and 0.03 below the centre: 0.2 and 0.1 output pixels.
    const vec2 inside = wrs_landed_position(vec2(3.56f, 7.47f), uvec2(3u, 7u), landed);
    EXPECT_NEAR(inside.x, -0.2f, 1e-5f);
    EXPECT_NEAR(inside.y, 0.1f, 1e-5f);
    // 0.7 output pixels away on x (next door, offered by the footprint): onto the edge, inside the footprint.
    const vec2 next = wrs_landed_position(vec2(3.5f - 0.21f, 7.5f), uvec2(3u, 7u), landed);
    EXPECT_EQ(next, vec2(126.0f / WRS_OFFSET_SCALE, 0.0f));
    EXPECT_EQ(wrs_landed_position(vec2(3.5f + 0.21f, 7.5f), uvec2(3u, 7u), landed), vec2(-0.5f, 0.0f));

    uint outcome;
    float margin;
    // Fresh: stored where it landed (to the offset code's step), not at the centre.
    RetainInput c = retainInput(vec3(0.3f), 0.16f, 50.0f);
    wrs_offer_landed(c, vec4(0.4f, 0.4f, 0.4f, 1.0f), inside);
    Tracked r = wrs_retain(WRS_RULE_MERGE, false, Tracked{}, vec2(0.0f), c, vec3(0.0f), 0.5f, outcome, margin);
    EXPECT_EQ(outcome, WRS_OUT_FRESH);
    EXPECT_EQ(r.d, inside);
    const vec2 stored = wrs_unpack_tracked(wrs_pack_tracked(r, vec2(0.5f))).d;
    EXPECT_NEAR(stored.x, inside.x, 1.0f / WRS_OFFSET_SCALE);
    EXPECT_NEAR(stored.y, inside.y, 1.0f / WRS_OFFSET_SCALE);
    // Merged with the next landed sample (tracked to d_new): the mean's position moves towards the new
    // sample's by the merge weight, as its colour does.
    Tracked h = r;
    const vec2 d_new(0.3f, -0.2f);
    RetainInput c2 = retainInput(vec3(0.38f), 0.16f, 50.0f);
    wrs_offer_landed(c2, vec4(0.38f, 0.38f, 0.38f, 1.0f), next);
    r = wrs_retain(WRS_RULE_MERGE, true, h, d_new, c2, vec3(0.0f), 0.5f, outcome, margin);
    ASSERT_EQ(outcome, WRS_OUT_MERGED);
    const float t = wrs_merge_weight(h.w_sum, WRS_LANDED_Q);
    EXPECT_GT(t, 0.0f);
    EXPECT_LT(t, 1.0f);
    EXPECT_NEAR(r.d.x, d_new.x + (next.x - d_new.x) * t, 1e-6f);
    EXPECT_NEAR(r.d.y, d_new.y + (next.y - d_new.y) * t, 1e-6f);
    EXPECT_NEAR(r.color.x, 0.4f + (0.38f - 0.4f) * t, 1e-6f);
    EXPECT_LT(std::max(std::abs(r.d.x), std::abs(r.d.y)), 0.5f) << "a mean of positions inside the footprint stays inside";
    // A composed candidate (no landed sample) merges as a sample at the centre.
    Tracked hc = tracked(vec3(0.3f), 0.16f, 50.0f);
    r = wrs_retain(WRS_RULE_MERGE, true, hc, d_new, retainInput(vec3(0.32f), 0.16f, 50.0f), vec3(0.0f), 0.5f, outcome, margin);
    ASSERT_EQ(outcome, WRS_OUT_MERGED);
    EXPECT_EQ(r.d, d_new * (1.0f - wrs_merge_weight(hc.w_sum, 0.16f)));
}

// Landed weights: a sample's weight is its footprint's overlap (1/4 to 1) where weighted, else 1, and 0
// where it is not offered; in the running mean of the class a sample on the centre then outweighs one next
// door (0.8 of the way to it after one at overlap 1/4, where equal weights go halfway), and the weight cap
// stays WRS_MERGE_CAP candidates of the class's quality.
TEST(Landed, WeightsFavourTheSamplesNearestThePixelsCentre) {
    EXPECT_EQ(wrs_landed_weight(vec2(0.0f), true), 1.0f);
    EXPECT_EQ(wrs_landed_weight(vec2(0.5f, 0.5f), true), 0.25f);
    EXPECT_FLOAT_EQ(wrs_landed_weight(vec2(-0.3f, 0.2f), true), 0.7f * 0.8f);
    EXPECT_EQ(wrs_landed_weight(vec2(-0.3f, 0.2f), false), 1.0f);
    EXPECT_EQ(wrs_landed_weight(vec2(0.8f, -0.1f), true), 0.0f);  // under a quarter: not offered
    EXPECT_EQ(wrs_landed_weight(vec2(0.8f, -0.1f), false), 0.0f);
    EXPECT_EQ(wrs_landed_weight(vec2(std::nanf(""), 0.0f), true), 0.0f);
    auto offered = [](vec3 colour, float weight) {
        RetainInput c = retainInput(vec3(0.3f), 0.16f, 50.0f);
        c.jittered = true;
        wrs_offer_landed(c, vec4(colour, weight), vec2(0.0f));
        return c;
    };
    uint outcome;
    float margin;
    for (bool weighted : {false, true}) {
        const RetainInput far = offered(vec3(0.28f), weighted ? 0.25f : 1.0f);
        const RetainInput near = offered(vec3(0.6f), 1.0f);
        Tracked r = wrs_retain(WRS_RULE_MERGE, false, Tracked{}, vec2(0.0f), far, vec3(0.0f), 0.5f, outcome, margin);
        EXPECT_FLOAT_EQ(r.w_sum, WRS_LANDED_Q * (weighted ? 0.25f : 1.0f));
        r = wrs_retain(WRS_RULE_MERGE, true, r, vec2(0.0f), near, vec3(0.0f), 0.5f, outcome, margin);
        EXPECT_EQ(outcome, WRS_OUT_MERGED);
        EXPECT_NEAR(r.color.x, weighted ? 0.28f + 0.32f * 0.8f : 0.44f, 1e-6f) << (weighted ? "weighted" : "equal");
        for (int i = 0; i < 40; ++i)
            r = wrs_retain(WRS_RULE_MERGE, true, r, vec2(0.0f), near, vec3(0.0f), 0.5f, outcome, margin);
        EXPECT_FLOAT_EQ(r.w_sum, WRS_MERGE_CAP * WRS_LANDED_Q);
    }
}

// A new phase of a jittered view moves the composed fingerprint as sub-pixel motion does: the change
// test allows the fingerprint taps' range for it, and only for it.
TEST(Landed, AJitteredViewsNewPhaseIsNotAChange) {
    const Tracked h = tracked(vec3(0.3f), 0.64f, 50.0f);
    RetainInput c = retainInput(vec3(0.3f), 0.16f, 53.0f, 4.0f);
    uint outcome;
    float margin;
    wrs_retain(WRS_RULE_MERGE, true, h, vec2(0.0f), c, vec3(0.0f), 0.5f, outcome, margin);
    EXPECT_EQ(outcome, WRS_OUT_CHANGED) << "3 L* is a change of a still, unjittered view";
    c.jittered = true;
    wrs_retain(WRS_RULE_MERGE, true, h, vec2(0.0f), c, vec3(0.0f), 0.5f, outcome, margin);
    EXPECT_EQ(outcome, WRS_OUT_KEPT);
    EXPECT_TRUE(wrs_gap_shows(h, c));
    c.fp = 56.0f;  // beyond the taps' range too
    wrs_retain(WRS_RULE_MERGE, true, h, vec2(0.0f), c, vec3(0.0f), 0.5f, outcome, margin);
    EXPECT_EQ(outcome, WRS_OUT_CHANGED);
}

// Every phase merged: the wide box's taps lie one wide pixel apart (the output pixels per wide pixel,
// rounded, at least 1), clamped to the image; a tap that was not finite is left out; only wide
// candidates (up to the wide view's quality) take it.
TEST(Landed, TheWideBoxSpansTheWideViewAroundThePixel) {
    const uint s = wrs_wide_box_steps(vec2(4.0f, 2.5f));
    EXPECT_EQ(s & 0xffffu, 4u);
    EXPECT_EQ(s >> 16u, 3u) << "2.5 rounds to 3";
    EXPECT_EQ(wrs_wide_box_steps(vec2(0.8f, 1.0f)), 1u | (1u << 16u)) << "at least one pixel";
    const uvec2 size(64u, 48u), p(10u, 1u);
    EXPECT_EQ(wrs_wide_box_tap(p, 0u, s, size), uvec2(6u, 0u)) << "clamped at the top edge";
    EXPECT_EQ(wrs_wide_box_tap(p, 4u, s, size), p) << "the centre tap is the pixel";
    EXPECT_EQ(wrs_wide_box_tap(p, 8u, s, size), uvec2(14u, 4u));
    EXPECT_EQ(wrs_wide_box_tap(uvec2(62u, 47u), 8u, s, size), uvec2(63u, 47u)) << "clamped at the far corner";
    vec3 lo(0.5f), hi(0.5f);
    wrs_wide_box_add(lo, hi, vec4(0.2f, 0.7f, 0.5f, 1.0f));
    wrs_wide_box_add(lo, hi, vec4(100.0f, 100.0f, 100.0f, 0.0f));  // not finite: validity 0
    EXPECT_EQ(lo, vec3(0.2f, 0.5f, 0.5f));
    EXPECT_EQ(hi, vec3(0.5f, 0.7f, 0.5f));
    EXPECT_TRUE(wrs_wide_box_applies(0.16f, 0.16f));
    EXPECT_TRUE(wrs_wide_box_applies(0.0f, 0.16f)) << "an invalid candidate's box does not matter, but is wide";
    EXPECT_FALSE(wrs_wide_box_applies(0.5f, 0.16f)) << "the inset's blend keeps its own box";
    EXPECT_FALSE(wrs_wide_box_applies(1.0f, 0.16f));
}

}  // namespace
}  // namespace wrsfov::gpu

// ---- Reading an sRGB input through a view of its own format (shaders/wrs_input.h) ----------------

namespace wrsfov::gpu {
namespace {

// The smallest distance from code k's linear value to its neighbours'.
float srgbStep(int k) {
    const auto& t = wrs_srgb8_table();
    float step = std::numeric_limits<float>::infinity();
    if (k > 0) step = std::min(step, t[k] - t[k - 1]);
    if (k < 255) step = std::min(step, t[k + 1] - t[k]);
    return step;
}

// A device's decode of every code, exact or off by up to a third of the step to the next code (what
// the recovery promises to absorb), recovers the code, whichever result the spec lets pow give.
TEST(Input, SrgbViewRecoversEveryCode) {
    const auto& t = wrs_srgb8_table();
    EXPECT_NEAR(srgbStep(0), 1.0 / (255.0 * 12.92), 1e-9);
    for (Permitted p : {Permitted::Nearest, Permitted::Low, Permitted::High, Permitted::Mixed}) {
        DeviceRounding model;
        model.builtins = p;
        model.unorm = p;
        model.seed = 5;
        ScopedDeviceRounding scoped(model);
        for (int k = 0; k < 256; ++k)
            for (float off : {0.0f, -0.33f, 0.33f, -0.1f, 0.1f}) {
                const float decoded = std::max(0.0f, t[k] + off * srgbStep(k));
                EXPECT_EQ(wrs_srgb8_code_of(decoded), uint(k)) << "code " << k << " decoded off by " << off
                                                                 << " of a step, pow " << int(p);
            }
        // Two thirds of a step is the next code's (the recovery is the nearest code, not a guess).
        for (int k = 0; k < 255; ++k)
            EXPECT_EQ(wrs_srgb8_code_of(t[k] + 0.67f * (t[k + 1] - t[k])), uint(k + 1)) << "code " << k;
    }
}

// One reading function: a code read through a UNORM view (code / 255) and through an sRGB view (its
// linear value) decode to the same bits; linear and composed input pass through; non-finite channels
// are sanitised to 0 and mark the texel unusable, from either view.
TEST(Input, BothViewsOfAnSrgbImageDecodeToTheSameBits) {
    const auto& t = wrs_srgb8_table();
    for (int k = 0; k < 256; ++k) {
        const vec4 unorm(wrs_unorm8_value(uint(k)), wrs_unorm8_value(uint(255 - k)), wrs_unorm8_value(uint(k / 2)), 1.0f);
        const vec4 decoded(t[k], t[255 - k], t[k / 2], 1.0f);
        const vec4 a = wrs_decode_input(unorm, WRS_INPUT_SRGB), b = wrs_decode_input(decoded, WRS_INPUT_SRGB_VIEW);
        for (int c = 0; c < 4; ++c)
            EXPECT_EQ(std::bit_cast<uint32_t>(a[c]), std::bit_cast<uint32_t>(b[c])) << "code " << k << " channel " << c;
        EXPECT_EQ(a.x, t[k]);
        EXPECT_EQ(a.w, 1.0f);
    }
    const vec4 lin(0.25f, 2.0f, 0.0f, 0.5f);
    EXPECT_EQ(vec3(wrs_decode_input(lin, WRS_INPUT_LINEAR)), vec3(lin));
    EXPECT_EQ(wrs_decode_input(lin, WRS_INPUT_LINEAR).w, 1.0f);
    EXPECT_EQ(wrs_decode_input(vec4(0.5f, 0.5f, 0.5f, 0.0f), WRS_INPUT_COMPOSED).w, 0.0f);  // no valid tap
    const float nan = std::numeric_limits<float>::quiet_NaN(), inf = std::numeric_limits<float>::infinity();
    for (uint enc : {WRS_INPUT_LINEAR, WRS_INPUT_COMPOSED}) {
        const vec4 r = wrs_decode_input(vec4(nan, inf, -inf, 1.0f), enc);
        EXPECT_EQ(vec3(r), vec3(0.0f, 0.0f, 0.0f)) << "encoding " << enc;
        EXPECT_EQ(r.w, 0.0f) << "encoding " << enc;
    }
    // An sRGB view cannot return a non-finite value, but whatever reaches the recovery maps to a code.
    for (float v : {nan, inf, -inf, -1.0f, 2.0f}) {
        const vec4 r = wrs_decode_input(vec4(v, v, v, 1.0f), WRS_INPUT_SRGB_VIEW);
        EXPECT_TRUE(wrs_finite3(vec3(r))) << v;
        EXPECT_LE(r.x, 1.0f) << v;
    }
}

}  // namespace
}  // namespace wrsfov::gpu

namespace wrsfov::gpu {
namespace {

// The steady display (wrs_display_fold_step): a pixel without history and a history that is not finite show
// retention's colour as it is; a still pixel converges to it, also where it stands out of its wide
// neighbourhood's box (the box grows to hold it); a history far outside is clipped to the box before the
// blend, so a change shows within a frame.
struct DisplayNeighbourhood {
    vec3 mu, sigma;  // the moments of the wide taps around the pixel (YCoCg)
    explicit DisplayNeighbourhood(vec3 centre, vec3 around) {
        vec3 m1(0.0f), m2(0.0f);
        for (int i = 0; i < 9; ++i) wrs_moments_add(m1, m2, wrs_rgb_to_ycocg(i == 4 ? centre : around));
        wrs_moments_of_nine(m1, m2, mu, sigma);
    }
    vec3 step(vec3 shown, vec3 hist, bool has, float alpha = WRS_DISPLAY_ALPHA) const {
        return wrs_display_fold_step(mu, sigma, shown, hist, has, alpha);
    }
};

TEST(SteadyDisplay, NoHistoryAndNonFiniteHistoryShowRetentionsColour) {
    const vec3 shown(0.6f, 0.3f, 0.2f), hist(0.1f, 0.1f, 0.1f);
    DisplayNeighbourhood n(shown, vec3(0.5f, 0.3f, 0.2f));
    for (vec3 r : {n.step(shown, hist, false), n.step(shown, vec3(std::nanf(""), 0.0f, 0.0f), true),
                   n.step(shown, vec3(0.0f, std::numeric_limits<float>::infinity(), 0.0f), true)})
        for (int k = 0; k < 3; ++k) EXPECT_EQ(r[k], shown[k]);
    // The moments are the nine taps' (wrs_taa_moments of the same taps, one at a time).
    vec3 nb[9];
    for (int i = 0; i < 9; ++i) nb[i] = wrs_rgb_to_ycocg(i == 4 ? shown : vec3(0.5f, 0.3f, 0.2f));
    vec3 mu, sigma;
    wrs_taa_moments(nb, mu, sigma);
    for (int k = 0; k < 3; ++k) {
        EXPECT_EQ(mu[k], n.mu[k]);
        EXPECT_EQ(sigma[k], n.sigma[k]);
    }
    // A tap whose input was not finite counts as the pixel's own composed colour.
    EXPECT_EQ(wrs_display_tap(vec4(0.1f, 0.2f, 0.3f, 0.0f), vec4(0.7f, 0.6f, 0.5f, 1.0f)), vec3(0.7f, 0.6f, 0.5f));
    EXPECT_EQ(wrs_display_tap(vec4(0.1f, 0.2f, 0.3f, 1.0f), vec4(0.7f, 0.6f, 0.5f, 1.0f)), vec3(0.1f, 0.2f, 0.3f));
}

// What the display stores of a colour (its history): fp16 RGB, the hand conversion's values, and a flag that
// a never-written (zeroed) buffer does not have.
TEST(SteadyDisplay, ShownColoursAreStoredInFp16WithAWrittenFlag) {
    for (vec3 c : {vec3(0.0f), vec3(0.9f, 0.123456f, 1e-6f), vec3(65504.0f, 3.0e-5f, 0.5f), vec3(7.77777f)}) {
        const glm::uvec2 w = wrs_pack_shown(c);
        EXPECT_TRUE(wrs_shown_written(w));
        const vec3 back = wrs_unpack_shown(w);
        for (int k = 0; k < 3; ++k) EXPECT_EQ(back[k], wrs_round_f16(c[k])) << k;
    }
    EXPECT_FALSE(wrs_shown_written(glm::uvec2(0u)));
    // Beyond fp16's range the history reads as not finite, and the display shows retention's colour.
    const vec3 shown(0.6f, 0.3f, 0.2f);
    DisplayNeighbourhood n(shown, vec3(0.5f, 0.3f, 0.2f));
    const vec3 huge = wrs_unpack_shown(wrs_pack_shown(vec3(1e6f, 0.0f, 0.0f)));
    EXPECT_FALSE(wrs_finite3(huge));
    const vec3 r = n.step(shown, huge, true);
    for (int k = 0; k < 3; ++k) EXPECT_EQ(r[k], shown[k]);
}

TEST(SteadyDisplay, AStillPixelConvergesToWhatRetentionShowsEvenOutsideTheBox) {
    // A bright pixel of fine detail in a dark wide neighbourhood: far outside mean ± gamma sigma of it.
    const vec3 shown(0.9f), around(0.05f);
    DisplayNeighbourhood n(around, around);
    ASSERT_GT(wrs_rgb_to_ycocg(shown).x, n.mu.x + WRS_DISPLAY_GAMMA * n.sigma.x) << "the case the grown box is for";
    vec3 d = vec3(0.5f);  // a history halfway
    for (int i = 0; i < 200; ++i) d = n.step(shown, d, true);
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(d[k], shown[k], 1e-4f);
    // With the history stored in fp16, as the display stores it, a step under half an fp16 step stalls:
    // within 2e-3 of what retention shows, and shown with its 8-bit code.
    vec3 h = vec3(0.5f), c(0.0f);
    for (int i = 0; i < 200; ++i) {
        c = n.step(shown, h, true);
        h = wrs_unpack_shown(wrs_pack_shown(c));
    }
    for (int k = 0; k < 3; ++k) {
        EXPECT_NEAR(h[k], shown[k], 2e-3f);
        EXPECT_EQ(std::lround(wrs_output_value(c)[k] * 255.0f), std::lround(wrs_output_value(shown)[k] * 255.0f)) << k;
    }
}

// The weight where the pixel moves (wrs_display_weight): the weight as it is up to the full speed, in either
// direction; beyond it, falling as the speed's inverse (a pixel crossing k times the full speed a frame
// weighs the current frame 1/k as much) down to WRS_DISPLAY_FAST_SHARE of it; a motion that is not finite,
// or a full speed of 0, leaves it as it is.
TEST(SteadyDisplay, TheWeightFallsAsTheSpeedBeyondTheFullSpeed) {
    ASSERT_EQ(WRS_DISPLAY_FAST_SHARE, 0.5f) << "the figures below are for a floor at half the weight";
    const float a = 0.3f, v0 = 1.5f;
    for (vec3 m : {vec3(0.0f), vec3(1.5f, 0.0f, 0.0f), vec3(0.0f, -1.5f, 0.2f), vec3(0.9f, -1.2f, 0.0f),
                   vec3(-0.6f, 0.8f, 5.0f)})
        EXPECT_EQ(wrs_display_weight(a, m, v0), a) << m.x << "," << m.y;
    EXPECT_FLOAT_EQ(wrs_display_weight(a, vec3(3.0f, 0.0f, 0.0f), v0), a / 2.0f);
    EXPECT_FLOAT_EQ(wrs_display_weight(a, vec3(0.0f, -2.25f, 0.0f), v0), a * 1.5f / 2.25f);
    EXPECT_FLOAT_EQ(wrs_display_weight(a, vec3(-1.2f, 1.6f, 1.0f), v0), a * 1.5f / 2.0f) << "the speed is |(x, y)|";
    EXPECT_EQ(wrs_display_weight(a, vec3(0.0f, -6.0f, 0.0f), v0), a * WRS_DISPLAY_FAST_SHARE) << "the floor";
    EXPECT_EQ(wrs_display_weight(a, vec3(1e30f, 0.0f, 0.0f), v0), a * WRS_DISPLAY_FAST_SHARE);
    // Monotone in the speed, and never above the weight.
    float last = a;
    for (float s = 0.0f; s < 40.0f; s += 0.25f) {
        const float w = wrs_display_weight(a, vec3(s, 0.0f, 0.0f), v0);
        EXPECT_LE(w, last);
        EXPECT_GT(w, 0.0f);
        last = w;
    }
    const float inf = std::numeric_limits<float>::infinity();
    for (vec3 m : {vec3(std::nanf(""), 0.0f, 0.0f), vec3(0.0f, inf, 0.0f), vec3(-inf, 1.0f, 0.0f)})
        EXPECT_EQ(wrs_display_weight(a, m, v0), a);
    EXPECT_EQ(wrs_display_weight(a, vec3(50.0f, 0.0f, 0.0f), 0.0f), a) << "0: one weight at every speed";
    EXPECT_EQ(wrs_display_weight(a, vec3(std::nanf("")), std::nanf("")), a);
}

// The history resampling of the steady display and `taau` (wrs_history_add): Lanczos-2 over the 4x4
// pixels, deringed to the bilinear cell's four.
namespace {
// A 1-D history (one row, `img[x]` its pixels) read at x0 + f as the shaders read it (the 4x4 taps of rows
// that are all this row).
vec3 resampledRow(const std::vector<vec3>& img, uint x0, float f) {
    TaauGather g = wrs_taau_gather_start();
    const uvec2 size(uint(img.size()), 4u);
    const vec4 wx = wrs_history_weights(f), wy = wrs_history_weights(0.0f);
    for (uint j = 0; j < 16u; ++j) wrs_history_add(g, img[wrs_history_tap(uvec2(x0, 1u), size, j).x], wx, wy, j);
    return wrs_history_result(g);
}
vec3 bilinearRow(const std::vector<vec3>& img, uint x0, float f) {
    return img[x0] + (img[std::min<std::size_t>(x0 + 1, img.size() - 1)] - img[x0]) * f;
}
// 10-90 % width in pixels of a rising edge from 0 to 1 (channel x).
float edgeWidth(const std::vector<vec3>& img) {
    auto cross = [&](float level) {
        for (std::size_t x = 1; x < img.size(); ++x)
            if (img[x].x >= level) return float(x - 1) + (level - img[x - 1].x) / (img[x].x - img[x - 1].x);
        return float(img.size());
    };
    return cross(0.9f) - cross(0.1f);
}
}  // namespace

TEST(HistoryResampling, AWholePixelReadsThePixelAndAFlatHistoryStaysFlat) {
    std::vector<vec3> row(16);
    for (std::size_t x = 0; x < row.size(); ++x) row[x] = vec3(0.05f * float(x), 0.3f, float(x % 3) * 0.4f);
    // (the polynomial's zeros at 1 and 2 are zeros to within a float's rounding: 1e-7 of a neighbour leaks in)
    for (uint x = 0; x < 16u; ++x)
        for (int k = 0; k < 3; ++k) EXPECT_NEAR(resampledRow(row, x, 0.0f)[k], row[x][k], 1e-6f) << "f = 0 is the pixel itself, x " << x;
    // The 4x4 weights at any fraction: the cell's four positive, the sum near 1.
    for (float fx : {0.0f, 0.1f, 0.25f, 0.5f, 0.8f, 0.999f})
        for (float fy : {0.0f, 0.3f, 0.5f, 0.9f}) {
            TaauGather g = wrs_taau_gather_start();
            for (uint j = 0; j < 16u; ++j) wrs_history_add(g, vec3(0.6f), wrs_history_weights(fx), wrs_history_weights(fy), j);
            EXPECT_GT(g.acc.w, 0.9f) << fx << "," << fy;
            EXPECT_LT(g.acc.w, 1.1f) << fx << "," << fy;
            for (int k = 0; k < 3; ++k) EXPECT_FLOAT_EQ(wrs_history_result(g)[k], 0.6f) << "a flat history";
        }
    // Taps beyond the view's edge read its edge pixel.
    EXPECT_EQ(wrs_history_tap(uvec2(0u, 0u), uvec2(8u, 8u), 0u), uvec2(0u, 0u));
    EXPECT_EQ(wrs_history_tap(uvec2(7u, 7u), uvec2(8u, 8u), 15u), uvec2(7u, 7u));
    EXPECT_EQ(wrs_history_tap(uvec2(3u, 4u), uvec2(8u, 8u), 6u), uvec2(4u, 4u));
}

TEST(HistoryResampling, ANoRingingEdgeStaysSharperThanBilinearUnderMotion) {
    // A step edge carried 0.5 px a frame for 24 frames, the history resampled each frame (what a display
    // whose current frame weighs nothing would show): bilinear blurs it frame after frame, Lanczos-2 keeps it.
    const std::size_t n = 64;
    std::vector<vec3> lz(n), bl(n);
    for (std::size_t x = 0; x < n; ++x) lz[x] = bl[x] = vec3(x < 20 ? 0.0f : 1.0f);
    for (int t = 0; t < 24; ++t) {
        std::vector<vec3> l2(n), b2(n);
        const float shift = t % 2 ? 0.5f : 0.25f;  // the edge moves right: pixel x reads x - shift
        for (std::size_t x = 1; x < n; ++x) {
            l2[x] = resampledRow(lz, uint(x - 1), 1.0f - shift);
            b2[x] = bilinearRow(bl, uint(x - 1), 1.0f - shift);
        }
        l2[0] = lz[0], b2[0] = bl[0];
        lz = l2, bl = b2;
        for (std::size_t x = 0; x < n; ++x) {
            EXPECT_GE(lz[x].x, 0.0f) << "deringed: no undershoot, frame " << t;
            EXPECT_LE(lz[x].x, 1.0f) << "deringed: no overshoot, frame " << t;
        }
    }
    const float wl = edgeWidth(lz), wb = edgeWidth(bl);
    EXPECT_LT(wl, 0.5f * wb) << "Lanczos-2 " << wl << " px against bilinear " << wb << " px";
    EXPECT_GT(wb, 3.0f) << "bilinear reprojection blurs";
}

TEST(HistoryResampling, ANonFiniteTapMakesTheHistoryNonFiniteSoThatItIsNotUsed) {
    std::vector<vec3> row(8, vec3(0.4f));
    row[3] = vec3(std::nanf(""), 0.4f, 0.4f);
    EXPECT_FALSE(wrs_finite3(resampledRow(row, 3u, 0.5f)));
    row[3] = vec3(0.4f, std::numeric_limits<float>::infinity(), 0.4f);
    EXPECT_FALSE(wrs_finite3(resampledRow(row, 2u, 0.25f)));
    // The display then shows retention's colour (wrs_display_fold_step's guard).
    const vec3 shown(0.25f, 0.5f, 0.75f);
    EXPECT_EQ(wrs_display_fold_step(vec3(0.3f), vec3(0.1f), shown, resampledRow(row, 2u, 0.25f), true, 0.3f), shown);
}

TEST(SteadyDisplay, AHistoryFarOutsideIsClippedBeforeTheBlend) {
    const vec3 shown(0.2f);
    DisplayNeighbourhood n(shown, vec3(0.2f));  // a flat neighbourhood: the box is one 8-bit step wide
    const vec3 r = n.step(shown, vec3(1.0f), true);
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(r[k], 0.2f, 2.0f / 255.0f) << "a white history does not ghost";
    // Inside the box, the blend weighs the current colour by alpha.
    DisplayNeighbourhood m(vec3(0.5f), vec3(0.3f));
    const vec3 inside = m.step(vec3(0.5f), vec3(0.45f), true, 0.25f);
    EXPECT_NEAR(inside.x, 0.45f + 0.25f * (0.5f - 0.45f), 1e-5f);
    // The box is mean ± WRS_DISPLAY_GAMMA sigma: a history just outside it is pulled onto its edge first.
    DisplayNeighbourhood w(vec3(0.3f), vec3(0.3f, 0.32f, 0.3f));
    const vec3 edge = w.mu + WRS_DISPLAY_GAMMA * w.sigma;
    const vec3 far = w.step(vec3(0.3f), vec3(0.9f, 0.3f, 0.3f), true, 0.0f);
    EXPECT_LE(wrs_rgb_to_ycocg(far).x, std::max(edge.x, wrs_rgb_to_ycocg(vec3(0.3f)).x) + 1e-5f);
}

}  // namespace
}  // namespace wrsfov::gpu
