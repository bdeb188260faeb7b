// Real-time setup for the tick thread, each step applied only when permitted
// and reported either way: SCHED_FIFO priority, CPU affinity, mlockall.
#pragma once

#include <pthread.h>

#include <string>

namespace sinew::firmware {

struct RealtimeOptions {
  int fifo_priority = 0;  // 1..99 for SCHED_FIFO; 0 keeps the default policy
  int cpu = -1;           // pin the calling thread to this CPU; -1 = no affinity
  bool lock_memory = false;
  // The CPUs' wake-up latency requested for a live run, from before the
  // start-up probe of the tick to the end (cpu_latency.hpp): 0 keeps them
  // in a polling idle state; -1 makes no request.
  int cpu_latency_us = 0;
  // Threads the tick's parallel stages run over, the tick thread included
  // (firmware/runtime/worker_pool.hpp); 0: the CPUs the process may run on
  // but one (left to the I/O threads), 1 to 4. The output is the same for every count. The workers take the
  // tick's fifo_priority; worker_cpu >= 0 pins worker i (1..workers-1) to
  // CPU worker_cpu + i - 1.
  int workers = 0;
  int worker_cpu = -1;
  // The sinks' I/O threads (firmware/runtime/async_sink.hpp): one per sink,
  // fed through a ring of `sink_ring_frames` frames. Below the tick thread's
  // priority, so a write never preempts a tick; on a 4-core board, pin the
  // tick thread to one isolated core and the I/O threads to another.
  int io_fifo_priority = 0;  // 1..99 SCHED_FIFO for the I/O threads; 0 keeps the default policy
  int io_cpu = -1;           // pin the I/O threads to this CPU; -1 = no affinity
  int sink_ring_frames = 128;
  // After the devices, sockets and files are open and the settings above
  // applied: run as this user ("": as started; privileges.hpp).
  std::string user;
  // 0: the tick wakes an I/O thread per frame; > 0: the I/O threads drain
  // their rings every io_poll_us and the tick makes no system call for
  // output (a frame leaves up to io_poll_us later).
  int io_poll_us = 0;
};

// Applies the options to the calling thread/process. Returns one line per
// option saying what took effect (e.g. "SCHED_FIFO 80: not permitted (EPERM)").
std::string apply_realtime(const RealtimeOptions& options);

// The same for another thread (an I/O thread): SCHED_FIFO priority (0: keep
// the default policy) and CPU (-1: none). Lines start with `label`.
std::string apply_thread_realtime(pthread_t thread, int fifo_priority, int cpu, const std::string& label);
// The worker count `workers` asks for: itself when > 0, else the CPUs this
// process may run on (sched_getaffinity) but one, 1 to 4.
int resolved_workers(int workers);

}  // namespace sinew::firmware
