#include <gtest/gtest.h>

#include "firmware/daemon/config.hpp"
#include "firmware/daemon/loaded_rig.hpp"

using sinew::firmware::DaemonConfig;
using sinew::firmware::parse_config;

namespace {
std::string error_of(const std::string& text) {
  DaemonConfig c;
  std::string error;
  EXPECT_FALSE(parse_config(text, "test.toml", &c, &error)) << text;
  return error;
}
}  // namespace

TEST(DaemonConfig, DefaultsAndValues) {
  DaemonConfig c;
  std::string error;
  ASSERT_TRUE(parse_config("[rig]\nbuiltin = \"hand\"\n[loop]\nrate_hz = 500\n[[source]]\ntype = \"trajectory\"\nperiod_ms = 4\n",
                           "t.toml", &c, &error))
      << error;
  EXPECT_EQ(c.rig_builtin, "hand");
  EXPECT_EQ(c.rate_hz, 500u);
  EXPECT_DOUBLE_EQ(c.timeout_factor, 1.5);
  ASSERT_EQ(c.sources.size(), 1u);
  EXPECT_EQ(c.sources[0].table["period_ms"].value_or(0.0), 4.0);
}

TEST(DaemonConfig, BadInputNamesFileLineAndKey) {
  EXPECT_NE(error_of("[rig]\nbuiltin = \"leg\"\n").find("test.toml:2: [rig] builtin"), std::string::npos);
  EXPECT_NE(error_of("[loop]\n").find("[rig] needs exactly one"), std::string::npos);
  EXPECT_NE(error_of("[rig]\nbuiltin = \"arm\"\n[loop]\nrate_hz = 0\n").find("test.toml:4: rate_hz"), std::string::npos);
  EXPECT_NE(error_of("[rig]\nbuiltin = \"arm\"\n[loop]\nmode = \"fast\"\n").find("[loop] mode"), std::string::npos);
  EXPECT_NE(error_of("[rig]\nbuiltin = \"arm\"\n[[source]]\nperiod_ms = 3\n").find("[[source]] type"), std::string::npos);
  EXPECT_NE(error_of("[rig\n").find("test.toml:1"), std::string::npos);
}

TEST(DaemonConfig, CorruptRigBlobIsRejectedWithTheLoaderMessage) {
  const std::string path = testing::TempDir() + "/corrupt.rig";
  FILE* f = std::fopen(path.c_str(), "wb");
  ASSERT_NE(f, nullptr);
  const char junk[100] = "SNRG not really a rig";
  std::fwrite(junk, 1, sizeof(junk), f);
  std::fclose(f);
  sinew::firmware::LoadedRig rig;
  std::string error;
  EXPECT_FALSE(sinew::firmware::load_rig("", path, &rig, &error));
  EXPECT_NE(error.find("corrupt.rig: rig blob: header"), std::string::npos) << error;
}
