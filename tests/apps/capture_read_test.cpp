// The reading half of `ecat-master --capture` (apps/ecat-master/capture_read.cpp)
// against in-process virtual slaves (tests/master/in_process_bus.hpp): the
// ESC registers and every SII byte the size word announces, capped at 64 KiB;
// a slave whose SDO information fails is captured from its SII alone, with
// the note that says so; a slave with SDO information gives its dictionary
// with the uploaded values as defaults.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>

#include "apps/ecat-master/capture_read.hpp"
#include "esi/capture_model.hpp"
#include "esi/device_loader.hpp"
#include "esi/esi_writer_device_xml.hpp"
#include "esi/sii_writer.hpp"
#include "tests/master/in_process_bus.hpp"

namespace ecat::app {
namespace {

using master::test::InProcessBus;
using master::test::device_path;

// A variant of the default drive written to the test output directory.
std::string variant(const std::string& name, void (*change)(od::DeviceDescription&)) {
  auto d = esi::load_device_file(device_path("generic-servo.xml"));
  EXPECT_TRUE(d);
  change(*d);
  const std::string path = std::string(ECAT_BINARY_DIR) + "/test-output/" + name;
  std::filesystem::create_directories(std::filesystem::path(path).parent_path());
  std::ofstream(path) << esi::write_device_xml(*d);
  return path;
}

void to_preop(master::Master& m) {
  ASSERT_TRUE(m.configure_mailbox(0).has_value());
  auto st = m.request_state(0, master::AlState::PreOp);
  ASSERT_TRUE(st.has_value());
  ASSERT_TRUE(st->is(master::AlState::PreOp));
}

TEST(CaptureRead, SiiAndEscRegistersAsTheSlaveHoldsThem) {
  InProcessBus bus;
  ASSERT_TRUE(bus.add(device_path("generic-servo.xml")));
  master::Master m(bus.transport, bus.clock);
  ASSERT_EQ(m.scan().value_or(0), 1u);
  esi::CaptureInput in;
  ASSERT_TRUE(read_slave_memory(m, 0, in));
  const auto& image = bus.chain()[0].device();
  auto sii = esi::write_sii(image);
  ASSERT_TRUE(sii) << sii.error();
  const std::vector<std::uint8_t>& expected = *sii;
  // Every byte the size word announces: the whole EEPROM as the slave holds it.
  EXPECT_EQ(in.sii.size(), static_cast<std::size_t>(image.esc.eeprom_bytes));
  ASSERT_GE(in.sii.size(), expected.size());
  EXPECT_TRUE(std::equal(expected.begin(), expected.end(), in.sii.begin()));
  EXPECT_EQ(in.esc_info[0], bus.chain()[0].esc().register_u16(0x0000) & 0xFF);  // ESC type
  EXPECT_EQ(in.esc_info[4], bus.chain()[0].esc().register_u16(0x0004) & 0xFF);  // FMMUs supported
}

// A size word announcing 8 MiB (0xFFFF: (n+1) * 128 bytes): the capture reads
// 64 KiB and no more (esi::kCaptureMaxSiiBytes).
TEST(CaptureRead, SiiReadStopsAt64KiB) {
  InProcessBus bus;
  ASSERT_TRUE(bus.add(device_path("generic-servo.xml")));
  const std::size_t image_bytes = bus.chain()[0].device().esc.eeprom_bytes;
  constexpr std::size_t kSizeWordByte = 0x7C;  // SII word 3Eh (sii-eeprom.md §2)
  ASSERT_TRUE(bus.chain()[0].esc().patch_eeprom_and_reload(kSizeWordByte, 0xFF));
  ASSERT_TRUE(bus.chain()[0].esc().patch_eeprom_and_reload(kSizeWordByte + 1, 0xFF));
  master::Master m(bus.transport, bus.clock);
  ASSERT_EQ(m.scan().value_or(0), 1u);
  esi::CaptureInput in;
  ASSERT_TRUE(read_slave_memory(m, 0, in));
  EXPECT_EQ(in.sii.size(), esi::kCaptureMaxSiiBytes);
  EXPECT_EQ(in.sii[kSizeWordByte], 0xFF);
  EXPECT_EQ(in.sii[kSizeWordByte + 1], 0xFF);
  // Beyond the EEPROM the ESC reads 0xFFFF (esc/sii_interface.cpp).
  EXPECT_EQ(in.sii[image_bytes], 0xFF);
  EXPECT_EQ(in.sii.back(), 0xFF);
  // The model says the size word announces more than a capture reads.
  auto model = esi::device_from_capture(in);
  ASSERT_TRUE(model) << model.error();
  std::string notes;
  for (const auto& n : model->notes) notes += n + "\n";
  EXPECT_NE(notes.find("SII: the size word announces 8388608 bytes, the image read has 65536; "),
            std::string::npos) << notes;
}

// SDO information that fails (the slave's CoE has none and answers with a
// mailbox error, whatever a master expects): one note, no dictionary; the
// model then comes from the SII alone.
TEST(CaptureRead, SdoInformationFailingLeavesTheSiiPath) {
  const std::string file = variant("capture_read_no_sdo_info.xml", [](od::DeviceDescription& d) { d.mailbox.sdo_info = false; });
  InProcessBus bus;
  ASSERT_TRUE(bus.add(file));
  master::Master m(bus.transport, bus.clock);
  ASSERT_EQ(m.scan().value_or(0), 1u);
  esi::CaptureInput in;
  ASSERT_TRUE(read_slave_memory(m, 0, in));
  to_preop(m);
  std::vector<std::string> notes;
  read_dictionary(m, 0, in, notes);
  EXPECT_FALSE(in.dictionary_read);
  EXPECT_TRUE(in.objects.empty());
  ASSERT_EQ(notes.size(), 1u);
  // The slave's CoE answers SDO information with a mailbox error reply
  // (ETG.1000.4 §5.6: service not supported).
  EXPECT_EQ(notes[0], "SDO information: OD list failed (mailbox error reply); dictionary not captured");
  auto model = esi::device_from_capture(in);
  ASSERT_TRUE(model) << model.error();
  const auto& dev = bus.chain()[0].device();
  EXPECT_EQ(model->device.identity.product_code, dev.identity.product_code);
  // The PDOs are the SII's, their objects created as process data.
  EXPECT_EQ(model->device.rx_pdos.size(), dev.rx_pdos.size());
  EXPECT_EQ(model->device.tx_pdos.size(), dev.tx_pdos.size());
  EXPECT_EQ(model->device.dictionary.find(0x6502), nullptr);  // not mapped, not in the SII
  EXPECT_TRUE(std::any_of(model->notes.begin(), model->notes.end(),
                          [](const std::string& n) { return n.find("dictionary") != std::string::npos; }));
}

TEST(CaptureRead, DictionaryThroughSdoInformationWithUploadedValues) {
  InProcessBus bus;
  ASSERT_TRUE(bus.add(device_path("generic-servo.xml")));
  master::Master m(bus.transport, bus.clock);
  ASSERT_EQ(m.scan().value_or(0), 1u);
  esi::CaptureInput in;
  ASSERT_TRUE(read_slave_memory(m, 0, in));
  to_preop(m);
  std::vector<std::string> notes;
  read_dictionary(m, 0, in, notes);
  EXPECT_TRUE(in.dictionary_read);
  const auto& dev = bus.chain()[0].device();
  EXPECT_EQ(in.objects.size(), dev.dictionary.size());
  auto it = std::find_if(in.objects.begin(), in.objects.end(), [](const auto& o) { return o.index == 0x6502; });
  ASSERT_NE(it, in.objects.end());
  ASSERT_EQ(it->entries.size(), 1u);
  ASSERT_TRUE(it->entries[0].value);
  EXPECT_EQ(*it->entries[0].value, dev.dictionary.find(0x6502, 0)->default_value);
}

}  // namespace
}  // namespace ecat::app
