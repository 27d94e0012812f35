// The node inspector against the relaxation itself: every node's inspected move ends where
// relax_step put the node, and its terms are the paper's vectors (eqs. 1-6).
#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <string>

#include "core/names.h"
#include "core/node_inspection.h"
#include "core/phantom.h"
#include "core/relaxation.h"
#include "core/segmentation.h"
#include "core/surface_net.h"

using namespace snert;

namespace {

// A phantom's net and grey field (the field points into the phantom: kept on the heap).
struct Case {
    Phantom phantom;
    SurfaceNet net;
    GreyField grey;
};

std::unique_ptr<const Case> make_case(const std::string& name, const RelaxOptions& options) {
    auto c = std::make_unique<Case>();
    c->phantom = make_phantom(name);
    c->net = build_surface_net(segment_threshold(c->phantom.volume, c->phantom.iso));
    c->grey = make_grey_field(c->phantom.volume, options);
    return c;
}

// Positions after `iterations` iterations, and the next iteration's result.
struct Step {
    std::vector<glm::vec3> before, after;
};
Step run(const Case& s, const RelaxOptions& options, int iterations) {
    Step r;
    RelaxOptions o = options;
    o.max_iterations = iterations;
    o.epsilon = 0.0f;
    r.before = iterations > 0 ? relax(s.net, &s.grey, o).positions : s.net.positions;
    r.after.resize(r.before.size());
    relax_step(s.net, &s.grey, options, iterations + 1, r.before, r.after);
    return r;
}

// Checks every node; returns how many the mesh guard shortened.
std::size_t check_all(const Case& s, const RelaxOptions& options, const Step& step, int iteration) {
    std::size_t shortened = 0;
    for (std::uint32_t i = 0; i < s.net.node_count(); ++i) {
        const NodeInspection n =
            inspect_node(s.net, &s.grey, options, iteration, step.before, step.after, i);
        if (n.shortened) {
            ++shortened;
            continue;
        }
        // Bit for bit where the relaxation put the node.
        EXPECT_EQ(n.constrained, step.after[i]) << "node " << i;
    }
    return shortened;
}

} // namespace

// The inspector takes one node's gradient step alone, a relaxation step several nodes' side by
// side: the same bits, with every gradient.
TEST(NodeInspection, SimultaneousStepEqualsRelaxationForEveryNode) {
    for (const GradientMethod gradient :
         {GradientMethod::Trilinear, GradientMethod::Central, GradientMethod::Gaussian})
        for (const Constraint c : {Constraint::RayBox, Constraint::Clip}) {
            RelaxOptions options;
            options.constraint = c;
            options.gradient = gradient;
            options.iso = 0.0f;
            const auto owned = make_case("small-sphere", options);
            const Case& s = *owned;
            const Step step = run(s, options, 2);
            const std::size_t shortened = check_all(s, options, step, 3);
            EXPECT_LT(shortened, s.net.node_count() / 10) << name_of(c);
        }
}

TEST(NodeInspection, SmoothingFirstHasTwoSubStepsEndingWhereTheRelaxationDid) {
    RelaxOptions options;
    options.schedule = Schedule::SmoothingFirst;
    const auto owned = make_case("crease", options);
    const Case& s = *owned;
    const Step step = run(s, options, 1);
    EXPECT_LT(check_all(s, options, step, 2), s.net.node_count() / 10);
    const NodeInspection n = inspect_node(s.net, &s.grey, options, 2, step.before, step.after, 0);
    ASSERT_EQ(n.sub_steps.size(), 2u);
    // Smoothing first, then the gradient term (favour accuracy).
    EXPECT_TRUE(n.sub_steps[0].sub_step.smoothing && !n.sub_steps[0].sub_step.gradient);
    EXPECT_TRUE(!n.sub_steps[1].sub_step.smoothing && n.sub_steps[1].sub_step.gradient);
    EXPECT_EQ(n.sub_steps[0].terms.dg, glm::vec3(0.0f));
    EXPECT_EQ(n.sub_steps[1].terms.a, glm::vec3(0.0f));
    EXPECT_EQ(n.sub_steps[1].from, n.sub_steps[0].ray_box);
}

