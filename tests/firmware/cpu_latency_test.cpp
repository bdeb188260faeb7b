// The wake-up latency request (firmware/runtime/cpu_latency.hpp), on a
// regular file standing in for /dev/cpu_dma_latency: the value written as
// the device reads it (a binary int32), held open until released, and a
// device that cannot be opened reported without a request held.
#include "firmware/runtime/cpu_latency.hpp"

#include <fcntl.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>

namespace cpu_latency_test {

using sinew::firmware::CpuLatencyRequest;

int32_t written_value(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  int32_t v = -12345;
  in.read(reinterpret_cast<char*>(&v), sizeof(v));
  EXPECT_EQ(in.gcount(), static_cast<std::streamsize>(sizeof(v)));
  return v;
}

// Descriptors open in this process on `path` (from /proc/self/fd).
int open_on(const std::string& path) {
  const std::string canonical = std::filesystem::canonical(path).string();
  int n = 0;
  for (int fd = 0; fd < 1024; ++fd) {
    char link[64], target[4096];
    std::snprintf(link, sizeof(link), "/proc/self/fd/%d", fd);
    const ssize_t len = readlink(link, target, sizeof(target) - 1);
    if (len > 0 && std::string(target, static_cast<size_t>(len)) == canonical) ++n;
  }
  return n;
}

TEST(CpuLatencyRequest, WritesTheValueAsInt32AndHoldsItUntilReleased) {
  const std::string path = testing::TempDir() + "/cpu_dma_latency";
  { std::ofstream create(path); }
  CpuLatencyRequest request;
  const std::string report = request.request(0, path.c_str());
  EXPECT_NE(report.find("cpu latency 0 us"), std::string::npos) << report;
  EXPECT_NE(report.find("held"), std::string::npos) << report;
  EXPECT_TRUE(request.held());
  EXPECT_EQ(written_value(path), 0);
  EXPECT_EQ(open_on(path), 1);  // the kernel keeps the request while it is open
  // A new request replaces the old one: one descriptor, the new value.
  { std::ofstream truncate(path); }
  request.request(20, path.c_str());
  EXPECT_EQ(written_value(path), 20);
  EXPECT_EQ(open_on(path), 1);
  request.release();
  EXPECT_FALSE(request.held());
  EXPECT_EQ(open_on(path), 0);
}

TEST(CpuLatencyRequest, ReleasedWhenItGoesOutOfScope) {
  const std::string path = testing::TempDir() + "/cpu_dma_latency_scope";
  { std::ofstream create(path); }
  {
    CpuLatencyRequest request;
    request.request(5, path.c_str());
    EXPECT_EQ(open_on(path), 1);
  }
  EXPECT_EQ(open_on(path), 0);
}

TEST(CpuLatencyRequest, ADeviceThatCannotBeOpenedIsReportedNotHeld) {
  CpuLatencyRequest request;
  const std::string report = request.request(0, "/nonexistent-dir/cpu_dma_latency");
  EXPECT_NE(report.find("not applied (No such file or directory)"), std::string::npos) << report;
  EXPECT_FALSE(request.held());
}

}  // namespace cpu_latency_test
