#include "firmware/daemon/config.hpp"

#include <gtest/gtest.h>
#include <sys/stat.h>

#include <cstdio>
#include <filesystem>

#include "firmware/daemon/sources.hpp"
#include "firmware/rig/loaded_rig.hpp"

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
  ASSERT_TRUE(parse_config(
      "[rig]\nbuiltin = \"hand\"\n[loop]\nrate_hz = 500\n[[source]]\ntype = \"trajectory\"\nperiod_ms = 4\n", "t.toml",
      &c, &error))
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
  EXPECT_NE(error_of("[rig]\nbuiltin = \"arm\"\n[loop]\nrate_hz = 0\n").find("test.toml:4: rate_hz"),
            std::string::npos);
  EXPECT_NE(error_of("[rig]\nbuiltin = \"arm\"\n[loop]\nmode = \"fast\"\n").find("[loop] mode"), std::string::npos);
  EXPECT_NE(error_of("[rig]\nbuiltin = \"arm\"\n[[source]]\nperiod_ms = 3\n").find("[[source]] type"),
            std::string::npos);
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

#if SINEW_SIMULATED_DEVICES
// A gpio source on the simulated rig's chip: encoders only, encoder-glitch
// faults only, and the wiring checked like a real chip's.
TEST(DaemonConfig, SimulatedGpioChipRejectsWhatItCannotSimulate) {
  sinew::firmware::LoadedRig rig;
  std::string error;
  ASSERT_TRUE(sinew::firmware::load_rig("arm", "", &rig, &error)) << error;
  const auto source_error = [&](const std::string& source) {
    DaemonConfig c;
    std::string e;
    EXPECT_TRUE(
        parse_config("[rig]\nbuiltin = \"arm\"\n[[source]]\ntype = \"gpio\"\nname = \"enc\"\n"
                     "chip = \"simulated-rig\"\n" +
                         source,
                     "t.toml", &c, &e))
        << e;
    EXPECT_EQ(sinew::firmware::open_source(c.sources[0], {c, rig, 0}, &e), nullptr) << source;
    return e;
  };
  const std::string encoder = "[[source.encoder]]\ninput = \"elbow.0\"\nline_a = 0\nline_b = 1\n";
  EXPECT_NE(source_error(encoder + "[[source.fault]]\nkind = \"drop\"\nfrom_s = 1\nto_s = 2\n")
                .find("source enc: fault.kind 'drop' does not apply to GPIO (encoder-glitch)"),
            std::string::npos);
  EXPECT_NE(source_error(encoder + "[[source.limit]]\ninput = \"elbow.0\"\nline = 5\n").find("drives encoders only"),
            std::string::npos);
  EXPECT_NE(source_error("lines = 8\n[[source.encoder]]\ninput = \"elbow.0\"\nline_a = 0\nline_b = 9\n")
                .find("line 9 is beyond the simulated chip's 8 lines"),
            std::string::npos);
  // Out-of-range timing is refused when the file is read, with its line.
  EXPECT_NE(error_of("[rig]\nbuiltin = \"arm\"\n[[source]]\ntype = \"gpio\"\nchip = \"simulated-rig\"\n"
                     "update_ms = 0.001\n")
                .find("test.toml:6: [[source]] update_ms: must be a number in [0.01, 1000]"),
            std::string::npos);

  DaemonConfig c;
  ASSERT_TRUE(
      parse_config("[rig]\nbuiltin = \"arm\"\n[[source]]\ntype = \"gpio\"\nname = \"enc\"\n"
                   "chip = \"simulated-rig\"\n" +
                       encoder,
                   "t.toml", &c, &error))
      << error;
  EXPECT_NE(sinew::firmware::open_source(c.sources[0], {c, rig, 0}, &error), nullptr) << error;
}
#else
// A production image carries no simulated devices: their source and chip are
// refused by name, not silently replaced.
TEST(DaemonConfig, SimulatedRigRefusedWithoutSimulatedDevices) {
  sinew::firmware::LoadedRig rig;
  std::string error;
  ASSERT_TRUE(sinew::firmware::load_rig("arm", "", &rig, &error)) << error;
  for (const std::string source :
       {"type = \"simulated-rig\"\nname = \"rig\"\n", "type = \"gpio\"\nname = \"rig\"\nchip = \"simulated-rig\"\n"}) {
    DaemonConfig c;
    ASSERT_TRUE(parse_config("[rig]\nbuiltin = \"arm\"\n[[source]]\n" + source, "t.toml", &c, &error)) << error;
    EXPECT_EQ(sinew::firmware::open_source(c.sources[0], {c, rig, 0}, &error), nullptr) << source;
    EXPECT_NE(error.find("built without simulated devices"), std::string::npos) << error;
  }
}
#endif

