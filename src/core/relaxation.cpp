// Relaxation of SurfaceNet nodes: averaging, gradient and the combined SNERT step.
//
// This work is based on:
//   P. W. de Bruin, F. M. Vos, F. H. Post, S. F. Frisken-Gibson, A. M. Vossepoel,
//   "Improving triangle mesh quality with SurfaceNets", MICCAI 2000, equations 1-6;
//   S. F. F. Gibson, "Constrained elastic SurfaceNets", MICCAI 1998 (clipping constraint).
//
// Every iteration is a Jacobi update: moves are computed from the old positions only, so the
// result does not depend on node order and a step can run in parallel over nodes.
#include "relaxation.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "huge_pages.h"
#include "mesh_guard.h"
#include "parallel.h"

namespace snert {

namespace {

// Below this gradient length (grey units per voxel, relative to the value range) the gradient
// direction is noise: no gradient step.
constexpr float kMinGradient = 1e-6f;
// How far the node may be moved by d in one step; the cell constraint bounds it further.
constexpr float kMaxDistance = 1.0f;

// Averaging vector a: from p to the mean of the linked neighbours (eq. 1).
glm::vec3 averaging_vector(const SurfaceNet& net, std::span<const glm::vec3> positions,
                           std::uint32_t node) {
    const std::uint32_t first = net.link_offsets[node], last = net.link_offsets[node + 1];
    if (first == last) return glm::vec3(0.0f);
    glm::vec3 sum(0.0f);
    for (std::uint32_t k = first; k < last; ++k) sum += positions[net.links[k]];
    return sum / float(last - first) - positions[node];
}

struct GradientStep {
    glm::vec3 g{0.0f};    // unit direction towards the iso-surface in world shape, or 0 (eq. 3)
    glm::vec3 step{0.0f}; // the index-space move of one world unit (of the smallest spacing)
                          // along g
    float d = 0.0f;       // distance to the iso-surface along g (eq. 4), same unit
};

// The grey value and its gradient at p: from the precomputed field, the trilinear field's own,
// or central differences from the samples around p's cell.
ValueGradient grey_sample(const GreyField& grey, glm::vec3 p) {
    if (!grey.gradient.values.empty())
        return {sample_trilinear(*grey.volume, p), sample_trilinear(grey.gradient, p)};
    if (grey.method == GradientMethod::Trilinear)
        return sample_trilinear_with_gradient(*grey.volume, p);
    return sample_value_gradient(*grey.volume, p);
}

// Nodes whose gradient steps are taken side by side (gradient_steps).
constexpr std::size_t kStepBatch = 4;

// g = SIGN(Iiso - I(p)) grad I / |grad I| (eq. 3), and d from a linear model of I along g:
// I is sampled at p and at p + h g, with h the first-order distance estimate, so the second
// sample lands near the surface and the two samples bracket or nearly bracket it. Directions
// and distances are those of world space (index offsets times grey.scale), so on thick slices
// the node moves along the true normal.
// For up to kStepBatch points at once, stage by stage: a step is one long chain of dependent
// operations around two samples from far apart in the volume, so the points' samples are waited
// for together instead of one after another (a node pass on the CT at -500 in 0.72-0.78x the
// time; 0.63x with move_terms and inner_box inlined as well).
// Each point's operations are those of one alone, in the same order: the same results.
void gradient_steps(const GreyField& grey, std::span<const glm::vec3> points,
                    std::span<GradientStep> steps) {
    const std::size_t n = std::min(points.size(), kStepBatch);
    ValueGradient here[kStepBatch];
    for (std::size_t k = 0; k < n; ++k) here[k] = grey_sample(grey, points[k]);
    float length[kStepBatch] = {}, difference[kStepBatch] = {}, first_order[kStepBatch] = {},
          h[kStepBatch] = {};
    bool ahead_needed[kStepBatch];
    for (std::size_t k = 0; k < n; ++k) {
        GradientStep& step = steps[k];
        step = GradientStep{};
        ahead_needed[k] = false;
        const float value = here[k].value;
        const glm::vec3 gradient = here[k].gradient / grey.scale;
        length[k] = glm::length(gradient);
        if (!(length[k] > kMinGradient) || !std::isfinite(value)) continue;
        difference[k] = grey.iso - value;
        // On the iso-surface d is 0 but g still defines the plane of eq. 5's projection.
        step.g = (difference[k] >= 0.0f ? 1.0f : -1.0f) * gradient / length[k];
        step.step = step.g / grey.scale;
        if (difference[k] == 0.0f) continue;
        first_order[k] = std::abs(difference[k]) / length[k];
        h[k] = std::clamp(first_order[k], 0.05f, kMaxDistance);
        ahead_needed[k] = true;
    }
    float ahead[kStepBatch] = {};
    for (std::size_t k = 0; k < n; ++k)
        if (ahead_needed[k])
            ahead[k] = sample_trilinear(*grey.volume, points[k] + h[k] * steps[k].step);
    for (std::size_t k = 0; k < n; ++k) {
        if (!ahead_needed[k]) continue;
        GradientStep& step = steps[k];
        // Slope of I along g, signed so that it is positive when I approaches iso along g.
        const float slope =
            (ahead[k] - here[k].value) / h[k] * (difference[k] > 0.0f ? 1.0f : -1.0f);
        step.d = slope > kMinGradient ? std::abs(difference[k]) / slope : first_order[k];
        step.d = std::min(step.d, kMaxDistance);
    }
}

GradientStep gradient_step(const GreyField& grey, glm::vec3 p) {
    GradientStep step;
    gradient_steps(grey, std::span<const glm::vec3>(&p, 1), std::span<GradientStep>(&step, 1));
    return step;
}

// A node keeps a margin away from its box's faces (a flat box stays flat): then the triangles
// of two quads without a common cell cannot even touch, which is what lets keep_mesh_valid look
// only within cells. The margin must survive the rounding of the world map (its points are what
// is checked and written): 2^-12 voxel, more where the world coordinates are large against the
// spacing. It costs nothing measurable (the sphere's vertex error moves by 1e-5 voxel).
constexpr float kMinCellMargin = 1.0f / 4096.0f;

float cell_margin(const GreyField* grey) {
    if (grey == nullptr) return kMinCellMargin;
    const Volume& v = *grey->volume;
    const float extent =
        glm::length(glm::abs(v.origin)) + glm::length(glm::vec3(v.dims) * glm::abs(v.spacing));
    const float smallest = std::min({v.spacing.x, v.spacing.y, v.spacing.z});
    if (!(smallest > 0.0f) || !std::isfinite(extent)) return kMinCellMargin;
    // Eight float roundings of the largest world coordinate, in voxels.
    return std::max(kMinCellMargin, 8.0f * extent * 0x1p-24f / smallest);
}

// Inlined into the node pass, as move_terms is: called once a node, their calls and the terms
// returned through memory were a tenth of the pass (GCC kept both out of line).
[[gnu::always_inline]] inline NodeBox inner_box(NodeBox box, float margin) {
    for (int a = 0; a < 3; ++a)
        if (box.hi[a] > box.lo[a]) box.lo[a] += margin, box.hi[a] -= margin;
    return box;
}

// Whether the sub-step's moves take the grey values' gradient term.
bool uses_grey(const GreyField* grey, const RelaxOptions& options, SubStep sub_step) {
    return sub_step.gradient && grey != nullptr && options.mode != RelaxMode::Averaging;
}

// node_move_terms with the node's gradient step given (zero where the sub-step takes none).
// Inlined into the node pass (see inner_box).
[[gnu::always_inline]] inline MoveTerms move_terms(const SurfaceNet& net, const GreyField* grey,
                                                   const RelaxOptions& options,
                                                   std::span<const glm::vec3> positions,
                                                   std::uint32_t node, SubStep sub_step,
                                                   bool at_sliver, const GradientStep& step) {
    MoveTerms terms;
    const bool use_grey = uses_grey(grey, options, sub_step);
    terms.g = step.g;
    terms.d = step.d;
    if (sub_step.smoothing && options.mode != RelaxMode::Gradient) {
        terms.a = averaging_vector(net, positions, node);
        terms.a_p = terms.a;
        // eq. 5: in SNERT's simultaneous step the averaging acts only within the iso-surface
        // (the projection taken in world shape).
        if (options.mode == RelaxMode::Snert && use_grey) {
            const glm::vec3 world = terms.a * grey->scale;
            terms.a_p = (world - step.g * glm::dot(world, step.g)) / grey->scale;
        }
        terms.move += options.smoothing_weight * terms.a_p;
    }
    if (use_grey) {
        terms.dg = step.d * step.step;
        // eq. 4 / eq. 6, the product in the order relax_step has always taken it (same bits)
        terms.move += options.gradient_weight * step.d * step.step;
    }
    // Part of keeping the mesh valid: the existing slivers are lifted (mesh_guard.h).
    if (at_sliver) {
        terms.relief = sliver_relief(net, options.triangulation,
                                     grey != nullptr ? grey->volume->spacing : glm::vec3(1.0f),
                                     positions, node);
        terms.move += terms.relief;
    }
    return terms;
}

// constrain_move's work, inlined into the node pass (see inner_box): a call a node, out of line.
[[gnu::always_inline]] inline glm::vec3 move_in_box(glm::vec3 p, glm::vec3 move, glm::vec3 lo,
                                                    glm::vec3 hi, Constraint constraint) {
    if (!std::isfinite(move.x) || !std::isfinite(move.y) || !std::isfinite(move.z)) return p;
    if (constraint == Constraint::Clip) return glm::clamp(p + move, lo, hi);
    // Ray-box (eq. 2's c): the largest t in [0, 1] with p + t move inside the cell, so the node
    // keeps its direction of motion and stops on the cell boundary. A flat box (a link node's
    // face) takes only the move within it. Along each axis the face the move heads for gives the
    // larger of the two quotients (the other is not positive, and rounding keeps the order), so
    // there is no branch on the move's sign, which is random: its mispredictions were a sixth of
    // a sub-step. A move of 0 along an axis (rare, so well predicted) sets no bound.
    float t = 1.0f;
    for (int a = 0; a < 3; ++a) {
        if (!(hi[a] > lo[a])) move[a] = 0.0f;
        const float reach = std::max((hi[a] - p[a]) / move[a], (lo[a] - p[a]) / move[a]);
        if (move[a] != 0.0f) t = std::min(t, reach);
    }
    t = std::max(t, 0.0f);
    // Rounding can put the end point a hair outside; clamping only removes that hair.
    return glm::clamp(p + t * move, lo, hi);
}

} // namespace

MoveTerms node_move_terms(const SurfaceNet& net, const GreyField* grey, const RelaxOptions& options,
                          std::span<const glm::vec3> positions, std::uint32_t node,
                          SubStep sub_step, bool at_sliver) {
    const GradientStep step =
        uses_grey(grey, options, sub_step) ? gradient_step(*grey, positions[node]) : GradientStep{};
    return move_terms(net, grey, options, positions, node, sub_step, at_sliver, step);
}

NodeBox relax_box(const SurfaceNet& net, const GreyField* grey, std::size_t node) {
    return inner_box(node_box(net, node), cell_margin(grey));
}

std::vector<SubStep> sub_steps(const RelaxOptions& options, const GreyField* grey) {
    const bool two_terms = options.mode == RelaxMode::Snert && grey != nullptr;
    if (options.schedule == Schedule::Simultaneous || !two_terms) return {{true, true}};
    // "Smoothing first, ending with the favoured goal": two Jacobi sub-steps, one term each.
    const bool first_smooth = options.favour_accuracy;
    return {{first_smooth, !first_smooth}, {!first_smooth, first_smooth}};
}

std::vector<std::uint8_t> sliver_flags(const SurfaceNet& net, const GreyField* grey,
                                       const RelaxOptions& options, SubStep sub_step,
                                       std::span<const glm::vec3> positions,
                                       std::span<const std::uint8_t> splits) {
    const glm::vec3 spacing = grey != nullptr ? grey->volume->spacing : glm::vec3(1.0f);
    return options.keep_valid && sub_step.smoothing
               ? sliver_apexes(net, options.triangulation, spacing, positions, splits)
               : std::vector<std::uint8_t>(positions.size(), 0);
}

float step_scale(const RelaxOptions& options, int iteration) {
    if (iteration <= options.damping_start || !(options.damping_halving > 0.0f)) return 1.0f;
    return std::exp2(-float(iteration - options.damping_start) / options.damping_halving);
}

void relax_sub_step(const SurfaceNet& net, const GreyField* grey, const RelaxOptions& options,
                    SubStep sub_step, std::span<const glm::vec3> old_positions,
                    std::span<glm::vec3> new_positions, std::span<const std::uint8_t> splits) {
    // Jacobi: every node reads only old positions, so chunks of nodes run independently.
    constexpr std::size_t kChunk = 4096;
    const float margin = cell_margin(grey);
    const std::vector<std::uint8_t> at_sliver =
        sliver_flags(net, grey, options, sub_step, old_positions, splits);
    // The grey samples of a node a few ahead are fetched while this one is worked out, when the
    // sub-step reads them, and the gradient steps of kStepBatch nodes are taken together.
    const bool reads_grey = uses_grey(grey, options, sub_step);
    for_each_chunk(
        old_positions.size(), kChunk, [&](std::size_t, std::size_t begin, std::size_t end) {
            constexpr std::size_t kAhead = 8;
            for (std::size_t first = begin; first < end; first += kStepBatch) {
                const std::size_t count = std::min(kStepBatch, end - first);
                GradientStep steps[kStepBatch];
                if (reads_grey) {
                    for (std::size_t i = first; i < first + count; ++i)
                        if (i + kAhead < end)
                            prefetch_cell(*grey->volume, old_positions[i + kAhead]);
                    gradient_steps(*grey, old_positions.subspan(first, count),
                                   std::span<GradientStep>(steps, count));
                }
                for (std::size_t i = first; i < first + count; ++i) {
                    const glm::vec3 move =
                        move_terms(net, grey, options, old_positions, std::uint32_t(i), sub_step,
                                   at_sliver[i] != 0, steps[i - first])
                            .move;
                    const NodeBox box = inner_box(node_box(net, i), margin);
                    new_positions[i] =
                        move_in_box(old_positions[i], move, box.lo, box.hi, options.constraint);
                }
            }
        });
}

GreyField make_grey_field(const Volume& volume, const RelaxOptions& options) {
    GreyField grey;
    grey.volume = &volume;
    grey.iso = options.iso;
    grey.method = options.gradient;
    const float smallest = std::min({volume.spacing.x, volume.spacing.y, volume.spacing.z});
    if (smallest > 0.0f && std::isfinite(smallest)) grey.scale = volume.spacing / smallest;
    if (options.gradient == GradientMethod::Gaussian)
        grey.gradient = gradient_field_gaussian(volume, options.gradient_sigma);
    return grey;
}

glm::vec3 constrain_move(glm::vec3 p, glm::vec3 move, glm::ivec3 cell, Constraint constraint) {
    return constrain_move(p, move, glm::vec3(cell), glm::vec3(cell) + 1.0f, constraint);
}

glm::vec3 constrain_move(glm::vec3 p, glm::vec3 move, glm::vec3 lo, glm::vec3 hi,
                         Constraint constraint) {
    return move_in_box(p, move, lo, hi, constraint);
}

namespace {

// The largest distance between old and new positions, chunk by chunk on every thread: on the
// calling thread alone it was 1.5 ms of a step on the CT at 200, a fortieth of a step on two
// threads. The largest of the chunks' largest is the same whichever thread took which chunk.
float largest_move(std::span<const glm::vec3> old_positions,
                   std::span<const glm::vec3> new_positions) {
    constexpr std::size_t kChunk = std::size_t(1) << 16;
    std::vector<float> largest(chunk_count(old_positions.size(), kChunk), 0.0f);
    for_each_chunk(old_positions.size(), kChunk,
                   [&](std::size_t chunk, std::size_t b, std::size_t e) {
                       float m = 0.0f;
                       for (std::size_t i = b; i < e; ++i)
                           m = std::max(m, glm::length(new_positions[i] - old_positions[i]));
                       largest[chunk] = m;
                   });
    float m = 0.0f;
    for (const float chunk_largest : largest) m = std::max(m, chunk_largest);
    return m;
}

} // namespace

float relax_step(const SurfaceNet& net, const GreyField* grey, const RelaxOptions& options,
                 int iteration, std::span<const glm::vec3> old_positions,
                 std::span<glm::vec3> new_positions, std::size_t* shortened,
                 MeshGuardScratch* scratch) {
    const std::vector<SubStep> steps = sub_steps(options, grey);
    // The quads' splits where the last step left the nodes, which are these old positions.
    const std::span<const std::uint8_t> splits = scratch != nullptr && options.keep_valid
                                                     ? scratch->splits_at(old_positions)
                                                     : std::span<const std::uint8_t>();
    if (steps.size() == 1) {
        relax_sub_step(net, grey, options, steps[0], old_positions, new_positions, splits);
    } else {
        std::vector<glm::vec3> middle(old_positions.size());
        relax_sub_step(net, grey, options, steps[0], old_positions, middle, splits);
        relax_sub_step(net, grey, options, steps[1], middle, new_positions);
    }
    // Safeguards: the damping schedule (a point of the cell's box stays in the box when its
    // move is shortened), then the mesh's validity.
    if (const float scale = step_scale(options, iteration); scale < 1.0f)
        for (std::size_t i = 0; i < old_positions.size(); ++i)
            new_positions[i] = old_positions[i] + scale * (new_positions[i] - old_positions[i]);
    // The spacing the pipeline triangulates with and the world points it exports, so the guard
    // sees the very mesh that is measured and written.
    const glm::vec3 spacing = grey != nullptr ? grey->volume->spacing : glm::vec3(1.0f);
    const IndexToWorld to_world =
        grey != nullptr ? index_to_world_map(*grey->volume) : IndexToWorld{};
    const std::size_t refused = options.keep_valid
                                    ? keep_mesh_valid(net, options.triangulation, spacing, to_world,
                                                      old_positions, new_positions, scratch)
                                    : 0;
    if (shortened != nullptr) *shortened = refused;
    return largest_move(old_positions, new_positions);
}

RelaxResult relax(const SurfaceNet& net, const GreyField* grey, const RelaxOptions& options,
                  const IterationCallback& on_iteration, const Progress& progress,
                  const RelaxStart& start) {
    RelaxResult result;
    if (!start.positions.empty() && start.positions.size() != net.positions.size())
        throw std::invalid_argument("relax: " + std::to_string(start.positions.size()) +
                                    " start positions for a net of " +
                                    std::to_string(net.positions.size()) + " nodes");
    // Both buffers on huge pages: a clinical net's positions (5-21 MB) faulted 4 KiB at a time,
    // on this thread alone, before the first step.
    const std::span<const glm::vec3> first =
        start.positions.empty() ? std::span<const glm::vec3>(net.positions) : start.positions;
    detail::reserve_mapped_on_huge_pages(result.positions, first.size());
    result.positions.assign(first.begin(), first.end());
    std::vector<glm::vec3> next;
    detail::resize_on_huge_pages(next, first.size());
    MeshGuardScratch scratch; // shared by the steps: each starts where the last one ended
    const int done = start.iteration;
    const int count = options.max_iterations - done;
    for (int it = done + 1; it <= options.max_iterations; ++it) {
        progress.update(float(it - 1 - done) / float(count));
        std::size_t shortened = 0;
        const float max_move =
            relax_step(net, grey, options, it, result.positions, next, &shortened, &scratch);
        result.shortened_moves += shortened;
        result.positions.swap(next);
        result.max_moves.push_back(max_move);
        if (on_iteration && !on_iteration({it, max_move}, result.positions)) break;
        if (max_move < options.epsilon) {
            result.converged = true;
            break;
        }
    }
    progress.update(1.0f);
    return result;
}

} // namespace snert
