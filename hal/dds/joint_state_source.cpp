#include "joint_state_source.hpp"

#include <dds/dds.h>

#include <cstdio>
#include <cstring>

#include "dds_entity.hpp"
#include "hal/common/monotonic_clock.hpp"
#include "qos.hpp"
#include "ros2_names.hpp"
#include "sensor_msgs/msg/JointState.h"

namespace sinew::hal::dds {

namespace {

// How long the reader thread waits for data before it looks at its stop
// flag and the matched publishers again.
constexpr dds_duration_t kWaitTimeout = DDS_MSECS(50);
// Samples taken per call (loaned from the reader's cache).
constexpr size_t kTakeBatch = 16;
// Joints one source reads: a sample's values are checked on the stack first.
constexpr size_t kMaxJoints = 256;

}  // namespace

struct JointStateSource::Dds {
  DdsEntity participant, topic, reader, waitset, readable;
};

JointStateSource::JointStateSource(JointStateSourceOptions options)
    : options_(std::move(options)),
      dds_(std::make_unique<Dds>()),
      current_{std::vector<int32_t>(options_.joints.size(), 0), std::vector<uint64_t>(options_.joints.size(), 0),
               std::vector<uint64_t>(options_.joints.size(), 0), 0},
      exchange_(current_),
      latched_(options_.joints.size(), 0) {}

std::unique_ptr<JointStateSource> JointStateSource::create(JointStateSourceOptions options, std::string* error) {
  if (options.joints.empty()) return *error = "no joints to read", nullptr;
  if (options.joints.size() > kMaxJoints)
    return *error = std::to_string(options.joints.size()) + " joints: at most " + std::to_string(kMaxJoints), nullptr;
  if (options.domain_id > kMaxDomainId)
    return *error = "domain_id " + std::to_string(options.domain_id) + " is beyond 232", nullptr;
  std::unique_ptr<JointStateSource> s(new JointStateSource(std::move(options)));
  const JointStateSourceOptions& o = s->options_;
  if (!ros2_topic_name(o.ros_namespace, o.topic, &s->dds_topic_, error)) return nullptr;
  Dds& d = *s->dds_;
  d.participant = DdsEntity(dds_create_participant(o.domain_id, nullptr, nullptr));
  if (!d.participant.valid())
    return *error =
               "DDS participant on domain " + std::to_string(o.domain_id) + ": " + dds_error_text(d.participant.get()),
           nullptr;
  d.topic = DdsEntity(dds_create_topic(d.participant.get(), &sensor_msgs_msg_dds__JointState__desc,
                                       s->dds_topic_.c_str(), nullptr, nullptr));
  if (!d.topic.valid()) return *error = "DDS topic " + s->dds_topic_ + ": " + dds_error_text(d.topic.get()), nullptr;
  dds_qos_t* qos = joint_state_qos(o.depth);
  d.reader = DdsEntity(dds_create_reader(d.participant.get(), d.topic.get(), qos, nullptr));
  dds_delete_qos(qos);
  if (!d.reader.valid())
    return *error = "DDS reader on " + s->dds_topic_ + ": " + dds_error_text(d.reader.get()), nullptr;
  d.waitset = DdsEntity(dds_create_waitset(d.participant.get()));
  d.readable = DdsEntity(dds_create_readcondition(d.reader.get(), DDS_ANY_STATE));
  if (!d.waitset.valid() || !d.readable.valid() ||
      dds_waitset_attach(d.waitset.get(), d.readable.get(), d.readable.get()) != DDS_RETCODE_OK)
    return *error = "DDS waitset on " + s->dds_topic_, nullptr;
  s->thread_ = std::thread([raw = s.get()] { raw->run(); });
  return s;
}

JointStateSource::~JointStateSource() {
  stop_.store(true);
  if (thread_.joinable()) thread_.join();
}

void JointStateSource::run() {
  void* samples[kTakeBatch] = {};
  dds_sample_info_t infos[kTakeBatch];
  while (!stop_.load(std::memory_order_relaxed)) {
    dds_waitset_wait(dds_->waitset.get(), nullptr, 0, kWaitTimeout);
    dds_subscription_matched_status_t matched{};
    if (dds_get_subscription_matched_status(dds_->reader.get(), &matched) == DDS_RETCODE_OK)
      publishers_.store(matched.current_count, std::memory_order_relaxed);
    bool took = false;
    for (;;) {
      samples[0] = nullptr;  // loaned buffers
      const dds_return_t n = dds_take(dds_->reader.get(), samples, infos, kTakeBatch, kTakeBatch);
      if (n <= 0) break;
      const uint64_t now = monotonic_ns();
      for (dds_return_t i = 0; i < n; ++i)
        if (infos[i].valid_data) take(samples[i], now), took = true;
      dds_return_loan(dds_->reader.get(), samples, n);
      if (static_cast<size_t>(n) < kTakeBatch) break;
    }
    if (!took) continue;
    // Sizes match, so the copy reuses back()'s storage: no allocation.
    Latest& back = exchange_.back();
    back.value = current_.value;
    back.taken_ns = current_.taken_ns;
    back.accepted = current_.accepted;
    back.rejected = current_.rejected;
    exchange_.publish();
  }
}

void JointStateSource::take(const void* data, uint64_t now_ns) {
  const auto& msg = *static_cast<const sensor_msgs_msg_dds__JointState_*>(data);
  samples_.fetch_add(1, std::memory_order_relaxed);
  const uint32_t n = msg.name._length;
  const auto fits = [n](const dds_sequence_double& a) { return a._length == 0 || a._length == n; };
  if (msg.position._length != n || !fits(msg.velocity) || !fits(msg.effort)) {
    rejected_lengths_.fetch_add(1, std::memory_order_relaxed);
    ++current_.rejected;
    return;
  }
  // Every joint first, then commit: a sample is taken whole or not at all.
  int32_t values[kMaxJoints];
  const size_t joints = options_.joints.size();
  for (size_t j = 0; j < joints; ++j) {
    const JointStateSourceOptions::Joint& joint = options_.joints[j];
    uint32_t k = 0;
    while (k < n &&
           std::strcmp(msg.name._buffer[k] != nullptr ? msg.name._buffer[k] : "", joint.channel.name.c_str()) != 0)
      ++k;
    if (k == n) {
      rejected_names_.fetch_add(1, std::memory_order_relaxed);
      ++current_.rejected;
      return;
    }
    const bool force = joint.channel.unit == JointUnit::kNewton;
    if (force && msg.effort._length != n) {
      rejected_lengths_.fetch_add(1, std::memory_order_relaxed);
      ++current_.rejected;
      return;
    }
    const double si = force ? msg.effort._buffer[k] : msg.position._buffer[k];
    if (!joint_value_from_si(si, joint.channel.unit, options_.length_exponent, &values[j])) {
      rejected_values_.fetch_add(1, std::memory_order_relaxed);
      ++current_.rejected;
      return;
    }
  }
  for (size_t j = 0; j < joints; ++j) {
    current_.value[j] = values[j];
    current_.taken_ns[j] = now_ns;
    ++current_.accepted[j];
  }
  accepted_.fetch_add(1, std::memory_order_relaxed);
}

size_t JointStateSource::latch(uint64_t until_ns, std::span<JointSample> out, InputHealth& health) {
  exchange_.refresh();
  const Latest& latest = exchange_.front();
  for (; latched_rejected_ < latest.rejected; ++latched_rejected_) health.reject(-1, RejectReason::kMalformed);
  size_t count = 0;
  for (size_t j = 0; j < latched_.size() && count < out.size(); ++j) {
    if (latest.accepted[j] == latched_[j] || latest.taken_ns[j] > until_ns) continue;
    latched_[j] = latest.accepted[j];
    out[count++] = {options_.joints[j].input, latest.value[j], latest.taken_ns[j], kSampleOk};
  }
  return count;
}

SourceState JointStateSource::state() const {
  return publishers_.load(std::memory_order_relaxed) > 0 ? SourceState::kOk : SourceState::kDown;
}

JointStateSourceCounters JointStateSource::counters() const {
  return {samples_.load(),        accepted_.load(),        rejected_lengths_.load(),
          rejected_names_.load(), rejected_values_.load(), publishers_.load()};
}

std::string JointStateSource::status_line() const {
  const JointStateSourceCounters c = counters();
  return "dds " + dds_topic_ + ": " + std::to_string(c.publishers) + " publishers, " + std::to_string(c.samples) +
         " samples, " + std::to_string(c.accepted) + " taken, rejected: lengths " + std::to_string(c.rejected_lengths) +
         ", names " + std::to_string(c.rejected_names) + ", values " + std::to_string(c.rejected_values);
}

}  // namespace sinew::hal::dds
