// Loading the app's volumes: phantoms from core/phantom.h, files through io/load_volume.h
// (ITK) where the build has it.
#include "volume_source.h"

#include <cmath>
#include <filesystem>
#include <sstream>
#include <stdexcept>

#include "core/phantom.h"

#if __has_include("io/load_volume.h")
#include "core/volume_stats.h"
#include "io/load_volume.h"
#define SNERT_APP_HAVE_FILES 1
#endif

namespace snert::app {

namespace {

std::string grid_text(const Volume& v) {
    std::ostringstream out;
    out << v.dims.x << " x " << v.dims.y << " x " << v.dims.z << " voxels, spacing " << v.spacing.x
        << " x " << v.spacing.y << " x " << v.spacing.z << " mm";
    return out.str();
}

void describe(SourceVolume& source, const std::string& prefix) {
    const ValueRange range = value_range(*source.volume);
    std::ostringstream out;
    out << prefix << grid_text(*source.volume) << ", values " << range.min << " .. " << range.max;
    source.description = out.str();
    source.histogram = value_histogram(*source.volume);
}

SourceVolume load_phantom(const VolumeSpec& spec, std::string_view name) {
    Phantom phantom = make_phantom(name, spec.phantom_size);
    SourceVolume source;
    source.spec = spec;
    source.title =
        "phantom " + phantom.name + ", " + std::to_string(spec.phantom_size) + "\xC2\xB3";
    source.suggested_iso = phantom.iso;
    source.analytic = true;
    source.reference = phantom.reference_distance;
    source.reference_volume = phantom.reference_volume;
    source.volume = std::make_shared<const Volume>(std::move(phantom.volume));
    describe(source, "");
    return source;
}

SourceVolume load_file(const VolumeSpec& spec, const Progress& progress) {
#ifdef SNERT_APP_HAVE_FILES
    LoadOptions options;
    options.progress = progress;
    snert::LoadedVolume loaded = open_volume(spec.input, options);
    SourceVolume source;
    source.spec = spec;
    source.title = std::filesystem::path(spec.input).filename().string();
    if (source.title.empty()) source.title = spec.input;
    source.suggested_iso = suggest_iso(loaded.volume);
    source.volume = std::make_shared<const Volume>(std::move(loaded.volume));
    describe(source, loaded.info.format + " " + loaded.info.scalar_type + ", ");
    return source;
#else
    (void)progress;
    throw std::runtime_error(spec.input + ": reading volume files is not available in this build");
#endif
}

} // namespace

bool can_load_files() {
#ifdef SNERT_APP_HAVE_FILES
    return true;
#else
    return false;
#endif
}

ValueHistogram value_histogram(const Volume& volume, int bins) {
    ValueHistogram h;
    const ValueRange range = value_range(volume);
    h.lo = range.min;
    h.hi = range.max;
    h.counts.assign(std::size_t(std::max(bins, 1)), 0.0f);
    const float width = (h.hi - h.lo) / float(h.counts.size());
    for (const float v : volume.samples) {
        if (!std::isfinite(v)) continue;
        std::size_t bin = width > 0.0f ? std::size_t((v - h.lo) / width) : 0;
        if (bin >= h.counts.size()) bin = h.counts.size() - 1; // v == hi
        h.counts[bin] += 1.0f;
    }
    return h;
}

SourceVolume load_source(const VolumeSpec& spec, const Progress& progress) {
    if (spec.input.empty()) throw std::invalid_argument("no volume given");
    progress.update(0.0f);
    SourceVolume source;
    if (const std::string_view name = phantom_spec_name(spec.input); !name.empty())
        source = load_phantom(spec, name);
    else
        source = load_file(spec, progress);
    progress.update(1.0f);
    return source;
}

} // namespace snert::app
