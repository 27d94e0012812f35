// Resampling an anisotropic scan (thick slices: 1 x 1 x 4.8 mm) to cubic voxels before anything
// else runs, so the net's cells, and with them its triangles, are not stretched along one axis.
// Grey values are interpolated linearly (ITK's ResampleImageFilter); a label's mask is resampled
// the same way as a 0/1 image and cut at 0.5.
//
// The cubic grid keeps the stored grid's origin (sample 0 stays where the scanner put it) and
// direction; along each axis it has as many samples as fit in the stored extent, so every new
// sample lies inside the stored grid (nothing is extrapolated) and the far end of the world
// extent is kept to within one new voxel (exactly when the extent is a multiple of the edge).
//
// No ITK type in this header; isotropic.cpp is one of the sources that include ITK. Results do
// not depend on the thread count: every output sample is computed on its own, and ITK splits the
// grid into whole rows.
#pragma once

#include <cstdint>
#include <string>

#include <glm/glm.hpp>

#include "core/segmentation.h"
#include "core/volume.h"

namespace snert {

// The grid of cubic voxels a volume is resampled to.
struct IsotropicGrid {
    glm::ivec3 dims{0};
    float edge = 0.0f; // mm; the spacing along every axis
    glm::vec3 origin{0.0f};
    glm::mat3 direction{1.0f};
};

// The cubic grid for `volume` with voxels of `edge_mm` (0: the volume's smallest spacing).
// Throws std::runtime_error "<name>: resampling to cubic voxels of E mm: ..." when the edge is
// not a positive finite number or an axis would hold more samples than snert can address.
IsotropicGrid isotropic_grid(const std::string& name, const Volume& volume, float edge_mm);

// True when the volume's samples already lie on `grid` (resampling would change nothing).
bool on_grid(const Volume& volume, const IsotropicGrid& grid);

// Bytes the resampling takes at its peak beyond the stored volume: the new float32 grid and
// ITK's output buffer it is copied from; with `with_mask`, also the stored mask as a 0/1 float
// image, its resampled float image and the new mask. Saturates instead of overflowing.
std::uint64_t isotropic_bytes_needed(const Volume& volume, const IsotropicGrid& grid,
                                     bool with_mask);

// Refuses, before anything is allocated, a resampling whose isotropic_bytes_needed exceed
// `limit_bytes` (0: the memory available, sizes.h). The std::runtime_error is one line:
// "<name>: resampling to cubic voxels of E mm: 256 x 256 x 35 samples (spacing 1 x 1 x 4.8 mm)
// would become 256 x 256 x 164, which need 82.0 MiB, but only ... of memory is available".
void check_isotropic_memory(const std::string& name, const Volume& volume,
                            const IsotropicGrid& grid, bool with_mask, std::uint64_t limit_bytes);

// The grey values on `grid`, interpolated linearly.
Volume resample_linear(const Volume& volume, const IsotropicGrid& grid);

// A mask on the grid of `geometry` (its samples are not read) resampled to `grid`: the 0/1
// image interpolated linearly, inside where the result is >= 0.5.
Segmentation resample_mask(const Segmentation& mask, const Volume& geometry,
                           const IsotropicGrid& grid);

} // namespace snert
