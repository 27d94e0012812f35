// DICOM: a folder's series, read through GDCM in a child process.
//
// Debian's GDCM 3.0 keeps its assert()s: a truncated .dcm can abort the process inside the
// folder scan or the read. DICOM is therefore scanned and read in a forked child that streams
// slices back through a pipe; a crash there becomes an error here. No ITK type appears in this
// header (dicom_series.cpp is one of the sources that include ITK).
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "load_volume.h"

namespace snert {

// The DICOM series in a folder, largest first. The folder is scanned in a child process, so a
// damaged file cannot take the caller down. Throws std::invalid_argument when `folder` is not
// a folder, std::runtime_error when the scan fails; an empty list means no DICOM.
// A series whose files differ in orientation or size is split by GDCM into parts that share
// one uid; LoadOptions::dicom_series_uid then picks the largest part.
struct DicomSeries {
    std::string uid; // SeriesInstanceUID (0020,000E): what LoadOptions takes
    std::size_t files = 0;
    std::string description; // SeriesDescription (0008,103E), may be empty
};
std::vector<DicomSeries> list_dicom_series(const std::string& folder);

namespace detail {

// Whether `path` is a DICOM file: extension .dcm, .ima or .dicom, or "DICM" at byte 128.
bool is_dicom_file(const std::string& path);

// Reads a DICOM series (see load_volume.h): the one options.dicom_series_uid names, else the
// largest in `folder`; or, from a file, the series of that file in its folder. Slices are
// sorted by position along the slice normal; a series whose slices are not evenly spaced, or a
// slice whose Pixel Data is cut short (dicom_pixel_data.h), is refused. Throws
// std::invalid_argument for a series UID that is not there, std::runtime_error otherwise.
LoadedVolume open_dicom_folder(const std::string& folder, const LoadOptions& options);
LoadedVolume open_dicom_file(const std::string& file, const LoadOptions& options);

} // namespace detail
} // namespace snert
