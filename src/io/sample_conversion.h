// Stored sample types and their conversion to float32 (no ITK).
//
// Every reader ends here: stored samples (uint8 .. float64, either byte order) become the
// float32 grid of a Volume. Samples of up to 4 bytes are read straight into the grid's tail and
// widened in place, front to back, so a volume needs no second full-size buffer; 8-byte samples
// go through a separate buffer. Conversion is exact where float32 can hold the value (every
// 8/16-bit value, 24-bit magnitudes) and rounds otherwise.
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <string>
#include <type_traits>

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
const char* endian_name(Endian endian);       // "little" | "big"

namespace detail {

Endian native_endian();

// Where stored samples must be placed inside a float buffer of `count` floats so that
// convert_in_place() can widen them without a second buffer: the last count * size bytes.
// Only for types of at most 4 bytes.
void* stored_tail(float* buffer, std::size_t count, ScalarType type);

// Converts `count` samples of `type` in `endian` byte order, stored at stored_tail(buffer),
// into floats in buffer[0 .. count). Front to back, each sample is loaded before its float
// is written, and the write never reaches a sample not yet loaded (see the .cpp).
void convert_in_place(float* buffer, std::size_t count, ScalarType type, Endian endian);

// Converts `count` samples from a separate buffer (any type, 8-byte ones included).
void convert_samples(const void* stored, std::size_t count, ScalarType type, Endian endian,
                     float* out);
// value * slope + intercept, in double, for every sample (NIfTI scl_slope / scl_inter).
void rescale_in_place(float* samples, std::size_t count, double slope, double intercept);

// One value of type T from unaligned bytes, byte-swapped when `swap` is true.
template <class T> T load_sample(const unsigned char* at, bool swap) {
    static_assert(std::is_trivially_copyable_v<T>);
    unsigned char bytes[sizeof(T)];
    std::memcpy(bytes, at, sizeof(T));
    if (swap) std::reverse(bytes, bytes + sizeof(T));
    T value;
    std::memcpy(&value, bytes, sizeof(T));
    return value;
}

// load_sample at `offset` of a header's bytes; the caller has checked that it fits.
template <class T> T read_at(const std::uint8_t* bytes, std::size_t offset, bool swap) {
    return load_sample<T>(bytes + offset, swap);
}

} // namespace detail
} // namespace snert
