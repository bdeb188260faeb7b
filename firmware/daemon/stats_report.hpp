// The daemon's periodic and final statistics lines (stdout).
#pragma once

#include <string>

#include "firmware/rig/loaded_rig.hpp"
#include "firmware/runtime/runtime.hpp"

namespace sinew::firmware {

// Step times, deadline misses, input health, each source and sink, and the
// mean and worst time of every pipeline stage that runs; the final report
// adds the rejections by reason and the inputs left stale.
// Returns the first line (the step times and counters), without its newline.
std::string print_stats(Runtime& runtime, const LoadedRig& rig, bool final_report);
// The live run's one-line verdict: ticks, deadline misses and their share,
// skipped ticks, the slowest stage by mean time, and whether the run kept
// within the budget of at most 0.1 % of ticks late and none skipped; the
// rate the run used, and the configured one when [loop] over_budget slowed it.
std::string run_verdict(Runtime& runtime, uint64_t skipped_ticks, uint32_t rate_hz, uint32_t configured_hz);

}  // namespace sinew::firmware
