#include "coe/parameter_store.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "tests/coe/rig.hpp"

namespace ecat::coe {
namespace {

using test::Frame;
using test::sdo;

std::uint32_t code_of(const Frame& reply) {
  if (reply[2] != 0x80) return 0;
  return static_cast<std::uint32_t>(reply[6] | (reply[7] << 8) | (reply[8] << 16) | (reply[9] << 24));
}

class ParameterStoreTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir = std::filesystem::path(ECAT_BINARY_DIR) / "coe_param_test" /
          ::testing::UnitTest::GetInstance()->current_test_info()->name();
    std::filesystem::remove_all(dir);
    std::filesystem::create_directories(dir);
    path = (dir / "params.bin").string();
  }
  std::filesystem::path dir;
  std::string path;
};

TEST(Crc32, KnownVector) {
  const std::string s = "123456789";
  EXPECT_EQ(crc32({reinterpret_cast<const std::uint8_t*>(s.data()), s.size()}), 0xCBF43926u);
}

TEST_F(ParameterStoreTest, StoreThenNewServerFromFileGetsTheValuesBack) {
  {
    test::Rig rig;
    ParameterStore params(rig.store, path);
    EXPECT_EQ(code_of(rig.sdo_request(sdo(0x2B, 0x2000, 0, 42))), 0u);
    EXPECT_EQ(code_of(rig.sdo_request(sdo(0x21, 0x2002, 0, 5, {1, 2, 3, 4, 5}))), 0u);
    EXPECT_EQ(code_of(rig.sdo_request(sdo(0x2F, 0x1600, 0, 0))), 0u);
    EXPECT_EQ(code_of(rig.sdo_request(sdo(0x23, 0x1600, 1, 0x70020020))), 0u);
    EXPECT_EQ(code_of(rig.sdo_request(sdo(0x2F, 0x1600, 0, 1))), 0u);
    EXPECT_EQ(code_of(rig.sdo_request(sdo(0x23, 0x1010, 1, 0x65766173))), 0u);  // "save"
    // Reads back the capability, not the signature.
    EXPECT_EQ(rig.sdo_request(sdo(0x40, 0x1010, 1)), (Frame{0x00, 0x30, 0x43, 0x10, 0x10, 0x01, 1, 0, 0, 0}));
  }
  ASSERT_TRUE(std::filesystem::exists(path));
  EXPECT_FALSE(std::filesystem::exists(path + ".tmp"));
  test::Rig fresh;
  ParameterStore params(fresh.store, path);
  EXPECT_EQ(fresh.store.get<std::int16_t>(0x2000, 0), 5);
  auto applied = params.load();
  ASSERT_TRUE(applied) << applied.error();
  EXPECT_GT(*applied, 10u);
  EXPECT_EQ(fresh.store.get<std::int16_t>(0x2000, 0), 42);
  EXPECT_EQ(fresh.store.value(0x2002, 0).size(), 5u);
  EXPECT_EQ(fresh.store.get<std::uint8_t>(0x1600, 0), 1);
  EXPECT_EQ(fresh.store.get<std::uint32_t>(0x1600, 1), 0x70020020u);
  EXPECT_EQ(fresh.store.get<std::uint32_t>(0x1000, 0), 0x00020192u);  // read-only: not in the file
}

TEST_F(ParameterStoreTest, CorruptedFileIsIgnoredAndLeftInPlace) {
  {
    test::Rig rig;
    ParameterStore params(rig.store, path);
    ASSERT_TRUE(rig.store.set<std::int16_t>(0x2000, 0, 33));
    ASSERT_TRUE(params.save());
  }
  std::vector<char> bytes;
  {
    std::ifstream in(path, std::ios::binary);
    bytes.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  }
  bytes[20] ^= 0x01;
  {
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  }
  test::Rig fresh;
  ParameterStore params(fresh.store, path);
  auto r = params.load();
  ASSERT_FALSE(r);
  EXPECT_NE(r.error().find("checksum"), std::string::npos);
  EXPECT_EQ(fresh.store.get<std::int16_t>(0x2000, 0), 5);
  EXPECT_EQ(std::filesystem::file_size(path), bytes.size());
  // Truncated and foreign files too.
  { std::ofstream(path, std::ios::binary | std::ios::trunc) << "ECPS"; }
  EXPECT_FALSE(params.load());
}

TEST_F(ParameterStoreTest, RestoreDefaultsAppliesAtNextStart) {
  test::Rig rig;
  ParameterStore params(rig.store, path);
  ASSERT_TRUE(rig.store.set<std::int16_t>(0x2000, 0, 77));
  ASSERT_TRUE(params.save());
  EXPECT_EQ(code_of(rig.sdo_request(sdo(0x23, 0x1011, 1, 0x64616F6C))), 0u);  // "load"
  EXPECT_EQ(rig.store.get<std::int16_t>(0x2000, 0), 77);  // not before the next start
  EXPECT_FALSE(std::filesystem::exists(path));
  test::Rig next;
  ParameterStore again(next.store, path);
  ASSERT_TRUE(again.load());
  EXPECT_EQ(next.store.get<std::int16_t>(0x2000, 0), 5);
}

