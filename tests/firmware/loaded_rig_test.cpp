// The daemon's rig loading: every rig input gets a name and limits (even one
// no joint uses), and a file is judged by its header before it is read whole.
#include "firmware/rig/loaded_rig.hpp"

#include <gtest/gtest.h>

#include <cstring>
#include <fstream>

#include "firmware/builtin/builtin_rigs.hpp"
#include "firmware/daemon/config.hpp"
#include "firmware/daemon/run_setup.hpp"
#include "firmware/runtime/runtime.hpp"
#include "host_tools/rigc/builtin_rigs.hpp"
#include "sim_core/rig/crc32c.hpp"

namespace fw = sinew::firmware;
namespace rg = sinew::rig;

namespace {

std::vector<uint8_t> hand_blob_bytes() {
  const std::span<const uint8_t> blob = fw::builtin_rig_blob("hand");
  return {blob.begin(), blob.end()};
}

void rewrite_crc(std::vector<uint8_t>* bytes) {
  constexpr size_t kCrc = offsetof(rg::FileHeader, crc32c);
  std::memset(bytes->data() + kCrc, 0, 4);
  const uint32_t crc = rg::crc32c(0, bytes->data(), bytes->size());
  std::memcpy(bytes->data() + kCrc, &crc, 4);
}

std::string write_file(const std::string& name, const std::vector<uint8_t>& bytes) {
  const std::string path = testing::TempDir() + "/" + name;
  std::ofstream(path, std::ios::binary)
      .write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
  return path;
}

}  // namespace

// The format lets an input drive no joint. The daemon once named only the
// inputs joints use, then refused to start with "one input limit per rig
// input ... is required", naming neither the file nor the input.
TEST(LoadedRig, AnInputNoJointUsesIsNamedLimitedAndRuns) {
  // The hand without layers (a layer section records the rig's input count).
  std::vector<uint8_t> bytes;
  sinew::rigc::CompileReport report;
  std::string error;
  ASSERT_TRUE(sinew::rigc::compile_rig(sinew::rigc::builtin_hand(), &bytes, &report, &error)) << error;
  rg::FileHeader h;
  std::memcpy(&h, bytes.data(), sizeof(h));
  const uint32_t unused = h.input_count;
  h.input_count += 1;
  std::memcpy(bytes.data(), &h, sizeof(h));
  rewrite_crc(&bytes);

  fw::LoadedRig rig;
  ASSERT_TRUE(fw::load_rig_bytes(sinew::hal::blob_from_bytes(bytes.data(), bytes.size()), "hand+1", &rig, &error))
      << error;
  ASSERT_EQ(rig.rig.input_count, unused + 1);
  EXPECT_EQ(rig.input_names[unused], "input" + std::to_string(unused));
  ASSERT_EQ(rig.unused_inputs, std::vector<uint32_t>{unused});

  fw::DaemonConfig config;
  const std::vector<fw::InputLimits> limits = fw::input_limits(rig, config, 10'000'000);
  ASSERT_EQ(limits.size(), rig.input_count());
  fw::Runtime runtime;
  sinew::pipeline::PipelineOptions options;
  ASSERT_TRUE(runtime.init(rig.rig, rig.layers, options, limits, 0, &error)) << error;
  const sinew::hal::PoseFrame& frame = runtime.step(10'000'000, 0);
  EXPECT_EQ(frame.input_count, rig.input_count());
}

// A large file that is not a rig once was read whole (1 GB: 9.5 s, 2.1 GB of
// memory) before "not a sinew rig blob". Now the header is read first.
TEST(LoadedRig, AFileIsJudgedByItsHeaderBeforeItIsReadWhole) {
  std::vector<uint8_t> junk(1 << 20, 0x5A);
  const std::string path = write_file("junk.rig", junk);
  fw::LoadedRig rig;
  std::string error;
  EXPECT_FALSE(fw::load_rig("", path, &rig, &error));
  EXPECT_NE(error.find(path), std::string::npos) << error;
  EXPECT_NE(error.find("not a sinew rig blob"), std::string::npos) << error;

  // A valid blob with bytes after its declared end: not a file rigc wrote.
  std::vector<uint8_t> padded = hand_blob_bytes();
  padded.resize(padded.size() + 8, 0);
  EXPECT_FALSE(fw::load_rig("", write_file("padded.rig", padded), &rig, &error));
  EXPECT_NE(error.find("total_size"), std::string::npos) << error;

  // Shorter than its header says.
  std::vector<uint8_t> cut = hand_blob_bytes();
  cut.resize(cut.size() / 2);
  EXPECT_FALSE(fw::load_rig("", write_file("cut.rig", cut), &rig, &error));
  EXPECT_NE(error.find("shorter than its declared size"), std::string::npos) << error;

  // Shorter than a header.
  EXPECT_FALSE(fw::load_rig("", write_file("tiny.rig", std::vector<uint8_t>(10, 0)), &rig, &error));
  EXPECT_NE(error.find("64-byte header"), std::string::npos) << error;

  // And the untouched blob as a file loads.
  EXPECT_TRUE(fw::load_rig("", write_file("hand.rig", hand_blob_bytes()), &rig, &error)) << error;
}
