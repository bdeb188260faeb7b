#include "bus_sources.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>

#include "hal/can/can_input_source.hpp"
#include "hal/can/candump_replay_source.hpp"
#include "hal/can/joint_stream_decoder.hpp"
#include "hal/can/recording_frame_source.hpp"
#include "hal/can/socketcan_source.hpp"
#include "hal/gpio/gpio_source.hpp"
#include "hal/modbus/modbus_source.hpp"
#if SINEW_SIMULATED_DEVICES
#include "hal/can/sim/simulated_rig_bus.hpp"
#include "hal/gpio/sim/simulated_encoders.hpp"
#include "hal/modbus/sim/modbus_feeder.hpp"
#include "hal/units/float_to_fixed.hpp"
#endif

namespace sinew::firmware {

namespace {

using hal::can::FrameSource;

// Frames decoded per tick at most: with up to 32 samples per frame this stays
// within the runtime's per-tick sample buffer.
constexpr size_t kFramesPerTick = 128;

std::string where(const SourceConfig& s, const std::string& key) { return "source " + s.name + ": " + key; }

bool read_ms(const SourceConfig& s, const char* key, double fallback, double lo, double hi, uint64_t* ns,
             std::string* error) {
  const double ms = s.table[key].value_or(fallback);
  if (!(ms >= lo && ms <= hi))
    return *error = where(s, key) + " must be in [" + std::to_string(lo) + ", " + std::to_string(hi) + "] ms", false;
  *ns = static_cast<uint64_t>(std::llround(ms * 1e6));
  return true;
}

// Per-input kind: true for a joint's rotation DOF (the simulated rig's
// Modbus layout sends those in hundredths of a degree).
std::vector<bool> rig_rotation(const LoadedRig& rig) {
  std::vector<bool> rotation(rig.input_count(), false);
  for (const rig::JointRecord& j : rig.rig.joints)
    for (uint32_t d = 0; d < j.dof_count; ++d)
      rotation[j.first_input + d] = j.dof_kind == static_cast<uint8_t>(rig::DofKind::kRotation);
  return rotation;
}

#if SINEW_SIMULATED_DEVICES
// Per-input range and kind from the rig and its external inputs (the
// simulator's motion and layout): the simulated rig swings an external force
// across its range like a joint.
void rig_inputs(const LoadedRig& rig, std::vector<hal::sim::InputRange>* ranges, std::vector<bool>* rotation) {
  ranges->assign(rig.input_count(), {});
  *rotation = rig_rotation(rig);
  for (const rig::JointRecord& j : rig.rig.joints)
    for (uint32_t d = 0; d < j.dof_count; ++d) (*ranges)[j.first_input + d] = {j.dof_min[d], j.dof_max[d]};
  for (size_t k = 0; k < rig.external.size(); ++k)
    (*ranges)[rig.rig.input_count + k] = {rig.external[k].min, rig.external[k].max};
}

bool read_faults(const SourceConfig& s, const LoadedRig& rig, hal::sim::FaultPlan* plan, std::string* error) {
  const toml::array* faults = s.table["fault"].as_array();
  if (faults == nullptr) return true;
  for (const toml::node& node : *faults) {
    const toml::table* t = node.as_table();
    if (t == nullptr) return *error = where(s, "fault") + " entries must be tables", false;
    hal::sim::Fault f;
    const std::string kind = (*t)["kind"].value_or<std::string>("");
    if (!hal::sim::parse_fault_kind(kind, &f.kind))
      return *error = where(s, "fault.kind") + " '" + kind +
                      "' unknown (drop, delay, duplicate, corrupt, stuck-counter, out-of-range, bus-off, "
                      "modbus-timeout, modbus-exception, encoder-glitch)",
             false;
    const double from = (*t)["from_s"].value_or(-1.0), to = (*t)["to_s"].value_or(-1.0);
    if (!(from >= 0 && to > from && to < 1e6)) return *error = where(s, "fault") + " needs 0 <= from_s < to_s", false;
    f.from_ns = static_cast<uint64_t>(std::llround(from * 1e9));
    f.to_ns = static_cast<uint64_t>(std::llround(to * 1e9));
    f.amount = static_cast<uint64_t>(std::llround((*t)["delay_ms"].value_or(0.0) * 1e6));
    if (const auto name = (*t)["input"].value<std::string>()) {
      const auto it = std::find(rig.input_names.begin(), rig.input_names.end(), *name);
      if (it == rig.input_names.end())
        return *error = where(s, "fault.input") + " '" + *name + "' is no rig input", false;
      f.input = static_cast<int32_t>(it - rig.input_names.begin());
    }
    plan->faults.push_back(f);
  }
  return true;
}
#endif  // SINEW_SIMULATED_DEVICES

std::unique_ptr<hal::InputSource> can_source(const SourceConfig& s, const LoadedRig& rig, const DaemonConfig& config,
                                             std::unique_ptr<FrameSource> frames, uint64_t start_ns,
                                             std::string* error) {
  uint64_t period = 0;
  if (!read_ms(s, "period_ms", config.default_period_ms, 0.01, 60000, &period, error)) return nullptr;
  hal::can::JointStreamConfig stream =
      hal::can::default_joint_stream_config(rig.input_count(), s.table["fd"].value_or(false), period);
  auto decoder = std::make_unique<hal::can::JointStreamDecoder>();
  if (!decoder->configure(stream, error)) return *error = where(s, "protocol") + ": " + *error, nullptr;
  if (const auto path = s.table["record"].value<std::string>()) {
    auto recording = hal::can::RecordingFrameSource::create(
        std::move(frames), *path, s.table["interface"].value_or<std::string>("can0"), start_ns, error);
    if (!recording) return *error = where(s, "record") + ": " + *error, nullptr;
    frames = std::move(recording);
  }
  // sync_id: the frame that closes each cycle (`[loop] trigger = "sync"`);
  // identifiers above 11 bits are extended.
  hal::can::SyncFrameOptions sync;
  if (const auto id = s.table["sync_id"].value<int64_t>()) {
    if (*id < 0 || *id > hal::can::kExtendedIdMask)
      return *error = where(s, "sync_id") + " must be 0..0x1FFFFFFF", nullptr;
    sync.enabled = true;
    sync.id = {static_cast<uint32_t>(*id), *id > hal::can::kStandardIdMask};
  }
  auto source = hal::can::CanInputSource::create(s.name, std::move(frames), std::move(decoder), kFramesPerTick,
                                                 start_ns, error, sync);
  if (!source) *error = "source " + s.name + ": " + *error;
  return source;
}

#if SINEW_SIMULATED_DEVICES
// A source that also keeps a helper alive (the simulated Modbus device).
class KeepAlive final : public hal::InputSource {
 public:
  KeepAlive(std::unique_ptr<hal::InputSource> inner, std::shared_ptr<void> extra)
      : inner_(std::move(inner)), extra_(std::move(extra)) {}
  const char* name() const override { return inner_->name(); }
  size_t latch(uint64_t until_ns, std::span<hal::JointSample> out, hal::InputHealth& health) override {
    return inner_->latch(until_ns, out, health);
  }
  hal::SourceState state() const override { return inner_->state(); }
  std::string status_line() const override { return inner_->status_line(); }
  uint8_t arrival_signals() const override { return inner_->arrival_signals(); }
  hal::Arrival arrival(uint64_t now_ns) override { return inner_->arrival(now_ns); }

