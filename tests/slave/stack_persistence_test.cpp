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

// Issue 20: the slaves of a chain share one budget over the state directory.
// Room for one parameter file (plus a little) lets the first slave store and
// makes the second one's store fail with 06060000 (CiA 301 §7.5.2.13), seen
// by a real master over the in-process wire; the first file stays intact.
TEST(InProcessStack, SlavesOfAChainShareOneStateQuota) {
  const auto dir = fresh_dir("quota");
  std::uintmax_t one_file = 0;
  {
    InProcess p;
    ASSERT_NO_FATAL_FAILURE(start_in_preop(p, dir));
    master::CoeClient coe(p.master, 0);
    ASSERT_TRUE(coe.download_value(kStoreParameters, 1, kSaveSignature, 4));
    one_file = std::filesystem::file_size(dir / "slave.par");
    std::filesystem::remove(dir / "slave.par");
  }
  auto quota = std::make_shared<coe::StorageQuota>(coe::StorageQuota::Limits{one_file + one_file / 2, 10});
  InProcess p;
  auto d = esi::load_default_device();
  ASSERT_TRUE(d);
  for (int i = 1; i <= 2; ++i) {
    slave::SlaveOptions o;
    o.state_dir = dir;
    o.name = "slave-" + std::to_string(i);
    o.state_quota = quota;
    p.add(*d, o);
  }
  ASSERT_EQ(p.master.scan().value_or(0), 2u);
  for (std::size_t i = 0; i < 2; ++i) {
    ASSERT_TRUE(p.master.configure_mailbox(i));
    auto st = p.master.request_state(i, master::AlState::PreOp);
    ASSERT_TRUE(st && !st->error());
  }
  master::CoeClient first(p.master, 0);
  master::CoeClient second(p.master, 1);
  ASSERT_TRUE(first.download_value(kStoreParameters, 1, kSaveSignature, 4));
  const auto stored = std::filesystem::file_size(dir / "slave-1.par");
  auto refused = second.download_value(kStoreParameters, 1, kSaveSignature, 4);
  ASSERT_FALSE(refused);
  EXPECT_TRUE(refused.error().from_slave);
  EXPECT_EQ(refused.error().code, master::SdoAbortCode::HardwareError);
  EXPECT_FALSE(std::filesystem::exists(dir / "slave-2.par"));
  EXPECT_FALSE(std::filesystem::exists(dir / "slave-2.par.tmp"));
  EXPECT_EQ(std::filesystem::file_size(dir / "slave-1.par"), stored);
  EXPECT_EQ(quota->used_bytes(), stored);
  EXPECT_EQ(quota->used_files(), 1u);
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace ecat::test
