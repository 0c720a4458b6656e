// The WKC of every command on one slave and on a line of three, from one
// table (ETG.1000.4 §5.4.3; Section I Table 5). Each slave has station
// address 0x1001+i, plain RAM at 0x1000 and one read+write FMMU for logical
// 0x10000 onto 0x1000.
#include <gtest/gtest.h>

#include "esc_fixture.hpp"

namespace ecat::esc::test {
namespace {

struct Case {
  Command command;
  std::uint32_t address;
  std::uint16_t wkc_one;    // line of one
  std::uint16_t wkc_three;  // line of three
};

constexpr std::uint32_t kLogical = 0x10000;

class CommandWkc : public ::testing::TestWithParam<Case> {};

Line& prepared(Line& line) {
  assign_stations(line);
  for (std::uint16_t i = 0; i < line.escs.size(); ++i) {
    config_fmmu(line.segment, static_cast<std::uint16_t>(0x1001 + i), 0, kLogical, 4, 0, 7, 0x1000, 0, 3);
  }
  return line;
}

TEST_P(CommandWkc, OnOneAndThree) {
  const Case& c = GetParam();
  Line one(1);
  EXPECT_EQ(transact(prepared(one).segment, c.command, c.address, 4).wkc, c.wkc_one);
  Line three(3);
  EXPECT_EQ(transact(prepared(three).segment, c.command, c.address, 4).wkc, c.wkc_three);
}

INSTANTIATE_TEST_SUITE_P(
    All, CommandWkc,
    ::testing::Values(Case{Command::Nop, device_address(0, 0x1000), 0, 0},
                      Case{Command::Aprd, device_address(0, 0x1000), 1, 1},
                      Case{Command::Apwr, device_address(0, 0x1000), 1, 1},
                      Case{Command::Aprw, device_address(0, 0x1000), 3, 3},
                      Case{Command::Fprd, device_address(0x1001, 0x1000), 1, 1},
                      Case{Command::Fpwr, device_address(0x1001, 0x1000), 1, 1},
                      Case{Command::Fprw, device_address(0x1001, 0x1000), 3, 3},
                      Case{Command::Brd, device_address(0, 0x1000), 1, 3},
                      Case{Command::Bwr, device_address(0, 0x1000), 1, 3},
                      Case{Command::Brw, device_address(0, 0x1000), 3, 9},
                      Case{Command::Lrd, kLogical, 1, 3},
                      Case{Command::Lwr, kLogical, 1, 3},
                      Case{Command::Lrw, kLogical, 3, 9},
                      Case{Command::Armw, device_address(0, 0x1000), 1, 3},
                      Case{Command::Frmw, device_address(0x1001, 0x1000), 1, 3}),
    [](const auto& p) { return std::string(to_string(p.param.command)); });

}  // namespace
}  // namespace ecat::esc::test
