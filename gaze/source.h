// Gaze sources: what the compositor and the tools poll at frame times.
#pragma once

#include <cstddef>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "gaze/gaze_file.h"
#include "gaze/generator.h"
#include "gaze/result.h"
#include "gaze/sample.h"

namespace wrsfov::gaze {

/// What a source reports when the tracker has no fresh valid sample.
struct DropoutPolicy {
    /// The last valid direction is held this long after it was measured; after that the eye is
    /// reported invalid, and the compositor falls back to a fixed centre with a larger fovea.
    double hold_s = 0.1;
    /// Valid samples further apart than this are not interpolated between: the time between them
    /// is a dropout (a tracker that stopped reporting, a gap in a recording), handled as above.
    double max_gap_s = 0.1;
};

/// A gaze source polled at arbitrary times.
class GazeSource {
public:
    virtual ~GazeSource() = default;

    /// Gaze at `t_s` in the source's time line: interpolated between the samples around it,
    /// with invalid eyes handled by the source's `DropoutPolicy`. Never blocks.
    virtual GazeSample sample(double t_s) = 0;
};

/// Interpolates a time-ordered sample sequence at `t_s` under `policy`. Per eye: both
/// neighbours valid and at most `max_gap_s` apart -> normalised linear interpolation of the
/// directions; otherwise the most recent valid sample at or before `t_s` is held if it is at most
/// `hold_s` old, else the eye is invalid. The label is the one of the nearest sample.
GazeSample interpolate_samples(std::span<const GazeSample> samples, double t_s, const DropoutPolicy& policy);

/// Replays recorded samples (any format `read_gaze_file` reads). Times outside the recording
/// follow the dropout policy from its first/last sample.
class ReplaySource final : public GazeSource {
public:
    ReplaySource(std::vector<GazeSample> samples, DropoutPolicy policy = {});

    /// Opens a gaze file; bad rows are skipped (see `issues()`).
    static Result<std::unique_ptr<ReplaySource>> open(const std::string& path, DropoutPolicy policy = {},
                                                      const ReadOptions& options = {});

    GazeSample sample(double t_s) override;
    double duration_s() const;
    const std::vector<FileIssue>& issues() const { return issues_; }

private:
    std::vector<GazeSample> samples_;
    DropoutPolicy policy_;
    std::vector<FileIssue> issues_;
};

/// Synthetic gaze: generates `config.seconds` once and replays it, looping (the wrap is an
/// ordinary gaze jump).
class SyntheticSource final : public GazeSource {
public:
    static Result<std::unique_ptr<SyntheticSource>> create(const GeneratorConfig& config, DropoutPolicy policy = {});

    GazeSample sample(double t_s) override;
    const GeneratedGaze& generated() const { return gen_; }

private:
    SyntheticSource(GeneratedGaze gen, double period, DropoutPolicy policy);
    GeneratedGaze gen_;
    double period_;
    DropoutPolicy policy_;
};

}  // namespace wrsfov::gaze
