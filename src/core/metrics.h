// Mesh metrics: triangle quality, smoothness, accuracy and topology, as plain structs.
//
// Quality of a triangle, three ways (1 = equilateral, 0 = degenerate):
//   quality        smallest angle / largest angle, the paper's measure (section 3);
//   quality60      smallest angle / 60 degrees;
//   radius_ratio   2 r / R (inradius over circumradius), as in Verdict.
// Smoothness (paper section 3): mean over interior manifold vertices of |2 pi - sum of the
// angles of the incident triangles| (radians; best case 0, a plane).
// Accuracy (paper eq. 7): mean distance of the vertices, and of the face centres, to a reference
// surface, given as a distance function; and the same over the whole surface, area-weighted.
// The vertex figure alone flatters Marching Cubes: its vertices lie on the trilinear
// iso-surface by construction, so their first-order distance is ~0 whatever the triangles do.
//
// Every function here is a pure analyser of a Mesh: it returns a plain struct and changes
// nothing. Large meshes (millions of triangles) are processed on all hardware threads, in chunks
// whose boundaries do not depend on the thread count, so results are the same on every machine.
// All functions throw std::invalid_argument when an index is out of range or the index count is
// not a multiple of 3.
#pragma once

#include <array>
#include <cstddef>
#include <functional>
#include <limits>
#include <memory>
#include <optional>
#include <span>
#include <string_view>
#include <vector>

#include <glm/glm.hpp>

#include "mesh.h"

