// Header handling and sample conversion written for snert itself (no ITK): the checks that
// stand between an untrusted file and an allocation, and the conversion of stored samples to
// float32. Used by the ITK loader (load_volume_itk.cpp), the raw reader (raw_volume.cpp) and
// the libFuzzer target in tests/fuzz, which feeds every parser here arbitrary bytes.
//
// Why snert checks what ITK already reads: ITK 5.2 zero-fills truncated NIfTI, MetaImage, VTK
// and DICOM data without an error, allocates whatever size a header claims before reading, and
// GDCM asserts (aborts) on some damaged DICOM headers. So sizes are checked here, against the
// file, before ITK reads any sample.
//
// Every parser takes a byte range and never reads outside it; every failure is a
// std::runtime_error whose message starts with `name` (the file), one line.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "load_volume.h"

namespace snert::detail {

// ---- Sizes and memory ------------------------------------------------------------------------

// Largest extent snert accepts along one axis (Volume::dims is an ivec3).
inline constexpr std::uint64_t max_axis_extent = 2147483647u;

// Checks stored dims (each axis 1 .. max_axis_extent, the float32 grid's byte count does not
// overflow) and returns them as an ivec3. Throws std::runtime_error "<name>: absurd dimensions
// A x B x C (...)" otherwise.
glm::ivec3 checked_dims(const std::string& name, std::uint64_t x, std::uint64_t y, std::uint64_t z);

// MemAvailable of a /proc/meminfo text, in bytes; 0 when the line is missing or malformed.
std::uint64_t parse_meminfo_available(const std::string& meminfo);
// MemAvailable of this machine (falls back to sysconf's available pages), in bytes.
std::uint64_t available_memory_bytes();

// Refuses (std::runtime_error with both sizes) a grid whose float32 samples plus
// `extra_bytes` of temporary storage exceed `limit_bytes` (0: available_memory_bytes()).
void check_memory(const std::string& name, glm::ivec3 dims, std::uint64_t extra_bytes,
                  std::uint64_t limit_bytes);

// "1.5 GiB", "400.0 MiB", "12 bytes".
std::string format_bytes(std::uint64_t bytes);

// ---- Sample conversion -------------------------------------------------------------------------

Endian native_endian();

// Where stored samples must be placed inside a float buffer of `count` floats so that
// convert_in_place() can widen them without a second buffer: the last count * size bytes.
// Only for types of at most 4 bytes.
void* stored_tail(float* buffer, std::size_t count, ScalarType type);

// Converts `count` samples of `type` in `endian` byte order, stored at stored_tail(buffer),
// into floats in buffer[0 .. count). Front to back, each sample is loaded before its float
// is written, and the write never reaches a sample not yet loaded (see the .cpp).
void convert_in_place(float* buffer, std::size_t count, ScalarType type, Endian endian);

// Converts `count` samples from a separate buffer (any type, 8-byte ones included), applying
// value * slope + intercept when `rescale` is true.
void convert_samples(const void* stored, std::size_t count, ScalarType type, Endian endian,
                     float* out);
void rescale_in_place(float* samples, std::size_t count, double slope, double intercept);

// ---- Numbered slice series ---------------------------------------------------------------------

// A file name with a number in it: prefix + number + suffix, e.g. "quarter." 1 "" or
// "IM-" 0001 ".raw" (width 4: zero padding is kept).
struct NumberedName {
    std::string prefix, suffix;
    std::uint64_t number = 0;
    std::size_t width = 0; // digits to pad to (0: no padding)
};
// Every run of digits in the file name (not in the folder) read as the slice number, most
// likely first: the last run before the extension ("IM-0001.raw", "s001.f64"), then the others
// from the end ("quarter.1"). The raw reader takes the first whose next number exists.
std::vector<NumberedName> numbered_name_candidates(const std::string& path);
std::optional<NumberedName> parse_numbered_name(const std::string& path); // first candidate
std::string numbered_path(const NumberedName& name, std::uint64_t number);

// ---- NIfTI-1 / NIfTI-2 ------------------------------------------------------------------------

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
const char* nifti_datatype_name(int datatype);

// ---- MetaImage (.mha / .mhd) ------------------------------------------------------------------

struct MetaHeader {
    std::vector<std::uint64_t> dims;
    std::string element_type; // e.g. "MET_SHORT"
    std::optional<ScalarType> type;
    std::uint64_t channels = 1;
    bool binary = true; // BinaryData (ASCII data is not size-checked)
    bool compressed = false;
    std::optional<std::uint64_t> compressed_size;
    std::int64_t header_size = 0;   // HeaderSize; -1: data is at the end of the file
    std::string data_file;          // ElementDataFile value; "LOCAL": after the header
    std::uint64_t local_offset = 0; // for LOCAL: first byte after the ElementDataFile line

