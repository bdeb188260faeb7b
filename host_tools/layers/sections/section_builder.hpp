// One layer section's payload (sim_core/pipeline/layer_format.hpp) as the
// section's descriptor (sim_core/<layer>/<layer>_section.hpp) lists it; each
// layer's writer (host_tools/layers/<layer>/*_section_writer.cpp) uses it.
#pragma once

#include <cstdint>
#include <cstring>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "host_tools/layers/sections/layer_section.hpp"
#include "sim_core/layer/section_format.hpp"
#include "sim_core/pipeline/layer_format.hpp"

namespace sinew::layers {

// Header, params, array table, then each array at a multiple of 8, as the
// section's descriptor (sim_core/<layer>/<layer>_section.hpp) lists them for
// that version: the params size, the number of arrays and each array's
// element size come from the descriptor the runtime loader also reads, and
// a writer whose record or arrays differ from it is refused, named.
class SectionBuilder {
 public:
  SectionBuilder(const layer::SectionDescriptor& section, uint32_t version, uint32_t rate_hz, const void* params,
                 uint32_t params_size)
      : section_(section), version_(section.find(version)) {
    if (version_ == nullptr) {
      fault("version " + std::to_string(version) + " is not in the descriptor");
    } else if (params_size != version_->params_size) {
      fault("version " + std::to_string(version) + " params record is " + std::to_string(params_size) +
            " bytes, the descriptor's " + std::to_string(version_->params_size));
    }
    const uint32_t arrays = version_ != nullptr ? version_->array_count : 0;
    pipeline::LayerSectionHeader h{};
    h.layer_version = version;
    h.params_size = params_size;
    h.array_count = arrays;
    h.rate_hz = rate_hz;
    put(&h, sizeof(h));
    put(params, params_size);
    table_ = bytes_.size();
    bytes_.resize(table_ + size_t{arrays} * sizeof(pipeline::LayerArrayEntry), 0);
  }
  // The next array, which must be the descriptor's next by name and
  // element size: a writer listing two arrays of one type in another order
  // than the loader reads them is refused too.
  template <typename T>
  SectionBuilder& array(std::string_view name, std::span<const T> values) {
    if (version_ == nullptr) return *this;
    if (next_ >= version_->array_count) {
      fault("more arrays than the descriptor's " + std::to_string(version_->array_count));
      return *this;
    }
    const layer::SectionArray& spec = section_.arrays[next_];
    if (name != spec.name)
      fault("array " + std::to_string(next_) + " is " + spec.name + " in the descriptor, not " + std::string(name));
    if (sizeof(T) != spec.element_size)
      fault(std::string(spec.name) + " elements are " + std::to_string(sizeof(T)) + " bytes, the descriptor's " +
            std::to_string(spec.element_size));
    bytes_.resize(align8(bytes_.size()), 0);
    pipeline::LayerArrayEntry e{static_cast<uint32_t>(bytes_.size()), static_cast<uint32_t>(values.size()),
                                static_cast<uint32_t>(sizeof(T)), 0};
    std::memcpy(bytes_.data() + table_ + next_++ * sizeof(e), &e, sizeof(e));
    put(values.data(), values.size_bytes());
    return *this;
  }
  LayerSection finish() {
    if (version_ != nullptr && next_ != version_->array_count)
      fault(std::to_string(next_) + " arrays written, the descriptor's " + std::to_string(version_->array_count));
    bytes_.resize(align8(bytes_.size()), 0);
    if (!problem_.empty()) bytes_.clear();
    return {section_.id, std::move(bytes_), problem_};
  }

 private:
  void fault(const std::string& what) {
    if (problem_.empty()) problem_ = std::string("internal: the ") + section_.name + " writer: " + what;
  }
  void put(const void* data, size_t size) {
    const size_t at = align8(bytes_.size());
    bytes_.resize(at + align8(size), 0);
    if (size > 0) std::memcpy(bytes_.data() + at, data, size);
  }
  static constexpr size_t align8(size_t v) { return (v + 7u) & ~size_t{7}; }
  const layer::SectionDescriptor& section_;
  const layer::SectionVersion* version_;
  std::vector<uint8_t> bytes_;
  std::string problem_;
  size_t table_ = 0;
  size_t next_ = 0;
};

template <typename P>
SectionBuilder builder(const layer::SectionDescriptor& section, uint32_t version, uint32_t rate_hz, const P& params) {
  return SectionBuilder(section, version, rate_hz, &params, sizeof(P));
}

// A builder whose params record is `params`.
template <typename P>
inline SectionBuilder section_builder(const layer::SectionDescriptor& section, uint32_t version, uint32_t rate_hz,
                                      const P& params) {
  return SectionBuilder(section, version, rate_hz, &params, sizeof(P));
}

}  // namespace sinew::layers
