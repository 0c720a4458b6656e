// The PDI fast paths of issue 8 (Esc::read/Esc::write): a whole or partial
// SM buffer access goes straight to its SyncManager, the AL event request
// 0x0220 is read in one step, and no PDI access recomputes the DL status
// 0x0110 (every input of it updates it where it changes). Each test runs the
// same accesses on an ESC with EscConfig::fast_paths and on one without
// (every PDI access through the general memory walk, 0x0110 recomputed
// after each) and compares the data read, the whole ESC memory, the IRQ and
// the timers; the process-data cycle also checks the exact register values.
#include <gtest/gtest.h>

#include <cstring>
#include <random>

#include "esc/dc/dc_registers.hpp"
#include "esc/register_bits.hpp"
#include "esc/sii_interface.hpp"
#include "esc_fixture.hpp"

namespace ecat::esc::test {
namespace {

constexpr std::uint16_t kStation = 0x1001;
constexpr std::uint16_t kOutputs = 0x1100;  // SM2, ECAT writes, PDI reads
constexpr std::uint16_t kInputs = 0x1200;   // SM3, PDI writes, ECAT reads
constexpr std::uint16_t kMbxOut = 0x1000;   // SM0 mailbox, ECAT writes
constexpr std::uint16_t kMbxIn = 0x1080;    // SM1 mailbox, PDI writes
constexpr std::uint16_t kPdBytes = 4;
constexpr std::uint16_t kMbxBytes = 16;
constexpr std::uint8_t kCtlOutputs = 0x64;  // buffered, ECAT writes, AL event, watchdog trigger
constexpr std::uint8_t kCtlInputs = 0x20;   // buffered, ECAT reads, AL event
constexpr std::uint8_t kCtlMbxOut = 0x26;   // mailbox, ECAT writes, AL event
constexpr std::uint8_t kCtlMbxIn = 0x22;    // mailbox, ECAT reads, AL event
constexpr std::uint32_t kAlEventSm2 = 1u << (bits::kAlEventSmShift + 2);  // 0x0220 bit 8+n
constexpr std::uint32_t kAlEventSm3 = 1u << (bits::kAlEventSmShift + 3);

EscConfig config(bool fast) {
  EscConfig c = make_config();
  c.fast_paths = fast;
  return c;
}

struct Twin {
  Twin() : fast(1, config(true)), checked(1, config(false)) {
    ecat(Command::Apwr, ap(0, reg::kConfiguredStationAddress), le16(kStation));
  }

