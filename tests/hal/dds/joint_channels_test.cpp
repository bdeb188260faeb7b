// Engine values <-> SI on a JointState: what the sink publishes, the source
// reads back word for word; what cannot be an engine value is refused.
#include "hal/dds/joint_channels.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <numbers>

namespace joint_channels_test {

using sinew::hal::dds::joint_value_from_si;
using sinew::hal::dds::joint_value_to_si;
using sinew::hal::dds::JointUnit;

TEST(JointChannels, EveryUnitRoundTripsWordForWord) {
  for (const JointUnit unit : {JointUnit::kRadian, JointUnit::kMetre, JointUnit::kNewton, JointUnit::kScalar})
    for (const int32_t v : {0, 1, -1, 123456789, -987654321, INT32_MAX, INT32_MIN}) {
      int32_t back = 0;
      ASSERT_TRUE(joint_value_from_si(joint_value_to_si(v, unit, -4), unit, -4, &back)) << v;
      EXPECT_EQ(back, v) << static_cast<int>(unit);
    }
}

TEST(JointChannels, SiValuesAreRos2s) {
  // A quarter turn is pi/2 rad; one rig unit of 2^-4 m at Q12.20.
  EXPECT_DOUBLE_EQ(joint_value_to_si(1 << 30, JointUnit::kRadian, 0), std::numbers::pi / 2);
  EXPECT_DOUBLE_EQ(joint_value_to_si(1 << 20, JointUnit::kMetre, -4), 1.0 / 16);
  EXPECT_DOUBLE_EQ(joint_value_to_si(3 << 16, JointUnit::kNewton, 0), 3.0);
  int32_t v = 0;
  ASSERT_TRUE(joint_value_from_si(-std::numbers::pi / 2, JointUnit::kRadian, 0, &v));
  EXPECT_EQ(v, -(1 << 30));
  ASSERT_TRUE(joint_value_from_si(2.5 * std::numbers::pi, JointUnit::kRadian, 0, &v));  // reduced to one turn
  EXPECT_EQ(v, 1 << 30);
}

TEST(JointChannels, NonFiniteAndOutOfRangeAreRefused) {
  int32_t v = 7;
  for (const JointUnit unit : {JointUnit::kRadian, JointUnit::kMetre, JointUnit::kNewton})
    for (const double x : {std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::infinity(),
                           -std::numeric_limits<double>::infinity()})
      EXPECT_FALSE(joint_value_from_si(x, unit, 0, &v)) << x;
  EXPECT_FALSE(joint_value_from_si(5000.0, JointUnit::kMetre, 0, &v));    // beyond 2048 rig units
  EXPECT_FALSE(joint_value_from_si(40000.0, JointUnit::kNewton, 0, &v));  // beyond Q16.16
  EXPECT_EQ(v, 7);
}

}  // namespace joint_channels_test
