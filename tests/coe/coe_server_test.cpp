#include "coe/coe_server.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "tests/coe/rig.hpp"

namespace ecat::coe {
namespace {

using test::Frame;

CoeOptions options(std::string parameter_file) {
  CoeOptions o;
  o.parameter_file = std::move(parameter_file);
  return o;
}

std::filesystem::path scratch(const char* name) {
  auto dir = std::filesystem::path(ECAT_BINARY_DIR) / "coe_server_test" / name;
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir;
}

TEST(CoeServer, LoadsTheParameterFileAtConstruction) {
  const auto dir = scratch("load");
  const od::DeviceDescription device = test::make_device();
  test::FakeEsc esc;
  esc.configure_mailboxes(test::kSm0, test::kMbxLen, test::kSm1, test::kMbxLen);
  {
    CoeServer coe(esc, device, options((dir / "p.par").string()));
    ASSERT_TRUE(coe.objects().set<std::uint32_t>(0x1600, 1, 0x70020020));
    ASSERT_TRUE(coe.objects().set<std::uint8_t>(0x1600, 0, 1));
    ASSERT_TRUE(coe.parameters().save());
  }
  CoeServer coe(esc, device, options((dir / "p.par").string()));
  EXPECT_TRUE(coe.warnings().empty());
  // The PDO layout follows the loaded mapping.
  EXPECT_EQ(coe.pdo().outputs().byte_length(), 4u);
}

TEST(CoeServer, BadParameterFileIsAWarningNotAFailure) {
  const auto dir = scratch("bad");
  { std::ofstream(dir / "p.par") << "garbage that is long enough to be checked"; }
  const od::DeviceDescription device = test::make_device();
  test::FakeEsc esc;
  CoeServer coe(esc, device, options((dir / "p.par").string()));
  ASSERT_EQ(coe.warnings().size(), 1u);
  EXPECT_NE(coe.warnings()[0].find("checksum"), std::string::npos);
  EXPECT_EQ(coe.objects().get<std::int16_t>(0x2000, 0), 5);
}

TEST(CoeServer, ServicesFollowTheDevice) {
  od::DeviceDescription device = test::make_device();
  device.mailbox.foe = false;
  device.mailbox.sdo_info = false;
  test::FakeEsc esc;
  esc.configure_mailboxes(test::kSm0, test::kMbxLen, test::kSm1, test::kMbxLen);
  CoeServer coe(esc, device);
  auto ask = [&](const Frame& f) {
    EXPECT_TRUE(esc.master_write(f));
    coe.poll(Nanoseconds{0});
    auto r = esc.master_read();
    return r ? Frame(r->begin(), r->begin() + 10) : Frame{};
  };
  EXPECT_EQ(ask(test::mbx(4, 1, {1, 0, 0, 0, 0, 0, 'a'})), (Frame{4, 0, 0, 0, 0, 0x10, 1, 0, 2, 0}));
  EXPECT_EQ(ask(test::mbx(3, 2, {0x00, 0x80, 0x01, 0x00, 0x00, 0x00, 0x01, 0x00})),
            (Frame{4, 0, 0, 0, 0, 0x20, 1, 0, 4, 0}));
  Frame up = ask(test::mbx(3, 3, test::sdo(0x40, 0x1000, 0)));
  EXPECT_EQ(up[8], 0x43);
}

TEST(CoeServer, EsmHookChecksOnlyPreOpToSafeOp) {
  const od::DeviceDescription device = test::make_device();
  test::FakeEsc esc;
  CoeServer coe(esc, device);
  // SM2/SM3 not configured: the default mapping (3 and 5 bytes) does not fit.
  EXPECT_EQ(coe.esm_hooks().check_transition(esc::AlState::PreOp, esc::AlState::SafeOp),
            esc::AlStatusCode::InvalidOutputConfiguration);
  EXPECT_EQ(coe.esm_hooks().check_transition(esc::AlState::Init, esc::AlState::PreOp), esc::AlStatusCode::NoError);
  EXPECT_EQ(coe.esm_hooks().check_transition(esc::AlState::SafeOp, esc::AlState::Op), esc::AlStatusCode::NoError);
  esc.configure_sm(2, 0x1100, 3, 0x64);
  esc.configure_sm(3, 0x1180, 5, 0x20);
  EXPECT_EQ(coe.esm_hooks().check_transition(esc::AlState::PreOp, esc::AlState::SafeOp), esc::AlStatusCode::NoError);
}

}  // namespace
}  // namespace ecat::coe
