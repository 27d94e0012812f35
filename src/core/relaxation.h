// Relaxation of a SurfaceNet (de Bruin et al., sections 2.2-2.4), one Jacobi iteration at a time.
//
// Modes:
//   Averaging (SNA)   move towards the mean of the linked neighbours, a (eq. 1), p += c(a) (eq. 2)
//   Gradient          move along g = SIGN(Iiso - I(p)) * grad I / |grad I| (eq. 3) by the
//                     distance d to the iso-surface, p += c(d g) (eq. 4)
//   Snert             the averaging vector projected on the plane normal to g, a_p = a - g (a.g)
//                     (eq. 5), plus the gradient step: p += c(a_p + d g) (eq. 6)
// Each term has a weight. With the "smoothing first" schedule an iteration applies the smoothing
// term and then the gradient term as two Jacobi sub-steps, ending with the favoured goal.
// d comes from a linear model of the grey values along g: I is sampled at p and at p + h g.
// Where |grad I| is about 0 there is no gradient step. The constraint c keeps every node inside
// its own cell: RayBox shortens the move along its own direction to the cell boundary; Clip
// clips x, y and z separately (the original SurfaceNet, kept for teaching).
#pragma once

#include <functional>
#include <span>
#include <vector>

#include <glm/glm.hpp>

#include "progress.h"
#include "surface_net.h"
#include "triangulation.h"
#include "volume.h"

