// rigsim: the simulated rig as its own process. Plays a motion (the built-in
// swing, CSV joint tracks in degrees, or a BVH take mapped onto the rig's
// joints) at the rig's send rate, as a real rig would: default joint-stream frames on a SocketCAN interface (vcan0 or
// real), written to a candump log, and joint registers on a libmodbus TCP
// server on loopback; with the same fault injection as the daemon's
// simulated-rig source.
//   rigsim --rig arm --can vcan0 --modbus-port 1502 --duration 10 \
//          --fault corrupt:1.0:1.5 --fault drop:2:3:elbow.0
//   rigsim --spec my_arm.toml --motion take.bvh --candump take.log
#include <linux/can.h>
#include <linux/can/raw.h>
#include <net/if.h>
#include <sys/ioctl.h>
#include <sys/socket.h>
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <ctime>

#include "firmware/rig/loaded_rig.hpp"
#include "hal/can/candump_writer.hpp"
#include "hal/can/sim/simulated_rig_bus.hpp"
#include "hal/common/monotonic_clock.hpp"
#include "hal/modbus/sim/modbus_feeder.hpp"
#include "hal/units/float_to_fixed.hpp"
#include "host_tools/layers/rig_layers.hpp"
#include "host_tools/motion/bvh_drive.hpp"
#include "host_tools/motion/csv_tracks.hpp"
#include "host_tools/rigc/motion_tracks.hpp"
#include "host_tools/rigc/quantize.hpp"
#include "host_tools/rigc/toml_motion.hpp"
#include "host_tools/rigc/toml_spec.hpp"

namespace {

volatile std::sig_atomic_t g_stop = 0;
void on_signal(int) { g_stop = 1; }

int open_can(const std::string& interface, std::string* error) {
  const int fd = socket(PF_CAN, SOCK_RAW, CAN_RAW);
  if (fd < 0) return *error = std::string("socket(PF_CAN): ") + std::strerror(errno), -1;
  ifreq ifr{};
  std::snprintf(ifr.ifr_name, sizeof ifr.ifr_name, "%s", interface.c_str());
  if (ioctl(fd, SIOCGIFINDEX, &ifr) < 0) {
    *error = interface + ": " + std::strerror(errno);
    close(fd);
    return -1;
  }
  sockaddr_can addr{};
  addr.can_family = AF_CAN;
  addr.can_ifindex = ifr.ifr_ifindex;
  if (bind(fd, reinterpret_cast<sockaddr*>(&addr), sizeof addr) < 0) {
    *error = interface + ": bind: " + std::strerror(errno);
    close(fd);
    return -1;
  }
  return fd;
}

bool parse_fault(const std::string& text, const sinew::firmware::LoadedRig& rig, sinew::hal::sim::Fault* f,
                 std::string* error) {
  // kind:from_s:to_s[:input[:delay_ms]]
  std::vector<std::string> parts;
  size_t start = 0;
  for (size_t at; (at = text.find(':', start)) != std::string::npos; start = at + 1)
    parts.push_back(text.substr(start, at - start));
  parts.push_back(text.substr(start));
  if (parts.size() < 3 || !sinew::hal::sim::parse_fault_kind(parts[0], &f->kind))
    return *error = "--fault " + text + ": expected kind:from_s:to_s[:input[:delay_ms]]", false;
  if (f->kind == sinew::hal::sim::FaultKind::kEncoderGlitch)
    return *error = "--fault " + text +
                    ": encoder glitches need the simulated GPIO chip, which lives inside sinewd "
                    "(a gpio source with chip = \"simulated-rig\")",
           false;
  char* end = nullptr;
  const double from = std::strtod(parts[1].c_str(), &end), to = std::strtod(parts[2].c_str(), &end);
  if (!(from >= 0 && to > from)) return *error = "--fault " + text + ": needs 0 <= from < to", false;
  f->from_ns = static_cast<uint64_t>(from * 1e9);
  f->to_ns = static_cast<uint64_t>(to * 1e9);
  if (parts.size() > 3 && !parts[3].empty()) {
    const auto it = std::find(rig.input_names.begin(), rig.input_names.end(), parts[3]);
    if (it == rig.input_names.end()) return *error = "--fault " + text + ": no rig input " + parts[3], false;
    f->input = static_cast<int32_t>(it - rig.input_names.begin());
  }
  if (parts.size() > 4) f->amount = static_cast<uint64_t>(std::strtod(parts[4].c_str(), &end) * 1e6);
  return true;
}

// Compiles a rig spec as rigc does and loads it as the daemon loads a blob;
// also returns the spec's [motion.bvh_joints] table.
bool load_spec_rig(const std::string& path, sinew::firmware::LoadedRig* rig,
                   std::vector<sinew::motion::BvhJointName>* bvh_joints, std::string* error) {
  using namespace sinew;
  rigc::RigSpec spec;
  layers::LayerSpecs layer_specs;
  std::vector<std::string> report;
  std::vector<uint8_t> bytes;
  rigc::CompileReport compiled;
  if (!rigc::load_toml_rig(path, &spec, &layer_specs, error) || !rigc::load_toml_motion(path, spec, bvh_joints, error))
    return false;
  if (!layers::add_layer_dofs(&spec, layer_specs, &report, error) ||
      !rigc::compile_rig(spec, &bytes, &compiled, error) ||
      !layers::compile_layers(spec, layer_specs, &bytes, &report, error))
    return *error = path + ": " + *error, false;
  return firmware::load_rig_bytes(hal::blob_from_bytes(bytes.data(), bytes.size()), path, rig, error);
}

// The loaded rig's joints as the BVH mapping sees them: names from the input
// names ("<joint>.<dof>"), DOF axes from the joint records (Q2.30).
std::vector<sinew::motion::RigJointDofs> loaded_joint_dofs(const sinew::firmware::LoadedRig& rig) {
  using namespace sinew;
  std::vector<motion::RigJointDofs> out;
  for (const rig::JointRecord& j : rig.rig.joints) {
    if (j.dof_count == 0) continue;  // nothing to drive
    motion::RigJointDofs r;
    const std::string& first = rig.input_names[j.first_input];
    r.name = first.substr(0, first.rfind('.'));
    r.rotation = j.dof_kind == static_cast<uint8_t>(rig::DofKind::kRotation);
    for (uint32_t d = 0; d < j.dof_count; ++d)
      r.axes.push_back({std::ldexp(j.dof_axis[d][0], -fx::kUnitFracBits),
                        std::ldexp(j.dof_axis[d][1], -fx::kUnitFracBits),
                        std::ldexp(j.dof_axis[d][2], -fx::kUnitFracBits)});
    out.push_back(r);
  }
  return out;
}

}  // namespace