  // An ECAT datagram through both ESCs; the replies must be identical.
  Reply ecat(Command c, std::uint32_t address, const Data& d) {
    const Reply a = transact(fast.segment, c, address, d, now);
    const Reply b = transact(checked.segment, c, address, d, now);
    EXPECT_EQ(a.wkc, b.wkc);
    EXPECT_EQ(a.data, b.data);
    return a;
  }
  void sm(unsigned n, std::uint16_t start, std::uint16_t length, std::uint8_t control, std::uint8_t activate = 1) {
    ecat(Command::Fpwr, fp(kStation, reg::sync_manager(n)),
         Data{static_cast<std::uint8_t>(start), static_cast<std::uint8_t>(start >> 8),
              static_cast<std::uint8_t>(length), static_cast<std::uint8_t>(length >> 8), control, 0, activate, 0});
  }
  Data pdi_read(std::uint16_t address, std::size_t n) {
    Data a(n, 0xEE);
    Data b(n, 0xEE);
    fast[0].read(address, a);
    checked[0].read(address, b);
    EXPECT_EQ(a, b) << "PDI read at 0x" << std::hex << address;
    return a;
  }
  void pdi_write(std::uint16_t address, const Data& d) {
    fast[0].write(address, d);
    checked[0].write(address, d);
  }
  // The whole-buffer calls (Pdi::read_buffer, write_buffer_begin/commit):
  // in place on the fast ESC where it can, through Esc::read/write on the
  // checked one (without fast_paths every access takes the general path).
  Data pdi_read_buffer(std::uint16_t address, std::size_t n) {
    Data sa(n, 0xEE);
    Data sb(n, 0xEE);
    const std::span<const std::uint8_t> a = fast[0].read_buffer(address, sa);
    const std::span<const std::uint8_t> b = checked[0].read_buffer(address, sb);
    EXPECT_EQ(b.data(), sb.data());  // the checked ESC never hands out a view
    EXPECT_EQ(a.size(), n);
    Data got(a.begin(), a.end());
    EXPECT_EQ(got, Data(b.begin(), b.end())) << "PDI read_buffer at 0x" << std::hex << address;
    last_in_place = a.data() != sa.data();
    return got;
  }
  void pdi_write_buffer(std::uint16_t address, const Data& d) {
    Data sa(d.size(), 0xEE);
    Data sb(d.size(), 0xEE);
    const std::span<std::uint8_t> a = fast[0].write_buffer_begin(address, sa);
    const std::span<std::uint8_t> b = checked[0].write_buffer_begin(address, sb);
    EXPECT_EQ(b.data(), sb.data());
    ASSERT_EQ(a.size(), d.size());
    std::copy(d.begin(), d.end(), a.begin());
    std::copy(d.begin(), d.end(), b.begin());
    last_in_place = a.data() != sa.data();
    fast[0].write_buffer_commit(address, a);
    checked[0].write_buffer_commit(address, b);
  }
  void advance(Nanoseconds dt) {
    now += dt;
    fast.clock.set(now);
    checked.clock.set(now);
    EXPECT_EQ(fast.segment.poll(now), checked.segment.poll(now));
  }
  void set_link(unsigned port, bool up) {
    fast[0].set_link(port, up);
    checked[0].set_link(port, up);
  }
  void expect_same(const char* what) {
    ASSERT_EQ(fast[0].memory_size(), checked[0].memory_size()) << what;
    ASSERT_EQ(0, std::memcmp(fast[0].memory(), checked[0].memory(), fast[0].memory_size()))
        << what << ": memory differs at 0x" << std::hex << first_difference();
    ASSERT_EQ(fast[0].irq(), checked[0].irq()) << what;
    ASSERT_EQ(fast[0].pdi_attention(), checked[0].pdi_attention()) << what;
    ASSERT_EQ(fast[0].next_timer(), checked[0].next_timer()) << what;
  }
  std::size_t first_difference() {
    std::size_t i = 0;
    while (i < fast[0].memory_size() && fast[0].memory()[i] == checked[0].memory()[i]) ++i;
    return i;
  }
  std::uint8_t byte(std::uint16_t a) { return fast[0].memory()[a]; }
  std::uint16_t u16(std::uint16_t a) { return fast[0].register_u16(a); }
  std::uint32_t u32(std::uint16_t a) { return load_le<std::uint32_t>(fast[0].memory() + a); }

