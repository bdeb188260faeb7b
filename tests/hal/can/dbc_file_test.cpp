// hal/can/sinew_joints.dbc describes the default joint stream: its messages
// and signals match the protocol constants, and decoding encoder output with
// the DBC's own signal definitions gives the protocol decoder's values.
#include <gtest/gtest.h>

#include <cstdio>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "hal/can/joint_stream_decoder.hpp"
#include "hal/can/joint_stream_encoder.hpp"
#include "hal/can/signal_decoder.hpp"

namespace sinew::hal::can {
namespace {

struct DbcSignal {
  std::string name;
  uint16_t start = 0;
  uint8_t length = 0;
  bool intel = true;
  bool is_signed = false;
  double scale = 0, offset = 0, min = 0, max = 0;
  std::string unit;
};

struct DbcMessage {
  uint32_t id = 0;
  std::string name;
  int dlc = 0;
  std::vector<DbcSignal> signals;
};

// Just enough of the DBC grammar for the lines this file uses.
std::map<uint32_t, DbcMessage> read_dbc() {
  std::ifstream in(SINEW_CAN_DBC_PATH);
  EXPECT_TRUE(in.good()) << SINEW_CAN_DBC_PATH;
  std::map<uint32_t, DbcMessage> messages;
  DbcMessage* current = nullptr;
  std::string line;
  while (std::getline(in, line)) {
    unsigned id = 0;
    int dlc = 0;
    char name[64] = {};
    char sender[64] = {};
    if (line.rfind("BO_ ", 0) == 0) {
      EXPECT_EQ(std::sscanf(line.c_str(), "BO_ %u %63[^:]: %d %63s", &id, name, &dlc, sender), 4) << line;
      current = &messages[id];
      current->id = id;
      current->name = name;
      current->dlc = dlc;
    } else if (line.rfind(" SG_ ", 0) == 0) {
      DbcSignal s;
      unsigned start = 0, length = 0;
      char order = 0, sign = 0;
      int consumed = 0;
      const int fields = std::sscanf(line.c_str(), " SG_ %63s : %u|%u@%c%c (%lf,%lf) [%lf|%lf]%n", name, &start,
                                     &length, &order, &sign, &s.scale, &s.offset, &s.min, &s.max, &consumed);
      EXPECT_EQ(fields, 9) << "unparsed signal line: " << line;
      if (current == nullptr || fields != 9) continue;
      const std::string rest = line.substr(static_cast<size_t>(consumed));
      const size_t q1 = rest.find('"');
      const size_t q2 = rest.find('"', q1 + 1);
      EXPECT_TRUE(q1 != std::string::npos && q2 != std::string::npos) << line;
      s.name = name;
      s.start = static_cast<uint16_t>(start);
      s.length = static_cast<uint8_t>(length);
      s.intel = order == '1';
      s.is_signed = sign == '-';
      s.unit = rest.substr(q1 + 1, q2 - q1 - 1);
      current->signals.push_back(s);
    }
  }
  return messages;
}

const DbcSignal* find(const DbcMessage& msg, const std::string& name) {
  for (const DbcSignal& s : msg.signals) {
    if (s.name == name) return &s;
  }
  return nullptr;
}

std::string joint_name(size_t j) {
  char buf[16];
  std::snprintf(buf, sizeof buf, "Joint%02zu", j);
  return buf;
}

constexpr size_t kDbcJoints = 32;

TEST(DbcFile, MessagesMatchTheDefaultLayout) {
  const auto messages = read_dbc();
  for (bool fd : {false, true}) {
    for (const JointFrame& f : default_joint_stream_config(kDbcJoints, fd, 0).frames) {
      ASSERT_EQ(messages.count(f.can_id), 1u) << std::hex << f.can_id;
      const DbcMessage& msg = messages.at(f.can_id);
      EXPECT_EQ(msg.dlc, fd ? 64 : 8);
      EXPECT_EQ(msg.signals.size(), f.joints.size() * 5);
    }
  }
  EXPECT_EQ(messages.size(), kDbcJoints + kDbcJoints / kJointsPerFdFrame);
}

TEST(DbcFile, SignalsMatchTheRecordLayout) {
  const auto messages = read_dbc();
  const double lsb_degrees = 360.0 / 4294967296.0;
  for (bool fd : {false, true}) {
    for (const JointFrame& f : default_joint_stream_config(kDbcJoints, fd, 0).frames) {
      const DbcMessage& msg = messages.at(f.can_id);
      for (size_t k = 0; k < f.joints.size(); ++k) {
        const std::string name = joint_name(f.joints[k].input);
        const uint16_t base = static_cast<uint16_t>(k * 64);
        const DbcSignal* crc = find(msg, name + "_Crc");
        const DbcSignal* counter = find(msg, name + "_Counter");
        const DbcSignal* status = find(msg, name + "_Status");
        const DbcSignal* angle = find(msg, name + "_Angle");
        const DbcSignal* reserved = find(msg, name + "_Reserved");
        ASSERT_TRUE(crc && counter && status && angle && reserved) << msg.name << " " << name;
        EXPECT_EQ(crc->start, base);
        EXPECT_EQ(crc->length, 8);
        EXPECT_EQ(counter->start, base + 8);
        EXPECT_EQ(counter->length, 4);
        EXPECT_EQ(counter->max, 14.0);
        EXPECT_EQ(status->start, base + 12);
        EXPECT_EQ(status->length, 4);
        EXPECT_EQ(angle->start, base + 16);
        EXPECT_EQ(angle->length, 32);
        EXPECT_TRUE(angle->intel);
        EXPECT_TRUE(angle->is_signed);
        EXPECT_EQ(angle->scale, lsb_degrees);  // exact: 45 / 2^29
        EXPECT_EQ(angle->unit, "deg");
        EXPECT_EQ(angle->min, -180.0);
        EXPECT_EQ(angle->max, 180.0 - lsb_degrees);
        EXPECT_EQ(reserved->start, base + 48);
        EXPECT_EQ(reserved->length, 16);
        for (const DbcSignal* s : {crc, counter, status, reserved}) {
          EXPECT_TRUE(s->intel && !s->is_signed && s->scale == 1.0 && s->offset == 0.0) << s->name;
        }
      }
    }
  }
}

// A CAN tool decoding with the DBC sees what the runtime decodes.
TEST(DbcFile, DecodingWithTheDbcSignalsAgreesWithTheProtocolDecoder) {
  const auto messages = read_dbc();
  for (bool fd : {false, true}) {
    const JointStreamConfig config = default_joint_stream_config(kDbcJoints, fd, 0);
    std::vector<SignalSpec> specs;
    for (const JointFrame& f : config.frames) {
      for (const JointChannel& j : f.joints) {
        const DbcSignal* angle = find(messages.at(f.can_id), joint_name(j.input) + "_Angle");
        ASSERT_NE(angle, nullptr);
        SignalSpec s;
        s.can_id = f.can_id;
        s.start_bit = angle->start;
        s.length = angle->length;
        s.byte_order = angle->intel ? ByteOrder::kIntel : ByteOrder::kMotorola;
        s.is_signed = angle->is_signed;
        s.scale = angle->scale;
        s.offset = angle->offset;
        s.min = angle->min;
        s.max = angle->max;
        s.unit = PhysicalUnit::kDegrees;
        s.input = j.input;
        specs.push_back(s);
      }
    }
    SignalDecoder via_dbc;
    JointStreamDecoder via_protocol;
    JointStreamSender sender;
    std::string error;
    ASSERT_TRUE(via_dbc.configure(specs, &error)) << error;
    ASSERT_TRUE(via_protocol.configure(config, &error)) << error;
    ASSERT_TRUE(sender.configure(config, &error)) << error;
    int32_t v = -2147483647 - 1;
    for (int round = 0; round < 20; ++round) {
      for (size_t f = 0; f < sender.frame_count(); ++f) {
        int32_t values[kJointsPerFdFrame];
        for (int32_t& x : values) {
          x = v;
          v = static_cast<int32_t>(static_cast<uint32_t>(v) + 0x0ABCDEF1u);  // walks the whole circle
        }
        const CanFrame frame = sender.next(f, values);
        FrameDecode a, b;
        via_dbc.decode(frame, a);
        via_protocol.decode(frame, b);
        ASSERT_EQ(a.sample_count, b.sample_count);
        for (size_t k = 0; k < a.sample_count; ++k) {
          EXPECT_EQ(a.samples[k].input, b.samples[k].input);
          EXPECT_EQ(a.samples[k].value, b.samples[k].value);
        }
        // The counter and CRC signals read the record's bytes.
        const DbcSignal* counter =
            find(messages.at(config.frames[f].can_id), joint_name(config.frames[f].joints[0].input) + "_Counter");
        EXPECT_EQ(extract_bits({frame.data.data(), frame.len}, counter->start, counter->length, ByteOrder::kIntel),
                  static_cast<uint64_t>(round % 15));
      }
    }
  }
}

}  // namespace
}  // namespace sinew::hal::can
