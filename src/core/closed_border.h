// Closed surfaces: the volume as if surrounded by one layer of outside, so that every surface
// that reaches the volume border is closed there, by Marching Cubes and by the net alike (as 3D
// Slicer pads a label map before it makes a surface). The padded volume has one more sample on
// each side and its origin moved one voxel back along every axis, so world coordinates do not
// change; the meshers, the relaxation and the metrics then run on it unchanged, and the caps on
// the border get the same relaxation, constraint and safeguard as the rest of the surface.
#pragma once

#include "segmentation.h"
#include "volume.h"

namespace snert {

// The value of a pad sample next to the border sample `value`: always outside by `rule` at
// `iso`. An inside sample is mirrored about the iso value (2 iso - value), so the trilinear
// iso-surface, Marching Cubes' vertices and the gradient term's linear model all put the cap
// half a voxel beyond the border sample, where the voxel ends; an outside sample is repeated,
// so the field there goes on as before (no crossing, no new gradient).
float outside_pad_value(float value, float iso, InsideIs rule);

// `volume` with one layer of samples on each side, each pad sample outside_pad_value() of the
// nearest border sample, and the origin moved so that world coordinates stay the same (index
// (i, j, k) of the padded volume is index (i - 1, j - 1, k - 1) of `volume`). Throws
// std::invalid_argument when the padded sample count would overflow.
Volume pad_outside(const Volume& volume, float iso, InsideIs rule);

// A segmentation with one layer of outside voxels on each side (same index shift).
Segmentation pad_outside(const Segmentation& segmentation);

} // namespace snert
