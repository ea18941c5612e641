// The fovea a method is worth (eval::foveaWorth): the fov fovea of equal score, interpolated linearly
// between the swept foveas, on synthetic JOD-against-fovea curves.
#include <gtest/gtest.h>

#include "eval/bench.h"

namespace wrsfov::eval {
namespace {

using Bound = FoveaWorth::Bound;

TEST(FoveaWorth, InterpolatesLinearlyInsideTheSweep) {
    // JOD 6.0 at 5°, 6.4 at 7.5°, 7.0 at 10°: 6.7 lies half way between 7.5° and 10°.
    const FoveaWorth w = foveaWorth({{5.0, 6.0}, {7.5, 6.4}, {10.0, 7.0}, {12.5, 7.3}, {15.0, 7.5}}, 6.7);
    EXPECT_EQ(w.bound, Bound::Exact);
    EXPECT_NEAR(w.deg, 8.75, 1e-12);
    EXPECT_EQ(toString(w), "8.8°");
    // On a sweep point exactly, and in any order.
    const FoveaWorth on = foveaWorth({{10.0, 7.0}, {5.0, 6.0}, {7.5, 6.4}}, 6.4);
    EXPECT_EQ(on.bound, Bound::Exact);
    EXPECT_NEAR(on.deg, 7.5, 1e-12);
}

TEST(FoveaWorth, AboveTheSweepIsMoreThanItsLargestFovea) {
    const FoveaWorth w = foveaWorth({{5.0, 6.0}, {7.5, 6.4}, {10.0, 7.0}, {12.5, 7.3}, {15.0, 7.5}}, 7.9);
    EXPECT_EQ(w.bound, Bound::MoreThan);
    EXPECT_EQ(w.deg, 15.0);
    EXPECT_EQ(toString(w), "more than 15.0°");
}

TEST(FoveaWorth, NoBetterThanTheSmallestFoveaIsAtMostIt) {
    const FoveaWorth w = foveaWorth({{5.0, 6.0}, {10.0, 7.0}}, 5.9);
    EXPECT_EQ(w.bound, Bound::AtMost);
    EXPECT_EQ(w.deg, 5.0);
    EXPECT_EQ(toString(w), "5.0° or less");
}

TEST(FoveaWorth, NonMonotonicCurveTakesTheFirstCrossing) {
    // fov's JOD dips at 10° (noise of a short run): the smallest fovea reaching 6.5 is between 5° and 7.5°,
    // and a target reached only after the dip is interpolated on the rising segment after it.
    const std::vector<std::pair<double, double>> curve{{5.0, 6.0}, {7.5, 6.8}, {10.0, 6.2}, {12.5, 7.0}, {15.0, 7.4}};
    const FoveaWorth early = foveaWorth(curve, 6.4);
    EXPECT_EQ(early.bound, Bound::Exact);
    EXPECT_NEAR(early.deg, 6.25, 1e-12);
    const FoveaWorth late = foveaWorth(curve, 6.9);
    EXPECT_EQ(late.bound, Bound::Exact);
    EXPECT_NEAR(late.deg, 10.0 + 2.5 * (6.9 - 6.2) / (7.0 - 6.2), 1e-12);
}

TEST(FoveaWorth, IgnoresMissingScoresAndSaysWhenUnknown) {
    const double nan = std::numeric_limits<double>::quiet_NaN();
    const FoveaWorth w = foveaWorth({{5.0, 6.0}, {7.5, nan}, {10.0, 7.0}}, 6.5);
    EXPECT_EQ(w.bound, Bound::Exact);
    EXPECT_NEAR(w.deg, 7.5, 1e-12);
    EXPECT_EQ(foveaWorth({}, 6.5).bound, Bound::Unknown);
    EXPECT_EQ(foveaWorth({{5.0, 6.0}}, nan).bound, Bound::Unknown);
    EXPECT_EQ(toString(foveaWorth({}, 6.5)), "n/a");
}

}  // namespace
}  // namespace wrsfov::eval
