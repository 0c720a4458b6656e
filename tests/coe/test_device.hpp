// A small device for the CoE tests, built in code: identity, PDO mapping and
// assignment objects, a few application objects covering every access right,
// min/max, a 64 KiB octet string and a bit-packed record.
#pragma once

#include <cstdint>
#include <initializer_list>
#include <string>

#include "od/device.hpp"

namespace ecat::coe::test {

inline od::Value le(std::uint64_t v, std::size_t n) {
  od::Value out(n);
  for (std::size_t i = 0; i < n; ++i) out[i] = static_cast<std::uint8_t>(v >> (8 * i));
  return out;
}

inline od::Entry entry(std::uint8_t sub, std::string name, od::DataType type, std::uint16_t bits,
                       std::uint16_t access, od::Value def = {}) {
  od::Entry e;
  e.subindex = sub;
  e.name = std::move(name);
  e.type = type;
  e.bit_length = bits;
  e.access.bits = access;
  e.default_value = def.empty() && !od::is_string(type) ? od::Value((bits + 7) / 8, 0) : def;
  return e;
}

inline od::Object var(std::uint16_t index, std::string name, od::DataType type, std::uint16_t bits,
                      std::uint16_t access, od::Value def = {}) {
  od::Object o;
  o.index = index;
  o.name = name;
  o.code = od::ObjectCode::Var;
  o.type = type;
  o.entries.push_back(entry(0, std::move(name), type, bits, access, std::move(def)));
  return o;
}

inline od::Object composite(std::uint16_t index, std::string name, od::ObjectCode code, od::DataType type,
                            std::uint16_t sub0_access, std::initializer_list<od::Entry> entries,
                            std::uint8_t sub0 = 0xFF) {
  od::Object o;
  o.index = index;
  o.name = std::move(name);
  o.code = code;
  o.type = type;
  std::uint8_t n = 0;
  for (const auto& e : entries) n = std::max(n, e.subindex);
  if (sub0 == 0xFF) sub0 = n;
  o.entries.push_back(entry(0, "Number of entries", od::DataType::Unsigned8, 8, sub0_access, {sub0}));
  for (const auto& e : entries) o.entries.push_back(e);
  return o;
}

constexpr std::uint16_t kRo = od::Access::kRo;
constexpr std::uint16_t kRw = od::Access::kRw;
constexpr std::uint16_t kWo = od::Access::kWo;
constexpr std::uint16_t kRwPreOp = od::Access::kReadAll | od::Access::kWritePreOp;
constexpr std::uint16_t kRxMap = od::Access::kRxPdoMappable;
constexpr std::uint16_t kTxMap = od::Access::kTxPdoMappable;

inline od::DeviceDescription make_device() {
  using od::DataType;
  using od::ObjectCode;
  od::DeviceDescription d;
  d.identity.vendor_id = 0x00000ABC;
  d.identity.product_code = 0x12345678;
  d.mailbox.foe = true;
  d.sync_managers = {
      {od::SmType::MailboxOut, 0x1000, 128, 0x26, true, 0, 0},
      {od::SmType::MailboxIn, 0x1080, 128, 0x22, true, 0, 0},
      {od::SmType::Outputs, 0x1100, 0, 0x64, true, 0, 16},
      {od::SmType::Inputs, 0x1180, 0, 0x20, true, 0, 16},
  };
  auto& od = d.dictionary;
  auto put = [&](od::Object o) { (void)od.put(std::move(o)); };
  put(var(0x1000, "Device type", DataType::Unsigned32, 32, kRo, le(0x00020192, 4)));
  put(var(0x1001, "Error register", DataType::Unsigned8, 8, kRo));
  od::Value name{'e', 'c', 'a', 't', ' ', 't', 'e', 's', 't'};
  put(var(0x1008, "Device name", DataType::VisibleString, 8 * 32, kRo, name));
  put(composite(0x1010, "Store parameters", ObjectCode::Array, DataType::Unsigned32, kRo,
                {entry(1, "Save all parameters", DataType::Unsigned32, 32, kRw, le(1, 4))}));
  put(composite(0x1011, "Restore default parameters", ObjectCode::Array, DataType::Unsigned32, kRo,
                {entry(1, "Restore all default parameters", DataType::Unsigned32, 32, kRw, le(1, 4))}));
  put(composite(0x1018, "Identity", ObjectCode::Record, DataType::Identity, kRo,
                {entry(1, "Vendor ID", DataType::Unsigned32, 32, kRo, le(0xABC, 4)),
                 entry(2, "Product code", DataType::Unsigned32, 32, kRo, le(0x12345678, 4)),
                 entry(3, "Revision", DataType::Unsigned32, 32, kRo, le(0x00010002, 4)),
                 entry(4, "Serial number", DataType::Unsigned32, 32, kRo, le(0x0BADCAFE, 4))}));
  auto mapping = [&](std::uint16_t index, std::string nm, std::initializer_list<std::uint32_t> defaults) {
    od::Object o = composite(index, nm, ObjectCode::Record, DataType::PdoMapping, kRwPreOp, {},
                             static_cast<std::uint8_t>(defaults.size()));
    std::uint8_t sub = 1;
    for (std::uint32_t v : defaults) {
      o.entries.push_back(entry(sub, "Entry " + std::to_string(sub), DataType::Unsigned32, 32, kRwPreOp, le(v, 4)));
      ++sub;
    }
    for (; sub <= 8; ++sub) {
      o.entries.push_back(entry(sub, "Entry " + std::to_string(sub), DataType::Unsigned32, 32, kRwPreOp));
    }
    put(o);
  };
  mapping(0x1600, "RxPDO 1", {0x70000010, 0x70010008});
  mapping(0x1601, "RxPDO 2", {0x70020020});
  mapping(0x1A00, "TxPDO 1", {0x60000020, 0x60010008});
  put(composite(0x1C00, "Sync manager type", ObjectCode::Array, DataType::Unsigned8, kRo,
                {entry(1, "SM0", DataType::Unsigned8, 8, kRo, {1}), entry(2, "SM1", DataType::Unsigned8, 8, kRo, {2}),
                 entry(3, "SM2", DataType::Unsigned8, 8, kRo, {3}), entry(4, "SM3", DataType::Unsigned8, 8, kRo, {4})}));
  put(composite(0x1C12, "RxPDO assign", ObjectCode::Array, DataType::Unsigned16, kRwPreOp,
                {entry(1, "PDO 1", DataType::Unsigned16, 16, kRwPreOp, le(0x1600, 2)),
                 entry(2, "PDO 2", DataType::Unsigned16, 16, kRwPreOp)},
                1));
  put(composite(0x1C13, "TxPDO assign", ObjectCode::Array, DataType::Unsigned16, kRwPreOp,
                {entry(1, "PDO 1", DataType::Unsigned16, 16, kRwPreOp, le(0x1A00, 2))}));
  od::Object limited = var(0x2000, "Limited", DataType::Integer16, 16, kRw, le(5, 2));
  limited.entries[0].min_value = le(static_cast<std::uint16_t>(-100), 2);
  limited.entries[0].max_value = le(100, 2);
  put(limited);
  put(var(0x2001, "Write only", DataType::Unsigned32, 32, kWo));
  put(var(0x2002, "Blob", DataType::OctetString, 0, kRw));
  put(composite(0x2003, "Array", ObjectCode::Array, DataType::Unsigned16, kRo,
                {entry(1, "A1", DataType::Unsigned16, 16, kRw, le(0x1111, 2)),
                 entry(2, "A2", DataType::Unsigned16, 16, kRw, le(0x2222, 2)),
                 entry(3, "A3", DataType::Unsigned16, 16, kRo, le(0x3333, 2))}));
  put(var(0x2004, "PreOp only", DataType::Unsigned8, 8, kRwPreOp, {7}));
  od::Object bits = composite(0x2005, "Bits", ObjectCode::Record, DataType::Record, kRo,
                              {entry(1, "Flag", DataType::Boolean, 1, kRw, {1}),
                               entry(2, "Three", DataType::Bit3, 3, kRw, {5}),
                               entry(3, "Word", DataType::Unsigned16, 16, kRw, le(0xBEEF, 2))});
  bits.entries[3].max_value = le(0xF000, 2);
  put(bits);
  put(var(0x6000, "Input 32", DataType::Unsigned32, 32, kRo | kTxMap, le(0x11223344, 4)));
  put(var(0x6001, "Input 8", DataType::Unsigned8, 8, kRo | kTxMap, {0x55}));
  put(var(0x7000, "Output 16", DataType::Unsigned16, 16, kRw | kRxMap));
  put(var(0x7001, "Output 8", DataType::Unsigned8, 8, kRw | kRxMap));
  put(var(0x7002, "Output 32", DataType::Unsigned32, 32, kRw | kRxMap));
  return d;
}

}  // namespace ecat::coe::test
