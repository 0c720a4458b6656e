// A small, hand-assembled SII image (sii-eeprom.md layout) shared by the
// master tests: identity 0x00000A5A/0x00001234/rev 2/serial 7, mailbox SM0
// 0x1000+128 (control 0x26), SM1 0x1080+128 (0x22), CoE; SM2 0x1100 outputs
// (0x64), SM3 0x1400 inputs (0x20); RxPDO 0x1600 = 0x7000:01 16 bits,
// TxPDO 0x1A00 = 0x6000:01 32 bits.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "common/le.hpp"
#include "master/sii.hpp"

namespace ecat::master::test {

inline void put16(std::vector<std::uint8_t>& v, std::uint16_t x) {
  v.push_back(static_cast<std::uint8_t>(x));
  v.push_back(static_cast<std::uint8_t>(x >> 8));
}
inline void put32(std::vector<std::uint8_t>& v, std::uint32_t x) {
  put16(v, static_cast<std::uint16_t>(x));
  put16(v, static_cast<std::uint16_t>(x >> 16));
}
inline void category(std::vector<std::uint8_t>& image, std::uint16_t type, std::vector<std::uint8_t> data) {
  if (data.size() % 2 != 0) data.push_back(0);
  put16(image, type);
  put16(image, static_cast<std::uint16_t>(data.size() / 2));
  image.insert(image.end(), data.begin(), data.end());
}

inline constexpr std::uint32_t kVendor = 0x00000A5A;
inline constexpr std::uint32_t kProduct = 0x00001234;
inline constexpr std::uint16_t kSm0Start = 0x1000, kSm1Start = 0x1080, kMailboxSize = 128;
inline constexpr std::uint16_t kSm2Start = 0x1100, kSm3Start = 0x1400;

inline std::vector<std::uint8_t> test_sii_image() {
  std::vector<std::uint8_t> img(sii::kFixedAreaBytes, 0);
  auto w16 = [&](std::size_t word, std::uint16_t v) { store_le(img.data() + 2 * word, v); };
  auto w32 = [&](std::size_t word, std::uint32_t v) { store_le(img.data() + 2 * word, v); };
  w16(0, 0x0C05);  // PDI SPI, DC units on (worked example in sii-eeprom.md §2)
  w16(1, 0x4400);
  w16(2, 0x0064);
  img[14] = sii::config_crc(ConstBytes(img.data(), 14));
  w32(sii::kVendorId, kVendor);
  w32(sii::kProductCode, kProduct);
  w32(sii::kRevision, 2);
  w32(sii::kSerial, 7);
  w16(sii::kStdRxMailboxOffset, kSm0Start);
  w16(sii::kStdRxMailboxSize, kMailboxSize);
  w16(sii::kStdTxMailboxOffset, kSm1Start);
  w16(sii::kStdTxMailboxSize, kMailboxSize);
  w16(sii::kMailboxProtocols, sii::kProtoCoe);
  w16(sii::kSize, 15);
  w16(sii::kVersion, 1);

  std::vector<std::uint8_t> strings{2};
  for (std::string s : {"TestSlave", "Outputs"}) {
    strings.push_back(static_cast<std::uint8_t>(s.size()));
    strings.insert(strings.end(), s.begin(), s.end());
  }
  category(img, 10, strings);
  std::vector<std::uint8_t> general(32, 0);
  general[3] = 1;  // name = string 1
  general[5] = sii::kCoeSdo | sii::kCoeSdoInfo | sii::kCoePdoAssign | sii::kCoePdoConfig | sii::kCoeCompleteAccess;
  general[0x0C] = 100;  // 100 mA
  general[0x10] = 0x11;  // MII, MII
  category(img, 30, general);
  category(img, 40, {sii::kFmmuOutputs, sii::kFmmuInputs, sii::kFmmuSyncMStatus, 0xFF});
  std::vector<std::uint8_t> syncm;
  auto sm = [&](std::uint16_t start, std::uint16_t len, std::uint8_t ctrl, std::uint8_t type) {
    put16(syncm, start);
    put16(syncm, len);
    syncm.push_back(ctrl);
    syncm.push_back(0);
    syncm.push_back(1);
    syncm.push_back(type);
  };
  sm(kSm0Start, kMailboxSize, 0x26, 1);
  sm(kSm1Start, kMailboxSize, 0x22, 2);
  sm(kSm2Start, 0, 0x64, 3);
  sm(kSm3Start, 0, 0x20, 4);
  category(img, 41, syncm);
  auto pdo = [](std::uint16_t index, std::uint8_t smn, std::uint16_t entry, std::uint8_t bits, std::uint8_t type) {
    std::vector<std::uint8_t> d;
    put16(d, index);
    d.push_back(1);
    d.push_back(smn);
    d.push_back(0);
    d.push_back(2);
    put16(d, 0);
    put16(d, entry);
    d.push_back(1);
    d.push_back(0);
    d.push_back(type);
    d.push_back(bits);
    put16(d, 0);
    return d;
  };
  category(img, 50, pdo(0x1A00, 3, 0x6000, 32, 0x07));
  category(img, 51, pdo(0x1600, 2, 0x7000, 16, 0x06));
  put16(img, 0xFFFF);
  put16(img, 0xFFFF);
  return img;
}

}  // namespace ecat::master::test
