// Writes the seed corpora of frame_log_reader_fuzz and udp_receiver_fuzz with
// the project's own encoders (the frame-log writer, the pose codec and the UDP
// datagram header), prefixed with the harness's mode byte:
//   sinew-fuzz-seeds OUT_DIR   (writes OUT_DIR/frame_log/* and OUT_DIR/udp/*)
#include <unistd.h>

#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "hal/output/frame_log_writer.hpp"
#include "hal/output/pose_codec.hpp"
#include "hal/output/udp_datagram.hpp"
#include "tests/hal/output/datagrams.hpp"

namespace {

using namespace sinew::hal::output;
namespace fs = std::filesystem;

// A small pose: `vertices` vertices, 2 inputs, positions and normals varying with the tick.
struct Pose {
  std::vector<int32_t> position[3], normal[3], input;
  std::vector<uint8_t> status;
  sinew::hal::PoseFrame frame;
  Pose(uint32_t vertices, uint64_t tick, bool normals) {
    for (int a = 0; a < 3; ++a) {
      for (uint32_t v = 0; v < vertices; ++v) {
        position[a].push_back(static_cast<int32_t>((v + 1) * 1000u * static_cast<uint32_t>(a + 1) + tick));
        normal[a].push_back(a == 2 ? 1 << 30 : 0);
      }
      frame.position[a] = position[a].data();
      if (normals) frame.normal[a] = normal[a].data();
    }
    input = {static_cast<int32_t>(tick * 100), -5000};
    status = {sinew::hal::kJointOk, sinew::hal::kJointClampedStatus};
    frame.tick = tick;
    frame.timestamp_ns = 1000000 * (tick + 1);
    frame.length_exponent = -3;
    frame.vertex_count = vertices;
    frame.input_count = 2;
    frame.input_value = input.data();
    frame.input_status = status.data();
  }
};

FrameShape shape(uint32_t vertices, bool normals) {
  FrameShape s;
  s.vertex_count = vertices;
  s.input_count = 2;
  s.length_exponent = -3;
  s.normals = normals;
  return s;
}

void write_file(const fs::path& path, uint8_t mode, const std::vector<uint8_t>& bytes) {
  std::ofstream out(path, std::ios::binary);
  out.put(static_cast<char>(mode));
  out.write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
  if (!out) std::fprintf(stderr, "cannot write %s\n", path.c_str()), std::exit(1);
}

std::vector<uint8_t> log_bytes(uint32_t vertices, bool normals, int records, const FrameLogOptions& options = {}) {
  const fs::path tmp = fs::temp_directory_path() / ("sinew-seed-" + std::to_string(getpid()) + ".log");
  fs::remove(tmp);
  FrameLogWriter writer;
  std::string error;
  if (!writer.open(tmp.string(), shape(vertices, normals), options, &error))
    std::fprintf(stderr, "%s\n", error.c_str()), std::exit(1);
  for (int t = 0; t < records; ++t) writer.write(Pose(vertices, static_cast<uint64_t>(t), normals).frame);
  writer.close();
  std::ifstream in(tmp, std::ios::binary);
  std::vector<uint8_t> bytes{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
  fs::remove(tmp);
  return bytes;
}

// Datagrams of one frame, split into fragments of at most `fragment` payload bytes.
std::vector<std::vector<uint8_t>> datagrams(const Pose& pose, const FrameShape& s, uint32_t stream, uint64_t sequence,
                                            size_t fragment) {
  std::vector<uint8_t> payload(max_pose_payload_bytes(s));
  payload.resize(encode_pose(pose.frame, s, payload));
  return sinew::test::fragment_frame(payload, stream, sequence, fragment);
}

// The harness's input: each datagram as a 2-byte little-endian length and its bytes.
std::vector<uint8_t> stream_bytes(const std::vector<std::vector<uint8_t>>& list) {
  std::vector<uint8_t> out;
  for (const auto& d : list) {
    out.push_back(static_cast<uint8_t>(d.size() & 0xFF));
    out.push_back(static_cast<uint8_t>(d.size() >> 8));
    out.insert(out.end(), d.begin(), d.end());
  }
  return out;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) return std::fprintf(stderr, "usage: %s OUT_DIR\n", argv[0]), 2;
  const fs::path root = argv[1];
  fs::create_directories(root / "frame_log");
  fs::create_directories(root / "udp");

  write_file(root / "frame_log" / "three_records", 0, log_bytes(3, false, 3));
  write_file(root / "frame_log" / "normals", 0, log_bytes(2, true, 2));
  write_file(root / "frame_log" / "header_only", 0, log_bytes(4, false, 0));
  std::vector<uint8_t> torn = log_bytes(3, false, 2);
  torn.resize(torn.size() - 7);
  write_file(root / "frame_log" / "torn_tail", 1, torn);
  // Version 2: a metadata block after the header (sinewd's run description).
  FrameLogOptions described;
  described.metadata = "rig arm 0123456789abcdef\nrate_hz 1000\nlayers metaballs barnet\n";
  write_file(root / "frame_log" / "metadata", 1, log_bytes(3, false, 2, described));
  // Compressed records: a key, deltas, and a key again (key_every_frames 3).
  FrameLogOptions zstd = described;
  zstd.compress = true;
  zstd.key_every_frames = 3;
  write_file(root / "frame_log" / "zstd_keys_and_deltas", 1, log_bytes(4, true, 7, zstd));
  zstd.metadata.clear();
  write_file(root / "frame_log" / "zstd_plain_header", 1, log_bytes(3, false, 3, zstd));

  const FrameShape plain = shape(3, false), with_normals = shape(2, true);
  const auto one = datagrams(Pose(3, 0, false), plain, 0x01020304, 0, 1400);
  write_file(root / "udp" / "single_fragment", 0, stream_bytes(one));
  // Two frames in 48-byte fragments, the second frame's fragments reversed and
  // interleaved with a duplicate and a frame from another stream.
  auto first = datagrams(Pose(3, 1, false), plain, 0x01020304, 1, 48);
  auto second = datagrams(Pose(3, 2, false), plain, 0x01020304, 2, 48);
  std::vector<std::vector<uint8_t>> mixed = first;
  mixed.push_back(first.front());
  for (auto it = second.rbegin(); it != second.rend(); ++it) mixed.push_back(*it);
  for (const auto& d : datagrams(Pose(2, 9, true), with_normals, 0x0A0B0C0D, 7, 64)) mixed.push_back(d);
  write_file(root / "udp" / "fragments", 0, stream_bytes(mixed));
  // A lost frame (sequence 4 missing) with a frame-size limit and a stream filter.
  std::vector<std::vector<uint8_t>> gap = datagrams(Pose(3, 3, false), plain, 0x01020304, 3, 1400);
  for (const auto& d : datagrams(Pose(3, 5, false), plain, 0x01020304, 5, 100)) gap.push_back(d);
  write_file(root / "udp" / "lost_frame", 0x18, stream_bytes(gap));
  return 0;
}
