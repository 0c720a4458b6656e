// Bad input must give a clear error, never a crash or a hang: random and
// mutated mailbox frames through the whole CoE stack (run under ASan/UBSan in CI).
#include <gtest/gtest.h>

#include <random>

#include "coe/foe_server.hpp"
#include "tests/coe/rig.hpp"

namespace ecat::coe {
namespace {

using test::Frame;

TEST(Robustness, RandomAndMutatedFramesAlwaysGetAWellFormedAnswerOrNone) {
  test::Rig rig;
  std::mt19937 rng(12345);
  const std::vector<Frame> seeds = {
      test::mbx(3, 1, test::sdo(0x40, 0x1018, 1)),
      test::mbx(3, 1, test::sdo(0x21, 0x2002, 0, 300, Frame(100, 7))),
      test::mbx(3, 1, test::sdo(0x50, 0x1C12, 0)),
      test::mbx(3, 1, test::sdo(0x31, 0x1600, 0, 6, {1, 0, 0x10, 0, 0, 0x70})),
      test::mbx(3, 1, {0x00, 0x80, 0x01, 0x00, 0x00, 0x00, 0x01, 0x00}),
      test::mbx(3, 1, {0x00, 0x80, 0x05, 0x00, 0x00, 0x00, 0x00, 0x20, 0x00, 0x7F}),
      test::mbx(3, 1, test::segment(0x00, {1, 2, 3})),
  };
  for (int i = 0; i < 20000; ++i) {
    Frame f;
    if (i % 4 == 0) {
      f.resize(rng() % test::kMbxLen);
      for (auto& b : f) b = static_cast<std::uint8_t>(rng());
    } else {
      f = seeds[rng() % seeds.size()];
      const int flips = 1 + static_cast<int>(rng() % 4);
      for (int k = 0; k < flips; ++k) f[rng() % f.size()] = static_cast<std::uint8_t>(rng());
    }
    f.resize(test::kMbxLen);
    ASSERT_TRUE(rig.esc.master_write(f));
    rig.mailbox.poll(Nanoseconds{0});
    while (auto reply = rig.esc.master_read()) {
      const std::size_t len = (*reply)[0] | ((*reply)[1] << 8);
      ASSERT_LE(len + 6, reply->size());
      const std::uint8_t type = (*reply)[5] & 0x0F;
      ASSERT_TRUE(type == 0 || type == 3) << int(type);
      if (type == 0) {
        ASSERT_EQ(len, 4u);
        const int code = (*reply)[8] | ((*reply)[9] << 8);
        ASSERT_GE(code, 1);
        ASSERT_LE(code, 8);
      }
      rig.mailbox.poll(Nanoseconds{0});
    }
    ASSERT_FALSE(rig.esc.full(0));
  }
}

}  // namespace
}  // namespace ecat::coe
