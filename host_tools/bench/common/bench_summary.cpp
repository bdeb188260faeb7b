#include "host_tools/bench/common/bench_summary.hpp"

#include <cstdio>
#include <cstdlib>
#include <nlohmann/json.hpp>

namespace sinew::bench {

namespace {

SummaryTarget make_target(TargetOn on, TargetSense sense, double bound) {
  SummaryTarget t;
  t.set = true;
  t.on = on;
  t.sense = sense;
  t.bound = bound;
  return t;
}

std::string target_text(const SummaryTarget& t) {
  if (!t.set) return "";
  char text[64];
  std::snprintf(text, sizeof(text), "%s %s %g", t.on == TargetOn::ratio ? "ratio" : "figure",
                t.sense == TargetSense::at_least ? ">=" : "<=", t.bound);
  return text;
}

}  // namespace

SummaryTarget ratio_at_least(double bound) { return make_target(TargetOn::ratio, TargetSense::at_least, bound); }
SummaryTarget ratio_at_most(double bound) { return make_target(TargetOn::ratio, TargetSense::at_most, bound); }
SummaryTarget figure_at_least(double bound) { return make_target(TargetOn::figure, TargetSense::at_least, bound); }
SummaryTarget figure_at_most(double bound) { return make_target(TargetOn::figure, TargetSense::at_most, bound); }

double summary_ratio(const SummaryRow& row) {
  if (row.baseline.empty() || row.baseline_figure == 0) return 0;
  return row.figure / row.baseline_figure;
}

const char* summary_verdict(const SummaryRow& row) {
  if (!row.target.set) return "-";
  if (row.target.on == TargetOn::ratio && row.baseline.empty()) return "-";
  const double value = row.target.on == TargetOn::ratio ? summary_ratio(row) : row.figure;
  const bool met = row.target.sense == TargetSense::at_least ? value >= row.target.bound : value <= row.target.bound;
  return met ? "met" : "not met";
}

bool summary_row(const SummaryRow& row) {
  std::printf("summary: [%s] %s: %.4g %s", row.bench.c_str(), row.measure.c_str(), row.figure, row.unit.c_str());
  if (!row.baseline.empty())
    std::printf("; %s %.4g %s, ratio %.3f", row.baseline.c_str(), row.baseline_figure, row.unit.c_str(),
                summary_ratio(row));
  if (row.target.set) std::printf("; target %s: %s", target_text(row.target).c_str(), summary_verdict(row));
  std::printf("\n");
  const char* path = std::getenv("SINEW_BENCH_SUMMARY");
  if (path == nullptr || *path == '\0') return true;
  nlohmann::json j = {{"bench", row.bench},
                      {"measure", row.measure},
                      {"figure", row.figure},
                      {"unit", row.unit},
                      {"baseline", row.baseline},
                      {"baseline_figure", row.baseline_figure},
                      {"ratio", summary_ratio(row)},
                      {"target", target_text(row.target)},
                      {"target_source", row.target_source},
                      {"verdict", summary_verdict(row)}};
  std::FILE* f = std::fopen(path, "a");
  if (f == nullptr) {
    std::fprintf(stderr, "bench summary: cannot open %s for appending\n", path);
    return false;
  }
  const std::string line = j.dump() + "\n";
  const bool written = std::fwrite(line.data(), 1, line.size(), f) == line.size();
  const bool closed = std::fclose(f) == 0;
  if (!written || !closed) std::fprintf(stderr, "bench summary: cannot write %s\n", path);
  return written && closed;
}

}  // namespace sinew::bench
