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

namespace detail {

// Runs body over the ranges and joins each range's value into one total
// with Join{}(std::atomic_ref<uint32_t>, value).
template <class Join, class Body>
uint32_t run_ranges_joined(const Workers* workers, uint32_t count, const Body& body) {
  struct Job {
    const Body* body;
    uint32_t total;
  } job{&body, 0};
  run_ranges(
      workers, count,
      [](void* context, uint32_t begin, uint32_t end) {
        Job& j = *static_cast<Job*>(context);
        Join{}(std::atomic_ref<uint32_t>(j.total), (*j.body)(begin, end));
      },
      &job);
  return job.total;
}

struct AddInto {
  void operator()(std::atomic_ref<uint32_t> total, uint32_t part) const {
    total.fetch_add(part, std::memory_order_relaxed);
  }
};

struct RaiseTo {
  void operator()(std::atomic_ref<uint32_t> total, uint32_t part) const {
    uint32_t seen = total.load(std::memory_order_relaxed);
    while (part > seen && !total.compare_exchange_weak(seen, part, std::memory_order_relaxed)) {
    }
  }
};

}  // namespace detail

// body(begin, end) handles [begin, end) and returns its count; returns the
// sum over [0, count). Must not allocate (nor may body).
template <class Body>
uint32_t run_ranges_summed(const Workers* workers, uint32_t count, const Body& body) {
  return detail::run_ranges_joined<detail::AddInto>(workers, count, body);
}

// body(begin, end) handles [begin, end) and returns its largest value;
// returns the largest over [0, count) (0 for none).
template <class Body>
uint32_t run_ranges_max(const Workers* workers, uint32_t count, const Body& body) {
  return detail::run_ranges_joined<detail::RaiseTo>(workers, count, body);
}

}  // namespace sinew::layer
