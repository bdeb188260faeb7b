// Biovision Hierarchy (BVH) motion files: the skeleton (HIERARCHY) and the
// per-frame channel values (MOTION), read into plain data.
//
//   HIERARCHY
//   ROOT Hips
//   {
//     OFFSET 0 0 0
//     CHANNELS 6 Xposition Yposition Zposition Zrotation Xrotation Yrotation
//     JOINT Chest { OFFSET 0 5 0  CHANNELS 3 Zrotation Xrotation Yrotation  End Site { OFFSET 0 4 0 } }
//   }
//   MOTION
//   Frames: 2
//   Frame Time: 0.0333333
//   <one row of values per frame, in CHANNELS declaration order>
//
// Each joint may declare 0 to 6 channels in any order; rotations are in
// degrees. Keywords are matched without regard to case.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace sinew::motion {

using Vec3 = std::array<double, 3>;

enum class BvhChannel : uint8_t { kXposition, kYposition, kZposition, kXrotation, kYrotation, kZrotation };

std::string_view channel_name(BvhChannel channel);
bool is_rotation(BvhChannel channel);
int channel_axis(BvhChannel channel);  // 0 = X, 1 = Y, 2 = Z

struct BvhJoint {
  std::string name;
  int parent = -1;  // index into Bvh::joints; parents always precede their children
  Vec3 offset{0, 0, 0};
  std::vector<BvhChannel> channels;  // in the order the file lists them
  size_t first_value = 0;            // where this joint's values start within a frame row
};

// The tip of a chain: a fixed point with no channels, kept for drawing bones
// and for tests of the rest pose.
struct BvhEndSite {
  int parent = -1;
  Vec3 offset{0, 0, 0};
};

struct Bvh {
  std::vector<BvhJoint> joints;  // ROOT and JOINT entries in file order (End Sites are not joints)
  std::vector<BvhEndSite> end_sites;
  double frame_time = 0;  // seconds per frame
  size_t frame_count = 0;
  size_t channel_count = 0;    // values per frame row
  std::vector<double> values;  // frame_count rows of channel_count values, frame-major

  std::span<const double> frame(size_t index) const;  // throws std::out_of_range
  int find_joint(std::string_view name) const;        // first joint of that name, or -1
};

// Parses BVH text. On failure returns false and sets `error` to
// "line <n>: <problem>"; never crashes on malformed input.
bool parse_bvh(std::string_view text, Bvh* out, std::string* error);

// Reads and parses a file; errors are prefixed with the path ("<path>: line <n>: ...").
bool load_bvh(const std::string& path, Bvh* out, std::string* error);

}  // namespace sinew::motion
