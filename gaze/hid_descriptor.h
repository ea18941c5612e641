// A general HID report-descriptor parser and report field extraction (HID 1.11, section 6.2.2).
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "gaze/result.h"

namespace wrsfov::gaze::hid {

/// Descriptors larger than this are refused (Linux's HID_MAX_DESCRIPTOR_SIZE).
inline constexpr size_t kMaxDescriptorBytes = 4096;
/// Reports larger than this are refused (hidraw's buffer).
inline constexpr size_t kMaxReportBytes = 4096;

enum class ReportType : uint8_t { Input, Output, Feature };
std::string_view report_type_name(ReportType t);

/// A 32-bit usage: page in the high 16 bits, id in the low 16 bits.
constexpr uint32_t make_usage(uint16_t page, uint16_t id) { return (uint32_t{page} << 16) | id; }
constexpr uint16_t usage_page(uint32_t usage) { return static_cast<uint16_t>(usage >> 16); }
constexpr uint16_t usage_id(uint32_t usage) { return static_cast<uint16_t>(usage & 0xFFFF); }

/// Usage page 0x12, "Eye and Head Trackers" (HUT).
namespace eye {
inline constexpr uint16_t kPage = 0x12;
inline constexpr uint16_t kEyeTracker = 0x01, kHeadTracker = 0x02;
inline constexpr uint16_t kTrackingData = 0x10, kCapabilities = 0x11, kConfiguration = 0x12, kStatus = 0x13,
                          kControl = 0x14;
inline constexpr uint16_t kSensorTimestamp = 0x20, kPositionX = 0x21, kPositionY = 0x22, kPositionZ = 0x23,
                          kGazePoint = 0x24, kLeftEyePosition = 0x25, kRightEyePosition = 0x26, kHeadPosition = 0x27,
                          kHeadDirectionPoint = 0x28, kRotationX = 0x29, kRotationY = 0x2A, kRotationZ = 0x2B;
inline constexpr uint16_t kTrackerQuality = 0x100, kMinimumTrackingDistance = 0x101, kOptimumTrackingDistance = 0x102,
                          kMaximumTrackingDistance = 0x103, kMaximumScreenPlaneWidth = 0x104,
                          kMaximumScreenPlaneHeight = 0x105;
inline constexpr uint16_t kDisplayManufacturerId = 0x200, kDisplayProductId = 0x201, kDisplaySerialNumber = 0x202,
                          kDisplayManufacturerDate = 0x203, kCalibratedScreenWidth = 0x204,
                          kCalibratedScreenHeight = 0x205;
inline constexpr uint16_t kSamplingFrequency = 0x300, kConfigurationStatus = 0x301, kDeviceModeRequest = 0x400;
}  // namespace eye

/// Human-readable usage ("Eye and Head Trackers: Gaze Point", "page 0xFF00: 0x0001").
std::string usage_name(uint32_t usage);
std::string usage_page_name(uint16_t page);

/// An inclusive usage range; a single usage has min == max.
struct UsageRange {
    uint32_t min = 0, max = 0;
};

/// A collection (Physical 0, Application 1, Logical 2, ...).
struct Collection {
    uint8_t kind = 0;
    uint32_t usage = 0;
    int parent = -1;
};

/// One main item: `count` elements of `bit_size` bits at `bit_offset` in the report payload
/// (the bytes after the report ID, if the descriptor uses IDs).
struct Field {
    ReportType type = ReportType::Input;
    uint8_t report_id = 0;
    uint32_t bit_offset = 0;
    uint32_t bit_size = 0;
    uint32_t count = 0;
    uint32_t flags = 0;  ///< main item data: bit 0 constant, bit 1 variable, bit 2 relative, ...
    std::vector<UsageRange> usages;
    int64_t logical_min = 0, logical_max = 0;
    int64_t physical_min = 0, physical_max = 0;
    uint32_t unit = 0;
    int unit_exponent = 0;
    int collection = -1;  ///< innermost enclosing collection, index into `ReportDescriptor::collections`

    bool is_constant() const { return flags & 1u; }
    bool is_variable() const { return flags & 2u; }
    bool is_relative() const { return flags & 4u; }
    bool is_signed() const { return logical_min < 0; }
    /// Usage of element `i` of a variable field (the last usage repeats, HID 1.11 6.2.2.8);
    /// for an array field the i-th usage of its list. 0 when there is none.
    uint32_t usage_at(uint32_t i) const;
    /// Number of usages listed.
    uint64_t usage_count() const;
};

/// A parsed descriptor.
struct ReportDescriptor {
    std::vector<Collection> collections;
    std::vector<Field> fields;
    bool uses_report_ids = false;

    /// Payload bytes of a report (without the ID byte); 0 if the report does not exist.
    size_t payload_bytes(ReportType type, uint8_t id) const;
    /// Bytes as read from hidraw: payload plus the ID byte if IDs are used.
    size_t report_bytes(ReportType type, uint8_t id) const;
    /// The report IDs of a type in ascending order (just 0 without IDs).
    std::vector<uint8_t> report_ids(ReportType type) const;
    /// Collection usages from the innermost outward for a field.
    std::vector<uint32_t> collection_path(const Field& f) const;
};

/// Parses a report descriptor. Errors name the byte offset and what is wrong.
Result<ReportDescriptor> parse_descriptor(std::span<const uint8_t> bytes);

/// A report split into its ID and payload after checking it against the descriptor.
struct ReportView {
    uint8_t id = 0;
    std::span<const uint8_t> payload;
};

/// Checks a report's ID and length (exactly the descriptor's size).
Result<ReportView> view_report(const ReportDescriptor& d, ReportType type, std::span<const uint8_t> bytes);

/// Raw value of element `index` of a field (sign-extended when the logical minimum is negative).
/// Fields wider than 64 bits cannot be read as one number.
Result<int64_t> read_raw(const Field& f, uint32_t index, std::span<const uint8_t> payload);

/// Logical -> physical mapping (HID 1.11 6.2.2.7), without the unit exponent. Identity when the
/// physical range is unset or the logical range is empty.
double to_physical(const Field& f, int64_t raw);

/// "SI linear: cm^1", "none", ... and the exponent.
std::string unit_name(uint32_t unit);

}  // namespace wrsfov::gaze::hid
