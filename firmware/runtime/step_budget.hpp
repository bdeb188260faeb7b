// The tick's step measured before a live run starts, so the daemon knows
// whether its configuration fits the machine it runs on and can say so, or
// slow its rate to fit ([loop] step_budget and over_budget; docs/pipeline.md,
// "Fitting the tick to the machine").
//
// The probe steps a pipeline of its own (the run's rig, layers, options and
// worker threads) while every input sweeps its accepted range, so the layers
// work as they do on a moving rig rather than at rest, where several take
// shortcuts. It allocates (its arena), so it runs at start-up only.
#pragma once

#include <cstdint>
#include <span>
#include <string>

#include "runtime.hpp"
#include "sim_core/pipeline/pipeline.hpp"

namespace sinew::firmware {

struct StepProbeResult {
  uint32_t steps = 0;  // steps timed (after the warm-up)
  uint64_t p50_ns = 0, p99_ns = 0, max_ns = 0;
  pipeline::Stage slowest = pipeline::Stage::kSkinning;  // the stage with the largest mean
  uint64_t slowest_mean_ns = 0;
  // The slowest of the stages [layers] can switch off (every stage but
  // skinning, which is always on), for the remedy an over-budget message
  // names; false when none of them ran.
  bool any_layer = false;
  pipeline::Stage slowest_layer = pipeline::Stage::kSkinning;
};

// Times `steps` steps (after a few untimed warm-up steps) or as many as fit
// in wall_limit_ns, whichever ends first; at least 8 are timed. limits: one
// per rig input then per external input (the daemon's accepted ranges).
// False with `error` when the pipeline refuses the options.
bool probe_step(const rig::Rig& rig, const pipeline::LayerSet& layers, const pipeline::PipelineOptions& options,
                std::span<const InputLimits> limits, uint32_t steps, uint64_t wall_limit_ns, StepProbeResult* out,
                std::string* error);

// Sets r->slowest to the stage with the largest total time (the first of
// equal ones) and r->slowest_mean_ns to its mean over `steps` (> 0), and
// r->slowest_layer likewise among the stages other than skinning that ran
// (a total above 0; r->any_layer says whether one did).
void name_slowest(const uint64_t (&stage_total_ns)[pipeline::kStageCount], uint32_t steps, StepProbeResult* r);

// The probe's input k at step s: a triangle wave over [lo, hi] with a
// period of 128 steps, each input at its own phase so the joints do not all
// move together (layers that couple two joints see them differ).
int32_t swept_input(int32_t lo, int32_t hi, uint64_t step, size_t input);

struct WakeProbeResult {
  uint32_t wakeups = 0;
  uint64_t p50_ns = 0, p99_ns = 0, max_ns = 0;  // how late the thread woke after each deadline
  // The mean excess over p99 of the wake-ups later than p99: the scale of
  // an exponential tail fitted beyond p99 (peaks over threshold; for an
  // exponential tail the mean excess is its maximum-likelihood scale). 0
  // when no wake-up was later than p99.
  uint64_t tail_scale_ns = 0;
};

// Fills p50, p99, max and tail_scale_ns from the lateness of each wake-up.
WakeProbeResult summarise_wakeups(std::span<const uint64_t> late_ns);

// The lateness a wake-up exceeds with `probability` (0 < probability <= 1):
// below 1 % the tail above extrapolated, p99 + scale ln(0.01 / probability),
// never less than the largest lateness seen (a probe of a thousand
// wake-ups sees its 1-in-1000 event, the tail only estimates it).
uint64_t wake_lateness_at(const WakeProbeResult& wake, double probability);

// Sleeps to `count` absolute deadlines (CLOCK_MONOTONIC, TIMER_ABSTIME)
// interval_ns apart and records how late each wake-up was: the machine's
// timer and scheduling latency, as cyclictest measures it, which every live
// tick adds to its step. A virtual machine's vCPU stalls show here.
WakeProbeResult probe_wakeups(uint64_t interval_ns, uint32_t count);

// What a live tick needs, from the two probes: a wake-up after its
// deadline, then a step.
struct TickNeed {
  uint64_t step_p99_ns = 0;
  WakeProbeResult wake;
  double duration_s = 0;  // the run's length; 0: until stopped
};

// A run may miss 0.1 % of its deadlines (the daemon's verdict). A run of
// N ticks may then miss A = floor(N / 1000) of them: the tolerated
// probability per tick is lambda / N for the largest mean lambda of a
// Poisson count that stays within A in nine runs of ten (0.105 / N when A
// = 0: a 5 s run below 200 Hz may miss none), and at most half the 0.1 %
// share; an endless run takes that half.
double tolerated_miss_probability(const TickNeed& need, uint32_t rate_hz);

// The typical tick (step p99 + wake-up p99) and the worst it must hold at a
// rate: step p99 + the wake-up lateness at the tolerated miss probability.
uint64_t typical_tick_ns(const TickNeed& need);
uint64_t worst_tick_ns(const TickNeed& need, uint32_t rate_hz);

// The largest rate rate_hz / k (k = 1, 2, ...; only exact divisors, so the
// slower ticks keep the configured schedule's slots) whose period P holds
// the typical tick within `share` of it (typical <= share P, 0 < share <= 1)
// and the worst tick at that rate within it (worst <= P); 0 when not even
// 1 Hz does.
uint32_t fitting_rate(uint32_t rate_hz, double share, const TickNeed& need);

}  // namespace sinew::firmware