namespace snert {

// A triangle is degenerate when its height over its longest edge is below this fraction of
// that edge (2 * area <= kDegenerateHeightRatio * longest^2): exactly flat triangles, triangles
// with coincident corners, and slivers flatter than float coordinates can resolve. A
// non-finite corner also makes a triangle degenerate.
inline constexpr double kDegenerateHeightRatio = 1e-6;

struct TriangleShape {
    float quality = 0;       // smallest / largest angle (best 1, 0 when degenerate)
    float quality60 = 0;     // smallest angle / 60 degrees (best 1, 0 when degenerate)
    float radius_ratio = 0;  // 2 r / R (best 1, 0 when degenerate)
    float min_angle = 0;     // degrees (best 60, 0 when degenerate)
    float area = 0;          // the true area, also when degenerate (0 when not finite)
    bool degenerate = false; // see kDegenerateHeightRatio
    float max_angle = 180;   // degrees (best 60, 180 when degenerate)
    // Verdict's aspect ratio: longest edge * perimeter / (4 sqrt(3) area) (best 1, infinite
    // when degenerate).
    float aspect_ratio = std::numeric_limits<float>::infinity();
};
// Angles are computed in double as atan2(|cross|, dot), exact also for needle triangles
// (vector_angle.h: within 2 units in the last place of the C library's atan2).
TriangleShape triangle_shape(glm::vec3 a, glm::vec3 b, glm::vec3 c);

// Per-triangle smallest/largest angle, the quantity the views colour by (0 for degenerate).
std::vector<float> triangle_quality(const Mesh& mesh);

inline constexpr int kQualityBins = 20;

// The per-triangle measures a view can colour by (names in core/names.h: q, q60, radius-ratio,
// distance-iso, distance-other). The three shapes come from the mesh alone; the two distances
// (core/triangle_distances.h) need the volume or the other method's mesh, and cost a pass over
// the volume or a nearest-point search per triangle, so they are computed only when chosen.
enum class ShapeMeasure { Quality, Quality60, RadiusRatio, DistanceIso, DistanceOther };
bool is_distance(ShapeMeasure measure);
// What a measure is, for legends and axes: "smallest angle / largest angle", ...
std::string_view measure_definition(ShapeMeasure measure);

// The range a measure's colours and histogram bins span. Values outside are drawn in the end
// colours and counted in the end bins. The shapes span [0, 1]; a distance spans a range in
// voxels that suits the meshes measured (triangle_distances.h's distance_scale: symmetric
// around 0 on a diverging map for the signed distance to the iso-surface, from 0 on the
// sequential one for the distance to the other mesh); measure_scale gives it one voxel wide
// until then.
struct MeasureScale {
    float low = 0.0f, high = 1.0f;
    bool diverging = false;
    std::string_view unit; // "voxels" for the distances, empty for the shapes
};
MeasureScale measure_scale(ShapeMeasure measure);

// All three shape measures per triangle in one pass, in triangle order (0 for degenerate).
struct TriangleMeasures {
    std::vector<float> quality, quality60, radius_ratio;
    std::vector<float> min_angle, max_angle; // degrees (0 and 180 for a degenerate triangle)
    // Empty for a distance (not a shape).
    std::span<const float> of(ShapeMeasure measure) const;
};
TriangleMeasures triangle_measures(const Mesh& mesh);

// Mean and histogram (kQualityBins equal bins over the scale's range, the bins of
// QualityStats::histogram for the default [0, 1]) of per-triangle values. NaN values are left
// out of both.
struct MeasureSummary {
    double mean = 0;
    std::array<std::size_t, kQualityBins> histogram{};
};
MeasureSummary summarize_measure(std::span<const float> values, const MeasureScale& scale = {});

// A sliver: a triangle with quality (smallest / largest angle) below this. Degenerate triangles
// (quality 0) are slivers too.
inline constexpr double kSliverQuality = 0.1;

// The angle limits of the FE-readiness summary (fe_readiness.h), in degrees: its shares of
// triangles with a smallest angle under the first two, a largest angle over the third.
inline constexpr double kFeSmallAngle = 15.0;
inline constexpr double kFeNarrowAngle = 30.0;
inline constexpr double kFeObtuseAngle = 120.0;

// Statistics over all triangles; degenerate ones take part with quality 0 (they are the worst
// triangles, not missing ones). All zero for a mesh without triangles.
struct QualityStats {
    double mean = 0, min = 0;     // smallest / largest angle (best 1)
    double quality60_mean = 0;    // best 1
    double radius_ratio_mean = 0; // best 1
    double min_angle_min = 0;     // degrees (best 60)
    std::size_t degenerate = 0;   // triangles with (near) zero area, see above (best 0)
    std::size_t slivers = 0;      // triangles with quality < kSliverQuality (best 0)
    // Counts of quality over [0, 1]: bin i holds [i / kQualityBins, (i + 1) / kQualityBins), the
    // last bin also holds q = 1.
    std::array<std::size_t, kQualityBins> histogram{};
    // For the FE-readiness summary, from the same pass: the triangles, those against its angle
    // limits, and the ranges of two measures (0 for a mesh without triangles).
    std::size_t triangles = 0;
    std::size_t min_angle_below_15 = 0, min_angle_below_30 = 0, max_angle_above_120 = 0;
    double radius_ratio_min = 0, radius_ratio_max = 0; // 2 r / R
    double aspect_ratio_min = 0, aspect_ratio_max = 0; // Verdict's aspect ratio
};
QualityStats quality_stats(const Mesh& mesh);

// Mean |2 pi - angle sum| over interior manifold vertices (those whose incident triangles form
// one closed fan, every edge at the vertex shared by exactly two triangles, no triangle using
// the vertex twice). Boundary and non-manifold vertices are left out. Radians (best 0, a plane);
// 0 when there is no interior vertex. Orientation does not matter.
double smoothness(const Mesh& mesh);

// Combinatorial checks, from sorted per-vertex triangle lists (linear time, no map per edge).
// An edge is an unordered pair of distinct vertices used by consecutive corners of a triangle.
// A "collapsed" triangle repeats a vertex index; its self-loop is not an edge. For an empty mesh
// every flag is false.
// Closed and manifold are separate facts: a disc is manifold but not closed; two cubes sharing
// a corner are closed but not manifold. A closed 2-manifold is `watertight && manifold`.
struct Topology {
    bool watertight = false; // closed: every edge has exactly two incident triangles, none
                             // collapsed (no boundary, no non-manifold edge)
    bool manifold = false;   // edge- and vertex-manifold, a boundary allowed: no edge of three or
                             // more triangles, every vertex's triangles form a single fan (open
                             // at a boundary vertex, closed inside), no collapsed triangle
    bool oriented = false;   // no edge is used twice in the same direction (so every interior
                             // edge is used once in each direction)
    long euler = 0;          // V - E + F over referenced vertices (2 for a sphere)
    std::size_t boundary_edges = 0;       // edges of one triangle
    std::size_t nonmanifold_edges = 0;    // edges of three or more triangles (best 0)
    std::size_t nonmanifold_vertices = 0; // vertices whose triangles form more than one fan, or a
                                          // fan through a non-manifold edge or a collapsed
                                          // triangle (best 0)
    std::size_t collapsed_triangles = 0;
};
Topology topology(const Mesh& mesh);

// Boundary edges (edges of one triangle) with an end farther than `margin` from every face of
// the grid box [0, dims - 1]^3, for a mesh in index space: holes inside the volume, as opposed
// to the cuts a surface gets where the object leaves the volume. Marching Cubes' border edges
// lie on the box faces; a SurfaceNet's in the outermost cells, within one voxel of them.
std::size_t boundary_edges_off_border(const Mesh& index_mesh, glm::ivec3 dims, float margin = 1.0f);

// topology(index_mesh), boundary_edges_off_border(index_mesh, dims) and the smoothness() of the
// mesh with the same triangles at `world_positions` (its points in the world), bit for bit, from
// one analysis of each vertex's fan where each function alone makes its own. Throws
// std::invalid_argument unless there is one world point a vertex.
struct FanMeasures {
    Topology topology;
    std::size_t boundary_edges_off_border = 0;
    double smoothness = 0.0;
};
FanMeasures fan_measures(const Mesh& index_mesh, glm::ivec3 dims,
                         std::span<const glm::vec3> world_positions);

// Sum of the triangle areas (accumulated in double).
double surface_area(const Mesh& mesh);
// Signed enclosed volume (divergence theorem); positive for a closed outward-wound mesh. The
// sum is taken relative to the centre of the bounding box for precision, which changes nothing
// for a closed mesh (an open mesh has no well-defined volume).
double enclosed_volume(const Mesh& mesh);

using DistanceFunction = std::function<float(glm::vec3)>;

// Sample points per triangle of the surface accuracy: the centroids of the k^2 congruent
// sub-triangles of a k-fold split of each side (the composite centroid rule), k = 3.
inline constexpr int kSurfaceSampleSplit = 3;

struct Accuracy {
    double vertices_mean = 0, vertices_max = 0; // at the vertices (the paper's eq. 7)
    double faces_mean = 0, faces_max = 0;       // at the triangles' centroids
    // Over the whole surface: the area-weighted mean of |distance| at kSurfaceSampleSplit^2 fixed
    // points of every triangle (each point stands for 1 / k^2 of its triangle's area), and the
    // largest sample. Measures every mesh the same way, whatever its vertices are placed by.
    double surface_mean = 0, surface_max = 0;
};
// Mean and max of |distance(p)| over every vertex (mesh.positions), over every triangle's
// centroid, and area-weighted over the sample points of every triangle; a signed distance works
// too. The weights are the triangle areas of `mesh`'s triangles on `area_positions` when given (the
// same vertices in other coordinates, e.g. an index-space mesh's world points), else on `mesh`'s.
// `distance` is called from several threads at once, so it must be thread-safe (pure functions,
// MeshDistance and volume sampling are). Deterministic. All zero for an empty mesh; the surface
// figures are zero when the total area is.
Accuracy accuracy(const Mesh& mesh, const DistanceFunction& distance,
                  std::span<const glm::vec3> area_positions = {});

// accuracy()'s figures at the vertices and the centroids, the surface's left zero: a seventh of
// the distances, what a plot over the iterations shows.
Accuracy point_accuracy(const Mesh& mesh, const DistanceFunction& distance);

// The surface figures of accuracy() alone, at the split^2 sub-triangle centroids of a `split`-fold
// split of every triangle (accuracy() uses kSurfaceSampleSplit; 1 is each triangle's centroid,
// enough where the triangles are small against the distances measured). Throws
// std::invalid_argument for split < 1 or area points that are not one per vertex.
struct SurfaceDistance {
    double mean = 0, max = 0;
};
SurfaceDistance surface_distance(const Mesh& mesh, const DistanceFunction& distance,
                                 std::span<const glm::vec3> area_positions, int split);

// Exact Euclidean distance from points to a triangle mesh, accelerated by a uniform grid in which
// each triangle is listed in every cell its bounding box overlaps (cell size about the mean edge
// length, at most about eight million cells). A query visits cubic shells of cells around the
// point's cell, skipping shells known to be empty from a chessboard distance transform over blocks
// of cells, and stops once no unvisited cell can hold anything nearer: never all pairs.
// Build once, query many times; queries are const and thread-safe; copies share the grid.
class MeshDistance {
  public:
    // Throws std::invalid_argument when `reference` has no triangles or a bad index. Keeps the
    // mesh (pass a temporary or std::move it to spare a copy).
    explicit MeshDistance(Mesh reference);
    // The distance to `reference` as `to_space` maps its points (world to index space, say),
    // measured in that space without a copy of the mesh: `reference` must outlive this object
    // and its copies, unchanged. Throws as above.
    MeshDistance(const Mesh& reference, const WorldToIndex& to_space);
    // Distance to the nearest point of any triangle; NaN for a non-finite point.
    float operator()(glm::vec3 p) const;

  private:
    struct Impl;
    std::shared_ptr<const Impl> impl_;
};

} // namespace snert