TEST_F(ParameterStoreTest, RefusedCommands) {
  test::Rig rig;
  ParameterStore params(rig.store, path);
  EXPECT_EQ(code_of(rig.sdo_request(sdo(0x23, 0x1010, 1, 0x64616F6C))), 0x08000020u);  // "load" to store
  EXPECT_EQ(code_of(rig.sdo_request(sdo(0x23, 0x1011, 1, 0x65766173))), 0x08000020u);  // "save" to restore
  EXPECT_FALSE(std::filesystem::exists(path));
  test::Rig no_file;
  ParameterStore none(no_file.store, "");
  EXPECT_EQ(code_of(no_file.sdo_request(sdo(0x23, 0x1010, 1, 0x65766173))), 0x08000021u);
  test::Rig bad_dir;
  ParameterStore broken(bad_dir.store, (dir / "missing" / "params.bin").string());
  // CiA 301 §7.5.2.13: a store that fails is aborted with 06060000.
  EXPECT_EQ(code_of(bad_dir.sdo_request(sdo(0x23, 0x1010, 1, 0x65766173))), 0x06060000u);
}

std::vector<char> file_bytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

TEST_F(ParameterStoreTest, StoreBeyondTheQuotaAbortsWith06060000AndKeepsTheEarlierFile) {
  test::Rig rig;
  std::uint64_t size = 0;
  {
    ParameterStore probe(rig.store, path);
    ASSERT_TRUE(probe.save());
    size = std::filesystem::file_size(path);
    std::filesystem::remove(path);
  }
  // Room for one file and half of a second copy: the first store fits, a
  // second one (which needs the old and the new file until the rename) not.
  StorageQuota quota({size + size / 2, 10});
  ParameterStore params(rig.store, path, &quota);
  ASSERT_TRUE(rig.store.set<std::int16_t>(0x2000, 0, 42));
  EXPECT_EQ(code_of(rig.sdo_request(sdo(0x23, 0x1010, 1, 0x65766173))), 0u);
  EXPECT_EQ(quota.used_bytes(), size);
  EXPECT_EQ(quota.used_files(), 1u);
  const std::vector<char> before = file_bytes(path);
  ASSERT_TRUE(rig.store.set<std::int16_t>(0x2000, 0, 43));
  // The whole abort: SDO request service, abort command, 1010h:01, 06060000.
  EXPECT_EQ(rig.sdo_request(sdo(0x23, 0x1010, 1, 0x65766173)),
            (Frame{0x00, 0x20, 0x80, 0x10, 0x10, 0x01, 0x00, 0x00, 0x06, 0x06}));
  EXPECT_EQ(file_bytes(path), before);
  EXPECT_FALSE(std::filesystem::exists(path + ".tmp"));
  EXPECT_EQ(quota.used_bytes(), size);
  EXPECT_EQ(quota.used_files(), 1u);
  test::Rig next;
  ParameterStore again(next.store, path);
  ASSERT_TRUE(again.load());
  EXPECT_EQ(next.store.get<std::int16_t>(0x2000, 0), 42);
  // Restore defaults (1011h) deletes the file and gives it back.
  EXPECT_EQ(code_of(rig.sdo_request(sdo(0x23, 0x1011, 1, 0x64616F6C))), 0u);
  EXPECT_EQ(quota.used_bytes(), 0u);
  EXPECT_EQ(quota.used_files(), 0u);
  EXPECT_EQ(code_of(rig.sdo_request(sdo(0x23, 0x1010, 1, 0x65766173))), 0u);  // fits again
}

TEST_F(ParameterStoreTest, StoreBeyondTheFileCountAbortsWith06060000) {
  test::Rig rig;
  StorageQuota quota({1u << 20, 1});
  ParameterStore params(rig.store, path, &quota);
  EXPECT_EQ(code_of(rig.sdo_request(sdo(0x23, 0x1010, 1, 0x65766173))), 0u);
  const std::vector<char> before = file_bytes(path);
  // The temporary file of the next store would be a second file.
  ASSERT_TRUE(rig.store.set<std::int16_t>(0x2000, 0, 44));
  EXPECT_EQ(code_of(rig.sdo_request(sdo(0x23, 0x1010, 1, 0x65766173))), 0x06060000u);
  EXPECT_EQ(file_bytes(path), before);
  EXPECT_FALSE(std::filesystem::exists(path + ".tmp"));
  EXPECT_EQ(quota.used_files(), 1u);
}

}  // namespace
}  // namespace ecat::coe
