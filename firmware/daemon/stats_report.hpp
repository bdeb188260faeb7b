// The daemon's periodic and final statistics lines (stdout).
#pragma once

#include "firmware/rig/loaded_rig.hpp"
#include "firmware/runtime/runtime.hpp"

namespace sinew::firmware {

// Step times, deadline misses, input health, each source and sink, and the
// mean and worst time of every pipeline stage that runs; the final report
// adds the rejections by reason and the inputs left stale.
void print_stats(Runtime& runtime, const LoadedRig& rig, bool final_report);

}  // namespace sinew::firmware
