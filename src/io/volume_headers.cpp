// Header parsing, size checks and sample conversion for untrusted volume files.
//
// This work is based on the published format descriptions:
//  - NIfTI-1 (nifti1.h, NIfTI DFWG 2004) and NIfTI-2 (nifti2.h, 2011) header layouts;
//  - MetaImage / MetaIO key = value headers (Kitware, MetaIO documentation);
//  - VTK legacy file format, structured points (VTK User's Guide, "VTK File Formats");
//  - DICOM PS3.5 data element encoding (explicit / implicit VR, Pixel Data (7FE0,0010)).
// Every read is bounds-checked against the byte range given; the fuzz target relies on it.
#include "volume_headers.h"

#include <algorithm>
#include <bit>
#include <cctype>
#include <cmath>
#include <cstring>
#include <fstream>
#include <limits>
#include <sstream>
#include <stdexcept>

#include <sys/stat.h>
#include <unistd.h>
#include <zlib.h>

namespace snert {

// ---- Scalar types (declared in load_volume.h) ---------------------------------------------------

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

namespace detail {

// ---- Sizes and memory ------------------------------------------------------------------------

glm::ivec3 checked_dims(const std::string& name, std::uint64_t x, std::uint64_t y,
                        std::uint64_t z) {
    const std::uint64_t axes[3] = {x, y, z};
    const std::string text =
        std::to_string(x) + " x " + std::to_string(y) + " x " + std::to_string(z);
    for (std::uint64_t n : axes)
        if (n < 1 || n > max_axis_extent)
            throw std::runtime_error(name + ": absurd dimensions " + text +
                                     " (each axis must hold 1 to " +
                                     std::to_string(max_axis_extent) + " samples)");
    std::uint64_t bytes = sizeof(float);
    for (std::uint64_t n : axes)
        if (__builtin_mul_overflow(bytes, n, &bytes) ||
            bytes > std::numeric_limits<std::size_t>::max() / 2)
            throw std::runtime_error(name + ": absurd dimensions " + text +
                                     " (the sample count overflows)");
    return {int(x), int(y), int(z)};
}

std::uint64_t parse_meminfo_available(const std::string& meminfo) {
    std::istringstream lines(meminfo);
    std::string line;
    while (std::getline(lines, line)) {
        if (line.rfind("MemAvailable:", 0) != 0) continue;
        std::istringstream fields(line.substr(13));
        std::uint64_t kib = 0;
        std::string unit;
        if (!(fields >> kib >> unit) || unit != "kB") return 0;
        if (kib > std::numeric_limits<std::uint64_t>::max() / 1024) return 0;
        return kib * 1024;
    }
    return 0;
}

namespace {
std::string read_small_text(const char* path) {
    std::ifstream in(path);
    std::ostringstream text;
    text << in.rdbuf();
    return text.str();
}

// Room left under a cgroup v2 memory limit ("max" or absent: no limit).
std::uint64_t cgroup_room() {
    const std::string max_text = read_small_text("/sys/fs/cgroup/memory.max");
    const std::string current_text = read_small_text("/sys/fs/cgroup/memory.current");
    if (max_text.empty() || max_text.rfind("max", 0) == 0 || current_text.empty())
        return std::numeric_limits<std::uint64_t>::max();
    try {
        const std::uint64_t max = std::stoull(max_text), current = std::stoull(current_text);
        return max > current ? max - current : 0;
    } catch (const std::exception&) {
        return std::numeric_limits<std::uint64_t>::max();
    }
}
} // namespace

std::uint64_t available_memory_bytes() {
    std::uint64_t bytes = parse_meminfo_available(read_small_text("/proc/meminfo"));
    if (bytes == 0) {
        const long pages = sysconf(_SC_AVPHYS_PAGES), page = sysconf(_SC_PAGESIZE);
        if (pages > 0 && page > 0) bytes = std::uint64_t(pages) * std::uint64_t(page);
    }
    return std::min(bytes, cgroup_room());
}

std::string format_bytes(std::uint64_t bytes) {
    const char* units[] = {"KiB", "MiB", "GiB", "TiB", "PiB", "EiB"};
    if (bytes < 1024) return std::to_string(bytes) + " bytes";
    double value = double(bytes) / 1024.0;
    int unit = 0;
    while (value >= 1024.0 && unit < 5) {
        value /= 1024.0;
        ++unit;
    }
    char text[64];
    std::snprintf(text, sizeof text, "%.1f %s", value, units[unit]);
    return text;
}

void check_memory(const std::string& name, glm::ivec3 dims, std::uint64_t extra_bytes,
                  std::uint64_t limit_bytes) {
    const std::uint64_t grid =
        std::uint64_t(dims.x) * std::uint64_t(dims.y) * std::uint64_t(dims.z) * sizeof(float);
    std::uint64_t need = 0;
    if (__builtin_add_overflow(grid, extra_bytes, &need))
        need = std::numeric_limits<std::uint64_t>::max();
    const bool explicit_limit = limit_bytes != 0;
    const std::uint64_t limit = explicit_limit ? limit_bytes : available_memory_bytes();
    if (limit == 0 || need <= limit) return;
    std::string message = name + ": " + std::to_string(dims.x) + " x " + std::to_string(dims.y) +
                          " x " + std::to_string(dims.z) + " samples need " + format_bytes(grid) +
                          " as float32";
    if (extra_bytes) message += " plus " + format_bytes(extra_bytes) + " while reading";
    message += explicit_limit ? ", above the memory limit of " + format_bytes(limit)
                              : ", but only " + format_bytes(limit) + " of memory is available";
    throw std::runtime_error(message);
}

// ---- Sample conversion -------------------------------------------------------------------------

Endian native_endian() {
    return std::endian::native == std::endian::little ? Endian::Little : Endian::Big;
}

void* stored_tail(float* buffer, std::size_t count, ScalarType type) {
    const std::size_t size = scalar_type_size(type);
    return reinterpret_cast<unsigned char*>(buffer) + count * (sizeof(float) - size);
}

namespace {

template <class T> T load_sample(const unsigned char* at, bool swap) {
    static_assert(std::is_trivially_copyable_v<T>);
    unsigned char bytes[sizeof(T)];
    std::memcpy(bytes, at, sizeof(T));
    if (swap) std::reverse(bytes, bytes + sizeof(T));
    T value;
    std::memcpy(&value, bytes, sizeof(T));
    return value;
}

// Widens samples front to back. With stored samples in the buffer's tail (in place), sample i
// starts at byte count*(4-s) + i*s and its float goes to bytes [4i, 4i+4): that end never
// passes the start of sample i+1 (4(i+1) <= count*(4-s) + (i+1)*s since i+1 <= count), so
// every sample is loaded before anything overwrites it.
template <class T>
void widen(const unsigned char* stored, std::size_t count, bool swap, float* out) {
    for (std::size_t i = 0; i < count; ++i)
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

// ---- Numbered slice series ---------------------------------------------------------------------

std::vector<NumberedName> numbered_name_candidates(const std::string& path) {
    const std::size_t slash = path.find_last_of('/');
    const std::size_t name_start = slash == std::string::npos ? 0 : slash + 1;
    std::vector<NumberedName> runs; // from the end of the name
    for (std::size_t end = path.size(); end > name_start;) {
        if (!std::isdigit(static_cast<unsigned char>(path[end - 1]))) {
            --end;
            continue;
        }
        std::size_t begin = end;
        while (begin > name_start && std::isdigit(static_cast<unsigned char>(path[begin - 1])))
            --begin;
        const std::string digits = path.substr(begin, end - begin);
        if (digits.size() <= 18) { // keeps number + count inside uint64
            NumberedName name;
            name.prefix = path.substr(0, begin);
            name.suffix = path.substr(end);
            name.number = std::stoull(digits);
            name.width = digits.size() > 1 && digits[0] == '0' ? digits.size() : 0;
            runs.push_back(std::move(name));
        }
        end = begin;
    }
    // The last run before the extension goes first, when the name has one.
    const std::size_t dot = path.find_last_of('.');
    if (dot != std::string::npos && dot > name_start) {
        const auto before_ext = std::find_if(
            runs.begin(), runs.end(), [&](const NumberedName& n) { return n.prefix.size() < dot; });
        if (before_ext != runs.end()) std::rotate(runs.begin(), before_ext, before_ext + 1);
    }
    return runs;
}

std::optional<NumberedName> parse_numbered_name(const std::string& path) {
    auto runs = numbered_name_candidates(path);
    if (runs.empty()) return std::nullopt;
    return runs.front();
}

std::string numbered_path(const NumberedName& name, std::uint64_t number) {
    std::string digits = std::to_string(number);
    if (digits.size() < name.width) digits.insert(0, name.width - digits.size(), '0');
    return name.prefix + digits + name.suffix;
}

// ---- NIfTI
// ----------------------------------------------------------------------------------------

namespace {

template <class T> T read_at(const std::uint8_t* bytes, std::size_t offset, bool swap) {
    return load_sample<T>(bytes + offset, swap);
}

std::uint64_t saturating_product(const std::int64_t* values, int from, int to) {
    std::uint64_t product = 1;
    for (int i = from; i <= to; ++i) {
        const std::uint64_t v = values[i] > 0 ? std::uint64_t(values[i]) : 0;
        if (__builtin_mul_overflow(product, v, &product))
            return std::numeric_limits<std::uint64_t>::max();
    }
    return product;
}

std::optional<ScalarType> nifti_type(int datatype) {
    switch (datatype) {
    case 2:
        return ScalarType::UInt8;
    case 4:
        return ScalarType::Int16;
    case 8:
        return ScalarType::Int32;
    case 16:
        return ScalarType::Float32;
    case 64:
        return ScalarType::Float64;
    case 256:
        return ScalarType::Int8;
    case 512:
        return ScalarType::UInt16;
    case 768:
        return ScalarType::UInt32;
    case 1024:
        return ScalarType::Int64;
    case 1280:
        return ScalarType::UInt64;
    default:
        return std::nullopt;
    }
}

} // namespace

const char* nifti_datatype_name(int datatype) {
    switch (datatype) {
    case 1:
        return "binary";
    case 32:
        return "complex64";
    case 128:
        return "RGB24";
    case 1536:
        return "float128";
    case 1792:
        return "complex128";
    case 2048:
        return "complex256";
    case 2304:
        return "RGBA32";
    default:
        if (auto type = nifti_type(datatype)) return scalar_type_name(*type);
        return "unknown";
    }
}

std::uint64_t NiftiHeader::voxels() const {
    std::int64_t d[8] = {0, 1, 1, 1, 1, 1, 1, 1};
    for (int i = 1; i <= std::min<std::int64_t>(dim[0], 3); ++i) d[i] = dim[i];
    return saturating_product(d, 1, 3);
}

std::uint64_t NiftiHeader::volumes() const {
    if (dim[0] <= 3) return 1;
    return saturating_product(dim, 4, int(std::min<std::int64_t>(dim[0], 7)));
}

bool NiftiHeader::rescales() const {
    return std::isfinite(scl_slope) && std::isfinite(scl_inter) && scl_slope != 0.0 &&
           !(scl_slope == 1.0 && scl_inter == 0.0);
}

NiftiHeader parse_nifti_header(const std::uint8_t* bytes, std::size_t size,
                               const std::string& name) {
    if (size < 348) throw std::runtime_error(name + ": too short for a NIfTI header");
    NiftiHeader h;
    const std::int32_t sizeof_hdr = read_at<std::int32_t>(bytes, 0, false);
    const std::int32_t swapped = read_at<std::int32_t>(bytes, 0, true);
    bool swap = false;
    if (sizeof_hdr == 348 || sizeof_hdr == 540) {
        h.version = sizeof_hdr == 348 ? 1 : 2;
    } else if (swapped == 348 || swapped == 540) {
        h.version = swapped == 348 ? 1 : 2;
        swap = true;
    } else {
        throw std::runtime_error(name + ": not a NIfTI header (sizeof_hdr is " +
                                 std::to_string(sizeof_hdr) + ", expected 348 or 540)");
    }
    h.endian = swap == (native_endian() == Endian::Little) ? Endian::Big : Endian::Little;
    double vox_offset = 0.0;
    if (h.version == 1) {
        h.single_file = std::memcmp(bytes + 344, "n+1\0", 4) == 0;
        for (int i = 0; i < 8; ++i) h.dim[i] = read_at<std::int16_t>(bytes, 40 + 2 * i, swap);
        h.datatype = read_at<std::int16_t>(bytes, 70, swap);
        h.bitpix = read_at<std::int16_t>(bytes, 72, swap);
        vox_offset = read_at<float>(bytes, 108, swap);
        h.scl_slope = read_at<float>(bytes, 112, swap);
        h.scl_inter = read_at<float>(bytes, 116, swap);
    } else {
        if (size < nifti_header_bytes)
            throw std::runtime_error(name + ": too short for a NIfTI-2 header");
        h.single_file = std::memcmp(bytes + 4, "n+2\0", 4) == 0;
        if (!h.single_file && std::memcmp(bytes + 4, "ni2\0", 4) != 0)
            throw std::runtime_error(name + ": NIfTI-2 header without its magic string");
        h.datatype = read_at<std::int16_t>(bytes, 12, swap);
        h.bitpix = read_at<std::int16_t>(bytes, 14, swap);
        for (int i = 0; i < 8; ++i) h.dim[i] = read_at<std::int64_t>(bytes, 16 + 8 * i, swap);
        const std::int64_t offset = read_at<std::int64_t>(bytes, 168, swap);
        vox_offset = offset < 0 ? -1.0 : double(offset);
        h.scl_slope = read_at<double>(bytes, 176, swap);
        h.scl_inter = read_at<double>(bytes, 184, swap);
    }
    if (h.dim[0] < 1 || h.dim[0] > 7)
        throw std::runtime_error(name + ": bad NIfTI header: dim[0] is " +
                                 std::to_string(h.dim[0]) + " (expected 1 to 7)");
    for (int i = 1; i <= h.dim[0]; ++i)
        if (h.dim[i] < 1)
            throw std::runtime_error(name + ": bad NIfTI header: dim[" + std::to_string(i) +
                                     "] is " + std::to_string(h.dim[i]));
    h.type = nifti_type(h.datatype);
    if (h.type && h.bitpix != int(8 * scalar_type_size(*h.type)))
        throw std::runtime_error(name + ": bad NIfTI header: bitpix " + std::to_string(h.bitpix) +
                                 " does not match datatype " + nifti_datatype_name(h.datatype));
    const double header_end = h.version == 1 ? 348.0 : 540.0;
    if (!std::isfinite(vox_offset) || vox_offset < 0.0 || vox_offset > 9.0e15 ||
        (h.single_file && vox_offset < header_end))
        throw std::runtime_error(name + ": bad NIfTI header: vox_offset " +
                                 std::to_string(vox_offset) + " is not a valid data offset");
    h.vox_offset = std::uint64_t(vox_offset);
    return h;
}

// ---- MetaImage --------------------------------------------------------------------------------

namespace {

std::string trim(const std::string& s) {
    std::size_t b = 0, e = s.size();
    while (b < e && std::isspace(static_cast<unsigned char>(s[b]))) ++b;
    while (e > b && std::isspace(static_cast<unsigned char>(s[e - 1]))) --e;
    return s.substr(b, e - b);
}

std::string lower(std::string s) {
    for (char& c : s) c = char(std::tolower(static_cast<unsigned char>(c)));
    return s;
}

bool parse_bool_word(const std::string& value) {
    const std::string v = lower(value);
    return v == "true" || v == "1" || v == "yes";
}

// A whole unsigned decimal number (no sign, no trailing text), or empty.
std::optional<std::uint64_t> parse_count(const std::string& text) {
    if (text.empty() || text.size() > 19) return std::nullopt;
    std::uint64_t value = 0;
    for (char c : text) {
        if (!std::isdigit(static_cast<unsigned char>(c))) return std::nullopt;
        value = value * 10 + std::uint64_t(c - '0');
    }
    return value;
}

std::optional<std::int64_t> parse_signed(const std::string& text) {
    if (!text.empty() && text[0] == '-') {
        auto v = parse_count(text.substr(1));
        if (!v || *v > std::uint64_t(std::numeric_limits<std::int64_t>::max())) return std::nullopt;
        return -std::int64_t(*v);
    }
    auto v = parse_count(text);
    if (!v || *v > std::uint64_t(std::numeric_limits<std::int64_t>::max())) return std::nullopt;
    return std::int64_t(*v);
}

std::vector<std::string> words(const std::string& text) {
    std::istringstream in(text);
    std::vector<std::string> out;
    std::string w;
    while (in >> w) out.push_back(w);
    return out;
}

std::optional<ScalarType> meta_type(std::string element_type) {
    const std::string suffix = "_ARRAY";
    if (element_type.size() > suffix.size() &&
        element_type.compare(element_type.size() - suffix.size(), suffix.size(), suffix) == 0)
        element_type.resize(element_type.size() - suffix.size());
    // MetaIO sizes: MET_LONG / MET_ULONG are 4 bytes, MET_LONG_LONG 8.
    static const std::pair<const char*, ScalarType> table[] = {
        {"MET_UCHAR", ScalarType::UInt8},       {"MET_CHAR", ScalarType::Int8},
        {"MET_USHORT", ScalarType::UInt16},     {"MET_SHORT", ScalarType::Int16},
        {"MET_UINT", ScalarType::UInt32},       {"MET_INT", ScalarType::Int32},
        {"MET_ULONG", ScalarType::UInt32},      {"MET_LONG", ScalarType::Int32},
        {"MET_ULONG_LONG", ScalarType::UInt64}, {"MET_LONG_LONG", ScalarType::Int64},
        {"MET_FLOAT", ScalarType::Float32},     {"MET_DOUBLE", ScalarType::Float64},
    };
    for (const auto& [n, t] : table)
        if (element_type == n) return t;
    return std::nullopt;
}

std::uint64_t checked_product(const std::vector<std::uint64_t>& factors) {
    std::uint64_t product = 1;
    for (std::uint64_t f : factors)
        if (__builtin_mul_overflow(product, f, &product)) return 0;
    return product;
}

} // namespace

std::uint64_t MetaHeader::data_bytes() const {
    std::vector<std::uint64_t> factors = dims;
    factors.push_back(channels);
    factors.push_back(type ? scalar_type_size(*type) : 0);
    return checked_product(factors);
}

MetaHeader parse_metaimage_header(const std::string& text, const std::string& name) {
    MetaHeader h;
    std::optional<std::uint64_t> ndims;
    bool have_dims = false, have_file = false;
    std::size_t pos = 0;
    while (pos < text.size() && !have_file) {
        std::size_t end = text.find('\n', pos);
        const std::size_t next = end == std::string::npos ? text.size() : end + 1;
        const std::string line = text.substr(pos, next - pos);
        pos = next;
        const std::size_t eq = line.find('=');
        if (eq == std::string::npos) continue;
        const std::string key = lower(trim(line.substr(0, eq)));
        const std::string value = trim(line.substr(eq + 1));
        if (key == "ndims") {
            ndims = parse_count(value);
            if (!ndims || *ndims < 1 || *ndims > 16)
                throw std::runtime_error(name + ": bad MetaImage header: NDims = " + value);
        } else if (key == "dimsize") {
            h.dims.clear();
            for (const auto& w : words(value)) {
                auto n = parse_count(w);
                if (!n)
                    throw std::runtime_error(name + ": bad MetaImage header: DimSize = " + value);
                h.dims.push_back(*n);
            }
            have_dims = true;
        } else if (key == "elementtype") {
            h.element_type = value;
            h.type = meta_type(value);
        } else if (key == "elementnumberofchannels") {
            auto n = parse_count(value);
            if (!n || *n < 1)
                throw std::runtime_error(name +
                                         ": bad MetaImage header: "
                                         "ElementNumberOfChannels = " +
                                         value);
            h.channels = *n;
        } else if (key == "binarydata") {
            h.binary = parse_bool_word(value);
        } else if (key == "compresseddata") {
            h.compressed = parse_bool_word(value);
        } else if (key == "compresseddatasize") {
            h.compressed_size = parse_count(value);
        } else if (key == "headersize") {
            auto n = parse_signed(value);
            if (!n || *n < -1)
                throw std::runtime_error(name + ": bad MetaImage header: HeaderSize = " + value);
            h.header_size = *n;
        } else if (key == "elementdatafile") {
            h.data_file = value;
            h.local_offset = pos;
            have_file = true;
        }
    }
    if (!have_file)
        throw std::runtime_error(name + ": bad MetaImage header: no ElementDataFile line");
    if (!have_dims || h.dims.empty())
        throw std::runtime_error(name + ": bad MetaImage header: no DimSize line");
    if (ndims) {
        if (h.dims.size() < *ndims)
            throw std::runtime_error(name + ": bad MetaImage header: DimSize has " +
                                     std::to_string(h.dims.size()) +
                                     " values for NDims = " + std::to_string(*ndims));
        h.dims.resize(*ndims);
    }
    return h;
}

// ---- VTK legacy ---------------------------------------------------------------------------------

namespace {

std::optional<ScalarType> vtk_type(const std::string& name) {
    static const std::pair<const char*, ScalarType> table[] = {
        {"unsigned_char", ScalarType::UInt8},   {"char", ScalarType::Int8},
        {"unsigned_short", ScalarType::UInt16}, {"short", ScalarType::Int16},
        {"unsigned_int", ScalarType::UInt32},   {"int", ScalarType::Int32},
        {"unsigned_long", ScalarType::UInt64},  {"long", ScalarType::Int64},
        {"vtktypeuint64", ScalarType::UInt64},  {"vtktypeint64", ScalarType::Int64},
        {"float", ScalarType::Float32},         {"double", ScalarType::Float64},
    };
    const std::string key = lower(name);
    for (const auto& [n, t] : table)
        if (key == n) return t;
    return std::nullopt;
}

// Reads lines of a byte range, remembering where the next line starts.
class LineReader {
  public:
    LineReader(const std::uint8_t* bytes, std::size_t size) : bytes_(bytes), size_(size) {}
    std::optional<std::string> next() {
        if (pos_ >= size_) return std::nullopt;
        const auto* start = bytes_ + pos_;
        const auto* nl = static_cast<const std::uint8_t*>(std::memchr(start, '\n', size_ - pos_));
        const std::size_t len = nl ? std::size_t(nl - start) : size_ - pos_;
        pos_ += len + (nl ? 1 : 0);
        std::string line(reinterpret_cast<const char*>(start), len);
        if (!line.empty() && line.back() == '\r') line.pop_back();
        return line;
    }
    std::size_t position() const { return pos_; }

  private:
    const std::uint8_t* bytes_;
    std::size_t size_, pos_ = 0;
};

} // namespace

std::uint64_t VtkHeader::data_bytes() const {
    if (!type) return 0;
    return checked_product({points, components, scalar_type_size(*type)});
}

std::optional<VtkHeader> parse_vtk_header(const std::uint8_t* bytes, std::size_t size,
                                          const std::string& name) {
    LineReader lines(bytes, size);
    auto first = lines.next();
    if (!first || first->rfind("# vtk DataFile Version", 0) != 0) return std::nullopt;
    if (!lines.next()) return std::nullopt; // title
    auto encoding = lines.next();
    if (!encoding) return std::nullopt;
    VtkHeader h;
    const std::string enc = lower(trim(*encoding));
    if (enc == "binary")
        h.binary = true;
    else if (enc != "ascii")
        return std::nullopt;
    bool structured_points = false, have_dims = false, have_points = false;
    while (auto line = lines.next()) {
        const auto w = words(*line);
        if (w.empty()) continue;
        const std::string key = lower(w[0]);
        if (key == "dataset") {
            if (w.size() < 2 || lower(w[1]) != "structured_points") return std::nullopt;
            structured_points = true;
        } else if (key == "dimensions") {
            if (w.size() != 4) return std::nullopt;
            for (int a = 0; a < 3; ++a) {
                auto n = parse_count(w[std::size_t(a) + 1]);
                if (!n) return std::nullopt;
                h.dims[a] = *n;
            }
            have_dims = true;
        } else if (key == "spacing" || key == "aspect_ratio" || key == "origin") {
            continue;
        } else if (key == "point_data") {
            auto n = w.size() == 2 ? parse_count(w[1]) : std::nullopt;
            if (!n) return std::nullopt;
            h.points = *n;
            have_points = true;
        } else if (key == "scalars" && have_points) {
            if (w.size() < 3) return std::nullopt;
            h.attribute = "SCALARS";
            h.type = vtk_type(w[2]);
            if (w.size() >= 4) {
                auto n = parse_count(w[3]);
                if (!n || *n < 1 || *n > 4) return std::nullopt;
                h.components = *n;
            }
            auto table = lines.next(); // LOOKUP_TABLE name: required after SCALARS
            const auto table_words = table ? words(*table) : std::vector<std::string>{};
            if (table_words.empty() || lower(table_words[0]) != "lookup_table") return std::nullopt;
            h.data_offset = lines.position();
            break;
        } else if (key == "vectors" && have_points) {
            if (w.size() < 3) return std::nullopt;
            h.attribute = "VECTORS";
            h.type = vtk_type(w[2]);
            h.components = 3;
            h.data_offset = lines.position();
            break;
        } else {
            return std::nullopt; // FIELD, CELL_DATA, COLOR_SCALARS ...: not checked here
        }
    }
    if (!structured_points || !have_dims || !have_points || h.attribute.empty() || !h.type)
        return std::nullopt;
    const std::uint64_t grid = checked_product({h.dims[0], h.dims[1], h.dims[2]});
    if (grid != h.points)
        throw std::runtime_error(name + ": bad VTK header: POINT_DATA " + std::to_string(h.points) +
                                 " does not match DIMENSIONS " + std::to_string(h.dims[0]) + " " +
                                 std::to_string(h.dims[1]) + " " + std::to_string(h.dims[2]));
    return h;
}

std::uint64_t count_tokens(const std::uint8_t* bytes, std::size_t size, std::uint64_t enough) {
    std::uint64_t tokens = 0;
    bool in_token = false;
    for (std::size_t i = 0; i < size && tokens < enough; ++i) {
        const bool space = std::isspace(bytes[i]) != 0;
        if (!space && !in_token) ++tokens;
        in_token = !space;
    }
    return tokens;
}

namespace {

std::string folder_of(const std::string& path) {
    const std::size_t slash = path.find_last_of('/');
    return slash == std::string::npos ? std::string() : path.substr(0, slash + 1);
}

[[noreturn]] void throw_short(const std::string& path, const std::string& what, std::uint64_t need,
                              const std::string& data_path, std::uint64_t have) {
    throw std::runtime_error(path + ": truncated " + what + ": the header promises " +
                             std::to_string(need) + " bytes of samples, " +
                             (data_path == path ? std::string("the file") : data_path) + " holds " +
                             std::to_string(have));
}

// Absurd dimensions, then memory, for a header's axes (extra axes fold into z).
void check_grid(const std::string& path, const std::vector<std::uint64_t>& axes,
                std::uint64_t memory_limit) {
    std::uint64_t d[3] = {1, 1, 1};
    for (std::size_t a = 0; a < axes.size(); ++a) {
        if (a < 3) {
            d[a] = axes[a];
        } else if (__builtin_mul_overflow(d[2], axes[a], &d[2])) {
            d[2] = std::numeric_limits<std::uint64_t>::max();
        }
    }
    check_memory(path, checked_dims(path, d[0], d[1], d[2]), 0, memory_limit);
}

} // namespace

void check_metaimage_data(const std::string& path, std::uint64_t memory_limit) {
    const auto prefix = read_file_prefix(path, 1 << 20);
    const MetaHeader h = parse_metaimage_header(std::string(prefix.begin(), prefix.end()), path);
    if (!h.element_type.empty() && !h.type)
        throw std::runtime_error(path + ": unsupported MetaImage ElementType " + h.element_type);
    check_grid(path, h.dims, memory_limit);
    const std::string data_file = lower(h.data_file);
    if (!h.binary || data_file == "list" || h.data_file.find('%') != std::string::npos ||
        h.data_file.empty())
        return;
    const std::uint64_t need = h.data_bytes();
    if (need == 0) return; // unknown type or overflow: ITK refuses, or checked_dims does
    const bool local = data_file == "local";
    const std::string data_path =
        local ? path : (h.data_file[0] == '/' ? h.data_file : folder_of(path) + h.data_file);
    std::uint64_t size = 0;
    try {
        size = file_size(data_path);
    } catch (const std::runtime_error&) {
        throw std::runtime_error(path + ": its data file " + data_path + " is missing");
    }
    std::uint64_t start = local ? h.local_offset : 0;
    if (h.header_size > 0) start += std::uint64_t(h.header_size);
    if (h.compressed) {
        const std::uint64_t stored = size > start ? size - start : 0;
        if (h.compressed_size && stored < *h.compressed_size)
            throw std::runtime_error(path + ": truncated MetaImage: CompressedDataSize is " +
                                     std::to_string(*h.compressed_size) + " bytes, " + data_path +
                                     " holds " + std::to_string(stored));
        const std::uint64_t produced = inflated_file_bytes(data_path, start, need);
        if (produced < need) throw_short(path, "MetaImage", need, data_path, produced);
        return;
    }
    // HeaderSize = -1: the samples are the last bytes of the file, whatever precedes them.
    const std::uint64_t have = h.header_size == -1 ? size : (size > start ? size - start : 0);
    if (have < need) throw_short(path, "MetaImage", need, data_path, have);
}

void check_vtk_data(const std::string& path, std::uint64_t memory_limit) {
    const std::uint64_t size = file_size(path);
    const auto prefix = read_file_prefix(path, 1 << 16);
    const auto h = parse_vtk_header(prefix.data(), prefix.size(), path);
    if (!h || h->data_offset > size) return;
    check_grid(path, {h->dims[0], h->dims[1], h->dims[2]}, memory_limit);
    if (h->binary) {
        const std::uint64_t need = h->data_bytes();
        if (need != 0 && size - h->data_offset < need)
            throw_short(path, "VTK", need, path, size - h->data_offset);
        return;
    }
    const std::uint64_t need = h->points * h->components;
    const auto all = read_file_prefix(path, std::size_t(size));
    const std::uint64_t have =
        count_tokens(all.data() + h->data_offset, all.size() - std::size_t(h->data_offset), need);
    if (have < need)
        throw std::runtime_error(path + ": truncated VTK: the header promises " +
                                 std::to_string(need) + " ASCII values, the file holds " +
                                 std::to_string(have));
}

// ---- NRRD ---------------------------------------------------------------------------------------

namespace {

std::optional<ScalarType> nrrd_type(const std::string& name) {
    static const std::pair<const char*, ScalarType> table[] = {
        {"signed char", ScalarType::Int8},
        {"int8", ScalarType::Int8},
        {"int8_t", ScalarType::Int8},
        {"uchar", ScalarType::UInt8},
        {"unsigned char", ScalarType::UInt8},
        {"uint8", ScalarType::UInt8},
        {"uint8_t", ScalarType::UInt8},
        {"short", ScalarType::Int16},
        {"short int", ScalarType::Int16},
        {"signed short", ScalarType::Int16},
        {"signed short int", ScalarType::Int16},
        {"int16", ScalarType::Int16},
        {"int16_t", ScalarType::Int16},
        {"ushort", ScalarType::UInt16},
        {"unsigned short", ScalarType::UInt16},
        {"unsigned short int", ScalarType::UInt16},
        {"uint16", ScalarType::UInt16},
        {"uint16_t", ScalarType::UInt16},
        {"int", ScalarType::Int32},
        {"signed int", ScalarType::Int32},
        {"int32", ScalarType::Int32},
        {"int32_t", ScalarType::Int32},
        {"uint", ScalarType::UInt32},
        {"unsigned int", ScalarType::UInt32},
        {"uint32", ScalarType::UInt32},
        {"uint32_t", ScalarType::UInt32},
        {"longlong", ScalarType::Int64},
        {"long long", ScalarType::Int64},
        {"long long int", ScalarType::Int64},
        {"signed long long", ScalarType::Int64},
        {"signed long long int", ScalarType::Int64},
        {"int64", ScalarType::Int64},
        {"int64_t", ScalarType::Int64},
        {"ulonglong", ScalarType::UInt64},
        {"unsigned long long", ScalarType::UInt64},
        {"unsigned long long int", ScalarType::UInt64},
        {"uint64", ScalarType::UInt64},
        {"uint64_t", ScalarType::UInt64},
        {"float", ScalarType::Float32},
        {"double", ScalarType::Float64},
    };
    const std::string key = lower(name);
    for (const auto& [n, t] : table)
        if (key == n) return t;
    return std::nullopt;
}

} // namespace

std::uint64_t NrrdHeader::data_bytes() const {
    if (!type) return 0;
    std::vector<std::uint64_t> factors = sizes;
    factors.push_back(scalar_type_size(*type));
    return checked_product(factors);
}

std::optional<NrrdHeader> parse_nrrd_header(const std::uint8_t* bytes, std::size_t size,
                                            const std::string& name) {
    LineReader lines(bytes, size);
    auto magic = lines.next();
    if (!magic || magic->size() < 8 || magic->rfind("NRRD000", 0) != 0) return std::nullopt;
    NrrdHeader h;
    std::optional<std::uint64_t> dimension;
    while (auto line = lines.next()) {
        if (line->empty()) break; // end of the header; attached data follows
        if ((*line)[0] == '#' || line->find(":=") != std::string::npos) continue;
        const std::size_t colon = line->find(": ");
        if (colon == std::string::npos) continue;
        const std::string key = lower(trim(line->substr(0, colon)));
        const std::string value = trim(line->substr(colon + 2));
        const auto bad = [&] {
            return std::runtime_error(name + ": bad NRRD header: " + key + ": " + value);
        };
        if (key == "type") {
            h.type_name = value;
            h.type = nrrd_type(value);
        } else if (key == "dimension") {
            dimension = parse_count(value);
            if (!dimension || *dimension < 1 || *dimension > 16) throw bad();
        } else if (key == "sizes") {
            h.sizes.clear();
            for (const auto& w : words(value)) {
                auto n = parse_count(w);
                if (!n) throw bad();
                h.sizes.push_back(*n);
            }
        } else if (key == "encoding") {
            h.encoding = lower(value);
        } else if (key == "data file" || key == "datafile") {
            h.data_file = value;
        } else if (key == "line skip" || key == "lineskip") {
            auto n = parse_signed(value);
            if (!n || *n < 0) throw bad();
            h.line_skip = *n;
        } else if (key == "byte skip" || key == "byteskip") {
            auto n = parse_signed(value);
            if (!n || *n < -1) throw bad();
            h.byte_skip = *n;
        }
    }
    h.data_offset = lines.position();
    if (dimension && h.sizes.size() != *dimension)
        throw std::runtime_error(name + ": bad NRRD header: " + std::to_string(h.sizes.size()) +
                                 " sizes for dimension " + std::to_string(*dimension));
    if (h.sizes.empty()) throw std::runtime_error(name + ": bad NRRD header: no sizes field");
    return h;
}

void check_nrrd_data(const std::string& path, std::uint64_t memory_limit) {
    const auto prefix = read_file_prefix(path, 1 << 20);
    const auto h = parse_nrrd_header(prefix.data(), prefix.size(), path);
    if (!h) return;
    if (!h->type)
        throw std::runtime_error(path + ": unsupported NRRD type '" + h->type_name +
                                 "'; snert reads integer and float samples");
    check_grid(path, h->sizes, memory_limit);
    const std::string& file = h->data_file;
    if (lower(file).rfind("list", 0) == 0 || file.find('%') != std::string::npos ||
        file.find(' ') != std::string::npos || h->line_skip > 0)
        return; // slice lists, patterns and line skips: left to ITK
    const std::string data_path =
        file.empty() ? path : (file[0] == '/' ? file : folder_of(path) + file);
    std::uint64_t size = 0;
    try {
        size = file_size(data_path);
    } catch (const std::runtime_error&) {
        throw std::runtime_error(path + ": its data file " + data_path + " is missing");
    }
    const std::uint64_t start = (file.empty() ? h->data_offset : 0) +
                                std::uint64_t(std::max<std::int64_t>(h->byte_skip, 0));
    const std::uint64_t need = h->data_bytes();
    if (need == 0) return;
    if (h->encoding == "raw") {
        // byte skip -1: the samples are the last bytes of the file.
        const std::uint64_t have = h->byte_skip == -1 ? size : (size > start ? size - start : 0);
        if (have < need) throw_short(path, "NRRD", need, data_path, have);
    } else if (h->encoding == "gzip" || h->encoding == "gz") {
        const std::uint64_t produced = inflated_file_bytes(data_path, start, need);
        if (produced < need) throw_short(path, "NRRD", need, data_path, produced);
    }
}

// ---- DICOM
// ----------------------------------------------------------------------------------------

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

// ---- gzip / zlib
// ----------------------------------------------------------------------------------

bool has_gzip_magic(const std::uint8_t* bytes, std::size_t size) {
    return size >= 2 && bytes[0] == 0x1f && bytes[1] == 0x8b;
}

InflateCounter::InflateCounter(std::string name, std::uint64_t enough)
    : name_(std::move(name)), enough_(enough), stream_(new z_stream{}) {
    auto* z = static_cast<z_stream*>(stream_);
    if (inflateInit2(z, 15 + 32) != Z_OK) { // 15 + 32: zlib or gzip, detected from the header
        delete z;
        throw std::runtime_error(name_ + ": cannot start zlib");
    }
}

InflateCounter::~InflateCounter() {
    auto* z = static_cast<z_stream*>(stream_);
    inflateEnd(z);
    delete z;
}

bool InflateCounter::feed(const std::uint8_t* bytes, std::size_t size) {
    auto* z = static_cast<z_stream*>(stream_);
    unsigned char scratch[1 << 14];
    while (!done_ && size > 0) {
        const std::size_t chunk = std::min<std::size_t>(size, 1u << 30);
        z->next_in = const_cast<unsigned char*>(bytes);
        z->avail_in = unsigned(chunk);
        while (!done_ && z->avail_in > 0) {
            z->next_out = scratch;
            z->avail_out = sizeof scratch;
            const int status = inflate(z, Z_NO_FLUSH);
            produced_ += sizeof scratch - z->avail_out;
            if (status == Z_STREAM_END || produced_ >= enough_)
                done_ = true;
            else if (status == Z_BUF_ERROR)
                break; // needs more input
            else if (status != Z_OK)
                throw std::runtime_error(name_ + ": corrupt compressed data (" +
                                         (z->msg ? z->msg : "zlib error") + ")");
        }
        const std::size_t used = chunk - z->avail_in;
        bytes += used;
        size -= used;
        if (used == 0) break;
    }
    return !done_;
}

std::uint64_t inflated_file_bytes(const std::string& path, std::uint64_t offset,
                                  std::uint64_t enough) {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw std::runtime_error(path + ": cannot open");
    in.seekg(std::streamoff(offset));
    InflateCounter counter(path, enough);
    std::vector<std::uint8_t> chunk(1 << 16);
    while (in) {
        in.read(reinterpret_cast<char*>(chunk.data()), std::streamsize(chunk.size()));
        const auto got = std::size_t(in.gcount());
        if (got == 0 || !counter.feed(chunk.data(), got)) break;
    }
    return counter.produced();
}

// ---- Files
// ---------------------------------------------------------------------------------------

std::uint64_t file_size(const std::string& path) {
    struct stat st {};
    if (::stat(path.c_str(), &st) != 0) throw std::runtime_error(path + ": no such file");
    if (!S_ISREG(st.st_mode)) throw std::runtime_error(path + ": not a regular file");
    return std::uint64_t(st.st_size);
}

std::vector<std::uint8_t> read_file_prefix(const std::string& path, std::size_t max_bytes) {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw std::runtime_error(path + ": cannot open");
    std::vector<std::uint8_t> bytes;
    std::vector<char> chunk(std::min<std::size_t>(max_bytes, 1 << 16));
    while (bytes.size() < max_bytes && in) {
        const std::size_t want = std::min(chunk.size(), max_bytes - bytes.size());
        in.read(chunk.data(), std::streamsize(want));
        const auto got = std::size_t(in.gcount());
        bytes.insert(bytes.end(), chunk.begin(), chunk.begin() + std::ptrdiff_t(got));
        if (got < want) break;
    }
    return bytes;
}

std::string volume_extension(const std::string& path) {
    const std::size_t slash = path.find_last_of('/');
    const std::string file = lower(slash == std::string::npos ? path : path.substr(slash + 1));
    std::size_t dot = file.find_last_of('.');
    if (dot == std::string::npos || dot == 0) return "";
    if (file.compare(dot, std::string::npos, ".gz") == 0 && dot > 0) {
        const std::size_t inner = file.find_last_of('.', dot - 1);
        if (inner != std::string::npos && inner > 0) return file.substr(inner);
    }
    return file.substr(dot);
}

// ---- NIfTI data
// ----------------------------------------------------------------------------------

namespace {

struct GzFile {
    gzFile file = nullptr;
    explicit GzFile(const std::string& path) : file(gzopen(path.c_str(), "rb")) {
        if (file) gzbuffer(file, 1 << 18);
    }
    ~GzFile() {
        if (file) gzclose(file);
    }
    GzFile(const GzFile&) = delete;
    GzFile& operator=(const GzFile&) = delete;

    // Reads up to `size` bytes; returns how many were read, throws on a corrupt stream.
    std::uint64_t read(void* into, std::uint64_t size, const std::string& path) {
        std::uint64_t done = 0;
        auto* out = static_cast<unsigned char*>(into);
        while (done < size) {
            const unsigned chunk = unsigned(std::min<std::uint64_t>(size - done, 1u << 26));
            const int got = gzread(file, out + done, chunk);
            if (got < 0) {
                int code = 0;
                const char* message = gzerror(file, &code);
                throw std::runtime_error(path + ": corrupt gzip data (" +
                                         (message ? message : "zlib error") + ")");
            }
            done += std::uint64_t(got);
            if (unsigned(got) < chunk) break;
        }
        return done;
    }
};

void throw_truncated(const std::string& path, const NiftiHeader& h, std::uint64_t have) {
    const std::uint64_t need = h.voxels() * scalar_type_size(*h.type);
    throw std::runtime_error(path + ": truncated NIfTI: the header promises " +
                             std::to_string(need) + " data bytes from offset " +
                             std::to_string(h.vox_offset) + ", the file holds " +
                             std::to_string(have));
}

} // namespace

NiftiHeader read_nifti_header(const std::string& path) {
    GzFile gz(path);
    if (!gz.file) throw std::runtime_error(path + ": cannot open");
    std::uint8_t bytes[nifti_header_bytes];
    const std::uint64_t got = gz.read(bytes, sizeof bytes, path);
    return parse_nifti_header(bytes, std::size_t(got), path);
}

void read_nifti_samples(const std::string& path, const NiftiHeader& h, float* out,
                        const Progress& progress) {
    if (!h.type) throw std::logic_error("read_nifti_samples: unsupported datatype");
    GzFile gz(path);
    if (!gz.file) throw std::runtime_error(path + ": cannot open");
    // Skip to vox_offset by reading: gzseek would silently stop at the end of a short file.
    std::vector<unsigned char> skip(std::size_t(std::min<std::uint64_t>(h.vox_offset, 1 << 16)));
    for (std::uint64_t left = h.vox_offset; left > 0;) {
        const std::uint64_t want = std::min<std::uint64_t>(left, skip.size());
        if (gz.read(skip.data(), want, path) != want) throw_truncated(path, h, 0);
        left -= want;
    }
    const std::uint64_t count = h.voxels();
    const std::size_t size = scalar_type_size(*h.type);
    const std::uint64_t slab_samples = std::max<std::uint64_t>(1, (std::uint64_t(1) << 26) / size);
    if (size <= sizeof(float)) {
        auto* tail = static_cast<unsigned char*>(stored_tail(out, count, *h.type));
        for (std::uint64_t done = 0; done < count;) {
            const std::uint64_t n = std::min(slab_samples, count - done);
            if (gz.read(tail + done * size, n * size, path) != n * size)
                throw_truncated(path, h, done * size);
            done += n;
            progress.update(0.9f * float(done) / float(count));
        }
        convert_in_place(out, count, *h.type, h.endian);
    } else {
        std::vector<unsigned char> slab(std::size_t(slab_samples * size));
        for (std::uint64_t done = 0; done < count;) {
            const std::uint64_t n = std::min(slab_samples, count - done);
            if (gz.read(slab.data(), n * size, path) != n * size)
                throw_truncated(path, h, done * size);
            convert_samples(slab.data(), n, *h.type, h.endian, out + done);
            done += n;
            progress.update(0.9f * float(done) / float(count));
        }
    }
    if (h.rescales()) rescale_in_place(out, count, h.scl_slope, h.scl_inter);
}

} // namespace detail
} // namespace snert
