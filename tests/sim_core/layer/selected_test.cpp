// visit_selected (sim_core/layer/selected.hpp): the elements its test
// selects, each once, in ascending order, across block boundaries.
#include "sim_core/layer/selected.hpp"

#include <gtest/gtest.h>

#include <cstdint>
#include <vector>

namespace layer = sinew::layer;

TEST(VisitSelected, VisitsExactlyTheSelectedElementsInOrder) {
  // Ranges shorter than, equal to and spanning several blocks, starting off a block's edge.
  const uint32_t ranges[][2] = {{0, 0}, {5, 6}, {3, 3 + layer::kSelectBlock}, {17, 1000}, {0, 4 * layer::kSelectBlock}};
  for (const auto& r : ranges) {
    for (uint32_t every : {1u, 2u, 7u, 1000u}) {
      std::vector<uint32_t> seen, expected;
      for (uint32_t i = r[0]; i < r[1]; ++i)
        if (i % every == 0) expected.push_back(i);
      layer::visit_selected(
          r[0], r[1], [&](uint32_t i) { return i % every == 0; }, [&](uint32_t i) { seen.push_back(i); });
      EXPECT_EQ(seen, expected) << r[0] << ".." << r[1] << " every " << every;
    }
  }
}
