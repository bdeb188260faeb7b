// The one bump carver of sim_core: every layer carves its state out of the
// caller's memory with it, only while initialising. Counting mode (a null
// base) reports the bytes a layout needs, so state_bytes() and init() share
// one layout function and cannot disagree.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>

namespace sinew::fx {

class ArenaCarver {
 public:
  ArenaCarver(void* base, size_t size) : base_(static_cast<uint8_t*>(base)), size_(size) {}

  // `count` value-initialised elements, 8-byte aligned; empty for count 0 or
  // when the memory is exhausted (then failed() is set).
  template <typename T>
  std::span<T> take(size_t count) {
    static_assert(alignof(T) <= 8, "every carve is 8-byte aligned");
    uint8_t* p = raw(count * sizeof(T));
    if (p == nullptr) return {};
    T* t = static_cast<T*>(static_cast<void*>(p));
    for (size_t i = 0; i < count; ++i) t[i] = T{};
    return {t, count};
  }

  // `bytes` uninitialised bytes, 8-byte aligned (a sub-arena for a layer).
  uint8_t* raw(size_t bytes) {
    if (bytes == 0) return nullptr;
    const size_t padded = (bytes + 7u) & ~size_t{7};
    needed_ += padded;
    if (base_ == nullptr || used_ + padded > size_) {
      failed_ = true;
      return nullptr;
    }
    uint8_t* p = base_ + used_;
    used_ += padded;
    return p;
  }

  size_t needed() const { return needed_; }
  bool failed() const { return failed_; }

 private:
  uint8_t* base_;
  size_t size_;
  size_t used_ = 0;
  size_t needed_ = 0;
  bool failed_ = false;
};

inline bool aligned8(const void* p) { return p != nullptr && (reinterpret_cast<uintptr_t>(p) & 7u) == 0; }

}  // namespace sinew::fx
