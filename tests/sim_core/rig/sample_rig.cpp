#include "sample_rig.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstddef>

#include "host_tools/rigc/rig_spec.hpp"
#include "sim_core/rig/crc32c.hpp"

namespace sinew::test {
namespace {

constexpr double kPi = 3.14159265358979323846;

rigc::JointSpec joint(const char* name, int parent, rigc::Vec3d translation) {
  rigc::JointSpec j;
  j.name = name;
  j.parent = parent;
  j.translation = translation;
  return j;
}

// Column-major 4x4 inverse of T(t) * Rz(degrees): Rz(-a) * T(-t).
rigc::Mat4d inverse_bind(rigc::Vec3d t, double degrees) {
  const double c = std::cos(degrees * kPi / 180), s = std::sin(degrees * kPi / 180);
  // Rows of Rz(-a): (c, s, 0), (-s, c, 0), (0, 0, 1).
  const double tx = -(c * t[0] + s * t[1]), ty = -(-s * t[0] + c * t[1]), tz = -t[2];
  return {c, -s, 0, 0, s, c, 0, 0, 0, 0, 1, 0, tx, ty, tz, 1};
}

}  // namespace

rigc::RigSpec sample_rig_spec() {
  rigc::RigSpec spec;
  rigc::JointSpec root = joint("root", -1, {0, 0, 0});
  root.dof_kind = rigc::DofKind::kTranslation;
  root.dofs = {{{0, 0, 1}, -0.05, 0.05}};
  rigc::JointSpec knuckle = joint("knuckle", 0, {0, 0.04, 0});
  knuckle.dofs = {{{1, 0, 0}, -10, 90}, {{0, 0, 1}, -20, 20}};
  rigc::JointSpec tip = joint("tip", 1, {0, 0.03, 0});
  tip.rotation = {std::cos(kPi / 12), 0, 0, std::sin(kPi / 12)};  // 30 degrees about z
  tip.dofs = {{{1, 0, 0}, -5, 80}};
  spec.joints = {root, knuckle, tip};
  spec.synergies = {{1, 2, 0, 0.6}};  // knuckle flexion drags the tip
  spec.palette = {
      {0, inverse_bind({0, 0, 0}, 0)}, {1, inverse_bind({0, 0.04, 0}, 0)}, {2, inverse_bind({0, 0.07, 0}, 30)}};
  for (int row = 0; row < 10; ++row) {
    for (int side = 0; side < 2; ++side) {
      rigc::VertexSpec v;
      v.position = {side == 0 ? -0.01 : 0.01, 0.01 * row, 0.002 * side};
      const int p = row * 3 / 10;  // palette entry nearest along the strip
      if (row % 2 == 0)
        v.influences = {{p, 0.6}, {(p + 1) % 3, 0.3}, {(p + 2) % 3, 0.1}};
      else
        v.influences = {{p, 0.7}, {(p + 1) % 3, 0.3}};
      v.dual_quaternion = (row + side) % 4 == 0;
      spec.vertices.push_back(v);
    }
  }
  for (uint32_t row = 0; row + 1 < 10; ++row) {
    const uint32_t a = 2 * row;
    spec.triangles.push_back({a, a + 1, a + 2});
    spec.triangles.push_back({a + 1, a + 3, a + 2});
  }
  spec.primitives = {{0, 20}};
  return spec;
}

Blob::Blob(const std::vector<uint8_t>& bytes) : words_(bytes.size() / 8 + 1, 0), size_(bytes.size()) {
  std::memcpy(data(), bytes.data(), bytes.size());
}

size_t Blob::entry_offset(uint32_t id) const {
  const rig::FileHeader h = header();
  for (uint32_t i = 0; i < h.section_count; ++i) {
    const size_t at = h.section_table_offset + i * sizeof(rig::SectionEntry);
    if (read<rig::SectionEntry>(at).id == id) return at;
  }
  ADD_FAILURE() << "section " << id << " not in the blob";
  return 0;
}

void Blob::reseal() {
  const size_t crc_at = offsetof(rig::FileHeader, crc32c);
  write<uint32_t>(crc_at, 0);
  write(crc_at, rig::crc32c(0, data(), header().total_size));
}

Blob compile_sample() {
  std::vector<uint8_t> bytes;
  rigc::CompileReport report;
  std::string error;
  EXPECT_TRUE(rigc::compile_rig(sample_rig_spec(), &bytes, &report, &error)) << error;
  return Blob(bytes);
}

std::vector<Section> sections_of(const Blob& blob) {
  std::vector<Section> out;
  const rig::FileHeader h = blob.header();
  for (uint32_t i = 0; i < h.section_count; ++i) {
    const auto e = blob.read<rig::SectionEntry>(h.section_table_offset + i * sizeof(rig::SectionEntry));
    out.push_back({e.id, std::vector<uint8_t>(blob.data() + e.offset, blob.data() + e.offset + e.size)});
  }
  return out;
}

Blob assemble(rig::FileHeader header, const std::vector<Section>& sections) {
  auto align8 = [](size_t v) { return (v + 7) & ~size_t{7}; };
  const size_t table = sizeof(rig::FileHeader);
  std::vector<uint8_t> bytes(table + sections.size() * sizeof(rig::SectionEntry), 0);
  for (size_t i = 0; i < sections.size(); ++i) {
    const size_t at = align8(bytes.size()), padded = align8(sections[i].bytes.size());
    const rig::SectionEntry e{sections[i].id, static_cast<uint32_t>(at), static_cast<uint32_t>(padded), 0};
    std::memcpy(bytes.data() + table + i * sizeof(e), &e, sizeof(e));
    bytes.resize(at + padded, 0);
    std::copy(sections[i].bytes.begin(), sections[i].bytes.end(), bytes.begin() + static_cast<ptrdiff_t>(at));
  }
  header.section_count = static_cast<uint32_t>(sections.size());
  header.section_table_offset = static_cast<uint32_t>(table);
  header.total_size = static_cast<uint32_t>(bytes.size());
  std::memcpy(bytes.data(), &header, sizeof(header));
  Blob blob(bytes);
  blob.reseal();
  return blob;
}

}  // namespace sinew::test
