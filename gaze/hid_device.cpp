#include "gaze/hid_device.h"

#include <hidapi/hidapi.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cwchar>
#include <fstream>
#include <iterator>

namespace wrsfov::gaze::hid {

namespace {

std::string narrow(const wchar_t* w) {
    std::string out;
    if (!w) return out;
    for (; *w; ++w) out += (*w >= 0x20 && *w < 0x7F) ? static_cast<char>(*w) : '?';
    return out;
}

Status init_hidapi() {
    static const int rc = hid_init();
    if (rc != 0) return fail("hidapi could not be initialised (hid_init failed)");
    return Ok{};
}

class HidapiConnection final : public Connection {
public:
    HidapiConnection(hid_device* dev, std::string path) : dev_(dev), path_(std::move(path)) {}
    ~HidapiConnection() override { hid_close(dev_); }

    Result<std::vector<uint8_t>> descriptor() override { return read_sysfs_descriptor(path_); }

    int read(std::span<uint8_t> buf) override {
        const int n = hid_read_timeout(dev_, buf.data(), buf.size(), 0);
        return n;
    }

    Result<std::vector<uint8_t>> get_feature(uint8_t id, size_t length) override {
        std::vector<uint8_t> buf(std::max<size_t>(length, 2), 0);
        buf[0] = id;
        const int n = hid_get_feature_report(dev_, buf.data(), buf.size());
        if (n < 0) return fail("reading feature report " + std::to_string(id) + " from " + path_ + " failed");
        buf.resize(static_cast<size_t>(n));
        return buf;
    }

private:
    hid_device* dev_;
    std::string path_;
};

class HidapiConnector final : public Connector {
public:
    explicit HidapiConnector(std::string path) : path_(std::move(path)) {}
    Result<std::unique_ptr<Connection>> open() override {
        if (Status s = init_hidapi(); !s) return s.error();
        hid_device* dev = hid_open_path(path_.c_str());
        if (!dev)
            return fail("cannot open " + path_ +
                        " (unplugged, or no permission: add a udev rule giving your user "
                        "access to the hidraw node)");
        if (hid_set_nonblocking(dev, 1) != 0) {
            hid_close(dev);
            return fail("cannot make " + path_ + " non-blocking");
        }
        return std::unique_ptr<Connection>(std::make_unique<HidapiConnection>(dev, path_));
    }
    std::string name() const override { return path_; }

private:
    std::string path_;
};

}  // namespace

Result<std::vector<DeviceInfo>> enumerate_devices() {
    if (Status s = init_hidapi(); !s) return s.error();
    std::vector<DeviceInfo> out;
    hid_device_info* list = hid_enumerate(0, 0);
    for (hid_device_info* d = list; d; d = d->next) {
        DeviceInfo i;
        i.path = d->path ? d->path : "";
        i.vendor_id = d->vendor_id;
        i.product_id = d->product_id;
        i.usage_page = d->usage_page;
        i.usage = d->usage;
        i.interface_number = d->interface_number;
        i.manufacturer = narrow(d->manufacturer_string);
        i.product = narrow(d->product_string);
        i.serial = narrow(d->serial_number);
        out.push_back(std::move(i));
    }
    hid_free_enumeration(list);
    return out;
}

Result<std::vector<uint8_t>> read_sysfs_descriptor(const std::string& hidraw_path) {
    const size_t slash = hidraw_path.find_last_of('/');
    const std::string node = slash == std::string::npos ? hidraw_path : hidraw_path.substr(slash + 1);
    if (node.rfind("hidraw", 0) != 0)
        return fail("'" + hidraw_path +
                    "' is not a hidraw node (expected /dev/hidrawN): the descriptor is read from sysfs");
    const std::string sys = "/sys/class/hidraw/" + node + "/device/report_descriptor";
    std::ifstream in(sys, std::ios::binary);
    if (!in) return fail("cannot read " + sys + " (device unplugged?)");
    std::vector<uint8_t> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    if (bytes.empty()) return fail(sys + " is empty");
    return bytes;
}

std::unique_ptr<Connector> hidapi_connector(std::string path) {
    return std::make_unique<HidapiConnector>(std::move(path));
}

Result<std::string> resolve_device(const std::string& id) {
    if (id.find('/') != std::string::npos) return id;
    auto devices = enumerate_devices();
    if (!devices) return devices.error();
    const size_t colon = id.find(':');
    if (colon != std::string::npos) {
        unsigned vid = 0, pid = 0;
        if (std::sscanf(id.c_str(), "%x:%x", &vid, &pid) != 2) return fail("device '" + id + "' is not VID:PID in hex");
        for (const DeviceInfo& d : *devices)
            if (d.vendor_id == vid && d.product_id == pid && d.is_eye_tracker()) return d.path;
        return fail("no eye-tracker collection (usage page 0x12) on device " + id + " (see `wrsfov-gaze list`)");
    }
    char* end = nullptr;
    const unsigned long idx = std::strtoul(id.c_str(), &end, 10);
    if (id.empty() || *end != '\0') return fail("device '" + id + "' is neither a path, an index nor VID:PID");
    if (idx >= devices->size())
        return fail("device index " + id + " is out of range (" + std::to_string(devices->size()) +
                    " devices; see `wrsfov-gaze list`)");
    return (*devices)[idx].path;
}

double HidTrackerSource::steady_seconds() {
    return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

HidTrackerSource::HidTrackerSource(std::unique_ptr<Connector> connector, HidSourceOptions options, Clock clock)
    : connector_(std::move(connector)), options_(options), clock_(std::move(clock)) {
    next_retry_ = -1e300;
    backoff_ = options_.backoff_min_s;
}

void HidTrackerSource::lose(double now, std::string why) {
    connection_.reset();
    last_error_ = std::move(why);
    next_retry_ = now + backoff_;
    backoff_ = std::min(backoff_ * 2, options_.backoff_max_s);
    clock_offset_.reset();
}

void HidTrackerSource::try_open(double now) {
    ++open_attempts_;
    auto conn = connector_->open();
    if (!conn) return lose(now, conn.error().message);
    auto bytes = (*conn)->descriptor();
    if (!bytes) return lose(now, bytes.error().message);
    auto desc = parse_descriptor(*bytes);
    if (!desc) return lose(now, connector_->name() + ": report descriptor: " + desc.error().message);
    auto layout = find_eye_tracker(*desc);
    if (!layout) return lose(now, connector_->name() + ": " + layout.error().message);
    std::optional<ScreenSize> screen = options_.screen;
    if (!screen) {
        if (!layout->screen_width.found())
            return lose(now, connector_->name() + ": no Calibrated Screen Width/Height feature; give the screen size");
        const size_t len = desc->report_bytes(ReportType::Feature, layout->screen_report_id);
        auto feat = (*conn)->get_feature(layout->screen_report_id, len);
        if (!feat) return lose(now, feat.error().message);
        auto s = decode_screen(*desc, *layout, *feat);
        if (!s) return lose(now, connector_->name() + ": " + s.error().message);
        screen = *s;
    }
    connection_ = std::move(*conn);
    descriptor_ = std::move(*desc);
    layout_ = *layout;
    screen_ = screen;
    last_report_ = now;  // give a fresh connection the full silence allowance
}

void HidTrackerSource::handle(std::span<const uint8_t> report, double now) {
    if (descriptor_.uses_report_ids && !report.empty() && report[0] != layout_.tracking_report_id) return;
    auto t = decode_tracking(descriptor_, layout_, report);
    if (!t) {
        ++decode_errors_;
        last_error_ = t.error().message;
        return;
    }
    last_report_ = now;
    backoff_ = options_.backoff_min_s;  // data flows again: the next loss starts with a short delay
    double ts = now;
    if (t->timestamp_us) {
        // Device clock -> our clock with the smallest delay seen; a jump (device reset) restarts it.
        const double dev = *t->timestamp_us * 1e-6;
        const double off = now - dev;
        if (!clock_offset_ || off < *clock_offset_ || off - *clock_offset_ > 1.0) clock_offset_ = off;
        ts = dev + *clock_offset_;
    }
    if (!buffer_.empty() && !(ts > buffer_.back().t_s)) ts = std::nextafter(buffer_.back().t_s, 1e300);
    GazeSample s;
    s.t_s = ts;
    const auto eyes = eyes_from_gaze_point(*t, *screen_, options_.viewer);
    s.eye[0] = eyes[0];
    s.eye[1] = eyes[1];
    buffer_.push_back(s);
    if (fresh_.size() < 1'000'000) fresh_.push_back(s);
}

void HidTrackerSource::poll() {
    const double now = clock_();
    if (!connection_) {
        if (now < next_retry_) return;
        try_open(now);
        if (!connection_) return;
    }
    uint8_t buf[kMaxReportBytes + 1];
    for (size_t n = 0; n < options_.max_reports_per_poll; ++n) {
        const int r = connection_->read(buf);
        if (r == 0) break;
        if (r < 0) return lose(now, connector_->name() + ": read failed (device unplugged?)");
        handle(std::span<const uint8_t>(buf, static_cast<size_t>(r)), now);
    }
    if (now - last_report_ > options_.silence_s) {
        char msg[128];
        std::snprintf(msg, sizeof msg, ": no report for %.2f s", now - last_report_);
        return lose(now, connector_->name() + msg);
    }
    const double keep_from = buffer_.empty() ? 0 : buffer_.back().t_s - options_.buffer_s;
    const auto first =
        std::find_if(buffer_.begin(), buffer_.end(), [&](const GazeSample& s) { return s.t_s >= keep_from; });
    buffer_.erase(buffer_.begin(), first);
}

GazeSample HidTrackerSource::sample(double t_s) {
    poll();
    return interpolate_samples(buffer_, t_s, options_.policy);
}

std::vector<GazeSample> HidTrackerSource::take_new_samples() {
    std::vector<GazeSample> out;
    out.swap(fresh_);
    return out;
}

}  // namespace wrsfov::gaze::hid
