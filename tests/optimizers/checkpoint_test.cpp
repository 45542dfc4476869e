// Checkpoints and resumed runs (optimizers/checkpoint.hpp): a run hands out its state every
// checkpoint_every iterations and at the end; minimize(..., &checkpoint) continues from it with
// the history, counts and clock going on, for every back-end. gradient_descent keeps its whole
// state, so its resumed run retraces the uninterrupted one exactly.
#include "optimizers/checkpoint.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <stdexcept>
#include <vector>

#include "tests/optimizers/test_functionals.hpp"
#include "tests/support/every_backend.hpp"

namespace tailor::test::checkpoint_test {
namespace {

using ::testing::HasSubstr;

Vector start() { return Eigen::Vector2d(-1.2, 1.0); }

// A run of Rosenbrock(2) from (-1.2, 1): the iterations of the checkpoints it handed out, and
// the checkpoints themselves at the iterations asked for in `keep` (each holds the history, so
// keeping all of a long run would take quadratic memory).
struct CheckpointedRun {
  OptimizerResult result;
  std::vector<int> iterations;
  std::vector<OptimizerCheckpoint> checkpoints;
};

OptimizerOptions options_for(OptimizerBackend backend, int every) {
  OptimizerOptions options;
  options.backend = backend;
  options.max_iterations = 100000;
  options.gradient_tolerance = 1e-8;
  options.checkpoint_every = every;
  return options;
}

CheckpointedRun run(OptimizerBackend backend, int every, const OptimizerCheckpoint* resume = nullptr,
                    const std::vector<int>& keep = {}) {
  CheckpointedRun out;
  OptimizerOptions options = options_for(backend, every);
  options.on_checkpoint = [&out, &keep](const OptimizerCheckpoint& c) {
    out.iterations.push_back(c.iteration);
    if (std::find(keep.begin(), keep.end(), c.iteration) != keep.end()) out.checkpoints.push_back(c);
  };
  Rosenbrock rosenbrock(2);
  out.result = minimize(rosenbrock, start(), {}, {}, options, resume);
  return out;
}

// Checkpoints of a run with `iterations` iterations every k: at k, 2k, ... and the last.
std::vector<int> expected_iterations(int iterations, int k) {
  std::vector<int> out;
  for (int i = k; i <= iterations; i += k) out.push_back(i);
  if (out.empty() || out.back() != iterations) out.push_back(iterations);
  return out;
}

class CheckpointEveryBackend : public ::testing::TestWithParam<OptimizerBackend> {};

TEST_P(CheckpointEveryBackend, CheckpointsComeEveryKIterationsAndAtTheEnd) {
  const int k = 3;
  const CheckpointedRun first = run(GetParam(), k);
  ASSERT_TRUE(first.result.converged()) << first.result.message;
  const int iterations = first.result.history.back().iteration;
  EXPECT_EQ(first.iterations, expected_iterations(iterations, k));

  const CheckpointedRun full = run(GetParam(), k, nullptr, {k, iterations});
  ASSERT_EQ(full.checkpoints.size(), 2u);
  for (const OptimizerCheckpoint& c : full.checkpoints) {
    EXPECT_EQ(c.backend, GetParam());
    ASSERT_EQ(static_cast<int>(c.history.size()), c.iteration + 1);
    for (int i = 0; i <= c.iteration; ++i)
      EXPECT_EQ(c.history[static_cast<std::size_t>(i)].objective,
                full.result.history[static_cast<std::size_t>(i)].objective);
    EXPECT_EQ(c.objective, c.history.back().objective);
    EXPECT_DOUBLE_EQ(Rosenbrock(2).value(c.z), c.objective);  // z is the row's iterate
    EXPECT_LE(c.best_objective, c.objective);
    EXPECT_LE(c.evaluations, full.result.evaluations);
    // The work up to the checkpoint (the final one also counts a back-end's last evaluations).
    EXPECT_GE(c.counters.forward_solves, c.history.back().forward_solves);
  }
  EXPECT_EQ(full.checkpoints.front().counters.forward_solves,
            full.checkpoints.front().history.back().forward_solves);
}

// Resumed from the checkpoint in the middle of the run, every back-end reaches the same
// minimum; the history keeps the checkpoint's rows and goes on from its iteration.
TEST_P(CheckpointEveryBackend, ResumedRunReachesTheSameMinimumAndContinuesTheHistory) {
  const int k = 2;
  const CheckpointedRun first = run(GetParam(), k);
  ASSERT_TRUE(first.result.converged()) << first.result.message;
  ASSERT_GE(first.iterations.size(), 2u) << "too short a run to resume in the middle";
  const int middle_iteration = first.iterations[first.iterations.size() / 2 - 1];
  const CheckpointedRun full = run(GetParam(), k, nullptr, {middle_iteration});
  ASSERT_EQ(full.checkpoints.size(), 1u);
  const OptimizerCheckpoint& middle = full.checkpoints.front();

  const CheckpointedRun resumed = run(GetParam(), k, &middle);
  const OptimizerResult& r = resumed.result;
  std::cout << to_string(GetParam()) << ": uninterrupted " << full.result.history.back().iteration
            << " iterations; resumed at " << middle.iteration << ", ends at " << r.history.back().iteration
            << "\n";
  ASSERT_TRUE(r.converged()) << r.message;
  ASSERT_TRUE(r.resumed_from);
  EXPECT_EQ(*r.resumed_from, middle.iteration);
  EXPECT_THAT(r.report(), HasSubstr("resumed        : from the checkpoint at iteration " +
                                    std::to_string(middle.iteration)));
  EXPECT_LT((r.z - Vector::Ones(2)).lpNorm<Eigen::Infinity>(), 1e-5);
  EXPECT_NEAR(r.objective, full.result.objective, 1e-10);
  // The history: the checkpoint's rows unchanged, then one row per iteration from there.
  ASSERT_GT(r.history.size(), middle.history.size());
  for (std::size_t i = 0; i < r.history.size(); ++i) EXPECT_EQ(r.history[i].iteration, static_cast<int>(i));
  for (std::size_t i = 0; i < middle.history.size(); ++i) {
    EXPECT_EQ(r.history[i].objective, middle.history[i].objective);
    EXPECT_EQ(r.history[i].seconds, middle.history[i].seconds);
  }
  // Counts and time go on from the checkpoint's.
  EXPECT_GT(r.evaluations, middle.evaluations);
  EXPECT_GE(r.seconds, middle.seconds);
  EXPECT_GE(r.history[middle.history.size()].seconds, middle.seconds);
  EXPECT_GT(r.counters.forward_solves, middle.counters.forward_solves);
  EXPECT_LE(r.history.back().forward_solves, r.counters.forward_solves);
  // Its own checkpoints continue the numbering (none at the resumed iteration again).
  ASSERT_FALSE(resumed.iterations.empty());
  EXPECT_GT(resumed.iterations.front(), middle.iteration);
  EXPECT_EQ(resumed.iterations.back(), r.history.back().iteration);
}

INSTANTIATE_TEST_SUITE_P(Optimizers, CheckpointEveryBackend, ::testing::ValuesIn(test::every_backend()),
                         [](const ::testing::TestParamInfo<OptimizerBackend>& param_info) {
                           return to_string(param_info.param);
                         });

// gradient_descent's state is its iterate and its step length: resumed anywhere, it takes the
// same steps as the uninterrupted run, to the last bit.
TEST(GradientDescentResume, RetracesTheUninterruptedRunExactly) {
  const int k = 25;
  const CheckpointedRun first = run(OptimizerBackend::gradient_descent, k);
  ASSERT_TRUE(first.result.converged()) << first.result.message;
  ASSERT_GE(first.iterations.size(), 3u);
  const CheckpointedRun full = run(OptimizerBackend::gradient_descent, k, nullptr,
                                   {first.iterations.front(), first.iterations[first.iterations.size() / 2]});
  ASSERT_EQ(full.checkpoints.size(), 2u);
  for (const OptimizerCheckpoint* c : {&full.checkpoints.front(), &full.checkpoints.back()}) {
    ASSERT_TRUE(c->backend_state.count("step"));
    const CheckpointedRun resumed = run(OptimizerBackend::gradient_descent, k, c);
    const OptimizerResult& r = resumed.result;
    ASSERT_EQ(r.history.size(), full.result.history.size()) << "resumed at " << c->iteration;
    for (std::size_t i = 0; i < r.history.size(); ++i) {
      EXPECT_EQ(r.history[i].objective, full.result.history[i].objective) << i;
      EXPECT_EQ(r.history[i].step_norm, full.result.history[i].step_norm) << i;
    }
    EXPECT_EQ(r.z, full.result.z);
    EXPECT_EQ(r.status, full.result.status);
  }
}

TEST(CeresLeastSquaresResume, TakesTheTrustRegionRadiusBack) {
  const CheckpointedRun full = run(OptimizerBackend::ceres_least_squares, 2, nullptr, {2});
  ASSERT_FALSE(full.checkpoints.empty());
  const auto radius = full.checkpoints.front().backend_state.find("trust_region_radius");
  ASSERT_NE(radius, full.checkpoints.front().backend_state.end());
  EXPECT_GT(radius->second, 0.0);
}

TEST(Resume, RefusesACheckpointOfAnotherRun) {
  const CheckpointedRun full = run(OptimizerBackend::nlopt_lbfgs, 2, nullptr, {2});
  ASSERT_FALSE(full.checkpoints.empty());
  OptimizerCheckpoint c = full.checkpoints.front();
  Rosenbrock rosenbrock(2);
  OptimizerResult r =
      minimize(rosenbrock, start(), {}, {}, options_for(OptimizerBackend::gradient_descent, 2), &c);
  EXPECT_EQ(r.status, OptimizerStatus::failed);
  EXPECT_THAT(r.message, HasSubstr("the checkpoint is of back-end nlopt_lbfgs, not gradient_descent"));
  EXPECT_EQ(rosenbrock.calls, 0);

  Rosenbrock larger(3);
  r = minimize(larger, Vector::Zero(3), {}, {}, options_for(OptimizerBackend::nlopt_lbfgs, 2), &c);
  EXPECT_EQ(r.status, OptimizerStatus::failed);
  EXPECT_THAT(r.message, HasSubstr("the checkpoint's design has size 2, the functional 3"));

  c.history.pop_back();
  r = minimize(rosenbrock, start(), {}, {}, options_for(OptimizerBackend::nlopt_lbfgs, 2), &c);
  EXPECT_EQ(r.status, OptimizerStatus::failed);
  EXPECT_THAT(r.message, HasSubstr("does not end at its iteration"));
}

TEST(Resume, AtOrBeyondMaxIterationsStopsAtOnce) {
  const CheckpointedRun full = run(OptimizerBackend::gradient_descent, 5, nullptr, {5});
  ASSERT_FALSE(full.checkpoints.empty());
  const OptimizerCheckpoint& c = full.checkpoints.front();
  OptimizerOptions options = options_for(OptimizerBackend::gradient_descent, 5);
  options.max_iterations = c.iteration;
  Rosenbrock rosenbrock(2);
  const OptimizerResult r = minimize(rosenbrock, start(), {}, {}, options, &c);
  EXPECT_EQ(r.status, OptimizerStatus::max_iterations) << r.message;
  EXPECT_EQ(r.history.size(), c.history.size());
  EXPECT_EQ(r.z, c.best_z);
  EXPECT_EQ(rosenbrock.calls, 0);
}

// The callback may fail (a full disk): the run stops with the reason instead of going on
// without checkpoints, and keeps its best point.
TEST(Checkpoint, AFailingCallbackStopsTheRun) {
  OptimizerOptions options = options_for(OptimizerBackend::nlopt_lbfgs, 4);
  int calls = 0;
  options.on_checkpoint = [&calls](const OptimizerCheckpoint&) {
    ++calls;
    throw std::runtime_error("cannot write 'checkpoint.json.tmp': No space left on device");
  };
  Rosenbrock rosenbrock(2);
  const OptimizerResult r = minimize(rosenbrock, start(), {}, {}, options);
  EXPECT_EQ(r.status, OptimizerStatus::failed);
  EXPECT_THAT(r.message, HasSubstr("checkpoint failed: cannot write 'checkpoint.json.tmp'"));
  EXPECT_EQ(calls, 1);  // not retried at the end
  EXPECT_EQ(r.history.back().iteration, 4);
  EXPECT_LT(r.objective, Rosenbrock(2).value(start()));
}

TEST(Checkpoint, NoneWithoutACallbackOrWithKZero) {
  OptimizerOptions options = options_for(OptimizerBackend::nlopt_lbfgs, 0);
  int calls = 0;
  options.on_checkpoint = [&calls](const OptimizerCheckpoint&) { ++calls; };
  Rosenbrock rosenbrock(2);
  const OptimizerResult r = minimize(rosenbrock, start(), {}, {}, options);
  EXPECT_TRUE(r.converged()) << r.message;
  EXPECT_EQ(calls, 1);  // only the final one
  EXPECT_FALSE(r.resumed_from);
}

}  // namespace
}  // namespace tailor::test::checkpoint_test
