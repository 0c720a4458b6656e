#include "esi_test_device.hpp"

#include <stdexcept>

namespace ecat::esi::test {
namespace {

using od::Access;
using od::DataType;
using od::Entry;
using od::Object;
using od::ObjectCode;

od::Value le(std::uint64_t v, std::size_t bytes) {
  od::Value out(bytes);
  for (std::size_t i = 0; i < bytes; ++i) out[i] = static_cast<std::uint8_t>(v >> (8 * i));
  return out;
}

Entry entry(std::uint8_t sub, std::string name, DataType t, std::uint16_t bits, std::uint16_t access,
            od::Value def = {}) {
  Entry e;
  e.subindex = sub;
  e.name = std::move(name);
  e.type = t;
  e.bit_length = bits;
  e.access.bits = access;
  e.default_value = std::move(def);
  return e;
}

Object var(std::uint16_t index, std::string name, DataType t, std::uint16_t bits,
           std::uint16_t access, od::Value def = {}) {
  Object o;
  o.index = index;
  o.name = name;
  o.code = ObjectCode::Var;
  o.type = t;
  o.entries.push_back(entry(0, std::move(name), t, bits, access, std::move(def)));
  return o;
}

Entry count(std::uint8_t n, std::uint16_t access = Access::kRo) {
  return entry(0, "Number of entries", DataType::Unsigned8, 8, access, le(n, 1));
}

void put(od::Dictionary& d, Object o) {
  if (auto ok = d.put(std::move(o)); !ok) throw std::logic_error(ok.error());
}

}  // namespace

od::DeviceDescription make_test_device() {
  od::DeviceDescription d;
  auto& id = d.identity;
  id.vendor_id = 0x00000ABC;
  id.vendor_name = "Example & Co";
  id.product_code = 0x00001234;
  id.revision = 0x00020001;
  id.name = "Test Servo";
  id.type_name = "TS-100";
  id.group_type = "Servo";
  id.group_name = "Servo drives";
  id.device_type = 0x00020192;

  d.esc.pdi_control = 0x0C05;
  d.esc.pdi_configuration = 0x4400;
  d.esc.sync_impulse_length = 0x0064;
  d.esc.eeprom_bytes = 2048;

  d.sync_managers = {
      {od::SmType::MailboxOut, 0x1000, 128, 0x26, true, 0, 0},
      {od::SmType::MailboxIn, 0x1080, 128, 0x22, true, 0, 0},
      {od::SmType::Outputs, 0x1100, 0, 0x64, true, 0, 0},
      {od::SmType::Inputs, 0x1400, 0, 0x20, true, 0, 0},
  };
  d.fmmus = {od::FmmuUsage::Outputs, od::FmmuUsage::Inputs, od::FmmuUsage::MailboxState};
  d.dc_op_modes = {{"FreeRun", "Free Run", 0x0000, 1, 0, 0, 0},
                   {"DC", "DC Sync0", 0x0300, 1, 0, 0, 0}};

  constexpr std::uint16_t kRwRx = Access::kRw | Access::kRxPdoMappable;
  constexpr std::uint16_t kRoTx = Access::kRo | Access::kTxPdoMappable;
  auto& od = d.dictionary;
  put(od, var(0x1000, "Device type", DataType::Unsigned32, 32, Access::kRo, le(0x00020192, 4)));
  put(od, var(0x1008, "Device name", DataType::VisibleString, 80, Access::kRo,
              od::Value{'T', 'e', 's', 't', ' ', 'S', 'e', 'r', 'v', 'o'}));
  {
    Object o;
    o.index = 0x1018;
    o.name = "Identity";
    o.code = ObjectCode::Record;
    o.type = DataType::Identity;
    o.entries = {count(4),
                 entry(1, "Vendor ID", DataType::Unsigned32, 32, Access::kRo, le(0xABC, 4)),
                 entry(2, "Product code", DataType::Unsigned32, 32, Access::kRo, le(0x1234, 4)),
                 entry(3, "Revision", DataType::Unsigned32, 32, Access::kRo, le(0x20001, 4)),
                 entry(4, "Serial number", DataType::Unsigned32, 32, Access::kRo, le(0, 4))};
    put(od, o);
  }
  {
    Object o;
    o.index = 0x1600;
    o.name = "RxPDO 1";
    o.code = ObjectCode::Array;
    o.type = DataType::Unsigned32;
    constexpr std::uint16_t kPreOpRw = Access::kRo | Access::kWritePreOp;
    o.entries = {count(4, kPreOpRw),
                 entry(1, "Entry 1", DataType::Unsigned32, 32, kPreOpRw, le(0x60400010, 4)),
                 entry(2, "Entry 2", DataType::Unsigned32, 32, kPreOpRw, le(0x607A0020, 4)),
                 entry(3, "Entry 3", DataType::Unsigned32, 32, kPreOpRw, le(0x60600008, 4)),
                 entry(4, "Entry 4", DataType::Unsigned32, 32, kPreOpRw, le(0x00000008, 4))};
    put(od, o);
  }
  {
    Object o;
    o.index = 0x2000;
    o.name = "Tuning";
    o.code = ObjectCode::Record;
    o.type = DataType::Record;
    o.entries = {count(3),
                 entry(1, "Enable", DataType::Boolean, 1, Access::kRw, le(1, 1)),
                 entry(2, "Gain", DataType::Integer16, 16, Access::kRw | Access::kBackup,
                       le(0xFF9C, 2)),
                 entry(3, "Filter", DataType::Real32, 32, Access::kRw, le(0x3F800000, 4))};
    o.entries[2].min_value = le(0xFC18, 2);  // -1000
    o.entries[2].max_value = le(0x03E8, 2);  // 1000
    put(od, o);
  }
  put(od, var(0x6040, "Controlword", DataType::Unsigned16, 16, kRwRx, le(0, 2)));
  put(od, var(0x6041, "Statusword", DataType::Unsigned16, 16, kRoTx, le(0, 2)));
  put(od, var(0x6060, "Modes of operation", DataType::Integer8, 8,
              Access::kRw | Access::kRxPdoMappable, le(8, 1)));
  put(od, var(0x6064, "Position actual value", DataType::Integer32, 32, kRoTx, le(0, 4)));
  {
    Object o = var(0x607A, "Target position", DataType::Integer32, 32, kRwRx, le(0, 4));
    o.entries[0].min_value = le(0x80000000, 4);
    o.entries[0].max_value = le(0x7FFFFFFF, 4);
    put(od, o);
  }
  // Writable in PreOp and SafeOp only, readable in all states.
  put(od, var(0x6502, "Supported drive modes", DataType::Unsigned32, 32,
              Access::kReadAll | Access::kWritePreOp | Access::kWriteSafeOp, le(0x000003A5, 4)));

  od::Pdo rx;
  rx.index = 0x1600;
  rx.name = "RxPDO 1";
  rx.sm = 2;
  rx.entries = {{0x6040, 0, 16, "Controlword", DataType::Unsigned16},
                {0x607A, 0, 32, "Target position", DataType::Integer32},
                {0x6060, 0, 8, "Modes of operation", DataType::Integer8},
                {0x0000, 0, 8, "", DataType::Unsigned8}};
  d.rx_pdos.push_back(rx);
  od::Pdo tx;
  tx.index = 0x1A00;
  tx.name = "TxPDO 1";
  tx.sm = 3;
  tx.fixed = true;
  tx.mandatory = true;
  tx.entries = {{0x6041, 0, 16, "Statusword", DataType::Unsigned16},
                {0x6064, 0, 32, "Position actual value", DataType::Integer32}};
  d.tx_pdos.push_back(tx);
  d.drive = od::DriveProfile{};
  d.drive->supported_modes = 0x000003A5;
  return d;
}

}  // namespace ecat::esi::test
