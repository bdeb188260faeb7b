// libFuzzer target: any bytes as a sinewd config, taken as far as sinewd
// takes it before its loop: parsed, its layers and input limits applied to
// the built-in rig it names (arm unless it names the hand), every source and
// sink it lists constructed (the simulated devices included), then a few
// offline ticks run and the outputs flushed.
//
// What is stubbed, so that millions of runs touch nothing of the machine:
// - socket() and getaddrinfo() fail (EACCES, EAI_FAIL): SocketCAN, Modbus
//   TCP, the simulated rig's Modbus device and the UDP sink take their "no
//   network" paths; no name is resolved and no datagram leaves.
// - libgpiod finds no chip: a GPIO source on a kernel chip takes its "no such
//   chip" path (chip = "simulated-rig" runs for real).
// - Files: a config whose strings contain '/' (or are "..") is skipped, and
//   the file names it gives (a candump source's path, a CAN source's record,
//   a Modbus RTU device, a log sink's path, a CAN sink's candump log; a CAN
//   sink without one gets one, so it runs on its simulated twin) are taken
//   inside a fresh
//   temporary directory, emptied after every input: logs, recordings and
//   replays are created and read there only. It holds one candump log,
//   "replay.candump", for candump sources to read. (The process keeps its
//   working directory: libFuzzer's corpus paths may be relative.)
// - [rig] blob is not read: the built-in rig runs instead.
#include <dirent.h>
#include <netdb.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cerrno>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <string_view>
#include <vector>

#include "firmware/daemon/config.hpp"
#include "firmware/daemon/run_setup.hpp"
#include "firmware/daemon/sinks.hpp"
#include "firmware/daemon/sources.hpp"
#include "firmware/rig/loaded_rig.hpp"
#include "firmware/runtime/runtime.hpp"

extern "C" {
// These replace libc's (and libmodbus's calls into it) in this executable.
int socket(int, int, int) {
  errno = EACCES;
  return -1;
}
int getaddrinfo(const char*, const char*, const struct addrinfo*, struct addrinfo** res) {
  if (res != nullptr) *res = nullptr;
  return EAI_FAIL;
}
struct gpiod_chip;
gpiod_chip* gpiod_chip_open_lookup(const char*) {
  errno = ENOENT;
  return nullptr;
}
}

namespace {

constexpr const char* kReplayLog = "replay.candump";
std::string g_dir;  // the temporary directory, made once
// Frames of the default joint stream (ids 0x100..) and others, a bad line too.
constexpr std::string_view kReplayText =
    "(0.001000) can0 100#0000000000000000\n"
    "(0.002000) can0 101#00112233445566F0\n"
    "(0.003000) can0 102##1000102030405060708090A0B0C0D0E0F\n"
    "(0.004000) can0 18FF0001#0102\n"
    "(0.005000) can0 100#R\n"
    "not a frame\n";

void write_replay_log() {
  std::FILE* f = std::fopen((g_dir + "/" + kReplayLog).c_str(), "wb");
  if (f == nullptr || std::fwrite(kReplayText.data(), 1, kReplayText.size(), f) != kReplayText.size()) __builtin_trap();
  std::fclose(f);
}

// Removes everything an input left in the directory (files only: no code
// path makes directories), then puts the replay log back.
void reset_directory() {
  DIR* d = opendir(g_dir.c_str());
  if (d == nullptr) __builtin_trap();
  std::vector<std::string> names;
  while (const dirent* e = readdir(d)) {
    const std::string name = e->d_name;
    if (name != "." && name != "..") names.push_back(name);
  }
  closedir(d);
  for (const std::string& name : names)
    if (unlink((g_dir + "/" + name).c_str()) != 0) __builtin_trap();
  write_replay_log();
}

// True when no string value in the node could name a file outside the directory.
bool local_strings(const toml::node& node) {
  if (const auto* s = node.as_string()) {
    const std::string& v = s->get();
    return v.find('/') == std::string::npos && v != "..";
  }
  if (const auto* t = node.as_table()) {
    for (const auto& [key, value] : *t)
      if (!local_strings(value)) return false;
  }
  if (const auto* a = node.as_array()) {
    for (const toml::node& value : *a)
      if (!local_strings(value)) return false;
  }
  return true;
}

// Takes the file names a table gives inside the directory.
void localize(toml::table* table) {
  for (const char* key : {"path", "record", "device", "candump"})
    if (const auto name = (*table)[key].value<std::string>()) table->insert_or_assign(key, g_dir + "/" + *name);
}

// A CAN sink always writes its candump twin inside the directory: a fuzzed
// configuration never puts frames on a machine's CAN interface.
void keep_off_the_bus(sinew::firmware::SinkConfig* sink) {
  if (sink->type == "can" && !sink->table.contains("candump")) sink->table.insert_or_assign("candump", "sink.candump");
}

const sinew::firmware::LoadedRig& builtin_rig(const std::string& name) {
  static const auto load = [](const char* which) {
    auto* rig = new sinew::firmware::LoadedRig;
    std::string error;
    if (!sinew::firmware::load_rig(which, "", rig, &error)) __builtin_trap();
    return rig;
  };
  static const sinew::firmware::LoadedRig* arm = load("arm");
  static const sinew::firmware::LoadedRig* hand = load("hand");
  return name == "hand" ? *hand : *arm;
}

void run(const sinew::firmware::DaemonConfig& config) {
  using namespace sinew::firmware;
  const LoadedRig& rig = builtin_rig(config.rig_builtin);
  std::string error;
  sinew::pipeline::PipelineOptions options;
  if (!layer_options(config, rig, &options, &error)) return;
  const uint64_t period = 1000000000u / config.rate_hz;
  const std::vector<InputLimits> limits = input_limits(rig, config, period);
  Runtime runtime;
  if (!runtime.init(rig.rig, rig.layers, options, limits, 0, &error)) return;
  if (!add_sources(config, rig, 0, &runtime, &error) || !add_sinks(config, rig, &runtime, &error)) {
    if (error.empty()) __builtin_trap();
    return;
  }
  for (uint64_t tick = 0; tick < 3; ++tick) runtime.step((tick + 1) * period, tick);
  runtime.flush();
}

// At a normal exit: the directory goes too.
void remove_directory() {
  reset_directory();
  unlink((g_dir + "/" + kReplayLog).c_str());
  rmdir(g_dir.c_str());
}

}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  const char* tmp = std::getenv("TMPDIR");
  g_dir = std::string(tmp != nullptr && *tmp != '\0' ? tmp : "/tmp") + "/sinew-daemon-fuzz-XXXXXX";
  if (mkdtemp(g_dir.data()) == nullptr) __builtin_trap();
  write_replay_log();
  std::atexit(remove_directory);
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  sinew::firmware::DaemonConfig config;
  std::string error;
  if (!sinew::firmware::parse_config(text, "fuzz.toml", &config, &error)) {
    if (error.empty()) __builtin_trap();
    return 0;
  }
  if (config.rig_blob.find('/') != std::string::npos) return 0;
  for (auto& s : config.sources) {
    if (!local_strings(s.table)) return 0;
    localize(&s.table);
  }
  for (auto& s : config.sinks) {
    if (!local_strings(s.table)) return 0;
    keep_off_the_bus(&s);
    localize(&s.table);
  }
  run(config);
  reset_directory();
  return 0;
}
