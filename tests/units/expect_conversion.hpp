// Compares a conversion's value and flags in one assertion, with both in the
// failure message.
#pragma once

#include <gtest/gtest.h>

#include "hal/units/float_to_fixed.hpp"

namespace sinew::units {

template <typename Result, typename Value>
testing::AssertionResult converts_to(const Result& r, Value value, ConversionFlags flags) {
  if (r.value == value && r.flags == flags) return testing::AssertionSuccess();
  return testing::AssertionFailure() << "got {" << r.value << ", flags " << int{r.flags} << "}, want {"
                                     << value << ", flags " << int{flags} << "}";
}

}  // namespace sinew::units
