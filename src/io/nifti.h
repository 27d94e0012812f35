// NIfTI-1 / NIfTI-2: snert's own header parser and sample reader (no ITK).
//
// Single-file NIfTI (.nii, .nii.gz) is read by snert itself: ITK 5.2 zero-fills a truncated
// file without an error, and would decompress into a second full-size buffer. The header is
// parsed here, the samples are read straight into the float32 grid (gzip decompressed on the
// fly) and widened in place, and a file that holds less than its header promises is refused.
// ITK still reads the geometry (qform / sform, RAS turned into LPS); see itk_image_io.cpp.
//
// The parser takes a byte range and never reads outside it (tests/fuzz feeds it arbitrary
// bytes); every failure is a std::runtime_error whose message starts with `name`, one line.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>

#include "core/progress.h"
#include "sample_conversion.h"

namespace snert::detail {

struct NiftiHeader {
    int version = 1;         // 1 (348-byte header) or 2 (540 bytes)
    bool single_file = true; // magic "n+1"/"n+2" (data in this file at vox_offset)
    Endian endian = Endian::Little;
    std::int64_t dim[8] = {}; // dim[0] = number of dimensions
    int datatype = 0;         // NIfTI DT_* code
    int bitpix = 0;
    std::uint64_t vox_offset = 0; // byte offset of the data
    double scl_slope = 0.0, scl_inter = 0.0;
    std::optional<ScalarType> type; // empty for complex, RGB, float128 ...

    // Samples in the first 3-D volume (dim[1] * dim[2] * dim[3]).
    std::uint64_t voxels() const;
    // Volumes after the first three axes (dim[4] * ... * dim[dim[0]]).
    std::uint64_t volumes() const;
    bool rescales() const; // slope finite and nonzero, and not the identity
};
// Bytes a NIfTI header needs to be parsed (540, enough for both versions).
inline constexpr std::size_t nifti_header_bytes = 540;
// Parses the header at the start of `bytes` (decompressed). Throws std::runtime_error for a
// header that is not NIfTI or is inconsistent (bad dims, bitpix that does not fit datatype,
// vox_offset inside the header).
NiftiHeader parse_nifti_header(const std::uint8_t* bytes, std::size_t size,
                               const std::string& name);
// "int16", "RGB24", "complex64", ... ("unknown" for codes NIfTI does not define).
const char* nifti_datatype_name(int datatype);

// Reads the NIfTI header of `path` (decompressing .gz) with parse_nifti_header.
NiftiHeader read_nifti_header(const std::string& path);
// Reads the samples of a single-file NIfTI (.nii or .nii.gz, parsed by parse_nifti_header)
// into `out` (header.voxels() floats), applying scl_slope / scl_inter. Stored values go
// straight into `out` and are widened in place; gzip is decompressed on the fly. Throws
// std::runtime_error when the file holds fewer bytes than the header promises.
void read_nifti_samples(const std::string& path, const NiftiHeader& header, float* out,
                        const Progress& progress);

} // namespace snert::detail
