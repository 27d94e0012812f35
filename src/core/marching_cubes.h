// Marching Cubes (Lorensen & Cline 1987) with a topologically consistent case table.
//
// Output: an indexed mesh in index space (voxel (i, j, k) at the point (i, j, k)). Each vertex
// lies on a grid edge whose two samples are on different sides of the iso value, placed by
// linear interpolation, and is shared by every cell around that edge: exactly one vertex per
// crossed edge, none unreferenced. Triangles are wound counter-clockwise seen from outside: the
// normal cross(p1 - p0, p2 - p0) points from inside to outside. Inside is I >= iso for
// InsideIs::Above and I <= iso for InsideIs::Below; NaN samples are outside.
//
// Consistency: on a face with two diagonally opposite inside corners (an ambiguous face) the
// inside corners are always separated. Both cells sharing the face see the same four samples,
// so they make the same choice and the surface has no cracks: it is closed, consistently
// oriented, edge-manifold (every edge in exactly two triangles) and vertex-manifold (the
// triangles around each vertex form one fan) wherever it does not reach the volume border, for
// any input including random noise. Where it reaches the border it is open there. The
// 256-case table is generated, not typed in; each cell's surface is one triangulated polygon
// per closed loop of crossed edges, every diagonal running through the cell's interior, so no
// two cells can share one. The mesh depends on the samples only through the segmentation
// (which samples are inside) and the crossing positions: its connectivity is that of the
// binary segmentation's case table, whatever the grey values.
//
// Samples exactly at iso count as inside, as if inside by an infinitesimal amount (a symbolic
// perturbation of the iso value): the crossings of such a sample stay separate vertices, each
// kept 2^-10 voxel off the sample along its edge (more for coordinates of 8192 and beyond; see
// crossing_margin in the .cpp), as is any crossing closer to a sample than that. Vertices
// therefore never coincide and no triangle is degenerate by the measure of metrics.h, on any
// input, at the price of a position error of at most 2^-10 voxel at such samples. A surface
// running through many samples (a plane through grid points) keeps a tiny cap of triangles
// around each of them, so its triangles are more and, on average, of lower quality than where
// it passes between samples.
//
// Work is organised as passes over z-slabs (classify, count per slab, prefix sum, allocate
// exactly, fill) as in VTK's flying edges; each slab writes only its own output ranges. The
// passes run over fixed chunks of slabs on up to one thread per core (parallel.h; a ThreadLimit
// caps it), and the output (vertex and triangle order, positions) is the same, bit for bit, for
// any thread count. Whole rows of empty cells are skipped with word operations. Progress is
// reported about once per slice and pass, one call at a time and increasing (the callback need
// not be thread-safe), and cancellation (Cancelled) is checked at the same points.
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
    float iso = 0.0f;                  // iso value, in the units of the samples
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
    std::uint8_t loop_edges[12] = {};       // the loops one after another, each in the order
                                            // of its polygon, counter-clockwise seen from outside
    std::uint8_t triangle_count = 0;        // sum over loops of (size - 2)
    std::uint8_t triangles[kMaxTriangles][3] = {}; // crossed edges, wound outward
};
const MarchingCubesCase& marching_cubes_case(unsigned inside_mask);
int cube_edge_corner(int edge, int end);

} // namespace detail

} // namespace snert
