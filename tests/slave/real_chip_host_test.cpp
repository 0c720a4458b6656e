// Issue 18: the firmware as `ecat-slave --pdi` runs it on a real chip - no
// VirtualSlave, no look into the ESC: the host sees only the chip's IRQ pin
// and passes the AL event mask the firmware itself programmed (EscLines),
// exactly the loop of apps/ecat-slave/run_spi.cpp, here with the spidev bus
// replaced by the emulated chip. A master brings it to Op and exchanges
// process data; every transaction stays within the chip's framing.
#include <gtest/gtest.h>

#include <type_traits>

#include "esc/segment.hpp"
#include "esi/device_loader.hpp"
#include "master/coe_client.hpp"
#include "master/master.hpp"
#include "pdi_spi/emulated_et1100_spi.hpp"
#include "pdi_spi/emulated_lan9252.hpp"
#include "pdi_spi/et1100_spi_pdi.hpp"
#include "pdi_spi/lan9252_pdi.hpp"
#include "slave/esc_setup.hpp"
#include "slave/firmware.hpp"
#include "transport/in_memory_transport.hpp"

namespace ecat::test {
namespace {

constexpr Nanoseconds kWireTime = std::chrono::microseconds(5);
constexpr Nanoseconds kCycle = std::chrono::milliseconds(1);

template <typename Chip, typename Backend>
void run_like_a_real_host() {
  auto device = esi::load_device_file(std::string(ECAT_SOURCE_DIR) + "/xml/devices/generic-servo.xml");
  ASSERT_TRUE(device) << device.error().to_string();
  auto config = slave::esc_config_for(*device);
  ASSERT_TRUE(config) << config.error();
  ManualClock clock;
  esc::Esc esc(std::move(*config), clock);
  esc::Segment segment;
  segment.add(esc);
  Chip chip(esc);
  Backend pdi(chip);
  if constexpr (std::is_same_v<Backend, pdi_spi::Lan9252Pdi>) {
    ASSERT_TRUE(pdi.init()) << pdi.error();
  }
  slave::Firmware firmware(pdi, *device, slave::SlaveOptions{});

  // The host's pass: IRQ pin, the mask the firmware programmed, deadlines.
  std::uint64_t passes = 0;
  auto host = [&] {
    (void)esc.poll(clock.now());
    const slave::EscLines lines{chip.irq_pin(), firmware.event_mask()};
    if (firmware.wants_poll(clock.now(), lines)) {
      (void)firmware.poll(clock.now(), lines);
      ++passes;
    }
  };
  transport::InMemoryTransport wire([&](Bytes frame) {
    clock.advance(kWireTime);
    (void)segment.process_frame(frame, clock.now());
    host();
  });
  master::Master master(wire, clock);
  auto advance = [&](Nanoseconds d) {
    clock.advance(d);
    host();
  };

  auto n = master.scan();
  ASSERT_TRUE(n);
  ASSERT_EQ(*n, 1u);
  ASSERT_TRUE(master.configure_mailbox(0));
  auto st = master.request_state(0, master::AlState::PreOp);
  ASSERT_TRUE(st && !st->error());
  master::CoeClient coe(master, 0);
  ASSERT_TRUE(coe.read_pdo_sizes());
  ASSERT_TRUE(master.configure_process_data());
  st = master.request_state(0, master::AlState::SafeOp);
  ASSERT_TRUE(st && !st->error());
  for (int c = 0; c < 10; ++c) {
    advance(kCycle);
    ASSERT_TRUE(master.exchange_process_data());
  }
  st = master.request_state(0, master::AlState::Op);
  ASSERT_TRUE(st && !st->error());
  const std::uint64_t cycles_before = firmware.status().application_cycles;
  for (int c = 0; c < 50; ++c) {
    advance(kCycle);
    auto r = master.exchange_process_data();
    ASSERT_TRUE(r);
    EXPECT_TRUE(r->ok());
  }
  EXPECT_EQ(firmware.esm().state(), esc::AlState::Op);
  EXPECT_GE(firmware.status().application_cycles - cycles_before, 50u);
  // SDO over the mailbox still answers in Op.
  auto id = coe.upload_value(0x1018, 2);
  ASSERT_TRUE(id);
  EXPECT_EQ(*id, device->identity.product_code);
  EXPECT_FALSE(pdi.failed()) << pdi.error();
  EXPECT_EQ(chip.violations(), 0u);
  EXPECT_GT(passes, 60u);
}

TEST(RealChipHost, Lan9252ReachesOpOnItsIrqPinAlone) {
  run_like_a_real_host<pdi_spi::EmulatedLan9252, pdi_spi::Lan9252Pdi>();
}

TEST(RealChipHost, Et1100ReachesOpOnItsIrqPinAlone) {
  run_like_a_real_host<pdi_spi::EmulatedEt1100Spi, pdi_spi::Et1100SpiPdi>();
}

}  // namespace
}  // namespace ecat::test
