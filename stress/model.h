// The exact (double precision, unrounded) model of the temporal combine and the statistical tests
// the stress run compares the shipping code against.
//
// Model: paper eq. 7 (eq. 6 x change term) and Alg. 2 without any storage rounding, WRS_WSUM_MIN
// floor or M cap:
//   no history (first frame, flush):  s = w,                      the candidate is taken (p = 1)
//   otherwise:  s1 = s (1 − |ΔL|) · s / (s + w)   (bias off: s1 = s (1 − |ΔL|))
//               p  = w / (s1 + w)   probability that the candidate replaces the kept sample
//               s  = s1 + w
// For streams whose w_sum trajectory does not depend on the kept sample (Stream::model), p is known
// for every frame in advance, so the distribution of the kept sample's birth frame is known too.
#pragma once

#include <cstdint>
#include <map>
#include <utility>
#include <vector>

#include "stress/streams.h"

namespace wrsfov::stress {

/// One frame of the exact model: the replacement probability and w_sum after the frame.
struct ModelFrame {
    double p = 1.0;
    double wsum = 0.0;
};

/// Runs a stream's model for frames 1..frames (index 0 unused); `f16Colour` as in Stream::model.
std::vector<ModelFrame> runModel(const Stream& stream, uint64_t frames, bool f16Colour);

/// The conditional replacement probability of one decision, given the history as loaded: eq. 7 and
/// Alg. 2 in double precision.
double replaceProbability(double wsum, double w, double change, bool bernoulli);

/// Birth-frame distribution of the kept sample at frame `at`, summed into buckets keyed by
/// (class of the birth frame's candidate, floor(log2(age + 1))).
using BucketKey = std::pair<uint32_t, uint32_t>;
std::map<BucketKey, double> birthBuckets(const Stream& stream, const std::vector<ModelFrame>& model, uint64_t at);
BucketKey bucketOf(const Stream& stream, uint64_t birth, uint64_t at);

/// Pearson chi-square of observed counts against expected probabilities (n = total count); buckets
/// with an expected count below 5 are merged in key order.
struct ChiSquare {
    double chi2 = 0;
    int dof = 0;
    double p = 1;  ///< upper tail probability
    bool valid = false;
};
ChiSquare chiSquare(const std::map<BucketKey, double>& expected, const std::map<BucketKey, uint64_t>& observed,
                    uint64_t n);

/// Upper tail of the chi-square distribution with `dof` degrees of freedom.
double chiSquareUpperTail(double chi2, int dof);
/// Two-sided tail of the standard normal.
double normalTwoSided(double z);

/// Sum of independent Bernoulli trials (Poisson-binomial): observed count against expectation.
struct ZTest {
    double observed = 0, expected = 0, variance = 0;
    void add(double p) {
        expected += p;
        variance += p * (1.0 - p);
    }
    double z() const;
};

}  // namespace wrsfov::stress
