// A PM QoS request for the CPUs' wake-up latency (/dev/cpu_dma_latency),
// held for as long as the object lives: the kernel keeps every CPU out of
// idle states whose exit latency is above the request while the file stays
// open, and drops the request when it closes (Documentation/power/pm_qos_
// interface.rst). cyclictest makes the same request (0 us) before it
// measures. A board's deep idle states take tens to hundreds of
// microseconds to leave; a virtual machine's vCPU that halts may be
// descheduled by the host for milliseconds, where the guest's polling idle
// state (0 us, e.g. cpuidle-haltpoll) keeps it running (docs/pipeline.md,
// "Fitting the tick to the machine").
#pragma once

#include <cstdint>
#include <string>

namespace sinew::firmware {

class CpuLatencyRequest {
 public:
  static constexpr const char* kDevice = "/dev/cpu_dma_latency";
  CpuLatencyRequest() = default;
  ~CpuLatencyRequest();
  CpuLatencyRequest(const CpuLatencyRequest&) = delete;
  CpuLatencyRequest& operator=(const CpuLatencyRequest&) = delete;

  // Requests at most latency_us (0..2000000000) of wake-up latency by
  // writing it as a binary int32 to `device` and keeping it open; a
  // request held before is released first. Returns one line saying what
  // took effect (e.g. "cpu latency 0 us: not applied (Permission denied)").
  std::string request(int32_t latency_us, const char* device = kDevice);
  bool held() const { return fd_ >= 0; }
  void release();

 private:
  int fd_ = -1;
};

}  // namespace sinew::firmware
