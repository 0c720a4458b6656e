// Process data on more than one SM per direction, end to end (issue 14,
// docs/twins.md "Process data on several SMs per direction"): the twin of a
// Beckhoff EK1828 (vendor corpus beckhoff-ek18xx.xml; no mailbox, outputs on
// SM0 at 0F00h and SM1 at 0F01h - the ESC's digital output register - and
// inputs on SM2 at 1000h) under the project's master. The master sizes each
// SM from the SII PDOs naming it, programs every SM and one FMMU per run of
// SMs lying back to back (SOEM joins them the same way), and the firmware
// copies each SM's bytes to and from the objects its 1C10h+n assigns.
#include <gtest/gtest.h>

#include <array>
#include <fstream>

#include <unistd.h>

#include "esc/al_status_code.hpp"
#include "esi/esi_writer_device_xml.hpp"
#include "esi/twin_import.hpp"
#include "in_process_bus.hpp"
#include "master/coe_client.hpp"

namespace ecat::master::test {
namespace {

constexpr std::uint32_t kEk1828 = 0x07242C52;
constexpr std::uint32_t kEk1828Revision = 0x00100000;

// The AL status code as the master reads it from 0x0134.
constexpr std::uint16_t code(esc::AlStatusCode c) { return static_cast<std::uint16_t>(c); }

std::string ek1828_device_xml() {
  esi::TwinImportOptions o;
  o.selection.product_code = kEk1828;
  o.selection.revision = kEk1828Revision;
  std::vector<esi::EsiWarning> warnings;
  auto twin = esi::import_twin(std::string(ECAT_SOURCE_DIR) + "/tests/data/esi-vendor/beckhoff-ek18xx.xml", o, &warnings);
  if (!twin) {
    ADD_FAILURE() << twin.error().to_string();
    return {};
  }
  const std::string file = ::testing::TempDir() + "ek1828-" + std::to_string(::getpid()) + ".device.xml";
  std::ofstream(file) << esi::write_device_xml(*twin);
  return file;
}

std::array<std::uint8_t, 16> fmmu(slave::VirtualSlave& s, unsigned n) {
  std::array<std::uint8_t, 16> b{};
  for (unsigned i = 0; i < b.size(); ++i) b[i] = s.esc().memory()[0x0600 + 16 * n + i];
  return b;
}

std::array<std::uint8_t, 8> sm(slave::VirtualSlave& s, unsigned n) {
  std::array<std::uint8_t, 8> b{};
  for (unsigned i = 0; i < b.size(); ++i) b[i] = s.esc().memory()[0x0800 + 8 * n + i];
  return b;
}

class MultiSmTwin : public ::testing::Test {
 protected:
  void SetUp() override {
    const std::string file = ek1828_device_xml();
    ASSERT_FALSE(file.empty());
    ASSERT_TRUE(bus.add(file));
    ASSERT_EQ(master.scan().value_or(0), 1u);
    ASSERT_TRUE(master.request_state(0, AlState::PreOp).value().is(AlState::PreOp));
  }
  InProcessBus bus;
  Master master{bus.transport, bus.clock};
};

TEST_F(MultiSmTwin, SiiNamesEverySmAndItsPdos) {
  const SiiInfo& sii = master.slave(0).sii;
  ASSERT_EQ(sii.sync_managers.size(), 3u);
  EXPECT_EQ(sii.sync_managers[0].start, 0x0F00);
  EXPECT_EQ(sii.sync_managers[0].control, 0x44);
  EXPECT_EQ(sii.sync_managers[0].type, sii::kSmTypeOutputs);
  EXPECT_EQ(sii.sync_managers[1].start, 0x0F01);
  EXPECT_EQ(sii.sync_managers[1].type, sii::kSmTypeOutputs);
  EXPECT_EQ(sii.sync_managers[2].start, 0x1000);
  EXPECT_EQ(sii.sync_managers[2].control, 0x00);
  EXPECT_EQ(sii.sync_managers[2].type, sii::kSmTypeInputs);
  // RxPDO 1600h-1603h on SM0, 1604h-1607h on SM1 (4 bits of gap each), TxPDOs on SM2.
  EXPECT_EQ(sii.default_pdo_bits(false, 0), 8u);
  EXPECT_EQ(sii.default_pdo_bits(false, 1), 8u);
  EXPECT_EQ(sii.default_pdo_bits(true, 2), 8u);
  EXPECT_EQ(sii.default_pdo_bits(false, 2), 0u);
}

TEST_F(MultiSmTwin, EverySmAndFmmuProgrammedAndDataCopiedPerSm) {
  master.size_process_data_from_sii(0);
  const ProcessDataLayout& pd = master.slave(0).pd;
  ASSERT_TRUE(pd.per_sm);
  ASSERT_EQ(pd.sms.size(), 3u);
  ASSERT_TRUE(master.configure_process_data());
  EXPECT_EQ(pd.output_bytes, 2u);
  EXPECT_EQ(pd.input_bytes, 1u);
  EXPECT_EQ(master.expected_wkc(), 3);
  slave::VirtualSlave& s = bus.chain()[0];
  // SM0/SM1/SM2: start, length 1, control, enable (0x0800+8n, Section II).
  EXPECT_EQ(sm(s, 0)[0], 0x00);
  EXPECT_EQ(sm(s, 0)[1], 0x0F);
  EXPECT_EQ(sm(s, 0)[2], 0x01);
  EXPECT_EQ(sm(s, 0)[3], 0x00);
  EXPECT_EQ(sm(s, 0)[4], 0x44);
  EXPECT_EQ(sm(s, 0)[6], 0x01);
  EXPECT_EQ(sm(s, 1)[0], 0x01);
  EXPECT_EQ(sm(s, 1)[1], 0x0F);
  EXPECT_EQ(sm(s, 1)[2], 0x01);
  EXPECT_EQ(sm(s, 1)[4], 0x44);
  EXPECT_EQ(sm(s, 1)[6], 0x01);
  EXPECT_EQ(sm(s, 2)[0], 0x00);
  EXPECT_EQ(sm(s, 2)[1], 0x10);
  EXPECT_EQ(sm(s, 2)[2], 0x01);
  EXPECT_EQ(sm(s, 2)[4], 0x00);
  EXPECT_EQ(sm(s, 2)[6], 0x01);
  // FMMU0: logical 0, 2 bytes, bits 0..7, physical 0F00h (SM0 and SM1 back
  // to back), write, enabled. FMMU1: logical 2, 1 byte, physical 1000h, read.
  EXPECT_EQ(fmmu(s, 0), (std::array<std::uint8_t, 16>{0, 0, 0, 0, 2, 0, 0, 7, 0x00, 0x0F, 0, 0x02, 1, 0, 0, 0}));
  EXPECT_EQ(fmmu(s, 1), (std::array<std::uint8_t, 16>{2, 0, 0, 0, 1, 0, 0, 7, 0x00, 0x10, 0, 0x01, 1, 0, 0, 0}));
  EXPECT_EQ(fmmu(s, 2), (std::array<std::uint8_t, 16>{}));

  auto safe = master.request_state(0, AlState::SafeOp);
  ASSERT_TRUE(safe && safe->is(AlState::SafeOp) && !safe->error()) << (safe ? safe->code : 0);
  // Inputs 6000h:01 and 6020h:01 set: bits 0 and 2 of SM2's byte.
  ecat::coe::ObjectStore& objects = s.firmware().coe().objects();
  ASSERT_TRUE(objects.set<std::uint8_t>(0x6000, 1, 1));
  ASSERT_TRUE(objects.set<std::uint8_t>(0x6020, 1, 1));
  // Outputs: SM0's byte has a 4-bit gap then 7000h/7010h/7020h/7030h:01;
  // SM1's byte 7040h..7070h:01 then a 4-bit gap.
  master.outputs(0)[0] = 0xA0;  // 7010h:01 = 1, 7030h:01 = 1
  master.outputs(0)[1] = 0x09;  // 7040h:01 = 1, 7070h:01 = 1
  for (int c = 0; c < 5; ++c) {
    auto r = master.exchange_process_data();
    ASSERT_TRUE(r && r->ok()) << (r ? r->wkc : 0);
    bus.wait(std::chrono::milliseconds(1));
  }
  auto op = master.request_state(0, AlState::Op);
  ASSERT_TRUE(op && op->is(AlState::Op) && !op->error()) << (op ? op->code : 0);
  for (int c = 0; c < 10; ++c) {
    auto r = master.exchange_process_data();
    ASSERT_TRUE(r) << describe(r.error());
    EXPECT_EQ(r->wkc, 3);
    bus.wait(std::chrono::milliseconds(1));
  }
  EXPECT_EQ(master.inputs(0).size(), 1u);
  EXPECT_EQ(master.inputs(0)[0], 0x05);
  EXPECT_EQ(master.process_image()[2], 0x05);
  // The ESC's digital output register holds what the FMMU wrote...
  EXPECT_EQ(s.esc().memory()[0x0F00], 0xA0);
  EXPECT_EQ(s.esc().memory()[0x0F01], 0x09);
  // ...and the firmware copied each SM's byte into the objects its 1C10h/1C11h assigns.
  EXPECT_EQ(objects.get<std::uint8_t>(0x7000, 1), 0);
  EXPECT_EQ(objects.get<std::uint8_t>(0x7010, 1), 1);
  EXPECT_EQ(objects.get<std::uint8_t>(0x7020, 1), 0);
  EXPECT_EQ(objects.get<std::uint8_t>(0x7030, 1), 1);
  EXPECT_EQ(objects.get<std::uint8_t>(0x7040, 1), 1);
  EXPECT_EQ(objects.get<std::uint8_t>(0x7050, 1), 0);
  EXPECT_EQ(objects.get<std::uint8_t>(0x7060, 1), 0);
  EXPECT_EQ(objects.get<std::uint8_t>(0x7070, 1), 1);
  EXPECT_EQ(objects.get<std::uint16_t>(0x1C10, 0), 4);
  EXPECT_EQ(objects.get<std::uint16_t>(0x1C11, 1), 0x1604);
  EXPECT_EQ(objects.get<std::uint16_t>(0x1C12, 1), 0x1A00);
}

TEST_F(MultiSmTwin, SecondOutputsSmWithAnotherLengthRefusedWith0x001D) {
  master.size_process_data_from_sii(0);
  ASSERT_TRUE(master.configure_process_data());
  // SM1 two bytes long: its PDOs (1604h-1607h) make one byte.
  ASSERT_TRUE(master.write_sync_manager(0, 1, 0x0F01, 2, 0x44, true));
  auto st = master.request_state(0, AlState::SafeOp);
  ASSERT_TRUE(st);
  EXPECT_TRUE(st->is(AlState::PreOp));
  EXPECT_TRUE(st->error());
  EXPECT_EQ(st->code, code(esc::AlStatusCode::InvalidOutputConfiguration));
}

TEST_F(MultiSmTwin, InputsSmLeftOffRefusedWith0x001E) {
  master.size_process_data_from_sii(0);
  ASSERT_TRUE(master.configure_process_data());
  ASSERT_TRUE(master.write_sync_manager(0, 2, 0x1000, 1, 0x00, false));
  auto st = master.request_state(0, AlState::SafeOp);
  ASSERT_TRUE(st);
  EXPECT_TRUE(st->is(AlState::PreOp));
  EXPECT_EQ(st->code, code(esc::AlStatusCode::InvalidInputConfiguration));
}

// NI 9144 (vendor corpus ni-9144.xml): an inputs-only device with an outputs
// SM (SM2, 1000h, DefaultSize 200h) but no RxPDO. SOEM 2.x leaves SM2 at the
// SII's 512 bytes and enables it (it sizes SM2 only from a non-zero
// mapping). SSC built without outputs (MAX_PD_OUTPUT_SIZE 0) has no SM2
// check compiled in, so the device accepts it; the twin does the same.
std::string twin_file(const char* corpus, std::uint32_t product, std::uint32_t revision, const char* name) {
  esi::TwinImportOptions o;
  o.selection.product_code = product;
  o.selection.revision = revision;
  auto twin = esi::import_twin(std::string(ECAT_SOURCE_DIR) + "/tests/data/esi-vendor/" + corpus, o);
  if (!twin) {
    ADD_FAILURE() << twin.error().to_string();
    return {};
  }
  const std::string file = ::testing::TempDir() + name + std::to_string(::getpid()) + ".device.xml";
  std::ofstream(file) << esi::write_device_xml(*twin);
  return file;
}

TEST(OutputsSmWithoutOutputs, EnabledSm2OfAnInputsOnlyDeviceIsAccepted) {
  InProcessBus bus;
  const std::string file = twin_file("ni-9144.xml", 0x23B8, 1, "ni9144-");
  ASSERT_FALSE(file.empty());
  ASSERT_TRUE(bus.add(file));
  Master master(bus.transport, bus.clock);
  ASSERT_EQ(master.scan().value_or(0), 1u);
  ASSERT_TRUE(master.configure_mailbox(0));
  ASSERT_TRUE(master.request_state(0, AlState::PreOp).value().is(AlState::PreOp));
  CoeClient coe(master, 0);
  ASSERT_TRUE(coe.read_pdo_sizes());
  ASSERT_TRUE(master.configure_process_data());
  EXPECT_EQ(master.slave(0).pd.output_bytes, 0u);
  ASSERT_GT(master.slave(0).pd.input_bytes, 0u);
  // What SOEM 2.x writes: SM2 = 1000h, 512 bytes, control 64h, enabled.
  ASSERT_TRUE(master.write_sync_manager(0, 2, 0x1000, 0x200, 0x64, true));
  auto safe = master.request_state(0, AlState::SafeOp);
  ASSERT_TRUE(safe);
  EXPECT_TRUE(safe->is(AlState::SafeOp)) << "code " << safe->code;
  EXPECT_FALSE(safe->error());
  EXPECT_EQ(bus.chain()[0].esc().register_u16(0x0812), 0x0200);
  for (int c = 0; c < 3; ++c) ASSERT_TRUE(master.exchange_process_data());
  auto op = master.request_state(0, AlState::Op);
  ASSERT_TRUE(op);
  EXPECT_TRUE(op->is(AlState::Op)) << "code " << op->code;
}

// A device that has outputs (RxPDOs) but whose assignment is empty: SSC's
// CheckSmSettings refuses an enabled SM2 with a length (0x001D) - the SM
// has to be off when the output size is 0.
TEST(OutputsSmWithoutOutputs, EnabledSm2WithAnEmptyAssignmentIsRefusedWith0x001D) {
  InProcessBus bus;
  ASSERT_TRUE(bus.add(device_path("generic-servo.xml")));
  Master master(bus.transport, bus.clock);
  ASSERT_EQ(master.scan().value_or(0), 1u);
  ASSERT_TRUE(master.configure_mailbox(0));
  ASSERT_TRUE(master.request_state(0, AlState::PreOp).value().is(AlState::PreOp));
  CoeClient coe(master, 0);
  ASSERT_TRUE(coe.download_value(0x1C12, 0, 0, 1));
  ASSERT_TRUE(coe.read_pdo_sizes());
  ASSERT_EQ(master.slave(0).pd.output_bytes, 0u);
  ASSERT_TRUE(master.configure_process_data());
  const std::uint16_t sm2_start = master.slave(0).pd.first(true)->start;
  ASSERT_TRUE(master.write_sync_manager(0, 2, sm2_start, 4, 0x64, true));
  auto st = master.request_state(0, AlState::SafeOp);
  ASSERT_TRUE(st);
  EXPECT_TRUE(st->is(AlState::PreOp));
  EXPECT_EQ(st->code, code(esc::AlStatusCode::InvalidOutputConfiguration));
  // Left off (length 0, disabled) as SOEM writes it for no outputs: SafeOp.
  ASSERT_TRUE(master.acknowledge_error(0));
  ASSERT_TRUE(master.write_sync_manager(0, 2, sm2_start, 0, 0x64, false));
  auto ok = master.request_state(0, AlState::SafeOp);
  ASSERT_TRUE(ok);
  EXPECT_TRUE(ok->is(AlState::SafeOp)) << "code " << ok->code;
}

}  // namespace
}  // namespace ecat::master::test
