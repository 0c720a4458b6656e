#include "coe/foe_server.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "tests/coe/rig.hpp"

namespace ecat::coe {
namespace {

using test::Frame;
using test::mbx;

Frame foe_frame(std::uint8_t opcode, std::uint32_t value, const Frame& rest = {}) {
  return test::concat({opcode, 0, static_cast<std::uint8_t>(value), static_cast<std::uint8_t>(value >> 8),
                       static_cast<std::uint8_t>(value >> 16), static_cast<std::uint8_t>(value >> 24)},
                      rest);
}
Frame name(const std::string& s) { return Frame(s.begin(), s.end()); }

class FoeTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir = std::filesystem::path(ECAT_BINARY_DIR) / "coe_foe_test" /
          ::testing::UnitTest::GetInstance()->current_test_info()->name();
    std::filesystem::remove_all(dir);
    std::filesystem::create_directories(dir);
    foe = std::make_unique<FoeServer>(options());
    rig.mailbox.add_service(*foe);
  }
  virtual FoeServer::Options options() { return FoeServer::Options{dir.string(), 200, 16}; }
  Frame request(const Frame& payload) {
    counter = MailboxHeader::next_counter(counter);
    auto reply = rig.request(mbx(4, counter, payload));
    if (!reply) return {};
    EXPECT_EQ((*reply)[5] & 0x0F, 4);
    return Frame(reply->begin() + 6, reply->end());
  }
  static std::uint32_t error_code(const Frame& f) {
    if (f.size() < 6 || f[0] != 5) return 0;
    return static_cast<std::uint32_t>(f[2] | (f[3] << 8) | (f[4] << 16) | (f[5] << 24));
  }

  test::Rig rig;
  std::filesystem::path dir;
  std::unique_ptr<FoeServer> foe;
  std::uint8_t counter = 0;
};

Frame pattern(std::size_t n) {
  Frame f(n);
  for (std::size_t i = 0; i < n; ++i) f[i] = static_cast<std::uint8_t>(i * 13);
  return f;
}

TEST_F(FoeTest, WriteThenReadBack) {
  const Frame data = pattern(190);  // 116 + 74 with a 128-byte mailbox
  EXPECT_EQ(request(foe_frame(2, 0, name("fw.bin"))), foe_frame(4, 0));
  EXPECT_EQ(request(foe_frame(3, 1, Frame(data.begin(), data.begin() + 116))), foe_frame(4, 1));
  EXPECT_FALSE(std::filesystem::exists(dir / "fw.bin"));  // not complete yet
  EXPECT_EQ(request(foe_frame(3, 2, Frame(data.begin() + 116, data.end()))), foe_frame(4, 2));
  ASSERT_TRUE(std::filesystem::exists(dir / "fw.bin"));
  EXPECT_FALSE(std::filesystem::exists(dir / "fw.bin.part"));
  EXPECT_EQ(std::filesystem::file_size(dir / "fw.bin"), 190u);

  Frame first = request(foe_frame(1, 0, name("fw.bin")));
  ASSERT_EQ(first.size(), 122u);
  EXPECT_EQ(Frame(first.begin(), first.begin() + 6), foe_frame(3, 1));
  Frame second = request(foe_frame(4, 1));
  ASSERT_EQ(second.size(), 6u + 74);
  EXPECT_EQ(Frame(second.begin(), second.begin() + 6), foe_frame(3, 2));
  Frame back(first.begin() + 6, first.end());
  back.insert(back.end(), second.begin() + 6, second.end());
  EXPECT_EQ(back, data);
  EXPECT_TRUE(request(foe_frame(4, 2)).empty());  // last ACK: nothing more
}

