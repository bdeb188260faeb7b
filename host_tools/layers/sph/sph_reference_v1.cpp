// The first sph implementation, verbatim but for the state type (RefState,
// vectors instead of a carved arena), the public names (ref_*) and the
// Tresca yield, which follows sph_step's per-substep rule and the joint's
// sim_core/sph/sph_yield.hpp since the yield stopped latching for the run:
// see sph_reference_v1.hpp. Do not optimise or reformat: it is the reference.
#include "host_tools/layers/sph/sph_reference_v1.hpp"

#include <array>
#include <cstddef>

#include "sim_core/fixed/arena.hpp"
#include "sim_core/fixed/scalar.hpp"
#include "sim_core/fixed/wide.hpp"
#include "sim_core/rig/message.hpp"
#include "sim_core/sph/sph_yield.hpp"

namespace sinew::sph_reference_v1 {
using namespace ::sinew::sph;  // the model, params and status types (unchanged)
using SphState = RefState;

// Smoothing kernels of Mueller, Charypar and Gross 2003 (the paper's [37]), in
// normalised form: each takes s = q^2 with q = distance / h in Q2.30, s in
// [0, 1], and omits the constants (they fold into the particle mass and the
// gains of SphParams). Working in units of h keeps every value in [0, ~32]:
// fixed point neither overflows nor underflows whatever the rig's units.
//   poly6:      W  ~ (1 - q^2)^3            (density)
//   spiky grad: dW ~ (1 - q)^2 / q * (r/h)  (pressure; factor tabulated)
//   viscosity:  L  ~ (1 - q)                (viscosity Laplacian)
// The two kernels that need q itself come from 1025-entry tables over s
// (built at compile time with an exact integer sqrt) with linear
// interpolation: pure integer, identical on every platform.

namespace kernel_detail {

constexpr uint64_t isqrt(uint64_t v) {
  uint64_t root = 0, bit = uint64_t{1} << 62;
  while (bit > v) bit >>= 2;
  while (bit != 0) {
    if (v >= root + bit) {
      v -= root + bit;
      root = (root >> 1) + bit;
    } else {
      root >>= 1;
    }
    bit >>= 2;
  }
  return root;
}

inline constexpr int kTableBits = 10;  // 1024 intervals over s in [0, 1]
inline constexpr int kStepShift = 30 - kTableBits;
inline constexpr size_t kTableSize = (size_t{1} << kTableBits) + 1;

// q in Q30 for s in Q30.
constexpr int64_t q_of(int64_t s) { return static_cast<int64_t>(isqrt(static_cast<uint64_t>(s) << 30)); }

// (1 - q)^2 / q in Q24; below the first table step q is clamped to 1/32
// (coincident particles have no direction anyway).
constexpr std::array<int32_t, kTableSize> make_spiky() {
  std::array<int32_t, kTableSize> t{};
  for (size_t i = 0; i < kTableSize; ++i) {
    const int64_t s = static_cast<int64_t>(i == 0 ? 1 : i) << kStepShift;
    const int64_t q = q_of(s), one = int64_t{1} << 30;
    const int64_t num = (one - q) * (one - q);  // Q60
    t[i] = static_cast<int32_t>((num / q + 32) >> 6);
  }
  return t;
}

// 1 - q in Q30.
constexpr std::array<int32_t, kTableSize> make_viscosity() {
  std::array<int32_t, kTableSize> t{};
  for (size_t i = 0; i < kTableSize; ++i)
    t[i] = static_cast<int32_t>((int64_t{1} << 30) - q_of(static_cast<int64_t>(i) << kStepShift));
  return t;
}

inline constexpr std::array<int32_t, kTableSize> kSpiky = make_spiky();
inline constexpr std::array<int32_t, kTableSize> kViscosity = make_viscosity();

inline int32_t lookup(const std::array<int32_t, kTableSize>& t, uint32_t s) {
  const uint32_t i = s >> kStepShift;
  if (i >= kTableSize - 1) return t[kTableSize - 1];
  const int64_t frac = s & ((uint32_t{1} << kStepShift) - 1);
  const int64_t a = t[i], b = t[i + 1];
  return static_cast<int32_t>(a + fx::round_shift((b - a) * frac, kStepShift));
}

}  // namespace kernel_detail

// s = q^2 in Q2.30, s < 2^30 (inside the kernel). Result in Q2.30.
inline int32_t poly6(uint32_t s) {
  const int64_t t = (int64_t{1} << 30) - s;
  const int64_t t2 = fx::round_shift(t * t, 30);
  return static_cast<int32_t>(fx::round_shift(t2 * t, 30));
}

// (1 - q)^2 / q in Q8.24.
inline int32_t spiky_factor(uint32_t s) { return kernel_detail::lookup(kernel_detail::kSpiky, s); }

// (1 - q) in Q2.30.
inline int32_t viscosity_factor(uint32_t s) { return kernel_detail::lookup(kernel_detail::kViscosity, s); }

// Normalised offset (a - b) / h in Q2.30 and s = q^2 in Q2.30 for two
// positions closer than h on every axis; false (and nothing written) when
// they are not within the kernel. inv_h: 2^50 / h, rounded (see InvH).
struct PairGeometry {
  fx::Vec3 d;  // (a - b) / h, Q2.30, each component in (-1, 1)
  uint32_t s;  // |d|^2, Q2.30, < 2^30
};

struct InvH {
  int64_t inv = 0;  // round(2^50 / h)
  fx::Len h = 0;
};

inline InvH make_inv_h(fx::Len h) { return {fx::div_round(int64_t{1} << 50, h), h}; }

inline bool pair_geometry(fx::Vec3 a, fx::Vec3 b, const InvH& ih, PairGeometry* out) {
  const int64_t dx = int64_t{a.x} - b.x, dy = int64_t{a.y} - b.y, dz = int64_t{a.z} - b.z;
  if (dx >= ih.h || dx <= -ih.h || dy >= ih.h || dy <= -ih.h || dz >= ih.h || dz <= -ih.h) return false;
  // |d| < h < 2^31 and inv < 2^50 / h, so the products stay below 2^50.
  const int64_t nx = fx::round_shift(dx * ih.inv, 20), ny = fx::round_shift(dy * ih.inv, 20),
                nz = fx::round_shift(dz * ih.inv, 20);
  const int64_t s = fx::round_shift(nx * nx + ny * ny + nz * nz, 30);
  if (s >= (int64_t{1} << 30)) return false;
  out->d = {static_cast<int32_t>(nx), static_cast<int32_t>(ny), static_cast<int32_t>(nz)};
  out->s = static_cast<uint32_t>(s);
  return true;
}

namespace {

struct JointFrame {
  const fx::Mat34* proximal;
  const fx::Mat34* distal;
  fx::Vec3 centre;  // Len: the distal joint's origin
  fx::Vec3 axis;    // Q2.30 unit flexion axis, model space
};

uint32_t axis_cell(const SphState& st, int32_t centre, int32_t p) {
  const SphParams& pr = st.model->params;
  const int64_t off = int64_t{p} - (int64_t{centre} - pr.grid_radius);
  if (off <= 0) return 0;
  const uint64_t c = static_cast<uint64_t>(off) / static_cast<uint64_t>(pr.h);
  return c >= st.grid_dim ? st.grid_dim - 1 : static_cast<uint32_t>(c);
}

uint32_t cell_index(const RefState& st, fx::Vec3 centre, fx::Vec3 p) {
  const uint32_t d = st.grid_dim;
  return (axis_cell(st, centre.z, p.z) * d + axis_cell(st, centre.y, p.y)) * d + axis_cell(st, centre.x, p.x);
}

void build_neighbours(SphState* st, fx::Vec3 centre) {
  const SphModel& m = *st->model;
  const uint32_t n = m.particle_count(), d = st->grid_dim, cells = d * d * d;
  const uint32_t k_max = m.params.max_neighbours;
  for (uint32_t c = 0; c <= cells; ++c) st->cell_start[c] = 0;
  for (uint32_t i = 0; i < n; ++i) {
    const fx::Vec3 p{st->position[0][i], st->position[1][i], st->position[2][i]};
    st->cell[i] = cell_index(*st, centre, p);
    ++st->cell_start[st->cell[i] + 1];
  }
  for (uint32_t c = 0; c < cells; ++c) st->cell_start[c + 1] += st->cell_start[c];
  // Scatter in index order (stable), using cell_start[c] as the cursor, then
  // shift the cursors back to the starts.
  for (uint32_t i = 0; i < n; ++i) st->sorted[st->cell_start[st->cell[i]]++] = static_cast<uint16_t>(i);
  for (uint32_t c = cells; c > 0; --c) st->cell_start[c] = st->cell_start[c - 1];
  st->cell_start[0] = 0;

  const InvH ih = make_inv_h(m.params.h);
  for (uint32_t i = 0; i < n; ++i) {
    const fx::Vec3 pi{st->position[0][i], st->position[1][i], st->position[2][i]};
    const uint32_t c = st->cell[i];
    const int32_t cx = static_cast<int32_t>(c % d), cy = static_cast<int32_t>((c / d) % d),
                  cz = static_cast<int32_t>(c / (d * d));
    Neighbour* list = &st->neighbours[size_t{i} * k_max];
    uint32_t count = 0;
    for (int32_t z = cz - 1; z <= cz + 1; ++z) {
      if (z < 0 || z >= static_cast<int32_t>(d)) continue;
      for (int32_t y = cy - 1; y <= cy + 1; ++y) {
        if (y < 0 || y >= static_cast<int32_t>(d)) continue;
        for (int32_t x = cx - 1; x <= cx + 1; ++x) {
          if (x < 0 || x >= static_cast<int32_t>(d)) continue;
          const uint32_t cc = (static_cast<uint32_t>(z) * d + static_cast<uint32_t>(y)) * d + static_cast<uint32_t>(x);
          for (uint32_t k = st->cell_start[cc]; k < st->cell_start[cc + 1]; ++k) {
            const uint32_t j = st->sorted[k];
            if (j == i) continue;
            PairGeometry g;
            if (!pair_geometry(pi, {st->position[0][j], st->position[1][j], st->position[2][j]}, ih, &g)) continue;
            if (count == k_max) {
              ++st->stats.neighbour_overflow;
              continue;
            }
            list[count++] = {static_cast<uint16_t>(j), 0, g.s};
          }
        }
      }
    }
    st->neighbour_count[i] = static_cast<uint8_t>(count);
    st->stats.neighbour_pairs += count;
    if (count > st->stats.max_neighbour_count) st->stats.max_neighbour_count = count;
  }
}

void compute_density(SphState* st) {
  const uint32_t n = st->model->particle_count(), k_max = st->model->params.max_neighbours;
  for (uint32_t i = 0; i < n; ++i) {
    int64_t sum = int64_t{1} << 30;  // the particle itself: poly6(0) = 1
    const Neighbour* list = &st->neighbours[size_t{i} * k_max];
    for (uint32_t k = 0; k < st->neighbour_count[i]; ++k) sum += poly6(list[k].s);
    // At most 1 + 96 terms of at most 1.0: below 2^37 in Q30, 97 in Q8.24.
    st->density[i] = static_cast<Dens>(fx::round_shift(sum, 30 - kDensFracBits));
  }
}

bool joint_frame(const SphModel& m, std::span<const fx::Mat34> transforms, JointFrame* out) {
  if (m.joint.proximal_joint >= transforms.size() || m.joint.distal_joint >= transforms.size()) return false;
  out->proximal = &transforms[m.joint.proximal_joint];
  out->distal = &transforms[m.joint.distal_joint];
  out->centre = {out->distal->t[0], out->distal->t[1], out->distal->t[2]};
  // The linear part may carry scale (Q8.24); renormalise the axis.
  const fx::Vec3 a = fx::transform_vector(*out->distal, m.joint.axis);
  if (!fx::normalize_to_unit(a, &out->axis)) out->axis = m.joint.axis;
  return true;
}

void compute_ideal(SphState* st, const JointFrame& f) {
  const SphModel& m = *st->model;
  for (uint32_t i = 0; i < m.particle_count(); ++i) {
    const fx::Mat34& M = m.bone[i] == static_cast<uint8_t>(Bone::kDistal) ? *f.distal : *f.proximal;
    const fx::Vec3 p = fx::transform_point(M, {m.rest_local[0][i], m.rest_local[1][i], m.rest_local[2][i]});
    st->ideal[0][i] = p.x;
    st->ideal[1][i] = p.y;
    st->ideal[2][i] = p.z;
  }
}

}  // namespace

namespace {

uint32_t grid_dim_of(const SphParams& p) { return static_cast<uint32_t>((2 * int64_t{p.grid_radius} + p.h - 1) / p.h); }

void layout(const SphModel& m, RefState* s) {
  const size_t n = m.particle_count(), sv = m.skin_count();
  const size_t d = grid_dim_of(m.params), cells = d * d * d;
  for (int a = 0; a < 3; ++a) {
    s->position[a].assign(n, 0);
    s->velocity[a].assign(n, 0);
    s->ideal[a].assign(n, 0);
    s->scratch[a].assign(n, 0);
    s->skin_offset[a].assign(sv, 0);
  }
  s->pressure.assign(n, 0);
  s->yielded.assign(n, 0);
  s->density.assign(n, 0);
  s->rest_density.assign(n, 0);
  s->inv_density.assign(n, 0);
  s->cell.assign(n, 0);
  s->cell_start.assign(cells + 1, 0);
  s->sorted.assign(n, 0);
  s->neighbours.assign(n * m.params.max_neighbours, Neighbour{});
  s->neighbour_count.assign(n, 0);
  s->skin_particle.assign(sv * kMaxVertexNeighbours, 0);
  s->skin_weight.assign(sv * kMaxVertexNeighbours, 0);
  s->skin_count.assign(sv, 0);
  s->grid_dim = static_cast<uint32_t>(d);
}

LayerStatus fail(LayerError e, const char* what) {
  LayerStatus s;
  s.error = e;
  rig::MessageBuilder(s.message, sizeof s.message).text("sph init: ").text(what);
  return s;
}

// Kernel weights of eq. (2) between each skin vertex and the particles, at
// rest: the interpolation is embedded in the rest configuration (constant
// weights), only the particles' displacements and densities change.
void skin_weights(SphState* st, fx::Vec3 centre) {
  const SphModel& m = *st->model;
  const uint32_t d = st->grid_dim;
  const InvH ih = make_inv_h(m.params.h);
  for (uint32_t v = 0; v < m.skin_count(); ++v) {
    const fx::Vec3 pv{m.skin_rest[0][v], m.skin_rest[1][v], m.skin_rest[2][v]};
    const uint32_t c = cell_index(*st, centre, pv);
    const int32_t cx = static_cast<int32_t>(c % d), cy = static_cast<int32_t>((c / d) % d),
                  cz = static_cast<int32_t>(c / (d * d));
    uint32_t count = 0;
    for (int32_t z = cz - 1; z <= cz + 1; ++z)
      for (int32_t y = cy - 1; y <= cy + 1; ++y)
        for (int32_t x = cx - 1; x <= cx + 1; ++x) {
          if (x < 0 || y < 0 || z < 0 || x >= static_cast<int32_t>(d) || y >= static_cast<int32_t>(d) ||
              z >= static_cast<int32_t>(d))
            continue;
          const uint32_t cc = (static_cast<uint32_t>(z) * d + static_cast<uint32_t>(y)) * d + static_cast<uint32_t>(x);
          for (uint32_t k = st->cell_start[cc]; k < st->cell_start[cc + 1] && count < kMaxVertexNeighbours; ++k) {
            const uint32_t j = st->sorted[k];
            PairGeometry g;
            if (!pair_geometry(pv, {st->position[0][j], st->position[1][j], st->position[2][j]}, ih, &g)) continue;
            st->skin_particle[size_t{v} * kMaxVertexNeighbours + count] = static_cast<uint16_t>(j);
            st->skin_weight[size_t{v} * kMaxVertexNeighbours + count] = poly6(g.s);
            ++count;
          }
        }
    st->skin_count[v] = static_cast<uint8_t>(count);
  }
}

}  // namespace

LayerStatus ref_init(const SphModel& model, std::span<const fx::Mat34> rest_transforms, RefState* out) {
  LayerStatus status = sph_validate_model(model);
  if (!status.ok()) return status;
  RefState s;
  s.model = &model;
  layout(model, &s);
  JointFrame f;
  if (!joint_frame(model, rest_transforms, &f))
    return fail(LayerError::kBadInput, "rest_transforms shorter than the joints");
  // Rest density of every particle, from its rest neighbourhood: the state of
  // minimum principal stress (§4.2) and the reference of the equation of state.
  for (int a = 0; a < 3; ++a)
    for (uint32_t i = 0; i < model.particle_count(); ++i) s.position[a][i] = model.rest_model[a][i];
  build_neighbours(&s, f.centre);
  compute_density(&s);
  skin_weights(&s, f.centre);
  for (uint32_t i = 0; i < model.particle_count(); ++i) s.rest_density[i] = s.density[i];
  // Rotational inertia of the distal particles about the axis (equal masses).
  int64_t inertia = 0;
  for (uint32_t i = 0; i < model.particle_count(); ++i) {
    if (model.bone[i] != static_cast<uint8_t>(Bone::kDistal)) continue;
    const fx::Vec3 r = fx::sub({model.rest_model[0][i], model.rest_model[1][i], model.rest_model[2][i]}, f.centre);
    const fx::Vec3 rp = fx::cross(f.axis, r, 30);          // |axis x r| = |r_perp|
    inertia += fx::round_shift(fx::dot_wide(rp, rp), 28);  // Q40 -> Q12
  }
  if (inertia <= 0) return fail(LayerError::kBadValue, "distal particles have no lever arm about the joint axis");
  s.inertia_q12 = inertia;
  *out = s;
  status = ref_reset(out, rest_transforms);
  out->stats = {};
  return status;
}

LayerStatus ref_reset(RefState* st, std::span<const fx::Mat34> transforms) {
  JointFrame f;
  if (st == nullptr || st->model == nullptr) return fail(LayerError::kBadInput, "state is not initialised");
  if (!joint_frame(*st->model, transforms, &f))
    return fail(LayerError::kBadInput, "transforms shorter than the joints");
  compute_ideal(st, f);
  const uint32_t n = st->model->particle_count();
  for (int a = 0; a < 3; ++a)
    for (uint32_t i = 0; i < n; ++i) {
      st->position[a][i] = st->ideal[a][i];
      st->velocity[a][i] = 0;
    }
  for (uint32_t i = 0; i < n; ++i) {
    st->density[i] = st->rest_density[i];
    st->pressure[i] = 0;
    st->yielded[i] = 0;
    st->inv_density[i] = static_cast<fx::Unit>(fx::div_round(int64_t{1} << 54, st->rest_density[i]));
  }
  for (int a = 0; a < 3; ++a)
    for (uint32_t v = 0; v < st->model->skin_count(); ++v) st->skin_offset[a][v] = 0;
  st->bend = 0;
  st->joint_yielded = false;
  st->yielded_particles = 0;
  st->yield_torque_q12 = 0;
  st->distal_flexed = *f.distal;
  return {};
}

namespace {

constexpr int32_t kMaxForce = int32_t{1} << 30;  // newtons Q16.16: 16384 N

LayerStatus bad_input(const char* what) {
  LayerStatus s;
  s.error = LayerError::kBadInput;
  rig::MessageBuilder(s.message, sizeof s.message).text("sph step: ").text(what);
  return s;
}

// Torque of the external force about the joint axis, rig unit x N in Q12:
// ((P - c) x F) . n with P the load point (Len), F in Q16.16.
int64_t load_torque_q12(const JointFrame& f, const fx::Vec3& load_point, fx::Vec3 force) {
  const fx::Vec3 p = fx::transform_point(*f.distal, load_point);
  const int64_t r[3] = {int64_t{p.x} - f.centre.x, int64_t{p.y} - f.centre.y, int64_t{p.z} - f.centre.z};
  const int64_t F[3] = {force.x, force.y, force.z};
  const int64_t n[3] = {f.axis.x, f.axis.y, f.axis.z};
  int64_t torque = 0;
  for (int a = 0; a < 3; ++a) {
    const int b = (a + 1) % 3, c = (a + 2) % 3;
    // |r| < 2^32, |F| <= 2^30: each product < 2^62, the difference < 2^63.
    const int64_t cross_q36 = r[b] * F[c] - r[c] * F[b];
    torque += fx::mul_shift_round(cross_q36, n[a], 54);  // Q36 x Q30 -> Q12
  }
  return torque;
}

// Tresca yield, eq. (4), per substep: the rule sph_step applies since the
// yield stopped latching (a particle yields while its density is 2 tau_f
// above its rest density, held there).
void density_and_yield(SphState* st, bool tresca) {
  const SphModel& m = *st->model;
  compute_density(st);
  st->yielded_particles = 0;
  for (uint32_t i = 0; i < m.particle_count(); ++i) {
    Dens rho = st->density[i];
    const int64_t limit = int64_t{st->rest_density[i]} + 2 * int64_t{m.params.tau_f};
    st->yielded[i] = tresca && rho >= limit ? 1 : 0;
    if (st->yielded[i] != 0) {
      rho = static_cast<Dens>(limit);
      ++st->yielded_particles;
    }
    st->density[i] = rho;
    st->pressure[i] = fx::sat_i32(int64_t{rho} - st->rest_density[i]);
    st->inv_density[i] = static_cast<fx::Unit>(fx::div_round(int64_t{1} << 54, rho < kDensOne ? kDensOne : rho));
  }
}

// Per-substep velocity change (Len per substep) of every particle, into scratch.
void accelerations(SphState* st, const JointFrame& f, const fx::Mat34& loaded, fx::Unit beta, fx::Saturation& sat) {
  const SphModel& m = *st->model;
  const SphParams& pr = m.params;
  const InvH ih = make_inv_h(pr.h);
  for (uint32_t i = 0; i < m.particle_count(); ++i) {
    const fx::Vec3 xi{st->position[0][i], st->position[1][i], st->position[2][i]};
    const int64_t vi[3] = {st->velocity[0][i], st->velocity[1][i], st->velocity[2][i]};
    int64_t press[3] = {0, 0, 0};  // normalised units, Q8.24
    int64_t visc[3] = {0, 0, 0};   // Len per substep
    const Neighbour* list = &st->neighbours[size_t{i} * pr.max_neighbours];
    for (uint32_t k = 0; k < st->neighbour_count[i]; ++k) {
      const uint32_t j = list[k].j;
      PairGeometry g;
      if (!pair_geometry(xi, {st->position[0][j], st->position[1][j], st->position[2][j]}, ih, &g)) continue;
      // Pressure, symmetric form of Mueller 2003 eq. (10) with the spiky
      // gradient: (p_i + p_j) / (2 rho_j) (1 - q)^2 / q (r_ij / h).
      const int64_t psum = int64_t{st->pressure[i]} + st->pressure[j];                  // Q24
      const int64_t t = fx::round_shift(psum * st->inv_density[j], 31);                 // Q24, halved
      const int64_t tg = fx::sat_i32(fx::round_shift(t * spiky_factor(g.s), 24), sat);  // Q24
      press[0] += fx::round_shift(tg * g.d.x, 30);
      press[1] += fx::round_shift(tg * g.d.y, 30);
      press[2] += fx::round_shift(tg * g.d.z, 30);
      // Viscosity, Mueller 2003 eq. (14): (v_j - v_i) / rho_j * laplacian.
      const int64_t lw = fx::round_shift(int64_t{viscosity_factor(g.s)} * st->inv_density[j], 30);  // Q30
      for (int a = 0; a < 3; ++a) {
        const int64_t dv = int64_t{st->velocity[a][j]} - vi[a];
        visc[a] += fx::round_shift(dv * lw, 30);
      }
    }
    // Load carried by the distal bone, applied as its rigid-body angular
    // acceleration beta (axis x r) at each particle bound to it, unless it
    // yields, with r the particle's rest offset on the bone as the bone
    // stands (flexed by the bend so far). Taken at the particle's own
    // position the field would follow it (a circulatory force, whose damped
    // oscillator flutters once beta > c sqrt(k_e)); taken unflexed it would
    // shear the tissue instead of turning it (docs/sph.md).
    fx::Vec3 ext{0, 0, 0};
    if (beta != 0 && m.bone[i] == static_cast<uint8_t>(Bone::kDistal) && st->yielded[i] == 0) {
      const fx::Vec3 on_bone =
          fx::transform_point(loaded, {m.rest_local[0][i], m.rest_local[1][i], m.rest_local[2][i]});
      ext = fx::scale(fx::cross(f.axis, fx::sub(on_bone, f.centre), 30), beta);
    }
    const int32_t x[3] = {xi.x, xi.y, xi.z};
    const int32_t e[3] = {ext.x, ext.y, ext.z};
    for (int a = 0; a < 3; ++a) {
      // Pressure: Q24 (units of h) -> Len via gain (Q30) and h.
      const int64_t p16 = fx::sat_i32(fx::round_shift(press[a], 8), sat);  // Q16
      const int64_t pg = fx::round_shift(p16 * pr.pressure_gain, 30);      // Q16
      const int64_t p_len = fx::round_shift(pg * pr.h, 16);
      const int64_t v_len = fx::round_shift(fx::clamp_i64(visc[a], INT32_MIN, INT32_MAX) * pr.viscosity_gain, 30);
      // Elastic pull toward the skinned rest position (§4.1 tension).
      const int64_t pull = fx::round_shift((int64_t{st->ideal[a][i]} - x[a]) * pr.elastic_gain, 30);
      st->scratch[a][i] = fx::sat_i32(p_len + v_len + pull + e[a], sat);
    }
  }
}

void integrate(SphState* st, fx::Saturation& sat) {
  const SphModel& m = *st->model;
  for (int a = 0; a < 3; ++a)
    for (uint32_t i = 0; i < m.particle_count(); ++i) {
      // Symplectic Euler in Len per substep: v' = damping v + a dt^2, x' = x + v'.
      // damping v truncated toward zero, as sph_step (every velocity decays to rest).
      const int64_t kept = int64_t{st->velocity[a][i]} * m.params.damping;
      const int64_t v = (kept >= 0 ? kept >> 30 : -((-kept) >> 30)) + st->scratch[a][i];
      st->velocity[a][i] = fx::sat_i32(v, sat);
      st->position[a][i] = fx::sat_i32(int64_t{st->position[a][i]} + st->velocity[a][i], sat);
    }
}

// Best-fit rotation about the axis of the distal particles from their ideal
// to their current positions: atan2(sum n.(g x x), sum g_perp . x_perp).
fx::Angle measure_bend(const SphState& st, const JointFrame& f) {
  const SphModel& m = *st.model;
  int64_t s = 0, c = 0;
  for (uint32_t i = 0; i < m.particle_count(); ++i) {
    if (m.bone[i] != static_cast<uint8_t>(Bone::kDistal)) continue;
    const fx::Vec3 g = fx::sub({st.ideal[0][i], st.ideal[1][i], st.ideal[2][i]}, f.centre);
    const fx::Vec3 x = fx::sub({st.position[0][i], st.position[1][i], st.position[2][i]}, f.centre);
    const fx::Vec3 gx = fx::cross(g, x, 20);             // Len
    s += fx::round_shift(fx::dot_wide(gx, f.axis), 30);  // Len
    // g_perp . x_perp = g . x - (g . n)(x . n) (the flexion the distal
    // particles carry, sph-elastic-joints-tresca §4). |g . n| and |x . n|
    // reach sqrt(3) x 2^31 (offsets saturated to Len along a diagonal axis),
    // so their product (up to 3 x 2^62) is formed in 128 bits and rounded
    // once: the same value as before wherever it fitted in int64. g . x
    // saturates (dot_wide) only when both offsets lie near a corner of the
    // Len range.
    const int64_t gn = fx::round_shift(fx::dot_wide(g, f.axis), 30);
    const int64_t xn = fx::round_shift(fx::dot_wide(x, f.axis), 30);
    c += fx::round_shift(fx::dot_wide(g, x), 20) - fx::mul_shift_round(gn, xn, 20);
  }
  while (s >= (int64_t{1} << 30) || s <= -(int64_t{1} << 30) || c >= (int64_t{1} << 30) || c <= -(int64_t{1} << 30)) {
    s >>= 1;
    c >>= 1;
  }
  return fx::atan2_angle(static_cast<int32_t>(s), static_cast<int32_t>(c));
}

// Displacement of eq. (2): A(r) = sum_j m_j A_j W(r - r_j, h) / rho_j, A_j the
// particle's offset from its anchor in the flexed pose; kernel weights taken
// at rest. In normalised units m_j W / rho_j = w / rho_hat, so a vertex deep
// in the tissue takes the full displacement and one outside every kernel
// none: the interpolation itself blends SPH with the skinning result.
void skin_displacement(SphState* st, fx::Saturation& sat) {
  const SphModel& m = *st->model;
  for (uint32_t i = 0; i < m.particle_count(); ++i) {
    const fx::Vec3 r{m.rest_local[0][i], m.rest_local[1][i], m.rest_local[2][i]};
    const bool distal = m.bone[i] == static_cast<uint8_t>(Bone::kDistal);
    const fx::Vec3 anchor = distal ? fx::transform_point(st->distal_flexed, r)
                                   : fx::Vec3{st->ideal[0][i], st->ideal[1][i], st->ideal[2][i]};
    st->scratch[0][i] = fx::sub_sat(st->position[0][i], anchor.x);
    st->scratch[1][i] = fx::sub_sat(st->position[1][i], anchor.y);
    st->scratch[2][i] = fx::sub_sat(st->position[2][i], anchor.z);
  }
  for (uint32_t v = 0; v < m.skin_count(); ++v) {
    int64_t sum[3] = {0, 0, 0};
    const size_t base = size_t{v} * kMaxVertexNeighbours;
    for (uint32_t k = 0; k < st->skin_count[v]; ++k) {
      const uint32_t j = st->skin_particle[base + k];
      const int64_t w = fx::round_shift(int64_t{st->skin_weight[base + k]} * st->inv_density[j], 30);  // Q30
      for (int a = 0; a < 3; ++a) sum[a] += fx::round_shift(int64_t{st->scratch[a][j]} * w, 30);
    }
    for (int a = 0; a < 3; ++a) st->skin_offset[a][v] = fx::sat_i32(sum[a], sat);
  }
}

}  // namespace

LayerStatus ref_step(RefState* st, const SphInputs& in) {
  if (st == nullptr || st->model == nullptr) return bad_input("state is not initialised");
  const SphModel& m = *st->model;
  JointFrame f;
  if (!joint_frame(m, in.transforms, &f)) return bad_input("transforms: fewer than the model's joints");
  if (in.force.x < -kMaxForce || in.force.x > kMaxForce || in.force.y < -kMaxForce || in.force.y > kMaxForce ||
      in.force.z < -kMaxForce || in.force.z > kMaxForce)
    return bad_input("force: a component beyond 16384 N");
  fx::Saturation sat;
  st->stats.neighbour_overflow = 0;
  st->stats.max_neighbour_count = 0;
  st->stats.neighbour_pairs = 0;

  const int64_t requested = fx::clamp_i64(load_torque_q12(f, m.joint.load_point, in.force), INT32_MIN, INT32_MAX);
  const JointYield before{st->joint_yielded, st->yield_torque_q12};
  const int64_t torque = held_load_torque(before, requested);
  // Angular acceleration x dt^2 of the distal bone: torque x load_gain / I.
  const fx::Unit beta = fx::sat_i32(
      fx::clamp_i64(fx::div_round(torque * m.params.load_gain, st->inertia_q12), -fx::kUnitOne, fx::kUnitOne), sat);

  compute_ideal(st, f);
  // The distal bone as it stands: the tick's pose flexed by the bend so far.
  const fx::Mat34 loaded =
      fx::mul(*f.distal, fx::mat34_from_quat(fx::quat_from_axis_angle(m.joint.axis, st->bend), {0, 0, 0}));
  for (uint32_t s = 0; s < m.params.substeps; ++s) {
    build_neighbours(st, f.centre);
    density_and_yield(st, in.tresca);
    accelerations(st, f, loaded, beta, sat);
    integrate(st, sat);
  }
  const JointYield after =
      next_joint_yield(before, in.tresca, st->yielded_particles, m.params.yield_count, requested, torque);
  st->joint_yielded = after.yielded;
  st->yield_torque_q12 = after.held_torque_q12;
  st->bend = measure_bend(*st, f);
  const fx::Mat34 flex = fx::mat34_from_quat(fx::quat_from_axis_angle(m.joint.axis, st->bend), {0, 0, 0});
  st->distal_flexed = fx::mul(*f.distal, flex);
  skin_displacement(st, sat);
  st->stats.saturated = sat.events;
  ++st->stats.steps;
  return {};
}

void ref_apply_skin(const RefState& st, std::span<fx::Len> position[3]) {
  const SphModel& m = *st.model;
  for (uint32_t v = 0; v < m.skin_count(); ++v) {
    const uint32_t idx = m.skin_vertex[v];
    for (int a = 0; a < 3; ++a)
      if (idx < position[a].size()) position[a][idx] = fx::add_sat(position[a][idx], st.skin_offset[a][v]);
  }
}

}  // namespace sinew::sph_reference_v1
