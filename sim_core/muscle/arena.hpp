// Bump carver over caller memory, used only while initialising layer state
// (the engine has the same pattern privately). Counting mode (null base)
// reports the bytes a layout needs.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>

namespace sinew::muscle {

class ArenaCarver {
 public:
  ArenaCarver(void* base, size_t size) : base_(static_cast<uint8_t*>(base)), size_(size) {}
  template <typename T>
  std::span<T> take(size_t count) {
    static_assert(alignof(T) <= 8, "every carve is 8-byte aligned");
    if (count == 0) return {};
    const size_t bytes = (count * sizeof(T) + 7u) & ~size_t{7};
    needed_ += bytes;
    if (base_ == nullptr || used_ + bytes > size_) {
      failed_ = true;
      return {};
    }
    T* p = static_cast<T*>(static_cast<void*>(base_ + used_));
    for (size_t i = 0; i < count; ++i) p[i] = T{};
    used_ += bytes;
    return {p, count};
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

}  // namespace sinew::muscle
