// Reading real volumes: medical image files, DICOM folders and headerless raw data.
//
// Formats (read through ITK's ImageIO, the library 3D Slicer and ITK-SNAP rely on; no ITK type
// appears in this header):
//   NRRD .nrrd/.nhdr, NIfTI .nii/.nii.gz (and Analyze .hdr/.img), MetaImage .mha/.mhd,
//   VTK legacy structured points .vtk, and DICOM: a folder holding a series (the largest one,
//   or the one whose SeriesInstanceUID is given) or one .dcm file of a series.
// Headerless raw data (one file, or a numbered series of slice files) has its own reader.
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
// NaN / infinity policy (float data only; integer types cannot hold them):
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
#include <cstdint>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "core/progress.h"
#include "core/volume.h"

namespace snert {

// Stored sample types, as found in files (raw data names them on the command line).
enum class ScalarType {
    UInt8,
    Int8,
    UInt16,
    Int16,
    UInt32,
    Int32,
    UInt64,
    Int64,
    Float32,
    Float64
};

const char* scalar_type_name(ScalarType type); // "uint8", "int16", "float32", ...
std::size_t scalar_type_size(ScalarType type); // bytes per sample
// Parses a name from scalar_type_name(); throws std::invalid_argument listing the valid names.
ScalarType parse_scalar_type(const std::string& name);

enum class Endian { Little, Big };
Endian parse_endian(const std::string& name); // "little" | "big", else std::invalid_argument

enum class NonFinitePolicy {
    Replace, // NaN, -inf -> smallest finite sample; +inf -> largest finite sample (default)
    Refuse,  // any NaN or inf fails the load
};

struct LoadOptions {
    std::string dicom_series_uid;       // DICOM folder: this SeriesInstanceUID; empty: largest
    std::size_t memory_limit_bytes = 0; // refuse grids larger than this; 0: MemAvailable
    NonFinitePolicy nonfinite = NonFinitePolicy::Replace;
    Progress progress; // reports per slab / slice; cancels by Cancelled
};

// Headerless raw samples: one file of dims.x*dims.y*dims.z samples (its size must match
// exactly), or a numbered series of slice files, each dims.x*dims.y samples. A series is
// recognised when `path` names a file of exactly one slice whose name holds a number
// (quarter.1, IM-0001.raw): the following slices are the same name with the number counting
// up (quarter.2 ... quarter.93; zero padding, as in 0001, is kept).
struct RawOptions {
    glm::ivec3 dims{0}; // samples along x, y, z (each >= 1)
    ScalarType type = ScalarType::UInt8;
    glm::vec3 spacing{1.0f};        // millimetres, each > 0
    Endian endian = Endian::Little; // byte order of multi-byte samples
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

// Loads headerless raw data (one file or a numbered slice series, see RawOptions).
LoadedVolume open_raw(const std::string& path, const RawOptions& raw,
                      const LoadOptions& options = {});
Volume load_raw(const std::string& path, const RawOptions& raw, const LoadOptions& options = {});

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

// ---- NaN / infinity policy -----------------------------------------------------------------

struct NonFiniteCount {
    std::size_t nan = 0, positive_infinity = 0, negative_infinity = 0;
    std::size_t total() const { return nan + positive_infinity + negative_infinity; }
};
// Applies the policy described at the top of this header to the samples; `name` starts the
// error message. Returns what was found (and, for Replace, replaced).
NonFiniteCount apply_nonfinite_policy(Volume& volume, NonFinitePolicy policy,
                                      const std::string& name);

// ---- Label maps beside a grey image ----------------------------------------------------------

// Throws std::invalid_argument when the two volumes do not share one grid: same dims, spacing
// and origin equal within 1e-3 of the smallest voxel size, direction columns within 1e-3. The
// message names both files, says what differs and gives both grids.
void check_same_grid(const Volume& grey, const std::string& grey_name, const Volume& labels,
                     const std::string& labels_name);

} // namespace snert
