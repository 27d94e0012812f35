#include <gtest/gtest.h>

#include <cmath>

#include "core/metrics.h"
#include "core/phantom.h"
#include "core/relaxation.h"
#include "core/triangulation.h"

using namespace snert;

namespace {

struct Relaxed {
    SurfaceNet net;
    RelaxResult result;
    Mesh mesh;
};

Relaxed relax_phantom(const Phantom& p, RelaxOptions options) {
    Relaxed r;
    r.net = build_surface_net(segment_threshold(p.volume, p.iso));
    options.iso = p.iso;
    const GreyField grey = make_grey_field(p.volume, options);
    r.result = relax(r.net, &grey, options);
    r.mesh = triangulate(r.net, r.result.positions);
    return r;
}

double mean_reference_distance(const Phantom& p, const std::vector<glm::vec3>& points) {
    double sum = 0;
    for (const glm::vec3& q : points) sum += p.reference_distance(q);
    return sum / double(points.size());
}

bool inside_cell(glm::vec3 p, glm::ivec3 cell) {
    return glm::all(glm::greaterThanEqual(p, glm::vec3(cell))) &&
           glm::all(glm::lessThanEqual(p, glm::vec3(cell) + 1.0f));
}

} // namespace

TEST(Constraint, RayBoxShortensAlongTheMove) {
    const glm::vec3 p(0.5f, 0.5f, 0.5f);
    const glm::vec3 q = constrain_move(p, {1.0f, 0.25f, 0.0f}, glm::ivec3(0), Constraint::RayBox);
    EXPECT_NEAR(q.x, 1.0f, 1e-6f);
    EXPECT_NEAR(q.y, 0.625f, 1e-6f); // same direction: half the move
    const glm::vec3 c = constrain_move(p, {1.0f, 0.25f, 0.0f}, glm::ivec3(0), Constraint::Clip);
    EXPECT_NEAR(c.x, 1.0f, 1e-6f);
    EXPECT_NEAR(c.y, 0.75f, 1e-6f); // clipping keeps the full y move
    const glm::vec3 inside =
        constrain_move(p, {0.1f, -0.2f, 0.3f}, glm::ivec3(0), Constraint::RayBox);
    EXPECT_NEAR(glm::distance(inside, p + glm::vec3(0.1f, -0.2f, 0.3f)), 0.0f, 1e-6f);
    EXPECT_EQ(constrain_move(p, {NAN, 0, 0}, glm::ivec3(0), Constraint::RayBox), p);
}

TEST(Relaxation, NodesNeverLeaveTheirCells) {
    const Phantom p = make_phantom("noisy-sphere", 24);
    for (RelaxMode mode : {RelaxMode::Averaging, RelaxMode::Gradient, RelaxMode::Snert})
        for (Constraint constraint : {Constraint::RayBox, Constraint::Clip}) {
            RelaxOptions o;
            o.mode = mode;
            o.constraint = constraint;
            o.max_iterations = 15;
            o.smoothing_weight = 1.7f; // overshooting weights must still be contained
            o.gradient_weight = 2.5f;
            const Relaxed r = relax_phantom(p, o);
            for (std::size_t i = 0; i < r.net.node_count(); ++i)
                ASSERT_TRUE(inside_cell(r.result.positions[i], r.net.cells[i]))
                    << "node " << i << " mode " << int(mode);
        }
}

TEST(Relaxation, SnertFitsTheSphere) {
    const Phantom p = make_phantom("sphere", 64);
    RelaxOptions o;
    o.mode = RelaxMode::Snert;
    o.max_iterations = 40;
    const Relaxed r = relax_phantom(p, o);
    EXPECT_LT(mean_reference_distance(p, r.result.positions), 0.05);
}

TEST(Relaxation, AveragingShrinksAndSnertDoesNot) {
    const Phantom p = make_phantom("sphere", 48);
    const Mesh initial = [&] {
        const SurfaceNet net = build_surface_net(segment_threshold(p.volume, p.iso));
        return triangulate(net, net.positions);
    }();
    RelaxOptions o;
    o.max_iterations = 30;
    o.epsilon = 0.0f;
    o.mode = RelaxMode::Averaging;
    const double sna = enclosed_volume(relax_phantom(p, o).mesh);
    o.mode = RelaxMode::Snert;
    const double snert = enclosed_volume(relax_phantom(p, o).mesh);
    EXPECT_LT(sna, enclosed_volume(initial));
    EXPECT_LT(sna, 0.99 * p.reference_volume);
    EXPECT_NEAR(snert / p.reference_volume, 1.0, 0.01);
}

