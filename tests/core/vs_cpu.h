// The GPU pipeline against the CPU reference over many frames of random colour, depth, motion and gaze
// (test_gpu_vs_cpu.cpp), and the same frames against references that round as another conformant
// device may (test_gpu_rounding.cpp). Each frame the references start from the GPU's own history, so
// every frame checks one step of every pixel.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "gpu_rig.h"

namespace wrsfov::test {

/// A pipeline to compare.
struct Case {
    const char* name;
    Method method;
    FoveationMode mode;
    layers::Format color;
    std::optional<layers::Format> depth;
    std::optional<layers::Format> motion;
    ChangeMetric change;
    bool reversed;
    EqualQuality rule = EqualQuality::Merge;
    bool steadyFloor = false;
};

/// `wrs-paper`'s selections and every method's outputs.
struct Tally {
    uint64_t decisions = 0, kept = 0, mismatches = 0, nearThreshold = 0, outputOff = 0, maxOutputDiff = 0;
    uint64_t channels = 0, channelsOneStep = 0;  ///< output channels compared, and those one 8-bit step apart
};
/// `wrs` and the oracles: decisions by outcome, and those that differ from the reference's.
struct RetainTally {
    uint64_t decisions = 0, outcomes[gpu::WRS_OUTCOMES] = {}, mismatches = 0, nearThreshold = 0;
};
/// The steady floor's texels (Case::steadyFloor).
struct SteadyTally {
    uint64_t texels = 0, differ = 0;
};

/// One reference stepped beside the GPU: what it models of the device (the CPU's own rounding by
/// default) and what its comparison found.
struct Variant {
    std::string name;
    gpu::DeviceRounding model;
    Tally t;
    RetainTally rt;
    SteadyTally st;
};

/// Runs `frames` random frames of case `c` at W x H through the compositor and, from the GPU's history
/// each frame, through one reference per variant, comparing every decision, reservoir and output (the
/// steady floor's texels too where it runs). Failures name the variant; the tallies are in `variants`.
void runAgainstReferences(const Case& c, uint32_t W, uint32_t H, int frames, std::vector<Variant>& variants);

/// The checks on a variant's tallies that hold for every conformant device: decisions equal except
/// near their thresholds (and few of those), outputs within one 8-bit step, the steady floor within one
/// fp16 step.
void expectAgreement(const Case& c, const Variant& v);

/// The pipelines of the comparison.
std::vector<Case> comparedPipelines();

}  // namespace wrsfov::test
