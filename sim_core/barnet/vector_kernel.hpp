// Who computes the bar-net's inner loops: the scalar specification, or the
// vector kernels beside it (x86-64 only): AVX2, chosen when the CPU reports
// AVX2; AVX-512, chosen when it reports F + VL + CD, which runs the triangle
// frames' normalisation eight at a time and every other loop by the AVX2
// kernels (every CPU with those extensions has AVX2). Every kernel writes
// the same words for every input; the kernel tests compare them word for
// word.
#pragma once

#include <cstdint>

namespace sinew::barnet {

enum class VectorKernel : uint8_t { kScalar, kAvx2, kAvx512 };

// Whether `kernel` runs the AVX2 loops (the AVX-512 kernel runs them too).
inline bool runs_avx2_loops(VectorKernel kernel) {
  return kernel == VectorKernel::kAvx2 || kernel == VectorKernel::kAvx512;
}

// True if this build and this CPU run `kernel` (reads CPUID data, no OS call).
bool vector_kernel_supported(VectorKernel kernel);
// The fastest supported kernel.
VectorKernel vector_kernel_default();

}  // namespace sinew::barnet
