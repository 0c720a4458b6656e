// The capture conversion (esi/capture_model.hpp): what ecat-master --capture
// reads off a slave (SII image, ESC registers 0x0000-0x000F, SDO information
// replies with uploaded values) into a device description. Exact fields from
// known inputs; a slave without CoE from its SII alone, with notes; damaged
// input (truncated SII, a size word that lies, lying lengths in SDO
// information) gives a clear error or a note, never a crash.
#include <gtest/gtest.h>

#include <algorithm>
#include <random>

#include "esi/capture_model.hpp"
#include "esi/device_loader.hpp"
#include "esi/esi_writer_device_xml.hpp"
#include "esi/sii_parser.hpp"
#include "esi/sii_writer.hpp"

namespace ecat::esi {
namespace {

using Bytes = std::vector<std::uint8_t>;

bool has_note(const std::vector<std::string>& notes, const std::string& part) {
  return std::any_of(notes.begin(), notes.end(), [&](const std::string& n) { return n.find(part) != std::string::npos; });
}

std::string all_notes(const std::vector<std::string>& notes) {
  std::string s;
  for (const auto& n : notes) s += n + "\n";
  return s;
}

// An EL2004-like digital output terminal without a mailbox: SM0 outputs at
// 0F00h, one RxPDO 1600h with 7000h:01 and a 3-bit gap and 7010h:01..04.
SiiImage dio_image() {
  SiiImage img;
  img.config.pdi_control = 0x0104;
  img.config.sync_impulse_length = 0;
  img.vendor_id = 0x00000002;
  img.product_code = 0x07D43052;
  img.revision = 0x00110000;
  img.serial = 42;
  img.size_word = 15;
  img.version = sii::kVersion;
  img.strings = {"EL-DIO", "DigOut", "Out 1 name", "Channel 1", "Outputs"};
  SiiGeneral g;
  g.group_idx = 2;
  g.order_idx = 1;
  g.name_idx = 3;
  g.physical_ports = 0x0033;  // EBUS, EBUS
  img.general = g;
  img.fmmus = {sii::kFmmuOutputs};
  img.sync_managers = {SiiSyncManager{0x0F00, 1, 0x44, 0, sii::kSmEnable, 3}};
  SiiPdo p;
  p.index = 0x1600;
  p.sync_manager = 0;
  p.name_idx = 5;
  p.flags = sii::kPdoFixed | sii::kPdoMandatory | sii::kPdoDefault;
  p.entries.push_back(SiiPdoEntry{0x7000, 1, 4, 0x01, 1, 0});
  p.entries.push_back(SiiPdoEntry{0x0000, 0, 0, 0x00, 3, 0});
  for (std::uint8_t k = 1; k <= 4; ++k) p.entries.push_back(SiiPdoEntry{0x7010, k, 0, 0x01, 1, 0});
  img.rx_pdos.push_back(p);
  return img;
}

Bytes encode(const SiiImage& img, std::size_t bytes = 2048) {
  auto out = encode_sii(img, bytes);
  EXPECT_TRUE(out) << out.error();
  return out ? *out : Bytes{};
}

// ET1100-like registers: type 11h, revision 2, build 1234h, 8 FMMUs, 8 SMs,
// 8 KiB RAM, ports 0/1 MII (port descriptor 0Fh), DC + 64-bit DC.
std::array<std::uint8_t, kEscInfoBytes> et1100_registers() {
  return {0x11, 0x02, 0x34, 0x12, 0x08, 0x08, 0x08, 0x0F, 0x0C, 0x00, 0, 0, 0, 0, 0, 0};
}

// The captured device file loads, and from its first load on it is a fixed
// point: load -> device XML -> load -> device XML (the loader derives the
// objects a device file may leave out: 1000h, 1018h, 1C00h, 16xxh, 1C1xh).
void expect_reloads_identically(const od::DeviceDescription& d) {
  const std::string first = write_device_xml(d);
  auto back = load_device_string(first, "capture.xml");
  ASSERT_TRUE(back) << back.error().to_string() << "\n" << first;
  const std::string second = write_device_xml(*back);
  auto again = load_device_string(second, "capture.xml");
  ASSERT_TRUE(again) << again.error().to_string();
  EXPECT_EQ(write_device_xml(*again), second);
}

TEST(CaptureModel, EscRegistersGiveTheSiliconsProperties) {
  od::DeviceDescription d;
  apply_esc_registers(et1100_registers(), d);
  EXPECT_EQ(d.esc.esc_type, 0x11);
  EXPECT_EQ(d.esc.revision, 0x02);
  EXPECT_EQ(d.esc.build, 0x1234);
  EXPECT_EQ(d.esc.fmmu_count, 8);
  EXPECT_EQ(d.esc.sm_count, 8);
  EXPECT_EQ(d.esc.process_ram_bytes, 8192u);
  EXPECT_EQ(d.esc.physics, "YY");
  EXPECT_TRUE(d.esc.dc_supported);
  EXPECT_TRUE(d.esc.dc_64bit);
  EXPECT_FALSE(d.esc.no_lrw);
  auto regs = et1100_registers();
  regs[7] = 0x3B;  // port 0 MII, 1 E-bus, 2 MII, 3 not implemented: an EK1100
  regs[8] = 0x00;
  regs[9] = 0x02;  // feature bit 9: LRW not supported
  apply_esc_registers(regs, d);
  EXPECT_EQ(d.esc.physics, "YKY");
  EXPECT_FALSE(d.esc.dc_supported);
  EXPECT_TRUE(d.esc.no_lrw);
}

TEST(CaptureModel, SlaveWithoutCoeFromItsSiiAlone) {
  CaptureInput in;
  in.sii = encode(dio_image());
  in.esc_info = et1100_registers();
  auto r = device_from_capture(in);
  ASSERT_TRUE(r) << r.error();
  const od::DeviceDescription& d = r->device;
  EXPECT_EQ(d.identity.vendor_id, 0x00000002u);
  EXPECT_EQ(d.identity.product_code, 0x07D43052u);
  EXPECT_EQ(d.identity.revision, 0x00110000u);
  EXPECT_EQ(d.identity.serial, 42u);
  EXPECT_EQ(d.identity.name, "Out 1 name");
  EXPECT_EQ(d.identity.type_name, "EL-DIO");
  EXPECT_EQ(d.identity.group_type, "DigOut");
  EXPECT_FALSE(d.mailbox.coe);
  EXPECT_EQ(d.esc.pdi_control, 0x0104);
  EXPECT_EQ(d.esc.eeprom_bytes, 2048);
  ASSERT_EQ(d.sync_managers.size(), 1u);
  EXPECT_EQ(d.sync_managers[0].type, od::SmType::Outputs);
  EXPECT_EQ(d.sync_managers[0].start_address, 0x0F00);
  EXPECT_EQ(d.sync_managers[0].default_size, 1);
  EXPECT_EQ(d.sync_managers[0].control, 0x44);
  EXPECT_TRUE(d.sync_managers[0].enable);
  ASSERT_EQ(d.fmmus.size(), 1u);
  EXPECT_EQ(d.fmmus[0], od::FmmuUsage::Outputs);
  ASSERT_EQ(d.rx_pdos.size(), 1u);
  EXPECT_TRUE(d.tx_pdos.empty());
  const od::Pdo& p = d.rx_pdos[0];
  EXPECT_EQ(p.index, 0x1600);
  EXPECT_EQ(p.name, "Outputs");
  EXPECT_TRUE(p.fixed);
  EXPECT_TRUE(p.mandatory);
  ASSERT_EQ(p.sm, std::optional<std::uint8_t>(0));
  ASSERT_EQ(p.entries.size(), 6u);
  EXPECT_EQ(p.entries[0].name, "Channel 1");
  EXPECT_EQ(p.entries[1].index, 0);
  EXPECT_EQ(p.entries[1].bit_length, 3);
  EXPECT_EQ(p.bit_length(), 8u);
  // The PDO entries' objects, created as process data: 7000h a RECORD with
  // SI0 = 1, 7010h with SI0 = 4, rw and RxPDO-mappable, default 0.
  const od::Entry* e = d.dictionary.find(0x7000, 1);
  ASSERT_NE(e, nullptr);
  EXPECT_EQ(e->type, od::DataType::Boolean);
  EXPECT_EQ(e->bit_length, 1);
  EXPECT_TRUE(e->access.writable());
  EXPECT_TRUE(e->access.rx_mappable());
  ASSERT_NE(d.dictionary.find(0x7010, 0), nullptr);
  EXPECT_EQ(d.dictionary.find(0x7010, 0)->default_value, Bytes{4});
  EXPECT_EQ(d.dictionary.find(0x7000, 0)->default_value, Bytes{1});
  EXPECT_EQ(d.dictionary.size(), 2u);
  EXPECT_TRUE(has_note(r->notes, "PDO 1600h: 7010h:04 has no dictionary object; created as process data (1 bits)"))
      << all_notes(r->notes);
  EXPECT_FALSE(has_note(r->notes, "not read over SDO information"));  // no CoE: nothing expected of it
  expect_reloads_identically(d);
}

TEST(CaptureModel, SiiOfTheCapturedDeviceIsTheImageCaptured) {
  // The twin of a capture writes its SII from the device file: for the
  // capture to be a fixed point, that image must be the one read.
  CaptureInput in;
  in.sii = encode(dio_image());
  auto r = device_from_capture(in);
  ASSERT_TRUE(r) << r.error();
  auto written = write_sii(r->device);
  ASSERT_TRUE(written) << written.error();
  auto parsed = parse_sii(*written);
  ASSERT_TRUE(parsed) << parsed.error();
  auto original = parse_sii(in.sii);
  ASSERT_TRUE(original);
  // PDOs as the image has them, but for string indices (the writer orders
  // its string table its own way): index, SM, flags, entries.
  ASSERT_EQ(parsed->rx_pdos.size(), 1u);
  const SiiPdo& a = parsed->rx_pdos[0];
  const SiiPdo& b = original->rx_pdos[0];
  EXPECT_EQ(a.index, b.index);
  EXPECT_EQ(a.sync_manager, b.sync_manager);
  EXPECT_EQ(a.flags, b.flags);
  ASSERT_EQ(a.entries.size(), b.entries.size());
  for (std::size_t k = 0; k < a.entries.size(); ++k) {
    EXPECT_EQ(a.entries[k].index, b.entries[k].index);
    EXPECT_EQ(a.entries[k].subindex, b.entries[k].subindex);
    EXPECT_EQ(a.entries[k].data_type, b.entries[k].data_type);
    EXPECT_EQ(a.entries[k].bit_length, b.entries[k].bit_length);
  }
  EXPECT_EQ(parsed->string_at(a.name_idx), "Outputs");
  EXPECT_EQ(parsed->string_at(parsed->general->order_idx), "EL-DIO");
  EXPECT_EQ(parsed->general->physical_ports, 0x0033);  // no port descriptor read: the SII's ports
  EXPECT_EQ(parsed->sync_managers, original->sync_managers);
  EXPECT_EQ(parsed->fmmus, original->fmmus);
  EXPECT_EQ(parsed->vendor_id, original->vendor_id);
  EXPECT_EQ(parsed->product_code, original->product_code);
  EXPECT_EQ(parsed->revision, original->revision);
  EXPECT_EQ(parsed->serial, original->serial);
  EXPECT_EQ(parsed->config, original->config);
  EXPECT_EQ(parsed->size_word, original->size_word);
}

// A CoE slave's SII (mailbox SM0/SM1, outputs SM2, inputs SM3).
SiiImage servo_image() {
  SiiImage img;
  img.vendor_id = 0x0000ABCD;
  img.product_code = 0x00000402;
  img.revision = 3;
  img.size_word = 15;
  img.version = sii::kVersion;
  img.mailbox_protocols = sii::kProtoCoE;
  img.standard_mailbox = {0x1000, 128, 0x1080, 128};
  img.strings = {"SERVO-1", "Drive", "Servo 1"};
  SiiGeneral g;
  g.group_idx = 2;
  g.order_idx = 1;
  g.name_idx = 3;
  g.coe_details = sii::kCoeEnableSdo | sii::kCoeSdoInfo;
  img.general = g;
  img.fmmus = {sii::kFmmuOutputs, sii::kFmmuInputs, sii::kFmmuSyncMStatus};
  img.sync_managers = {SiiSyncManager{0x1000, 128, 0x26, 0, 1, 1}, SiiSyncManager{0x1080, 128, 0x22, 0, 1, 2},
                       SiiSyncManager{0x1100, 0, 0x64, 0, 1, 3}, SiiSyncManager{0x1180, 0, 0x20, 0, 1, 4}};
  return img;
}

constexpr std::uint16_t kRo = od::Access::kRo, kRw = od::Access::kRw;
constexpr std::uint16_t kTxMap = od::Access::kTxPdoMappable, kRxMap = od::Access::kRxPdoMappable;
constexpr std::uint16_t kUdint = 0x0007, kUint = 0x0006, kUsint = 0x0005, kVisible = 0x0009;

CapturedObject var(std::uint16_t index, std::uint16_t type, std::uint16_t bits, std::uint16_t access, Bytes value,
                   std::string name) {
  return CapturedObject{index, type, 0, 7, name, {CapturedEntry{0, type, bits, access, name, std::move(value)}}};
}

std::vector<CapturedObject> servo_objects() {
  std::vector<CapturedObject> o;
  o.push_back(var(0x1000, kUdint, 32, kRo, {0x92, 0x01, 0x02, 0x00}, "Device type"));
  o.push_back(var(0x1008, kVisible, 64, kRo, {'S', 'e', 'r', 'v', 'o', 0, 0, 0}, "Device name"));
  CapturedObject id{0x1018, 0x0023, 4, 9, "Identity", {}};
  id.entries.push_back({0, kUsint, 8, kRo, "Number of entries", Bytes{4}});
  id.entries.push_back({1, kUdint, 32, kRo, "Vendor ID", Bytes{0xCD, 0xAB, 0, 0}});
  id.entries.push_back({2, kUdint, 32, kRo, "Product code", Bytes{0x02, 0x04, 0, 0}});
  o.push_back(id);
  CapturedObject map{0x1A00, 0x0021, 2, 9, "Inputs", {}};
  map.entries.push_back({0, kUsint, 8, kRw, "Number of entries", Bytes{2}});
  map.entries.push_back({1, kUdint, 32, kRw, "Entry 1", Bytes{0x10, 0x00, 0x41, 0x60}});  // 6041:00, 16 bits
  map.entries.push_back({2, kUdint, 32, kRw, "Entry 2", Bytes{0x20, 0x00, 0x64, 0x60}});  // 6064:00, 32 bits
  o.push_back(map);
  CapturedObject assign{0x1C13, kUint, 1, 8, "TxPDO assign", {}};
  assign.entries.push_back({0, kUsint, 8, kRw, "Number of entries", Bytes{1}});
  assign.entries.push_back({1, kUint, 16, kRw, "PDO 1", Bytes{0x00, 0x1A}});
  o.push_back(assign);
  o.push_back(var(0x6041, kUint, 16, kRo | kTxMap, {0x50, 0x02}, "Statusword"));
  o.push_back(var(0x6064, 0x0004, 32, kRo | kTxMap, {0x78, 0x56, 0x34, 0x12}, "Position actual value"));
  o.push_back(var(0x607A, 0x0004, 32, kRw | kRxMap, {0x10, 0x27, 0, 0}, "Target position"));
  return o;
}

TEST(CaptureModel, DictionaryFromSdoInformation) {
  CaptureInput in;
  in.sii = encode(servo_image());
  in.esc_info = et1100_registers();
  in.objects = servo_objects();
  in.dictionary_read = true;
  auto r = device_from_capture(in);
  ASSERT_TRUE(r) << r.error();
  const od::DeviceDescription& d = r->device;
  EXPECT_EQ(d.identity.device_type, 0x00020192u);
  EXPECT_TRUE(d.mailbox.coe);
  EXPECT_TRUE(d.mailbox.sdo_info);
  EXPECT_EQ(d.dictionary.size(), 8u);
  // The name's NUL padding is dropped; the uploaded values are the defaults.
  ASSERT_NE(d.dictionary.find(0x1008, 0), nullptr);
  EXPECT_EQ(d.dictionary.find(0x1008, 0)->default_value, (Bytes{'S', 'e', 'r', 'v', 'o'}));
  EXPECT_EQ(d.dictionary.find(0x6064, 0)->default_value, (Bytes{0x78, 0x56, 0x34, 0x12}));
  EXPECT_EQ(d.dictionary.find(0x6064, 0)->type, od::DataType::Integer32);
  EXPECT_EQ(d.dictionary.find(0x607A, 0)->access.bits, kRw | kRxMap);
  EXPECT_EQ(d.dictionary.find(0x1018)->code, od::ObjectCode::Record);
  EXPECT_EQ(d.dictionary.find(0x1C13)->code, od::ObjectCode::Array);
  ASSERT_EQ(d.tx_pdos.size(), 1u);
  EXPECT_TRUE(d.rx_pdos.empty());
  const od::Pdo& p = d.tx_pdos[0];
  EXPECT_EQ(p.index, 0x1A00);
  EXPECT_EQ(p.sm, std::optional<std::uint8_t>(3));  // from 1C13h:01
  EXPECT_FALSE(p.fixed);                             // SI0 writable
  ASSERT_EQ(p.entries.size(), 2u);
  EXPECT_EQ(p.entries[0].index, 0x6041);
  EXPECT_EQ(p.entries[0].bit_length, 16);
  EXPECT_EQ(p.entries[0].name, "Statusword");
  EXPECT_EQ(p.entries[1].index, 0x6064);
  EXPECT_EQ(p.entries[1].type, od::DataType::Integer32);
  EXPECT_TRUE(r->notes.empty()) << all_notes(r->notes);
  expect_reloads_identically(d);
}

// What KickCAT's simulated devices answer (docs/twins.md "Capturing KickCAT's
// simulated devices"): VARs named "SubIndex 000" by their entry description or by
// their object description (the other name is the real one), a 512-byte entry
// described as BYTE with 4096 bits, and 1C32h:04 = 401Fh (bits 4:2 all set: SYNC0,
// SYNC1 and subordinated modes supported).
TEST(CaptureModel, KickcatShapedRepliesKeepNamesAndDcSync0) {
  CaptureInput in;
  in.sii = encode(servo_image());
  in.esc_info = et1100_registers();
  in.objects = servo_objects();
  for (CapturedObject& o : in.objects) {
    if (o.index == 0x6041) o.entries.front().name = "SubIndex 000";
    if (o.index == 0x6064) o.name = "SubIndex 000";  // the other way round
  }
  CapturedObject sync{0x1C32, 0x0051, 5, 9, "SM output parameter", {}};
  sync.entries.push_back({0, kUsint, 8, kRo, "SM output parameter", Bytes{5}});
  sync.entries.push_back({1, kUint, 16, kRw, "Synchronization Type", Bytes{0, 0}});
  sync.entries.push_back({4, kUint, 16, kRo, "Synchronization Types supported", Bytes{0x1F, 0x40}});
  sync.entries.push_back({5, kUdint, 32, kRo, "Minimum Cycle Time", Bytes{0xA0, 0x86, 0x01, 0x00}});
  in.objects.push_back(sync);
  CapturedObject bytes{0x58B2, 0x0051, 1, 9, "DT58B2", {}};
  bytes.entries.push_back({0, kUsint, 8, kRw, "SubIndex 000", Bytes{1}});
  bytes.entries.push_back({1, 0x001E, 4096, kRo, "Data1", Bytes(512, 0xA5)});  // BYTE, 512 bytes
  in.objects.push_back(bytes);
  in.dictionary_read = true;
  auto r = device_from_capture(in);
  ASSERT_TRUE(r) << r.error();
  const od::DeviceDescription& d = r->device;
  ASSERT_NE(d.dictionary.find(0x6041, 0), nullptr);
  EXPECT_EQ(d.dictionary.find(0x6041, 0)->name, "Statusword");
  EXPECT_EQ(d.dictionary.find(0x6064, 0)->name, "Position actual value");
  EXPECT_TRUE(d.sync.free_run);
  EXPECT_TRUE(d.sync.sm_synchronous);
  EXPECT_TRUE(d.sync.dc_sync0);
  EXPECT_EQ(d.sync.min_cycle_time_ns, 100000u);
  ASSERT_NE(d.dictionary.find(0x58B2, 1), nullptr);
  EXPECT_EQ(d.dictionary.find(0x58B2, 1)->type, od::DataType::OctetString);
  EXPECT_EQ(d.dictionary.find(0x58B2, 1)->bit_length, 4096);
  EXPECT_EQ(d.dictionary.find(0x58B2, 1)->default_value, Bytes(512, 0xA5));
  ASSERT_EQ(r->notes.size(), 1u) << all_notes(r->notes);
  EXPECT_EQ(r->notes[0], "58B2h:01: BYTE of 4096 bits; captured as OCTET_STRING");
  // Bit 2 clear (only SYNC1, 0x0008): no SYNC0.
  for (CapturedObject& o : in.objects) {
    if (o.index == 0x1C32) o.entries[2].value = Bytes{0x0B, 0x00};
  }
  auto sync1_only = device_from_capture(in);
  ASSERT_TRUE(sync1_only) << sync1_only.error();
  EXPECT_FALSE(sync1_only->device.sync.dc_sync0);
  expect_reloads_identically(d);
}

TEST(CaptureModel, CoeSlaveWithoutDictionaryGetsANote) {
  SiiImage img = servo_image();
  SiiPdo p;
  p.index = 0x1A00;
  p.sync_manager = 3;
  p.entries.push_back(SiiPdoEntry{0x6041, 0, 0, 0x06, 16, 0});
  img.tx_pdos.push_back(p);
  CaptureInput in;
  in.sii = encode(img);
  auto r = device_from_capture(in);
  ASSERT_TRUE(r) << r.error();
  EXPECT_TRUE(has_note(r->notes, "dictionary: not read over SDO information")) << all_notes(r->notes);
  ASSERT_NE(r->device.dictionary.find(0x6041, 0), nullptr);
  EXPECT_EQ(r->device.dictionary.find(0x6041)->code, od::ObjectCode::Var);
  EXPECT_EQ(r->device.dictionary.find(0x6041, 0)->type, od::DataType::Unsigned16);
}

TEST(CaptureModel, LyingSdoInformationBecomesNotes) {
  std::vector<CapturedObject> o = servo_objects();
  // An upload of 2 bytes for a 32-bit entry: default 0.
  o.push_back(var(0x2000, kUdint, 32, kRw, {0x01, 0x02}, "Short upload"));
  // Described as 16 bits but typed UNSIGNED32: the type's size wins.
  o.push_back(var(0x2001, kUdint, 16, kRw, {0x01, 0x02, 0x03, 0x04}, "Wrong length"));
  // A string longer than its description.
  o.push_back(var(0x2002, kVisible, 16, kRo, {'a', 'b', 'c', 'd'}, "Long string"));
  // An unknown data type of 24 bits: captured as UNSIGNED24; of 40 bits (no
  // UNSIGNEDn the rule gives): as an OCTET_STRING.
  o.push_back(var(0x2003, 0x0777, 24, kRo, {1, 2, 3}, "Odd type"));
  o.push_back(var(0x2006, 0x0777, 40, kRo, {1, 2, 3, 4, 5}, "Odd type, 40 bits"));
  // An unknown data type of 12 bits: no device-file type, the object has no SI0 left.
  o.push_back(var(0x2004, 0x0777, 12, kRo, {}, "Bits"));
  // No subindex 0 described.
  o.push_back(CapturedObject{0x2005, kUint, 1, 8, "No count", {CapturedEntry{1, kUint, 16, kRo, "x", Bytes{1, 0}}}});
  // A mapping whose SI0 says 3 entries, only 1 described; an object code of 5.
  CapturedObject map{0x1600, 0x0021, 3, 5, "Outputs", {}};
  map.entries.push_back({0, kUsint, 8, kRo, "Number of entries", Bytes{3}});
  map.entries.push_back({1, kUdint, 32, kRo, "Entry 1", Bytes{0x20, 0x00, 0x7A, 0x60}});
  o.push_back(map);
  // An assignment of a PDO the dictionary does not have, and of an RxPDO to the inputs SM.
  CapturedObject assign{0x1C12, kUint, 2, 8, "RxPDO assign", {}};
  assign.entries.push_back({0, kUsint, 8, kRw, "Number of entries", Bytes{2}});
  assign.entries.push_back({1, kUint, 16, kRw, "PDO 1", Bytes{0x01, 0x16}});
  assign.entries.push_back({2, kUint, 16, kRw, "PDO 2", Bytes{0x00, 0x16}});
  o.push_back(assign);
  CapturedObject wrong{0x1C13, kUint, 2, 8, "TxPDO assign", {}};
  wrong.entries.push_back({0, kUsint, 8, kRw, "Number of entries", Bytes{2}});
  wrong.entries.push_back({1, kUint, 16, kRw, "PDO 1", Bytes{0x00, 0x1A}});
  wrong.entries.push_back({2, kUint, 16, kRw, "PDO 2", Bytes{0x00, 0x16}});
  std::replace_if(o.begin(), o.end(), [](const CapturedObject& c) { return c.index == 0x1C13; }, wrong);

  CaptureInput in;
  in.sii = encode(servo_image());
  in.esc_info = et1100_registers();
  in.objects = o;
  in.dictionary_read = true;
  auto r = device_from_capture(in);
  ASSERT_TRUE(r) << r.error();
  const auto& n = r->notes;
  const od::Dictionary& dict = r->device.dictionary;
  EXPECT_TRUE(has_note(n, "2000h:00: uploaded 2 bytes for a 32-bit entry; default 0")) << all_notes(n);
  EXPECT_EQ(dict.find(0x2000, 0)->default_value, (Bytes{0, 0, 0, 0}));
  EXPECT_TRUE(has_note(n, "2001h:00: described as 16 bits, UNSIGNED32 has 32; the type's size is used"));
  EXPECT_EQ(dict.find(0x2001, 0)->bit_length, 32);
  EXPECT_TRUE(has_note(n, "2002h:00: value of 4 bytes longer than the described 16 bits; length taken from the value"));
  EXPECT_EQ(dict.find(0x2002, 0)->bit_length, 32);
  // 24 bits: UNSIGNED24, as for 8, 16, 32 and 64 (od/type_of_bits.hpp); other whole bytes: OCTET_STRING.
  EXPECT_TRUE(has_note(n, "2003h:00: data type 0777h unknown; captured as UNSIGNED24 (24 bits)")) << all_notes(n);
  EXPECT_TRUE(has_note(n, "2006h:00: data type 0777h unknown; captured as OCTET_STRING (40 bits)")) << all_notes(n);
  EXPECT_TRUE(has_note(n, "2004h:00: data type 0777h of 12 bits has no device-file type; left out"));
  EXPECT_EQ(dict.find(0x2004), nullptr);
  EXPECT_TRUE(has_note(n, "2005h: no usable subindex 0; object left out"));
  EXPECT_EQ(dict.find(0x2005), nullptr);
  EXPECT_TRUE(has_note(n, "PDO 1600h: SI0 = 3 but subindex 2 was not read; mapping ends there"));
  EXPECT_TRUE(has_note(n, "1600h: object code 5 is not VAR/ARRAY/RECORD; captured as RECORD"));
  EXPECT_TRUE(has_note(n, "1C12h:01 assigns PDO 1601h, which is not in the dictionary"));
  EXPECT_TRUE(has_note(n, "1C13h:02 assigns PDO 1600h to SM3, which is not its direction's SM; not assigned"));
  ASSERT_EQ(r->device.rx_pdos.size(), 1u);
  EXPECT_EQ(r->device.rx_pdos[0].entries.size(), 1u);
  EXPECT_EQ(r->device.rx_pdos[0].sm, std::optional<std::uint8_t>(2));
  expect_reloads_identically(r->device);
}

TEST(CaptureModel, DamagedSiiIsAClearError) {
  const Bytes good = encode(dio_image());
  CaptureInput in;
  in.sii.assign(good.begin(), good.begin() + 100);  // shorter than the fixed area
  auto r = device_from_capture(in);
  ASSERT_FALSE(r);
  EXPECT_EQ(r.error(), "SII: SII image is 100 bytes, shorter than the 128-byte fixed area");
  // Cut in the middle of the categories: the list runs past the end.
  in.sii.assign(good.begin(), good.begin() + 160);
  r = device_from_capture(in);
  ASSERT_FALSE(r);
  EXPECT_NE(r.error().find("runs past the end"), std::string::npos) << r.error();
}

TEST(CaptureModel, SizeWordThatLiesIsANote) {
  // The size word says 4 KiB, the image read is 2 KiB (a reader that
  // stopped, or an EEPROM smaller than announced): captured with a note,
  // the device file keeps the size of the image read.
  Bytes sii = encode(dio_image());
  sii[sii::kWordSize * 2] = 31;
  CaptureInput in;
  in.sii = sii;
  auto r = device_from_capture(in);
  ASSERT_TRUE(r) << r.error();
  EXPECT_TRUE(has_note(r->notes, "SII: the size word announces 4096 bytes, the image read has 2048")) << all_notes(r->notes);
  EXPECT_EQ(r->device.esc.eeprom_bytes, 2048);
  // A size word the device-file cannot hold (more than 64 KiB): the image's size.
  sii[sii::kWordSize * 2] = 0xFF;
  sii[sii::kWordSize * 2 + 1] = 0xFF;
  in.sii = sii;
  r = device_from_capture(in);
  ASSERT_TRUE(r) << r.error();
  EXPECT_EQ(r->device.esc.eeprom_bytes, 2048);
}

TEST(CaptureModel, MutatedImagesNeverCrash) {
  const Bytes good = encode(servo_image());
  std::mt19937 rng(32);
  std::size_t converted = 0;
  for (int round = 0; round < 3000; ++round) {
    Bytes b = good;
    const int flips = 1 + static_cast<int>(rng() % 8);
    for (int k = 0; k < flips; ++k) {
      // Mostly the header, the fixed area's mailbox words and the first categories.
      const std::size_t at = rng() % 320;
      b[at] = static_cast<std::uint8_t>(rng());
    }
    if (rng() % 4 == 0) b.resize(rng() % b.size());
    CaptureInput in;
    in.sii = b;
    in.esc_info[7] = static_cast<std::uint8_t>(rng());
    auto r = device_from_capture(in);
    if (!r) {
      EXPECT_EQ(r.error().rfind("SII: ", 0), 0u) << r.error();
      continue;
    }
    ++converted;
    (void)write_device_xml(r->device);
  }
  EXPECT_GT(converted, 100u);
}

}  // namespace
}  // namespace ecat::esi
