// Keeping every iteration's mesh valid for finite-element work: a relaxation step may move a
// node only as far as the triangulated net stays free of self-intersections and of new slivers.
//
// Nodes stay in their cells (the paper's constraint), so the triangles of a quad lie in the
// 2 x 2 x 1 block of its four cells, and two quads can only meet inside a cell they share. For
// each cell this checks every pair of triangles of the quads around its nodes (exactly, see
// triangle_intersection.h; a cell of one node whose star is shown embedded as a whole needs no
// pair test), and each quad's smallest/largest angle: a quad under
// kSliverQuality that was better before the step is refused too, and so is a pair of triangles
// across an edge folded onto each other (normals more than 170 degrees apart) that was less
// folded before (or not in the mesh: a quad's diagonal flipped), refusing every corner of
// both polygons: not an intersection, but an FE mesher (TetGen) cannot recover two facets
// that nearly overlap. The nodes of a refused pair or
// quad take half their move, then none; the check is repeated around them until nothing is
// refused. A step from a valid mesh therefore gives a valid mesh, at the price of moves left
// short (counted by the caller).
#pragma once

#include <cstddef>
#include <memory>
#include <span>
#include <vector>

#include <glm/glm.hpp>

#include "mesh.h"
#include "metrics.h"
#include "surface_net.h"
#include "triangulation.h"

namespace snert {

// What keep_mesh_valid keeps from one step of a relaxation to the next: the net's cells (its
// topology alone, the same every step), the step's node- and polygon-sized buffers (fresh ones
// cost a page fault a page, about a tenth of a step on a clinical CT), and how each quad splits
// where the step left the nodes, which is how it splits where the next one starts. One scratch
// serves one net and one rule and spacing; relax() keeps one for its run.
class MeshGuardScratch {
  public:
    MeshGuardScratch();
    ~MeshGuardScratch();
    MeshGuardScratch(MeshGuardScratch&&) noexcept;
    MeshGuardScratch& operator=(MeshGuardScratch&&) noexcept;

    // How each quad splits (1: along a-c) at `positions`, when they are the very buffer the last
    // keep_mesh_valid with this scratch left its result in (no other code has written it since):
    // quad_splits_along_ac's values (triangulation.h), kept. Empty otherwise.
    std::span<const std::uint8_t> splits_at(std::span<const glm::vec3> positions) const;

    struct Impl;

  private:
    friend std::size_t keep_mesh_valid(const SurfaceNet&, TriangulationRule, glm::vec3,
                                       const IndexToWorld&, std::span<const glm::vec3>,
                                       std::span<glm::vec3>, MeshGuardScratch*);
    std::unique_ptr<Impl> impl_;
};

// Shortens the moves from `old_positions` to `new_positions` (index space) where they would make
// the net's mesh self-intersect or create a sliver. Quads split as triangulate() splits them with
// `spacing`; the checks run on the world points `to_world` gives, which are the very floats a
// mesh file holds (rounding there could otherwise make two triangles meet that did not in index
// space). Returns the number of nodes whose move was shortened. `scratch` (optional) is what the
// steps of one relaxation share; the result is the same with or without it.
std::size_t keep_mesh_valid(const SurfaceNet& net, TriangulationRule rule, glm::vec3 spacing,
                            const IndexToWorld& to_world, std::span<const glm::vec3> old_positions,
                            std::span<glm::vec3> new_positions,
                            MeshGuardScratch* scratch = nullptr);

// A push (index space) that lifts `node` off the opposite side of every cap sliver (q < 0.1)
// whose obtuse corner it is, towards a height of half that side (world shape: index offsets
// times `shape`). Zero where the node is at no sliver's obtuse corner, so never on the phantoms.
// Slivers the first net already has (where pieces share a cell across thick slices) would
// otherwise stay: the guard keeps them from getting worse, not from staying.
// 1 for the nodes at the obtuse corner of a sliver (the only ones sliver_relief moves), so a
// relaxation step can skip the others: one pass over the polygons instead of one per node.
// `splits`, when not empty, is how each quad splits at `positions` (MeshGuardScratch::splits_at),
// so it is not worked out again.
std::vector<std::uint8_t> sliver_apexes(const SurfaceNet& net, TriangulationRule rule,
                                        glm::vec3 shape, std::span<const glm::vec3> positions,
                                        std::span<const std::uint8_t> splits = {});

glm::vec3 sliver_relief(const SurfaceNet& net, TriangulationRule rule, glm::vec3 shape,
                        std::span<const glm::vec3> positions, std::uint32_t node);

namespace detail {

// The guard's cheap first test of a triangle: true only where its smallest / largest angle ratio
// is at least kSliverQuality, shown without an angle (false: measure it with triangle_shape).
// Exposed so that tests can check that it never passes a sliver.
bool surely_no_sliver(glm::vec3 a, glm::vec3 b, glm::vec3 c);

// The guard's test of a node's star, as a relaxation step runs it on a cell that holds the node
// alone: true only where the star's triangles (its quads split as `along_ac` says, one flag a
// quad) surely meet in nothing but shared corners and edges (false: the pairs are tested).
// Exposed so that tests can check what it settles, which the guard's verdicts do not show.
bool star_surely_embedded(const SurfaceNet& net, std::uint32_t node,
                          const std::vector<std::uint8_t>& along_ac,
                          std::span<const glm::vec3> world);

} // namespace detail

} // namespace snert
