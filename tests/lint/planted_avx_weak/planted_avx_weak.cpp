// Planted for vector_symbols_lint: an inline function compiled with -mavx2
// for the whole file and emitted out of line, i.e. a weak function holding
// AVX instructions that the linker could keep for baseline callers.
#include <immintrin.h>

#include <cstdint>

inline __attribute__((noinline)) int64_t planted_lane_sum(const int64_t* p) {
  const __m256i v = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(p));
  const __m256i s = _mm256_add_epi64(v, _mm256_permute4x64_epi64(v, 0x4E));
  return _mm256_extract_epi64(s, 0) + _mm256_extract_epi64(s, 1);
}

int64_t planted_entry(const int64_t* p) { return planted_lane_sum(p); }
