#include "frame_shape.hpp"

namespace sinew::hal::output {

FrameShape shape_of(const PoseFrame& frame) {
  FrameShape s;
  s.vertex_count = frame.vertex_count;
  s.input_count = frame.input_count;
  s.length_exponent = frame.length_exponent;
  s.normals = frame.normal[0] != nullptr && frame.normal[1] != nullptr && frame.normal[2] != nullptr;
  return s;
}

}  // namespace sinew::hal::output