 private:
  std::unique_ptr<hal::InputSource> inner_;
  std::shared_ptr<void> extra_;
};

std::unique_ptr<hal::InputSource> simulated_rig(const SourceConfig& s, const LoadedRig& rig, const DaemonConfig& config,
                                                uint64_t start_ns, std::string* error) {
  hal::sim::SimulatedRigOptions options;
  if (!read_ms(s, "period_ms", config.default_period_ms, 0.01, 60000, &options.period_ns, error) ||
      !read_ms(s, "offset_ms", options.period_ns / 2e6, 0, 60000, &options.offset_ns, error) ||
      !read_faults(s, rig, &options.faults, error))
    return nullptr;
  options.period_ns = options.period_ns / 1000 * 1000;
  options.offset_ns = options.offset_ns / 1000 * 1000;
  if (const auto id = s.table["sync_id"].value<int64_t>()) {  // the simulated rig sends it, the receiver watches it
    options.send_sync = true;
    options.sync_id = static_cast<uint32_t>(*id);
  }
  std::vector<hal::sim::InputRange> ranges;
  std::vector<bool> rotation;
  rig_inputs(rig, &ranges, &rotation);
  if (!hal::sim::SimulatedRigBus::validate(options, ranges.size(), error)) return nullptr;
  const hal::sim::FaultPlan faults = options.faults;
  auto bus = std::make_unique<hal::sim::SimulatedRigBus>(hal::sim::RigMotion(ranges), std::move(options), start_ns);
  auto source = can_source(s, rig, config, std::move(bus), start_ns, error);
  if (!source) return nullptr;
  const int64_t port = s.table["modbus_port"].value_or(int64_t{-1});
  if (port < 0) return source;
  if (port > 65535) return *error = where(s, "modbus_port") + " must be 0..65535", nullptr;
  auto feeder = std::make_shared<hal::sim::ModbusFeeder>();
  // The device measures when asked, on its own clock (not the ticks).
  if (!feeder->start(hal::sim::RigMotion(ranges), rotation, faults, start_ns, static_cast<uint16_t>(port), error))
    return *error = "source " + s.name + ": " + *error, nullptr;
  return std::make_unique<KeepAlive>(std::move(source), std::move(feeder));
}
#endif  // SINEW_SIMULATED_DEVICES

std::unique_ptr<hal::InputSource> candump(const SourceConfig& s, const LoadedRig& rig, const DaemonConfig& config,
                                          uint64_t start_ns, std::string* error) {
  hal::can::CandumpReplayOptions options;
  const auto path = s.table["path"].value<std::string>();
  if (!path) return *error = where(s, "path") + " is required", nullptr;
  // A FIFO or a device would block the start-up read (or never end): a log is a file.
  std::error_code ec;
  const auto status = std::filesystem::status(*path, ec);
  if (!ec && !std::filesystem::is_regular_file(status))
    return *error = where(s, "path") + " '" + *path + "' is not a regular file", nullptr;
  options.path = *path;
  options.interface = s.table["interface"].value_or<std::string>("");
  if (const auto origin = s.table["origin_s"].value<double>()) {
    if (!(*origin >= 0 && *origin < 1e10)) return *error = where(s, "origin_s") + " must be >= 0", nullptr;
    options.has_origin = true;
    options.origin_ns = static_cast<uint64_t>(std::llround(*origin * 1e9));
  }
  auto replay = std::make_unique<hal::can::CandumpReplaySource>();
  if (!replay->load(options, start_ns, error)) return *error = "source " + s.name + ": " + *error, nullptr;
  if (!replay->parse_errors().empty())
    std::printf("source %s: %zu unreadable lines in %s (first at line %zu: %s)\n", s.name.c_str(),
                replay->parse_errors().size(), options.path.c_str(), replay->parse_errors()[0].line,
                replay->parse_errors()[0].message.c_str());
  return can_source(s, rig, config, std::move(replay), start_ns, error);
}

std::unique_ptr<hal::InputSource> socketcan(const SourceConfig& s, const LoadedRig& rig, const DaemonConfig& config,
                                            uint64_t start_ns, std::string* error) {
  hal::can::SocketCanOptions options;
  options.interface = s.table["interface"].value_or<std::string>("can0");
  options.fd = s.table["fd"].value_or(false);
  auto socket = std::make_unique<hal::can::SocketCanSource>(options);
  std::string open_error;
  // A missing interface is not fatal: the source reports down and reopens with back-off.
  if (!socket->open(start_ns, &open_error))
    std::printf("source %s: %s (retrying with back-off)\n", s.name.c_str(), open_error.c_str());
  return can_source(s, rig, config, std::move(socket), start_ns, error);
}

std::unique_ptr<hal::InputSource> modbus(const SourceConfig& s, const LoadedRig& rig, std::string* error) {
  hal::modbus::PollerConfig c;
  c.name = s.name;
  c.link.tcp.host = s.table["host"].value_or<std::string>("127.0.0.1");
  const int64_t port = s.table["port"].value_or(int64_t{502});
  if (port <= 0 || port > 65535) return *error = where(s, "port") + " must be 1..65535", nullptr;
  c.link.tcp.port = static_cast<uint16_t>(port);
  if (const auto device = s.table["device"].value<std::string>()) {
    c.link.transport = hal::modbus::Transport::kRtu;
    c.link.rtu.device = *device;
    c.link.rtu.baud = static_cast<uint32_t>(s.table["baud"].value_or(int64_t{19200}));
  }
  c.link.unit_id = static_cast<uint8_t>(s.table["unit_id"].value_or(int64_t{1}) & 0xFF);
  if (!read_ms(s, "period_ms", 10, 0, 60000, &c.period_ns, error) ||
      !read_ms(s, "timeout_ms", 100, 1, 10000, &c.response_timeout_ns, error) ||
      !read_ms(s, "backoff_ms", 50, 1, 60000, &c.backoff_initial_ns, error) ||
      !read_ms(s, "backoff_max_ms", 2000, 1, 600000, &c.backoff_max_ns, error))
    return nullptr;
  const std::string layout = s.table["layout"].value_or<std::string>("");
  if (layout == "simulated-rig") {
    // The simulated rig's device: input i at holding 2i..2i+1, 0.01 degree or 1 um.
    // A register map only: it reads any device laid out so, simulated or not.
    const std::vector<bool> rotation = rig_rotation(rig);
    for (size_t i = 0; i < rotation.size(); ++i) {
      hal::modbus::ChannelConfig ch;
      ch.name = rig.input_names[i];
      ch.input = static_cast<uint16_t>(i);
      ch.address = static_cast<uint16_t>(2 * i);
      ch.width = hal::modbus::RegisterWidth::k32;
      ch.scale = rotation[i] ? 0.01 : 1e-6;
      ch.quantity = rotation[i] ? hal::modbus::Quantity::kAngle : hal::modbus::Quantity::kTranslation;
      ch.min = rotation[i] ? -180.0 : -2000.0;
      ch.max = rotation[i] ? 180.0 : 2000.0;
      if (i >= rig.rig.input_count && rig.external[i - rig.rig.input_count].force) {
        // The feeder writes a non-angle as millionths of a Q12.20 unit: for a
        // Q16.16 force one register unit is 2^20 / 10^6 / 2^16 = 16 uN.
        ch.scale = 16e-6;
        ch.quantity = hal::modbus::Quantity::kForce;
        ch.min = -30000.0;
        ch.max = 30000.0;
      }
      c.channels.push_back(ch);
    }
  } else if (!layout.empty()) {
    return *error = where(s, "layout") + " '" + layout + "' unknown (simulated-rig, or [[source.channel]] tables)",
           nullptr;
  }
  if (const toml::array* channels = s.table["channel"].as_array()) {
    for (const toml::node& node : *channels) {
      const toml::table* t = node.as_table();
      if (t == nullptr) return *error = where(s, "channel") + " entries must be tables", nullptr;
      hal::modbus::ChannelConfig ch;
      const std::string input = (*t)["input"].value_or<std::string>("");
      ch.name = input;
      const auto it = std::find(rig.input_names.begin(), rig.input_names.end(), input);
      if (it == rig.input_names.end())
        return *error = where(s, "channel.input") + " '" + input + "' is no rig input", nullptr;
      ch.input = static_cast<uint16_t>(it - rig.input_names.begin());
      const std::string table = (*t)["table"].value_or<std::string>("holding");
      if (table != "holding" && table != "input")
        return *error = where(s, "channel.table") + " '" + table + "' unknown (holding, input)", nullptr;
      ch.table = table == "input" ? hal::modbus::RegisterTable::kInput : hal::modbus::RegisterTable::kHolding;
      const int64_t address = (*t)["address"].value_or(int64_t{-1});
      if (address < 0 || address > 65535) return *error = where(s, "channel.address") + " must be 0..65535", nullptr;
      ch.address = static_cast<uint16_t>(address);
      const int64_t width = (*t)["width"].value_or(int64_t{16});
      if (width != 16 && width != 32) return *error = where(s, "channel.width") + " must be 16 or 32", nullptr;
      ch.width = width == 32 ? hal::modbus::RegisterWidth::k32 : hal::modbus::RegisterWidth::k16;
      const std::string order = (*t)["word_order"].value_or<std::string>("high-first");
      if (order != "high-first" && order != "low-first")
        return *error = where(s, "channel.word_order") + " '" + order + "' unknown (high-first, low-first)", nullptr;
      ch.word_order =
          order == "low-first" ? hal::modbus::WordOrder::kLowWordFirst : hal::modbus::WordOrder::kHighWordFirst;
      ch.is_signed = (*t)["signed"].value_or(true);
      ch.scale = (*t)["scale"].value_or(1.0);
      ch.offset = (*t)["offset"].value_or(0.0);
      const std::string quantity = (*t)["quantity"].value_or<std::string>("angle");
      if (quantity != "angle" && quantity != "translation" && quantity != "force")
        return *error = where(s, "channel.quantity") + " '" + quantity + "' unknown (angle, translation, force)",
               nullptr;
      ch.quantity = quantity == "force"         ? hal::modbus::Quantity::kForce
                    : quantity == "translation" ? hal::modbus::Quantity::kTranslation
                                                : hal::modbus::Quantity::kAngle;
      ch.min = (*t)["min"].value_or(-180.0);
      ch.max = (*t)["max"].value_or(180.0);
      c.channels.push_back(ch);
    }
  }
  auto source = hal::modbus::ModbusSource::create(std::move(c), error);
  if (!source) *error = "source " + s.name + ": " + *error;
  return source;
}

#if SINEW_SIMULATED_DEVICES
// A GPIO source on the simulated rig's chip: each latch first plays the
// encoders' motion up to the tick onto the lines, then reads them as the
// real chip would be read.
class SimulatedGpioRig final : public hal::InputSource {
 public:
  SimulatedGpioRig(std::unique_ptr<hal::sim::SimulatedEncoders> rig, std::unique_ptr<hal::gpio::GpioSource> source)
      : rig_(std::move(rig)), source_(std::move(source)) {}
  const char* name() const override { return source_->name(); }
  size_t latch(uint64_t until_ns, std::span<hal::JointSample> out, hal::InputHealth& health) override {
    rig_->advance(until_ns);
    return source_->latch(until_ns, out, health);
  }
  hal::SourceState state() const override { return source_->state(); }
  std::string status_line() const override {
    return source_->status_line() + ", glitches injected " + std::to_string(rig_->glitches());
  }