int main(int argc, char** argv) {
  using namespace sinew;
  CLI::App app{"rigsim: the simulated rig (CAN joint stream, Modbus registers, faults)"};
  std::string rig_name = "arm", spec_path, can_interface, candump_path, csv_path;
  std::vector<std::string> fault_texts;
  double period_ms = 10.0, duration_s = 10.0;
  int modbus_port = -1;
  auto* rig_opt = app.add_option("--rig", rig_name, "built-in rig: arm or hand");
  app.add_option("--spec", spec_path,
                 "rig spec (TOML) compiled as rigc does, instead of --rig; its [motion.bvh_joints] maps BVH joints")
      ->excludes(rig_opt);
  app.add_option("--motion", csv_path,
                 "BVH take (.bvh: joints by the rig's names or the spec's [motion.bvh_joints]) or CSV joint tracks "
                 "(time, <joint>.<dof> columns in degrees); default: the swing");
  app.add_option("--period-ms", period_ms, "send period per input")->check(CLI::Range(0.1, 10000.0));
  app.add_option("--duration", duration_s, "seconds; 0 = until Ctrl-C")->check(CLI::Range(0.0, 1e6));
  app.add_option("--can", can_interface, "send on this SocketCAN interface (e.g. vcan0)");
  app.add_option("--candump", candump_path, "also log every frame sent (candump -L format)");
  app.add_option("--modbus-port", modbus_port, "serve the joint registers on 127.0.0.1:PORT")
      ->check(CLI::Range(0, 65535));
  app.add_option("--fault", fault_texts, "kind:from_s:to_s[:input[:delay_ms]] (kinds as in the daemon config)");
  CLI11_PARSE(app, argc, argv);

  firmware::LoadedRig rig;
  std::string error;
  std::vector<motion::BvhJointName> bvh_joints;
  if (!(spec_path.empty() ? firmware::load_rig(rig_name, "", &rig, &error)
                          : load_spec_rig(spec_path, &rig, &bvh_joints, &error)))
    return std::fprintf(stderr, "rigsim: %s\n", error.c_str()), 2;
  if (!spec_path.empty()) rig_name = spec_path;
  std::vector<hal::sim::InputRange> ranges(rig.rig.input_count);
  std::vector<bool> rotation(rig.rig.input_count, true);
  for (const rig::JointRecord& j : rig.rig.joints)
    for (uint32_t d = 0; d < j.dof_count; ++d) {
      ranges[j.first_input + d] = {j.dof_min[d], j.dof_max[d]};
      rotation[j.first_input + d] = j.dof_kind == static_cast<uint8_t>(rig::DofKind::kRotation);
    }
  hal::sim::RigMotion motion(ranges);
  if (!csv_path.empty()) {
    motion::JointTracks tracks;
    // A BVH take gives a track for every DOF (unmapped joints at rest, 0) at
    // every frame; the motion below interpolates them at each send time.
    const bool bvh = rigc::is_bvh_path(csv_path);
    if (bvh) {
      motion::Bvh take;
      if (!motion::load_bvh(csv_path, &take, &error)) return std::fprintf(stderr, "rigsim: %s\n", error.c_str()), 2;
      if (!motion::bvh_to_joint_tracks(take, loaded_joint_dofs(rig), bvh_joints, &tracks, &error))
        return std::fprintf(stderr, "rigsim: %s: %s\n", csv_path.c_str(), error.c_str()), 2;
    } else if (!motion::load_csv_tracks(csv_path, &tracks, &error)) {
      return std::fprintf(stderr, "rigsim: %s\n", error.c_str()), 2;
    }
    std::vector<bool> has(ranges.size(), false);
    std::vector<int> column(ranges.size(), -1);
    for (size_t i = 0; i < ranges.size(); ++i) {
      const std::string& name = rig.input_names[i];
      const size_t dot = name.rfind('.');
      if (const auto c = tracks.find(name.substr(0, dot), name.substr(dot + 1)))
        column[i] = static_cast<int>(*c), has[i] = true;
    }
    std::vector<uint64_t> times;
    std::vector<int32_t> values;
    for (size_t k = 0; k < tracks.times.size(); ++k) {
      times.push_back(static_cast<uint64_t>(std::llround(std::max(0.0, tracks.times[k]) * 1e9)));
      for (size_t i = 0; i < ranges.size(); ++i) {
        const double deg = column[i] < 0 ? 0 : tracks.values[k * tracks.tracks.size() + static_cast<size_t>(column[i])];
        if (bvh && !rotation[i]) {  // BVH positions are in model units
          values.push_back(rigc::to_len(deg, rig.rig.length_exponent));
          continue;
        }
        values.push_back(static_cast<int32_t>(units::angle_from_degrees(deg).value));  // binary angle, signed view
      }
    }
    motion = hal::sim::RigMotion::keyframed(ranges, std::move(times), std::move(values), std::move(has));
  }
  hal::sim::SimulatedRigOptions options;
  options.period_ns = static_cast<uint64_t>(period_ms * 1000) * 1000;
  options.offset_ns = 0;
  for (const std::string& t : fault_texts) {
    hal::sim::Fault f;
    if (!parse_fault(t, rig, &f, &error)) return std::fprintf(stderr, "rigsim: %s\n", error.c_str()), 2;
    options.faults.faults.push_back(f);
  }
  if (!hal::sim::SimulatedRigBus::validate(options, ranges.size(), &error))
    return std::fprintf(stderr, "rigsim: %s\n", error.c_str()), 2;
  const uint64_t start = hal::monotonic_ns();
  hal::sim::ModbusFeeder feeder;
  if (modbus_port >= 0 &&
      !feeder.start(motion, rotation, options.faults, start, static_cast<uint16_t>(modbus_port), &error))
    return std::fprintf(stderr, "rigsim: %s\n", error.c_str()), 2;
  const hal::sim::FaultPlan faults = options.faults;
  hal::sim::SimulatedRigBus bus(motion, options, start);
  int can_fd = -1;
  if (!can_interface.empty() && (can_fd = open_can(can_interface, &error)) < 0)
    return std::fprintf(stderr, "rigsim: %s\n", error.c_str()), 2;
  hal::can::CandumpWriter log;
  if (!candump_path.empty() && !log.open(candump_path, &error))
    return std::fprintf(stderr, "rigsim: %s\n", error.c_str()), 2;
  std::signal(SIGINT, on_signal);
  std::signal(SIGTERM, on_signal);
  std::printf("rigsim: rig %s, %u inputs every %.1f ms%s%s%s\n", rig_name.c_str(), rig.rig.input_count, period_ms,
              can_interface.empty() ? "" : (", CAN " + can_interface).c_str(),
              modbus_port >= 0 ? (", Modbus 127.0.0.1:" + std::to_string(feeder.port())).c_str() : "",
              candump_path.empty() ? "" : (", log " + candump_path).c_str());
  std::fflush(stdout);
  std::vector<hal::can::CanFrame> frames(4096);
  uint64_t sent = 0, send_errors = 0;
  for (uint64_t next = start; !g_stop && (duration_s <= 0 || next < start + static_cast<uint64_t>(duration_s * 1e9));
       next += options.period_ns) {
    const timespec ts{static_cast<time_t>(next / 1000000000u), static_cast<long>(next % 1000000000u)};
    clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &ts, nullptr);
    const size_t n = bus.drain(frames, next);
    for (size_t i = 0; i < n; ++i) {
      const hal::can::CanFrame& f = frames[i];
      if (f.kind == hal::can::FrameKind::kError) continue;  // a real controller reports its own state
      if (!candump_path.empty()) log.write(f, can_interface.empty() ? "can0" : can_interface);
      if (can_fd >= 0) {
        can_frame cf{};
        cf.can_id = f.id | (f.extended ? CAN_EFF_FLAG : 0u);
        cf.len = f.len;
        std::memcpy(cf.data, f.data.data(), f.len);
        if (write(can_fd, &cf, sizeof cf) != static_cast<ssize_t>(sizeof cf)) ++send_errors;
      }
      ++sent;
    }
  }
  log.flush();
  if (can_fd >= 0) close(can_fd);
  std::printf("rigsim: %llu frames sent, %llu send errors, %zu faults planned, %llu Modbus requests served\n",
              static_cast<unsigned long long>(sent), static_cast<unsigned long long>(send_errors), faults.faults.size(),
              static_cast<unsigned long long>(feeder.requests()));
  return 0;
}
