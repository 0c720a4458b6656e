// What a firmware does with the generated tables: its object dictionary,
// PDO mapping and identity come from servo_tables.hpp (constexpr, no XML at
// run time), and the SII image programmed into its EEPROM says the same.
// Prints a summary; exits 1 if the SII image disagrees with the tables.
#include <cstdint>
#include <cstdio>
#include <fstream>
#include <iterator>
#include <vector>

#include "servo_tables.hpp"

namespace {

// SII words 0x0008..0x000F: vendor id, product code, revision, serial
// (ETG.2010 Table 2), little-endian.
constexpr std::size_t kSiiVendorId = 0x08 * 2;
constexpr std::size_t kSiiProductCode = 0x0A * 2;
constexpr std::size_t kSiiRevision = 0x0C * 2;

constexpr std::uint16_t kControlword = 0x6040;
constexpr std::uint16_t kStatusword = 0x6041;

// The tables are constexpr: a firmware can check its own dictionary at compile time.
static_assert(servo::find_object(kControlword) != nullptr, "a CiA402 drive has 6040h");
static_assert(servo::find_object(kStatusword) != nullptr, "a CiA402 drive has 6041h");
static_assert(!servo::kRxPdos.empty() && !servo::kTxPdos.empty());

std::uint32_t u32(const std::vector<std::uint8_t>& b, std::size_t at) {
  return static_cast<std::uint32_t>(b[at] | (b[at + 1] << 8) | (b[at + 2] << 16)) |
         (static_cast<std::uint32_t>(b[at + 3]) << 24);
}

}  // namespace

int main() {
  std::ifstream file(SERVO_SII, std::ios::binary);
  const std::vector<std::uint8_t> sii((std::istreambuf_iterator<char>(file)), std::istreambuf_iterator<char>());
  if (sii.size() < kSiiRevision + 4) {
    std::fprintf(stderr, "firmware_tables: %s: SII image too short (%zu bytes)\n", SERVO_SII, sii.size());
    return 1;
  }
  const auto& id = servo::kIdentity;
  std::printf("%s (%s): vendor 0x%08X product 0x%08X revision 0x%08X\n", id.name, id.type_name,
              static_cast<unsigned>(id.vendor_id), static_cast<unsigned>(id.product_code),
              static_cast<unsigned>(id.revision));
  std::printf("%zu objects, %zu entries, %zu RxPDOs, %zu TxPDOs; SII %zu bytes; ESI %s\n",
              servo::kObjects.size(), servo::kEntries.size(), servo::kRxPdos.size(), servo::kTxPdos.size(),
              sii.size(), SERVO_ESI);
  if (u32(sii, kSiiVendorId) != id.vendor_id || u32(sii, kSiiProductCode) != id.product_code ||
      u32(sii, kSiiRevision) != id.revision) {
    std::fprintf(stderr, "firmware_tables: the SII identity differs from the C++ tables\n");
    return 1;
  }
  const auto* controlword = servo::find_object(kControlword);
  std::printf("6040h \"%s\": %u entr%s\n", controlword->name, unsigned{controlword->entry_count},
              controlword->entry_count == 1 ? "y" : "ies");
  return 0;
}
