// The one input model of the CLI and the app (see source.h): phantoms from core/phantom.h,
// files through load_volume.h, label maps beside the grey image, the iso suggestion and the
// accuracy reference.
#include "source.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>
#include <sstream>
#include <stdexcept>

#include "core/closed_border.h"
#include "core/phantom.h"
#include "core/pipeline.h"
#include "isotropic.h"
#include "nifti_label_names.h"

namespace snert {

namespace {

std::string grid_text(const Volume& v) {
    std::ostringstream out;
    out << v.dims.x << "x" << v.dims.y << "x" << v.dims.z << ", spacing " << v.spacing.x << "x"
        << v.spacing.y << "x" << v.spacing.z << " mm";
    return out.str();
}

std::string range_text(const Volume& v) {
    const ValueRange range = value_range(v);
    std::ostringstream out;
    out << "values " << range.min << " .. " << range.max;
    return out.str();
}

void open_phantom(Source& source, std::string_view name) {
    const SourceSpec& spec = source.spec;
    if (spec.raw) throw std::invalid_argument(spec.input + ": raw options apply to files only");
    if (!spec.series_uid.empty())
        throw std::invalid_argument(spec.input + ": a series applies to DICOM folders only");
    if (!spec.labels.empty() || spec.label)
        throw std::invalid_argument(spec.input + ": a label map needs a volume file");
    if (spec.isotropic)
        throw std::invalid_argument(spec.input + ": isotropic resampling applies to volume "
                                                 "files; a phantom's voxels are cubic already");
    Phantom phantom = make_phantom(name, spec.phantom_size);
    // A teaching phantom has its own small grid, whatever the size asked for.
    const glm::ivec3 d = phantom.volume.dims;
    source.title =
        "phantom " + phantom.name + ", " +
        (d.x == d.y && d.y == d.z ? std::to_string(d.x) + "\xC2\xB3"
                                  : std::to_string(d.x) + "\xC3\x97" + std::to_string(d.y) +
                                        "\xC3\x97" + std::to_string(d.z));
    source.suggested_iso = phantom.iso;
    source.suggested_inside = InsideIs::Above;
    std::ostringstream reason;
    reason << "the phantom's own iso " << phantom.iso << " (its exact surface)";
    source.iso_reason = reason.str();
    source.exact_reference.distance = phantom.reference_distance;
    source.exact_reference.analytic = true;
    source.exact_reference.volume = phantom.reference_volume;
    source.volume = std::make_shared<const Volume>(std::move(phantom.volume));
    source.description = "phantom " + phantom.name + " " + grid_text(*source.volume) + ", " +
                         range_text(*source.volume);
}

std::string describe(const VolumeInfo& info) {
    std::ostringstream out;
    out << info.format << " " << info.scalar_type << " " << info.dims.x << "x" << info.dims.y << "x"
        << info.dims.z << ", spacing " << info.spacing.x << "x" << info.spacing.y << "x"
        << info.spacing.z << " mm, values " << info.range.min << " .. " << info.range.max;
    if (info.files > 1) out << ", " << info.files << " files";
    if (!info.series_uid.empty()) out << ", series " << info.series_uid;
    return out.str();
}

// The labels of a label map with their voxel counts (rounded to the nearest integer, as
// segment_label compares) and their names where the file carries them.
std::vector<LabelEntry> count_labels(const Volume& labels, const std::string& path) {
    std::map<int, std::size_t> counts;
    for (const float v : labels.samples) {
        if (!std::isfinite(v) || std::abs(v) > 2.0e9f) continue;
        ++counts[int(std::nearbyint(v))];
    }
    const std::map<int, std::string> names = nifti_label_names(path);
    std::vector<LabelEntry> entries;
    entries.reserve(counts.size());
    for (const auto& [value, voxels] : counts) {
        LabelEntry e{value, voxels, {}};
        if (const auto it = names.find(value); it != names.end()) e.name = it->second;
        entries.push_back(std::move(e));
    }
    return entries;
}

std::string list_labels(const std::vector<LabelEntry>& labels) {
    std::string text;
    const std::size_t shown = std::min<std::size_t>(labels.size(), 40);
    for (std::size_t i = 0; i < shown; ++i) {
        if (i) text += ", ";
        text += std::to_string(labels[i].value);
        if (!labels[i].name.empty()) text += " " + labels[i].name;
    }
    if (shown < labels.size()) text += ", ...";
    return text.empty() ? "none" : text;
}

// `stored` is the grey image's grid as the file holds it (its samples are not read); with
// `cubic`, the label's mask is resampled to it, where the grey values already are.
void open_labels(Source& source, const LoadOptions& options, const Volume& stored,
                 const std::optional<IsotropicGrid>& cubic) {
    const SourceSpec& spec = source.spec;
    const std::string& path = spec.labels;
    LoadOptions label_options;
    label_options.memory_limit_bytes = options.memory_limit_bytes;
    label_options.progress = options.progress;
    const LoadedVolume labels = open_volume(path, label_options);
    check_same_grid(stored, spec.input, labels.volume, path);
    source.labels_present = count_labels(labels.volume, path);
    if (!spec.label) return;
    const int label = *spec.label;
    const auto entry = std::find_if(source.labels_present.begin(), source.labels_present.end(),
                                    [&](const LabelEntry& e) { return e.value == label; });
    if (entry == source.labels_present.end())
        throw std::invalid_argument(
            path + ": label " + std::to_string(label) +
            " does not occur (labels present: " + list_labels(source.labels_present) + ")");
    auto mask = std::make_shared<Segmentation>(segment_label(labels.volume, label));
    if (cubic) *mask = resample_mask(*mask, stored, *cubic);
    const BoundaryIso boundary = boundary_iso(*source.volume, *mask);
    source.mask = std::move(mask);
    source.suggested_iso = boundary.iso;
    source.suggested_inside = boundary.inside;
    std::ostringstream reason;
    reason << "label " << label;
    if (!entry->name.empty()) reason << " " << entry->name;
    reason << " (" << entry->voxels << " voxels): grey mean " << boundary.inside_mean << " inside, "
           << boundary.outside_mean << " outside its boundary; iso " << boundary.iso;
    source.iso_reason = reason.str();
}

void open_file(Source& source, const Progress& progress) {
    const SourceSpec& spec = source.spec;
    if (spec.label && spec.labels.empty())
        throw std::invalid_argument(spec.input + ": a label needs a label map");
    LoadOptions options;
    options.dicom_series_uid = spec.series_uid;
    options.memory_limit_bytes = spec.memory_limit;
    options.progress = progress;
    LoadedVolume loaded =
        spec.raw ? open_raw(spec.input, *spec.raw, options) : open_volume(spec.input, options);
    source.title = std::filesystem::path(spec.input).filename().string();
    if (source.title.empty()) source.title = spec.input;
    source.description = describe(loaded.info);
    if (loaded.info.nonfinite > 0)
        source.warnings.push_back(spec.input + ": " + std::to_string(loaded.info.nonfinite) +
                                  " NaN / infinite samples replaced (NaN and -inf by the "
                                  "smallest value, +inf by the largest)");
    source.info = std::move(loaded.info);
    // The stored grid, for the label map's check; the grey values are resampled first.
    Volume stored;
    stored.dims = loaded.volume.dims;
    stored.spacing = loaded.volume.spacing;
    stored.origin = loaded.volume.origin;
    stored.direction = loaded.volume.direction;
    std::optional<IsotropicGrid> cubic;
    if (spec.isotropic) {
        cubic = isotropic_grid(spec.input, loaded.volume, *spec.isotropic);
        if (on_grid(loaded.volume, *cubic)) {
            source.description += "; its voxels are cubic already";
            cubic.reset();
        } else {
            const bool with_mask = !spec.labels.empty() && spec.label;
            check_isotropic_memory(spec.input, loaded.volume, *cubic, with_mask, spec.memory_limit);
            loaded.volume = resample_linear(loaded.volume, *cubic);
            const glm::ivec3 d = cubic->dims;
            std::ostringstream text;
            text << "; resampled to " << d.x << "x" << d.y << "x" << d.z << ", cubic voxels of "
                 << cubic->edge << " mm";
            source.description += text.str();
        }
    }
    source.volume = std::make_shared<const Volume>(std::move(loaded.volume));
    if (!spec.labels.empty()) open_labels(source, options, stored, cubic);
}

// The histogram shown (128 bins) and, for a grey-value file, the iso suggestion (suggest_iso()'s
// Otsu threshold) from one pass over the samples: the one shown is the fine one merged.
void measure_histograms(Source& source) {
    // A file's loader measured the range already; a phantom's is measured here.
    const ValueRange range = source.info ? source.info->range : value_range(*source.volume);
    const Histogram fine = make_histogram(*source.volume, kIsoSuggestionBins, range);
    source.histogram = merge_bins(fine, 2);
    if (source.spec.is_phantom() || source.mask) return; // they have their own iso
    source.suggested_iso = otsu_threshold(fine);
    source.suggested_inside = InsideIs::Above;
    std::ostringstream reason;
    reason << "the Otsu threshold " << source.suggested_iso << " of the histogram";
    source.iso_reason = reason.str();
}

} // namespace

bool SourceSpec::is_phantom() const {
    return !phantom_spec_name(input).empty();
}

Source open_source(const SourceSpec& spec, const Progress& progress) {
    if (spec.input.empty()) throw std::invalid_argument("no volume given");
    progress.update(0.0f);
    Source source;
    source.spec = spec;
    if (const std::string_view name = phantom_spec_name(spec.input); !name.empty())
        open_phantom(source, name);
    else
        open_file(source, progress);
    measure_histograms(source);
    progress.update(1.0f);
    return source;
}

Source close_border(Source source, float iso, InsideIs inside) {
    if (source.border_closed || !source.volume) return source;
    source.volume = std::make_shared<const Volume>(pad_outside(*source.volume, iso, inside));
    if (source.mask) source.mask = std::make_shared<const Segmentation>(pad_outside(*source.mask));
    if (DistanceFunction exact = std::move(source.exact_reference.distance)) {
        // Index (i, j, k) of the padded grid is (i - 1, j - 1, k - 1) of the phantom's.
        source.exact_reference.distance = [exact = std::move(exact)](glm::vec3 p) {
            return exact(p - 1.0f);
        };
    }
    source.border_closed = true;
    return source;
}

bool closes_border_by_default(const SourceSpec& spec) {
    return !spec.labels.empty();
}

glm::ivec3 read_dims(const Source& source) {
    if (!source.volume) return glm::ivec3(0);
    return source.border_closed ? source.volume->dims - 2 : source.volume->dims;
}

AccuracyReference accuracy_reference(const Source& source, float iso) {
    if (source.exact_reference.distance && iso == source.suggested_iso)
        return source.exact_reference;
    if (!source.volume) return {};
    AccuracyReference reference;
    reference.distance = first_order_distance(source.volume, iso);
    return reference;
}

} // namespace snert
