// libFuzzer target: HID report-descriptor parser and eye-tracker report decoding.
//
// Input: two bytes of descriptor length (little-endian, taken modulo the input size), the
// descriptor, then report bytes. Any input must end in a result or an error, never a crash,
// a hang or undefined behaviour.
#include <cstddef>
#include <cstdint>
#include <span>

#include "gaze/hid_descriptor.h"
#include "gaze/hid_eyetracker.h"

namespace hid = wrsfov::gaze::hid;

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    if (size < 2) return 0;
    const size_t rest = size - 2;
    const size_t dlen = rest == 0 ? 0 : (size_t{data[0]} | size_t{data[1]} << 8) % (rest + 1);
    const std::span<const uint8_t> desc(data + 2, dlen);
    const std::span<const uint8_t> report(data + 2 + dlen, rest - dlen);

    auto d = hid::parse_descriptor(desc);
    if (!d) return 0;
    for (const hid::Field& f : d->fields) {
        (void)hid::usage_name(f.usage_at(0));
        (void)hid::unit_name(f.unit);
        for (uint32_t i = 0; i < f.count && i < 64; ++i) {
            auto raw = hid::read_raw(f, i, report);
            if (raw) (void)hid::to_physical(f, *raw);
        }
    }
    for (hid::ReportType t : {hid::ReportType::Input, hid::ReportType::Feature}) (void)hid::view_report(*d, t, report);
    auto layout = hid::find_eye_tracker(*d);
    if (!layout) return 0;
    auto t = hid::decode_tracking(*d, *layout, report);
    if (t) (void)hid::eyes_from_gaze_point(*t, {600000, 340000});
    (void)hid::decode_screen(*d, *layout, report);
    return 0;
}
