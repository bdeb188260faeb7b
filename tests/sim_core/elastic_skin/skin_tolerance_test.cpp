// Static relaxation's stopping rule (anatomically-based-modeling §5.2): stop
// at the tolerance or the iteration count, report iterations and residual.
#include <gtest/gtest.h>

#include <vector>

#include "tests/sim_core/muscle/anatomy_fixture.hpp"

using sinew::test::ArmAnatomy;

TEST(SkinTolerance, StopsAtTheFirstIterationBelowTheTolerance) {
  namespace ab = sinew::anatomy_build;
  ArmAnatomy arm([](ab::AnatomySpec& s) { s.skin.iterations = 40; });
  ASSERT_TRUE(arm.ok()) << arm.error();
  arm.set("elbow.0", 100);
  arm.set("shoulder.0", 30);
  ASSERT_TRUE(arm.step().ok());
  // Without a tolerance every iteration runs; this run is the oracle for the
  // stop: the same deterministic rounds, so with a tolerance the run must
  // stop right after the first round whose largest move is below it.
  const sinew::elastic_skin::SkinStats full = arm.skin().stats;
  EXPECT_EQ(full.iterations, 40u);
  EXPECT_EQ(full.converged, 0u);
  EXPECT_EQ(full.residual, full.max_relax_last);
  const std::vector<sinew::fx::Len> moves(arm.skin().max_relax.begin(), arm.skin().max_relax.begin() + 40);
  const sinew::fx::Len tolerance = moves[8] + 1;
  uint32_t expected = 40;
  for (uint32_t i = 0; i + 1 < 40; ++i)
    if (moves[i] < tolerance) {
      expected = i + 1;
      break;
    }
  ASSERT_LE(expected, 9u);

  sinew::elastic_skin::SkinModel model = arm.skin_model();
  model.solver.tolerance = tolerance;
  ASSERT_TRUE(arm.step_muscles().ok());
  ASSERT_TRUE(
      sinew::elastic_skin::skin_step(model, arm.muscle_model(), arm.muscles(), arm.engine().model, &arm.skin()).ok());
  const sinew::elastic_skin::SkinStats& s = arm.skin().stats;
  EXPECT_EQ(s.iterations, expected);
  EXPECT_EQ(s.converged, 1u);
  EXPECT_LT(s.residual, tolerance);
  // The early stop still removes every penetration.
  EXPECT_EQ(s.inside_after, 0u);
}
