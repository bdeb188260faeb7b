// Loops over the workers (workers.hpp) that also count or take a maximum:
// each range computes its own count (or maximum) and adds it to the total
// once, atomically. Unsigned integer sums and maxima come out the same in
// any order, so the totals, like the elements the ranges write, are the same
// for every number of parts and every scheduling. (A sum that rounds or
// saturates is order-dependent and is never reduced this way.)
#pragma once

#include <atomic>
#include <cstdint>

#include "workers.hpp"

namespace sinew::layer {

// body(begin, end) handles [begin, end) and returns its count; returns the
// sum over [0, count). Must not allocate (nor may body).
template <class Body>
uint32_t run_ranges_summed(const Workers* workers, uint32_t count, const Body& body) {
  struct Job {
    const Body* body;
    uint32_t total;
  } job{&body, 0};
  run_ranges(
      workers, count,
      [](void* context, uint32_t begin, uint32_t end) {
        Job& j = *static_cast<Job*>(context);
        const uint32_t part = (*j.body)(begin, end);
        std::atomic_ref<uint32_t>(j.total).fetch_add(part, std::memory_order_relaxed);
      },
      &job);
  return job.total;
}

// body(begin, end) handles [begin, end) and returns its largest value;
// returns the largest over [0, count) (0 for none).
template <class Body>
uint32_t run_ranges_max(const Workers* workers, uint32_t count, const Body& body) {
  struct Job {
    const Body* body;
    uint32_t largest;
  } job{&body, 0};
  run_ranges(
      workers, count,
      [](void* context, uint32_t begin, uint32_t end) {
        Job& j = *static_cast<Job*>(context);
        const uint32_t part = (*j.body)(begin, end);
        std::atomic_ref<uint32_t> total(j.largest);
        uint32_t seen = total.load(std::memory_order_relaxed);
        while (part > seen && !total.compare_exchange_weak(seen, part, std::memory_order_relaxed)) {
        }
      },
      &job);
  return job.largest;
}

}  // namespace sinew::layer