// [layers] switches compiled layers on and sets run-time options; the old
// build-at-start-up keys are refused with the way to the rig spec.
TEST(DaemonConfig, LayerSwitches) {
  DaemonConfig c;
  std::string error;
  ASSERT_TRUE(
      parse_config("[rig]\nbuiltin = \"arm\"\n[layers]\nsph = true\nanatomy = true\nskin_iterations = 8\n"
                   "tresca = false\n",
                   "t.toml", &c, &error))
      << error;
  using sinew::pipeline::Stage;
  EXPECT_TRUE(c.layers.stages.has(Stage::kSph));
  EXPECT_TRUE(c.layers.stages.has(Stage::kAnatomy));
  EXPECT_FALSE(c.layers.stages.has(Stage::kMetaballs));
  EXPECT_FALSE(c.layers.stages.has(Stage::kBarnet));
  EXPECT_FALSE(c.layers.sph.tresca);
  EXPECT_EQ(c.layers.anatomy.skin_iterations, 8u);
  const std::string old_key = error_of("[rig]\nbuiltin = \"arm\"\n[layers]\nsph_particles = 500\n");
  EXPECT_NE(old_key.find("test.toml:4: [layers] sph_particles: unknown key"), std::string::npos) << old_key;
  EXPECT_NE(old_key.find("compiled into the rig"), std::string::npos) << old_key;
  EXPECT_NE(error_of("[rig]\nbuiltin = \"arm\"\n[layers]\nskin_iterations = 300\n").find("skin_iterations"),
            std::string::npos);
  EXPECT_EQ(c.layers.anatomy.skin_max_anchor_acceleration, 500u);
  EXPECT_NE(error_of("[rig]\nbuiltin = \"arm\"\n[layers]\nskin_max_anchor_acceleration = 40000\n")
                .find("skin_max_anchor_acceleration"),
            std::string::npos);
  EXPECT_NE(error_of("[rig]\nbuiltin = \"arm\"\n[layers]\nanatomy = 1\n").find("must be true or false"),
            std::string::npos);
}

// A Modbus channel's enumerated keys accept only their documented values: a
// typo must not silently read an angle from the wrong table or word order.
TEST(DaemonConfig, ModbusChannelRejectsUnknownEnumValues) {
  sinew::firmware::LoadedRig rig;
  std::string error;
  ASSERT_TRUE(sinew::firmware::load_rig("arm", "", &rig, &error)) << error;
  const auto channel_error = [&](const std::string& key) {
    DaemonConfig c;
    std::string e;
    EXPECT_TRUE(
        parse_config("[rig]\nbuiltin = \"arm\"\n[[source]]\ntype = \"modbus\"\nname = \"mb\"\n"
                     "host = \"127.0.0.1\"\nport = 1502\n[[source.channel]]\ninput = \"elbow.0\"\n"
                     "address = 0\n" +
                         key,
                     "t.toml", &c, &e))
        << e;
    EXPECT_EQ(sinew::firmware::open_source(c.sources[0], {c, rig, 0}, &e), nullptr) << key;
    return e;
  };
  EXPECT_NE(channel_error("quantity = \"torque\"\n").find("channel.quantity 'torque' unknown"), std::string::npos);
  EXPECT_NE(channel_error("table = \"coil\"\n").find("channel.table 'coil' unknown"), std::string::npos);
  EXPECT_NE(channel_error("word_order = \"little\"\n").find("channel.word_order 'little' unknown"), std::string::npos);
  EXPECT_NE(channel_error("width = 24\n").find("channel.width must be 16 or 32"), std::string::npos);
}

