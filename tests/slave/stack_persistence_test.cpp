// Stored parameters (1010h) survive the slave: a new slave built on the same
// state directory comes up with the stored values.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "master/coe_client.hpp"
#include "tests/slave/inprocess_fixture.hpp"

namespace ecat::test {
namespace {

constexpr std::uint16_t kFollowingErrorWindow = 0x6065;
constexpr std::uint16_t kStoreParameters = 0x1010;
constexpr std::uint32_t kSaveSignature = 0x65766173;  // "save", CiA 301 §7.5.2.13

std::filesystem::path fresh_dir(const std::string& name) {
  auto dir = std::filesystem::temp_directory_path() / ("ecat-slave-test-" + name + "-" + std::to_string(::getpid()));
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir;
}

// A generic servo whose state lives in `dir`, brought to PreOp (mailbox open).
void start_in_preop(InProcess& p, const std::filesystem::path& dir) {
  auto d = esi::load_default_device();
  ASSERT_TRUE(d);
  slave::SlaveOptions o;
  o.state_dir = dir;
  p.add(*d, o);
  ASSERT_TRUE(p.master.scan());
  ASSERT_TRUE(p.master.configure_mailbox(0));
  auto st = p.master.request_state(0, master::AlState::PreOp);
  ASSERT_TRUE(st && !st->error());
}

Expected<std::uint32_t, master::SdoError> start_and_read(const std::filesystem::path& dir) {
  InProcess p;
  start_in_preop(p, dir);
  master::CoeClient coe(p.master, 0);
  return coe.upload_value(kFollowingErrorWindow, 0);
}

TEST(InProcessStack, StoredParametersComeBackInANewSlave) {
  const auto dir = fresh_dir("store");
  {
    InProcess p;
    ASSERT_NO_FATAL_FAILURE(start_in_preop(p, dir));
    master::CoeClient coe(p.master, 0);
    ASSERT_TRUE(coe.download_value(kFollowingErrorWindow, 0, 12345, 4));
    ASSERT_TRUE(coe.download_value(kStoreParameters, 1, kSaveSignature, 4));
  }
  auto v = start_and_read(dir);
  ASSERT_TRUE(v);
  EXPECT_EQ(*v, 12345u);

  // Without a store the change is gone at the next start.
  const auto other = fresh_dir("nostore");
  {
    InProcess p;
    ASSERT_NO_FATAL_FAILURE(start_in_preop(p, other));
    master::CoeClient coe(p.master, 0);
    ASSERT_TRUE(coe.download_value(kFollowingErrorWindow, 0, 777, 4));
  }
  auto fresh = start_and_read(other);
  ASSERT_TRUE(fresh);
  EXPECT_NE(*fresh, 777u);
  std::filesystem::remove_all(dir);
  std::filesystem::remove_all(other);
}

}  // namespace
}  // namespace ecat::test
