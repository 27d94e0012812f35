// libFuzzer target for snert's own header handling and raw reading (the parsers and size checks
// of src/io: nifti, metaimage, vtk_legacy, nrrd, dicom_pixel_data, gzip, numbered_series, sizes,
// sample_conversion; raw_volume.cpp; src/core/volume_stats.cpp): the code that stands between an
// untrusted file and an allocation. ITK is not linked (Debian's ITK headers do not compile with
// clang, and ITK is not instrumented); what ITK reads is only reached after these checks passed.
//
// The first input byte picks the target, the rest is its input. Every target may throw
// std::runtime_error / std::invalid_argument (that is the refusal path); anything else, a
// sanitizer report, a crash or a hang, is a bug.
//
// Built and run by tests/fuzz/run.sh (`make fuzz`).
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <string>
#include <vector>

#include <unistd.h>

#include "core/volume_stats.h"
#include "io/dicom_pixel_data.h"
#include "io/gzip.h"
#include "io/load_volume.h"
#include "io/metaimage.h"
#include "io/nifti.h"
#include "io/nrrd.h"
#include "io/numbered_series.h"
#include "io/raw_volume.h"
#include "io/sample_conversion.h"
#include "io/sizes.h"
#include "io/volume_checks.h"
#include "io/vtk_legacy.h"

using namespace snert;

namespace {

constexpr std::uint64_t kMemoryLimit = 64u << 20; // keeps every allocation small

// A scratch folder for the targets that read files, made once per process and removed at exit.
struct ScratchDir {
    std::string path;
    ScratchDir() {
        std::string pattern = (std::filesystem::temp_directory_path() / "snert-fuzz-XXXXXX");
        if (!::mkdtemp(pattern.data())) std::abort();
        path = pattern;
    }
    ~ScratchDir() {
        std::error_code ignored;
        std::filesystem::remove_all(path, ignored);
    }
};

const std::string& scratch_dir() {
    static const ScratchDir dir;
    return dir.path;
}

std::string write_scratch(const std::string& name, const std::uint8_t* data, std::size_t size) {
    const std::string path = scratch_dir() + "/" + name;
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(data), std::streamsize(size));
    return path;
}

std::uint64_t take_u64(const std::uint8_t*& data, std::size_t& size) {
    std::uint64_t v = 0;
    const std::size_t n = size < 8 ? size : 8;
    std::memcpy(&v, data, n);
    data += n;
    size -= n;
    return v;
}

const ScalarType kTypes[] = {ScalarType::UInt8,  ScalarType::Int8,   ScalarType::UInt16,
                             ScalarType::Int16,  ScalarType::UInt32, ScalarType::Int32,
                             ScalarType::UInt64, ScalarType::Int64,  ScalarType::Float32,
                             ScalarType::Float64};

void fuzz_conversion(const std::uint8_t* data, std::size_t size) {
    if (size < 2) return;
    const ScalarType type = kTypes[data[0] % 10];
    const Endian endian = data[1] & 1 ? Endian::Big : Endian::Little;
    data += 2;
    size -= 2;
    const std::size_t sample = scalar_type_size(type);
    const std::size_t count = size / sample;
    if (count == 0) return;
    std::vector<float> separate(count);
    detail::convert_samples(data, count, type, endian, separate.data());
    if (sample <= sizeof(float)) {
        std::vector<float> in_place(count);
        std::memcpy(detail::stored_tail(in_place.data(), count, type), data, count * sample);
        detail::convert_in_place(in_place.data(), count, type, endian);
        // Both paths must agree bit for bit (NaN payloads included).
        if (std::memcmp(in_place.data(), separate.data(), count * sizeof(float)) != 0) std::abort();
    }
}

// A small volume from the bytes: histogram, Otsu, the NaN policy, label helpers.
void fuzz_statistics(const std::uint8_t* data, std::size_t size) {
    if (size < 3) return;
    const glm::ivec3 dims(1 + data[0] % 6, 1 + data[1] % 6, 1 + data[2] % 6);
    data += 3;
    size -= 3;
    Volume v = make_volume(dims);
    for (std::size_t i = 0; i < v.samples.size() && (i + 1) * 4 <= size; ++i)
        std::memcpy(&v.samples[i], data + 4 * i, 4);
    Volume labels = v;
    const Histogram h = make_histogram(v, 1 + int(v.samples.size() % 300));
    const float otsu = otsu_threshold(h);
    if (h.total() > 0 && (otsu < h.lo || otsu > h.hi)) std::abort();
    (void)labels_present(labels);
    try {
        const NonFiniteCount n = apply_nonfinite_policy(v, NonFinitePolicy::Replace, "fuzz");
        for (float s : v.samples)
            if (!std::isfinite(s)) std::abort(); // the policy leaves no NaN or inf behind
        (void)n;
        Segmentation mask{dims, std::vector<std::uint8_t>(v.samples.size())};
        for (std::size_t i = 0; i < mask.inside.size(); ++i) mask.inside[i] = v.samples[i] > otsu;
        const BoundaryIso b = boundary_iso(v, mask);
        if (!(b.pairs > 0)) std::abort();
    } catch (const std::runtime_error&) {
    } catch (const std::invalid_argument&) {
    }
}