 private:
  std::unique_ptr<hal::sim::SimulatedEncoders> rig_;  // the wire outlives the source's chip
  std::unique_ptr<hal::gpio::GpioSource> source_;
};

std::unique_ptr<hal::InputSource> simulated_gpio(const SourceConfig& s, const LoadedRig& rig,
                                                 hal::gpio::GpioSourceConfig c, uint64_t start_ns, std::string* error) {
  hal::sim::SimulatedEncoderOptions options;
  if (!read_ms(s, "update_ms", 1.0, 0.01, 1000, &options.update_ns, error) ||
      !read_faults(s, rig, &options.faults, error))
    return nullptr;
  for (const hal::sim::Fault& f : options.faults.faults)
    if (f.kind != hal::sim::FaultKind::kEncoderGlitch)
      return *error = where(s, "fault.kind") + " '" + hal::sim::fault_kind_name(f.kind) +
                      "' does not apply to GPIO (encoder-glitch)",
             nullptr;
  if (!c.limits.empty() || c.sync.line != hal::gpio::kNoLine)
    return *error = where(s, "chip") + " \"simulated-rig\" drives encoders only (no limit or sync lines)", nullptr;
  const int64_t lines = s.table["lines"].value_or(int64_t{64});
  if (lines < 1 || lines > 65536) return *error = where(s, "lines") + " must be 1..65536", nullptr;
  std::vector<hal::sim::InputRange> ranges;
  std::vector<bool> rotation;
  rig_inputs(rig, &ranges, &rotation);
  hal::sim::RigMotion motion(ranges);
  const auto line_count = static_cast<uint32_t>(lines);
  if (!hal::sim::SimulatedEncoders::validate(c.encoders, options, motion, rotation, line_count, error))
    return *error = "source " + s.name + ": " + *error, nullptr;
  auto encoders = std::make_unique<hal::sim::SimulatedEncoders>(std::move(motion), c.encoders, std::move(options),
                                                                line_count, start_ns);
  auto source = hal::gpio::GpioSource::create(std::move(c), encoders->wire().chip(), error);
  if (!source) return *error = "source " + s.name + ": " + *error, nullptr;
  return std::make_unique<SimulatedGpioRig>(std::move(encoders), std::move(source));
}
#else
// Why a simulated-rig source or chip is refused in a build without them.
std::string no_simulated_devices(const SourceConfig& s, const std::string& what) {
  return "source " + s.name + ": " + what +
         " is unavailable: built without simulated devices (SINEW_SIMULATED_DEVICES=OFF)";
}
#endif  // SINEW_SIMULATED_DEVICES

std::unique_ptr<hal::InputSource> gpio(const SourceConfig& s, const LoadedRig& rig, uint64_t start_ns,
                                       std::string* error) {
  hal::gpio::GpioSourceConfig c;
  c.name = s.name;
  c.chip = s.table["chip"].value_or<std::string>("gpiochip0");
  c.consumer = s.table["consumer"].value_or<std::string>("sinew");
  c.event_capacity = static_cast<uint32_t>(s.table["event_capacity"].value_or(int64_t{1024}) & 0xFFFFFFFF);
  const auto line = [](const toml::table& t, const char* key, int64_t fallback) {
    const int64_t v = t[key].value_or(fallback);
    return v < -1 || v > 65535 ? int64_t{-2} : v;  // -2: out of range, caught by validate()
  };
  if (const toml::array* encoders = s.table["encoder"].as_array()) {
    for (const toml::node& node : *encoders) {
      const toml::table* t = node.as_table();
      if (t == nullptr) return *error = where(s, "encoder") + " entries must be tables", nullptr;
      hal::gpio::EncoderConfig e;
      if (!read_input(s, *t, rig, "encoder", &e.input, error)) return nullptr;
      const int64_t a = line(*t, "line_a", -1), b = line(*t, "line_b", -1);
      if (a < 0 || b < 0) return *error = where(s, "encoder") + " needs line_a and line_b (0..65535)", nullptr;
      e.line_a = static_cast<uint32_t>(a);
      e.line_b = static_cast<uint32_t>(b);
      e.line_index = static_cast<int32_t>(line(*t, "line_index", -1));
      e.active_low = (*t)["active_low"].value_or(false);
      const int64_t cpt = (*t)["counts_per_turn"].value_or(int64_t{4096});
      if (cpt < 1 || cpt > (int64_t{1} << 30))
        return *error = where(s, "encoder.counts_per_turn") + " must be 1..2^30", nullptr;
      e.counts_per_turn = static_cast<uint32_t>(cpt);
      const double offset_deg = (*t)["offset_deg"].value_or(0.0);
      if (!(offset_deg >= -360 && offset_deg <= 360))
        return *error = where(s, "encoder.offset_deg") + " must be -360..360", nullptr;
      e.offset = static_cast<int32_t>(units::angle_from_degrees(offset_deg).value);  // binary angle, signed view
      e.invert = (*t)["invert"].value_or(false);
      const double window_us = (*t)["window_us"].value_or(0.0);
      if (!(window_us >= 0 && window_us <= 1000))
        return *error = where(s, "encoder.window_us") + " must be 0..1000", nullptr;
      e.window_ns = static_cast<uint64_t>(std::llround(window_us * 1000));
      e.index_count = (*t)["index_count"].value_or(int64_t{0});
      e.home_every_index = (*t)["home_every_index"].value_or(false);
      c.encoders.push_back(e);
    }
  }
  if (const toml::array* limits = s.table["limit"].as_array()) {
    for (const toml::node& node : *limits) {
      const toml::table* t = node.as_table();
      if (t == nullptr) return *error = where(s, "limit") + " entries must be tables", nullptr;
      hal::gpio::LimitSwitchConfig l;
      if (!read_input(s, *t, rig, "limit", &l.input, error)) return nullptr;
      const int64_t ln = line(*t, "line", -1);
      if (ln < 0) return *error = where(s, "limit.line") + " is required (0..65535)", nullptr;
      l.line = static_cast<uint32_t>(ln);
      l.active_low = (*t)["active_low"].value_or(true);
      const std::string side = (*t)["side"].value_or<std::string>("min");
      if (side != "min" && side != "max") return *error = where(s, "limit.side") + " must be min or max", nullptr;
      l.side = side == "min" ? hal::gpio::LimitSide::kMin : hal::gpio::LimitSide::kMax;
      const double debounce_ms = (*t)["debounce_ms"].value_or(5.0);
      if (!(debounce_ms >= 0 && debounce_ms <= 1000))
        return *error = where(s, "limit.debounce_ms") + " must be 0..1000", nullptr;
      l.debounce_ns = static_cast<uint64_t>(std::llround(debounce_ms * 1e6));
      c.limits.push_back(l);
    }
  }
  if (const toml::table* sync = s.table["sync"].as_table()) {
    c.sync.line = static_cast<int32_t>(line(*sync, "line", -1));
    c.sync.active_low = (*sync)["active_low"].value_or(false);
  }
  if (const toml::table* fault = s.table["fault_line"].as_table()) {
    c.fault.line = static_cast<int32_t>(line(*fault, "line", -1));
    c.fault.active_low = (*fault)["active_low"].value_or(false);
  }
  // The simulated rig's encoders instead of a kernel chip (CI, demos).
  if (c.chip == "simulated-rig") {
#if SINEW_SIMULATED_DEVICES
    return simulated_gpio(s, rig, std::move(c), start_ns, error);
#else
    (void)start_ns;
    return *error = no_simulated_devices(s, "chip \"simulated-rig\""), nullptr;
#endif
  }
  auto source = hal::gpio::GpioSource::create(std::move(c), error);
  if (!source) *error = "source " + s.name + ": " + *error;
  return source;
}

}  // namespace

// A rig input named "<joint>.<dof>" or given by index.
bool read_input(const SourceConfig& s, const toml::table& t, const LoadedRig& rig, const char* what, uint16_t* input,
                std::string* error) {
  if (const auto name = t["input"].value<std::string>()) {
    const auto it = std::find(rig.input_names.begin(), rig.input_names.end(), *name);
    if (it == rig.input_names.end())
      return *error = where(s, std::string(what) + ".input") + " '" + *name + "' is no rig input", false;
    *input = static_cast<uint16_t>(it - rig.input_names.begin());
    return true;
  }
  const int64_t index = t["input"].value_or(int64_t{-1});
  if (index < 0 || index >= static_cast<int64_t>(rig.input_count()))
    return *error = where(s, std::string(what) + ".input") + " must name a rig input", false;
  *input = static_cast<uint16_t>(index);
  return true;
}

std::unique_ptr<hal::InputSource> open_can_source(const SourceConfig& s, const SourceSetup& setup, std::string* error) {
  return socketcan(s, setup.rig, setup.config, setup.start_ns, error);
}

std::unique_ptr<hal::InputSource> open_candump_source(const SourceConfig& s, const SourceSetup& setup,
                                                      std::string* error) {
  return candump(s, setup.rig, setup.config, setup.start_ns, error);
}

std::unique_ptr<hal::InputSource> open_simulated_rig_source(const SourceConfig& s, const SourceSetup& setup,
                                                            std::string* error) {
#if SINEW_SIMULATED_DEVICES
  return simulated_rig(s, setup.rig, setup.config, setup.start_ns, error);
#else
  (void)setup;
  return *error = no_simulated_devices(s, "type 'simulated-rig'"), nullptr;
#endif
}

std::unique_ptr<hal::InputSource> open_modbus_source(const SourceConfig& s, const SourceSetup& setup,
                                                     std::string* error) {
  return modbus(s, setup.rig, error);
}

std::unique_ptr<hal::InputSource> open_gpio_source(const SourceConfig& s, const SourceSetup& setup,
                                                   std::string* error) {
  return gpio(s, setup.rig, setup.start_ns, error);
}

}  // namespace sinew::firmware
