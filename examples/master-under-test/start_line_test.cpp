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

TEST_F(VirtualLine, ALineThatGoesQuietMidStartUpIsReportedNotHungOn) {
  // The cable is pulled once the first drive reached PreOp: the routine must
  // name the slave and the step, and return (the master's waits end on
  // simulated time).
  wire.set_processor([this](ecat::Bytes frame) {
    if (chain[0].status().state != ecat::esc::AlState::Init) {
      clock.advance(1ms);  // a lost frame costs the master its receive timeout
      wire.drop_next(1);
      return;
    }
    clock.advance(20us);
    if (!chain.process_frame(frame, clock.now())) wire.drop_next(1);
  });
  auto stations = line::start_line(master);
  ASSERT_FALSE(stations);
  EXPECT_EQ(stations.error(), "slave 1: PreOp: no reply (timeout)");
  EXPECT_EQ(chain[0].status().state, ecat::esc::AlState::PreOp);
  EXPECT_EQ(chain[1].status().state, ecat::esc::AlState::Init);
}

}  // namespace
