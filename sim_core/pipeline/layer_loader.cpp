// Loading of the layer sections (layer_format.hpp). Two passes, as the core
// loader: the structure of every section is checked against the blob before
// anything is read through a span (header, params size, array table, each
// array's alignment, element size, count and bounds); then each section is
// copied into the arena and its model handed to the layer's own validator,
// which checks every index and parameter against the rig.
#include <cstring>
#include <string_view>

#include "layer_set.hpp"
#include "sim_core/barnet/barnet_validate.hpp"
#include "sim_core/elastic_skin/skin_validate.hpp"
#include "sim_core/metaballs/validate.hpp"
#include "sim_core/muscle/muscle_validate.hpp"
#include "sim_core/rig/message.hpp"

namespace sinew::pipeline {
namespace {

using rig::LoadError;
using rig::LoadStatus;

constexpr uint64_t align8(uint64_t v) { return (v + 7u) & ~uint64_t{7}; }

const char* section_name(uint32_t id) {
  const layer::SectionDescriptor* d = find_layer_section(id);
  return d != nullptr ? d->name : nullptr;
}

// "rig blob: <SECT>#<instance>.<field>[<index>]: <problem> (<value>)"
LoadStatus fail(LoadError e, uint32_t id, uint32_t instance, const char* field, int64_t index, const char* what,
                int64_t value = 0, bool show_value = false) {
  LoadStatus s;
  s.error = e;
  rig::MessageBuilder m(s.message, sizeof(s.message));
  m.text("rig blob: ").text(section_name(id)).text("#").number(instance);
  if (field != nullptr && *field != '\0') m.text(".").text(field);
  if (index >= 0) m.text("[").number(index).text("]");
  m.text(": ").text(what);
  if (show_value) m.text(" (").number(value).text(")");
  return s;
}

LoadStatus from_layer(LoadError e, uint32_t id, uint32_t instance, const char* message) {
  LoadStatus s;
  s.error = e;
  rig::MessageBuilder m(s.message, sizeof(s.message));
  m.text("rig blob: ").text(section_name(id)).text("#").number(instance).text(": ").text(message);
  return s;
}

// Every descriptor fits the loader's array table, and every version's arrays
// are a prefix of its section's list.
static_assert([] {
  for (const layer::SectionDescriptor* d : kLayerSections) {
    if (d->arrays.size() > kMaxLayerArrays) return false;
    for (const layer::SectionVersion& v : d->versions)
      if (v.array_count > d->arrays.size()) return false;
  }
  return true;
}());

// A structurally checked layer section: where its params and arrays are.
struct SectionView {
  uint32_t id = 0, instance = 0;
  const uint8_t* base = nullptr;  // section start (in the blob, then in the arena)
  uint32_t size = 0;
  LayerSectionHeader header{};
  LayerArrayEntry arrays[kMaxLayerArrays] = {};
};

// The section's header, array table and array bounds against its descriptor
// (sim_core/<layer>/<layer>_section.hpp): a version the descriptor lists,
// its params size and array count, each array's element size and maximum.
LoadStatus check_section(uint32_t id, uint32_t instance, const uint8_t* base, uint32_t size, SectionView* out) {
  out->id = id;
  out->instance = instance;
  out->base = base;
  out->size = size;
  if (size < sizeof(LayerSectionHeader))
    return fail(LoadError::kSectionSize, id, instance, "size", -1, "shorter than the 32-byte layer header", size, true);
  std::memcpy(&out->header, base, sizeof(LayerSectionHeader));
  const LayerSectionHeader& h = out->header;
  const layer::SectionDescriptor* descriptor = find_layer_section(id);
  const layer::SectionVersion* version = descriptor != nullptr ? descriptor->find(h.layer_version) : nullptr;
  if (version == nullptr)
    return fail(LoadError::kBadVersion, id, instance, "layer_version", -1, "unsupported layer section version",
                h.layer_version, true);
  if (h.params_size != version->params_size)
    return fail(LoadError::kSectionSize, id, instance, "params_size", -1, "does not match this layer's record",
                h.params_size, true);
  if (h.array_count != version->array_count)
    return fail(LoadError::kSectionSize, id, instance, "array_count", -1, "does not match this layer's arrays",
                h.array_count, true);
  const uint64_t table = sizeof(LayerSectionHeader) + align8(h.params_size);
  const uint64_t data = table + uint64_t{h.array_count} * sizeof(LayerArrayEntry);
  if (data > size)
    return fail(LoadError::kSectionSize, id, instance, "array_count", -1, "array table runs past the section",
                h.array_count, true);
  for (uint32_t i = 0; i < h.array_count; ++i) {
    LayerArrayEntry e;
    std::memcpy(&e, base + table + uint64_t{i} * sizeof(LayerArrayEntry), sizeof(e));
    const layer::SectionArray& spec = descriptor->arrays[i];
    if (e.element_size != spec.element_size)
      return fail(LoadError::kSectionSize, id, instance, spec.name, -1, "element size differs from this loader's",
                  e.element_size, true);
    if (e.count > spec.max_count)
      return fail(LoadError::kLimit, id, instance, spec.name, -1, "count exceeds the documented maximum", e.count,
                  true);
    const uint64_t end = uint64_t{e.offset} + uint64_t{e.count} * e.element_size;
    if (e.count > 0 && ((e.offset & 7u) != 0 || e.offset < data || end > size))
      return fail(LoadError::kSectionSize, id, instance, spec.name, -1, "outside the section or misaligned", e.offset,
                  true);
    out->arrays[i] = e;
  }
  return {};
}

template <typename T>
std::span<const T> array_of(const SectionView& v, uint32_t i) {
  static_assert(alignof(T) <= 8, "arrays are 8-byte aligned");
  const LayerArrayEntry& e = v.arrays[i];
  if (e.count == 0) return {};
  // The arena bytes were written by memcpy, which creates implicit objects.
  return {static_cast<const T*>(static_cast<const void*>(v.base + e.offset)), e.count};
}

// The array the section's descriptor names `R` (layer::array_ref), read as
// T: a name the descriptor lacks, or a T of another size than the
// descriptor's element, does not compile, so the loader cannot drift from
// the descriptor the writer also reads.
template <typename T, layer::ArrayRef R>
std::span<const T> named(const SectionView& v) {
  static_assert(R.index != layer::kNoArray, "the section's descriptor lists no array of that name");
  static_assert(R.element_size == sizeof(T), "the descriptor's element size differs from the type read");
  return array_of<T>(v, R.index);
}

constexpr auto sph_array = [](std::string_view n) { return layer::array_ref(sph::kSphSectionArrays, n); };
constexpr auto mb_array = [](std::string_view n) { return layer::array_ref(metaballs::kMetaballsSectionArrays, n); };
constexpr auto muscle_array = [](std::string_view n) { return layer::array_ref(muscle::kMusclesSectionArrays, n); };
constexpr auto skin_array = [](std::string_view n) { return layer::array_ref(elastic_skin::kSkinSectionArrays, n); };
constexpr auto barnet_array = [](std::string_view n) { return layer::array_ref(barnet::kBarnetSectionArrays, n); };

template <typename P>
P params_of(const SectionView& v) {
  P p{};
  std::memcpy(&p, v.base + sizeof(LayerSectionHeader), sizeof(P));
  return p;
}

// Walks the section table (already checked by rig_validate) and calls
// visit(id, instance, offset, size) for every layer section; enforces the
// instance limits.
template <typename Visit>
LoadStatus for_each_layer_section(const uint8_t* blob, Visit visit) {
  rig::FileHeader h;
  std::memcpy(&h, blob, sizeof(h));
  uint32_t seen[6] = {};
  const uint32_t ids[6] = {kSectionSphJoint,    kSectionMetaballs, kSectionMuscles,
                           kSectionElasticSkin, kSectionBarnet,    kSectionExternalInputs};
  const uint32_t limits[6] = {kMaxSphJoints, 1, 1, 1, kMaxBarnets, 1};
  for (uint32_t i = 0; i < h.section_count; ++i) {
    rig::SectionEntry e;
    std::memcpy(&e, blob + h.section_table_offset + size_t{i} * sizeof(e), sizeof(e));
    int kind = -1;
    for (int k = 0; k < 6; ++k)
      if (ids[k] == e.id) kind = k;
    if (kind < 0) continue;
    if (seen[kind] >= limits[kind])
      return fail(LoadError::kSectionTable, e.id, seen[kind], "", -1, "more instances than the format allows",
                  limits[kind], true);
    LoadStatus st = visit(e.id, seen[kind]++, e.offset, e.size);
    if (!st.ok()) return st;
  }
  return {};
}

LoadStatus check_external(const SectionView& v, std::span<const ExternalInputRecord> inputs, const rig::Rig& rig) {
  for (uint32_t i = 0; i < inputs.size(); ++i) {
    const ExternalInputRecord& r = inputs[i];
    if (std::memchr(r.name, 0, sizeof(r.name)) == nullptr || r.name[0] == '\0')
      return fail(LoadError::kBadValue, v.id, v.instance, "name", i, "empty or not NUL-terminated");
    if (std::memchr(r.unit, 0, sizeof(r.unit)) == nullptr)
      return fail(LoadError::kBadValue, v.id, v.instance, "unit", i, "not NUL-terminated");
    if (r.quantity > static_cast<uint32_t>(InputQuantity::kAcceleration))
      return fail(LoadError::kBadValue, v.id, v.instance, "quantity", i, "unknown quantity", r.quantity, true);
    if (r.min >= r.max) return fail(LoadError::kBadValue, v.id, v.instance, "min", i, "must be below max", r.min, true);
    for (uint32_t k = 0; k < i; ++k)
      if (std::strcmp(inputs[k].name, r.name) == 0)
        return fail(LoadError::kBadValue, v.id, v.instance, "name", i, "duplicate external input name");
    for (const auto& joint : rig.names)
      if (std::strcmp(joint, r.name) == 0)
        return fail(LoadError::kBadValue, v.id, v.instance, "name", i, "clashes with a joint name");
  }
  return {};
}

LoadStatus load_sph(const SectionView& v, const rig::Rig& rig, uint32_t external_count, SphJointLayer* out) {
  // Version 1 has no surface tension: its record stops before tension_gain.
  SphSectionParams p{};
  if (v.header.layer_version == kSphSectionVersion2) {
    p = params_of<SphSectionParams>(v);
  } else {
    const SphSectionParamsV1 p1 = params_of<SphSectionParamsV1>(v);
    std::memcpy(static_cast<void*>(&p.params), p1.params, sizeof p1.params);
    p.params.tension_gain = 0;
    p.joint = p1.joint;
    p.force_input = p1.force_input;
  }
  sph::SphModel& m = out->model;
  m.params = p.params;
  m.joint = p.joint;
  m.rest_local[0] = named<fx::Len, sph_array("rest_local_x")>(v);
  m.rest_local[1] = named<fx::Len, sph_array("rest_local_y")>(v);
  m.rest_local[2] = named<fx::Len, sph_array("rest_local_z")>(v);
  m.rest_model[0] = named<fx::Len, sph_array("rest_model_x")>(v);
  m.rest_model[1] = named<fx::Len, sph_array("rest_model_y")>(v);
  m.rest_model[2] = named<fx::Len, sph_array("rest_model_z")>(v);
  m.skin_rest[0] = named<fx::Len, sph_array("skin_rest_x")>(v);
  m.skin_rest[1] = named<fx::Len, sph_array("skin_rest_y")>(v);
  m.skin_rest[2] = named<fx::Len, sph_array("skin_rest_z")>(v);
  m.bone = named<uint8_t, sph_array("bone")>(v);
  m.skin_vertex = named<uint32_t, sph_array("skin_vertex")>(v);
  if (v.header.rate_hz == 0)
    return fail(LoadError::kBadValue, v.id, v.instance, "rate_hz", -1, "an SPH joint's gains need its tick rate");
  const sph::LayerStatus st = sph::sph_validate(m, rig);
  if (!st.ok()) return from_layer(LoadError::kBadValue, v.id, v.instance, st.message);
  if (rig.joints[m.joint.distal_joint].dof_count == 0 ||
      rig.joints[m.joint.distal_joint].dof_kind != static_cast<uint8_t>(rig::DofKind::kRotation))
    return fail(LoadError::kBadValue, v.id, v.instance, "distal_joint", -1,
                "the driven joint needs a rotational DOF to bend", m.joint.distal_joint, true);
  if (p.force_input != kNoExternalInput && p.force_input >= external_count)
    return fail(LoadError::kBadIndex, v.id, v.instance, "force_input", -1, "names no external input", p.force_input,
                true);
  out->force_input = p.force_input;
  return {};
}

LoadStatus load_metaballs(const SectionView& v, const rig::Rig& rig, metaballs::MetaballModel* out) {
  const MetaballsSectionParams p = params_of<MetaballsSectionParams>(v);
  metaballs::MetaballModel& m = *out;
  m.joint_count = p.joint_count;
  m.vertex_count = p.vertex_count;
  m.pbd_iterations = p.pbd_iterations;
  m.jiggle_damping = p.jiggle_damping;
  m.jiggle_rate_hz = v.header.rate_hz;  // > 0: physical jiggle gains built for this rate
  m.smoothing_passes = p.smoothing_passes;
  m.smoothing_rate = p.smoothing_rate;
  m.inverse_bind = named<fx::Mat34, mb_array("inverse_bind")>(v);
  m.ball_rest = named<fx::Vec3, mb_array("ball_rest")>(v);
  m.ball_radius = named<fx::Len, mb_array("ball_radius")>(v);
  m.ball_bone = named<uint16_t, mb_array("ball_bone")>(v);
  m.ball_joint = named<uint16_t, mb_array("ball_joint")>(v);
  m.ball_weight = named<fx::Unit, mb_array("ball_weight")>(v);
  m.ball_jiggle = named<fx::Unit, mb_array("ball_jiggle")>(v);
  m.pairs = named<metaballs::BallPair, mb_array("pairs")>(v);
  m.bulges = named<metaballs::BulgeRecord, mb_array("bulges")>(v);
  m.vertex_ball = named<uint16_t, mb_array("vertex_ball")>(v);
  m.vertex_weight = named<fx::Unit, mb_array("vertex_weight")>(v);
  m.vertex_disp = named<fx::Vec3, mb_array("vertex_disp")>(v);
  m.joint_balls = named<metaballs::JointBall, mb_array("joint_balls")>(v);
  m.jv_vertex = named<uint32_t, mb_array("jv_vertex")>(v);
  m.jv_ball = named<uint16_t, mb_array("jv_ball")>(v);
  m.jv_alpha = named<fx::Unit, mb_array("jv_alpha")>(v);
  m.jv_blend = named<fx::Unit, mb_array("jv_blend")>(v);
  m.jv_disp = named<fx::Vec3, mb_array("jv_disp")>(v);
  m.jv_laplacian = named<fx::Vec3, mb_array("jv_laplacian")>(v);
  m.jv_neighbour_begin = named<uint32_t, mb_array("jv_neighbour_begin")>(v);
  m.jv_neighbours = named<uint32_t, mb_array("jv_neighbours")>(v);
  m.jv_inv_count = named<fx::Unit, mb_array("jv_inv_count")>(v);
  m.overlaps = named<metaballs::OverlapRecord, mb_array("overlaps")>(v);
  m.overlap_vertices = named<uint32_t, mb_array("overlap_vertices")>(v);
  m.overlap_balls = named<uint16_t, mb_array("overlap_balls")>(v);
  if (v.header.layer_version == kMetaballsSectionVersion2) {  // action lines
    m.action_lines = named<metaballs::ActionLine, mb_array("action_lines")>(v);
    m.action_balls = named<metaballs::ActionBall, mb_array("action_balls")>(v);
  }
  const metaballs::LayerStatus st = metaballs::metaballs_validate(m, rig);
  if (!st.ok()) return from_layer(LoadError::kBadValue, v.id, v.instance, st.message);
  return {};
}

LoadStatus load_muscles(const SectionView& v, const rig::Rig& rig, muscle::MuscleModel* out) {
  const MusclesSectionParams p = params_of<MusclesSectionParams>(v);
  const bool v2 = v.header.layer_version >= kMusclesSectionVersion2;
  const bool v3 = v.header.layer_version >= kMusclesSectionVersion3;
  const bool v4 = v.header.layer_version == kMusclesSectionVersion4;
  *out = {p.joint_count,
          p.ring_vertices,
          named<muscle::MuscleRecord, muscle_array("muscles")>(v),
          named<muscle::PrimitiveRecord, muscle_array("primitives")>(v),
          v2 ? named<muscle::PrimitiveDeformation, muscle_array("deformations")>(v)
             : std::span<const muscle::PrimitiveDeformation>{},
          v3 ? named<muscle::MuscleShape, muscle_array("shapes")>(v) : std::span<const muscle::MuscleShape>{},
          v4 ? named<muscle::PrimitiveExponents, muscle_array("exponents")>(v)
             : std::span<const muscle::PrimitiveExponents>{}};
  const muscle::LayerStatus st = muscle::muscle_validate(*out, rig);
  if (!st.ok()) return from_layer(LoadError::kBadValue, v.id, v.instance, st.message);
  return {};
}

LoadStatus load_skin(const SectionView& v, const rig::Rig& rig, const muscle::MuscleModel& muscles,
                     std::span<const ExternalInputRecord> external, LayerSet* set) {
  elastic_skin::SkinModel* out = &set->skin;
  std::span<const uint32_t>* region = &set->skin_region;
  std::span<const fx::Unit>* region_weight = &set->skin_region_weight;
  SkinSectionParamsV3 p{};
  if (v.header.layer_version == kSkinSectionVersion5) {
    const SkinSectionParamsV5 p5 = params_of<SkinSectionParamsV5>(v);
    p = p5.v3;
    for (int c = 0; c < 3; ++c) {
      const uint32_t k = p5.base_acceleration_input[c];
      if (k != kNoExternalInput && k >= external.size())
        return fail(LoadError::kBadIndex, v.id, v.instance, "base_acceleration_input", c,
                    "not an external input of the rig (EXTI)", k, true);
      if (k != kNoExternalInput && external[k].quantity != static_cast<uint32_t>(InputQuantity::kAcceleration))
        return fail(LoadError::kBadValue, v.id, v.instance, "base_acceleration_input", c,
                    "names an external input that is not an acceleration", k, true);
      set->skin_base_acceleration[c] = k;
    }
  } else if (v.header.layer_version == kSkinSectionVersion3 || v.header.layer_version == kSkinSectionVersion4) {
    p = params_of<SkinSectionParamsV3>(v);
  } else if (v.header.layer_version == kSkinSectionVersion2) {  // the solver record without edge_damping
    const SkinSectionParamsV2 p2 = params_of<SkinSectionParamsV2>(v);
    p.joint_count = p2.joint_count;
    p.vertex_count = p2.vertex_count;
    p.params = p2.params;
    std::memcpy(static_cast<void*>(&p.solver), p2.solver, kSkinSolverBytesV2);
  } else {  // version 1: the default solver (static relaxation)
    const SkinSectionParams p1 = params_of<SkinSectionParams>(v);
    p.joint_count = p1.joint_count;
    p.vertex_count = p1.vertex_count;
    p.params = p1.params;
  }
  *out = {p.joint_count,
          p.vertex_count,
          named<elastic_skin::Anchor, skin_array("anchors")>(v),
          named<elastic_skin::Stiffness, skin_array("anchor_stiffness")>(v),
          named<fx::Len, skin_array("fat")>(v),
          named<elastic_skin::Edge, skin_array("edges")>(v),
          named<elastic_skin::RubberBand, skin_array("bands")>(v),
          p.params,
          p.solver,
          rig.triangles};
  // fat_normal is a version 4 field (kept in 5): older sections keep the
  // anchor normal whatever their reserved byte holds.
  if (v.header.layer_version < kSkinSectionVersion4) out->solver.fat_normal = 0;
  *region = named<uint32_t, skin_array("region_vertex")>(v);
  *region_weight = named<fx::Unit, skin_array("region_weight")>(v);
  if (out->vertex_count != rig.vertex_count())
    return fail(LoadError::kBadValue, v.id, v.instance, "vertex_count", -1, "differs from the rig's", out->vertex_count,
                true);
  if (region->size() != region_weight->size())
    return fail(LoadError::kSectionSize, v.id, v.instance, "region_weight", -1, "count differs from region_vertex",
                static_cast<int64_t>(region_weight->size()), true);
  for (uint32_t i = 0; i < region->size(); ++i) {
    if ((*region)[i] >= rig.vertex_count() || (i > 0 && (*region)[i] <= (*region)[i - 1]))
      return fail(LoadError::kBadIndex, v.id, v.instance, "region_vertex", i,
                  "not an ascending vertex index of the rig", (*region)[i], true);
    if ((*region_weight)[i] <= 0 || (*region_weight)[i] > fx::kUnitOne)
      return fail(LoadError::kBadValue, v.id, v.instance, "region_weight", i, "outside (0, 1]", (*region_weight)[i],
                  true);
  }
  const muscle::LayerStatus st = elastic_skin::skin_validate(*out, rig, muscles);
  if (!st.ok()) return from_layer(LoadError::kBadValue, v.id, v.instance, st.message);
  return {};
}

LoadStatus load_barnet(const SectionView& v, const rig::Rig& rig, uint32_t external_count, barnet::BarnetModel* out) {
  const BarnetSectionParams p = params_of<BarnetSectionParams>(v);
  const bool v2 = v.header.layer_version == kBarnetSectionVersion2;
  *out = {p.joint_count,
          p.input_count,
          p.vertex_count,
          named<fx::Mat34, barnet_array("inverse_bind")>(v),
          named<barnet::NodeRecord, barnet_array("nodes")>(v),
          named<barnet::BarRecord, barnet_array("bars")>(v),
          named<barnet::LoadRecord, barnet_array("loads")>(v),
          named<barnet::ControlTriangle, barnet_array("triangles")>(v),
          named<barnet::WrapRecord, barnet_array("wrap")>(v),
          0,
          {}};
  if (v2) {
    if (p.external_count != external_count)
      return fail(LoadError::kBadValue, v.id, v.instance, "external_count", -1,
                  "differs from the rig's external inputs (EXTI)", p.external_count, true);
    out->external_count = p.external_count;
    out->q_inputs = named<barnet::ForceDensityInput, barnet_array("q_inputs")>(v);
  }
  const barnet::LayerStatus st = barnet::barnet_validate(*out, rig);
  if (!st.ok()) return from_layer(LoadError::kBadValue, v.id, v.instance, st.message);
  return {};
}

}  // namespace

LoadStatus layers_validate(const rig::Rig& rig, const uint8_t* blob, size_t size, size_t* arena_bytes) {
  (void)rig;
  size_t core_bytes = 0;
  LoadStatus st = rig::rig_validate(blob, size, &core_bytes);
  if (!st.ok()) return st;
  uint64_t bytes = 0;
  bool muscles = false, skin = false;
  st = for_each_layer_section(blob, [&](uint32_t id, uint32_t instance, uint32_t offset, uint32_t sz) {
    SectionView v;
    LoadStatus s = check_section(id, instance, blob + offset, sz, &v);
    muscles |= id == kSectionMuscles;
    skin |= id == kSectionElasticSkin;
    bytes += align8(sz);
    return s;
  });
  if (!st.ok()) return st;
  if (skin && !muscles)
    return fail(LoadError::kMissingSection, kSectionMuscles, 0, "", -1, "the elastic skin (SKIN) needs MUSC");
  *arena_bytes = static_cast<size_t>(bytes);
  return {};
}

LoadStatus layers_init(const rig::Rig& rig, const uint8_t* blob, size_t size, void* arena, size_t arena_bytes,
                       LayerSet* out) {
  size_t needed = 0;
  LoadStatus st = layers_validate(rig, blob, size, &needed);
  if (!st.ok()) return st;
  if ((needed > 0 && arena == nullptr) || arena_bytes < needed || (reinterpret_cast<uintptr_t>(arena) & 7u) != 0) {
    LoadStatus s;
    s.error = LoadError::kArenaTooSmall;
    rig::MessageBuilder m(s.message, sizeof(s.message));
    m.text("rig blob: layer arena: smaller than layers_validate's bytes or misaligned (")
        .number(static_cast<int64_t>(needed))
        .text(")");
    return s;
  }
  LayerSet set;
  uint8_t* a = static_cast<uint8_t*>(arena);
  size_t used = 0;
  // Copy every layer section first, keeping its view: the external inputs and
  // the muscles are needed by the SPH and skin sections whatever their order.
  SectionView views[kMaxSphJoints + kMaxBarnets + 4];
  uint32_t view_count = 0;
  st = for_each_layer_section(blob, [&](uint32_t id, uint32_t instance, uint32_t offset, uint32_t sz) {
    uint8_t* dst = a + used;
    if (sz > 0) std::memcpy(dst, blob + offset, sz);
    used += static_cast<size_t>(align8(sz));
    return check_section(id, instance, dst, sz, &views[view_count++]);
  });
  if (!st.ok()) return st;
  for (uint32_t i = 0; i < view_count; ++i)
    if (views[i].id == kSectionExternalInputs) {
      set.external = named<ExternalInputRecord, layer::array_ref(kExternalInputArraysList, "inputs")>(views[i]);
      if (!(st = check_external(views[i], set.external, rig)).ok()) return st;
    }
  for (uint32_t i = 0; i < view_count; ++i)
    if (views[i].id == kSectionMuscles) {
      set.has_muscles = true;
      if (!(st = load_muscles(views[i], rig, &set.muscles)).ok()) return st;
    }
  for (uint32_t i = 0; i < view_count; ++i) {
    const SectionView& v = views[i];
    switch (v.id) {
      case kSectionSphJoint:
        st = load_sph(v, rig, set.external_count(), &set.sph[set.sph_count]);
        if (st.ok() && set.rate_hz != 0 && set.rate_hz != v.header.rate_hz)
          st = fail(LoadError::kBadValue, v.id, v.instance, "rate_hz", -1, "differs from another SPH joint's",
                    v.header.rate_hz, true);
        set.rate_hz = v.header.rate_hz;
        ++set.sph_count;
        break;
      case kSectionMetaballs:
        set.has_metaballs = true;
        st = load_metaballs(v, rig, &set.metaballs);
        break;
      case kSectionElasticSkin:
        set.has_skin = true;
        st = load_skin(v, rig, set.muscles, set.external, &set);
        break;
      case kSectionBarnet:
        st = load_barnet(v, rig, set.external_count(), &set.barnet[set.barnet_count++]);
        break;
      default:
        break;
    }
    if (!st.ok()) return st;
  }
  *out = set;
  return {};
}

uint32_t find_external_input(const LayerSet& layers, const char* name) {
  for (uint32_t i = 0; i < layers.external.size(); ++i)
    if (std::strcmp(layers.external[i].name, name) == 0) return i;
  return kNoExternalInput;
}

}  // namespace sinew::pipeline
