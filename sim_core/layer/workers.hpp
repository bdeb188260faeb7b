// Threads a step may spread its per-element loops over. sim_core starts no
// thread: the caller supplies a pool (firmware/runtime/worker_pool.hpp, or a
// test's), as Box2D v3's task callbacks let the application run the solver's
// work. The library cuts a loop into fixed ranges; the pool runs them.
//
// Determinism: a loop given to run_ranges writes disjoint elements, and
// each range reads nothing another range of the same loop writes, so the
// words written are the same for every number of parts and every order or
// thread the ranges run on. A loop that reduces (a sum over elements) is
// never given to it; it stays serial in its fixed order.
#pragma once

#include <cstdint>

namespace sinew::layer {

// One range [begin, end) of a loop's elements.
using RangeJob = void (*)(void* context, uint32_t begin, uint32_t end);

struct Workers {
  // Runs job over [0, count) cut into `parts` ranges, range i being
  // [range_begin(count, parts, i), range_begin(count, parts, i + 1)), each
  // on some thread, and returns when every range is done. Must not allocate.
  void (*run)(void* pool, RangeJob job, void* context, uint32_t count) = nullptr;
  void* pool = nullptr;
  uint32_t parts = 1;  // 1..kMaxParts
  // Optional: called before and after the part of a step that runs loops
  // over the workers (pipeline_step: from the stage before the first
  // parallel stage to the end of the last, on every path), so a pool can
  // keep its threads awake and ready between the loops instead of waking
  // them for each (a wake can cost more than a loop's range).
  void (*begin_step)(void* pool) = nullptr;
  void (*end_step)(void* pool) = nullptr;
};

inline constexpr uint32_t kMaxParts = 64;

// The first element of range i of `parts` over `count` elements.
inline uint32_t range_begin(uint32_t count, uint32_t parts, uint32_t i) {
  return static_cast<uint32_t>(uint64_t{count} * i / parts);
}

// Runs job over [0, count): through the workers when there are any and the
// loop has at least 2 x kMinPerLoop elements, else as one range on the
// calling thread (a short loop costs less than waking a thread).
inline constexpr uint32_t kMinPerLoop = 64;
inline void run_ranges(const Workers* workers, uint32_t count, RangeJob job, void* context) {
  if (workers == nullptr || workers->run == nullptr || workers->parts <= 1 || count < 2 * kMinPerLoop) {
    job(context, 0, count);
    return;
  }
  workers->run(workers->pool, job, context, count);
}

}  // namespace sinew::layer