namespace snert {

class MeshGuardScratch; // mesh_guard.h

enum class RelaxMode { Averaging, Gradient, Snert };
enum class Schedule { Simultaneous, SmoothingFirst };
enum class Constraint { RayBox, Clip };
// Trilinear: the trilinear field's own gradient from the 8 corner samples that give the value
// (the default: the normal of the surface d is measured to, and the fastest; it jumps across
// cell faces); Central: central differences at those samples, interpolated (the paper's);
// Gaussian: Gaussian derivatives, precomputed for the volume.
enum class GradientMethod { Central, Gaussian, Trilinear };

struct RelaxOptions {
    RelaxMode mode = RelaxMode::Snert;
    float smoothing_weight = 1.0f; // weight of the averaging term (eq. 1 / eq. 5)
    float gradient_weight = 1.0f;  // weight of the gradient term d g (eq. 4 / eq. 6)
    Schedule schedule = Schedule::Simultaneous;
    bool favour_accuracy = true; // SmoothingFirst: end each iteration with the gradient term
    Constraint constraint = Constraint::RayBox;
    GradientMethod gradient = GradientMethod::Trilinear;
    float gradient_sigma = 1.0f; // voxels, for GradientMethod::Gaussian
    float iso = 0.0f;            // Iiso of eq. 3
    int max_iterations = 20;     // stop after this many iterations
    float epsilon = 1e-4f;       // ... or when the largest move (voxels) falls under this
    // How the quads are split (section 2.5); the step keeps the mesh so split valid.
    TriangulationRule triangulation = TriangulationRule::ShorterDiagonal;
    // Safeguard of the step length: from this iteration on every move is scaled by
    // 2^-((k - damping_start) / damping_halving), so a node that cannot settle (its cell holds
    // no iso-surface point it can reach, and it bounces between faces) still comes to rest.
    int damping_start = 100;
    float damping_halving = 10.0f;
    // Refuse (shorten) moves that would make the triangulated net self-intersect or add a sliver
    // (mesh_guard.h). Off only to see what the paper's plain step does.
    bool keep_valid = true;
    bool operator==(const RelaxOptions&) const = default;
};

// What the gradient term needs: the grey volume, and the gradient field when precomputed.
// Build it once per volume and options with make_grey_field.
struct GreyField {
    const Volume* volume = nullptr;
    GradientField gradient; // precomputed (Gaussian), or empty: `method` on the fly
    GradientMethod method = GradientMethod::Trilinear; // as RelaxOptions'
    float iso = 0.0f;
    glm::vec3 scale{1.0f}; // spacing / smallest spacing: index offsets to world shape
};
GreyField make_grey_field(const Volume& volume, const RelaxOptions& options);

// Returns the point of the cell [cell, cell + 1] reached from p along move, shortened by the
// constraint so that it stays inside the cell.
glm::vec3 constrain_move(glm::vec3 p, glm::vec3 move, glm::ivec3 cell, Constraint constraint);
// The same for the box [lo, hi] (a node's region, see surface_net.h).
glm::vec3 constrain_move(glm::vec3 p, glm::vec3 move, glm::vec3 lo, glm::vec3 hi,
                         Constraint constraint);

// One Jacobi sub-step of an iteration and the terms it applies. An iteration is one sub-step
// with both terms, or (Schedule::SmoothingFirst in Snert mode) two with one term each.
struct SubStep {
    bool smoothing = true;
    bool gradient = true;
};
std::vector<SubStep> sub_steps(const RelaxOptions& options, const GreyField* grey);

// One node's move in one sub-step, before the constraint, term by term: what relax_step adds
// up, and what the node inspector shows (index space).
struct MoveTerms {
    glm::vec3 a{0.0f};      // averaging vector (eq. 1); 0 when the sub-step does not smooth
    glm::vec3 a_p{0.0f};    // the averaging term used: a projected on the plane normal to g
                            // (eq. 5) in Snert mode with a gradient, else a itself
    glm::vec3 g{0.0f};      // unit direction towards the iso-surface, world shape (eq. 3), or 0
    float d = 0.0f;         // distance along g (eq. 4), in units of the smallest spacing
    glm::vec3 dg{0.0f};     // the gradient step d g as an index-space move
    glm::vec3 relief{0.0f}; // sliver relief (mesh_guard.h), 0 away from slivers
    // smoothing_weight a_p + gradient_weight d g + relief: the move the constraint c shortens
    glm::vec3 move{0.0f};
};
// `at_sliver`: the node is the apex of a sliver (sliver_flags below).
MoveTerms node_move_terms(const SurfaceNet& net, const GreyField* grey, const RelaxOptions& options,
                          std::span<const glm::vec3> positions, std::uint32_t node,
                          SubStep sub_step, bool at_sliver);
// Per node, whether the sub-step lifts it as a sliver's apex (only with keep_valid, when the
// sub-step smooths). `splits`: how each quad splits at `positions`, when known (sliver_apexes).
std::vector<std::uint8_t> sliver_flags(const SurfaceNet& net, const GreyField* grey,
                                       const RelaxOptions& options, SubStep sub_step,
                                       std::span<const glm::vec3> positions,
                                       std::span<const std::uint8_t> splits = {});
// The box the constraint keeps a node in: its region (node_box) less a small margin.
NodeBox relax_box(const SurfaceNet& net, const GreyField* grey, std::size_t node);
// The damping factor of iteration `iteration`'s moves (1 before options.damping_start).
float step_scale(const RelaxOptions& options, int iteration);

// One sub-step for every node (Jacobi: from `old_positions` only): the moves of
// node_move_terms, constrained to relax_box, into `new_positions`. No damping and no mesh check
// (relax_step adds them, and measures the moves once they are final). `splits` as sliver_flags'.
void relax_sub_step(const SurfaceNet& net, const GreyField* grey, const RelaxOptions& options,
                    SubStep sub_step, std::span<const glm::vec3> old_positions,
                    std::span<glm::vec3> new_positions, std::span<const std::uint8_t> splits = {});

// Iteration `iteration` (1 for the first): computes every node's new position from
// `old_positions` into `new_positions` (same size) and returns the largest move length
// (voxels). The result depends only on its arguments (the app recomputes iterations from
// keyframes). Moves are damped after options.damping_start and shortened where the mesh would
// stop being valid (mesh_guard.h); `shortened`, when given, receives how many were. `scratch`
// (optional) is what the steps of one run over `net` share (MeshGuardScratch): the same result,
// sooner.
float relax_step(const SurfaceNet& net, const GreyField* grey, const RelaxOptions& options,
                 int iteration, std::span<const glm::vec3> old_positions,
                 std::span<glm::vec3> new_positions, std::size_t* shortened = nullptr,
                 MeshGuardScratch* scratch = nullptr);

struct RelaxIteration {
    int iteration = 0;  // 1 for the first iteration
    float max_move = 0; // largest node move in this iteration (voxels)
};

// Called after every iteration with the new positions; return false to stop early.
using IterationCallback =
    std::function<bool(const RelaxIteration&, std::span<const glm::vec3> positions)>;

struct RelaxResult {
    std::vector<glm::vec3> positions;
    std::vector<float> max_moves;    // per iteration run by this call
    bool converged = false;          // stopped because max move < epsilon
    std::size_t shortened_moves = 0; // node moves shortened to keep the mesh valid, summed
};

// Where relax() starts: the net's own positions (iteration 0), or the positions after
// `iteration` iterations of an earlier relax() with the same net, field and options, to go on
// from there. The iterations keep their numbers (the damping schedule goes on where it was),
// so continuing equals one longer relaxation bit for bit.
struct RelaxStart {
    std::span<const glm::vec3> positions; // empty: net.positions; read before the first iteration
    int iteration = 0;                    // iterations already done
};

// Runs iterations start.iteration + 1 .. options.max_iterations, or until the largest move
// falls under options.epsilon. `grey` may be null for Averaging. Throws std::invalid_argument
// when the start positions are not one per node.
RelaxResult relax(const SurfaceNet& net, const GreyField* grey, const RelaxOptions& options,
                  const IterationCallback& on_iteration = {}, const Progress& progress = {},
                  const RelaxStart& start = {});

} // namespace snert
