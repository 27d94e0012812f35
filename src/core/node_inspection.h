// One node's move in one relaxation iteration, taken apart into the paper's vectors: the
// averaging vector a (eq. 1), its projection a_p (eq. 5), the gradient step d g (eqs. 3-4),
// their sum, and the constrained move c(...) (eq. 2 / eq. 6) by ray-box and by clipping side by
// side (section 2.2). Every vector comes from the relaxation's own functions (relaxation.h:
// node_move_terms, relax_box, relax_sub_step, constrain_move), so the inspector shows exactly
// what relax_step did; damping and the mesh guard are reported as what they changed.
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include <glm/glm.hpp>

#include "relaxation.h"
#include "surface_net.h"

namespace snert {

struct SubStepInspection {
    SubStep sub_step;
    glm::vec3 from{0.0f}; // the node's position before this sub-step (index space)
    MoveTerms terms;      // terms.move: the unconstrained sum
    // from + c(terms.move) by each constraint; the relaxation takes options.constraint's.
    glm::vec3 ray_box{0.0f};
    glm::vec3 clip{0.0f};
};

struct NodeInspection {
    std::uint32_t node = 0;
    glm::ivec3 cell{0};
    NodeBox box{};                            // where the constraint keeps the node (relax_box)
    int iteration = 0;                        // the move of this iteration (1: the first)
    glm::vec3 before{0.0f};                   // position after iteration - 1
    std::vector<SubStepInspection> sub_steps; // 1, or 2 (smoothing first)
    glm::vec3 constrained{0.0f};              // after the sub-steps with options.constraint
    float damping = 1.0f;                     // step_scale of the iteration
    glm::vec3 after{0.0f};                    // where relax_step put the node
    bool shortened = false; // the mesh guard shortened the move (after differs from the
                            // damped constrained point)
};

// Inspects `node`'s move in iteration `iteration` (>= 1) from `before` (all positions after
// iteration - 1) to `after` (relax_step's result). Throws std::invalid_argument for a node out
// of range, sizes that do not match the net, or an iteration below 1.
NodeInspection inspect_node(const SurfaceNet& net, const GreyField* grey,
                            const RelaxOptions& options, int iteration,
                            std::span<const glm::vec3> before, std::span<const glm::vec3> after,
                            std::uint32_t node);

// The first node (piece) of cell `cell`, or nothing when the cell holds none.
std::optional<std::uint32_t> node_of_cell(const SurfaceNet& net, glm::ivec3 cell);

} // namespace snert
