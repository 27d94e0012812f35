// Marching Cubes (Lorensen & Cline 1987) with a topologically consistent case table.
//
// Output: an indexed mesh in index space (voxel (i, j, k) at the point (i, j, k)). Each vertex
// lies on a grid edge whose two samples are on different sides of the iso value, placed by
// linear interpolation, and is shared by every cell around that edge: one vertex per crossed
// edge or welded sample (below), none unreferenced. Triangles are wound counter-clockwise seen from
// outside: the normal cross(p1 - p0, p2 - p0) points from inside to outside. Inside is I >= iso for
// InsideIs::Above and I <= iso for InsideIs::Below; NaN samples are outside.
//
// Consistency: on a face with two diagonally opposite inside corners (an ambiguous face) the
// inside corners are always separated. Both cells sharing the face see the same four samples,
// so they make the same choice and the surface has no cracks: it is closed, consistently
// oriented and edge-manifold (every edge in exactly two triangles) wherever it does not reach
// the volume border, for any input including random noise. Where it reaches the border it is
// open there. The 256-case table is generated, not typed in; each cell's surface is one
// triangulated polygon per closed loop of crossed edges; without welding every diagonal runs
// through the cell's interior, so no two cells can share one.
//
// Samples exactly at iso count as inside. Their crossings sit exactly on the sample and would
// make zero-area triangles, so the crossings of such a sample are welded into one vertex on the
// sample, and each cell's loops are triangulated with them merged (a loop left with fewer than
// three vertices vanishes, and a sample whose loops all vanish gets no vertex). A weld is kept
// only if afterwards every edge at its vertex is in exactly two triangles, one per direction
// (one on the volume border).
// Where the object is zero samples thick (a plate or line of samples exactly at iso, two
// neighbours at iso whose grid edge the surface touches from two sides) welding would join
// surfaces along an edge; there the crossings stay separate. The surface stays edge-manifold
// at the price of zero-area triangles in those pinched spots: none in a plane through samples,
// 0 to 3 per 10 000 triangles on the test CT/MRI volumes at their integer iso values, about
// 2.5% in integer noise {0, 1, 2} at iso 1. A welded vertex may join two sheets at one point (a
// pinch: the mesh is then not vertex-manifold there). Vertices of samples not exactly at iso but
// closer to it than float resolution can still coincide with the sample (a geometric degeneracy
// only).
//
// Work is organised as passes over z-slabs (classify, count per slab, prefix sum, allocate
// exactly, fill) as in VTK's flying edges; each slab writes only its own output ranges, so the
// output order does not depend on how slabs are scheduled. Runs serially: several hundred
// Mvoxels/s on one core (whole rows of empty cells are skipped with word operations), so a
// thread pool would rarely pay. Progress is reported about once per slice and pass, and
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
