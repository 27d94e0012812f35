// The node inspector: the relaxation's own terms for one node, re-run for that node only where
// the relaxation's step allows (the second sub-step needs every node's first sub-step).
#include "node_inspection.h"

#include <stdexcept>
#include <string>

namespace snert {

NodeInspection inspect_node(const SurfaceNet& net, const GreyField* grey,
                            const RelaxOptions& options, int iteration,
                            std::span<const glm::vec3> before, std::span<const glm::vec3> after,
                            std::uint32_t node) {
    const std::size_t n = net.node_count();
    if (node >= n)
        throw std::invalid_argument("node " + std::to_string(node) + " of a net of " +
                                    std::to_string(n) + " nodes");
    if (before.size() != n || after.size() != n)
        throw std::invalid_argument("inspect_node: positions are not one per node");
    if (iteration < 1) throw std::invalid_argument("inspect_node: iterations count from 1");
    NodeInspection r;
    r.node = node;
    r.cell = net.cells[node];
    r.box = relax_box(net, grey, node);
    r.iteration = iteration;
    r.before = before[node];
    r.damping = step_scale(options, iteration);
    r.after = after[node];

    const std::vector<SubStep> steps = sub_steps(options, grey);
    std::vector<glm::vec3> middle;
    std::span<const glm::vec3> positions = before;
    for (std::size_t s = 0; s < steps.size(); ++s) {
        if (s == 1) {
            // The second sub-step starts from every node's first sub-step.
            middle.resize(n);
            relax_sub_step(net, grey, options, steps[0], before, middle);
            positions = middle;
        }
        const std::vector<std::uint8_t> sliver =
            sliver_flags(net, grey, options, steps[s], positions);
        SubStepInspection step;
        step.sub_step = steps[s];
        step.from = positions[node];
        step.terms =
            node_move_terms(net, grey, options, positions, node, steps[s], sliver[node] != 0);
        step.ray_box =
            constrain_move(step.from, step.terms.move, r.box.lo, r.box.hi, Constraint::RayBox);
        step.clip =
            constrain_move(step.from, step.terms.move, r.box.lo, r.box.hi, Constraint::Clip);
        r.constrained = options.constraint == Constraint::RayBox ? step.ray_box : step.clip;
        r.sub_steps.push_back(step);
    }
    // relax_step's damping, in its arithmetic.
    glm::vec3 damped = r.constrained;
    if (r.damping < 1.0f) damped = r.before + r.damping * (r.constrained - r.before);
    r.shortened = damped != r.after;
    return r;
}

std::optional<std::uint32_t> node_of_cell(const SurfaceNet& net, glm::ivec3 cell) {
    for (std::size_t i = 0; i < net.node_count(); ++i)
        if (net.cells[i] == cell) return std::uint32_t(i);
    return std::nullopt;
}

} // namespace snert
