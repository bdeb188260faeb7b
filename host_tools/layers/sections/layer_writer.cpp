#include "layer_writer.hpp"

#include <cstring>
#include <string>
#include <string_view>

#include "sim_core/muscle/muscle_shape.hpp"
#include "sim_core/muscle/primitive_deform.hpp"
#include "sim_core/pipeline/layer_set.hpp"
#include "sim_core/rig/crc32c.hpp"
#include "sim_core/rig/rig.hpp"

namespace sinew::layers {
namespace {

constexpr size_t align8(size_t v) { return (v + 7u) & ~size_t{7}; }

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

}  // namespace

LayerSection sph_section(const sph::SphModel& m, uint32_t rate_hz, uint32_t force_input) {
  // Version 1 without surface tension (the bytes of rigs without it do not
  // change); version 2 stores the whole SphParams.
  ::sinew::sph::SphSectionParams p2{};
  ::sinew::sph::SphSectionParamsV1 p1{};
  const bool v2 = m.params.tension_gain != 0;
  p2.params = m.params;
  p2.joint = p1.joint = m.joint;
  p2.force_input = p1.force_input = force_input;
  std::memcpy(p1.params, &m.params, sizeof p1.params);
  SectionBuilder b = v2 ? builder(sph::kSphSection, ::sinew::sph::kSphSectionVersion2, rate_hz, p2)
                        : builder(sph::kSphSection, pipeline::kLayerSectionVersion, rate_hz, p1);
  b.array("rest_local_x", m.rest_local[0])
      .array("rest_local_y", m.rest_local[1])
      .array("rest_local_z", m.rest_local[2]);
  b.array("rest_model_x", m.rest_model[0])
      .array("rest_model_y", m.rest_model[1])
      .array("rest_model_z", m.rest_model[2]);
  b.array("bone", m.bone).array("skin_vertex", m.skin_vertex);
  b.array("skin_rest_x", m.skin_rest[0]).array("skin_rest_y", m.skin_rest[1]).array("skin_rest_z", m.skin_rest[2]);
  return b.finish();
}

LayerSection metaballs_section(const ::sinew::metaballs::MetaballModel& m) {
  const ::sinew::metaballs::MetaballsSectionParams p{m.joint_count,    m.vertex_count,     m.pbd_iterations,
                                                     m.jiggle_damping, m.smoothing_passes, m.smoothing_rate};
  // Version 1 without action lines (the bytes of rigs without them do not
  // change); version 2 appends them.
  const bool v2 = !m.action_lines.empty();
  SectionBuilder b =
      builder(metaballs::kMetaballsSection,
              v2 ? ::sinew::metaballs::kMetaballsSectionVersion2 : pipeline::kLayerSectionVersion, m.jiggle_rate_hz, p);
  b.array("inverse_bind", m.inverse_bind)
      .array("ball_rest", m.ball_rest)
      .array("ball_radius", m.ball_radius)
      .array("ball_bone", m.ball_bone)
      .array("ball_joint", m.ball_joint);
  b.array("ball_weight", m.ball_weight)
      .array("ball_jiggle", m.ball_jiggle)
      .array("pairs", m.pairs)
      .array("bulges", m.bulges);
  b.array("vertex_ball", m.vertex_ball).array("vertex_weight", m.vertex_weight).array("vertex_disp", m.vertex_disp);
  b.array("joint_balls", m.joint_balls)
      .array("jv_vertex", m.jv_vertex)
      .array("jv_ball", m.jv_ball)
      .array("jv_alpha", m.jv_alpha)
      .array("jv_blend", m.jv_blend);
  b.array("jv_disp", m.jv_disp)
      .array("jv_laplacian", m.jv_laplacian)
      .array("jv_neighbour_begin", m.jv_neighbour_begin)
      .array("jv_neighbours", m.jv_neighbours)
      .array("jv_inv_count", m.jv_inv_count);
  b.array("overlaps", m.overlaps).array("overlap_vertices", m.overlap_vertices).array("overlap_balls", m.overlap_balls);
  if (v2) b.array("action_lines", m.action_lines).array("action_balls", m.action_balls);
  return b.finish();
}

LayerSection muscles_section(const ::sinew::muscle::MuscleModel& m) {
  // Version 1 while no primitive is deformed (those rigs keep their bytes).
  bool deformed = false;
  for (const auto& d : m.deformations) deformed = deformed || ::sinew::muscle::is_deformed(d);
  // Version 3 only while some muscle has a non-default shape.
  bool shaped = false;
  for (const auto& s : m.shapes) shaped = shaped || !::sinew::muscle::is_default_shape(s);
  // Version 4 only while some primitive is a general superquadric.
  bool general = false;
  for (const auto& r : m.primitives) general = general || (!m.exponents.empty() && r.exponent == 0);
  const ::sinew::muscle::MusclesSectionParams p{m.joint_count, m.ring_vertices};
  const uint32_t version = general    ? ::sinew::muscle::kMusclesSectionVersion4
                           : shaped   ? ::sinew::muscle::kMusclesSectionVersion3
                           : deformed ? ::sinew::muscle::kMusclesSectionVersion2
                                      : pipeline::kLayerSectionVersion;
  SectionBuilder b = builder(muscle::kMusclesSection, version, 0, p);
  b.array("muscles", m.muscles).array("primitives", m.primitives);
  if (general || shaped || deformed)
    b.array("deformations", deformed ? m.deformations : std::span<const ::sinew::muscle::PrimitiveDeformation>{});
  if (general || shaped) b.array("shapes", shaped ? m.shapes : std::span<const ::sinew::muscle::MuscleShape>{});
  if (general) b.array("exponents", m.exponents);
  return b.finish();
}

LayerSection skin_section(const ::sinew::elastic_skin::SkinModel& m, std::span<const uint32_t> region,
                          std::span<const fx::Unit> region_weight, const uint32_t (&base_acceleration)[3]) {
  // Version 1 while the solver record is the default (the bytes of rigs
  // without the new settings do not change); version 2 otherwise.
  // Version 3 only with edge dashpots (the record's last member), 4 with
  // the fat along the surface normal, 5 with base-acceleration inputs.
  const elastic_skin::SkinSolverParams defaults{};
  const bool v5 = base_acceleration[0] != pipeline::kNoExternalInput ||
                  base_acceleration[1] != pipeline::kNoExternalInput ||
                  base_acceleration[2] != pipeline::kNoExternalInput;
  if (v5) {
    ::sinew::elastic_skin::SkinSectionParamsV5 p5{};
    p5.v3 = {m.joint_count, m.vertex_count, m.params, m.solver};
    for (int c = 0; c < 3; ++c) p5.base_acceleration_input[c] = base_acceleration[c];
    SectionBuilder b = builder(elastic_skin::kSkinSection, ::sinew::elastic_skin::kSkinSectionVersion5, 0, p5);
    b.array("anchors", m.anchors)
        .array("anchor_stiffness", m.anchor_stiffness)
        .array("fat", m.fat)
        .array("edges", m.edges)
        .array("bands", m.bands);
    b.array("region_vertex", region).array("region_weight", region_weight);
    return b.finish();
  }
  const bool v4 = m.solver.fat_normal != 0;
  const bool v3 = !v4 && m.solver.edge_damping != 0;
  const bool v2 = !v4 && !v3 && std::memcmp(&m.solver, &defaults, ::sinew::elastic_skin::kSkinSolverBytesV2) != 0;
  ::sinew::elastic_skin::SkinSectionParamsV3 p{};
  p.joint_count = m.joint_count;
  p.vertex_count = m.vertex_count;
  p.params = m.params;
  p.solver = m.solver;
  // The version 1 and 2 records are prefixes of the version 3 one.
  const uint32_t size = v4 || v3 ? uint32_t{sizeof(::sinew::elastic_skin::SkinSectionParamsV3)}
                        : v2     ? uint32_t{sizeof(::sinew::elastic_skin::SkinSectionParamsV2)}
                                 : uint32_t{sizeof(::sinew::elastic_skin::SkinSectionParams)};
  const uint32_t version = v4   ? ::sinew::elastic_skin::kSkinSectionVersion4
                           : v3 ? ::sinew::elastic_skin::kSkinSectionVersion3
                           : v2 ? ::sinew::elastic_skin::kSkinSectionVersion2
                                : pipeline::kLayerSectionVersion;
  SectionBuilder b(elastic_skin::kSkinSection, version, 0, &p, size);
  b.array("anchors", m.anchors)
      .array("anchor_stiffness", m.anchor_stiffness)
      .array("fat", m.fat)
      .array("edges", m.edges)
      .array("bands", m.bands);
  b.array("region_vertex", region).array("region_weight", region_weight);
  return b.finish();
}

LayerSection barnet_section(const ::sinew::barnet::BarnetModel& m) {
  // Version 1 while no load reads an external input and no q follows one
  // (the bytes of rigs without them do not change); version 2 otherwise.
  bool v2 = !m.q_inputs.empty();
  for (const ::sinew::barnet::LoadRecord& l : m.loads) v2 = v2 || l.input >= m.input_count;
  const ::sinew::barnet::BarnetSectionParams p{m.joint_count, m.input_count, m.vertex_count, v2 ? m.external_count : 0};
  SectionBuilder b = builder(barnet::kBarnetSection,
                             v2 ? ::sinew::barnet::kBarnetSectionVersion2 : pipeline::kLayerSectionVersion, 0, p);
  b.array("inverse_bind", m.inverse_bind)
      .array("nodes", m.nodes)
      .array("bars", m.bars)
      .array("loads", m.loads)
      .array("triangles", m.triangles)
      .array("wrap", m.wrap);
  if (v2) b.array("q_inputs", m.q_inputs);
  return b.finish();
}

LayerSection external_inputs_section(std::span<const pipeline::ExternalInputRecord> inputs) {
  SectionBuilder b(pipeline::kExternalInputSection, pipeline::kLayerSectionVersion, 0, nullptr, 0);
  b.array("inputs", inputs);
  return b.finish();
}

bool append_layer_sections(std::vector<uint8_t>* blob, const std::vector<LayerSection>& sections, std::string* error) {
  namespace fmt = sinew::rig;
  if (sections.empty()) return true;
  for (const LayerSection& s : sections)
    if (!s.problem.empty()) return *error = s.problem, false;
  fmt::FileHeader h;
  if (blob->size() < sizeof(h)) return *error = "internal: core blob too short", false;
  std::memcpy(&h, blob->data(), sizeof(h));
  std::vector<fmt::SectionEntry> table(h.section_count);
  std::memcpy(table.data(), blob->data() + h.section_table_offset, table.size() * sizeof(fmt::SectionEntry));
  const size_t count = table.size() + sections.size();
  if (count > fmt::kMaxSections)
    return *error = "rig has " + std::to_string(count) + " sections, more than the format's " +
                    std::to_string(fmt::kMaxSections),
           false;
  // New layout: header, the longer table, the core payloads, the layer payloads.
  std::vector<uint8_t> out(sizeof(fmt::FileHeader) + count * sizeof(fmt::SectionEntry), 0);
  std::vector<fmt::SectionEntry> new_table;
  for (const fmt::SectionEntry& e : table) {
    const size_t at = align8(out.size());
    out.resize(at + e.size, 0);
    std::memcpy(out.data() + at, blob->data() + e.offset, e.size);
    new_table.push_back({e.id, static_cast<uint32_t>(at), e.size, 0});
  }
  for (const LayerSection& s : sections) {
    const size_t at = align8(out.size());
    out.resize(at + s.payload.size(), 0);
    std::memcpy(out.data() + at, s.payload.data(), s.payload.size());
    new_table.push_back({s.id, static_cast<uint32_t>(at), static_cast<uint32_t>(s.payload.size()), 0});
  }
  out.resize(align8(out.size()), 0);
  if (out.size() > UINT32_MAX) return *error = "rig blob larger than 4 GiB", false;
  h.version_minor = 1;  // layer sections: format 1.1
  h.total_size = static_cast<uint32_t>(out.size());
  h.section_count = static_cast<uint32_t>(count);
  h.section_table_offset = sizeof(fmt::FileHeader);
  h.crc32c = 0;
  std::memcpy(out.data(), &h, sizeof(h));
  std::memcpy(out.data() + sizeof(h), new_table.data(), count * sizeof(fmt::SectionEntry));
  const uint32_t crc = fmt::crc32c(0, out.data(), out.size());
  std::memcpy(out.data() + offsetof(fmt::FileHeader, crc32c), &crc, 4);

  // Round trip through the runtime loaders: the compiler never emits a blob
  // the board would reject.
  std::vector<uint64_t> aligned(out.size() / 8 + 1);
  std::memcpy(aligned.data(), out.data(), out.size());
  const auto* data = reinterpret_cast<const uint8_t*>(aligned.data());
  size_t rig_bytes = 0, layer_bytes = 0;
  fmt::LoadStatus st = fmt::rig_validate(data, out.size(), &rig_bytes);
  std::vector<uint64_t> rig_arena(rig_bytes / 8 + 1);
  fmt::Rig rig;
  if (st.ok()) st = fmt::rig_init(data, out.size(), rig_arena.data(), rig_arena.size() * 8, &rig);
  if (st.ok()) st = pipeline::layers_validate(rig, data, out.size(), &layer_bytes);
  std::vector<uint64_t> layer_arena(layer_bytes / 8 + 1);
  pipeline::LayerSet set;
  if (st.ok()) st = pipeline::layers_init(rig, data, out.size(), layer_arena.data(), layer_arena.size() * 8, &set);
  if (!st.ok()) return *error = std::string("compiled layers rejected by the runtime loader: ") + st.message, false;
  *blob = std::move(out);
  return true;
}

}  // namespace sinew::layers