// A misspelt key or a wrongly typed flag is an error naming it, not a
// silent default.
TEST(DaemonConfig, UnknownKeysAndNonBooleanFlagsAreRejected) {
  const std::string rig = "[rig]\nbuiltin = \"arm\"\n";
  EXPECT_NE(error_of(rig + "[layers]\nmetaball = true\n").find("test.toml:4: [layers] metaball: unknown key"),
            std::string::npos);
  EXPECT_NE(error_of(rig + "[loop]\nrate = 100\n").find("[loop] rate: unknown key"), std::string::npos);
  EXPECT_NE(error_of(rig + "[inputs]\ntimeout = 2\n").find("[inputs] timeout: unknown key"), std::string::npos);
  EXPECT_NE(error_of(rig + "[realtime]\nlock_memory = 1\n").find("test.toml:4: lock_memory: must be true or false"),
            std::string::npos);
  EXPECT_NE(error_of(rig + "[layers]\nmetaballs = \"yes\"\n").find("metaballs: must be true or false"),
            std::string::npos);
  EXPECT_NE(error_of(rig + "[sources]\ntype = \"can\"\n").find("sources: unknown table or key"), std::string::npos);
  EXPECT_NE(error_of("loop = 3\n" + rig).find("test.toml:1: [loop]: must be a table"), std::string::npos);
  EXPECT_NE(error_of(rig + "blobs = \"a.rig\"\n").find("[rig] blobs: unknown key (builtin, blob)"), std::string::npos);
}

// Every configuration the project ships parses.
// Every shipped configuration, and the config fuzzer's seeds (a seed the
// parser refuses would start the fuzzer from error paths only).
TEST(DaemonConfig, ShippedConfigurationsAndFuzzSeedsParse) {
  size_t parsed = 0;
  for (const char* dir : {SINEW_FIRMWARE_CONFIG_DIR, SINEW_CONFIG_SEED_DIR}) {
    for (const auto& entry : std::filesystem::directory_iterator(dir)) {
      if (entry.path().extension() != ".toml") continue;
      DaemonConfig c;
      std::string error;
      EXPECT_TRUE(sinew::firmware::load_config(entry.path().string(), &c, &error)) << entry.path() << ": " << error;
      ++parsed;
    }
  }
  EXPECT_GE(parsed, 3u);
}

