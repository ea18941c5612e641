// HID eye trackers through hidapi: enumeration, report descriptors from sysfs, and a gaze source
// that survives unplugging.
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "gaze/hid_descriptor.h"
#include "gaze/hid_eyetracker.h"
#include "gaze/result.h"
#include "gaze/source.h"

namespace wrsfov::gaze::hid {

/// One HID top-level collection as hidapi lists it.
struct DeviceInfo {
    std::string path;  ///< e.g. /dev/hidraw3
    uint16_t vendor_id = 0, product_id = 0;
    uint16_t usage_page = 0, usage = 0;
    int interface_number = -1;
    std::string manufacturer, product, serial;
    bool is_eye_tracker() const { return usage_page == eye::kPage && usage == eye::kEyeTracker; }
};

/// All HID devices (hid_enumerate). An empty list is not an error.
Result<std::vector<DeviceInfo>> enumerate_devices();

/// The report descriptor of a hidraw node, from sysfs
/// (/sys/class/hidraw/hidrawN/device/report_descriptor): hidapi 0.13 cannot fetch it.
Result<std::vector<uint8_t>> read_sysfs_descriptor(const std::string& hidraw_path);

/// An open device. Implementations never block.
class Connection {
public:
    virtual ~Connection() = default;
    virtual Result<std::vector<uint8_t>> descriptor() = 0;
    /// Reads one pending input report into `buf` (with the ID byte if the device uses IDs).
    /// Returns its length, 0 when nothing is pending, < 0 when the device is gone.
    virtual int read(std::span<uint8_t> buf) = 0;
    /// Reads feature report `id` (`length` bytes including the ID byte).
    virtual Result<std::vector<uint8_t>> get_feature(uint8_t id, size_t length) = 0;
};

/// Opens a particular device, again after it was lost.
class Connector {
public:
    virtual ~Connector() = default;
    virtual Result<std::unique_ptr<Connection>> open() = 0;
    virtual std::string name() const = 0;
};

/// Connector for a hidraw path through hidapi.
std::unique_ptr<Connector> hidapi_connector(std::string path);

/// Resolves a device argument: a path (/dev/hidraw3), an index into `enumerate_devices()`, or
/// VID:PID in hex (the first eye-tracker collection of that device).
Result<std::string> resolve_device(const std::string& id);

struct HidSourceOptions {
    DropoutPolicy policy;
    ViewerDefaults viewer;
    std::optional<ScreenSize> screen;   ///< overrides the Calibrated Screen Width/Height feature
    double silence_s = 1.0;             ///< no report for this long: close and reopen
    double backoff_min_s = 0.25;        ///< first reopen delay, doubled per failure...
    double backoff_max_s = 4.0;         ///< ...up to this
    size_t max_reports_per_poll = 512;  ///< bounds the work of one poll
    double buffer_s = 2.0;              ///< samples kept for interpolation
};

/// Gaze from a HID eye tracker. Polling reads whatever reports are pending, never waits.
/// Samples carry the source's clock (seconds; `steady_seconds()` unless a clock is given): device
/// timestamps are mapped onto it with the smallest observed transport delay.
class HidTrackerSource final : public GazeSource {
public:
    using Clock = std::function<double()>;

    explicit HidTrackerSource(std::unique_ptr<Connector> connector, HidSourceOptions options = {},
                              Clock clock = steady_seconds);

    GazeSample sample(double t_s) override;

    /// Reads pending reports, reopening the device when it is due.
    void poll();
    /// Samples decoded since the last call (for recording).
    std::vector<GazeSample> take_new_samples();

    bool connected() const { return connection_ != nullptr; }
    /// The last problem (open failure, decode error, silence), empty if none.
    const std::string& last_error() const { return last_error_; }
    int open_attempts() const { return open_attempts_; }
    size_t decode_errors() const { return decode_errors_; }
    double next_retry_s() const { return next_retry_; }
    const std::optional<ScreenSize>& screen() const { return screen_; }

    static double steady_seconds();

private:
    void try_open(double now);
    void lose(double now, std::string why);
    void handle(std::span<const uint8_t> report, double now);

    std::unique_ptr<Connector> connector_;
    HidSourceOptions options_;
    Clock clock_;
    std::unique_ptr<Connection> connection_;
    ReportDescriptor descriptor_;
    EyeTrackerLayout layout_;
    std::optional<ScreenSize> screen_;
    std::vector<GazeSample> buffer_, fresh_;
    std::string last_error_;
    double next_retry_ = 0, backoff_ = 0, last_report_ = 0;
    std::optional<double> clock_offset_;
    int open_attempts_ = 0;
    size_t decode_errors_ = 0;
};

}  // namespace wrsfov::gaze::hid
