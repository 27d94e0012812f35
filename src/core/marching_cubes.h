// Marching Cubes (Lorensen & Cline 1987) with a topologically consistent case table.
//
// Output: an indexed mesh in index space (voxel (i, j, k) at the point (i, j, k)). Each vertex
// lies on a grid edge whose two samples are on different sides of the iso value, placed by
// linear interpolation, and is shared by every cell around that edge (no duplicate vertices,
// no unreferenced vertices). Triangles are wound counter-clockwise seen from outside: the
// normal cross(p1 - p0, p2 - p0) points from inside to outside. Inside is I >= iso for
// InsideIs::Above and I <= iso for InsideIs::Below; NaN samples are outside.
//
// Consistency: on a face with two diagonally opposite inside corners (an ambiguous face) the
// inside corners are always separated. Both cells sharing the face see the same four samples,
// so they make the same choice and the surface has no cracks: it is closed, consistently
// oriented and edge-manifold (every edge in exactly two triangles) wherever it does not reach
// the volume border, for any input including random noise. Where it reaches the border it is
// open there. The 256-case table is generated, not typed in; each cell's surface is one
// triangulated polygon per closed loop of crossed edges.
//
// Samples exactly at iso count as inside. Their crossings sit exactly on the sample and would
// make zero-area triangles; such crossings are welded into one vertex per sample (placed on the
// sample) and the triangles that collapse are dropped. Welding is skipped for a sample whose two
// neighbours along some axis are both outside (the object is zero voxels thick there), because
// merging the two sides could put one edge into four triangles; such pinched spots keep the
// surface manifold at the price of a few zero-area triangles. Ordinary data (and any sample
// with at most one outside neighbour per axis, e.g. any plane) gets no zero-area triangle.
// Vertices of samples that are not exactly at iso but closer to it than float resolution can
// still coincide with the sample (a geometric, not a topological, degeneracy).
//
// Work is organised as passes over z-slabs (classify, count per slab, prefix sum, allocate
// exactly, fill) as in VTK's flying edges; each slab writes only its own output ranges, so the
// output order does not depend on how slabs are scheduled. Runs serially (hundreds of
// Mvoxels/s on one core, see the .cpp); progress is reported about once per slice and
// cancellation (Cancelled) is checked at the same points.
//
// Throws std::invalid_argument when the sample count does not match the dimensions or the iso
// value is NaN. Volumes thinner than 2 samples along an axis have no cells: empty mesh.
#pragma once

#include <cstdint>

#include "mesh.h"
#include "progress.h"
#include "segmentation.h"
#include "volume.h"

namespace snert {

struct MarchingCubesOptions {
    float iso = 0.0f;                // iso value, in the units of the samples
    InsideIs inside = InsideIs::Above; // which side of iso is the object
};

Mesh marching_cubes(const Volume& volume, const MarchingCubesOptions& options,
                    const Progress& progress = {});

namespace detail {

// The generated case table, exposed so that tests can check how it is built.
//
// Cell corner c sits at offset (c & 1, (c >> 1) & 1, (c >> 2) & 1) from the cell's first
// sample; a case is the 8-bit mask of inside corners. Edge e runs along axis e / 4 (x, y, z);
// bit 0 and bit 1 of e % 4 are its offsets along the two other axes, lower axis first.
// cube_edge_corner(e, 0) is its lower corner, cube_edge_corner(e, 1) its upper one.
struct MarchingCubesCase {
    static constexpr int kMaxLoops = 4;
    static constexpr int kMaxTriangles = 12;
    std::uint8_t loop_count = 0;
    std::uint8_t loop_size[kMaxLoops] = {}; // crossed edges per loop (at least 3)
    std::uint8_t loop_edges[12] = {};      // the loops one after another, each in the order
                                           // of its polygon, counter-clockwise seen from outside
    std::uint8_t triangle_count = 0;       // sum over loops of (size - 2)
    std::uint8_t triangles[kMaxTriangles][3] = {}; // crossed edges, wound outward
};
const MarchingCubesCase& marching_cubes_case(unsigned inside_mask);
int cube_edge_corner(int edge, int end);

// A case with welded corners (a subset of the inside corners, exactly at iso): in each loop the
// crossings of a welded corner are merged into one vertex, loops left with fewer than three
// vertices vanish and the rest are triangulated again. A triangle corner is a crossed edge; if
// its inside corner is welded, it stands for that corner's vertex.
struct WeldedCase {
    std::uint8_t triangle_count = 0;
    std::uint8_t used_corners = 0; // welded corners that some triangle uses
    std::uint8_t triangles[MarchingCubesCase::kMaxTriangles][3] = {};
};
const WeldedCase& welded_case(unsigned inside_mask, unsigned welded_mask);

} // namespace detail

} // namespace snert