TEST(NodeInspection, TermsAreThePapersVectors) {
    RelaxOptions options;
    options.smoothing_weight = 0.7f;
    options.gradient_weight = 0.9f;
    options.keep_valid = false; // no sliver relief: the move is the two terms alone
    const auto owned = make_case("small-sphere", options);
    const Case& s = *owned;
    const Step step = run(s, options, 0);
    int closer = 0, differ = 0;
    for (std::uint32_t i = 0; i < s.net.node_count(); ++i) {
        const NodeInspection n =
            inspect_node(s.net, &s.grey, options, 1, step.before, step.after, i);
        ASSERT_EQ(n.sub_steps.size(), 1u);
        const SubStepInspection& sub = n.sub_steps[0];
        const MoveTerms& t = sub.terms;
        // eq. 1: the mean of the linked neighbours minus p.
        glm::vec3 mean(0.0f);
        const std::uint32_t first = s.net.link_offsets[i], last = s.net.link_offsets[i + 1];
        for (std::uint32_t k = first; k < last; ++k) mean += step.before[s.net.links[k]];
        mean /= float(last - first);
        EXPECT_LT(glm::length(t.a - (mean - step.before[i])), 1e-5f);
        // eq. 3: g is a unit vector; eq. 5: a_p has no component along g, and a - a_p does.
        ASSERT_NEAR(glm::length(t.g), 1.0f, 1e-5f);
        EXPECT_NEAR(glm::dot(t.a_p, t.g), 0.0f, 1e-5f);
        EXPECT_LT(glm::length(glm::cross(t.a - t.a_p, t.g)), 1e-5f);
        // eq. 4: d g points along g by d; eq. 6: the sum with the weights.
        EXPECT_LT(glm::length(t.dg - t.d * t.g), 1e-5f);
        EXPECT_LT(glm::length(t.move - (0.7f * t.a_p + 0.9f * t.dg)), 1e-5f);
        EXPECT_EQ(t.relief, glm::vec3(0.0f));
        // The gradient step brings the node nearer to the sphere.
        closer += s.phantom.reference_distance(step.before[i] + t.dg) <
                  s.phantom.reference_distance(step.before[i]);
        // Ray-box keeps the direction of the move (eq. 2's c); clipping need not.
        const glm::vec3 r = sub.ray_box - sub.from;
        EXPECT_LT(glm::length(glm::cross(r, t.move)), 1e-4f * (1.0f + glm::length(t.move)));
        EXPECT_LE(glm::length(r), glm::length(t.move) + 1e-6f);
        EXPECT_EQ(sub.clip, glm::clamp(sub.from + t.move, n.box.lo, n.box.hi));
        differ += glm::length(sub.clip - sub.ray_box) > 1e-3f;
        EXPECT_EQ(n.after, sub.ray_box); // no guard, no damping: exactly the ray-box point
        EXPECT_FALSE(n.shortened);
    }
    EXPECT_GT(closer, int(s.net.node_count() * 9 / 10));
    EXPECT_GT(differ, 0); // the two constraints part on some nodes of the first step
}

TEST(NodeInspection, DampingAndBadInput) {
    RelaxOptions options;
    options.damping_start = 0;
    options.damping_halving = 1.0f;
    const auto owned = make_case("tilted-plane", options);
    const Case& s = *owned;
    const Step step = run(s, options, 0);
    const NodeInspection n = inspect_node(s.net, &s.grey, options, 1, step.before, step.after, 3);
    EXPECT_FLOAT_EQ(n.damping, 0.5f);
    EXPECT_THROW(inspect_node(s.net, &s.grey, options, 1, step.before, step.after,
                              std::uint32_t(s.net.node_count())),
                 std::invalid_argument);
    EXPECT_THROW(inspect_node(s.net, &s.grey, options, 0, step.before, step.after, 0),
                 std::invalid_argument);
    ASSERT_TRUE(node_of_cell(s.net, s.net.cells[5]).has_value());
    EXPECT_EQ(s.net.cells[*node_of_cell(s.net, s.net.cells[5])], s.net.cells[5]);
    EXPECT_FALSE(node_of_cell(s.net, glm::ivec3(0, 0, 0)).has_value());
}
