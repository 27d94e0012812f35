// The Pixel Data element of a DICOM file, found by its tag and checked for its length.
//
// This work is based on DICOM PS3.5 data element encoding (explicit / implicit VR, Pixel Data
// (7FE0,0010)). Every read is bounds-checked against the byte range given; the fuzz target
// relies on it.
#include "dicom_pixel_data.h"

#include <cctype>
#include <cstring>

#include "sample_conversion.h"

namespace snert::detail {

PixelDataCheck check_dicom_pixel_data(const std::uint8_t* bytes, std::size_t size,
                                      std::uint64_t expected, bool big_endian) {
    PixelDataCheck result;
    if (expected == 0 || size < 8) return result;
    const std::uint8_t tag_le[4] = {0xE0, 0x7F, 0x10, 0x00};
    const std::uint8_t tag_be[4] = {0x7F, 0xE0, 0x00, 0x10};
    const std::uint8_t* tag = big_endian ? tag_be : tag_le;
    const bool swap = big_endian != (native_endian() == Endian::Big);
    const auto length_fits = [&](std::uint32_t length) {
        return length == expected || (expected % 2 == 1 && length == expected + 1);
    };
    // The Pixel Data element is the last top-level element, so the last match wins.
    for (std::size_t pos = 0; pos + 8 <= size; ++pos) {
        if (std::memcmp(bytes + pos, tag, 4) != 0) continue;
        std::uint64_t value_offset = 0;
        std::uint32_t length = 0;
        const bool vr_letters = std::isupper(bytes[pos + 4]) && std::isupper(bytes[pos + 5]) &&
                                bytes[pos + 6] == 0 && bytes[pos + 7] == 0;
        if (vr_letters && pos + 12 <= size &&
            length_fits(length = read_at<std::uint32_t>(bytes, pos + 8, swap))) {
            value_offset = pos + 12;
        } else if (length_fits(length = read_at<std::uint32_t>(bytes, pos + 4, swap))) {
            value_offset = pos + 8;
        } else {
            continue;
        }
        result.value_offset = value_offset;
        result.length = length;
        result.available = size - value_offset;
        result.state =
            result.available >= expected ? PixelDataCheck::Complete : PixelDataCheck::Truncated;
    }
    return result;
}

} // namespace snert::detail
