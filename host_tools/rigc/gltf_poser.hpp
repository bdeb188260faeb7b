// Poses a glTF skin through sinew's fixed-point pipeline: the animation is
// sampled on the host (double), converted to fixed-point local transforms,
// and everything after that - model transforms, skinning matrices, LBS - runs
// in sim_core exactly as on the board.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "gltf_import.hpp"
#include "host_tools/motion/bvh_drive.hpp"
#include "sim_core/engine/engine.hpp"
#include "sim_core/pipeline/pipeline.hpp"

namespace sinew::rigc {

class GltfPoser {
 public:
  bool open(const std::string& path, std::string* error);
  // A rig spec whose [rig] source is a glTF model: the spec's joints, DOFs
  // and layer tables are compiled (as rigc does), and every pose then runs
  // through the whole pipeline with every layer the spec asks for.
  // The animation is then simulated tick by tick at tick_hz from its start
  // to each requested time (the layers are dynamic: a lone sample would be
  // one huge step); a time earlier than the last restarts from the start.
  // need_animations false (to play a motion file): [rig] source may also be
  // a built-in rig.
  bool open_spec(const std::string& spec_path, uint32_t tick_hz, std::string* error, bool need_animations = true);
  // After open_spec: a motion file (BVH through the spec's
  // [motion.bvh_joints], or CSV joint tracks; motion_tracks.hpp) to play
  // instead of an animation. Its values become the rig's commanded inputs.
  bool set_motion(const std::string& path, std::string* error);
  const motion::JointTracks& motion_tracks() const { return tracks_; }
  // Skinned positions at `time` seconds of the motion (clamped to its
  // range), simulated tick by tick at tick_hz from its first sample, as pose().
  bool pose_motion(double time, std::vector<std::array<double, 3>>* positions, std::string* error);
  // The rig inputs of the last motion tick (binary angles or Q12.20 rig units).
  const std::vector<int32_t>& motion_inputs() const { return inputs_; }
  // One line per compiled layer (empty without --spec).
  const std::vector<std::string>& layer_report() const { return layer_report_; }
  const pipeline::LayerSet& layers() const { return layers_; }
  // Skinned world-space positions of every skinned primitive (document
  // order), in glTF units.
  bool pose(int animation, double time, std::vector<std::array<double, 3>>* positions, std::string* error);
  const CompileReport& report() const { return report_; }
  const rig::Rig& rig() const { return rig_; }
  // The engine holding the last pose: its joint locals and skinned vertices
  // (the pipeline's with a spec). For exports.
  const engine::Engine& posed_engine() const { return with_layers_ ? pipeline_.engine : engine_; }
  const tinygltf::Model& model() const { return gltf_.model; }

 private:
  GltfRig gltf_;
  CompileReport report_;
  std::vector<uint64_t> blob_;  // 8-byte aligned storage
  std::vector<uint64_t> rig_arena_, engine_arena_;
  rig::Rig rig_;
  engine::Engine engine_;
  std::vector<skeleton::LocalPose> locals_;
  // With a spec: the layers and the pipeline that runs them.
  bool with_layers_ = false;
  uint32_t tick_hz_ = 100;
  int sim_animation_ = -2;  // the animation simulated so far (-2: none)
  double sim_time_ = 0;     // its time at the last tick
  bool set_locals(int animation, double time, std::string* error);
  void set_motion_inputs(double time);
  RigSpec spec_;  // with the layers' DOFs: input order
  std::vector<motion::BvhJointName> bvh_joints_;
  motion::JointTracks tracks_;
  std::vector<int> track_of_input_;  // -1: no track, the DOF stays at rest
  std::vector<int32_t> inputs_;
  bool restart_pipeline(std::string* error);
  std::vector<std::string> layer_report_;
  std::vector<uint64_t> layer_arena_, pipeline_arena_;
  pipeline::LayerSet layers_;
  pipeline::Pipeline pipeline_;
};

}  // namespace sinew::rigc