// Raw reading end to end: dims and type from the first bytes, the rest is the file.
void fuzz_raw(const std::uint8_t* data, std::size_t size) {
    if (size < 5) return;
    RawOptions raw;
    raw.dims = {1 + data[0] % 16, 1 + data[1] % 16, 1 + data[2] % 16};
    raw.type = kTypes[data[3] % 10];
    raw.endian = data[4] & 1 ? Endian::Big : Endian::Little;
    LoadOptions options;
    options.memory_limit_bytes = kMemoryLimit;
    const std::string path = write_scratch("raw7", data + 5, size - 5); // "raw8" never exists
    const Volume v = load_raw(path, raw, options);
    if (v.voxel_count() != std::size_t(raw.dims.x * raw.dims.y * raw.dims.z)) std::abort();
}

void fuzz_nifti_file(const std::uint8_t* data, std::size_t size) {
    const std::string path = write_scratch("f.nii", data, size);
    const detail::NiftiHeader h = detail::read_nifti_header(path);
    if (!h.type || h.voxels() > (1u << 20) || h.volumes() != 1) return;
    std::vector<float> out(std::size_t(h.voxels()));
    detail::read_nifti_samples(path, h, out.data(), Progress{});
}

void run(std::uint8_t target, const std::uint8_t* data, std::size_t size) {
    const std::string text(reinterpret_cast<const char*>(data), size);
    switch (target % 14) {
    case 0:
        (void)detail::parse_nifti_header(data, size, "fuzz");
        break;
    case 1:
        (void)detail::parse_metaimage_header(text, "fuzz").data_bytes();
        break;
    case 2: {
        const auto h = detail::parse_vtk_header(data, size, "fuzz");
        if (h && h->data_offset > size) std::abort();
        break;
    }
    case 3: {
        const auto h = detail::parse_nrrd_header(data, size, "fuzz");
        if (h && h->data_offset > size) std::abort();
        break;
    }
    case 4: {
        const bool big = size > 0 && (data[0] & 1);
        const std::uint64_t expected = take_u64(data, size) % 4096;
        const auto c = detail::check_dicom_pixel_data(data, size, expected, big);
        if (c.state != detail::PixelDataCheck::NotFound && c.value_offset > size) std::abort();
        break;
    }
    case 5: {
        detail::InflateCounter counter("fuzz", 1u << 20);
        counter.feed(data, size);
        break;
    }
    case 6:
        fuzz_conversion(data, size);
        break;
    case 7: {
        for (const auto& n : detail::numbered_name_candidates(text))
            (void)detail::numbered_path(n, n.number + 1);
        break;
    }
    case 8:
        (void)detail::parse_meminfo_available(text);
        break;
    case 9:
        fuzz_statistics(data, size);
        break;
    case 10: {
        const std::uint64_t x = take_u64(data, size), y = take_u64(data, size);
        const std::uint64_t z = take_u64(data, size);
        (void)detail::checked_dims("fuzz", x, y, z);
        break;
    }
    case 11:
        fuzz_raw(data, size);
        break;
    case 12:
        fuzz_nifti_file(data, size);
        break;
    case 13: {
        // The file-based checks, on the same bytes as NRRD, MetaImage and VTK files.
        const std::string nrrd = write_scratch("f.nrrd", data, size);
        const std::string mhd = write_scratch("f.mhd", data, size);
        const std::string vtk = write_scratch("f.vtk", data, size);
        try {
            detail::check_nrrd_data(nrrd, kMemoryLimit);
        } catch (const std::runtime_error&) {
        }
        try {
            detail::check_metaimage_data(mhd, kMemoryLimit);
        } catch (const std::runtime_error&) {
        }
        detail::check_vtk_data(vtk, kMemoryLimit);
        break;
    }
    }
}

} // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    if (size == 0) return 0;
    try {
        run(data[0], data + 1, size - 1);
    } catch (const std::runtime_error&) {
    } catch (const std::invalid_argument&) {
    }
    return 0;
}