TEST_F(FoeTest, ExactMultipleEndsWithAnEmptyPacket) {
  const Frame data = pattern(116);
  EXPECT_EQ(request(foe_frame(2, 0, name("a"))), foe_frame(4, 0));
  EXPECT_EQ(request(foe_frame(3, 1, data)), foe_frame(4, 1));
  EXPECT_FALSE(std::filesystem::exists(dir / "a"));
  EXPECT_EQ(request(foe_frame(3, 2)), foe_frame(4, 2));
  EXPECT_EQ(std::filesystem::file_size(dir / "a"), 116u);
  EXPECT_EQ(request(foe_frame(1, 0, name("a"))).size(), 122u);
  EXPECT_EQ(request(foe_frame(4, 1)), foe_frame(3, 2));
}

TEST_F(FoeTest, UnsafeNamesAreRefused) {
  for (const char* bad : {"../etc", "a/b", ".hidden", "", "name-that-is-too-long", "sp ace"}) {
    EXPECT_EQ(error_code(request(foe_frame(2, 0, name(bad)))), 0x8002u) << bad;
    EXPECT_EQ(error_code(request(foe_frame(1, 0, name(bad)))), 0x8002u) << bad;
  }
  EXPECT_TRUE(std::filesystem::is_empty(dir));
}

TEST_F(FoeTest, ErrorsCarryFoECodes) {
  EXPECT_EQ(error_code(request(foe_frame(1, 0, name("missing")))), 0x8001u);
  EXPECT_EQ(error_code(request(foe_frame(3, 1, pattern(4)))), 0x8004u);  // data without a write
  EXPECT_EQ(request(foe_frame(2, 0, name("b"))), foe_frame(4, 0));
  EXPECT_EQ(error_code(request(foe_frame(3, 2, pattern(116)))), 0x8005u);  // packet 2 before 1
  EXPECT_FALSE(std::filesystem::exists(dir / "b.part"));
  EXPECT_EQ(request(foe_frame(2, 0, name("c"))), foe_frame(4, 0));
  EXPECT_EQ(request(foe_frame(3, 1, pattern(116))), foe_frame(4, 1));
  EXPECT_EQ(error_code(request(foe_frame(3, 2, pattern(116)))), 0x8003u);  // over 200 bytes
  EXPECT_FALSE(std::filesystem::exists(dir / "c"));
  EXPECT_FALSE(std::filesystem::exists(dir / "c.part"));
  // An ERR from the master ends a transfer silently.
  EXPECT_EQ(request(foe_frame(2, 0, name("d"))), foe_frame(4, 0));
  EXPECT_TRUE(request(foe_frame(5, 0x8000)).empty());
  EXPECT_FALSE(std::filesystem::exists(dir / "d.part"));
}

TEST_F(FoeTest, OfferedInBootstrap) {
  rig.esc.set_state(0x03);
  EXPECT_EQ(request(foe_frame(2, 0, name("boot.bin"))), foe_frame(4, 0));
}

