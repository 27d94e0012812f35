// Marching Cubes (Lorensen & Cline 1987) with a topologically consistent case table.
//
// Output: an indexed mesh in index space. Each vertex lies on a grid edge whose two samples are
// on different sides of the iso value, placed by linear interpolation, and is shared by every
// cell around that edge. Triangles are wound so normals point from inside to outside.
//
// Consistency: on a face with two diagonally opposite inside corners (an ambiguous face) the
// inside corners are always separated. Both cells sharing the face see the same four samples,
// so they make the same choice and the surface has no cracks: it is closed and edge-manifold
// wherever it does not reach the volume border, for any input including random noise.
//
// Samples exactly at iso count as inside. Their crossings would sit exactly on the sample,
// which makes zero-area triangles; such vertices are welded into one vertex per sample and the
// collapsed triangles dropped, so none is emitted.
//
// Work is organised as passes over z-slabs (classify/count, prefix sum, fill) as in VTK's
// flying edges; the output order does not depend on how slabs are scheduled.
#pragma once

#include "mesh.h"
#include "progress.h"
#include "segmentation.h"
#include "volume.h"

namespace snert {

struct MarchingCubesOptions {
    float iso = 0.0f;
    InsideIs inside = InsideIs::Above;
};

Mesh marching_cubes(const Volume& volume, const MarchingCubesOptions& options,
                    const Progress& progress = {});

} // namespace snert
