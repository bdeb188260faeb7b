#include "dds_entity.hpp"

#include <dds/dds.h>

namespace sinew::hal::dds {

DdsEntity& DdsEntity::operator=(DdsEntity&& o) noexcept {
  if (this != &o) {
    reset();
    handle_ = o.handle_;
    o.handle_ = 0;
  }
  return *this;
}

void DdsEntity::reset() {
  if (handle_ > 0) dds_delete(handle_);
  handle_ = 0;
}

std::string dds_error_text(int32_t code) { return dds_strretcode(code); }

}  // namespace sinew::hal::dds
