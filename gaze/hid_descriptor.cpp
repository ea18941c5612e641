#include "gaze/hid_descriptor.h"

#include <algorithm>
#include <cstdio>
#include <map>
#include <utility>

namespace wrsfov::gaze::hid {

namespace {

std::string hex(uint32_t v, int digits) {
    char b[16];
    std::snprintf(b, sizeof b, "0x%0*X", digits, v);
    return b;
}

int64_t sign_extend(uint64_t v, unsigned bits) {
    if (bits == 0 || bits >= 64) return static_cast<int64_t>(v);
    const uint64_t m = uint64_t{1} << (bits - 1);
    v &= (uint64_t{1} << bits) - 1;
    return static_cast<int64_t>((v ^ m) - m);
}

struct Globals {
    uint16_t usage_page = 0;
    int64_t logical_min = 0, logical_max = 0;
    unsigned logical_max_bits = 0;
    int64_t physical_min = 0, physical_max = 0;
    unsigned physical_max_bits = 0;
    uint32_t unit = 0;
    int unit_exponent = 0;
    uint32_t report_size = 0;
    uint32_t report_count = 0;
    uint8_t report_id = 0;
};

struct Locals {
    std::vector<UsageRange> usages;
    bool have_min = false;
    uint32_t min = 0;
    void clear() { *this = Locals{}; }
};

constexpr size_t kMaxGlobalStack = 16;
constexpr size_t kMaxCollectionDepth = 32;
constexpr size_t kMaxFields = 4096;
constexpr size_t kMaxUsagesPerItem = 4096;

}  // namespace

std::string_view report_type_name(ReportType t) {
    switch (t) {
        case ReportType::Input:
            return "input";
        case ReportType::Output:
            return "output";
        case ReportType::Feature:
            return "feature";
    }
    return "?";
}

std::string usage_page_name(uint16_t page) {
    switch (page) {
        case 0x01:
            return "Generic Desktop";
        case 0x07:
            return "Keyboard/Keypad";
        case 0x08:
            return "LED";
        case 0x09:
            return "Button";
        case 0x0C:
            return "Consumer";
        case 0x0D:
            return "Digitizers";
        case 0x12:
            return "Eye and Head Trackers";
        case 0x20:
            return "Sensors";
        default:
            return "page " + hex(page, 4);
    }
}

std::string usage_name(uint32_t usage) {
    const uint16_t page = usage_page(usage), id = usage_id(usage);
    if (page == eye::kPage) {
        static const std::pair<uint16_t, const char*> names[] = {
            {eye::kEyeTracker, "Eye Tracker"},
            {eye::kHeadTracker, "Head Tracker"},
            {eye::kTrackingData, "Tracking Data"},
            {eye::kCapabilities, "Capabilities"},
            {eye::kConfiguration, "Configuration"},
            {eye::kStatus, "Status"},
            {eye::kControl, "Control"},
            {eye::kSensorTimestamp, "Sensor Timestamp"},
            {eye::kPositionX, "Position X"},
            {eye::kPositionY, "Position Y"},
            {eye::kPositionZ, "Position Z"},
            {eye::kGazePoint, "Gaze Point"},
            {eye::kLeftEyePosition, "Left Eye Position"},
            {eye::kRightEyePosition, "Right Eye Position"},
            {eye::kHeadPosition, "Head Position"},
            {eye::kHeadDirectionPoint, "Head Direction Point"},
            {eye::kRotationX, "Rotation X"},
            {eye::kRotationY, "Rotation Y"},
            {eye::kRotationZ, "Rotation Z"},
            {eye::kTrackerQuality, "Tracker Quality"},
            {eye::kMinimumTrackingDistance, "Minimum Tracking Distance"},
            {eye::kOptimumTrackingDistance, "Optimum Tracking Distance"},
            {eye::kMaximumTrackingDistance, "Maximum Tracking Distance"},
            {eye::kMaximumScreenPlaneWidth, "Maximum Screen Plane Width"},
            {eye::kMaximumScreenPlaneHeight, "Maximum Screen Plane Height"},
            {eye::kDisplayManufacturerId, "Display Manufacturer ID"},
            {eye::kDisplayProductId, "Display Product ID"},
            {eye::kDisplaySerialNumber, "Display Serial Number"},
            {eye::kDisplayManufacturerDate, "Display Manufacturer Date"},
            {eye::kCalibratedScreenWidth, "Calibrated Screen Width"},
            {eye::kCalibratedScreenHeight, "Calibrated Screen Height"},
            {eye::kSamplingFrequency, "Sampling Frequency"},
            {eye::kConfigurationStatus, "Configuration Status"},
            {eye::kDeviceModeRequest, "Device Mode Request"},
        };
        for (const auto& [u, n] : names)
            if (u == id) return usage_page_name(page) + ": " + n;
    }
    if (page == 0x01) {
        static const std::pair<uint16_t, const char*> names[] = {
            {0x01, "Pointer"}, {0x02, "Mouse"}, {0x04, "Joystick"}, {0x05, "Game Pad"}, {0x06, "Keyboard"},
            {0x30, "X"},       {0x31, "Y"},     {0x32, "Z"},        {0x38, "Wheel"},
        };
        for (const auto& [u, n] : names)
            if (u == id) return usage_page_name(page) + ": " + n;
    }
    return usage_page_name(page) + ": " + hex(id, 4);
}

std::string unit_name(uint32_t unit) {
    if (unit == 0) return "none";
    static const char* systems[] = {"none", "SI linear", "SI rotation", "English linear", "English rotation"};
    static const char* dims[2][6] = {{"cm", "g", "s", "K", "A", "cd"}, {"in", "slug", "s", "F", "A", "cd"}};
    const unsigned sys = unit & 0xF;
    std::string out = sys < 5 ? systems[sys] : "vendor system " + std::to_string(sys);
    out += ":";
    const bool english = sys == 3 || sys == 4;
    for (int i = 0; i < 6; ++i) {
        const int e = static_cast<int>(sign_extend((unit >> (4 * (i + 1))) & 0xF, 4));
        if (e == 0) continue;
        const char* d = (i == 0 && (sys == 2 || sys == 4)) ? "rad" : dims[english ? 1 : 0][i];
        if (i == 0 && sys == 4) d = "deg";
        out += " ";
        out += d;
        if (e != 1) out += "^" + std::to_string(e);
    }
    return out;
}

uint64_t Field::usage_count() const {
    uint64_t n = 0;
    for (const UsageRange& r : usages) n += uint64_t{r.max} - r.min + 1;
    return n;
}

uint32_t Field::usage_at(uint32_t i) const {
    if (usages.empty()) return 0;
    uint64_t k = i;
    for (const UsageRange& r : usages) {
        const uint64_t n = uint64_t{r.max} - r.min + 1;
        if (k < n) return static_cast<uint32_t>(r.min + k);
        k -= n;
    }
    return is_variable() ? usages.back().max : 0;
}

size_t ReportDescriptor::payload_bytes(ReportType type, uint8_t id) const {
    uint64_t bits = 0;
    bool found = false;
    for (const Field& f : fields) {
        if (f.type != type || f.report_id != id) continue;
        found = true;
        bits = std::max<uint64_t>(bits, f.bit_offset + uint64_t{f.bit_size} * f.count);
    }
    return found ? static_cast<size_t>((bits + 7) / 8) : 0;
}

size_t ReportDescriptor::report_bytes(ReportType type, uint8_t id) const {
    const size_t p = payload_bytes(type, id);
    return p == 0 ? 0 : p + (uses_report_ids ? 1 : 0);
}

std::vector<uint8_t> ReportDescriptor::report_ids(ReportType type) const {
    std::vector<uint8_t> ids;
    for (const Field& f : fields)
        if (f.type == type && std::find(ids.begin(), ids.end(), f.report_id) == ids.end()) ids.push_back(f.report_id);
    std::sort(ids.begin(), ids.end());
    return ids;
}

std::vector<uint32_t> ReportDescriptor::collection_path(const Field& f) const {
    std::vector<uint32_t> path;
    for (int c = f.collection; c >= 0 && c < static_cast<int>(collections.size()) && path.size() <= kMaxCollectionDepth;
         c = collections[static_cast<size_t>(c)].parent)
        path.push_back(collections[static_cast<size_t>(c)].usage);
    return path;
}

Result<ReportDescriptor> parse_descriptor(std::span<const uint8_t> bytes) {
    if (bytes.empty()) return fail("report descriptor is empty");
    if (bytes.size() > kMaxDescriptorBytes)
        return fail("report descriptor is " + std::to_string(bytes.size()) + " bytes, more than the " +
                    std::to_string(kMaxDescriptorBytes) + " a HID device may have");
    ReportDescriptor d;
    Globals g;
    std::vector<Globals> stack;
    Locals l;
    std::vector<int> open;  // collection stack
    std::map<std::pair<ReportType, uint8_t>, uint64_t> offsets;
    bool saw_field_without_id = false;

    size_t pos = 0;
    while (pos < bytes.size()) {
        const size_t at = pos;
        auto err = [&](const std::string& m) { return Error{"byte " + std::to_string(at) + ": " + m}; };
        const uint8_t prefix = bytes[pos++];
        if (prefix == 0xFE) {  // long item: size, tag, data; no long items are defined
            if (pos + 2 > bytes.size()) return err("truncated long item");
            const size_t n = bytes[pos];
            pos += 2;
            if (pos + n > bytes.size()) return err("long item data runs past the end");
            pos += n;
            continue;
        }
        static constexpr unsigned kSizes[4] = {0, 1, 2, 4};
        const unsigned size = kSizes[prefix & 3];
        const unsigned type = (prefix >> 2) & 3, tag = prefix >> 4;
        if (pos + size > bytes.size())
            return err("item " + hex(prefix, 2) + " needs " + std::to_string(size) + " data bytes, only " +
                       std::to_string(bytes.size() - pos) + " left (truncated descriptor)");
        uint32_t u = 0;
        for (unsigned i = 0; i < size; ++i) u |= uint32_t{bytes[pos + i]} << (8 * i);
        pos += size;
        const int64_t s = sign_extend(u, 8 * size);

        if (type == 0) {  // main
            if (tag == 0x8 || tag == 0x9 || tag == 0xB) {
                const ReportType rt = tag == 0x8   ? ReportType::Input
                                      : tag == 0x9 ? ReportType::Output
                                                   : ReportType::Feature;
                if (g.report_count > 0) {
                    if (g.report_size == 0)
                        return err("main item with Report Count " + std::to_string(g.report_count) +
                                   " but Report Size 0");
                    if (d.uses_report_ids && saw_field_without_id)
                        return err("descriptor mixes reports with and without Report IDs");
                    if (g.report_id == 0) saw_field_without_id = true;
                    if (d.fields.size() >= kMaxFields)
                        return err("more than " + std::to_string(kMaxFields) + " fields");
                    uint64_t& off = offsets[{rt, g.report_id}];
                    const uint64_t bits = uint64_t{g.report_size} * g.report_count;
                    if (off + bits > uint64_t{kMaxReportBytes} * 8)
                        return err(std::string(report_type_name(rt)) + " report " + std::to_string(g.report_id) +
                                   " grows beyond " + std::to_string(kMaxReportBytes) + " bytes");
                    Field f;
                    f.type = rt;
                    f.report_id = g.report_id;
                    f.bit_offset = static_cast<uint32_t>(off);
                    f.bit_size = g.report_size;
                    f.count = g.report_count;
                    f.flags = u;
                    f.usages = std::move(l.usages);
                    f.logical_min = g.logical_min;
                    f.logical_max = g.logical_max;
                    // Common quirk: Logical Minimum 0, Logical Maximum 0xFF in one byte means 255.
                    if (f.logical_min >= 0 && f.logical_max < 0 && g.logical_max_bits > 0)
                        f.logical_max = static_cast<int64_t>(static_cast<uint64_t>(f.logical_max) &
                                                             ((uint64_t{1} << g.logical_max_bits) - 1));
                    f.physical_min = g.physical_min;
                    f.physical_max = g.physical_max;
                    if (f.physical_min >= 0 && f.physical_max < 0 && g.physical_max_bits > 0)
                        f.physical_max = static_cast<int64_t>(static_cast<uint64_t>(f.physical_max) &
                                                              ((uint64_t{1} << g.physical_max_bits) - 1));
                    f.unit = g.unit;
                    f.unit_exponent = g.unit_exponent;
                    f.collection = open.empty() ? -1 : open.back();
                    d.fields.push_back(std::move(f));
                    off += bits;
                }
            } else if (tag == 0xA) {
                if (open.size() >= kMaxCollectionDepth) return err("collections nested deeper than 32");
                Collection c;
                c.kind = static_cast<uint8_t>(u & 0xFF);
                c.usage = l.usages.empty() ? 0 : l.usages.front().min;
                c.parent = open.empty() ? -1 : open.back();
                d.collections.push_back(c);
                open.push_back(static_cast<int>(d.collections.size() - 1));
            } else if (tag == 0xC) {
                if (open.empty()) return err("End Collection without an open collection");
                open.pop_back();
            } else {
                return err("reserved main item tag " + hex(tag, 1));
            }
            l.clear();
        } else if (type == 1) {  // global
            switch (tag) {
                case 0x0:
                    g.usage_page = static_cast<uint16_t>(u);
                    break;
                case 0x1:
                    g.logical_min = s;
                    break;
                case 0x2:
                    g.logical_max = s;
                    g.logical_max_bits = 8 * size;
                    break;
                case 0x3:
                    g.physical_min = s;
                    break;
                case 0x4:
                    g.physical_max = s;
                    g.physical_max_bits = 8 * size;
                    break;
                // HID 1.11 codes the exponent in 4 bits; many devices write a signed byte instead.
                case 0x5:
                    g.unit_exponent = u < 16 ? static_cast<int>(sign_extend(u, 4)) : static_cast<int>(s);
                    break;
                case 0x6:
                    g.unit = u;
                    break;
                case 0x7:
                    if (u > 1024) return err("Report Size " + std::to_string(u) + " bits is unreasonably large");
                    g.report_size = u;
                    break;
                case 0x8:
                    if (u == 0 || u > 255) return err("Report ID " + std::to_string(u) + " is out of range 1..255");
                    if (saw_field_without_id) return err("descriptor mixes reports with and without Report IDs");
                    g.report_id = static_cast<uint8_t>(u);
                    d.uses_report_ids = true;
                    break;
                case 0x9:
                    if (u > 65535) return err("Report Count " + std::to_string(u) + " is unreasonably large");
                    g.report_count = u;
                    break;
                case 0xA:
                    if (stack.size() >= kMaxGlobalStack) return err("Push nested deeper than 16");
                    stack.push_back(g);
                    break;
                case 0xB:
                    if (stack.empty()) return err("Pop without Push");
                    g = stack.back();
                    stack.pop_back();
                    break;
                default:
                    return err("reserved global item tag " + hex(tag, 1));
            }
        } else if (type == 2) {  // local
            auto full = [&](uint32_t v) { return size == 4 ? v : make_usage(g.usage_page, static_cast<uint16_t>(v)); };
            switch (tag) {
                case 0x0:
                    if (l.usages.size() >= kMaxUsagesPerItem) return err("too many usages for one item");
                    l.usages.push_back({full(u), full(u)});
                    break;
                case 0x1:
                    l.have_min = true;
                    l.min = full(u);
                    break;
                case 0x2: {
                    if (!l.have_min) return err("Usage Maximum without Usage Minimum");
                    const uint32_t mx = full(u);
                    if (mx < l.min || usage_page(mx) != usage_page(l.min))
                        return err("Usage Minimum " + hex(l.min, 8) + " / Maximum " + hex(mx, 8) + " is not a range");
                    if (l.usages.size() >= kMaxUsagesPerItem) return err("too many usages for one item");
                    l.usages.push_back({l.min, mx});
                    l.have_min = false;
                    break;
                }
                case 0x3:
                case 0x4:
                case 0x5:
                case 0x7:
                case 0x8:
                case 0x9:
                case 0xA:
                    break;  // designators, strings and delimiters carry nothing we decode
                default:
                    return err("reserved local item tag " + hex(tag, 1));
            }
        } else {
            return err("reserved item type 3 (prefix " + hex(prefix, 2) + ")");
        }
    }
    if (!open.empty())
        return fail("report descriptor ends with " + std::to_string(open.size()) + " collection(s) not closed");
    if (d.fields.empty()) return fail("report descriptor declares no report fields");
    return d;
}

Result<ReportView> view_report(const ReportDescriptor& d, ReportType type, std::span<const uint8_t> bytes) {
    if (bytes.empty()) return fail(std::string(report_type_name(type)) + " report is empty");
    if (bytes.size() > kMaxReportBytes)
        return fail("report of " + std::to_string(bytes.size()) + " bytes is too large");
    ReportView v;
    if (d.uses_report_ids) {
        v.id = bytes[0];
        bytes = bytes.subspan(1);
    }
    const size_t want = d.payload_bytes(type, v.id);
    if (want == 0) {
        if (d.uses_report_ids)
            return fail(std::string(report_type_name(type)) + " report ID " + std::to_string(v.id) +
                        " is not in the descriptor");
        return fail(std::string("the descriptor has no ") + std::string(report_type_name(type)) + " report");
    }
    const size_t id_byte = d.uses_report_ids ? 1 : 0;
    if (bytes.size() != want)
        return fail(std::string(report_type_name(type)) + " report " + std::to_string(v.id) + " is " +
                    std::to_string(bytes.size() + id_byte) + " bytes, the descriptor says " +
                    std::to_string(want + id_byte) + (bytes.size() < want ? " (truncated)" : " (oversized)"));
    v.payload = bytes;
    return v;
}

Result<int64_t> read_raw(const Field& f, uint32_t index, std::span<const uint8_t> payload) {
    if (index >= f.count)
        return fail("element " + std::to_string(index) + " is past the field's " + std::to_string(f.count));
    if (f.bit_size > 64) return fail("a " + std::to_string(f.bit_size) + "-bit field cannot be read as one number");
    const uint64_t start = f.bit_offset + uint64_t{index} * f.bit_size;
    if (start + f.bit_size > uint64_t{payload.size()} * 8) return fail("field lies past the end of the report");
    uint64_t v = 0;
    for (uint32_t b = 0; b < f.bit_size; ++b) {
        const uint64_t bit = start + b;
        if ((payload[bit / 8] >> (bit % 8)) & 1u) v |= uint64_t{1} << b;
    }
    return f.is_signed() ? sign_extend(v, f.bit_size) : static_cast<int64_t>(v);
}

double to_physical(const Field& f, int64_t raw) {
    const bool no_physical = f.physical_min == 0 && f.physical_max == 0;
    if (no_physical || f.logical_max == f.logical_min) {
        // A 64-bit unsigned counter above INT64_MAX stays positive.
        if (!f.is_signed() && f.bit_size == 64 && raw < 0) return static_cast<double>(static_cast<uint64_t>(raw));
        return static_cast<double>(raw);
    }
    return (static_cast<double>(raw) - static_cast<double>(f.logical_min)) *
               (static_cast<double>(f.physical_max) - static_cast<double>(f.physical_min)) /
               (static_cast<double>(f.logical_max) - static_cast<double>(f.logical_min)) +
           static_cast<double>(f.physical_min);
}

}  // namespace wrsfov::gaze::hid
