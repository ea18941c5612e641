#include "gaze/random.h"

#include <cmath>

namespace wrsfov::gaze {

double gamma_sample(cv::RNG& rng, double shape, double scale) {
    if (!(shape > 0) || !(scale > 0)) return 0;
    if (shape < 1) {
        // Boost a shape < 1 draw: X = Y * U^(1/k) with Y ~ Gamma(k + 1).
        const double u = rng.uniform(1e-300, 1.0);
        return gamma_sample(rng, shape + 1, scale) * std::pow(u, 1.0 / shape);
    }
    const double d = shape - 1.0 / 3.0, c = 1.0 / std::sqrt(9.0 * d);
    for (;;) {
        double x, v;
        do {
            x = rng.gaussian(1.0);
            v = 1.0 + c * x;
        } while (v <= 0);
        v = v * v * v;
        const double u = rng.uniform(1e-300, 1.0);
        if (u < 1.0 - 0.0331 * x * x * x * x) return d * v * scale;
        if (std::log(u) < 0.5 * x * x + d * (1.0 - v + std::log(v))) return d * v * scale;
    }
}

double exponential_sample(cv::RNG& rng, double mean) { return -std::log(rng.uniform(1e-300, 1.0)) * mean; }

}  // namespace wrsfov::gaze
