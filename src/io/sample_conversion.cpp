// Stored sample types and their conversion to float32, in place where the samples fit.
#include "sample_conversion.h"

#include <bit>
#include <cstring>
#include <stdexcept>

namespace snert {

namespace {
struct TypeEntry {
    ScalarType type;
    const char* name;
    std::size_t size;
};
constexpr TypeEntry type_table[] = {
    {ScalarType::UInt8, "uint8", 1},     {ScalarType::Int8, "int8", 1},
    {ScalarType::UInt16, "uint16", 2},   {ScalarType::Int16, "int16", 2},
    {ScalarType::UInt32, "uint32", 4},   {ScalarType::Int32, "int32", 4},
    {ScalarType::UInt64, "uint64", 8},   {ScalarType::Int64, "int64", 8},
    {ScalarType::Float32, "float32", 4}, {ScalarType::Float64, "float64", 8},
};
const TypeEntry& entry(ScalarType type) {
    for (const auto& e : type_table)
        if (e.type == type) return e;
    return type_table[0];
}
} // namespace

const char* scalar_type_name(ScalarType type) {
    return entry(type).name;
}
std::size_t scalar_type_size(ScalarType type) {
    return entry(type).size;
}

ScalarType parse_scalar_type(const std::string& name) {
    std::string names;
    for (const auto& e : type_table) {
        if (name == e.name) return e.type;
        names += names.empty() ? "" : ", ";
        names += e.name;
    }
    throw std::invalid_argument("unknown sample type '" + name + "' (expected one of " + names +
                                ")");
}

Endian parse_endian(const std::string& name) {
    if (name == "little") return Endian::Little;
    if (name == "big") return Endian::Big;
    throw std::invalid_argument("unknown byte order '" + name + "' (expected little or big)");
}

const char* endian_name(Endian endian) {
    return endian == Endian::Big ? "big" : "little";
}

namespace detail {

Endian native_endian() {
    return std::endian::native == std::endian::little ? Endian::Little : Endian::Big;
}

void* stored_tail(float* buffer, std::size_t count, ScalarType type) {
    const std::size_t size = scalar_type_size(type);
    return reinterpret_cast<unsigned char*>(buffer) + count * (sizeof(float) - size);
}

namespace {

// Widens samples front to back. With stored samples in the buffer's tail (in place), sample i
// starts at byte count*(4-s) + i*s and its float goes to bytes [4i, 4i+4): that end never
// passes the start of sample i+1 (4(i+1) <= count*(4-s) + (i+1)*s since i+1 <= count), so
// every sample is loaded before anything overwrites it.
// In blocks of 16 where no bytes are swapped: a block is loaded whole before it is stored, so
// the order above still holds (block stores end at 4(i + 16) <= count*(4-s) + (i + 16)*s, the
// next block's start, for i + 16 <= count), and the compiler vectorises the conversion.
template <class T>
void widen(const unsigned char* stored, std::size_t count, bool swap, float* out) {
    std::size_t i = 0;
    if (!swap) {
        constexpr std::size_t kBlock = 16;
        for (; i + kBlock <= count; i += kBlock) {
            T block[kBlock];
            std::memcpy(block, stored + i * sizeof(T), sizeof(block));
            float wide[kBlock];
            for (std::size_t k = 0; k < kBlock; ++k) wide[k] = static_cast<float>(block[k]);
            std::memcpy(out + i, wide, sizeof(wide));
        }
    }
    for (; i < count; ++i)
        out[i] = static_cast<float>(load_sample<T>(stored + i * sizeof(T), swap));
}

template <class F> void dispatch(ScalarType type, F&& f) {
    switch (type) {
    case ScalarType::UInt8:
        return f(std::uint8_t{});
    case ScalarType::Int8:
        return f(std::int8_t{});
    case ScalarType::UInt16:
        return f(std::uint16_t{});
    case ScalarType::Int16:
        return f(std::int16_t{});
    case ScalarType::UInt32:
        return f(std::uint32_t{});
    case ScalarType::Int32:
        return f(std::int32_t{});
    case ScalarType::UInt64:
        return f(std::uint64_t{});
    case ScalarType::Int64:
        return f(std::int64_t{});
    case ScalarType::Float32:
        return f(float{});
    case ScalarType::Float64:
        return f(double{});
    }
}

} // namespace

void convert_in_place(float* buffer, std::size_t count, ScalarType type, Endian endian) {
    if (scalar_type_size(type) > sizeof(float))
        throw std::logic_error("convert_in_place: 8-byte samples need a separate buffer");
    const bool swap = endian != native_endian();
    const auto* stored = static_cast<const unsigned char*>(stored_tail(buffer, count, type));
    dispatch(type, [&](auto tag) {
        using T = decltype(tag);
        if constexpr (std::is_same_v<T, float>) {
            if (!swap) return; // already float32 in place
        }
        widen<T>(stored, count, swap, buffer);
    });
}

void convert_samples(const void* stored, std::size_t count, ScalarType type, Endian endian,
                     float* out) {
    const bool swap = endian != native_endian();
    dispatch(type, [&](auto tag) {
        widen<decltype(tag)>(static_cast<const unsigned char*>(stored), count, swap, out);
    });
}

void rescale_in_place(float* samples, std::size_t count, double slope, double intercept) {
    for (std::size_t i = 0; i < count; ++i)
        samples[i] = static_cast<float>(double(samples[i]) * slope + intercept);
}

} // namespace detail
} // namespace snert