// The state directory's budget (issue 20): 300 bytes, 3 files, with a
// 128-byte mailbox (116 data bytes per DATA) and a 1000-byte file limit.
class FoeQuotaTest : public FoeTest {
 protected:
  FoeServer::Options options() override { return FoeServer::Options{dir.string(), 1000, 16, &quota}; }
  // Writes `data` as `file` (DATA packets of 116 bytes); the last reply.
  Frame write(const std::string& file, const Frame& data) {
    EXPECT_EQ(request(foe_frame(2, 0, name(file))), foe_frame(4, 0));
    Frame last;
    std::uint32_t packet = 1;
    std::size_t at = 0;
    do {
      const std::size_t n = std::min<std::size_t>(116, data.size() - at);
      last = request(foe_frame(3, packet, Frame(data.begin() + at, data.begin() + at + n)));
      if (last != foe_frame(4, packet)) return last;
      at += n;
      ++packet;
      if (n < 116) break;
    } while (true);
    return last;
  }
  std::vector<std::uint8_t> contents(const std::string& file) const {
    std::ifstream in(dir / file, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
  }
  StorageQuota quota{{300, 3}};
};

TEST_F(FoeQuotaTest, BeyondTheBytesItIsDiskFullAndNothingPartialIsLeft) {
  const Frame a = pattern(190);
  EXPECT_EQ(write("a", a), foe_frame(4, 2));
  EXPECT_EQ(quota.used_bytes(), 190u);
  EXPECT_EQ(quota.used_files(), 1u);
  // 190 + 116 > 300: the first DATA of "b" is answered ERR 0x8003 "disk full".
  EXPECT_EQ(request(foe_frame(2, 0, name("b"))), foe_frame(4, 0));
  EXPECT_EQ(request(foe_frame(3, 1, pattern(116))), (Frame{0x05, 0x00, 0x03, 0x80, 0x00, 0x00}));
  EXPECT_FALSE(std::filesystem::exists(dir / "b"));
  EXPECT_FALSE(std::filesystem::exists(dir / "b.part"));
  EXPECT_EQ(contents("a"), a);  // the earlier file is intact
  EXPECT_EQ(quota.used_bytes(), 190u);
  EXPECT_EQ(quota.used_files(), 1u);
  // Exactly up to the limit is allowed: 190 + 110 = 300.
  EXPECT_EQ(write("b", pattern(110)), foe_frame(4, 1));
  EXPECT_EQ(quota.used_bytes(), 300u);
  EXPECT_EQ(quota.used_files(), 2u);
  // Replacing needs room for both copies while the transfer runs: one byte is too many.
  EXPECT_EQ(write("a", pattern(1)), (Frame{0x05, 0x00, 0x03, 0x80, 0x00, 0x00}));
  EXPECT_EQ(contents("a"), a);
  EXPECT_FALSE(std::filesystem::exists(dir / "a.part"));
  EXPECT_EQ(quota.used_bytes(), 300u);
}

TEST_F(FoeQuotaTest, BeyondTheFileCountItIsDiskFullAtTheWriteRequest) {
  EXPECT_EQ(write("x", pattern(3)), foe_frame(4, 1));
  EXPECT_EQ(write("y", pattern(3)), foe_frame(4, 1));
  EXPECT_EQ(write("z", pattern(3)), foe_frame(4, 1));
  EXPECT_EQ(quota.used_files(), 3u);
  EXPECT_EQ(request(foe_frame(2, 0, name("w"))), (Frame{0x05, 0x00, 0x03, 0x80, 0x00, 0x00}));
  EXPECT_FALSE(std::filesystem::exists(dir / "w.part"));
  // Once a file is gone (here: by hand, told to the ledger), a write fits
  // again; a transfer the master abandons gives its file and bytes back.
  std::filesystem::remove(dir / "z");
  quota.release_file(3);
  EXPECT_EQ(request(foe_frame(2, 0, name("w"))), foe_frame(4, 0));
  EXPECT_EQ(request(foe_frame(3, 1, pattern(116))), foe_frame(4, 1));
  EXPECT_EQ(quota.used_bytes(), 6u + 116u);
  EXPECT_TRUE(request(foe_frame(5, 0x8000)).empty());  // the master gives up
  EXPECT_FALSE(std::filesystem::exists(dir / "w.part"));
  EXPECT_EQ(quota.used_bytes(), 6u);
  EXPECT_EQ(quota.used_files(), 2u);
}

TEST_F(FoeQuotaTest, ReplacingAFileGivesTheOldOneBack) {
  EXPECT_EQ(write("a", pattern(190)), foe_frame(4, 2));
  EXPECT_EQ(write("a", pattern(100)), foe_frame(4, 1));  // 190 + 100 fit during the transfer
  EXPECT_EQ(quota.used_bytes(), 100u);
  EXPECT_EQ(quota.used_files(), 1u);
  EXPECT_EQ(contents("a"), pattern(100));
}

TEST_F(FoeQuotaTest, MakesTheFoeDirectoryOnFirstUse) {
  std::filesystem::remove_all(dir);
  EXPECT_EQ(write("fw", pattern(5)), foe_frame(4, 1));
  EXPECT_EQ(contents("fw"), pattern(5));
}

TEST(Foe, NotOfferedIsAMailboxError) {
  test::Rig rig;
  auto reply = rig.request(mbx(4, 1, foe_frame(1, 0, name("x"))));
  ASSERT_TRUE(reply);
  EXPECT_EQ(*reply, (Frame{0x04, 0x00, 0x00, 0x00, 0x00, 0x10, 0x01, 0x00, 0x02, 0x00}));
}

}  // namespace
}  // namespace ecat::coe

