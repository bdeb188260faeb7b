#include "step_timing.hpp"

#include <bit>

namespace sinew::firmware {

size_t StepTiming::bucket_of(uint64_t ns) {
  if (ns < kSub) return static_cast<size_t>(ns);  // exact below 16 ns
  const int octave = 63 - std::countl_zero(ns);   // >= 4
  const uint64_t sub = (ns >> (octave - 4)) & (kSub - 1);
  const size_t b = static_cast<size_t>((octave - 3) * kSub) + static_cast<size_t>(sub);
  return b < kSub * kOctaves ? b : kSub * kOctaves - 1;
}

uint64_t StepTiming::upper_edge(size_t bucket) {
  if (bucket < kSub) return bucket;
  const int octave = static_cast<int>(bucket / kSub) + 3;
  const uint64_t sub = bucket % kSub;
  return ((uint64_t{kSub} + sub + 1) << (octave - 4)) - 1;
}

void StepTiming::record(uint64_t step_ns, bool missed_deadline) {
  ++buckets_[bucket_of(step_ns)];
  ++count_;
  if (step_ns > max_) max_ = step_ns;
  if (missed_deadline) ++misses_;
}

uint64_t StepTiming::percentile_ns(double p) const {
  if (count_ == 0) return 0;
  const auto target = static_cast<uint64_t>(p * static_cast<double>(count_ - 1)) + 1;
  uint64_t seen = 0;
  for (size_t b = 0; b < buckets_.size(); ++b) {
    seen += buckets_[b];
    if (seen >= target) return upper_edge(b) < max_ ? upper_edge(b) : max_;
  }
  return max_;
}

}  // namespace sinew::firmware
