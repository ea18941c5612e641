// Adversarial per-pixel input streams for the long-run stress of the reservoir update.
//
// A stream says what one pixel is given in every frame: the colour and depth as an application
// submits them (before the load pass sanitizes them) and the sample weight p̂ the foveate pass
// would give that pixel if its colour is valid. Streams whose w_sum trajectory does not depend on
// which sample is kept also describe themselves to the exact model (stress/model.h), which gives
// the expected selection frequencies.
#pragma once

#include <cstdint>
#include <functional>
#include <glm/glm.hpp>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace wrsfov::stress {

/// What one pixel is given in one frame.
struct StreamSample {
    glm::vec3 color{0.5f};  ///< linear RGB as submitted (may be NaN/Inf/negative: the load pass sanitizes)
    float weight = 1.0f;    ///< p̂ of the candidate when its colour is valid (the load pass zeroes it otherwise)
    float depth = 0.5f;     ///< depth-buffer value as submitted, [0, 1] (anything else: unknown depth)
    uint32_t cls = 0;       ///< candidate class, for the selection statistics
};

/// One frame of a stream as the exact model sees it (same for every pixel of the stream).
struct ModelStep {
    double weight = 1.0;  ///< w_cur
    double change = 0.0;  ///< |ΔL| of eq. 7 between the candidate and the kept sample
    bool flush = false;   ///< the history is dropped (depth test): the candidate starts a new reservoir
};

/// Which weights a stream feeds the combine.
enum class Domain : uint8_t {
    Pipeline,  ///< weights the foveate pass produces: 0 (invalid colour) or p̂ in [minPipelineWeight(), 1]
    Extreme,   ///< weights in [0, 1] the foveate pass never produces (1e-6, FLT_MIN, denormals, 0 with a valid colour)
    Outside,   ///< weights no foveate pass produces and the combine does not promise to handle (> 1, NaN, < 0)
};
std::string_view toString(Domain d);

struct Stream {
    Stream() = default;
    Stream(std::string n, std::string d) : name(std::move(n)), description(std::move(d)) {}
    std::string name;
    std::string description;
    /// Pipeline and Extreme streams must meet every invariant (no NaN/Inf stored or output, w_sum
    /// bounded, M never wrapping) and, unless `knownDeviation` says otherwise, select as the model says.
    Domain domain = Domain::Pipeline;
    std::string knownDeviation;  ///< why the selection statistics are expected to differ from the exact model
    bool bernoulli = true;       ///< the eq. 6 survival bias (CompositorConfig::bernoulli)
    std::vector<std::string> classes{"all"};
    std::function<StreamSample(uint64_t frame, uint32_t pixel)> sample;
    /// Set when the w_sum trajectory is the same for every pixel and does not depend on the kept
    /// sample: then the exact model gives the selection probability of every frame. `f16Colour`: the
    /// kept sample's colour is stored in fp16, so a candidate equal to it before storage differs from it
    /// by the rounding, and the change term sees that difference.
    std::function<ModelStep(uint64_t frame, bool f16Colour)> model;
};

/// Depth conventions of the streams (standard Z, the host app's defaults) and the depth test.
inline constexpr float kNearZ = 0.1f, kFarZ = 100.0f, kDepthTau = 0.05f;

/// Seeded content randomness of the streams (splitmix64 of the inputs; independent of wrs_rand).
uint64_t streamHash(uint32_t seed, uint32_t stream, uint64_t a, uint64_t b = 0);
/// The top 24 bits of a hash as a float in [0, 1).
float unitFloat(uint64_t hash);

/// The smallest weight the foveate pass produces: eccentricity 180°, fovea diameter → 0.
float minPipelineWeight();

/// Every stream, for runs of `frames` frames (frames are numbered from 1; frame 1 has no history).
std::vector<Stream> makeStreams(uint64_t frames, uint32_t seed);
std::vector<std::string> streamNames();

}  // namespace wrsfov::stress
