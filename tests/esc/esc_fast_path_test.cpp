// The fast paths of issue 8 (register bytes copied as a block, byte-aligned
// FMMUs routed straight to their SM, cached port/SM/FMMU/timer state) must
// behave exactly as the per-byte checked handlers. Every test runs the same
// accesses on a line with EscConfig::fast_paths and on one without, and
// compares the frames, the whole ESC memory, the event state and PDI reads.
#include <gtest/gtest.h>

#include <cstring>
#include <random>

#include "esc/register_map.hpp"
#include "esc_fixture.hpp"

namespace ecat::esc::test {
namespace {

constexpr std::size_t kSlaves = 2;
constexpr std::uint16_t kFirstStation = 0x1001;

EscConfig config(bool fast) {
  EscConfig c = make_config();
  c.fast_paths = fast;
  return c;
}

// Two lines of ESCs, one with the fast paths and one without.
struct Twin {
  Twin() : fast(kSlaves, config(true)), checked(kSlaves, config(false)) {}

  // Sends the frame built by `build` through both lines; the frames that
  // come back must be identical.
  template <typename Build>
  void frame(Build&& build) {
    TestFrame a;
    TestFrame b;
    build(a);
    build(b);
    const bool ra = a.send(fast.segment, now);
    const bool rb = b.send(checked.segment, now);
    ASSERT_EQ(ra, rb);
    ASSERT_EQ(a.frame().size(), b.frame().size());
    ASSERT_EQ(0, std::memcmp(a.frame().data(), b.frame().data(), a.frame().size())) << "frame differs";
  }

  void pdi_read(std::size_t slave, std::uint16_t address, std::size_t n) {
    Data a(n, 0xEE);
    Data b(n, 0xEE);
    fast[slave].read(address, a);
    checked[slave].read(address, b);
    ASSERT_EQ(a, b) << "PDI read at " << address;
  }
  void pdi_write(std::size_t slave, std::uint16_t address, const Data& d) {
    fast[slave].write(address, d);
    checked[slave].write(address, d);
  }
  void advance(Nanoseconds dt) {
    now += dt;
    fast.clock.set(now);
    checked.clock.set(now);
    ASSERT_EQ(fast.segment.poll(now), checked.segment.poll(now));
  }

  // Whole memory image, IRQ pin, attention flag, ports and timers of every ESC.
  void expect_same(const char* what) {
    for (std::size_t i = 0; i < kSlaves; ++i) {
      ASSERT_EQ(fast[i].memory_size(), checked[i].memory_size()) << what;
      ASSERT_EQ(0, std::memcmp(fast[i].memory(), checked[i].memory(), fast[i].memory_size()))
          << what << ": memory of slave " << i << " differs at "
          << first_difference(fast[i].memory(), checked[i].memory(), fast[i].memory_size());
      ASSERT_EQ(fast[i].irq(), checked[i].irq()) << what;
      ASSERT_EQ(fast[i].pdi_attention(), checked[i].pdi_attention()) << what;
      ASSERT_EQ(fast[i].next_timer(), checked[i].next_timer()) << what;
      for (unsigned p = 0; p < kMaxPorts; ++p) ASSERT_EQ(fast[i].port_open(p), checked[i].port_open(p)) << what;
    }
  }
  static std::size_t first_difference(const std::uint8_t* a, const std::uint8_t* b, std::size_t size) {
    std::size_t i = 0;
    while (i < size && a[i] == b[i]) ++i;
    return i;
  }

