// Who computes the bar-net's inner loops: the scalar specification, or the
// AVX2 kernels beside it (x86-64 only, chosen when the CPU reports AVX2).
// Every kernel writes the same words for every input; the kernel tests
// compare them word for word.
#pragma once

#include <cstdint>

namespace sinew::barnet {

enum class VectorKernel : uint8_t { kScalar, kAvx2 };

// True if this build and this CPU run `kernel` (reads CPUID data, no OS call).
bool vector_kernel_supported(VectorKernel kernel);
// The fastest supported kernel.
VectorKernel vector_kernel_default();

}  // namespace sinew::barnet