// Every key of a [[source]], [[sink]] and their sub-tables is known for the
// type, of the right type and in range, and the error names file:line:key;
// before, a wrong type fell back to the default and an out-of-range integer
// was narrowed (port "15123" polled 502, unit_id 300 became 44).
TEST(DaemonConfig, SourceAndSinkKeysAreKnownTypedAndRangeChecked) {
  const std::string rig = "[rig]\nbuiltin = \"arm\"\n";
  const auto source = [&](const std::string& body) { return error_of(rig + "[[source]]\n" + body); };
  const auto sink = [&](const std::string& body) { return error_of(rig + "[[sink]]\n" + body); };
  const std::string modbus = "type = \"modbus\"\n";
  EXPECT_NE(
      source(modbus + "port = \"15123\"\n").find("test.toml:5: [[source]] port: must be an integer in [1, 65535]"),
      std::string::npos);
  EXPECT_NE(source(modbus + "unit_id = 300\n").find("test.toml:5: [[source]] unit_id: must be an integer in [0, 255]"),
            std::string::npos);
  EXPECT_NE(source(modbus + "device = \"/dev/ttyS0\"\nbaud = -5\n").find("test.toml:6: [[source]] baud"),
            std::string::npos);
  EXPECT_NE(source(modbus + "port = 1502.5\n").find("[[source]] port: must be an integer"), std::string::npos);
  EXPECT_NE(source(modbus + "perod_ms = 10\n").find("test.toml:5: [[source]] perod_ms: unknown key"),
            std::string::npos);
  EXPECT_NE(source(modbus + "period_ms = \"10\"\n").find("[[source]] period_ms: must be a number"), std::string::npos);
  EXPECT_NE(source(modbus + "[[source.channel]]\ninput = \"elbow.0\"\nadress = 3\n")
                .find("test.toml:7: [[source.channel]] adress: unknown key"),
            std::string::npos);
  EXPECT_NE(source("type = \"trajectory\"\nperiod_ms = 1e300\n").find("test.toml:5: [[source]] period_ms"),
            std::string::npos);
  EXPECT_NE(source("type = \"trajectory\"\nperiod_ms = nan\n").find("[[source]] period_ms"), std::string::npos);
  EXPECT_NE(source("type = \"can\"\nfd = 1\n").find("[[source]] fd: must be true or false"), std::string::npos);
  EXPECT_NE(source("type = \"simulated-rig\"\n[[source.fault]]\nkind = \"delay\"\nfrom_s = 1\nto_s = 2\n"
                   "delay_ms = -4\n")
                .find("test.toml:9: [[source.fault]] delay_ms: must be a number in [0, 60000]"),
            std::string::npos);
  EXPECT_NE(source("type = \"gpio\"\n[source.sync]\nline = 3\nlevel = 1\n").find("[source.sync] level: unknown key"),
            std::string::npos);
  EXPECT_NE(source("type = \"serial\"\n").find("test.toml:4: [[source]] type: unknown type 'serial'"),
            std::string::npos);
  EXPECT_NE(sink("type = \"log\"\npath = \"f.log\"\nsync_every_frames = -1\n").find("[[sink]] sync_every_frames"),
            std::string::npos);
  EXPECT_NE(error_of(rig + "[layers]\nsph_joint = \"both\"\n")
                .find("[layers] sph_joint: must be \"simulated\" or \"measured\""),
            std::string::npos);
  EXPECT_NE(sink("type = \"log\"\npath = \"f.log\"\ncompression = \"lz4\"\n")
                .find("[[sink]] compression: must be \"none\" or \"zstd\""),
            std::string::npos);
  EXPECT_NE(sink("type = \"log\"\npath = \"f.log\"\ncompression = \"zstd\"\ncompression_level = 20\n")
                .find("[[sink]] compression_level"),
            std::string::npos);
  EXPECT_NE(sink("type = \"log\"\npath = \"f.log\"\ncompression = \"zstd\"\nkey_every_frames = 0\n")
                .find("[[sink]] key_every_frames"),
            std::string::npos);
  EXPECT_NE(sink("type = \"udp\"\nport = 47800\nmax_datagram_bytes = -1\n").find("[[sink]] max_datagram_bytes"),
            std::string::npos);
  EXPECT_NE(sink("type = \"udp\"\nport = 47800\nnormal = true\n").find("[[sink]] normal: unknown key"),
            std::string::npos);
  EXPECT_NE(error_of(rig + "[loop]\nmode = 3\n").find("test.toml:4: [loop] mode: must be live, replay or offline"),
            std::string::npos);
}

