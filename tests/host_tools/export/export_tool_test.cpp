// sinew-export and sinew-pose --glb end to end: a run of the built-in arm
// logged by the daemon (offline), exported, parsed back against the log,
// checked by the Khronos glTF validator; hostile logs refused with a reason
// and no file left behind.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "hal/output/frame_log_reader.hpp"
#include "tests/host_tools/export/glb_parse.hpp"

namespace sinew::test {
namespace {

namespace fs = std::filesystem;

struct ExportRun {
  int status = -1;
  std::string out;
};

std::string export_slurp(const std::string& path) {
  std::ifstream in(path);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

ExportRun export_run(const std::string& command, const std::string& out_path) {
  const int raw = std::system((command + " > " + out_path + " 2>&1").c_str());
  return {WIFEXITED(raw) ? WEXITSTATUS(raw) : -1, export_slurp(out_path)};
}

// One offline daemon run of the built-in arm (100 Hz, 1 s of its built-in
// trajectory), logged with and without normals, made once for every test.
class ExportToolTest : public testing::Test {
 protected:
  static void SetUpTestSuite() {
    // One directory per test process: ctest runs these tests in parallel.
    dir_ = new std::string(testing::TempDir() + "/export_tool_" + std::to_string(::getpid()));
    fs::remove_all(*dir_);
    fs::create_directories(*dir_);
    const std::string config = *dir_ + "/run.toml";
    std::ofstream(config) << "[rig]\nbuiltin = \"arm\"\n[loop]\nrate_hz = 100\nduration_s = 1.0\n"
                          << "stats_interval_s = 0\nmode = \"offline\"\n"
                          << "[[source]]\ntype = \"trajectory\"\nperiod_ms = 10\n"
                          << "[[sink]]\ntype = \"log\"\nname = \"normals\"\nnormals = true\npath = \"" << *dir_
                          << "/arm.log\"\n"
                          << "[[sink]]\ntype = \"log\"\nname = \"plain\"\npath = \"" << *dir_ << "/plain.log\"\n";
    daemon_ = new ExportRun(export_run(std::string(SINEWD_EXE) + " --config " + config, *dir_ + "/daemon.out"));
  }
  static void TearDownTestSuite() {
    std::error_code ignored;
    fs::remove_all(*dir_, ignored);
    delete dir_;
    delete daemon_;
  }
  void SetUp() override { ASSERT_EQ(daemon_->status, 0) << daemon_->out; }

  static std::string file(const std::string& name) { return *dir_ + "/" + name; }
  static ExportRun run_export(const std::string& args, const std::string& name) {
    return export_run(std::string(SINEW_EXPORT_EXE) + " " + args, file(name + ".out"));
  }

  static std::string* dir_;
  static ExportRun* daemon_;
};
std::string* ExportToolTest::dir_ = nullptr;
ExportRun* ExportToolTest::daemon_ = nullptr;

// The Khronos validator's report on a file: its numErrors (-1 and a failure
// when it could not run; -2 when node is missing). With expect_valid, any
// error fails the test and its messages are printed.
int validator_errors(const std::string& glb, const std::string& report_path, bool expect_valid = true) {
  if (std::string(SINEW_NODE).empty()) return -2;
  const ExportRun v = export_run(std::string(SINEW_NODE) + " " + SINEW_GLTF_VALIDATOR + " " + glb, report_path);
  EXPECT_EQ(v.status, 0) << v.out;
  const nlohmann::json report = nlohmann::json::parse(v.out, nullptr, false);
  if (report.is_discarded() || !report.contains("issues")) {
    ADD_FAILURE() << "no validator report: " << v.out;
    return -1;
  }
  const int errors = report["issues"]["numErrors"].get<int>();
  if (errors != 0 && expect_valid)
    ADD_FAILURE() << "validator errors in " << glb << ":\n" << report["issues"]["messages"].dump(1);
  std::printf("gltf-validator %s: %d errors, %d warnings, %d infos\n", glb.c_str(), errors,
              report["issues"]["numWarnings"].get<int>(), report["issues"]["numInfos"].get<int>());
  return errors;
}

#define EXPORT_VALIDATE(glb, report)                                                                          \
  do {                                                                                                        \
    const int validator_result = validator_errors(glb, report);                                               \
    if (validator_result == -2) GTEST_SKIP() << "node is missing: install it (scripts/install-deps.sh test)"; \
    EXPECT_EQ(validator_result, 0);                                                                           \
  } while (0)

TEST_F(ExportToolTest, AnArmRunExportsAsTheLogSaysAndValidates) {
  const ExportRun run = run_export(file("arm.log") + " --rig arm -o " + file("arm.glb") + " --every 10", "arm");
  ASSERT_EQ(run.status, 0) << run.out;
  std::printf("%s", run.out.c_str());
  ParsedGlb glb;
  ASSERT_EQ(parse_glb(read_file_bytes(file("arm.glb")), &glb), "");
  const nlohmann::json& prim = glb.doc["meshes"][0]["primitives"][0];
  ASSERT_EQ(prim["targets"].size(), 10u);  // 100 frames, every 10th

  // Rest + target k is the log's frame 10 k, in metres (Q12.20 rig units x 2^e).
  hal::output::FrameLogReader reader;
  std::string error;
  ASSERT_TRUE(reader.open(file("arm.log"), &error)) << error;
  hal::output::DecodedPose pose;
  const std::vector<float> rest = accessor_floats(glb, prim["attributes"]["POSITION"].get<size_t>());
  uint64_t first_ns = 0;
  const nlohmann::json& anim = glb.doc["animations"][0];
  const std::vector<float> times = accessor_floats(glb, anim["samplers"][0]["input"].get<size_t>());
  ASSERT_EQ(times.size(), 10u);
  for (size_t record = 0; reader.next(&pose); ++record) {
    if (record == 0) first_ns = pose.timestamp_ns;
    if (record % 10 != 0) continue;
    const size_t k = record / 10;
    EXPECT_NEAR(times[k], static_cast<double>(pose.timestamp_ns - first_ns) * 1e-9, 1e-6);
    const std::vector<float> d = accessor_floats(glb, prim["targets"][k]["POSITION"].get<size_t>());
    ASSERT_EQ(d.size(), rest.size());
    double worst = 0;
    for (size_t v = 0; v < pose.vertex_count; ++v)
      for (size_t c = 0; c < 3; ++c) {
        const double logged = std::ldexp(static_cast<double>(pose.position[c][v]), pose.length_exponent - 20);
        worst = std::max(worst, std::fabs(double{rest[3 * v + c]} + double{d[3 * v + c]} - logged));
      }
    // Float rounding of rest and offset: a few ulps of a metre-scale value.
    EXPECT_LT(worst, 1e-6) << "frame " << k;
  }
  EXPECT_TRUE(reader.clean_end());
  EXPORT_VALIDATE(file("arm.glb"), file("arm.validator.json"));
}

TEST_F(ExportToolTest, TheMorphAnimationMovesTheSurface) {
  const ExportRun run = run_export(
      file("plain.log") + " --rig builtin:arm -o " + file("plain.glb") + " --from 0.2 --to 0.8 --every 30", "plain");
  ASSERT_EQ(run.status, 0) << run.out;
  ParsedGlb glb;
  ASSERT_EQ(parse_glb(read_file_bytes(file("plain.glb")), &glb), "");
  const nlohmann::json& prim = glb.doc["meshes"][0]["primitives"][0];
  ASSERT_EQ(prim["targets"].size(), 3u);  // t = 0.2, 0.5, 0.8
  const std::vector<float> a = accessor_floats(glb, prim["targets"][0]["POSITION"].get<size_t>()),
                           b = accessor_floats(glb, prim["targets"][2]["POSITION"].get<size_t>());
  ASSERT_EQ(a.size(), b.size());
  double moved = 0;
  for (size_t i = 0; i < a.size(); ++i) moved = std::max(moved, std::fabs(double{a[i]} - double{b[i]}));
  // The trajectory swings the arm's joints over 0.6 s: its skin moves by
  // centimetres, far above float rounding.
  EXPECT_GT(moved, 1e-3);
  std::printf("largest vertex move between the first and last exported frames: %.4f m\n", moved);
  // So do the joints: some joint's rotation keys differ between the frames.
  const nlohmann::json& anim = glb.doc["animations"][0];
  double turned = 0;
  for (size_t s = 2; s < anim["samplers"].size(); s += 2) {
    const std::vector<float> q = accessor_floats(glb, anim["samplers"][s]["output"].get<size_t>());
    for (size_t c = 0; c < 4; ++c) turned = std::max(turned, std::fabs(double{q[c]} - double{q[8 + c]}));
  }
  EXPECT_GT(turned, 1e-3);
  EXPORT_VALIDATE(file("plain.glb"), file("plain.validator.json"));
}

TEST_F(ExportToolTest, HostileLogsAreRefusedAndLeaveNoFile) {
  const std::string log = export_slurp(file("arm.log"));
  ASSERT_GT(log.size(), 1000u);
  fs::create_directories(file("hostile"));
  struct Case {
    std::string name, bytes, rig, expect;
  };
  std::string corrupt = log;
  corrupt[corrupt.size() / 2] = static_cast<char>(corrupt[corrupt.size() / 2] ^ 0x5A);
  const std::vector<Case> cases = {
      {"truncated", log.substr(0, log.size() - 1000), "arm", "is damaged: torn-tail"},
      {"corrupt", corrupt, "arm", "is damaged: bad-"},
      {"mismatch", log, "hand", "does not match the rig: vertex count"},
      {"notalog", "this is not a frame log at all, just text bytes....", "arm", "notalog.log: not a frame log"},
  };
  for (const Case& c : cases) {
    const std::string in = file("hostile/" + c.name + ".log"), out = file("hostile/" + c.name + ".glb");
    std::ofstream(in, std::ios::binary) << c.bytes;
    const ExportRun run = run_export(in + " --rig " + c.rig + " -o " + out, "hostile/" + c.name);
    EXPECT_EQ(run.status, 1) << c.name << ": " << run.out;
    EXPECT_NE(run.out.find(c.expect), std::string::npos) << c.name << ": " << run.out;
    EXPECT_FALSE(fs::exists(out)) << c.name;
  }
  // Only the inputs and the tool's messages are there: no partial or temporary file.
  for (const auto& entry : fs::directory_iterator(file("hostile"))) {
    const std::string name = entry.path().filename().string();
    EXPECT_TRUE(name.ends_with(".log") || name.ends_with(".out")) << name;
  }
  // An empty selection and an unwritable output say so too.
  ExportRun run = run_export(file("arm.log") + " --rig arm -o " + file("late.glb") + " --from 5", "late");
  EXPECT_EQ(run.status, 1);
  EXPECT_NE(run.out.find("no frame in the selected time range"), std::string::npos) << run.out;
  run = run_export(file("arm.log") + " --rig arm -o " + file("no/such/dir/x.glb"), "nodir");
  EXPECT_EQ(run.status, 1);
  EXPECT_NE(run.out.find("no/such/dir/x.glb"), std::string::npos) << run.out;
}

// The check can fail: the same export with one POSITION minimum moved is an
// error for the validator (glTF 2.0 §3.6.2.5: min and max are the exact bounds).
TEST_F(ExportToolTest, TheValidatorCatchesAWrongBound) {
  if (std::string(SINEW_NODE).empty()) GTEST_SKIP() << "node is missing: install it (scripts/install-deps.sh test)";
  const ExportRun run = run_export(file("arm.log") + " --rig arm -o " + file("bound.glb") + " --every 50", "bound");
  ASSERT_EQ(run.status, 0) << run.out;
  ASSERT_EQ(validator_errors(file("bound.glb"), file("bound.validator.json")), 0);
  std::vector<uint8_t> bytes = read_file_bytes(file("bound.glb"));
  ParsedGlb glb;
  ASSERT_EQ(parse_glb(bytes, &glb), "");
  glb.doc["accessors"][0]["min"][0] = glb.doc["accessors"][0]["min"][0].get<double>() - 1.0;
  std::string json = glb.doc.dump();
  json.resize((json.size() + 3) / 4 * 4, ' ');
  std::vector<uint8_t> out(bytes.begin(), bytes.begin() + 12);
  for (const uint32_t word : {static_cast<uint32_t>(json.size()), 0x4E4F534Au})
    for (int b = 0; b < 4; ++b) out.push_back(static_cast<uint8_t>(word >> (8 * b)));
  out.insert(out.end(), json.begin(), json.end());
  out.insert(out.end(), bytes.begin() + 20 + glb.json_length, bytes.end());
  for (int b = 0; b < 4; ++b) out[8 + static_cast<size_t>(b)] = static_cast<uint8_t>(out.size() >> (8 * b));
  std::ofstream(file("broken.glb"), std::ios::binary)
      .write(reinterpret_cast<const char*>(out.data()), static_cast<std::streamsize>(out.size()));
  EXPECT_GT(validator_errors(file("broken.glb"), file("broken.validator.json"), false), 0);
}

TEST(PoseGlb, AnAnimationPlayedThroughTheLayersExportsAndValidates) {
  const std::string dir = testing::TempDir() + "/export_pose";
  fs::remove_all(dir);
  fs::create_directories(dir);
  const std::string glb_path = dir + "/simple.glb";
  const ExportRun run = export_run(std::string(SINEW_POSE_EXE) + " --spec " + SINEW_TEST_DATA_DIR +
                                       "/rigged_simple_layers.toml --animation 0 --fps 5 --glb " + glb_path,
                                   dir + "/pose.out");
  ASSERT_EQ(run.status, 0) << run.out;
  ParsedGlb glb;
  ASSERT_EQ(parse_glb(read_file_bytes(glb_path), &glb), "");
  const nlohmann::json& prim = glb.doc["meshes"][0]["primitives"][0];
  ASSERT_GE(prim["targets"].size(), 3u);
  const std::vector<float> first = accessor_floats(glb, prim["targets"][0]["POSITION"].get<size_t>()),
                           last = accessor_floats(glb, prim["targets"].back()["POSITION"].get<size_t>());
  double moved = 0;
  for (size_t i = 0; i < first.size(); ++i) moved = std::max(moved, std::fabs(double{first[i]} - double{last[i]}));
  EXPECT_GT(moved, 1e-3) << "the animation bends the model";
  std::printf("sinew-pose --glb: %zu frames, largest vertex move %.4f\n", prim["targets"].size(), moved);
  EXPORT_VALIDATE(glb_path, dir + "/pose.validator.json");
}

// A motion file through the built-in arm: the elbow node's rotation keys
// follow the commanded angle. The elbow turns 90 degrees from its rest
// rotation by the last frame, so |<rest, q>| = cos(45 deg) (the quaternion
// of the relative turn has w = cos(angle / 2)).
TEST(PoseGlb, AMotionFileTurnsTheElbowNode) {
  const std::string dir = testing::TempDir() + "/export_pose_motion";
  fs::remove_all(dir);
  fs::create_directories(dir);
  std::ofstream(dir + "/arm.toml") << "[rig]\nsource = \"builtin:arm\"\n";
  std::ofstream(dir + "/elbow.csv") << "time,elbow.0\n0,0\n0.5,90\n";
  const std::string glb_path = dir + "/elbow.glb";
  const ExportRun run = export_run(std::string(SINEW_POSE_EXE) + " --spec " + dir + "/arm.toml --motion " + dir +
                                       "/elbow.csv --fps 10 --glb " + glb_path + " --out " + dir + "/elbow.csv.out",
                                   dir + "/pose.out");
  ASSERT_EQ(run.status, 0) << run.out;
  EXPECT_TRUE(fs::exists(dir + "/elbow.csv.out")) << "--out still writes the CSV beside the glb";
  ParsedGlb glb;
  ASSERT_EQ(parse_glb(read_file_bytes(glb_path), &glb), "");
  ASSERT_EQ(glb.doc["meshes"][0]["primitives"][0]["targets"].size(), 6u);  // 0, 0.1, ..., 0.5 s
  size_t elbow = 0;
  for (size_t n = 0; n < glb.doc["nodes"].size(); ++n)
    if (glb.doc["nodes"][n]["name"] == "elbow") elbow = n;
  ASSERT_GT(elbow, 0u) << "no elbow node";
  const nlohmann::json& rest = glb.doc["nodes"][elbow]["rotation"];
  const nlohmann::json& anim = glb.doc["animations"][0];
  std::vector<float> keys;
  for (const auto& channel : anim["channels"])
    if (channel["target"]["node"] == elbow && channel["target"]["path"] == "rotation")
      keys = accessor_floats(glb, anim["samplers"][channel["sampler"].get<size_t>()]["output"].get<size_t>());
  ASSERT_EQ(keys.size(), 24u);
  double first = 0, last = 0;
  for (size_t c = 0; c < 4; ++c) {
    first += rest[c].get<double>() * double{keys[c]};
    last += rest[c].get<double>() * double{keys[20 + c]};
  }
  EXPECT_NEAR(std::fabs(first), 1.0, 1e-6) << "at rest at 0 s";
  EXPECT_NEAR(std::fabs(last), std::sqrt(0.5), 1e-5) << "90 degrees at 0.5 s";
  EXPORT_VALIDATE(glb_path, dir + "/pose.validator.json");
}

}  // namespace
}  // namespace sinew::test
