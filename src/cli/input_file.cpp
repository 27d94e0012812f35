// Volume files as command inputs: format options, loading, the iso suggestion and label maps.
//
// What goes to stderr (stdout stays for the command's results): one line describing the
// volume, the iso that was chosen when --iso is absent and why, and a warning when the NaN
// policy replaced samples.
#include "input_file.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <sstream>

#include "core/volume_stats.h"
#include "io/load_volume.h"
#include "input.h"

namespace snert::cli {

namespace {

// "A,B,C" as three values parsed by `parse`; UsageError naming the option otherwise.
template <class T, class Parse>
glm::vec<3, T> triple(const Args& args, const std::string& name, Parse parse) {
    const std::string text = *args.value(name);
    const auto parts = split(text, ',');
    if (parts.size() != 3)
        throw UsageError("--" + name + " takes three comma-separated values X,Y,Z, got '" + text +
                         "'");
    glm::vec<3, T> v;
    for (int a = 0; a < 3; ++a) {
        const std::string& part = parts[std::size_t(a)];
        std::size_t used = 0;
        bool ok = !part.empty();
        try {
            if (ok) v[a] = parse(part, &used);
        } catch (const std::exception&) {
            ok = false;
        }
        if (!ok || used != part.size())
            throw UsageError("--" + name + ": '" + part + "' is not a number (in '" + text + "')");
    }
    return v;
}

RawOptions raw_options(const Args& args) {
    RawOptions raw;
    raw.dims = triple<int>(
        args, "raw", [](const std::string& s, std::size_t* used) { return std::stoi(s, used); });
    for (int a = 0; a < 3; ++a)
        if (raw.dims[a] < 1)
            throw UsageError("--raw: every dimension must be at least 1, got '" +
                             *args.value("raw") + "'");
    if (!args.has("raw-type"))
        throw UsageError("--raw needs --raw-type uint8|int8|uint16|int16|uint32|int32|float32|"
                         "float64");
    try {
        raw.type = parse_scalar_type(*args.value("raw-type"));
    } catch (const std::invalid_argument& e) {
        throw UsageError(std::string("--raw-type: ") + e.what());
    }
    if (raw.type == ScalarType::UInt64 || raw.type == ScalarType::Int64)
        throw UsageError("--raw-type: 64-bit integers are not offered for raw data");
    if (args.has("raw-spacing")) {
        raw.spacing =
            triple<float>(args, "raw-spacing", [](const std::string& s, std::size_t* used) {
                return std::stof(s, used);
            });
        for (int a = 0; a < 3; ++a)
            if (!(raw.spacing[a] > 0.0f) || !std::isfinite(raw.spacing[a]))
                throw UsageError("--raw-spacing: every spacing must be positive, got '" +
                                 *args.value("raw-spacing") + "'");
    }
    raw.endian = args.choice("raw-endian", "little", {"little", "big"}) == "little" ? Endian::Little
                                                                                    : Endian::Big;
    return raw;
}

std::string describe(const VolumeInfo& info) {
    std::ostringstream out;
    out << info.path << ": " << info.format << " " << info.scalar_type << " " << info.dims.x << "x"
        << info.dims.y << "x" << info.dims.z << ", spacing " << info.spacing.x << "x"
        << info.spacing.y << "x" << info.spacing.z << " mm, values " << info.range.min << " .. "
        << info.range.max;
    if (info.files > 1) out << ", " << info.files << " files";
    if (!info.series_uid.empty()) out << ", series " << info.series_uid;
    return out.str();
}

LoadedVolume load(const std::string& path, const Args& args) {
    LoadOptions options;
    if (args.has("series")) options.dicom_series_uid = *args.value("series");
    LoadedVolume loaded =
        args.has("raw") ? open_raw(path, raw_options(args), options) : open_volume(path, options);
    std::cerr << "snert: " << describe(loaded.info) << "\n";
    if (loaded.info.nonfinite > 0)
        std::cerr << "snert: warning: " << path << ": " << loaded.info.nonfinite
                  << " NaN / infinite samples replaced (NaN and -inf by the smallest value, "
                     "+inf by the largest)\n";
    return loaded;
}

std::string list_labels(const std::vector<int>& labels) {
    std::string text;
    const std::size_t shown = std::min<std::size_t>(labels.size(), 40);
    for (std::size_t i = 0; i < shown; ++i) text += (i ? " " : "") + std::to_string(labels[i]);
    if (shown < labels.size()) text += " ...";
    return text.empty() ? "none" : text;
}

// --labels FILE --label N: the label's mask on the grey image's grid, and the default iso
// of the grey image at the mask's boundary.
void load_labels(const Args& args, Input& input) {
    if (!args.has("label")) throw UsageError("--labels needs --label N (the label to extract)");
    const std::string path = *args.value("labels");
    const int label = args.integer("label", 0, -2147483647, 2147483647);
    LoadOptions options;
    const LoadedVolume labels = open_volume(path, options);
    check_same_grid(input.volume, input.name, labels.volume, path);
    input.labels = segment_label(labels.volume, label);
    if (input.labels->count_inside() == 0)
        throw std::invalid_argument(
            path + ": label " + std::to_string(label) +
            " does not occur (labels present: " + list_labels(labels_present(labels.volume)) + ")");
    const BoundaryIso boundary = boundary_iso(input.volume, *input.labels);
    if (!args.has("inside")) input.inside = boundary.inside;
    if (const auto iso = args.number("iso")) {
        input.iso = *iso;
        return;
    }
    input.iso = boundary.iso;
    std::cerr << "snert: label " << label << " (" << input.labels->count_inside()
              << " voxels): grey mean " << boundary.inside_mean << " inside, "
              << boundary.outside_mean << " outside its boundary; iso " << boundary.iso
              << " (set --iso to change)\n";
}

} // namespace

std::set<std::string> file_input_options() {
    return {"raw", "raw-type", "raw-spacing", "raw-endian", "series"};
}

void load_file_input(const std::string& path, const Args& args, Input& input) {
    if (!args.has("raw"))
        for (const char* name : {"raw-type", "raw-spacing", "raw-endian"})
            if (args.has(name))
                throw UsageError(std::string("--") + name + " needs --raw DIMX,DIMY,DIMZ");
    if (args.has("label") && !args.has("labels"))
        throw UsageError("--label needs --labels FILE (the label map)");
    LoadedVolume loaded = load(path, args);
    input.volume = std::move(loaded.volume);
    if (args.has("labels")) {
        load_labels(args, input);
    } else if (const auto iso = args.number("iso")) {
        input.iso = *iso;
    } else {
        input.iso = suggest_iso(input.volume);
        std::cerr << "snert: no --iso given; using the Otsu threshold " << input.iso
                  << " of the histogram\n";
    }
    input.reference = first_order_distance(input.volume, input.iso);
    input.analytic_reference = false;
    input.reference_volume = 0.0;
}

} // namespace snert::cli