// [loop] trigger is one of three names and its poll interval a number in
// range; a CAN source's sync_id an identifier: errors name file:line:key.
TEST(DaemonConfig, TriggerAndSyncIdAreTypedAndRangeChecked) {
  const std::string rig = "[rig]\nbuiltin = \"arm\"\n";
  const std::string must = "[loop] trigger: must be \"periodic\", \"inputs\" or \"sync\"";
  EXPECT_NE(error_of(rig + "[loop]\ntrigger = \"fast\"\n").find("test.toml:4: " + must), std::string::npos);
  EXPECT_NE(error_of(rig + "[loop]\nrate_hz = 500\ntrigger = 1\n").find("test.toml:5: " + must), std::string::npos);
  EXPECT_NE(error_of(rig + "[loop]\ntrigger = \"Inputs\"\n").find("test.toml:4: " + must), std::string::npos);
  EXPECT_NE(error_of(rig + "[loop]\ntrigger = [\"inputs\"]\n").find("test.toml:4: " + must), std::string::npos);
  EXPECT_NE(error_of(rig + "[loop]\ntrigger_poll_us = 0\n")
                .find("test.toml:4: trigger_poll_us: must be a number in [1, 1000]"),
            std::string::npos);
  EXPECT_NE(error_of(rig + "[loop]\ntrigger_poll_us = \"20\"\n").find("test.toml:4: trigger_poll_us"),
            std::string::npos);
  EXPECT_NE(error_of(rig + "[loop]\ntriger = \"inputs\"\n").find("test.toml:4: [loop] triger: unknown key"),
            std::string::npos);
  EXPECT_NE(error_of(rig + "[[source]]\ntype = \"can\"\nsync_id = -1\n")
                .find("test.toml:5: [[source]] sync_id: must be an integer in [0, 536870911]"),
            std::string::npos);
  EXPECT_NE(error_of(rig + "[[source]]\ntype = \"simulated-rig\"\nsync_id = \"0x80\"\n")
                .find("test.toml:5: [[source]] sync_id: must be an integer"),
            std::string::npos);
  EXPECT_NE(error_of(rig + "[[source]]\ntype = \"modbus\"\nsync_id = 128\n").find("[[source]] sync_id: unknown key"),
            std::string::npos);
  for (const auto& [name, trigger] : {std::pair{"periodic", sinew::firmware::TickTrigger::kPeriodic},
                                      std::pair{"inputs", sinew::firmware::TickTrigger::kInputs},
                                      std::pair{"sync", sinew::firmware::TickTrigger::kSync}}) {
    DaemonConfig c;
    std::string error;
    ASSERT_TRUE(parse_config(rig + "[loop]\ntrigger = \"" + name + "\"\ntrigger_poll_us = 50\n[[source]]\n" +
                                 "type = \"candump\"\npath = \"x.log\"\nsync_id = 0x080\n",
                             "t.toml", &c, &error))
        << error;
    EXPECT_EQ(c.trigger, trigger);
    EXPECT_DOUBLE_EQ(c.trigger_poll_us, 50.0);
  }
  DaemonConfig defaults;
  std::string error;
  ASSERT_TRUE(parse_config(rig, "t.toml", &defaults, &error)) << error;
  EXPECT_EQ(defaults.trigger, sinew::firmware::TickTrigger::kPeriodic);
}

// [loop] step_budget is a share of the period and over_budget one of three
// names; the defaults measure and warn, never change the rate.
TEST(DaemonConfig, StepBudgetAndOverBudgetAreTypedAndRangeChecked) {
  const std::string rig = "[rig]\nbuiltin = \"arm\"\n";
  const std::string must = "[loop] over_budget: must be \"warn\", \"slow\" or \"refuse\"";
  EXPECT_NE(error_of(rig + "[loop]\nover_budget = \"drop\"\n").find("test.toml:4: " + must), std::string::npos);
  EXPECT_NE(error_of(rig + "[loop]\nover_budget = true\n").find("test.toml:4: " + must), std::string::npos);
  EXPECT_NE(error_of(rig + "[loop]\nstep_budget = 1.5\n").find("test.toml:4: step_budget: must be a number in [0, 1]"),
            std::string::npos);
  EXPECT_NE(error_of(rig + "[loop]\nstep_budget = \"half\"\n").find("test.toml:4: step_budget"), std::string::npos);
  for (const auto& [name, over] :
       {std::pair{"warn", sinew::firmware::OverBudget::kWarn}, std::pair{"slow", sinew::firmware::OverBudget::kSlow},
        std::pair{"refuse", sinew::firmware::OverBudget::kRefuse}}) {
    DaemonConfig c;
    std::string error;
    ASSERT_TRUE(
        parse_config(rig + "[loop]\nstep_budget = 0.25\nover_budget = \"" + name + "\"\n", "t.toml", &c, &error))
        << error;
    EXPECT_EQ(c.over_budget, over);
    EXPECT_DOUBLE_EQ(c.step_budget, 0.25);
  }
  DaemonConfig defaults;
  std::string error;
  ASSERT_TRUE(parse_config(rig, "t.toml", &defaults, &error)) << error;
  EXPECT_EQ(defaults.over_budget, sinew::firmware::OverBudget::kWarn);
  EXPECT_DOUBLE_EQ(defaults.step_budget, 0.5);
}

