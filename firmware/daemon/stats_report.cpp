#include "stats_report.hpp"

#include <cstdio>

#include "sim_core/pipeline/stage_table.hpp"

namespace sinew::firmware {
namespace {

void print_layer_costs(const Runtime& runtime) {
  const StageTimes& t = runtime.stage_times();
  if (t.ticks == 0) return;
  uint64_t total = 0;
  for (uint64_t ns : t.total_ns) total += ns;
  std::printf("  tick by stage (mean, share, max):");
  for (uint32_t s = 0; s < pipeline::kStageCount; ++s) {
    if (!pipeline::pipeline_stage_on(runtime.pipeline(), static_cast<pipeline::Stage>(s))) continue;
    std::printf(" %s %.1f us %.0f%% %.1f us;", pipeline::stage_name(static_cast<pipeline::Stage>(s)),
                static_cast<double>(t.total_ns[s]) / static_cast<double>(t.ticks) / 1000.0,
                total > 0 ? 100.0 * static_cast<double>(t.total_ns[s]) / static_cast<double>(total) : 0.0,
                static_cast<double>(t.max_ns[s]) / 1000.0);
  }
  std::printf("\n");
}

}  // namespace

std::string print_stats(Runtime& runtime, const LoadedRig& rig, bool final_report) {
  StepTiming& t = runtime.timing();
  const InputHealth& h = runtime.health();
  uint64_t rejected = 0, accepted = 0;
  for (size_t i = 0; i < rig.input_count(); ++i) {
    accepted += h.counters(i).accepted;
    for (uint64_t r : h.counters(i).rejected) rejected += r;
  }
  for (uint64_t r : h.unassigned().rejected) rejected += r;
  char headline[320];
  std::snprintf(headline, sizeof(headline),
                "%s tick %llu: step p50 %.1f us p99 %.1f us max %.1f us, deadline misses %llu, inputs stale %zu/%u, "
                "samples accepted %llu rejected %llu, frames dropped %llu",
                final_report ? "final" : "stats", static_cast<unsigned long long>(runtime.ticks()),
                static_cast<double>(t.percentile_ns(0.5)) / 1000.0, static_cast<double>(t.percentile_ns(0.99)) / 1000.0,
                static_cast<double>(t.max_ns()) / 1000.0, static_cast<unsigned long long>(t.deadline_misses()),
                h.stale_count(), rig.input_count(), static_cast<unsigned long long>(accepted),
                static_cast<unsigned long long>(rejected), static_cast<unsigned long long>(runtime.dropped_frames()));
  std::printf("%s\n", headline);
  for (const auto& s : runtime.sources())
    std::printf("  source %-10s %-8s %s\n", s->name(), source_state_name(s->state()), s->status_line().c_str());
  print_layer_costs(runtime);
  if (runtime.layer_errors() > 0)
    std::printf("  layer errors %llu (the last: %s)\n", static_cast<unsigned long long>(runtime.layer_errors()),
                runtime.last_layer_error());
  for (const auto& s : runtime.sinks()) std::printf("  sink   %-10s %s\n", s->name(), s->status_line().c_str());
  if (final_report) {
    // Per-reason totals, one line the tests (and log scrapers) can parse.
    uint64_t by_reason[static_cast<int>(hal::RejectReason::kCount)] = {};
    uint64_t stale_events = 0;
    for (size_t i = 0; i < rig.input_count(); ++i) {
      for (int r = 0; r < static_cast<int>(hal::RejectReason::kCount); ++r) by_reason[r] += h.counters(i).rejected[r];
      stale_events += h.counters(i).stale_events;
    }
    std::printf("  rejected by reason:");
    for (int r = 0; r < static_cast<int>(hal::RejectReason::kCount); ++r)
      std::printf(" %s %llu", hal::reject_reason_name(static_cast<hal::RejectReason>(r)),
                  static_cast<unsigned long long>(by_reason[r] + h.unassigned().rejected[r]));
    std::printf("; stale events %llu\n", static_cast<unsigned long long>(stale_events));
  }
  if (final_report && h.stale_count() > 0) {
    for (size_t i = 0; i < rig.input_count(); ++i)
      if (h.status()[i] & hal::kJointStale) std::printf("  stale input %s\n", rig.input_names[i].c_str());
  }
  std::fflush(stdout);
  return headline;
}

std::string run_verdict(Runtime& runtime, uint64_t skipped_ticks, uint32_t rate_hz, uint32_t configured_hz) {
  const uint64_t ticks = runtime.ticks(), misses = runtime.timing().deadline_misses();
  const StageTimes& t = runtime.stage_times();
  uint32_t slowest = 0;
  for (uint32_t s = 1; s < pipeline::kStageCount; ++s)
    if (t.total_ns[s] > t.total_ns[slowest]) slowest = s;
  const double share = ticks > 0 ? 100.0 * static_cast<double>(misses) / static_cast<double>(ticks) : 0.0;
  // Budget: at most 0.1 % of ticks late (1 in 1000) and no tick skipped.
  const bool kept = misses * 1000 <= ticks && skipped_ticks == 0;
  char rate[64];
  if (rate_hz == configured_hz)
    std::snprintf(rate, sizeof(rate), "%u Hz", rate_hz);
  else
    std::snprintf(rate, sizeof(rate), "%u Hz (slowed from %u Hz to fit)", rate_hz, configured_hz);
  char line[400];
  std::snprintf(
      line, sizeof(line),
      "verdict: %llu ticks at %s, %llu deadline misses (%.2f %%), %llu skipped; slowest stage %s (%.1f us mean); %s",
      static_cast<unsigned long long>(ticks), rate, static_cast<unsigned long long>(misses), share,
      static_cast<unsigned long long>(skipped_ticks), pipeline::stage_name(static_cast<pipeline::Stage>(slowest)),
      t.ticks > 0 ? static_cast<double>(t.total_ns[slowest]) / static_cast<double>(t.ticks) / 1000.0 : 0.0,
      kept                       ? "within the budget (<= 0.1 % late, none skipped)"
      : rate_hz != configured_hz ? "over the budget (<= 0.1 % late, none skipped): lower [loop] step_budget for more "
                                   "margin, or switch a layer off"
                                 : "over the budget (<= 0.1 % late, none skipped): set [loop] over_budget = \"slow\", "
                                   "lower [loop] rate_hz or switch a layer off");
  return line;
}

}  // namespace sinew::firmware
