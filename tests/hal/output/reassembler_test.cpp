// Reassembly of UDP stream datagrams without a network: fragment order,
// duplicates, losses, stale frames, corruption, sender restarts.
#include "host_tools/receiver/reassembler.hpp"

#include <gtest/gtest.h>

#include "datagrams.hpp"

namespace sinew::test {
namespace {

using receiver::Reassembler;

constexpr size_t kFragment = 100;
constexpr uint32_t kStream = 77;

std::vector<uint8_t> delivered(const Reassembler& r) { return {r.frame_payload().begin(), r.frame_payload().end()}; }

// Feeds datagrams; returns the sequence numbers of the frames delivered, checking their bytes.
std::vector<uint64_t> feed_all(Reassembler& r, const std::vector<Datagram>& datagrams, size_t payload_bytes) {
  std::vector<uint64_t> out;
  for (const Datagram& d : datagrams)
    if (r.feed(d)) {
      out.push_back(r.frame_sequence());
      EXPECT_EQ(delivered(r), payload_for(r.frame_sequence(), payload_bytes)) << "frame " << r.frame_sequence();
    }
  return out;
}

TEST(Reassembler, SingleDatagramFrame) {
  Reassembler r;
  const auto d = fragment_frame(payload_for(0, 60), kStream, 0, kFragment);
  ASSERT_EQ(d.size(), 1u);
  EXPECT_EQ(feed_all(r, d, 60), std::vector<uint64_t>{0});
  EXPECT_EQ(r.stream_id(), kStream);
  EXPECT_EQ(r.stats().frames_delivered, 1u);
}

TEST(Reassembler, FragmentsInAnyOrder) {
  Reassembler r;
  auto d = fragment_frame(payload_for(5, 950), kStream, 5, kFragment);
  ASSERT_EQ(d.size(), 10u);
  std::reverse(d.begin(), d.end());
  std::swap(d[2], d[7]);
  EXPECT_EQ(feed_all(r, d, 950), std::vector<uint64_t>{5});
  EXPECT_EQ(r.stats().frames_lost, 0u);
}

TEST(Reassembler, DuplicatesAreIgnored) {
  Reassembler r;
  auto d = fragment_frame(payload_for(1, 250), kStream, 1, kFragment);
  std::vector<Datagram> sent = {d[0], d[0], d[1], d[1], d[2], d[2]};
  EXPECT_EQ(feed_all(r, sent, 250), std::vector<uint64_t>{1});
  EXPECT_EQ(r.stats().duplicate_fragments, 3u);  // two before completion, one after
}

TEST(Reassembler, AMissingFragmentIsALossNeverAWrongFrame) {
  Reassembler r;
  std::vector<Datagram> sent;
  for (uint64_t s = 0; s < 4; ++s) {
    auto d = fragment_frame(payload_for(s, 450), kStream, s, kFragment);
    if (s == 1) d.erase(d.begin() + 3);  // fragment 3 of frame 1 never arrives
    sent.insert(sent.end(), d.begin(), d.end());
  }
  EXPECT_EQ(feed_all(r, sent, 450), (std::vector<uint64_t>{0, 2, 3}));
  EXPECT_EQ(r.stats().frames_lost, 1u);
  EXPECT_EQ(r.stats().frames_incomplete, 1u);
}

TEST(Reassembler, InterleavedFramesCompleteInTheirOwnOrder) {
  Reassembler r;
  const auto a = fragment_frame(payload_for(0, 300), kStream, 0, kFragment);
  const auto b = fragment_frame(payload_for(1, 300), kStream, 1, kFragment);
  std::vector<Datagram> sent;
  for (size_t i = 0; i < a.size(); ++i) {
    sent.push_back(b[i]);
    sent.push_back(a[i]);
  }
  // b's last fragment precedes a's: b completes first, then a is stale.
  EXPECT_EQ(feed_all(r, sent, 300), std::vector<uint64_t>{1});
  EXPECT_EQ(r.stats().frames_lost, 0u);  // nothing was delivered before b
  // With a's last fragment first instead, both are delivered in order.
  Reassembler r2;
  std::vector<Datagram> sent2;
  for (size_t i = 0; i < a.size(); ++i) {
    sent2.push_back(a[i]);
    sent2.push_back(b[i]);
  }
  EXPECT_EQ(feed_all(r2, sent2, 300), (std::vector<uint64_t>{0, 1}));
}

TEST(Reassembler, AFrameOvertakenByANewerOneIsStale) {
  Reassembler r;
  std::vector<Datagram> sent;
  for (const uint64_t s : {0u, 2u, 1u, 3u}) {  // frame 1 arrives after frame 2
    const auto d = fragment_frame(payload_for(s, 250), kStream, s, kFragment);
    sent.insert(sent.end(), d.begin(), d.end());
  }
  EXPECT_EQ(feed_all(r, sent, 250), (std::vector<uint64_t>{0, 2, 3}));
  EXPECT_EQ(r.stats().frames_lost, 1u);
  EXPECT_EQ(r.stats().frames_out_of_order, 1u);  // counted once, though it had 3 fragments
  EXPECT_EQ(r.stats().stale_fragments, 3u);
}

TEST(Reassembler, CorruptDatagramsAreRejected) {
  Reassembler r;
  auto d = fragment_frame(payload_for(0, 250), kStream, 0, kFragment);
  for (size_t at = 0; at < d[1].size(); ++at) {
    Datagram bad = d[1];
    bad[at] ^= 0x10;
    EXPECT_FALSE(r.feed(bad)) << "byte " << at;
  }
  EXPECT_EQ(r.stats().bad_datagrams, d[1].size());
  Datagram truncated = d[2];
  truncated.pop_back();
  EXPECT_FALSE(r.feed(truncated));
  EXPECT_EQ(feed_all(r, d, 250), std::vector<uint64_t>{0});
}

TEST(Reassembler, FollowsANewStreamAfterARestart) {
  Reassembler r;
  feed_all(r, fragment_frame(payload_for(900, 150), kStream, 900, kFragment), 150);
  EXPECT_EQ(feed_all(r, fragment_frame(payload_for(0, 150), kStream + 1, 0, kFragment), 150), std::vector<uint64_t>{0});
  EXPECT_EQ(r.stats().stream_restarts, 1u);
  EXPECT_EQ(r.stats().frames_lost, 0u);
}

TEST(Reassembler, SequenceStartingOverIsARestart) {
  Reassembler r;
  feed_all(r, fragment_frame(payload_for(5000, 150), kStream, 5000, kFragment), 150);
  EXPECT_EQ(feed_all(r, fragment_frame(payload_for(0, 150), kStream, 0, kFragment), 150), std::vector<uint64_t>{0});
  EXPECT_EQ(r.stats().stream_restarts, 1u);
}

TEST(Reassembler, AStreamFilterIgnoresOthers) {
  receiver::ReassemblerOptions options;
  options.stream_id = kStream;
  Reassembler r(options);
  EXPECT_TRUE(feed_all(r, fragment_frame(payload_for(0, 150), kStream + 1, 0, kFragment), 150).empty());
  EXPECT_EQ(r.stats().foreign_datagrams, 2u);
  EXPECT_EQ(feed_all(r, fragment_frame(payload_for(1, 150), kStream, 1, kFragment), 150), std::vector<uint64_t>{1});
}

TEST(Reassembler, FragmentsDisagreeingWithTheirFrameAreRejected) {
  Reassembler r;
  const auto a = fragment_frame(payload_for(3, 300), kStream, 3, kFragment);
  const auto b = fragment_frame(payload_for(3, 400), kStream, 3, kFragment);  // same sequence, other size
  EXPECT_FALSE(r.feed(a[0]));
  EXPECT_FALSE(r.feed(b[1]));
  EXPECT_EQ(r.stats().inconsistent_fragments, 1u);
  EXPECT_FALSE(r.feed(a[1]));
  EXPECT_TRUE(r.feed(a[2]));
  EXPECT_EQ(delivered(r), payload_for(3, 300));
}

TEST(Reassembler, OldestFrameGivesWayWhenSlotsRunOut) {
  receiver::ReassemblerOptions options;
  options.slots = 2;
  Reassembler r(options);
  std::vector<Datagram> sent;
  for (uint64_t s = 0; s < 3; ++s) sent.push_back(fragment_frame(payload_for(s, 150), kStream, s, kFragment)[0]);
  for (uint64_t s = 0; s < 3; ++s) sent.push_back(fragment_frame(payload_for(s, 150), kStream, s, kFragment)[1]);
  // Frame 0 is evicted by frame 2's first fragment; 1 and 2 complete.
  EXPECT_EQ(feed_all(r, sent, 150), (std::vector<uint64_t>{1, 2}));
  EXPECT_EQ(r.stats().frames_incomplete, 1u);
}

}  // namespace
}  // namespace sinew::test
