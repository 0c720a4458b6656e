// Master code under test in your own CI: a GoogleTest fixture puts a line of
// virtual CiA402 drives (real ESC, ESM, CoE and drive firmware) behind an
// in-memory wire on simulated time, and start_line() runs against it.
#include "start_line.hpp"

#include <gtest/gtest.h>

#include <chrono>
#include <string>
#include <vector>

#include "esi/device_loader.hpp"
#include "slave/chain.hpp"
#include "transport/in_memory_transport.hpp"

namespace {

using namespace std::chrono_literals;

class VirtualLine : public ::testing::Test {
 protected:
  // Device files installed with ecatslave (share/ecatslave/devices).
  const std::vector<std::string> files{"generic-servo.xml", "simtach-rse.xml", "welcon-servo.xml"};

  void SetUp() override {
    for (const auto& name : files) {
      auto device = ecat::esi::load_device_file(std::string(ECATSLAVE_DEVICES) + "/" + name);
      ASSERT_TRUE(device) << device.error().to_string();
      identities.push_back(device->identity);
      ecat::slave::SlaveOptions options;
      options.name = name;
      ASSERT_TRUE(chain.add(std::move(*device), options));
    }
    wire.set_processor([this](ecat::Bytes frame) {
      clock.advance(20us);  // the frame's time on the wire
      if (!chain.process_frame(frame, clock.now())) wire.drop_next(1);
    });
  }

  ecat::ManualClock clock;
  ecat::slave::Chain chain{clock};
  ecat::transport::InMemoryTransport wire;
  ecat::master::Master master{wire, clock};
  std::vector<ecat::od::Identity> identities;
};

TEST_F(VirtualLine, BringsEveryDriveToOpAndNamesIt) {
  auto stations = line::start_line(master);
  ASSERT_TRUE(stations) << stations.error();
  ASSERT_EQ(stations->size(), files.size());
  for (std::size_t i = 0; i < files.size(); ++i) {
    EXPECT_EQ((*stations)[i].address, 0x1001 + i);  // MasterConfig::first_station_address onwards
    EXPECT_EQ((*stations)[i].vendor_id, identities[i].vendor_id) << files[i];
    EXPECT_EQ((*stations)[i].product_code, identities[i].product_code) << files[i];
    EXPECT_EQ(chain[i].status().state, ecat::esc::AlState::Op) << files[i];
  }
  // Every drive takes part in the cyclic frame: LRW counts 3 per slave.
  auto cycle = master.exchange_process_data();
  ASSERT_TRUE(cycle);
  EXPECT_EQ(cycle->wkc, 3 * files.size());
  EXPECT_TRUE(cycle->ok());
}

TEST_F(VirtualLine, ALineThatStopsAnsweringIsReported) {
  constexpr std::size_t kFramesAnswered = 40;
  // The line goes quiet after the scan's first frames: the routine must
  // report the step, not hang (the master's waits end on simulated time).
  wire.set_processor([this](ecat::Bytes frame) {
    if (wire.frames_sent() > kFramesAnswered) {
      clock.advance(1ms);  // a lost frame costs the master its receive timeout
      wire.drop_next(1);
      return;
    }
    clock.advance(20us);
    if (!chain.process_frame(frame, clock.now())) wire.drop_next(1);
  });
  auto stations = line::start_line(master);
  ASSERT_FALSE(stations);
  EXPECT_FALSE(stations.error().empty());
  EXPECT_NE(chain[0].status().state, ecat::esc::AlState::Op);
}

}  // namespace
