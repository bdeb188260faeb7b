// The daemon's key registry (firmware/daemon/config_registry.hpp): its
// defaults are the parser's, the parser takes exactly its keys, the printed
// configurations parse back to themselves, and the shipped default.toml sets
// each key to its default unless its comment says otherwise.
#include "firmware/daemon/config_registry.hpp"

#include <gtest/gtest.h>

#include <fstream>
#include <sstream>

namespace config_registry_test {

using sinew::firmware::DaemonConfig;
using sinew::firmware::DaemonKey;
using sinew::firmware::parse_config;

const std::string kRig = "[rig]\nbuiltin = \"arm\"\n";

DaemonConfig parsed(const std::string& text) {
  DaemonConfig c;
  std::string error;
  EXPECT_TRUE(parse_config(text, "t.toml", &c, &error)) << error << "\n" << text;
  return c;
}

// Changing a default in DaemonConfig (or in the registry) alone fails this.
TEST(ConfigRegistry, EveryDefaultIsTheParsers) {
  const DaemonConfig defaults = parsed(kRig);
  for (const DaemonKey& k : sinew::firmware::daemon_keys()) {
    EXPECT_EQ(k.value(defaults), k.default_toml) << "[" << k.table << "] " << k.key;
    // The default is itself a value the parser takes, and reads back alike.
    const DaemonConfig set = parsed(kRig + "[" + std::string(k.table) + "]\n" + std::string(k.key) + " = " +
                                    std::string(k.default_toml) + "\n");
    EXPECT_EQ(k.value(set), k.default_toml) << "[" << k.table << "] " << k.key;
    EXPECT_FALSE(k.doc.empty()) << k.key;
  }
}

TEST(ConfigRegistry, TheParserTakesExactlyTheRegistrysKeys) {
  for (const char* table : {"loop", "realtime", "inputs", "status"}) {
    DaemonConfig c;
    std::string error;
    EXPECT_FALSE(parse_config(kRig + "[" + table + "]\nnot_a_key = 1\n", "t.toml", &c, &error)) << table;
    EXPECT_NE(error.find("not_a_key: unknown key"), std::string::npos) << error;
    for (const std::string_view key : sinew::firmware::daemon_keys_of(table))
      EXPECT_NE(error.find(std::string(key)), std::string::npos) << "the refusal lists " << key << ": " << error;
  }
}

std::string slurp(const std::string& path) {
  std::ifstream in(path);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

TEST(ConfigRegistry, PrintedConfigurationsParseBackToThemselves) {
  const std::string shipped = slurp(std::string(SINEW_FIRMWARE_CONFIG_DIR) + "/default.toml");
  ASSERT_FALSE(shipped.empty());
  const std::string resolved = sinew::firmware::resolved_config_text(parsed(shipped));
  EXPECT_EQ(sinew::firmware::resolved_config_text(parsed(resolved)), resolved);
  // --print-default-config is a configuration whose every key is the default.
  const DaemonConfig from_defaults = parsed(sinew::firmware::default_config_text());
  EXPECT_EQ(sinew::firmware::resolved_config_text(from_defaults), sinew::firmware::resolved_config_text(parsed(kRig)));
}

// default.toml documents every key: where it sets one to another value than
// the default (the main job's 5 s run, its layers, its rate policy), the
// line's comment says so.
TEST(ConfigRegistry, TheShippedConfigSaysWhereItLeavesADefault) {
  const std::string shipped = slurp(std::string(SINEW_FIRMWARE_CONFIG_DIR) + "/default.toml");
  std::istringstream lines(shipped);
  std::string table, line;
  size_t checked = 0;
  while (std::getline(lines, line)) {
    if (line.rfind("[", 0) == 0) {
      table = line.substr(1, line.find(']') - 1);
      continue;
    }
    for (const DaemonKey& k : sinew::firmware::daemon_keys()) {
      if (k.table != table || line.rfind(std::string(k.key) + " ", 0) != 0) continue;
      const size_t eq = line.find('=');
      const size_t hash = line.find('#');
      std::string value = line.substr(eq + 1, hash == std::string::npos ? std::string::npos : hash - eq - 1);
      value.erase(0, value.find_first_not_of(' '));
      value.erase(value.find_last_not_of(' ') + 1);
      ++checked;
      if (value != k.default_toml)
        EXPECT_NE(line.find("default"), std::string::npos)
            << "default.toml sets [" << table << "] " << k.key << " = " << value << ", not the default "
            << k.default_toml << ", without saying so";
    }
  }
  EXPECT_GE(checked, 15u);
}

}  // namespace config_registry_test
