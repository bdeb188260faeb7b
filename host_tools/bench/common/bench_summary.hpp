// One row of the benchmarks' common table: a figure, the baseline it is
// compared with (measured in the same process, same run), their ratio and the
// target it is held to. Every bench prints its own detailed table; the rows it
// reports here are what `scripts/bench.sh` gathers into one table and one JSON
// file (docs/performance.md explains each measure).
//
// A bench reports with `summary_row(...)`: the row is printed on stdout as
// "summary: ..." and, when the environment variable SINEW_BENCH_SUMMARY names
// a file, appended to it as one JSON object per line.
#pragma once

#include <string>

namespace sinew::bench {

// How the target bounds a figure: `ratio` compares figure / baseline, `figure`
// the figure itself. `at_least` means bigger is better (throughput), `at_most`
// smaller is better (time, share of a tick).
enum class TargetOn { ratio, figure };
enum class TargetSense { at_least, at_most };

struct SummaryTarget {
  bool set = false;
  TargetOn on = TargetOn::ratio;
  TargetSense sense = TargetSense::at_least;
  double bound = 0;
};

SummaryTarget ratio_at_least(double bound);
SummaryTarget ratio_at_most(double bound);
SummaryTarget figure_at_least(double bound);
SummaryTarget figure_at_most(double bound);

struct SummaryRow {
  std::string bench;           // e.g. "skinning"
  std::string measure;         // what was measured, with its workload
  double figure = 0;           // in `unit`
  std::string unit;            // e.g. "vertices/s", "us", "pairs/s"
  std::string baseline;        // what it is compared with ("" when nothing)
  double baseline_figure = 0;  // in `unit`
  SummaryTarget target;        // unset: reported, not judged
  std::string target_source;   // where the target comes from (issue, paper, tick budget)
};

// figure / baseline_figure, or 0 when there is no baseline.
double summary_ratio(const SummaryRow& row);
// "met", "not met" or "-" (no target).
const char* summary_verdict(const SummaryRow& row);
// Prints the row and appends it to $SINEW_BENCH_SUMMARY when set. Returns
// false when the file cannot be written (the bench should then exit non-zero).
bool summary_row(const SummaryRow& row);

}  // namespace sinew::bench