  Line fast;
  Line checked;
  Nanoseconds now{0};
  bool last_in_place = false;  // the last whole-buffer call on the fast ESC went in place
};

// A process-data cycle as the firmware runs it (LRW by the master, then the
// PDI reads 0x0220, the whole SM2 buffer, writes the whole SM3 buffer), with
// the exact register values on the way.
// Run with Esc::read/write (false) and with the whole-buffer calls in place
// (true, coe::ProcessData's way): the same values.
class EscPdiProcessDataCycle : public testing::TestWithParam<bool> {};

TEST_P(EscPdiProcessDataCycle, RegisterValues) {
  const bool in_place = GetParam();
  Twin t;
  t.sm(2, kOutputs, kPdBytes, kCtlOutputs);
  t.sm(3, kInputs, kPdBytes, kCtlInputs);
  config_fmmu(t.fast.segment, kStation, 0, 0, kPdBytes, 0, 7, kOutputs, 0, 2);
  config_fmmu(t.checked.segment, kStation, 0, 0, kPdBytes, 0, 7, kOutputs, 0, 2);
  config_fmmu(t.fast.segment, kStation, 1, kPdBytes, kPdBytes, 0, 7, kInputs, 0, 1);
  config_fmmu(t.checked.segment, kStation, 1, kPdBytes, kPdBytes, 0, 7, kInputs, 0, 1);
  t.ecat(Command::Fpwr, fp(kStation, reg::kWatchdogTimePdi), le16(10));            // 1 ms
  t.ecat(Command::Fpwr, fp(kStation, reg::kWatchdogTimeProcessData), le16(20));    // 2 ms
  // The ECAT SM writes raised SM activation (0x0220 bit 4); the PDI reading
  // 0x0806 + 8n acknowledges it.
  EXPECT_EQ(t.pdi_read(reg::kAlEventRequest, 4), le32(bits::kAlEventSmActivation));
  t.pdi_read(reg::sync_manager(2) + reg::sm::kActivate, 1);
  EXPECT_EQ(t.pdi_read(reg::kAlEventRequest, 4), le32(0));
  ASSERT_NO_FATAL_FAILURE(t.expect_same("set-up"));
  // DL status: PDI operational (EEPROM loaded), PDI watchdog reloaded, the
  // closed ports' loop bits; no link in a one-ESC test line.
  const std::uint16_t dl = t.u16(reg::kDlStatus);
  EXPECT_EQ(dl & (bits::kDlPdiOperational | bits::kDlPdiWatchdogOk),
            bits::kDlPdiOperational | bits::kDlPdiWatchdogOk);

  for (std::uint8_t i = 1; i <= 5; ++i) {
    SCOPED_TRACE(testing::Message() << "cycle " << int{i});
    t.advance(Nanoseconds{500'000});
    const Data out{i, static_cast<std::uint8_t>(i + 1), static_cast<std::uint8_t>(i + 2), static_cast<std::uint8_t>(i + 3)};
    Data lrw = out;
    lrw.resize(2 * kPdBytes, 0);
    const Reply r = t.ecat(Command::Lrw, 0, lrw);
    EXPECT_EQ(r.wkc, 3);
    if (i > 1) {
      EXPECT_EQ(Data(r.data.begin() + kPdBytes, r.data.end()), Data(kPdBytes, static_cast<std::uint8_t>(i - 1)));
    }
    // SM2 written (status: write event, buffer = latest); SM3 read by ECAT:
    // AL event bits 10 and 11 pending, process-data watchdog restarted.
    EXPECT_EQ(t.byte(reg::sync_manager(2) + reg::sm::kStatus) & 0x01, 0x01);
    EXPECT_EQ(t.pdi_read(reg::kAlEventRequest, 4), le32(kAlEventSm2 | kAlEventSm3));
    EXPECT_EQ(t.byte(reg::kWatchdogStatusProcessData), 1);
    EXPECT_EQ(t.byte(reg::kWatchdogCounterProcessData), 0);
    EXPECT_EQ(t.fast[0].next_timer(), t.now + Nanoseconds{1'000'000});  // the PDI watchdog, 1 ms on
    // The firmware takes SM2: data, read event, AL bit 10 acknowledged.
    EXPECT_EQ(in_place ? t.pdi_read_buffer(kOutputs, kPdBytes) : t.pdi_read(kOutputs, kPdBytes), out);
    EXPECT_EQ(t.last_in_place, in_place);
    const std::uint8_t st2 = t.byte(reg::sync_manager(2) + reg::sm::kStatus);
    EXPECT_EQ(st2 & 0x0B, 0x02);  // read event, no write event, not open
    EXPECT_EQ(t.pdi_read(reg::kAlEventRequest, 4), le32(kAlEventSm3));
    // ... and writes SM3: AL bit 11 acknowledged by the access, write event,
    // buffer exchanged (status bits 5:4 = the latest buffer).
    t.last_in_place = false;
    if (in_place) {
      t.pdi_write_buffer(kInputs, Data(kPdBytes, i));
    } else {
      t.pdi_write(kInputs, Data(kPdBytes, i));
    }
    EXPECT_EQ(t.last_in_place, in_place);
    const std::uint8_t st3 = t.byte(reg::sync_manager(3) + reg::sm::kStatus);
    EXPECT_EQ(st3 & 0x0B, 0x01);
    EXPECT_NE(st3 & 0x30, 0x30);
    EXPECT_EQ(t.pdi_read(reg::kAlEventRequest, 4), le32(0));
    EXPECT_EQ(t.u16(reg::kDlStatus), dl);
    ASSERT_NO_FATAL_FAILURE(t.expect_same("cycle"));
  }
}

INSTANTIATE_TEST_SUITE_P(Paths, EscPdiProcessDataCycle, testing::Bool());

// The whole-buffer calls in place follow every SM change (the ESC keeps the
// SM it found per direction until an SM register changes): a moved area, a
// mailbox at the same place, a direction change, PDI deactivation, an ESC
// reset; the checked ESC (through read/write) gives the same bytes and
// memory after each step, and the exact values where they matter.
TEST(EscPdiFastPath, BufferCallsFollowSmChanges) {
  Twin t;
  t.sm(2, kOutputs, kPdBytes, kCtlOutputs);
  t.sm(3, kInputs, kPdBytes, kCtlInputs);
  t.ecat(Command::Fpwr, fp(kStation, kOutputs), Data{1, 2, 3, 4});
  EXPECT_EQ(t.pdi_read_buffer(kOutputs, kPdBytes), (Data{1, 2, 3, 4}));
  EXPECT_TRUE(t.last_in_place);
  EXPECT_EQ(t.byte(reg::sync_manager(2) + reg::sm::kStatus), 0x12);  // read event; latest buffer 1 (bits 5:4)
  t.pdi_write_buffer(kInputs, Data{5, 6, 7, 8});
  EXPECT_TRUE(t.last_in_place);
  EXPECT_EQ(t.byte(reg::sync_manager(3) + reg::sm::kStatus), 0x11);  // write event; latest buffer 1
  EXPECT_EQ(t.ecat(Command::Fprd, fp(kStation, kInputs), Data(kPdBytes, 0)).data, (Data{5, 6, 7, 8}));
  ASSERT_NO_FATAL_FAILURE(t.expect_same("first cycle"));
  // Part of a buffer goes in place too (the buffer opens on any first
  // access, closes on the last byte); an access crossing the area's end not.
  EXPECT_EQ(t.pdi_read_buffer(kOutputs + 1, 2), (Data{2, 3}));
  EXPECT_TRUE(t.last_in_place);
  EXPECT_EQ(t.byte(reg::sync_manager(2) + reg::sm::kStatus), 0x52);  // read buffer open
  t.pdi_read_buffer(kOutputs + 2, kPdBytes);
  EXPECT_FALSE(t.last_in_place);
  t.pdi_write_buffer(kInputs, Data{9, 9});
  EXPECT_TRUE(t.last_in_place);
  EXPECT_EQ(t.byte(reg::sync_manager(3) + reg::sm::kStatus), 0x90);  // write buffer open, the ECAT read event cleared
  t.pdi_write_buffer(kInputs + 2, Data{8, 8});
  EXPECT_EQ(t.ecat(Command::Fprd, fp(kStation, kInputs), Data(kPdBytes, 0)).data, (Data{9, 9, 8, 8}));
  ASSERT_NO_FATAL_FAILURE(t.expect_same("partial"));
  // SM2 moved: the old address is plain RAM now, the new one the buffer.
  t.sm(2, 0, 0, 0, 0);
  t.sm(2, kOutputs + 0x40, kPdBytes, kCtlOutputs);
  t.pdi_read_buffer(kOutputs, kPdBytes);
  EXPECT_FALSE(t.last_in_place);
  t.ecat(Command::Fpwr, fp(kStation, kOutputs + 0x40), Data{4, 3, 2, 1});
  EXPECT_EQ(t.pdi_read_buffer(kOutputs + 0x40, kPdBytes), (Data{4, 3, 2, 1}));
  EXPECT_TRUE(t.last_in_place);
  ASSERT_NO_FATAL_FAILURE(t.expect_same("moved"));
  // SM2 a mailbox at the same place: empty, so the read gets nothing (0s), then full.
  t.sm(2, 0, 0, 0, 0);
  t.sm(2, kOutputs + 0x40, kPdBytes, kCtlMbxOut);
  EXPECT_EQ(t.pdi_read_buffer(kOutputs + 0x40, kPdBytes), Data(kPdBytes, 0));
  EXPECT_FALSE(t.last_in_place);
  t.ecat(Command::Fpwr, fp(kStation, kOutputs + 0x40), Data{7, 7, 7, 7});
  EXPECT_EQ(t.pdi_read_buffer(kOutputs + 0x40, kPdBytes), (Data{7, 7, 7, 7}));
  ASSERT_NO_FATAL_FAILURE(t.expect_same("mailbox"));
  // SM3 turned round (ECAT writes): the PDI's write is refused, its read works.
  t.sm(3, 0, 0, 0, 0);
  t.sm(3, kInputs, kPdBytes, kCtlOutputs);
  t.pdi_write_buffer(kInputs, Data{1, 1, 1, 1});
  EXPECT_FALSE(t.last_in_place);
  t.pdi_read_buffer(kInputs, kPdBytes);
  EXPECT_TRUE(t.last_in_place);
  ASSERT_NO_FATAL_FAILURE(t.expect_same("turned"));
  t.sm(3, 0, 0, 0, 0);
  t.sm(3, kInputs, kPdBytes, kCtlInputs);
  t.pdi_write_buffer(kInputs, Data{2, 2, 2, 2});
  EXPECT_TRUE(t.last_in_place);
  // PDI deactivation (0x0807 bit 0) refuses both sides' accesses.
  t.pdi_write(reg::sync_manager(3) + reg::sm::kPdiControl, Data{1});
  t.pdi_write_buffer(kInputs, Data{3, 3, 3, 3});
  EXPECT_FALSE(t.last_in_place);
  EXPECT_EQ(t.ecat(Command::Fprd, fp(kStation, kInputs), Data(kPdBytes, 0)).wkc, 0);
  t.pdi_write(reg::sync_manager(3) + reg::sm::kPdiControl, Data{0});
  t.pdi_write_buffer(kInputs, Data{4, 4, 4, 4});
  EXPECT_TRUE(t.last_in_place);
  EXPECT_EQ(t.ecat(Command::Fprd, fp(kStation, kInputs), Data(kPdBytes, 0)).data, (Data{4, 4, 4, 4}));
  ASSERT_NO_FATAL_FAILURE(t.expect_same("deactivated"));
  // An ESC reset from the PDI: every SM off, nothing in place any more.
  for (std::uint8_t c : {std::uint8_t{'R'}, std::uint8_t{'E'}, std::uint8_t{'S'}}) t.pdi_write(reg::kEscResetPdi, Data{c});
  t.pdi_write_buffer(kInputs, Data{5, 5, 5, 5});
  EXPECT_FALSE(t.last_in_place);
  t.pdi_read_buffer(kOutputs + 0x40, kPdBytes);
  EXPECT_FALSE(t.last_in_place);
  ASSERT_NO_FATAL_FAILURE(t.expect_same("reset"));
}

// The PDI watchdog: a PDI access restarts it (deadline = access + time x
// unit); expiry clears 0x0110 bit 1, counts 0x0443 and raises ECAT event
// bit 2; the next PDI access sets bit 1 again - the same on both paths.
TEST(EscPdiFastPath, PdiWatchdogAndDlStatus) {
  Twin t;
  t.sm(2, kOutputs, kPdBytes, kCtlOutputs);
  t.ecat(Command::Fpwr, fp(kStation, reg::kWatchdogTimePdi), le16(10));  // 1 ms
  t.ecat(Command::Fprd, fp(kStation, reg::kDlStatus), Data(2, 0));       // acknowledge ECAT event bit 2
  t.advance(Nanoseconds{100'000});
  t.pdi_read(reg::kAlEventRequest, 4);
  EXPECT_EQ(t.fast[0].next_timer(), t.now + Nanoseconds{1'000'000});
  EXPECT_EQ(t.u16(reg::kDlStatus) & bits::kDlPdiWatchdogOk, bits::kDlPdiWatchdogOk);
  t.advance(Nanoseconds{999'999});
  EXPECT_EQ(t.byte(reg::kWatchdogCounterPdi), 0);
  t.advance(Nanoseconds{1});
  ASSERT_NO_FATAL_FAILURE(t.expect_same("expired"));
  EXPECT_EQ(t.u16(reg::kDlStatus) & bits::kDlPdiWatchdogOk, 0);
  EXPECT_EQ(t.byte(reg::kWatchdogCounterPdi), 1);
  EXPECT_EQ(t.u16(reg::kEcatEventRequest) & bits::kEcatEventDlStatus, bits::kEcatEventDlStatus);
  EXPECT_EQ(t.fast[0].next_timer(), Nanoseconds::max());
  // A whole-buffer read (fast path) restarts it with the divider and time of now.
  t.ecat(Command::Fpwr, fp(kStation, reg::kWatchdogDivider), le16(98));  // 4 µs unit
  t.advance(Nanoseconds{10});
  t.pdi_read(kOutputs, kPdBytes);
  EXPECT_EQ(t.u16(reg::kDlStatus) & bits::kDlPdiWatchdogOk, bits::kDlPdiWatchdogOk);
  EXPECT_EQ(t.fast[0].next_timer(), t.now + Nanoseconds{40'000});
  ASSERT_NO_FATAL_FAILURE(t.expect_same("restarted"));
  // Time 0 disables it.
  t.ecat(Command::Fpwr, fp(kStation, reg::kWatchdogTimePdi), le16(0));
  t.pdi_write(kInputs, Data{1});
  EXPECT_EQ(t.fast[0].next_timer(), Nanoseconds::max());
  ASSERT_NO_FATAL_FAILURE(t.expect_same("disabled"));
}

// 0x0220 read at every start and length around it (the fast path takes the
// accesses inside 0x0220-0x0223), with SM, AL control and watchdog events
// pending; and a PDI reset through 0x0041 (the write path resets last).
TEST(EscPdiFastPath, AlEventRequestEveryStartAndLength) {
  Twin t;
  t.sm(2, kOutputs, kPdBytes, kCtlOutputs);
  t.ecat(Command::Fpwr, fp(kStation, reg::kAlControl), le16(2));
  t.ecat(Command::Fpwr, fp(kStation, kOutputs), Data(kPdBytes, 7));
  for (std::uint16_t start = 0x021C; start <= 0x0224; ++start) {
    for (std::size_t n = 1; n <= 8; ++n) {
      SCOPED_TRACE(testing::Message() << "0x" << std::hex << start << " + " << n);
      t.pdi_read(start, n);
      ASSERT_NO_FATAL_FAILURE(t.expect_same("0x0220"));
    }
  }
  EXPECT_EQ(t.pdi_read(reg::kAlEventRequest, 4), le32(bits::kAlEventAlControl | bits::kAlEventSmActivation | kAlEventSm2));
  for (std::uint8_t c : {std::uint8_t{'R'}, std::uint8_t{'E'}, std::uint8_t{'S'}}) t.pdi_write(reg::kEscResetPdi, Data{c});
  ASSERT_NO_FATAL_FAILURE(t.expect_same("reset"));
  EXPECT_EQ(t.u16(reg::kDlStatus) & bits::kDlPdiWatchdogOk, 0);  // reset after the access
}

// Random accesses around SM areas (whole buffers, also through the
// whole-buffer calls, parts, crossing an area's
// end, overlapping SMs, mailboxes full and empty, PDI deactivation), 0x0220,
// watchdog settings, link changes, EEPROM reloads and time: the same
// results on both paths after every step.
class EscPdiFastPathRandom : public testing::TestWithParam<unsigned> {};

TEST_P(EscPdiFastPathRandom, SameAsCheckedPath) {
  std::mt19937 rng(GetParam());
  auto pick = [&](std::uint32_t lo, std::uint32_t hi) {  // inclusive
    return static_cast<std::uint32_t>(std::uniform_int_distribution<std::uint32_t>(lo, hi)(rng));
  };
  auto bytes = [&](std::size_t n) {
    Data d(n);
    for (auto& b : d) b = static_cast<std::uint8_t>(pick(0, 255));
    return d;
  };
  struct Area {
    std::uint16_t start;
    std::uint16_t length;
    std::uint8_t control;
  };
  Area areas[4] = {{kMbxOut, kMbxBytes, kCtlMbxOut},
                   {kMbxIn, kMbxBytes, kCtlMbxIn},
                   {kOutputs, kPdBytes, kCtlOutputs},
                   {kInputs, kPdBytes, kCtlInputs}};
  Twin t;
  bool links[4] = {};
  constexpr std::uint8_t kPortsClosed = 0xFC;  // 0x0101: ports 1-3 closed, port 0 auto
  for (unsigned n = 0; n < 4; ++n) t.sm(n, areas[n].start, areas[n].length, areas[n].control);
  // SYNC0 every 1 ms from 0.1 ms on (Section II 0x09A0, 0x0990, 0x0981):
  // pulses and their AL event for the DC block's reads below.
  constexpr std::uint32_t kSync0Ns = 1'000'000;
  constexpr std::uint64_t kStartNs = 100'000;
  constexpr std::uint8_t kSyncUnitAndSync0 = 0x03;  // 0x0981 bits 0 and 1
  t.ecat(Command::Fpwr, fp(kStation, reg::kDcBase + dcreg::kSync0CycleTime), le32(kSync0Ns));
  Data start = le32(static_cast<std::uint32_t>(kStartNs));
  const Data start_high = le32(static_cast<std::uint32_t>(kStartNs >> 32));
  start.insert(start.end(), start_high.begin(), start_high.end());
  t.ecat(Command::Fpwr, fp(kStation, reg::kDcBase + dcreg::kStartTimeCyclicOperation), start);
  t.ecat(Command::Fpwr, fp(kStation, reg::kDcBase + dcreg::kActivation), Data{kSyncUnitAndSync0});
  auto near_area = [&](unsigned n) {
    const Area& a = areas[n];
    return static_cast<std::uint16_t>(a.start + pick(0, a.length + 2) - pick(0, 1) * 2);
  };
  constexpr int kOps = 2000;
  for (int op = 0; op < kOps; ++op) {
    SCOPED_TRACE(testing::Message() << "seed " << GetParam() << " op " << op);
    const unsigned n = pick(0, 3);
    const Area& a = areas[n];
    const unsigned kind = pick(0, 16);
    switch (kind) {
      case 0:  // reconfigure an SM: another place (maybe overlapping another), length, or disabled
        areas[n].start = pick(0, 3) ? areas[n].start : static_cast<std::uint16_t>(0x1000 + pick(0, 0x210));
        areas[n].length = static_cast<std::uint16_t>(pick(0, 4) ? areas[n].length : pick(0, 20));
        t.sm(n, 0, 0, 0, 0);
        t.sm(n, areas[n].start, areas[n].length, areas[n].control, static_cast<std::uint8_t>(pick(0, 5) != 0));
        break;
      case 1:
      case 2:  // the master's side of the buffer
        t.ecat(Command::Fpwr, fp(kStation, a.start), bytes(a.length ? a.length : 1));
        t.ecat(Command::Fprd, fp(kStation, a.start), Data(a.length ? a.length : 1, 0));
        break;
      case 3:
      case 4:  // the whole buffer from the PDI
        t.pdi_read(a.start, a.length ? a.length : 1);
        break;
      case 5:
        t.pdi_write(a.start, bytes(a.length ? a.length : 1));
        break;
      case 6: {  // part of it, or across its edges
        const std::uint16_t at = near_area(n);
        if (pick(0, 1)) {
          t.pdi_read(at, pick(1, a.length + 3));
        } else {
          t.pdi_write(at, bytes(pick(1, a.length + 3)));
        }
        break;
      }
      case 7:  // 0x0220 and its neighbours
        t.pdi_read(static_cast<std::uint16_t>(0x021E + pick(0, 6)), pick(1, 6));
        break;
      case 8:  // PDI deactivation / repeat acknowledge, SM status and activation acknowledges
        if (pick(0, 1)) {
          t.pdi_write(static_cast<std::uint16_t>(reg::sync_manager(n) + reg::sm::kPdiControl),
                      Data{static_cast<std::uint8_t>(pick(0, 3) == 0)});
        } else if (pick(0, 1)) {
          t.pdi_read(reg::sync_manager(n), reg::kSyncManagerStride);
        } else {  // a part of the SM registers: one byte (status, activate), or across two SMs' blocks
          t.pdi_read(static_cast<std::uint16_t>(reg::sync_manager(n) + pick(0, 7)), pick(1, 12));
        }
        break;
      case 9:  // watchdog divider and times
        t.ecat(Command::Fpwr, fp(kStation, static_cast<std::uint16_t>(pick(0, 2) == 0 ? reg::kWatchdogDivider
                                                                       : pick(0, 1) ? reg::kWatchdogTimePdi
                                                                                    : reg::kWatchdogTimeProcessData)),
               le16(static_cast<std::uint16_t>(pick(0, 30))));
        break;
      case 10:  // what the master polls: DL status, watchdog status/counters, SM status
        t.ecat(Command::Fprd, fp(kStation, reg::kDlStatus), Data(2, 0));
        t.ecat(Command::Fprd, fp(kStation, reg::kWatchdogStatusProcessData), Data(4, 0));
        t.pdi_read(reg::kWatchdogStatusProcessData, 1);
        break;
      case 11: {  // links and loop control of ports 1-3; a port only opens with
                  // nothing behind it while no link is up, so every frame comes back
        const unsigned p = pick(1, 3);
        if (pick(0, 1)) {
          links[p] = pick(0, 1) != 0;
          if (links[p]) t.ecat(Command::Fpwr, fp(kStation, reg::kDlControl + 1), Data{kPortsClosed});
          t.set_link(p, links[p]);
        } else {
          // Auto (0), auto-close (1) or closed (3) per port; never forced open (2).
          std::uint8_t loops = 0;
          for (unsigned q = 1; q < 4; ++q) {
            static constexpr std::uint8_t kNotOpen[] = {0, 1, 3};
            loops = static_cast<std::uint8_t>(loops | kNotOpen[pick(0, 2)] << (2 * q));
          }
          const bool any = links[1] || links[2] || links[3];
          t.ecat(Command::Fpwr, fp(kStation, reg::kDlControl + 1), Data{any ? kPortsClosed : loops});
        }
        break;
      }
        break;
      case 12:  // EEPROM reload by the master (DL status bit 0 follows the checksum)
        t.ecat(Command::Fpwr, fp(kStation, reg::kEepromControlStatus), le16(sii_bits::kCommandReload));
        break;
      case 14:  // the whole-buffer calls (in place on the fast ESC): the whole buffer or around it
        if (pick(0, 2)) {
          t.pdi_read_buffer(a.start, a.length ? a.length : 1);
        } else {
          t.pdi_read_buffer(near_area(n), pick(1, a.length + 3));
        }
        break;
      case 15:
        if (pick(0, 2)) {
          t.pdi_write_buffer(a.start, bytes(a.length ? a.length : 1));
        } else {
          t.pdi_write_buffer(near_area(n), bytes(pick(1, a.length + 3)));
        }
        break;
      case 16:  // the DC block: the SYNC status alone (the acknowledge), around it, anywhere in it
        if (pick(0, 1)) {
          t.pdi_read(static_cast<std::uint16_t>(reg::kDcBase + dcreg::kSync0Status + pick(0, 1)), pick(1, 2));
        } else if (pick(0, 1)) {
          t.pdi_read(static_cast<std::uint16_t>(reg::kDcBase + dcreg::kSync0Status - pick(0, 8)), pick(1, 16));
        } else {
          t.pdi_read(static_cast<std::uint16_t>(reg::kDcBase + pick(0, dcreg::kBlockEnd)), pick(1, 8));
        }
        t.pdi_read(reg::kAlEventRequest, 4);
        break;
      default:
        t.advance(Nanoseconds{pick(0, 3'000'000)});
        break;
    }
    ASSERT_NO_FATAL_FAILURE(t.expect_same("random op"));
  }
}

INSTANTIATE_TEST_SUITE_P(Seeds, EscPdiFastPathRandom, testing::Range(1u, 9u));

}  // namespace
}  // namespace ecat::esc::test
