// NIfTI-1 / NIfTI-2 headers and samples, read by snert itself.
//
// This work is based on the published header layouts: NIfTI-1 (nifti1.h, NIfTI DFWG 2004) and
// NIfTI-2 (nifti2.h, 2011). Every read of the header is bounds-checked against the byte range
// given; the fuzz target relies on it.
#include "nifti.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <stdexcept>
#include <vector>

#include <zlib.h>

namespace snert::detail {

namespace {

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

} // namespace snert::detail
