// The one input model of the CLI and the app: what to open (a phantom, a volume file or DICOM
// folder, headerless raw data, a label map beside the grey image, a chosen DICOM series), and
// the opened input with everything both show and need before the methods run: the grey
// volume, the label's mask, the iso suggestion and why, the histogram, the accuracy reference.
// Whatever one of them can open, the other can, because both call open_source().
#pragma once

#include <cstddef>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "core/metrics.h"
#include "core/progress.h"
#include "core/segmentation.h"
#include "core/volume.h"
#include "core/volume_stats.h"
#include "load_volume.h"

namespace snert {

// What to open. Compared whole (operator==): the app reloads only when this changes.
struct SourceSpec {
    std::string input;             // "phantom:NAME", a volume file, a DICOM folder or a .dcm
    int phantom_size = 64;         // grid size of a phantom (phantoms only)
    std::optional<RawOptions> raw; // headerless raw data: how to read `input`
    std::string series_uid;        // DICOM folder: this SeriesInstanceUID; empty: the largest
    std::string labels;            // a label map on the same grid; empty: threshold the grey
    std::optional<int> label;      // the label to extract from `labels`
    // Resample to cubic voxels of this edge in mm before anything else (isotropic.h); 0: the
    // smallest spacing; empty: keep the stored grid. Files only: a phantom's voxels are cubic.
    std::optional<float> isotropic;
    std::size_t memory_limit = 0; // bytes a volume may take; 0: what the machine has
    bool operator==(const SourceSpec&) const = default;

    bool is_phantom() const;
};

// One label of a label map, as the label picker lists it.
struct LabelEntry {
    int value = 0;
    std::size_t voxels = 0;
    std::string name; // from the file's header extension where it carries one; else empty
};

// The accuracy reference: an unsigned distance in voxel units. It owns what it reads (the
// volume is shared), so a copy or a move of it, or of the Source, never dangles.
struct AccuracyReference {
    DistanceFunction distance; // empty: no reference
    bool analytic = false;     // the phantom's exact surface
    double volume = 0.0;       // enclosed volume of the exact surface (voxels^3), 0: unknown
};

struct Source {
    SourceSpec spec;
    std::string title;              // "phantom two-spheres, 64^3" or the file's name
    std::string description;        // one line: format, stored type, dims, spacing, value range
    std::optional<VolumeInfo> info; // files only
    std::shared_ptr<const Volume> volume; // the grey values
    // The label's mask (SourceSpec::labels with a label); null when thresholding the grey.
    std::shared_ptr<const Segmentation> mask;
    std::vector<LabelEntry> labels_present; // of the label map, ascending; empty without one
    float suggested_iso = 0.0f;             // the phantom's, the label boundary's, or Otsu's
    InsideIs suggested_inside = InsideIs::Above;
    std::string iso_reason; // one line: why suggested_iso (Otsu, label boundary means, phantom)
    Histogram histogram;    // of the grey values (128 bins)
    std::vector<std::string> warnings; // one line each, e.g. NaN samples replaced
    // The phantom's exact surface at suggested_iso (empty for files).
    AccuracyReference exact_reference;
    // close_border() padded `volume` and `mask` with one layer of outside (their dims are the
    // grid read + 2; world coordinates as read).
    bool border_closed = false;
};

// Opens `spec`. Throws std::invalid_argument (bad options: unknown phantom, raw dims, a label
// that does not occur, a series uid that is not there, isotropic resampling of a phantom) or
// std::runtime_error (the file: missing, truncated, not a volume, grids that differ; a cubic
// grid that would not fit in memory), each one line starting with the path;
// Cancelled when `progress` asks.
Source open_source(const SourceSpec& spec, const Progress& progress = {});

// The source with every surface closed at the volume border (core/closed_border.h), for both
// methods: the grey volume surrounded by one layer of samples outside at `iso` / `inside`
// (what Marching Cubes and the gradient term see), the label's mask by outside voxels, the
// phantom's exact reference moved with the grids' index shift. World coordinates stay as read;
// the histogram and the iso suggestion stay those of the volume read. The volume read is
// released when `source` held the only reference to it (so pass it with std::move); a source
// closed already is returned as it is.
Source close_border(Source source, float iso, InsideIs inside);

// Whether surfaces are closed at the border unless the user says otherwise: on for a label map
// (as 3D Slicer pads one), off for grey values (an open cut shows where the scan ends).
bool closes_border_by_default(const SourceSpec& spec);

// The grid as read: the volume's dims, less the padding of close_border().
glm::ivec3 read_dims(const Source& source);

// The reference accuracies are measured against at `iso`: the phantom's exact surface when
// iso is the phantom's own, else the first-order distance |I(p) - iso| / |grad I(p)| of the
// grey values (which keeps the volume alive through a shared pointer).
AccuracyReference accuracy_reference(const Source& source, float iso);

} // namespace snert
