// The daemon on rigs compiled from real glTF models with every layer kind
// (specs in tests/data, compiled here by rigc's library): offline at 100 Hz
// for 2 s, driven by the trajectory source, every layer on. Each run must
// finish without a layer error and print every stage's share of the tick.
#include <gtest/gtest.h>

#include <cstdio>
#include <fstream>
#include <string>
#include <vector>

#include "host_tools/layers/rig_layers.hpp"
#include "host_tools/rigc/toml_spec.hpp"
#include "tests/integration/daemon_harness.hpp"

namespace {

void run_model(const std::string& spec_name) {
  const std::string dir = testing::TempDir();
  sinew::rigc::RigSpec spec;
  sinew::layers::LayerSpecs layers;
  sinew::rigc::CompileReport core;
  std::vector<uint8_t> blob;
  std::vector<std::string> report;
  std::string error;
  ASSERT_TRUE(
      sinew::rigc::load_toml_rig(std::string(SINEW_SOURCE_DIR) + "/tests/data/" + spec_name, &spec, &layers, &error) &&
      sinew::layers::add_layer_dofs(&spec, layers, &report, &error) &&
      sinew::rigc::compile_rig(spec, &blob, &core, &error) &&
      sinew::layers::compile_layers(spec, layers, &blob, &report, &error))
      << spec_name << ": " << error;
  const std::string rig = dir + "/" + spec_name + ".rig", config = dir + "/" + spec_name + ".sinewd.toml";
  std::ofstream(rig, std::ios::binary)
      .write(reinterpret_cast<const char*>(blob.data()), static_cast<std::streamsize>(blob.size()));
  std::ofstream(config) << "[rig]\nblob = \"" << rig << "\"\n"
                        << "[loop]\nrate_hz = 100\nduration_s = 2.0\nstats_interval_s = 0\nmode = \"offline\"\n"
                        << "[layers]\nsph = true\nmetaballs = true\nbarnet = true\nanatomy = true\n"
                        << "[[source]]\ntype = \"trajectory\"\nname = \"sweep\"\nperiod_ms = 10\n";
  const sinew::test::DaemonRun daemon = sinew::test::run_sinewd(config, dir + "/" + spec_name + ".out");
  std::printf("%s", daemon.out.c_str());
  ASSERT_EQ(daemon.status, 0) << daemon.command << "\n" << daemon.out;
  EXPECT_NE(daemon.out.find("running: sph metaballs barnet anatomy"), std::string::npos) << daemon.out;
  EXPECT_NE(daemon.out.find("final tick 200"), std::string::npos) << daemon.out;
  for (const char* stage : {"skinning", "sph", "metaballs", "barnet", "anatomy"})
    EXPECT_NE(daemon.out.find(std::string(stage) + " "), std::string::npos) << stage;
  EXPECT_EQ(daemon.out.find("layer errors"), std::string::npos) << daemon.out;
}

}  // namespace

TEST(RealModelsEndToEnd, RiggedFigureWithEveryLayer) { run_model("rigged_figure_layers.toml"); }
TEST(RealModelsEndToEnd, GenericHandWithEveryLayer) { run_model("generic_hand_layers.toml"); }
// The same with the dynamic skin, its base acceleration swept by the
// trajectory source like every other input.
TEST(RealModelsEndToEnd, GenericHandWithTheDynamicSkin) { run_model("generic_hand_dynamic_layers.toml"); }
