// What the layer builders derive their defaults from, for any skeleton: the
// rest transforms (rest rotations and scales included), each joint's bone
// (towards its first child, else onward from its parent, else towards its
// vertices), the bone's length and the skin radius around it. Model units.
// Double precision with + - * / and sqrt only (compiled with
// -ffp-contract=off): the same numbers on every platform.
#pragma once

#include <array>
#include <string>
#include <vector>

#include "host_tools/rigc/rig_spec.hpp"

namespace sinew::layers {

using rigc::Vec3d;

struct RestFrame {
  double m[3][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};  // linear part, model from joint
  double inv[3][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  Vec3d t{0, 0, 0};
};

struct RigGeometry {
  std::vector<RestFrame> frame;  // per joint, rest pose, model space
  std::vector<int> first_child;  // -1 for a leaf
  std::vector<Vec3d> bone_dir;   // unit, model space
  std::vector<double> bone_length;
  std::vector<double> skin_radius;                 // median distance of the joint's vertices from its bone; 0 if none
  std::vector<int> dominant;                       // per vertex: the joint of its largest influence
  std::vector<std::vector<uint32_t>> vertices_of;  // per joint: vertices it dominates
};

// Fails (naming the joint) on a degenerate rest transform.
bool rig_geometry(const rigc::RigSpec& spec, RigGeometry* out, std::string* error);

Vec3d to_local(const RestFrame& f, const Vec3d& model_point);
Vec3d dir_to_local(const RestFrame& f, const Vec3d& model_dir);  // normalised
Vec3d dir_to_model(const RestFrame& f, const Vec3d& local_dir);  // normalised

double dot(const Vec3d& a, const Vec3d& b);
Vec3d cross(const Vec3d& a, const Vec3d& b);
Vec3d sub(const Vec3d& a, const Vec3d& b);
Vec3d add(const Vec3d& a, const Vec3d& b);
Vec3d scaled(const Vec3d& a, double s);
double norm(const Vec3d& a);
Vec3d normalized(const Vec3d& a);  // zero for a zero vector
// A unit vector perpendicular to unit u (deterministic choice).
Vec3d perpendicular(const Vec3d& u);

// The joint whose bone meets `joint` at its rest position: its parent when
// the parent carries skin; in a flat skeleton (every joint a child of one
// unskinned root, as WebXR hands) the skinned joint whose bone ends nearest
// it. -1 for a root with no such joint.
int anatomical_parent(const rigc::RigSpec& spec, const RigGeometry& geometry, int joint);

// Whether joint a is joint b or one of its ancestors.
bool is_ancestor_or_self(const rigc::RigSpec& spec, int a, int b);

}  // namespace sinew::layers