namespace ecat::coe {
namespace {

// Options::password: RRQ/WRQ must carry it; another one is ERR 0x800A (no
// rights, as SOES answers a wrong file password) and nothing is written.
class FoePasswordTest : public FoeTest {
 protected:
  FoeServer::Options options() override {
    FoeServer::Options o{dir.string(), 200, 16};
    o.password = 0x12345678;
    return o;
  }
};

TEST_F(FoePasswordTest, WrongPasswordIsNoRights) {
  EXPECT_EQ(error_code(request(foe_frame(2, 0, name("p.bin")))), 0x800Au);
  EXPECT_EQ(error_code(request(foe_frame(2, 0x12345679, name("p.bin")))), 0x800Au);
  EXPECT_FALSE(std::filesystem::exists(dir / "p.bin.part"));
  EXPECT_EQ(request(foe_frame(2, 0x12345678, name("p.bin"))), foe_frame(4, 0));
  EXPECT_EQ(request(foe_frame(3, 1, pattern(10))), foe_frame(4, 1));
  EXPECT_EQ(error_code(request(foe_frame(1, 0, name("p.bin")))), 0x800Au);
  EXPECT_EQ(request(foe_frame(1, 0x12345678, name("p.bin"))), foe_frame(3, 1, pattern(10)));
  // An unsafe name is still access denied, whatever the password.
  EXPECT_EQ(error_code(request(foe_frame(1, 0, name(".hidden")))), 0x8002u);
}

// Options::busy_replies: each RRQ/WRQ is answered BUSY N times - opcode 6,
// reserved 0, Done 0..N-1 (bytes 2-3), Entire N (bytes 4-5), no text - and
// served the N+1st time; errors found before (name, password) come at once.
class FoeBusyTest : public FoeTest {
 protected:
  FoeServer::Options options() override {
    FoeServer::Options o{dir.string(), 200, 16};
    o.busy_replies = 2;
    return o;
  }
};

TEST_F(FoeBusyTest, EachRequestIsBusyTwiceThenServed) {
  const Frame busy0{6, 0, 0, 0, 2, 0};
  const Frame busy1{6, 0, 1, 0, 2, 0};
  EXPECT_EQ(request(foe_frame(2, 0, name("b.bin"))), busy0);
  EXPECT_EQ(request(foe_frame(2, 0, name("b.bin"))), busy1);
  EXPECT_FALSE(std::filesystem::exists(dir / "b.bin.part"));
  EXPECT_EQ(request(foe_frame(2, 0, name("b.bin"))), foe_frame(4, 0));
  EXPECT_EQ(request(foe_frame(3, 1, pattern(10))), foe_frame(4, 1));
  // The read request is busy again, from Done 0.
  EXPECT_EQ(request(foe_frame(1, 0, name("b.bin"))), busy0);
  EXPECT_EQ(request(foe_frame(1, 0, name("b.bin"))), busy1);
  EXPECT_EQ(request(foe_frame(1, 0, name("b.bin"))), foe_frame(3, 1, pattern(10)));
  EXPECT_EQ(request(foe_frame(4, 1)), Frame{});  // the short packet ended it: no reply
  // A missing file is known only once the request is served.
  EXPECT_EQ(request(foe_frame(1, 0, name("none.bin"))), busy0);
  EXPECT_EQ(request(foe_frame(1, 0, name("none.bin"))), busy1);
  EXPECT_EQ(error_code(request(foe_frame(1, 0, name("none.bin")))), 0x8001u);
  // An unsafe name is refused at once.
  EXPECT_EQ(error_code(request(foe_frame(1, 0, name(".hidden")))), 0x8002u);
}

}  // namespace
}  // namespace ecat::coe
