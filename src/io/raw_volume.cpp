// Headerless raw volumes: one file or a numbered series of slice files (no ITK).
//
// Nothing in a raw file says what it holds, so the sizes are the only check there is: a single
// file must hold exactly dims.x * dims.y * dims.z samples, each slice file of a series exactly
// one slice. Anything else is refused before the grid is allocated, naming the sizes.
#include "raw_volume.h"

#include <cmath>
#include <cstdio>
#include <memory>
#include <stdexcept>
#include <vector>

#include <unistd.h>

#include "core/huge_pages.h"
#include "file_bytes.h"
#include "numbered_series.h"
#include "sizes.h"
#include "volume_checks.h"

namespace snert {

namespace {

struct FileCloser {
    void operator()(std::FILE* f) const { std::fclose(f); }
};

// Reads exactly `size` bytes of `path` into `into`; throws naming the file when it is short.
void read_exact(const std::string& path, void* into, std::uint64_t size) {
    std::unique_ptr<std::FILE, FileCloser> file(std::fopen(path.c_str(), "rb"));
    if (!file) throw std::runtime_error(path + ": cannot open");
    const std::uint64_t got = std::fread(into, 1, std::size_t(size), file.get());
    if (got != size)
        throw std::runtime_error(path + ": short read: expected " + std::to_string(size) +
                                 " bytes, got " + std::to_string(got));
}

void check_raw_options(const RawOptions& raw) {
    for (int a = 0; a < 3; ++a) {
        if (raw.dims[a] < 1)
            throw std::invalid_argument("raw dimensions must be at least 1 along each axis, got " +
                                        std::to_string(raw.dims.x) + "," +
                                        std::to_string(raw.dims.y) + "," +
                                        std::to_string(raw.dims.z));
        if (!(raw.spacing[a] > 0.0f) || !std::isfinite(raw.spacing[a]))
            throw std::invalid_argument("raw spacing must be positive and finite along each axis");
    }
}

std::string describe(const RawOptions& raw) {
    return std::to_string(raw.dims.x) + " x " + std::to_string(raw.dims.y) + " x " +
           std::to_string(raw.dims.z) + " " + scalar_type_name(raw.type) + " samples";
}

// The files of the volume, in z order: [path] for one file, or the numbered slice series.
std::vector<std::string> raw_files(const std::string& path, const RawOptions& raw) {
    const std::uint64_t slice =
        std::uint64_t(raw.dims.x) * std::uint64_t(raw.dims.y) * scalar_type_size(raw.type);
    const std::uint64_t total = slice * std::uint64_t(raw.dims.z);
    const std::uint64_t size = detail::file_size(path);
    if (size == total) return {path};
    if (size != slice || raw.dims.z == 1)
        throw std::runtime_error(path + ": holds " + std::to_string(size) + " bytes, but " +
                                 describe(raw) + " need " + std::to_string(total) + " bytes (or " +
                                 std::to_string(slice) +
                                 " bytes per file for a numbered slice series)");
    const auto candidates = detail::numbered_name_candidates(path);
    if (candidates.empty())
        throw std::runtime_error(path + ": holds one slice (" + std::to_string(slice) +
                                 " bytes) but its name has no number to count the series from");
    // The number that counts: the first candidate whose next file exists.
    const detail::NumberedName* name = &candidates.front();
    for (const auto& c : candidates)
        if (::access(detail::numbered_path(c, c.number + 1).c_str(), F_OK) == 0) {
            name = &c;
            break;
        }
    std::vector<std::string> files;
    files.reserve(std::size_t(raw.dims.z));
    for (int k = 0; k < raw.dims.z; ++k) {
        const std::string file = detail::numbered_path(*name, name->number + std::uint64_t(k));
        std::uint64_t file_bytes = 0;
        try {
            file_bytes = detail::file_size(file);
        } catch (const std::runtime_error&) {
            throw std::runtime_error(path + ": slice series stops at " + std::to_string(k) +
                                     " of " + std::to_string(raw.dims.z) + " files: " + file +
                                     " is missing");
        }
        if (file_bytes != slice)
            throw std::runtime_error(file + ": holds " + std::to_string(file_bytes) +
                                     " bytes, a slice of " + describe(raw) + " needs " +
                                     std::to_string(slice));
        files.push_back(file);
    }
    return files;
}

} // namespace

LoadedVolume open_raw(const std::string& path, const RawOptions& raw, const LoadOptions& options) {
    check_raw_options(raw);
    const glm::ivec3 dims = detail::checked_dims(
        path, std::uint64_t(raw.dims.x), std::uint64_t(raw.dims.y), std::uint64_t(raw.dims.z));
    const std::vector<std::string> files = raw_files(path, raw);
    const std::size_t sample_size = scalar_type_size(raw.type);
    const bool in_place = sample_size <= sizeof(float);
    const std::uint64_t per_file =
        std::uint64_t(dims.x) * std::uint64_t(dims.y) * std::uint64_t(dims.z / int(files.size()));
    // 8-byte samples cannot be widened in place: they pass through one file-sized buffer.
    detail::check_memory(path, dims, in_place ? 0 : per_file * sample_size,
                         options.memory_limit_bytes);

    LoadedVolume result;
    Volume& volume = result.volume;
    volume.dims = dims;
    volume.spacing = raw.spacing;
    detail::resize_on_huge_pages(volume.samples, volume.voxel_count());
    float* out = volume.samples.data();
    auto* tail = static_cast<unsigned char*>(
        in_place ? detail::stored_tail(out, volume.voxel_count(), raw.type) : nullptr);
    std::vector<unsigned char> scratch(in_place ? 0 : std::size_t(per_file * sample_size));
    for (std::size_t f = 0; f < files.size(); ++f) {
        if (in_place) {
            read_exact(files[f], tail + f * per_file * sample_size, per_file * sample_size);
        } else {
            read_exact(files[f], scratch.data(), scratch.size());
            detail::convert_samples(scratch.data(), std::size_t(per_file), raw.type, raw.endian,
                                    out + f * per_file);
        }
        options.progress.update(0.9f * float(f + 1) / float(files.size()));
    }
    if (in_place) detail::convert_in_place(out, volume.voxel_count(), raw.type, raw.endian);

    VolumeInfo& info = result.info;
    if (raw.type == ScalarType::Float32 || raw.type == ScalarType::Float64)
        info.nonfinite = apply_nonfinite_policy(volume, options.nonfinite, path).total();
    info.path = path;
    info.format = "raw";
    info.scalar_type = scalar_type_name(raw.type);
    info.dims = volume.dims;
    info.spacing = volume.spacing;
    info.origin = volume.origin;
    info.direction = volume.direction;
    info.range = value_range(volume);
    info.files = files.size();
    options.progress.update(1.0f);
    return result;
}

Volume load_raw(const std::string& path, const RawOptions& raw, const LoadOptions& options) {
    return open_raw(path, raw, options).volume;
}

} // namespace snert
