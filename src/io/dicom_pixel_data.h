// DICOM Pixel Data (7FE0,0010): is all of it in the file? (No ITK, no GDCM.)
//
// GDCM zero-fills a slice whose pixel data is cut short, silently. The DICOM reader
// (dicom_series.cpp) therefore finds the element in each file before GDCM reads it, and refuses
// a file that holds less than the slice needs. Based on DICOM PS3.5 data element encoding
// (explicit / implicit VR). The search takes a byte range and never reads outside it.
#pragma once

#include <cstddef>
#include <cstdint>

namespace snert::detail {

// Where the Pixel Data element (7FE0,0010) of one file is and whether all of it is there.
struct PixelDataCheck {
    enum State { Complete, Truncated, NotFound } state = NotFound;
    std::uint64_t value_offset = 0; // first pixel byte
    std::uint64_t length = 0;       // declared value length
    std::uint64_t available = 0;    // bytes present after value_offset
};
// Looks for the element with a declared length of `expected` (or expected + 1, even padding),
// explicit or implicit VR, in the byte order given. Encapsulated (compressed) pixel data has
// an undefined length and is reported NotFound.
PixelDataCheck check_dicom_pixel_data(const std::uint8_t* bytes, std::size_t size,
                                      std::uint64_t expected, bool big_endian);

} // namespace snert::detail
