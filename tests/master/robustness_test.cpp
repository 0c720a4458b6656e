// Bad input gives an error, never a crash or a hang: random SII images and
// random mailbox replies (run under ASan/UBSan in CI).
#include <gtest/gtest.h>

#include <random>

#include "master/coe_client.hpp"
#include "master/sii.hpp"
#include "master_fixture.hpp"

namespace ecat::master::test {
namespace {

TEST(SiiRobustness, RandomImagesNeverCrash) {
  std::mt19937 rng(1234);
  const auto good = test_sii_image();
  for (int i = 0; i < 2000; ++i) {
    std::vector<std::uint8_t> img = good;
    // Flip a few bytes in the category area, sometimes truncate.
    const int flips = 1 + static_cast<int>(rng() % 8);
    for (int f = 0; f < flips; ++f) {
      img[sii::kFixedAreaBytes + rng() % (img.size() - sii::kFixedAreaBytes)] = static_cast<std::uint8_t>(rng());
    }
    if (rng() % 3 == 0) img.resize(rng() % img.size());
    auto parsed = parse_sii(img);
    (void)parsed;
    (void)sii_image_length(img);
  }
  SUCCEED();
}

class MailboxRobustness : public MasterFixture {};

TEST_F(MailboxRobustness, RandomRepliesGiveErrorsNotCrashes) {
  scan_and_mailbox();
  std::mt19937 rng(99);
  std::vector<std::uint8_t> reply;
  fake.on_mailbox = [&](std::vector<std::uint8_t>) { return std::vector<std::vector<std::uint8_t>>{reply}; };
  CoeClient coe(master, 0);
  for (int i = 0; i < 120; ++i) {
    const std::size_t len = rng() % 122;
    reply.assign(6 + len, 0);
    for (auto& b : reply) b = static_cast<std::uint8_t>(rng());
    // Header: length field random but sometimes plausible, type CoE mostly.
    store_le(reply.data(), static_cast<std::uint16_t>(rng() % 2 == 0 ? len : rng() % 200));
    reply[5] = static_cast<std::uint8_t>((rng() % 4 == 0 ? rng() % 16 : 3) | 0x10);
    (void)coe.upload(0x1018, 1);
    (void)coe.od_list();
    // Drain whatever is left so the next round starts clean.
    fake.replies.clear();
    fake.mem[0x080D] = 0;
    fake.mem[0x0805] = 0;
  }
  SUCCEED();
}

}  // namespace
}  // namespace ecat::master::test
