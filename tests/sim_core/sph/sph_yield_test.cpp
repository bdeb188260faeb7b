// The joint-level yield (sim_core/sph/sph_yield.hpp): it enters at
// yield_count yielded particles and holds the torque it took; a load held
// above that keeps it yielded; it leaves only when no particle yields and
// the load has fallen back to the held torque; it never latches beyond that.
#include "sim_core/sph/sph_yield.hpp"

#include <gtest/gtest.h>

namespace sph = sinew::sph;

TEST(SphJointYield, EntersAtTheCountAndHoldsTheTorqueItTook) {
  const sph::JointYield none{};
  EXPECT_FALSE(sph::next_joint_yield(none, true, 4, 5, 900, 900).yielded) << "below the count";
  const sph::JointYield y = sph::next_joint_yield(none, true, 5, 5, -900, -900);
  ASSERT_TRUE(y.yielded);
  EXPECT_EQ(y.held_torque_q12, 900);
  // While it yields the load it takes is held, with the load's sign.
  EXPECT_EQ(sph::held_load_torque(y, 2000), 900);
  EXPECT_EQ(sph::held_load_torque(y, -2000), -900);
  EXPECT_EQ(sph::held_load_torque(y, 300), 300);
  EXPECT_EQ(sph::held_load_torque(none, 2000), 2000) << "an unyielded joint takes the whole load";
}

TEST(SphJointYield, LeavesOnlyWhenTheParticlesAndTheLoadHaveFallenBack) {
  const sph::JointYield y{true, 900};
  // One particle still at the limit: held.
  EXPECT_TRUE(sph::next_joint_yield(y, true, 1, 5, 100, 100).yielded);
  // No particle yields, but the load is still above the held torque (the
  // tissue relaxed under the hold): held, not released to the full load.
  const sph::JointYield held = sph::next_joint_yield(y, true, 0, 5, 2000, 900);
  EXPECT_TRUE(held.yielded);
  EXPECT_EQ(held.held_torque_q12, 900);
  // Both fallen back: released, nothing remembered.
  const sph::JointYield released = sph::next_joint_yield(y, true, 0, 5, -900, -900);
  EXPECT_FALSE(released.yielded);
  EXPECT_EQ(released.held_torque_q12, 0);
  EXPECT_EQ(sph::held_load_torque(released, 2000), 2000);
}

TEST(SphJointYield, WithoutTrescaNothingYields) {
  EXPECT_FALSE(sph::next_joint_yield({}, false, 100, 5, 900, 900).yielded);
  EXPECT_FALSE(sph::next_joint_yield({true, 900}, false, 100, 5, 900, 900).yielded);
}
