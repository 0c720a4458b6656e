#include "coe/storage_quota.hpp"

#include <gtest/gtest.h>

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <limits>
#include <string>

namespace ecat::coe {
namespace {

namespace fs = std::filesystem;

void write_file(const fs::path& p, std::size_t n) {
  std::ofstream out(p, std::ios::binary);
  out << std::string(n, 'x');
}

TEST(StorageQuota, ChargesUpToTheLimitsExactly) {
  StorageQuota q({100, 2});
  EXPECT_TRUE(q.charge_bytes(60));
  EXPECT_TRUE(q.charge_bytes(40));  // exactly the limit
  EXPECT_EQ(q.used_bytes(), 100u);
  EXPECT_FALSE(q.charge_bytes(1));  // one beyond: refused, nothing charged
  EXPECT_EQ(q.used_bytes(), 100u);
  EXPECT_TRUE(q.charge_bytes(0));
  q.release_bytes(1);
  EXPECT_TRUE(q.charge_bytes(1));
  EXPECT_FALSE(q.charge_bytes(std::numeric_limits<std::uint64_t>::max()));  // no wrap-around
  EXPECT_EQ(q.used_bytes(), 100u);

  EXPECT_TRUE(q.charge_file());
  EXPECT_TRUE(q.charge_file());
  EXPECT_FALSE(q.charge_file());
  EXPECT_EQ(q.used_files(), 2u);
  q.release_file(30);
  EXPECT_EQ(q.used_files(), 1u);
  EXPECT_EQ(q.used_bytes(), 70u);
  EXPECT_TRUE(q.charge_file());
  // Giving back more than was charged stops at zero.
  q.release_file(1000);
  q.release_file(0);
  q.release_file(0);
  EXPECT_EQ(q.used_bytes(), 0u);
  EXPECT_EQ(q.used_files(), 0u);
}

TEST(StorageQuota, CountsWhatTheDirectoryHoldsAtStart) {
  const fs::path dir = fs::path(ECAT_BINARY_DIR) / "coe_quota_test" / "existing";
  fs::remove_all(dir);
  fs::create_directories(dir / "slave-1-foe");
  write_file(dir / "slave-1.par", 10);
  write_file(dir / "slave-1-foe" / "fw.bin", 20);
  write_file(dir / "slave-1-foe" / "fw2.bin.part", 5);  // a crash's leftover counts too
  fs::create_symlink("/etc/passwd", dir / "link");    // not followed, not counted
  StorageQuota q({30, 10});
  ASSERT_TRUE(q.count_existing(dir));
  EXPECT_EQ(q.used_bytes(), 35u);
  EXPECT_EQ(q.used_files(), 3u);
  // Already beyond the byte limit: nothing more fits, files still do.
  EXPECT_FALSE(q.charge_bytes(1));
  EXPECT_TRUE(q.charge_file());
  EXPECT_EQ(StorageQuota::regular_file_size((dir / "slave-1.par").string()), std::uint64_t{10});
  EXPECT_FALSE(StorageQuota::regular_file_size((dir / "link").string()).has_value());
  EXPECT_FALSE(StorageQuota::regular_file_size((dir / "missing").string()).has_value());

  StorageQuota none({30, 10});
  EXPECT_TRUE(none.count_existing(dir / "does-not-exist"));
  EXPECT_EQ(none.used_bytes(), 0u);
  EXPECT_EQ(none.used_files(), 0u);
}

}  // namespace
}  // namespace ecat::coe