// Sources and sinks are reported and their errors given by name: two with
// one name would be indistinguishable.
TEST(DaemonConfig, DuplicateSourceAndSinkNamesAreRefused) {
  const std::string rig = "[rig]\nbuiltin = \"arm\"\n";
  EXPECT_NE(error_of(rig + "[[source]]\ntype = \"trajectory\"\n[[source]]\ntype = \"trajectory\"\n")
                .find("test.toml:5: [[source]] name: 'trajectory' is used twice"),
            std::string::npos);
  EXPECT_NE(error_of(rig + "[[sink]]\ntype = \"udp\"\nname = \"out\"\nport = 1\n[[sink]]\ntype = \"log\"\n"
                           "name = \"out\"\npath = \"f.log\"\n")
                .find("[[sink]] name: 'out' is used twice"),
            std::string::npos);
}

TEST(DaemonConfig, ADirectoryIsNamedAsSuchNotAParseError) {
  DaemonConfig c;
  std::string error;
  EXPECT_FALSE(sinew::firmware::load_config(testing::TempDir(), &c, &error));
  EXPECT_NE(error.find("is a directory"), std::string::npos) << error;
}

// A candump log is read whole at start-up: a FIFO or a device would block
// it (or never end), so only regular files are accepted.
TEST(DaemonConfig, CandumpPathMustBeARegularFile) {
  sinew::firmware::LoadedRig rig;
  std::string error;
  ASSERT_TRUE(sinew::firmware::load_rig("arm", "", &rig, &error)) << error;
  const std::string fifo = testing::TempDir() + "/candump.fifo";
  std::remove(fifo.c_str());
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  for (const std::string& path : {std::string("/dev/null"), fifo}) {
    DaemonConfig c;
    std::string e;
    ASSERT_TRUE(parse_config(
        "[rig]\nbuiltin = \"arm\"\n[[source]]\ntype = \"candump\"\nname = \"log\"\npath = \"" + path + "\"\n", "t.toml",
        &c, &e))
        << e;
    EXPECT_EQ(sinew::firmware::open_source(c.sources[0], {c, rig, 0}, &e), nullptr) << path;
    EXPECT_NE(e.find("is not a regular file"), std::string::npos) << e;
  }
  std::remove(fifo.c_str());
}

// A polled I/O thread must come round at least twice per ring, or a full
// ring drops frames however fast the sink is: 128 frames at 1 kHz is
// 128 ms, so 64 000 us passes and 64 001 us does not.
TEST(DaemonConfig, IoPollMustDrainTwicePerRing) {
  const std::string rig = "[rig]\nbuiltin = \"arm\"\n[loop]\nrate_hz = 1000\n[realtime]\nsink_ring_frames = 128\n";
  DaemonConfig c;
  std::string error;
  ASSERT_TRUE(parse_config(rig + "io_poll_us = 64000\n", "test.toml", &c, &error)) << error;
  EXPECT_EQ(c.realtime.io_poll_us, 64000);
  EXPECT_NE(error_of(rig + "io_poll_us = 64001\n").find("io_poll_us = 64001 is more than half the ring's 128000 us"),
            std::string::npos);
  EXPECT_NE(error_of(rig + "io_poll_us = -1\n").find("io_poll_us"), std::string::npos);
  EXPECT_NE(error_of(rig + "io_poll_us = \"500\"\n").find("io_poll_us"), std::string::npos);
}
