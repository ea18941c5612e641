#include "stress/model.h"

#include <algorithm>
#include <bit>
#include <cmath>

namespace wrsfov::stress {

double replaceProbability(double wsum, double w, double change, bool bernoulli) {
    double s1 = wsum * (1.0 - change);
    if (bernoulli) s1 *= wsum / (wsum + w);
    const double total = s1 + w;
    return total > 0.0 ? w / total : 0.0;
}

std::vector<ModelFrame> runModel(const Stream& stream, uint64_t frames, bool f16Colour) {
    std::vector<ModelFrame> m(frames + 1);
    double s = 0.0;
    for (uint64_t n = 1; n <= frames; ++n) {
        const ModelStep st = stream.model(n, f16Colour);
        if (n == 1 || st.flush) {
            s = st.weight;
            m[n] = {1.0, s};
            continue;
        }
        double s1 = s * (1.0 - st.change);
        if (stream.bernoulli) s1 *= s / (s + st.weight);
        const double total = s1 + st.weight;
        m[n] = {total > 0.0 ? st.weight / total : 0.0, total};
        s = total;
    }
    return m;
}

BucketKey bucketOf(const Stream& stream, uint64_t birth, uint64_t at) {
    const uint64_t age = at - birth;
    return {stream.sample(birth, 0).cls, uint32_t(std::bit_width(age + 1) - 1)};
}

std::map<BucketKey, double> birthBuckets(const Stream& stream, const std::vector<ModelFrame>& model, uint64_t at) {
    std::map<BucketKey, double> b;
    double survive = 1.0;
    for (uint64_t k = at; k >= 1 && survive > 0.0; --k) {
        const double p = model[k].p;
        if (p > 0.0) b[bucketOf(stream, k, at)] += p * survive;
        survive *= 1.0 - p;
    }
    return b;
}

ChiSquare chiSquare(const std::map<BucketKey, double>& expected, const std::map<BucketKey, uint64_t>& observed,
                    uint64_t n) {
    ChiSquare r;
    // Every key either side, in order; merge until each group expects at least 5.
    std::map<BucketKey, std::pair<double, double>> all;
    for (const auto& [k, p] : expected) all[k].first += p * double(n);
    for (const auto& [k, c] : observed) all[k].second += double(c);
    std::vector<std::pair<double, double>> groups;
    std::pair<double, double> acc{0, 0};
    for (const auto& [k, eo] : all) {
        acc.first += eo.first;
        acc.second += eo.second;
        if (acc.first >= 5.0) {
            groups.push_back(acc);
            acc = {0, 0};
        }
    }
    if (acc.first > 0 || acc.second > 0) {
        if (groups.empty()) {
            groups.push_back(acc);
        } else {
            groups.back().first += acc.first;
            groups.back().second += acc.second;
        }
    }
    for (const auto& [e, o] : groups) {
        if (e <= 0) {
            // An observation where the model says impossible: infinite evidence against it.
            if (o > 0) r.chi2 = INFINITY;
            continue;
        }
        r.chi2 += (o - e) * (o - e) / e;
    }
    r.dof = int(groups.size()) - 1;
    r.valid = r.dof >= 1 || std::isinf(r.chi2);
    r.p = r.valid ? chiSquareUpperTail(r.chi2, std::max(r.dof, 1)) : 1.0;
    return r;
}

namespace {

// Regularized lower incomplete gamma P(a, x) by its series (x < a + 1) and the upper Q(a, x) by a
// continued fraction (Lentz), the textbook split.
double gammaP_series(double a, double x) {
    double sum = 1.0 / a, term = sum;
    for (int n = 1; n < 10000; ++n) {
        term *= x / (a + n);
        sum += term;
        if (std::fabs(term) < std::fabs(sum) * 1e-15) break;
    }
    return sum * std::exp(-x + a * std::log(x) - std::lgamma(a));
}
double gammaQ_fraction(double a, double x) {
    const double tiny = 1e-300;
    double b = x + 1.0 - a, c = 1.0 / tiny, d = 1.0 / b, h = d;
    for (int i = 1; i < 10000; ++i) {
        const double an = -i * (i - a);
        b += 2.0;
        d = an * d + b;
        if (std::fabs(d) < tiny) d = tiny;
        c = b + an / c;
        if (std::fabs(c) < tiny) c = tiny;
        d = 1.0 / d;
        const double delta = d * c;
        h *= delta;
        if (std::fabs(delta - 1.0) < 1e-15) break;
    }
    return std::exp(-x + a * std::log(x) - std::lgamma(a)) * h;
}

}  // namespace

double chiSquareUpperTail(double chi2, int dof) {
    if (!(chi2 > 0)) return 1.0;
    if (std::isinf(chi2)) return 0.0;
    const double a = 0.5 * dof, x = 0.5 * chi2;
    return x < a + 1.0 ? 1.0 - gammaP_series(a, x) : gammaQ_fraction(a, x);
}

double normalTwoSided(double z) { return std::erfc(std::fabs(z) / std::sqrt(2.0)); }

double ZTest::z() const {
    if (variance > 0) return (observed - expected) / std::sqrt(variance);
    // No randomness expected: any difference is infinitely unlikely.
    return std::fabs(observed - expected) < 0.5 ? 0.0 : (observed > expected ? INFINITY : -INFINITY);
}

}  // namespace wrsfov::stress
