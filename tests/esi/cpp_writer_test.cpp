// C++ tables: the generated header compiles standalone with the system
// compiler and strict warnings, and its constexpr values are the model's
// (checked by static_assert in a test program compiled against it).
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>

#include "esi/cpp_writer.hpp"
#include "esi/device_loader.hpp"
#include "esi_test_device.hpp"
#include "esi_xmllint.hpp"

namespace ecat::esi {
namespace {

int compile(const std::string& file);

bool have_compiler() { return std::system("c++ --version > /dev/null 2>&1") == 0; }

// A header is checked through a one-line .cpp that includes it.
int compile_header(const std::string& header) {
  const auto name = std::filesystem::path(header).filename().string();
  return compile(test::write_test_file(name + ".cpp", "#include \"" + name + "\"\n"));
}

int compile(const std::string& file) {
  const std::string cmd = "c++ -std=c++20 -Wall -Wextra -Wpedantic -Wshadow -Wconversion -Werror "
                          "-fsyntax-only '" + file + "'";
  return std::system(cmd.c_str());
}

TEST(CppWriter, Deterministic) {
  EXPECT_EQ(write_cpp_tables(test::make_test_device()), write_cpp_tables(test::make_test_device()));
}

TEST(CppWriter, TablesHoldTheModel) {
  const std::string h = write_cpp_tables(test::make_test_device(), "gen::servo");
  EXPECT_NE(h.find("namespace gen::servo {"), std::string::npos);
  EXPECT_NE(h.find("inline constexpr Identity kIdentity{0x00000ABC, 0x00001234, 0x00020001, "
                   "0x00000000, 0x00020192, \"Test Servo\", \"TS-100\"};"),
            std::string::npos);
  EXPECT_NE(h.find("Object{0x6040, 7, 0x0006, "), std::string::npos);
  EXPECT_NE(h.find("Pdo{0x1A00, 0x03, true, true, 4, 2, \"TxPDO 1\"}"), std::string::npos);
  EXPECT_NE(h.find("SyncManager{0x1000, 128, 0x26, 1, true}"), std::string::npos);
}

TEST(CppWriter, CompilesStandaloneWithValuesChecked) {
  if (!have_compiler()) GTEST_SKIP() << "no c++ compiler on PATH";
  auto d = test::make_test_device();
  // Escaping; "?" "?=" as two literals keeps the text free of a trigraph
  // (and of a std::string + that GCC 12 misreports under -Warray-bounds).
  d.identity.name = "Quote \" back\\slash ?" "?= tab\t und \xC3\xBC";
  const auto header = test::write_test_file("cpp_writer_servo.hpp", write_cpp_tables(d, "gen"));
  const auto program = test::write_test_file("cpp_writer_servo_check.cpp", R"(
#include "cpp_writer_servo.hpp"
static_assert(gen::kIdentity.vendor_id == 0xABC);
static_assert(gen::kIdentity.product_code == 0x1234);
static_assert(gen::kObjects.size() == 11);
static_assert(gen::kObjects.front().index == 0x1000);
static_assert(gen::find_object(0x6040) != nullptr);
static_assert(gen::find_object(0x6041)->entry_count == 1);
static_assert(gen::find_object(0x1234) == nullptr);
static_assert(gen::find_object(0x1018)->object_code == 9);
static_assert(gen::find_entry(*gen::find_object(0x1018), 2)->bit_length == 32);
static_assert(gen::find_entry(*gen::find_object(0x2000), 2)->min_value.size == 2);
static_assert(gen::kValues[gen::find_entry(*gen::find_object(0x2000), 2)->default_value.offset] == 0x9C);
static_assert(gen::kValues[gen::find_entry(*gen::find_object(0x2000), 2)->max_value.offset + 1] == 0x03);
static_assert(gen::kRxPdos.size() == 1 && gen::kRxPdos[0].entry_count == 4);
static_assert(gen::kPdoEntries[gen::kRxPdos[0].first_entry + 1].index == 0x607A);
static_assert(gen::kTxPdos[0].sm == 3);
static_assert(gen::kSyncManagers[2].control == 0x64);
static_assert(gen::kIdentity.name[6] == '"');
int main() { return 0; }
)");
  EXPECT_EQ(compile(program), 0);
}

TEST(CppWriter, EmptyDeviceCompiles) {
  if (!have_compiler()) GTEST_SKIP() << "no c++ compiler on PATH";
  const auto header = test::write_test_file("cpp_writer_empty.hpp", write_cpp_tables(od::DeviceDescription{}));
  EXPECT_EQ(compile_header(header), 0);
}

TEST(CppWriter, ShippedDevicesCompile) {
  if (!have_compiler()) GTEST_SKIP() << "no c++ compiler on PATH";
  const auto dir = std::filesystem::path(ECAT_SOURCE_DIR) / "xml" / "devices";
  for (const auto& e : std::filesystem::directory_iterator(dir)) {
    if (e.path().extension() != ".xml") continue;
    auto d = load_device_file(e.path());
    ASSERT_TRUE(d) << d.error().to_string();
    const auto header = test::write_test_file("cpp_" + e.path().stem().string() + ".hpp",
                                              write_cpp_tables(*d));
    EXPECT_EQ(compile_header(header), 0) << e.path();
  }
}

}  // namespace
}  // namespace ecat::esi