TEST(Relaxation, GradientProjectsOntoThePlane) {
    const glm::vec3 normal = glm::normalize(glm::vec3(1, 2, 3)), point(11.3f);
    const Phantom p = make_plane_phantom(24, {1, 2, 3}, point);
    RelaxOptions o;
    o.mode = RelaxMode::Gradient;
    o.max_iterations = 5;
    const Relaxed r = relax_phantom(p, o);
    // A linear field: d is exact, so every node whose foot point on the plane lies in its own
    // cell lands on the plane; the others stop on their cell's wall.
    int checked = 0;
    for (std::size_t i = 0; i < r.net.node_count(); ++i) {
        const glm::vec3 start = r.net.positions[i];
        const glm::vec3 foot = start - normal * glm::dot(start - point, normal);
        const glm::vec3 lo = glm::vec3(r.net.cells[i]) + 0.01f, hi = lo + 0.98f;
        if (glm::all(glm::greaterThan(foot, lo)) && glm::all(glm::lessThan(foot, hi))) {
            EXPECT_LT(p.reference_distance(r.result.positions[i]), 1e-3f) << i;
            ++checked;
        }
    }
    EXPECT_GT(checked, int(r.net.node_count() / 2));
}

TEST(Relaxation, JacobiUpdateUsesOldPositionsOnly) {
    // Moving nodes in reverse order of computation must not change a Jacobi step.
    const Phantom p = make_phantom("sphere", 20);
    const SurfaceNet net = build_surface_net(segment_threshold(p.volume, p.iso));
    RelaxOptions o;
    o.mode = RelaxMode::Averaging;
    std::vector<glm::vec3> next(net.node_count());
    relax_step(net, nullptr, o, net.positions, next);
    for (std::uint32_t i = 0; i < net.node_count(); ++i) {
        glm::vec3 mean(0.0f);
        const auto n = net.link_offsets[i + 1] - net.link_offsets[i];
        for (auto k = net.link_offsets[i]; k < net.link_offsets[i + 1]; ++k)
            mean += net.positions[net.links[k]];
        const glm::vec3 expected = constrain_move(
            net.positions[i], mean / float(n) - net.positions[i], net.cells[i], Constraint::RayBox);
        ASSERT_NEAR(glm::distance(next[i], expected), 0.0f, 1e-5f) << i;
    }
}

TEST(Relaxation, StopsAtEpsilonAndReportsEveryIteration) {
    const Phantom p = make_phantom("sphere", 24);
    const SurfaceNet net = build_surface_net(segment_threshold(p.volume, p.iso));
    RelaxOptions o;
    o.max_iterations = 500;
    o.epsilon = 1e-3f;
    o.iso = p.iso;
    const GreyField grey = make_grey_field(p.volume, o);
    int calls = 0;
    const RelaxResult r = relax(net, &grey, o, [&](const RelaxIteration& it, auto positions) {
        ++calls;
        EXPECT_EQ(it.iteration, calls);
        EXPECT_EQ(positions.size(), net.node_count());
        return true;
    });
    EXPECT_TRUE(r.converged);
    EXPECT_LT(calls, 500);
    EXPECT_EQ(std::size_t(calls), r.max_moves.size());
    EXPECT_LT(r.max_moves.back(), 1e-3f);
    // Returning false from the callback stops at once.
    const RelaxResult stopped =
        relax(net, &grey, o, [](const RelaxIteration& it, auto) { return it.iteration < 3; });
    EXPECT_EQ(stopped.max_moves.size(), 3u);
}

TEST(Relaxation, SmoothingFirstScheduleAlsoFits) {
    const Phantom p = make_phantom("sphere", 40);
    RelaxOptions o;
    o.schedule = Schedule::SmoothingFirst;
    o.max_iterations = 30;
    const Relaxed r = relax_phantom(p, o);
    EXPECT_LT(mean_reference_distance(p, r.result.positions), 0.05);
}

TEST(Relaxation, GaussianGradientOnNoisySphere) {
    const Phantom p = make_phantom("noisy-sphere", 40);
    RelaxOptions o;
    o.gradient = GradientMethod::Gaussian;
    o.gradient_sigma = 1.0f;
    o.max_iterations = 30;
    const Relaxed r = relax_phantom(p, o);
    EXPECT_LT(mean_reference_distance(p, r.result.positions), 0.2);
}

TEST(Relaxation, CancelThrows) {
    const Phantom p = make_phantom("sphere", 16);
    const SurfaceNet net = build_surface_net(segment_threshold(p.volume, p.iso));
    std::stop_source source;
    source.request_stop();
    Progress progress{source.get_token(), {}};
    EXPECT_THROW(relax(net, nullptr, RelaxOptions{.mode = RelaxMode::Averaging}, {}, progress),
                 Cancelled);
}
