// Reading real volumes: medical image files, DICOM folders and headerless raw data.
//
// Formats (read through ITK's ImageIO, the library 3D Slicer and ITK-SNAP rely on; no ITK type
// appears in this header):
//   NRRD .nrrd/.nhdr, NIfTI .nii/.nii.gz (and Analyze .hdr/.img), MetaImage .mha/.mhd,
//   VTK legacy structured points .vtk, and DICOM: a folder holding a series (the largest one,
//   or the one whose SeriesInstanceUID is given) or one .dcm file of a series.
// Headerless raw data (one file, or a numbered series of slice files) has its own reader,
// raw_volume.h; the DICOM series of a folder are listed by dicom_series.h.
//
// Result, for every format:
//  - samples are float32, x fastest; stored types uint8 .. float64 are converted exactly where
//    float32 can hold the value (every 8/16-bit value, 24-bit magnitudes), rounded otherwise;
//    rescale slope/intercept (NIfTI scl_*, DICOM) is applied;
//  - spacing, origin and direction are kept as the file states them, in ITK's LPS world frame
//    (millimetres; NIfTI's RAS is converted), so index_to_world() places every sample where the
//    scanner put it. Raw data has origin 0 and identity direction;
//  - a scalar volume: files with several components per voxel (RGB, vectors, tensors) and 4-D
//    series with more than one time point are refused.
//
// NaN / infinity policy (float data only; integer types cannot hold them; volume_checks.h):
//  - default (NonFinitePolicy::Replace): every NaN and -inf becomes the smallest finite sample,
//    every +inf the largest finite sample, so they read as background / brightest tissue and
//    no NaN reaches a mesh, a gradient or a metric. The counts are reported in
//    VolumeInfo::nonfinite (the CLI prints a warning). A volume with no finite sample at all
//    is refused.
//  - NonFinitePolicy::Refuse: any non-finite sample makes the load fail (the message says how
//    many NaN and infinite samples there are).
//
// Memory: before any sample is allocated, the header is read and the float32 grid's size
// (plus any temporary the reader needs) is compared with LoadOptions::memory_limit_bytes, or
// with MemAvailable from /proc/meminfo when that is 0; a volume that does not fit is refused
// with both sizes in the message. Absurd dimensions (an axis of 0 or above 2^31 - 1, or a
// sample count that overflows) are refused first. Stored values are read straight into the
// float32 grid and converted in place, so a 512x512x400 int16 CT needs the 400 MiB grid and
// no second full-size copy (NRRD, NIfTI, MetaImage, VTK, raw; DICOM is read slice by slice).
// The checks themselves: sizes.h, and one header per format (nifti.h, nrrd.h, metaimage.h,
// vtk_legacy.h, dicom_pixel_data.h).
//
// DICOM: slices are sorted by position along the slice normal (GDCM); the z spacing comes from
// the positions, and a series whose slices are not evenly spaced (a missing or skipped file) is
// refused rather than silently stretched. Rescale slope / intercept is applied.
//
// Errors: std::runtime_error (bad or unreadable file: truncated data, a header that promises
// more data than the file holds, gzip that is not gzip, a folder without DICOM, a damaged .dcm
// that makes the DICOM library abort, which is contained in a child process) or
// std::invalid_argument (bad options: raw dims or type, a series UID that is not there). Each
// message is one line that starts with the path and says what is wrong.
#pragma once

#include <cstddef>
#include <string>

#include <glm/glm.hpp>

#include "core/progress.h"
#include "core/volume.h"
#include "sample_conversion.h"
#include "volume_checks.h"

namespace snert {

struct LoadOptions {
    std::string dicom_series_uid;       // DICOM folder: this SeriesInstanceUID; empty: largest
    std::size_t memory_limit_bytes = 0; // refuse grids larger than this; 0: MemAvailable
    NonFinitePolicy nonfinite = NonFinitePolicy::Replace;
    Progress progress; // reports per slab / slice; cancels by Cancelled
};

// What the app's open panel and the CLI show about a loaded volume.
struct VolumeInfo {
    std::string path;        // as given
    std::string format;      // "NRRD", "NIfTI", "MetaImage", "VTK", "DICOM", "raw"
    std::string scalar_type; // stored type before conversion, e.g. "int16"
    glm::ivec3 dims{0};
    glm::vec3 spacing{1.0f};
    glm::vec3 origin{0.0f};
    glm::mat3 direction{1.0f}; // columns: world directions of the index axes
    ValueRange range;          // finite samples, after the NaN policy
    std::size_t nonfinite = 0; // samples replaced by the NaN / infinity policy
    std::size_t files = 1;     // files read (DICOM and raw series: one per slice)
    std::string series_uid;    // DICOM: the SeriesInstanceUID read
};

struct LoadedVolume {
    Volume volume;
    VolumeInfo info;
};

// Loads a volume file, a DICOM folder or one .dcm of a series (see the top of this header).
LoadedVolume open_volume(const std::string& path, const LoadOptions& options = {});
Volume load_volume(const std::string& path, const LoadOptions& options = {});

} // namespace snert

// Headerless raw data (RawOptions, open_raw, load_raw) for the callers that take every kind of
// input. Included last: raw_volume.h needs LoadOptions and LoadedVolume from above.
#include "raw_volume.h"
