// Distributions on top of cv::RNG that OpenCV does not provide (gamma, exponential).
#pragma once

#include <opencv2/core.hpp>

namespace wrsfov::gaze {

/// Gamma(shape k, scale theta) by Marsaglia & Tsang (2000), driven by `rng`. k > 0, theta > 0.
double gamma_sample(cv::RNG& rng, double shape, double scale);

/// Gamma with the given mean and shape (scale = mean / shape).
inline double gamma_mean(cv::RNG& rng, double mean, double shape) { return gamma_sample(rng, shape, mean / shape); }

/// Exponential with the given mean.
double exponential_sample(cv::RNG& rng, double mean);

/// Uniform in [lo, hi).
inline double uniform_sample(cv::RNG& rng, double lo, double hi) { return rng.uniform(lo, hi); }

}  // namespace wrsfov::gaze
