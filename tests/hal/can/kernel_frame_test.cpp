// CanFrame <-> struct can_frame / canfd_frame and CAN_RAW_FILTER entries.
#include "hal/can/kernel_frame.hpp"

#include <gtest/gtest.h>
#include <linux/can.h>
#include <linux/can/error.h>

#include <cstring>

namespace sinew::hal::can {
namespace {

TEST(KernelFrame, ClassicStandardAndExtended) {
  can_frame k{};
  k.can_id = 0x123;
  k.len = 3;
  k.data[0] = 1;
  k.data[2] = 3;
  CanFrame f;
  ASSERT_TRUE(from_kernel(&k, CAN_MTU, 42, f));
  EXPECT_EQ(f.id, 0x123u);
  EXPECT_FALSE(f.extended);
  EXPECT_FALSE(f.fd);
  EXPECT_EQ(f.len, 3);
  EXPECT_EQ(f.data[2], 3);
  EXPECT_EQ(f.timestamp_ns, 42u);

  k.can_id = 0x1ABCDEF0 | CAN_EFF_FLAG;
  ASSERT_TRUE(from_kernel(&k, CAN_MTU, 0, f));
  EXPECT_TRUE(f.extended);
  EXPECT_EQ(f.id, 0x1ABCDEF0u);
}

TEST(KernelFrame, RemoteErrorAndRawDlc) {
  can_frame k{};
  k.can_id = 0x321 | CAN_RTR_FLAG;
  k.len = 4;
  CanFrame f;
  ASSERT_TRUE(from_kernel(&k, CAN_MTU, 0, f));
  EXPECT_EQ(f.kind, FrameKind::kRemote);
  EXPECT_EQ(f.len, 4);

  k = can_frame{};
  k.can_id = CAN_ERR_FLAG | CAN_ERR_BUSOFF;
  k.len = CAN_ERR_DLC;
  ASSERT_TRUE(from_kernel(&k, CAN_MTU, 0, f));
  EXPECT_EQ(f.kind, FrameKind::kError);
  EXPECT_EQ(f.id, static_cast<uint32_t>(CAN_ERR_BUSOFF));

  k = can_frame{};
  k.can_id = 0x10;
  k.len = 8;
  k.len8_dlc = 0xC;
  ASSERT_TRUE(from_kernel(&k, CAN_MTU, 0, f));
  EXPECT_EQ(f.len8_dlc, 0xC);
}

TEST(KernelFrame, CanFd) {
  canfd_frame k{};
  k.can_id = 0x180;
  k.len = 64;
  k.flags = CANFD_BRS | CANFD_FDF;
  k.data[63] = 0x77;
  CanFrame f;
  ASSERT_TRUE(from_kernel(&k, CANFD_MTU, 0, f));
  EXPECT_TRUE(f.fd);
  EXPECT_EQ(f.len, 64);
  EXPECT_EQ(f.fd_flags, CANFD_BRS | CANFD_FDF);
  EXPECT_EQ(f.data[63], 0x77);
}

TEST(KernelFrame, UnexpectedSizeIsRefused) {
  canfd_frame k{};
  CanFrame f;
  EXPECT_FALSE(from_kernel(&k, 10, 0, f));
  EXPECT_FALSE(from_kernel(&k, 0, 0, f));
}

TEST(KernelFrame, RoundTripsThroughTheKernelStructs) {
  CanFrame frames[4];
  frames[0].id = 0x7FF;
  frames[0].len = 8;
  frames[0].len8_dlc = 0xF;
  frames[0].data[7] = 9;
  frames[1].id = 0x1FFFFFFF;
  frames[1].extended = true;
  frames[1].kind = FrameKind::kRemote;
  frames[1].len = 2;
  frames[2].id = 0x180;
  frames[2].fd = true;
  frames[2].fd_flags = CANFD_BRS;
  frames[2].len = 48;
  frames[2].data[47] = 0xAB;
  frames[3].kind = FrameKind::kError;
  frames[3].id = CAN_ERR_CRTL;
  frames[3].len = 8;
  frames[3].data[1] = CAN_ERR_CRTL_RX_PASSIVE;
  for (const CanFrame& a : frames) {
    canfd_frame k;
    const size_t bytes = to_kernel(a, k);
    ASSERT_EQ(bytes, a.fd ? CANFD_MTU : CAN_MTU);
    CanFrame b;
    ASSERT_TRUE(from_kernel(&k, bytes, 0, b));
    EXPECT_EQ(a.id, b.id);
    EXPECT_EQ(a.kind, b.kind);
    EXPECT_EQ(a.extended, b.extended);
    EXPECT_EQ(a.fd, b.fd);
    EXPECT_EQ(a.len, b.len);
    EXPECT_EQ(a.len8_dlc, b.len8_dlc);
    if (a.kind != FrameKind::kRemote) {
      EXPECT_EQ(a.data, b.data);
    }
  }
}

TEST(KernelFrame, MalformedFramesAreNotWritten) {
  CanFrame f;
  f.id = 0x800;  // not 11-bit
  canfd_frame k;
  EXPECT_EQ(to_kernel(f, k), 0u);
  f.id = 1;
  f.len = 9;  // classic
  EXPECT_EQ(to_kernel(f, k), 0u);
  f.fd = true;
  f.len = 9;  // no CAN FD DLC gives 9 bytes
  EXPECT_EQ(to_kernel(f, k), 0u);
}

TEST(KernelFrame, FiltersMatchExactlyOneFormat) {
  const FrameId ids[] = {{0x100, false}, {0x100, true}};
  const auto filters = kernel_filters(ids);
  ASSERT_EQ(filters.size(), 2u);
  EXPECT_EQ(filters[0].can_id, 0x100u);
  EXPECT_EQ(filters[0].can_mask, CAN_EFF_FLAG | CAN_SFF_MASK);
  EXPECT_EQ(filters[1].can_id, 0x100u | CAN_EFF_FLAG);
  EXPECT_EQ(filters[1].can_mask, CAN_EFF_FLAG | CAN_EFF_MASK);
  // The kernel's rule: (received_id & mask) == (can_id & mask). A remote
  // frame passes (RTR is not in the mask) so the decoder can count it.
  auto matches = [](const can_filter& f, canid_t id) { return (id & f.can_mask) == (f.can_id & f.can_mask); };
  EXPECT_TRUE(matches(filters[0], 0x100));
  EXPECT_TRUE(matches(filters[0], 0x100 | CAN_RTR_FLAG));
  EXPECT_FALSE(matches(filters[0], 0x100 | CAN_EFF_FLAG));
  EXPECT_FALSE(matches(filters[0], 0x101));
  EXPECT_TRUE(matches(filters[1], 0x100 | CAN_EFF_FLAG));
}

}  // namespace
}  // namespace sinew::hal::can
