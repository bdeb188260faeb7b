#include "hal/can/engine_units.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <numbers>

namespace sinew::hal::can {
namespace {

int32_t convert(double v, PhysicalUnit u) {
  int32_t out = 12345;
  EXPECT_TRUE(to_engine_value(v, u, out)) << v;
  return out;
}

TEST(EngineUnits, DegreesToBinaryAngle) {
  EXPECT_EQ(convert(0.0, PhysicalUnit::kDegrees), 0);
  EXPECT_EQ(convert(90.0, PhysicalUnit::kDegrees), 1 << 30);
  EXPECT_EQ(convert(-90.0, PhysicalUnit::kDegrees), -(1 << 30));
  EXPECT_EQ(convert(180.0, PhysicalUnit::kDegrees), INT32_MIN);  // half a turn: the wrap point
  EXPECT_EQ(convert(-180.0, PhysicalUnit::kDegrees), INT32_MIN);
  EXPECT_EQ(convert(360.0, PhysicalUnit::kDegrees), 0);
  EXPECT_EQ(convert(450.0, PhysicalUnit::kDegrees), 1 << 30);  // angles wrap
}

TEST(EngineUnits, RadiansToBinaryAngle) {
  EXPECT_EQ(convert(std::numbers::pi / 2, PhysicalUnit::kRadians), 1 << 30);
  EXPECT_EQ(convert(-std::numbers::pi / 4, PhysicalUnit::kRadians), -(1 << 29));
}

TEST(EngineUnits, RoundsHalfUp) {
  const double lsb = 360.0 / 4294967296.0;
  EXPECT_EQ(convert(0.5 * lsb, PhysicalUnit::kDegrees), 1);
  EXPECT_EQ(convert(0.49 * lsb, PhysicalUnit::kDegrees), 0);
  EXPECT_EQ(convert(-0.5 * lsb, PhysicalUnit::kDegrees), 0);  // ties toward +infinity
  EXPECT_EQ(convert(0.5 / 1048576.0, PhysicalUnit::kRigUnits), 1);
  EXPECT_EQ(convert(-0.5 / 1048576.0, PhysicalUnit::kRigUnits), 0);
}

TEST(EngineUnits, RigUnitsToQ12_20) {
  EXPECT_EQ(convert(1.0, PhysicalUnit::kRigUnits), 1 << 20);
  EXPECT_EQ(convert(-1.5, PhysicalUnit::kRigUnits), -(3 << 19));
  EXPECT_EQ(convert(-2048.0, PhysicalUnit::kRigUnits), INT32_MIN);
  int32_t out = 7;
  EXPECT_FALSE(to_engine_value(2048.0, PhysicalUnit::kRigUnits, out));
  EXPECT_FALSE(to_engine_value(-2048.001, PhysicalUnit::kRigUnits, out));
  EXPECT_EQ(out, 7);
}

TEST(EngineUnits, NonFiniteIsRefused) {
  int32_t out = 7;
  EXPECT_FALSE(to_engine_value(std::numeric_limits<double>::quiet_NaN(), PhysicalUnit::kDegrees, out));
  EXPECT_FALSE(to_engine_value(std::numeric_limits<double>::infinity(), PhysicalUnit::kRadians, out));
  EXPECT_EQ(out, 7);
}

TEST(EngineUnits, InverseForReports) {
  EXPECT_DOUBLE_EQ(from_engine_value(1 << 30, PhysicalUnit::kDegrees), 90.0);
  EXPECT_DOUBLE_EQ(from_engine_value(3 << 19, PhysicalUnit::kRigUnits), 1.5);
}

}  // namespace
}  // namespace sinew::hal::can
