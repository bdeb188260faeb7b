// Offline candidates for surface overlapping between two bones that share no
// joint (metaballs-pbd-skinning, "Surface overlapping": the ball sets of two
// bones detect their collision; fingers side by side, a fingertip and the
// palm). For every pair of bones that are not parent and child, the pairs of
// balls that can collide somewhere in the joints' ranges (and do not at
// rest, where they are one tissue) become an OverlapRecord with joint ==
// kNoJoint, together with each bone's vertices that can lie in the other
// bone's colliding balls. docs/metaballs.md, "Overlap between any two
// bones", derives why the lists are complete.
#pragma once

#include <string>
#include <vector>

#include "builder.hpp"

namespace sinew::metaballs_build {

struct BonePairInput {
  const rigc::RigSpec* spec = nullptr;
  std::vector<int> anatomical_parent;  // per joint (layers::anatomical_parent), -1 for none
  std::vector<int> dominant;           // per vertex: its bone
  std::vector<fx::Vec3> vertex_len;    // per vertex, rest (bind) position, Len
  std::vector<double> largest_radius;  // per ball, bulged at most, model units scaled by 2^-e (Len / 2^20)
};

// Appends the records (after the joints' own) to b->overlaps and their lists
// to b->overlap_vertices / b->overlap_balls. False with a message when the
// lists pass the format's maxima.
bool add_bone_pair_overlaps(const BonePairInput& in, Build* b, std::string* error);

}  // namespace sinew::metaballs_build
