// Runs a costly per-element body on only the elements a cheap test selects,
// without a branch on the test per element: each block of kSelectBlock
// elements first lists the selected indices (every index is written, the
// count advances by the test's 0 or 1), then visits the list. Where the test
// passes for a mix of elements along the order, a branch on it mispredicts
// about once per change of outcome; the list costs a store per element.
// The visits run in ascending index order, as a plain loop would; a body
// that reads and writes only its own element gives the same words either way.
// No allocation: the list is a stack array.
#pragma once

#include <cstdint>

namespace sinew::layer {

inline constexpr uint32_t kSelectBlock = 256;

// selected(i) -> bool for each i in [begin, end), then visit(i) for each
// selected i, block by block.
template <class Selected, class Visit>
void visit_selected(uint32_t begin, uint32_t end, const Selected& selected, const Visit& visit) {
  uint32_t list[kSelectBlock];
  for (uint32_t block = begin; block < end;) {
    const uint32_t stop = end - block > kSelectBlock ? block + kSelectBlock : end;
    uint32_t count = 0;
    for (uint32_t i = block; i < stop; ++i) {
      list[count] = i;
      count += static_cast<uint32_t>(selected(i));
    }
    for (uint32_t k = 0; k < count; ++k) visit(list[k]);
    block = stop;
  }
}

}  // namespace sinew::layer
