// sinew-bench-table: gathers the rows the benches reported (one JSON object per
// line, see bench_summary.hpp) into one table on stdout and one JSON document
// with the machine's name, core count and load average at the end of the run.
#include <sys/utsname.h>
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <cstdio>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

namespace {

int table_fail(const std::string& message) {
  std::fprintf(stderr, "sinew-bench-table: %s\n", message.c_str());
  return 1;
}

std::string load_average() {
  std::ifstream in("/proc/loadavg");
  std::string one, five, fifteen;
  if (!(in >> one >> five >> fifteen)) return "unknown";
  return one + " " + five + " " + fifteen;
}

std::string machine() {
  utsname u{};
  if (uname(&u) != 0) return "unknown";
  return std::string(u.sysname) + " " + u.release + " " + u.machine;
}

std::string format_figure(double v) {
  char text[32];
  std::snprintf(text, sizeof(text), "%.4g", v);
  return text;
}

int run(int argc, char** argv) {
  CLI::App app{"Prints the benches' summary rows as one table and writes them as JSON."};
  std::string rows_path, json_path;
  app.add_option("rows", rows_path, "file of summary rows, one JSON object per line")->required();
  app.add_option("--json", json_path, "write the table as one JSON document here");
  CLI11_PARSE(app, argc, argv);

  std::ifstream in(rows_path);
  if (!in) return table_fail("cannot read " + rows_path);
  std::vector<nlohmann::json> rows;
  std::string line;
  for (int number = 1; std::getline(in, line); ++number) {
    if (line.empty()) continue;
    nlohmann::json row = nlohmann::json::parse(line, nullptr, false);
    if (row.is_discarded() || !row.is_object() || !row.contains("measure") || !row.contains("figure"))
      return table_fail(rows_path + ":" + std::to_string(number) + ": not a summary row");
    rows.push_back(std::move(row));
  }
  if (rows.empty()) return table_fail(rows_path + ": no summary rows (did every bench run?)");

  std::printf("%-10s %-58s %12s %-12s %-28s %8s %-14s %s\n", "bench", "measure", "figure", "unit", "baseline", "ratio",
              "target", "verdict");
  int met = 0, not_met = 0;
  for (const auto& r : rows) {
    const std::string ratio = r.value("baseline", "").empty() ? "-" : format_figure(r.value("ratio", 0.0));
    const std::string target = r.value("target", "").empty() ? "-" : r.value("target", "");
    const std::string verdict = r.value("verdict", "-");
    if (verdict == "met") ++met;
    if (verdict == "not met") ++not_met;
    std::printf("%-10s %-58s %12s %-12s %-28s %8s %-14s %s\n", r.value("bench", "").c_str(),
                r.value("measure", "").c_str(), format_figure(r.value("figure", 0.0)).c_str(),
                r.value("unit", "").c_str(), r.value("baseline", "-").c_str(), ratio.c_str(), target.c_str(),
                verdict.c_str());
  }
  const std::string load = load_average();
  std::printf("targets met %d, not met %d; machine %s, %ld cores, load average %s\n", met, not_met, machine().c_str(),
              sysconf(_SC_NPROCESSORS_ONLN), load.c_str());
  if (!json_path.empty()) {
    const nlohmann::json doc = {{"machine", machine()},       {"cores", sysconf(_SC_NPROCESSORS_ONLN)},
                                {"load_average", load},       {"targets_met", met},
                                {"targets_not_met", not_met}, {"rows", rows}};
    std::ofstream out(json_path);
    out << doc.dump(2) << "\n";
    out.close();
    if (!out) return table_fail("cannot write " + json_path);
    std::printf("wrote %s\n", json_path.c_str());
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  try {
    return run(argc, argv);
  } catch (const std::exception& e) {
    return table_fail(std::string("internal error: ") + e.what());
  }
}
