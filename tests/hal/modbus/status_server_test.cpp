// The read-only status server, read by a real libmodbus client over loopback.
#include "hal/modbus/status_server.hpp"

#include <gtest/gtest.h>
#include <modbus.h>

#include <array>
#include <cerrno>
#include <vector>

#include "hal/common/pose_frame.hpp"
#include "tests/support/alloc_guard.hpp"

namespace mb = sinew::hal::modbus;
namespace hal = sinew::hal;
namespace hal = sinew::hal;
namespace r = mb::status_reg;

namespace {

constexpr size_t kInputs = 5;

// A libmodbus client connected to the server.
class Client {
 public:
  explicit Client(uint16_t port) : ctx_(modbus_new_tcp("127.0.0.1", port)) {
    modbus_set_response_timeout(ctx_, 10, 0);  // a liveness bound: success returns at once
    connected_ = modbus_connect(ctx_) == 0;
  }
  ~Client() {
    modbus_close(ctx_);
    modbus_free(ctx_);
  }
  bool connected() const { return connected_; }
  std::vector<uint16_t> read(bool input_table, int address, int count) {
    std::vector<uint16_t> regs(static_cast<size_t>(count));
    const int rc = input_table ? modbus_read_input_registers(ctx_, address, count, regs.data())
                               : modbus_read_registers(ctx_, address, count, regs.data());
    last_errno = rc < 0 ? errno : 0;
    if (rc != count) regs.clear();
    return regs;
  }
  modbus_t* ctx() { return ctx_; }
  int last_errno = 0;

 private:
  modbus_t* ctx_;
  bool connected_ = false;
};

uint64_t tick_of(const std::vector<uint16_t>& regs) {
  uint64_t t = 0;
  for (int i = 0; i < 4; ++i) t = (t << 16) | regs[r::kTick + static_cast<size_t>(i)];
  return t;
}

}  // namespace

TEST(ModbusStatusServer, ServesCurrentValuesAndRefusesWrites) {
  mb::StatusServerConfig config;
  config.port = 0;  // any free port on 127.0.0.1
  config.input_count = kInputs;
  std::string error;
  auto server = mb::StatusServer::create(config, &error);
  ASSERT_NE(server, nullptr) << error;
  ASSERT_NE(server->port(), 0);

  const std::array<uint8_t, kInputs> inputs{0, hal::kJointStale, hal::kJointRejected, hal::kJointClampedStatus, 0};
  const std::array<hal::SourceState, 2> sources{hal::SourceState::kOk, hal::SourceState::kDown};
  mb::StatusUpdate update;
  update.tick = 123456789012u;
  update.last_step_ns = 87'654;
  update.stale_count = 1;
  update.input_status = inputs;
  update.source_states = sources;
  server->publish(update);

  Client client(server->port());
  ASSERT_TRUE(client.connected());
  const int total = static_cast<int>(mb::status_register_count(kInputs));
  const std::vector<uint16_t> holding = client.read(false, 0, total);
  ASSERT_EQ(holding.size(), static_cast<size_t>(total)) << modbus_strerror(client.last_errno);
  EXPECT_EQ(holding[r::kLayoutVersion], mb::kStatusLayout);
  EXPECT_EQ(holding[r::kHeartbeat], 1);
  EXPECT_EQ(tick_of(holding), 123456789012u);
  EXPECT_EQ(holding[r::kLastStepUs], 0);
  EXPECT_EQ(holding[r::kLastStepUs + 1], 87);
  EXPECT_EQ(holding[r::kStaleCount], 1);
  EXPECT_EQ(holding[r::kInputCount], kInputs);
  EXPECT_EQ(holding[r::kSourceCount], 2);
  EXPECT_EQ(holding[r::kSourcesDown], 1);
  EXPECT_EQ(holding[r::kSourceState], 0);
  EXPECT_EQ(holding[r::kSourceState + 1], 2);
  for (size_t i = 0; i < kInputs; ++i) EXPECT_EQ(holding[r::kInputStatus + i], inputs[i]) << "input " << i;
  EXPECT_EQ(client.read(true, 0, total), holding);  // the same image as input registers

  // Writes are refused with "illegal function" and change nothing.
  EXPECT_EQ(modbus_write_register(client.ctx(), r::kTick, 7), -1);
  EXPECT_EQ(errno, EMBXILFUN);
  const std::array<uint16_t, 2> words{1, 2};
  EXPECT_EQ(modbus_write_registers(client.ctx(), r::kInputStatus, 2, words.data()), -1);
  EXPECT_EQ(errno, EMBXILFUN);
  EXPECT_EQ(client.read(false, 0, total), holding);
  EXPECT_GE(server->requests_refused(), 2u);

  // Past the image: "illegal data address".
  EXPECT_TRUE(client.read(false, total, 1).empty());
  EXPECT_EQ(client.last_errno, EMBXILADD);

  // Later publishes show up on the next read; the publisher does not allocate.
  std::array<uint8_t, kInputs> later = inputs;
  later[0] = hal::kJointStale;
  update.input_status = later;
  sinew::test::AllocationCounter counter;
  for (int i = 0; i < 1000; ++i) {
    update.tick += 1;
    server->publish(update);
  }
  EXPECT_EQ(counter.allocations(), 0u);
  const std::vector<uint16_t> after = client.read(false, 0, total);
  ASSERT_EQ(after.size(), static_cast<size_t>(total));
  EXPECT_EQ(tick_of(after), 123456789012u + 1000);
  EXPECT_EQ(after[r::kHeartbeat], 1001);
  EXPECT_EQ(after[r::kInputStatus], hal::kJointStale);
  EXPECT_GE(server->reads_served(), 4u);
}

TEST(ModbusStatusServer, RefusesABadBindAddress) {
  mb::StatusServerConfig config;
  config.bind_address = "not-an-address";
  std::string error;
  EXPECT_EQ(mb::StatusServer::create(config, &error), nullptr);
  EXPECT_FALSE(error.empty());
}