    std::uint64_t data_bytes() const; // uncompressed bytes the header promises (0: overflow)
};
// Parses "Key = Value" lines up to and including ElementDataFile. Throws std::runtime_error
// when ElementDataFile, NDims or DimSize is missing or malformed.
MetaHeader parse_metaimage_header(const std::string& text, const std::string& name);

// ---- VTK legacy structured points ---------------------------------------------------------------

struct VtkHeader {
    bool binary = false;
    std::uint64_t dims[3] = {0, 0, 0};
    std::uint64_t points = 0; // POINT_DATA
    std::string attribute;    // "SCALARS", "VECTORS", ...: the first point attribute
    std::optional<ScalarType> type;
    std::uint64_t components = 1;
    std::uint64_t data_offset = 0; // first byte of the samples of that attribute

    std::uint64_t data_bytes() const; // binary bytes promised (0: overflow or unknown type)
};
// Parses a VTK legacy header. Returns empty when the text is not a structured-points file
// snert understands (the size check is then skipped; ITK decides). Throws std::runtime_error
// when the header is recognised but inconsistent (POINT_DATA != product of DIMENSIONS).
std::optional<VtkHeader> parse_vtk_header(const std::uint8_t* bytes, std::size_t size,
                                          const std::string& name);
// Whitespace-separated tokens in bytes (ASCII VTK data), stopping once `enough` are found.
std::uint64_t count_tokens(const std::uint8_t* bytes, std::size_t size, std::uint64_t enough);

// ---- NRRD (.nrrd / .nhdr) ----------------------------------------------------------------------

struct NrrdHeader {
    std::vector<std::uint64_t> sizes;
    std::string type_name;          // as written, e.g. "short"
    std::optional<ScalarType> type; // empty for "block" and unknown names
    std::string encoding = "raw";   // lower case: raw, gzip, gz, ascii, text, txt, hex, bzip2 ...
    std::string data_file;          // empty: attached data after the blank line
    std::int64_t line_skip = 0, byte_skip = 0; // byte_skip -1: raw data ends the file
    std::uint64_t data_offset = 0;             // attached data: first byte after the blank line

    std::uint64_t data_bytes() const; // bytes promised (0: overflow or unknown type)
};
// Parses a NRRD header (magic "NRRD000N", "field: value" lines up to a blank line). Returns
// empty when the magic is missing. Throws std::runtime_error for a malformed sizes, dimension
// or skip field.
std::optional<NrrdHeader> parse_nrrd_header(const std::uint8_t* bytes, std::size_t size,
                                            const std::string& name);

// Checks against the files on disk, run before ITK reads any header or sample, in this order:
// absurd dimensions (checked_dims), memory (check_memory with `memory_limit`, 0: available),
// then the data the header promises: std::runtime_error "<path>: truncated ...: the header
// promises N bytes, <file> holds M" when it is short. Variants they do not understand (ASCII
// MetaImage, slice lists, VTK files with other attributes, bzip2 NRRD) pass to ITK unchecked.
void check_nrrd_data(const std::string& path, std::uint64_t memory_limit);
void check_metaimage_data(const std::string& path, std::uint64_t memory_limit);
void check_vtk_data(const std::string& path, std::uint64_t memory_limit);

// ---- DICOM --------------------------------------------------------------------------------------

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

// ---- gzip / zlib
// ----------------------------------------------------------------------------------

bool has_gzip_magic(const std::uint8_t* bytes, std::size_t size);

// Counts the bytes a zlib or gzip stream inflates to, stopping once `enough` are produced.
// Throws std::runtime_error "<name>: corrupt compressed data" for a stream that is not zlib /
// gzip or is damaged; a stream cut short returns what it produced.
class InflateCounter {
  public:
    InflateCounter(std::string name, std::uint64_t enough);
    ~InflateCounter();
    InflateCounter(const InflateCounter&) = delete;
    InflateCounter& operator=(const InflateCounter&) = delete;
    // Feeds the next compressed bytes; returns false once done (enough bytes or end of stream).
    bool feed(const std::uint8_t* bytes, std::size_t size);
    std::uint64_t produced() const { return produced_; }

  private:
    std::string name_;
    std::uint64_t enough_, produced_ = 0;
    bool done_ = false;
    void* stream_;
};
// Inflated size of `size` bytes from `offset` of a file (at most `enough`).
std::uint64_t inflated_file_bytes(const std::string& path, std::uint64_t offset,
                                  std::uint64_t enough);

// ---- Files
// ---------------------------------------------------------------------------------------

// Size of a regular file; throws std::runtime_error naming it when it cannot be read.
std::uint64_t file_size(const std::string& path);
// Up to `max_bytes` from the start of a file (fewer if the file is shorter).
std::vector<std::uint8_t> read_file_prefix(const std::string& path, std::size_t max_bytes);
// Lower-case file name extension including ".gz" pairs: ".nii.gz", ".nrrd", "" for none.
std::string volume_extension(const std::string& path);

// Reads the samples of a single-file NIfTI (.nii or .nii.gz, parsed by parse_nifti_header)
// into `out` (header.voxels() floats), applying scl_slope / scl_inter. Stored values go
// straight into `out` and are widened in place; gzip is decompressed on the fly. Throws
// std::runtime_error when the file holds fewer bytes than the header promises.
void read_nifti_samples(const std::string& path, const NiftiHeader& header, float* out,
                        const Progress& progress);
// Reads the NIfTI header of `path` (decompressing .gz) with parse_nifti_header.
NiftiHeader read_nifti_header(const std::string& path);

} // namespace snert::detail
