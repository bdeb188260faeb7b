#include "vector_kernel.hpp"

namespace sinew::barnet {

bool vector_kernel_supported(VectorKernel kernel) {
  switch (kernel) {
    case VectorKernel::kScalar:
      return true;
    case VectorKernel::kAvx2:
#if defined(__x86_64__)
      return __builtin_cpu_supports("avx2") != 0;
#else
      return false;
#endif
    case VectorKernel::kAvx512:
#if defined(__x86_64__)
      return __builtin_cpu_supports("avx2") != 0 && __builtin_cpu_supports("avx512f") != 0 &&
             __builtin_cpu_supports("avx512vl") != 0 && __builtin_cpu_supports("avx512cd") != 0;
#else
      return false;
#endif
  }
  return false;
}

VectorKernel vector_kernel_default() {
  if (vector_kernel_supported(VectorKernel::kAvx512)) return VectorKernel::kAvx512;
  return vector_kernel_supported(VectorKernel::kAvx2) ? VectorKernel::kAvx2 : VectorKernel::kScalar;
}

}  // namespace sinew::barnet
