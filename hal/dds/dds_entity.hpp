// An owned Cyclone DDS entity (participant, topic, reader, writer, waitset,
// condition): dds_delete'd, with its children, when its owner goes. The
// handle is Cyclone's dds_entity_t (an int32_t; negative values are error
// codes), kept as a plain integer so this header needs no DDS header.
#pragma once

#include <cstdint>
#include <string>

namespace sinew::hal::dds {

class DdsEntity {
 public:
  DdsEntity() = default;
  explicit DdsEntity(int32_t handle) : handle_(handle) {}
  DdsEntity(const DdsEntity&) = delete;
  DdsEntity& operator=(const DdsEntity&) = delete;
  DdsEntity(DdsEntity&& o) noexcept : handle_(o.handle_) { o.handle_ = 0; }
  DdsEntity& operator=(DdsEntity&& o) noexcept;
  ~DdsEntity() { reset(); }

  int32_t get() const { return handle_; }
  bool valid() const { return handle_ > 0; }
  void reset();

 private:
  int32_t handle_ = 0;
};

// Cyclone's text for a return code (dds_strretcode), e.g. "Precondition Not Met".
std::string dds_error_text(int32_t code);

}  // namespace sinew::hal::dds