  Line fast;
  Line checked;
  Nanoseconds now{0};
};

// Every register byte, both sides, written and read one at a time on a
// single slave (auto-increment address, so a changed station address does
// not matter): the classification of esc/register_map.hpp against the
// per-byte handlers.
TEST(EscFastPath, EveryRegisterByteBehavesAsTheCheckedPath) {
  for (const std::uint8_t value : {std::uint8_t{0xFF}, std::uint8_t{0x5A}}) {
    Twin t;
    // Pending events, so the event and acknowledging registers have something to show.
    t.frame([](TestFrame& f) { f.add(Command::Apwr, ap(0, reg::kAlControl), Data{0x02}); });
    for (std::uint32_t a = 0; a < reg::kProcessRam; ++a) {
      if (a == reg::kEscResetEcat || a == reg::kEscResetPdi) continue;  // keep the ESC
      const auto addr = static_cast<std::uint16_t>(a);
      SCOPED_TRACE(testing::Message() << "register byte 0x" << std::hex << a);
      t.frame([&](TestFrame& f) {
        f.add(Command::Aprd, ap(0, addr), 1);
        f.add(Command::Apwr, ap(0, addr), Data{value});
        f.add(Command::Aprd, ap(0, addr), 1);
      });
      t.pdi_read(0, addr, 1);
      t.pdi_write(0, addr, Data{static_cast<std::uint8_t>(~value)});
      t.pdi_read(0, addr, 1);
      ASSERT_NO_FATAL_FAILURE(t.expect_same("register byte"));
    }
  }
}

// A register range mixing plain bytes with ones that have read effects and
// masks, read and written as one access.
TEST(EscFastPath, MixedRegisterRanges) {
  Twin t;
  t.frame([](TestFrame& f) { f.add(Command::Apwr, ap(0, reg::kAlControl), Data{0x04}); });
  for (std::uint16_t a = 0x0100; a < 0x0240; a = static_cast<std::uint16_t>(a + 3)) {
    t.frame([&](TestFrame& f) {
      f.add(Command::Aprd, ap(0, a), 24);
      f.add(Command::Brd, device_address(0, a), 24);
    });
    t.pdi_read(0, a, 24);
    ASSERT_NO_FATAL_FAILURE(t.expect_same("mixed range"));
  }
}

// The inline ECAT register read of the datagram engine (FPRD/APRD/FRMW/BRD):
// every length from 1 to 40 bytes (both sides of its 16-byte scan limit)
// starting on and around the bytes with read effects, with AL status and DL
// status changes pending so their acknowledges show; also reads that end in
// or start past the DC block and the last register bytes before the RAM.
TEST(EscFastPath, EcatRegisterReadsOfEveryLength) {
  Twin t;
  constexpr std::uint16_t kStarts[] = {0x0108, 0x0110, 0x0111, 0x012F, 0x0130, 0x0131, 0x0200,
                                       0x020F, 0x0210, 0x0211, 0x021F, 0x0220, 0x0440, 0x07F8,
                                       0x08F0, 0x08FF, 0x09FE, 0x0A00, 0x0FF0, 0x0FFF};
  constexpr std::uint16_t kMaxLength = 40;
  t.frame([](TestFrame& f) {
    for (std::uint16_t i = 0; i < kSlaves; ++i) {
      f.add(Command::Apwr, ap(i, reg::kConfiguredStationAddress), le16(static_cast<std::uint16_t>(kFirstStation + i)));
    }
  });
  std::uint8_t state = 0x01;
  for (const std::uint16_t start : kStarts) {
    for (std::uint16_t n = 1; n <= kMaxLength; ++n) {
      SCOPED_TRACE(testing::Message() << "read 0x" << std::hex << start << std::dec << " + " << n);
      // A PDI write of another AL status: ECAT event bit 3 pending again.
      state = static_cast<std::uint8_t>(state == 0x01 ? 0x02 : 0x01);
      t.pdi_write(0, reg::kAlStatus, Data{state});
      t.frame([&](TestFrame& f) {
        f.add(Command::Fprd, device_address(kFirstStation, start), n);
        f.add(Command::Frmw, device_address(kFirstStation + 1, start), n);
        f.add(Command::Brd, device_address(0, start), n);  // short ones through the inline read
        f.add(Command::Fprd, device_address(kFirstStation, reg::kEcatEventRequest), 2);
      });
      ASSERT_NO_FATAL_FAILURE(t.expect_same("ECAT register read"));
    }
  }
}

// Plain register bytes become protected when 0x0021 is set and writable
// again for the rest of a frame after 0x0020 (Section I §13).
TEST(EscFastPath, WriteProtectionInsideOneDatagram) {
  Twin t;
  t.frame([](TestFrame& f) {
    // One write: 0x0010..0x0033 sets the register protection midway.
    Data d(0x24, 0x00);
    d[reg::kRegisterWriteProtection - 0x10] = 0x01;
    f.add(Command::Apwr, ap(0, 0x0010), d);
    f.add(Command::Apwr, ap(0, reg::kWatchdogDivider), Data{0x12, 0x34});  // discarded
  });
  ASSERT_NO_FATAL_FAILURE(t.expect_same("protection set"));
  EXPECT_NE(t.fast[0].register_u16(reg::kWatchdogDivider), 0x3412);
  t.frame([](TestFrame& f) {
    f.add(Command::Apwr, ap(0, reg::kRegisterWriteEnable), Data{0x01});
    f.add(Command::Apwr, ap(0, reg::kWatchdogDivider), Data{0x12, 0x34});  // released for this frame
  });
  ASSERT_NO_FATAL_FAILURE(t.expect_same("protection released"));
  EXPECT_EQ(t.fast[0].register_u16(reg::kWatchdogDivider), 0x3412);
}

// The system time of every DC cycle (ARMW/FRMW of 0x0910, 8 or 4 bytes)
// has its own path with the fast paths (Esc::system_time_rmw): the reads
// of the addressed ESC, the time loops of the others (seen in the system
// time difference 0x092C and the times read back), WKC and ADP as the
// checked path's, with ESC write protection on and off and at lengths that
// take the general path.
TEST(EscFastPath, SystemTimeRmwBehavesAsTheCheckedPath) {
  Twin t;
  assign_stations(t.fast);
  assign_stations(t.checked);
  constexpr std::uint16_t kSystemTime = reg::kDcBase + 0x10;
  constexpr std::uint16_t kSystemTimeDifference = reg::kDcBase + 0x2C;
  for (int cycle = 0; cycle < 60; ++cycle) {
    SCOPED_TRACE(testing::Message() << "cycle " << cycle);
    ASSERT_NO_FATAL_FAILURE(t.advance(Nanoseconds{1'000'000 + 37 * cycle}));
    const bool wp = cycle % 20 >= 10;  // ESC write protection on slave 1 for 10 cycles of 20
    t.frame([&](TestFrame& f) {
      f.add(Command::Apwr, ap(1, reg::kEscWriteProtection), Data{static_cast<std::uint8_t>(wp ? 1 : 0)});
      f.add(Command::Armw, ap(0, kSystemTime), 8);
      f.add(Command::Frmw, fp(kFirstStation + 1, kSystemTime), 4);
      f.add(Command::Armw, ap(0, kSystemTime), static_cast<std::uint16_t>(cycle % 3 == 0 ? 2 : 6));
      for (std::uint16_t s = 0; s < kSlaves; ++s) {
        f.add(Command::Fprd, fp(static_cast<std::uint16_t>(kFirstStation + s), kSystemTimeDifference), 4);
        f.add(Command::Fprd, fp(static_cast<std::uint16_t>(kFirstStation + s), kSystemTime), 8);
      }
    });
    ASSERT_NO_FATAL_FAILURE(t.expect_same("system time"));
  }
}

// Random datagrams, SM/FMMU configurations (byte- and bit-granular,
// overlapping, partial), PDI accesses and time: the same results either way.
class EscFastPathRandom : public testing::TestWithParam<unsigned> {};

TEST_P(EscFastPathRandom, SameAsCheckedPath) {
  std::mt19937 rng(GetParam());
  auto pick = [&](std::uint32_t lo, std::uint32_t hi) {  // inclusive
    return static_cast<std::uint32_t>(std::uniform_int_distribution<std::uint32_t>(lo, hi)(rng));
  };
  auto bytes = [&](std::size_t n) {
    Data d(n);
    for (auto& b : d) b = static_cast<std::uint8_t>(pick(0, 255));
    return d;
  };
  // Addresses where things happen: registers with effects, SM/FMMU blocks, DC, RAM.
  auto address = [&]() -> std::uint16_t {
    static constexpr std::uint16_t kAreas[] = {0x0000, 0x0100, 0x0120, 0x0200, 0x0300, 0x0400,
                                               0x0600, 0x0800, 0x0900, 0x0F00, 0x0FF8, 0x1000};
    const std::uint16_t base = kAreas[pick(0, std::size(kAreas) - 1)];
    return static_cast<std::uint16_t>(base + pick(0, base >= 0x1000 ? 0x140 : 0x30));
  };
  Twin t;
  t.frame([](TestFrame& f) {
    for (std::uint16_t i = 0; i < kSlaves; ++i) {
      f.add(Command::Apwr, ap(i, reg::kConfiguredStationAddress), le16(static_cast<std::uint16_t>(kFirstStation + i)));
    }
  });
  struct Dg {
    Command cmd;
    std::uint32_t address;
    Data data;
  };
  std::vector<Dg> dgs;
  // Drawn once, sent through both lines.
  auto send = [&] {
    t.frame([&](TestFrame& f) {
      for (const Dg& d : dgs) f.add(d.cmd, d.address, d.data);
    });
    dgs.clear();
  };
  constexpr int kOps = 1500;
  for (int op = 0; op < kOps; ++op) {
    SCOPED_TRACE(testing::Message() << "seed " << GetParam() << " op " << op);
    const auto station = static_cast<std::uint16_t>(kFirstStation + pick(0, kSlaves - 1));
    switch (pick(0, 9)) {
      case 0: {  // an SM
        const unsigned n = pick(0, 3);
        static constexpr std::uint8_t kControls[] = {0x26, 0x22, 0x64, 0x20, 0x00, 0x04};
        Data d = le16(static_cast<std::uint16_t>(0x1000 + pick(0, 0x100)));
        for (auto b : le16(static_cast<std::uint16_t>(pick(0, 48)))) d.push_back(b);
        d.push_back(kControls[pick(0, std::size(kControls) - 1)]);
        d.push_back(0);
        d.push_back(static_cast<std::uint8_t>(pick(0, 3) != 0));
        d.push_back(0);
        dgs.push_back({Command::Fpwr, fp(station, reg::sync_manager(n)), d});
        send();
        break;
      }
      case 1: {  // an FMMU, mostly byte-aligned
        const unsigned n = pick(0, 2);
        const bool aligned = pick(0, 3) != 0;
        Data d = le32(pick(0, 0x80));
        for (auto b : le16(static_cast<std::uint16_t>(pick(1, 48)))) d.push_back(b);
        d.push_back(static_cast<std::uint8_t>(aligned ? 0 : pick(0, 7)));
        d.push_back(static_cast<std::uint8_t>(aligned ? 7 : pick(0, 7)));
        for (auto b : le16(static_cast<std::uint16_t>(0x1000 + pick(0, 0x100)))) d.push_back(b);
        d.push_back(static_cast<std::uint8_t>(aligned ? 0 : pick(0, 7)));
        d.push_back(static_cast<std::uint8_t>(pick(1, 3)));
        d.push_back(static_cast<std::uint8_t>(pick(0, 4) != 0));
        d.resize(reg::kFmmuStride, 0);
        dgs.push_back({Command::Fpwr, fp(station, reg::fmmu(n)), d});
        send();
        break;
      }
      case 2:
      case 3:
      case 4: {  // logical datagrams
        static constexpr Command kLogical[] = {Command::Lrd, Command::Lwr, Command::Lrw};
        for (std::uint32_t k = pick(1, 3); k > 0; --k) {
          const Command cmd = kLogical[pick(0, 2)];
          const std::uint32_t logical = pick(0, 0x90);
          dgs.push_back({cmd, logical, bytes(pick(1, 80))});
        }
        send();
        break;
      }
      case 5:
      case 6: {  // device-addressed datagrams of every kind
        for (std::uint32_t k = pick(1, 3); k > 0; --k) {
          const auto cmd = static_cast<Command>(pick(1, kLastCommand));
          if (addressing(cmd) == Addressing::Logical) continue;
          const std::uint16_t adp = pick(0, 1) ? station : auto_increment_adp(static_cast<std::uint16_t>(pick(0, 1)));
          const std::uint16_t ado = address();
          if (ado == reg::kEscResetEcat) continue;
          dgs.push_back({cmd, device_address(adp, ado), bytes(pick(1, 24))});
        }
        dgs.push_back({Command::Brd, device_address(0, reg::kAlStatus), Data(2, 0)});
        send();
        break;
      }
      case 7: {  // the application
        const auto slave = pick(0, kSlaves - 1);
        const std::uint16_t a = address();
        t.pdi_read(slave, a, pick(1, 24));
        break;
      }
      case 8: {
        const std::uint16_t a = address();
        if (a == reg::kEscResetPdi) break;
        const auto slave = pick(0, kSlaves - 1);
        t.pdi_write(slave, a, bytes(pick(1, 8)));
        break;
      }
      default:
        t.advance(Nanoseconds{pick(0, 300'000)});
        break;
    }
    ASSERT_NO_FATAL_FAILURE(t.expect_same("random op"));
  }
}

INSTANTIATE_TEST_SUITE_P(Seeds, EscFastPathRandom, testing::Range(1u, 13u));

// FMMUs that map whole 3-buffer SMs take them in one step (the LRW of a
// cyclic exchange): the same as the per-byte path while the SMs are
// reconfigured between frames from the ECAT side (control, length,
// activation) and the PDI side (0x0807 deactivation), with PDI buffer
// accesses, partial datagrams and the process-data watchdog running.
TEST(EscFastPath, WholeBufferSmRoutesFollowReconfiguration) {
  Twin t;
  constexpr std::uint16_t kOut = 0x1100;  // SM2: ECAT writes
  constexpr std::uint16_t kIn = 0x1180;   // SM3: ECAT reads
  constexpr std::uint16_t kLen = 8;
  auto sm = [](std::uint16_t start, std::uint16_t len, std::uint8_t control, std::uint8_t activate) {
    Data d = le16(start);
    for (auto b : le16(len)) d.push_back(b);
    d.push_back(control);
    d.push_back(0);
    d.push_back(activate);
    d.push_back(0);
    return d;
  };
  auto fmmu = [](std::uint32_t logical, std::uint16_t len, std::uint16_t physical, std::uint8_t type) {
    Data d = le32(logical);
    for (auto b : le16(len)) d.push_back(b);
    d.push_back(0);
    d.push_back(7);
    for (auto b : le16(physical)) d.push_back(b);
    d.push_back(0);
    d.push_back(type);
    d.push_back(1);
    d.resize(reg::kFmmuStride, 0);
    return d;
  };
  t.frame([&](TestFrame& f) {
    for (std::uint16_t i = 0; i < kSlaves; ++i) {
      const auto station = static_cast<std::uint16_t>(kFirstStation + i);
      f.add(Command::Apwr, ap(i, reg::kConfiguredStationAddress), le16(station));
      f.add(Command::Apwr, ap(i, reg::kWatchdogTimeProcessData), le16(100));
      f.add(Command::Apwr, ap(i, reg::sync_manager(2)), sm(kOut, kLen, 0x64, 1));
      f.add(Command::Apwr, ap(i, reg::sync_manager(3)), sm(kIn, kLen, 0x20, 1));
      f.add(Command::Apwr, ap(i, reg::fmmu(0)), fmmu(0x40u * i, kLen, kOut, 2));
      f.add(Command::Apwr, ap(i, reg::fmmu(1)), fmmu(0x40u * i + 0x20, kLen, kIn, 1));
    }
  });
  ASSERT_NO_FATAL_FAILURE(t.expect_same("setup"));
  std::mt19937 rng(7);
  auto pick = [&](std::uint32_t lo, std::uint32_t hi) {
    return static_cast<std::uint32_t>(std::uniform_int_distribution<std::uint32_t>(lo, hi)(rng));
  };
  auto bytes = [&](std::size_t n) {
    Data d(n);
    for (auto& b : d) b = static_cast<std::uint8_t>(pick(0, 255));
    return d;
  };
  static constexpr std::uint8_t kOutControls[] = {0x64, 0x24, 0x44, 0x04, 0x66, 0x20};
  static constexpr std::uint8_t kInControls[] = {0x20, 0x00, 0x60, 0x22, 0x24};
  for (int op = 0; op < 3000; ++op) {
    SCOPED_TRACE(testing::Message() << "op " << op);
    const std::size_t slave = pick(0, kSlaves - 1);
    const auto station = static_cast<std::uint16_t>(kFirstStation + slave);
    // Drawn once, sent through both lines.
    Command cmd = Command::Fpwr;
    std::uint32_t address = 0;
    Data data;
    switch (pick(0, 11)) {
      case 0:  // ECAT: control byte of either SM
        if (pick(0, 1)) {
          address = fp(station, reg::sync_manager(2) + reg::sm::kControl);
          data = Data{kOutControls[pick(0, std::size(kOutControls) - 1)]};
        } else {
          address = fp(station, reg::sync_manager(3) + reg::sm::kControl);
          data = Data{kInControls[pick(0, std::size(kInControls) - 1)]};
        }
        break;
      case 1: {  // ECAT: activation or length
        const unsigned n = pick(2, 3);
        if (pick(0, 1)) {
          address = fp(station, reg::sync_manager(n) + reg::sm::kActivate);
          data = Data{static_cast<std::uint8_t>(pick(0, 3) != 0)};
        } else {
          address = fp(station, reg::sync_manager(n) + reg::sm::kLength);
          data = le16(static_cast<std::uint16_t>(pick(0, 3) != 0 ? kLen : pick(1, kLen + 2)));
        }
        break;
      }
      case 2:  // PDI: deactivate / reactivate an SM
        t.pdi_write(slave, static_cast<std::uint16_t>(reg::sync_manager(pick(2, 3)) + reg::sm::kPdiControl),
                    Data{static_cast<std::uint8_t>(pick(0, 2) == 0)});
        break;
      case 3:  // PDI: the buffers, whole or in part
        if (pick(0, 1)) {
          t.pdi_write(slave, kIn, bytes(pick(0, 2) != 0 ? kLen : pick(1, kLen)));
        } else {
          ASSERT_NO_FATAL_FAILURE(t.pdi_read(slave, kOut, pick(0, 2) != 0 ? kLen : pick(1, kLen)));
        }
        break;
      case 4:  // a partial LRW: starts or ends inside a mapping
        cmd = Command::Lrw;
        address = pick(0, 0x30);
        data = bytes(pick(1, 0x50));
        break;
      case 5:
        ASSERT_NO_FATAL_FAILURE(t.advance(Nanoseconds{pick(0, 300'000)}));
        break;
      default: {  // the cyclic LRW over every slave, or LRD/LWR alone
        static constexpr Command kCmds[] = {Command::Lrw, Command::Lrw, Command::Lrd, Command::Lwr};
        cmd = kCmds[pick(0, 3)];
        data = bytes(0x40 * kSlaves);
        break;
      }
    }
    if (!data.empty()) {
      ASSERT_NO_FATAL_FAILURE(t.frame([&](TestFrame& f) {
        f.add(cmd, address, data);
        f.add(Command::Brd, device_address(0, reg::kAlStatus), Data(2, 0));
      }));
    }
    ASSERT_NO_FATAL_FAILURE(t.expect_same("whole-buffer op"));
  }
}

// The classification itself: plain bytes are fully writable by their side,
// and the blocks with their own handlers are never plain.
TEST(RegisterMap, PlainBytesAreFullyWritableAndBlocksAreSpecial) {
  using namespace register_map;
  for (std::uint32_t a = 0; a < reg::kProcessRam; ++a) {
    const auto addr = static_cast<std::uint16_t>(a);
    const RegisterWriteMask m = fixed_register_write_mask(addr);
    if (has(addr, kWritePlainEcat)) {
      EXPECT_EQ(m.ecat, 0xFF) << a;
    }
    if (has(addr, kWritePlainPdi)) {
      EXPECT_EQ(m.pdi, 0xFF) << a;
    }
  }
  for (const std::uint16_t a : {reg::kDcBase, reg::kEepromControlStatus, reg::kFmmuBase, reg::kSyncManagerBase,
                                reg::kAlControl, reg::kDlControl, reg::kEscResetEcat}) {
    EXPECT_FALSE(has(a, kWritePlainEcat)) << a;
  }
  EXPECT_TRUE(has(reg::kAlStatus, kReadEffectEcat));
  EXPECT_TRUE(has(reg::kAlControl, kReadEffectPdi));
  EXPECT_FALSE(has(reg::kAlControl, kReadEffectEcat));
  EXPECT_TRUE(has(bits::kUserRam, kWritePlainEcat));
  // Writable, but Watchdogs keeps the timeouts of the divider and times.
  EXPECT_FALSE(has(reg::kWatchdogDivider, kWritePlainEcat));
  EXPECT_FALSE(has(reg::kWatchdogTimePdi + 1, kWritePlainEcat));
  EXPECT_FALSE(has(reg::kWatchdogTimeProcessData, kWritePlainEcat));
  // Writable, but each write advances the ESC's address epoch (Esc::address_epoch_).
  EXPECT_FALSE(has(reg::kConfiguredStationAddress, kWritePlainEcat));
  EXPECT_FALSE(has(reg::kConfiguredStationAlias, kWritePlainPdi));
  EXPECT_FALSE(has(reg::kEcatEventMask, kWritePlainEcat));
  EXPECT_TRUE(has(bits::kUserRam, kWritePlainPdi));
}

}  // namespace
}  // namespace ecat::esc::test
