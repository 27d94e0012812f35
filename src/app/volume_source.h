// The volumes the app opens: a phantom ("phantom:NAME" at a chosen size) or a file, loaded with
// what the app shows beside the iso slider (the value histogram, the suggested iso).
//
// GL-free; runs on the worker thread.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "core/metrics.h"
#include "core/progress.h"
#include "core/volume.h"

namespace snert::app {

// What to open: "phantom:NAME" (phantom_names() of core/phantom.h) or a volume file / DICOM
// folder. phantom_size is the grid size of a phantom (ignored for files).
struct VolumeSpec {
    std::string input;
    int phantom_size = 64;
    bool operator==(const VolumeSpec&) const = default;
};

// Counts of the volume's finite samples in equal-width bins over [lo, hi].
struct ValueHistogram {
    float lo = 0.0f, hi = 0.0f;
    std::vector<float> counts;
};

struct SourceVolume {
    VolumeSpec spec;
    std::string title;       // "phantom two-spheres, 64^3" or the file's name
    std::string description; // dims, spacing, value range (and format for files)
    std::shared_ptr<const Volume> volume;
    float suggested_iso = 0.0f;    // the phantom's iso, or Otsu's threshold for files
    bool analytic = false;         // phantoms: `reference` is the exact surface
    DistanceFunction reference;    // at suggested_iso, voxel units; empty for files
    double reference_volume = 0.0; // voxels^3, 0 when unknown
    ValueHistogram histogram;
};

// Loads `spec`. Throws std::invalid_argument / std::runtime_error naming the input and the
// problem (unknown phantom, unreadable file, a build without file support); Cancelled when
// `progress` asks.
SourceVolume load_source(const VolumeSpec& spec, const Progress& progress = {});

// Equal-width histogram of the finite samples (bins >= 1).
ValueHistogram value_histogram(const Volume& volume, int bins = 128);

// True when this build can read volume files (ITK); phantoms always work.
bool can_load_files();

} // namespace snert::app
