// StagedFiles: outputs appear only on commit, all together; an abandoned or
// failed batch leaves neither temporary files nor partial targets.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "esi/atomic_file.hpp"

namespace ecat::esi {
namespace {

namespace fs = std::filesystem;

fs::path fresh_dir(const std::string& name) {
  const auto dir = fs::path(ECAT_BINARY_DIR) / "test-output" / name;
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

std::string read(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

std::size_t count_files(const fs::path& dir) {
  return static_cast<std::size_t>(std::distance(fs::directory_iterator(dir), fs::directory_iterator{}));
}

TEST(EsigenAtomicFile, NothingAppearsBeforeCommit) {
  const auto dir = fresh_dir("atomic1");
  StagedFiles files;
  ASSERT_TRUE(files.stage(dir / "a.txt", std::string_view("alpha")));
  ASSERT_TRUE(files.stage(dir / "b.bin", std::string_view("beta")));
  EXPECT_FALSE(fs::exists(dir / "a.txt"));
  EXPECT_EQ(count_files(dir), 2u);  // the two temporaries
  ASSERT_TRUE(files.commit());
  EXPECT_EQ(read(dir / "a.txt"), "alpha");
  EXPECT_EQ(read(dir / "b.bin"), "beta");
  EXPECT_EQ(count_files(dir), 2u);
}

TEST(EsigenAtomicFile, AbandonedBatchLeavesNothing) {
  const auto dir = fresh_dir("atomic2");
  std::ofstream(dir / "keep.txt") << "old";
  {
    StagedFiles files;
    ASSERT_TRUE(files.stage(dir / "keep.txt", std::string_view("new")));
    auto bad = files.stage(dir / "missing" / "x.txt", std::string_view("x"));
    ASSERT_FALSE(bad);
    EXPECT_NE(bad.error().find("missing/x.txt: cannot create a temporary file"), std::string::npos);
  }
  EXPECT_EQ(read(dir / "keep.txt"), "old");
  EXPECT_EQ(count_files(dir), 1u);
}

TEST(EsigenAtomicFile, ReplacesAnExistingFile) {
  const auto dir = fresh_dir("atomic3");
  std::ofstream(dir / "f.bin") << "0123456789";
  const std::vector<std::uint8_t> bytes = {1, 2, 3};
  ASSERT_TRUE(write_file_atomic(dir / "f.bin", bytes));
  EXPECT_EQ(read(dir / "f.bin"), std::string("\x01\x02\x03", 3));
  EXPECT_EQ(count_files(dir), 1u);
}

}  // namespace
}  // namespace ecat::esi
