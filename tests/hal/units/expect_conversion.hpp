// Helpers of the conversion tests: one assertion comparing a conversion's
// value and flags, and the neighbouring doubles of a range edge.
#pragma once

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "hal/units/float_to_fixed.hpp"

namespace sinew::units {

inline constexpr double kInf = std::numeric_limits<double>::infinity();

// The doubles just below and just above x.
inline double below(double x) { return std::nextafter(x, -kInf); }
inline double above(double x) { return std::nextafter(x, kInf); }

template <typename Result, typename Value>
testing::AssertionResult converts_to(const Result& r, Value value, ConversionFlags flags) {
  if (r.value == value && r.flags == flags) return testing::AssertionSuccess();
  return testing::AssertionFailure() << "got {" << r.value << ", flags " << int{r.flags} << "}, want {" << value
                                     << ", flags " << int{flags} << "}";
}

}  // namespace sinew::units
