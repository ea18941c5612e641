// Checks shared by the GPU tests: reading both eyes' reservoirs, one step of the GPU against the
// CPU reference started from the GPU's own history, and reservoir sanity.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "gpu_rig.h"

namespace wrsfov::test {

using Reservoirs = std::array<std::vector<glm::uvec4>, 2>;

/// Both eyes' reservoirs as the last frame wrote them (fails the test if they cannot be read).
Reservoirs readReservoirs(Compositor& comp);

struct StepTally {
    uint64_t decisions = 0;      ///< pixels that had history
    uint64_t mismatches = 0;     ///< selection differs from the reference
    uint64_t nearThreshold = 0;  ///< ... of which the random number was within 1e-6 of the threshold
    int maxOutputDiff = 0;       ///< 0..255
};

/// Compares the compositor's last frame with `ref`, which has just stepped the same frame from the
/// history `prev` (the GPU's reservoirs before the frame): M equal everywhere, w_sum to float
/// rounding, the same selection except within 1e-6 of the threshold, output within 1/255.
void compareWithReference(Compositor& gpu, const Reference& ref, const Reservoirs& prev, StepTally& tally,
                          const std::string& what);

/// Runs one frame on the GPU and the reference from the GPU's current history and compares them.
/// Returns the history the frame started from.
Reservoirs stepBoth(Compositor& gpu, StereoApp& app, Reference& ref, uint64_t frameIndex,
                    const std::array<EyeFrame, 2>& eyes, StepTally& tally, const std::string& what);

/// Two compositors that ran the same frames agree bit for bit: both eyes' outputs, and both eyes'
/// reservoirs (methods with history only). `what` names the comparison in failure messages.
void expectSameOutputs(Compositor& a, Compositor& b, const std::string& what);
/// Reservoirs equal byte for byte, except in tiles that sparse retention skipped in one of the two
/// (they stored nothing there; where both ran it the skipped tiles read as zero in both).
void expectSameReservoirs(Compositor& a, Compositor& b, const std::string& what);

/// Every reservoir unpacks finite, with w_sum > 0 and M >= 1 (the invariant of docs/conventions.md, "Reservoirs").
void expectReservoirsSane(const std::vector<glm::uvec4>& packed, const std::string& what);

/// Eccentricity in degrees of pixel (x, y) for the frame parameters, in double.
double eccentricity(const gpu::EyeParams& ep, uint32_t x, uint32_t y, uint32_t width, uint32_t height);

}  // namespace wrsfov::test
