// The relaxation history: keyframes under a memory budget, and recomputation that gives back
// exactly the positions the relaxation produced.
#include <gtest/gtest.h>

#include <cstring>

#include "app/iteration_history.h"
#include "core/phantom.h"
#include "core/pipeline.h"
#include "core/segmentation.h"
#include "support/test_meshes.h"

using namespace snert;
using namespace snert::app;

namespace {

struct Recorded {
    std::shared_ptr<const RelaxContext> context;
    std::vector<std::vector<glm::vec3>> positions; // [k] after iteration k, straight from relax()
};

std::shared_ptr<const RelaxContext> make_context(const Phantom& phantom, RelaxOptions options) {
    auto c = std::make_shared<RelaxContext>();
    c->volume = std::make_shared<const Volume>(phantom.volume);
    options.iso = phantom.iso;
    c->options = options;
    c->net = std::make_shared<const SurfaceNet>(test::phantom_net(phantom));
    c->grey = std::make_shared<const GreyField>(make_grey_field(*c->volume, c->options));
    return c;
}

// Runs relax() and feeds every iteration to `history`, keeping a full copy for comparison.
Recorded relax_into(IterationHistory& history) {
    Recorded r;
    const RelaxContext& c = history.context();
    r.positions.push_back(c.net->positions);
    relax(*c.net, c.grey.get(), c.options,
          [&](const RelaxIteration&, std::span<const glm::vec3> p) {
              history.append(p);
              r.positions.emplace_back(p.begin(), p.end());
              return true;
          });
    return r;
}

bool bitwise_equal(const std::vector<glm::vec3>& a, const std::vector<glm::vec3>& b) {
    return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(a[0])) == 0;
}

RelaxOptions options_for(int iterations) {
    RelaxOptions o;
    o.max_iterations = iterations;
    o.epsilon = 0.0f; // run every iteration
    return o;
}

std::size_t frame_bytes(const RelaxContext& c) {
    return c.net->positions.size() * sizeof(glm::vec3);
}

} // namespace

TEST(IterationHistory, KeepsEveryIterationWithinTheBudget) {
    const Phantom sphere = make_phantom("sphere", 20);
    auto context = make_context(sphere, options_for(12));
    IterationHistory history(context, std::size_t(1) << 30);
    const Recorded r = relax_into(history);
    ASSERT_EQ(history.count(), 13);
    EXPECT_EQ(history.stride(), 1);
    EXPECT_EQ(history.stored_bytes(), 12 * frame_bytes(*context));
    for (int k = 0; k < history.count(); ++k) {
        EXPECT_TRUE(history.stored(k)) << k;
        EXPECT_TRUE(bitwise_equal(history.positions(k), r.positions[std::size_t(k)])) << k;
        EXPECT_EQ(history.last_recomputed_steps(), 0);
    }
}

// The budget holds 5 frames; 40 iterations force the stride up to 8 (40 / 8 = 5 keyframes).
TEST(IterationHistory, RecomputesFromKeyframesExactlyBeyondTheBudget) {
    const Phantom sphere = make_phantom("two-spheres", 24);
    auto context = make_context(sphere, options_for(40));
    const std::size_t budget = 5 * frame_bytes(*context);
    IterationHistory history(context, budget);
    const Recorded r = relax_into(history);
    ASSERT_EQ(history.count(), 41);
    EXPECT_EQ(history.stride(), 8);
    EXPECT_LE(history.stored_bytes(), budget);
    EXPECT_EQ(history.stored_bytes(), 5 * frame_bytes(*context)); // 8, 16, 24, 32, 40
    int recomputed = 0;
    for (int k = 40; k >= 0; --k) { // backwards, so the scratch frame never helps
        EXPECT_EQ(history.stored(k), k % 8 == 0) << k;
        EXPECT_TRUE(bitwise_equal(history.positions(k), r.positions[std::size_t(k)])) << k;
        EXPECT_EQ(history.last_recomputed_steps(), k % 8) << k; // from the keyframe below k
        recomputed += history.last_recomputed_steps() > 0 ? 1 : 0;
    }
    EXPECT_EQ(recomputed, 41 - 6);
}

TEST(IterationHistory, SteppingForwardCostsOneStep) {
    const Phantom sphere = make_phantom("sphere", 20);
    auto context = make_context(sphere, options_for(20));
    IterationHistory history(context, 0); // keeps nothing but the latest
    const Recorded r = relax_into(history);
    EXPECT_EQ(history.stored_bytes(), 0u);
    EXPECT_TRUE(bitwise_equal(history.positions(10), r.positions[10]));
    EXPECT_EQ(history.last_recomputed_steps(), 10);
    for (int k = 11; k < 20; ++k) {
        EXPECT_TRUE(bitwise_equal(history.positions(k), r.positions[std::size_t(k)])) << k;
        EXPECT_EQ(history.last_recomputed_steps(), 1) << k;
    }
    EXPECT_TRUE(bitwise_equal(history.positions(20), r.positions[20]));
    EXPECT_EQ(history.last_recomputed_steps(), 0); // the latest is always kept
}

// Every mode and schedule replays exactly, the two-sub-step schedule and the Gaussian field too.
TEST(IterationHistory, ReplaysEveryModeExactly) {
    const Phantom torus = make_phantom("torus", 24);
    for (RelaxMode mode : {RelaxMode::Averaging, RelaxMode::Gradient, RelaxMode::Snert}) {
        for (Schedule schedule : {Schedule::Simultaneous, Schedule::SmoothingFirst}) {
            RelaxOptions o = options_for(9);
            o.mode = mode;
            o.schedule = schedule;
            o.gradient = GradientMethod::Gaussian;
            o.gradient_sigma = 1.2f;
            auto context = make_context(torus, o);
            IterationHistory history(context, 2 * frame_bytes(*context));
            const Recorded r = relax_into(history);
            for (int k = 0; k <= 9; ++k)
                EXPECT_TRUE(bitwise_equal(history.positions(k), r.positions[std::size_t(k)]))
                    << "mode " << int(mode) << " schedule " << int(schedule) << " k " << k;
        }
    }
}

TEST(IterationHistory, RejectsBadInput) {
    const Phantom sphere = make_phantom("sphere", 16);
    auto context = make_context(sphere, options_for(3));
    IterationHistory history(context, 0);
    std::vector<glm::vec3> wrong(context->net->positions.size() + 1);
    EXPECT_THROW(history.append(wrong), std::invalid_argument);
    EXPECT_EQ(history.count(), 1);
    EXPECT_THROW(history.positions(-1), std::out_of_range);
    EXPECT_THROW(history.positions(1), std::out_of_range);
    EXPECT_TRUE(bitwise_equal(history.positions(0), context->net->positions));
}

TEST(IterationHistory, RecomputationStopsWhenCancelled) {
    const Phantom sphere = make_phantom("sphere", 16);
    auto context = make_context(sphere, options_for(6));
    IterationHistory history(context, 0);
    relax_into(history);
    std::stop_source stop;
    stop.request_stop();
    EXPECT_THROW(history.positions(3, stop.get_token()), Cancelled);
}
