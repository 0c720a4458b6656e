// Skipping ESCs a frame does not address (issue 16 item 5, docs/esc.md):
// a line that lets frames pass its passive ESCs by must leave every byte,
// WKC, ADP, IRQ field, DC receive time, watchdog expiry and time exactly as
// the same line entering every ESC (Segment::set_skipping(false), the
// reference). Twin lines get the same frames, PDI accesses, polls, link
// cuts and times; frames, deliveries and every ESC's whole state are compared.
#include <gtest/gtest.h>

#include <bit>
#include <cstring>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include "esc_fixture.hpp"

namespace ecat::esc::test {
namespace {

constexpr std::size_t kSlaves = 70;  // past one 64-bit word of the skip index
constexpr auto kImage = static_cast<std::uint32_t>(4 * kSlaves);  // bytes of outputs (and of inputs)
constexpr std::uint16_t kSm2 = 0x1000;
constexpr std::uint16_t kIn = 0x1100;
constexpr std::uint32_t kInputs = 0x8000;  // logical start of the inputs
constexpr std::uint16_t kDcReceive = 0x0900;
constexpr std::uint16_t kDcSystemTime = 0x0910;
constexpr std::uint16_t kDcEnd = 0x0920;

std::uint16_t station(std::size_t i) { return static_cast<std::uint16_t>(0x1001 + i); }

// Two identical lines; `fast` skips, `ref` enters every ESC.
struct Twin {
  Twin() : fast(kSlaves), ref(kSlaves) { ref.segment.set_skipping(false); }
  void at(Nanoseconds t) {
    fast.clock.set(t);
    ref.clock.set(t);
  }
  // One frame built by `fill` through both; frames and deliveries equal.
  template <typename Fill>
  void frame(Nanoseconds now, Fill fill, const std::string& what) {
    (void)answers(now, fill, what);
  }
  // The same, with each datagram's WKC and data as the skipping line left them.
  template <typename Fill>
  std::vector<std::pair<std::uint16_t, Data>> answers(Nanoseconds now, Fill fill, const std::string& what) {
    TestFrame a;
    TestFrame b;
    fill(a);
    fill(b);
    a.send(fast.segment, now);
    b.send(ref.segment, now);
    ++frames;
    EXPECT_EQ(a.frame().size(), b.frame().size()) << what;
    if (a.frame().size() != b.frame().size()) return {};
    EXPECT_EQ(std::memcmp(a.frame().data(), b.frame().data(), a.frame().size()), 0) << what;
    std::vector<std::pair<std::uint16_t, Data>> out;
    for (std::size_t k = 0; a.frame().size() > 0 && k < count_of(a); ++k) out.emplace_back(a.wkc(k), a.data(k));
    return out;
  }
  static std::size_t count_of(const TestFrame& f) {
    std::size_t n = 0;
    for (DatagramView d = f.dg(0);; d = d.next()) {
      ++n;
      if (!d.more()) return n;
    }
  }
  void pdi_write(std::size_t i, std::uint16_t address, const Data& d) {
    fast[i].write(address, d);
    ref[i].write(address, d);
  }
  void pdi_read(std::size_t i, std::uint16_t address, std::size_t n, const std::string& what) {
    Data x(n);
    Data y(n);
    fast[i].read(address, x);
    ref[i].read(address, y);
    EXPECT_EQ(x, y) << what;
  }
  // Every ESC: its whole memory, DC receive times and system time, last
  // access, timers, IRQ and attention.
  void compare(const std::string& what) {
    for (std::size_t i = 0; i < kSlaves; ++i) {
      Esc& x = fast[i];
      Esc& y = ref[i];
      ASSERT_EQ(x.memory_size(), y.memory_size());
      if (const auto a = first_memory_difference(x, y)) {
        ADD_FAILURE() << what << ": slave " << i << " byte 0x" << std::hex << *a << ": "
                      << (*a < x.memory_size() ? int{x.memory()[*a]} : -1) << " != "
                      << (*a < y.memory_size() ? int{y.memory()[*a]} : -1);
        return;
      }
      EXPECT_EQ(x.last_time(), y.last_time()) << what << " slave " << i;
      EXPECT_EQ(x.next_timer(), y.next_timer()) << what << " slave " << i;
      EXPECT_EQ(x.irq(), y.irq()) << what << " slave " << i;
      EXPECT_EQ(x.pdi_attention(), y.pdi_attention()) << what << " slave " << i;
      for (std::uint16_t a = kDcReceive; a < kDcEnd; a += 2) {
        EXPECT_EQ(x.register_u16(a), y.register_u16(a)) << what << " slave " << i << " DC 0x" << std::hex << a;
      }
    }
  }
  Line fast;
  Line ref;
  std::size_t frames = 0;
};

// Station addresses, SM2 (3-buffer, ECAT writes, AL event, watchdog
// trigger) at 0x1000 mapped by FMMU 0 from logical 4 i, and FMMU 1 reading
// 0x1100 (plain RAM) from `inputs` + 4 i: the process image of a line.
void set_up(Twin& t, std::uint32_t inputs = kInputs) {
  for (Line* l : {&t.fast, &t.ref}) {
    assign_stations(*l);
    for (std::size_t i = 0; i < kSlaves; ++i) {
      config_sm(l->segment, station(i), 2, kSm2, 4, 0x64);
      config_fmmu(l->segment, station(i), 0, static_cast<std::uint32_t>(4 * i), 4, 0, 7, kSm2, 0, 2);
      config_fmmu(l->segment, station(i), 1, static_cast<std::uint32_t>(inputs + 4 * i), 4, 0, 7, kIn, 0, 1);
    }
  }
  t.compare("set-up");
}

TEST(SegmentSkip, LrwOfOneSlaveEntersFewEscsAndMatches) {
  Twin t;
  set_up(t);
  // LRW of slave 33's outputs and inputs only, many times: the skipping line
  // enters that ESC (and the last one), the result is the same.
  for (int k = 0; k < 20; ++k) {
    const auto now = Nanoseconds{1'000'000} + Nanoseconds{10'000} * k;
    t.at(now);
    t.frame(now, [&](TestFrame& f) {
      f.add(Command::Lrw, 33 * 4, le32(0x11223344u + static_cast<std::uint32_t>(k)));
      f.add(Command::Lrd, kInputs + 33 * 4, 4);
    }, "lrw " + std::to_string(k));
  }
  t.compare("after LRWs");
  EXPECT_EQ(t.fast[33].memory()[kSm2], t.ref[33].memory()[kSm2]);
  // The frames did pass ESCs by: one more enters slave 33 and the last
  // slave (which turns it back) only; the reference enters all 70.
  auto count = [](std::span<std::uint64_t> bits) {
    std::size_t c = 0;
    for (std::uint64_t& w : bits) {
      c += static_cast<std::size_t>(std::popcount(w));
      w = 0;
    }
    return c;
  };
  (void)count(t.fast.segment.entered());
  (void)count(t.ref.segment.entered());
  t.frame(Nanoseconds{2'000'000}, [&](TestFrame& f) { f.add(Command::Lrw, 33 * 4, le32(7)); }, "counted");
  const std::span<std::uint64_t> entered = t.fast.segment.entered();
  EXPECT_EQ(entered[0], std::uint64_t{1} << 33);
  EXPECT_EQ(entered[1], std::uint64_t{1} << (kSlaves - 1 - 64));
  EXPECT_EQ(count(t.ref.segment.entered()), kSlaves);
}

TEST(SegmentSkip, ProcessDataWatchdogExpiresOnTheSameFrame) {
  Twin t;
  set_up(t);
  // Slave 40: watchdog unit (98 + 2) x 40 ns = 4 µs, 25 units = 100 µs.
  for (Line* l : {&t.fast, &t.ref}) {
    transact(l->segment, Command::Fpwr, fp(station(40), reg::kWatchdogDivider), le16(98), Nanoseconds{0});
    transact(l->segment, Command::Fpwr, fp(station(40), reg::kWatchdogTimeProcessData), le16(25), Nanoseconds{0});
  }
  const Nanoseconds start{2'000'000};
  // Its outputs once (the trigger), then frames for slave 3 only, 7 µs apart:
  // one of them passes slave 40 after its deadline.
  t.frame(start, [&](TestFrame& f) { f.add(Command::Lwr, 40 * 4, le32(1)); }, "trigger");
  for (int k = 1; k < 30; ++k) {
    const Nanoseconds now = start + Nanoseconds{7'000} * k;
    t.frame(now, [&](TestFrame& f) { f.add(Command::Lrw, 3 * 4, le32(2)); }, "lrw slave 3");
    EXPECT_EQ(t.fast[40].memory()[reg::kWatchdogCounterProcessData],
              t.ref[40].memory()[reg::kWatchdogCounterProcessData])
        << "frame " << k;
  }
  EXPECT_EQ(t.ref[40].memory()[reg::kWatchdogCounterProcessData], 1);  // it expired
  t.compare("after expiry");
}

TEST(SegmentSkip, IrqFieldOfAnUnaddressedSlave) {
  Twin t;
  set_up(t);
  // Slave 50 asks for the AL status change event in the IRQ field (0x0200
  // bit 3); its firmware writes AL status (ECAT event 0x0210 bit 3).
  for (Line* l : {&t.fast, &t.ref}) {
    transact(l->segment, Command::Fpwr, fp(station(50), reg::kEcatEventMask), le16(0x0008), Nanoseconds{0});
  }
  t.pdi_write(50, reg::kAlStatus, le16(0x0002));
  t.frame(Nanoseconds{3'000'000}, [&](TestFrame& f) { f.add(Command::Lrd, kInputs + 2 * 4, 4); }, "irq");
  t.compare("irq");
}

TEST(SegmentSkip, ReceiveTimesLatchedBySkippingLine) {
  Twin t;
  set_up(t);
  // A latch on one slave, then on all, between frames that address others;
  // then an ESC reset after many skipped frames (its DC unit restarts the
  // rate correction at the latest time it saw).
  Nanoseconds now{4'000'000};
  for (int k = 0; k < 10; ++k) {
    now += Nanoseconds{13'000};
    t.frame(now, [&](TestFrame& f) { f.add(Command::Lrw, 7 * 4, le32(5)); }, "before");
  }
  t.frame(now += Nanoseconds{13'000}, [&](TestFrame& f) { f.add(Command::Fpwr, fp(station(20), kDcReceive), le32(0)); }, "latch one");
  t.frame(now += Nanoseconds{13'000}, [&](TestFrame& f) { f.add(Command::Lrw, 7 * 4, le32(5)); }, "after one");
  t.compare("latch one");
  t.frame(now += Nanoseconds{13'000}, [&](TestFrame& f) { f.add(Command::Bwr, device_address(0, kDcReceive), le32(0)); }, "latch all");
  for (int k = 0; k < 10; ++k) {
    t.frame(now += Nanoseconds{13'000}, [&](TestFrame& f) { f.add(Command::Lrw, 9 * 4, le32(5)); }, "after all");
  }
  t.frame(now += Nanoseconds{13'000}, [&](TestFrame& f) {
    f.add(Command::Fpwr, fp(station(30), kDcSystemTime), Data(8, 0x55));  // the time loop corrects the rate
  }, "system time");
  for (std::uint8_t c : {std::uint8_t{'R'}, std::uint8_t{'E'}, std::uint8_t{'S'}}) {
    t.frame(now += Nanoseconds{13'000}, [&](TestFrame& f) { f.add(Command::Fpwr, fp(station(30), reg::kEscResetEcat), Data{c}); }, "reset");
    for (int k = 0; k < 5; ++k) {
      t.frame(now += Nanoseconds{13'000}, [&](TestFrame& f) { f.add(Command::Lrw, 9 * 4, le32(5)); }, "between");
    }
  }
  t.compare("after reset");
}

// Skipping turned off and on again (issue 30: the dense path of
// Segment::send keeps no index): the frames the skipping line passed ESCs
// by are taken in before the first dense frame, and the first skipping
// frame after dense ones reads every ESC again - a slave whose FMMU moved,
// one accessed over the PDI, one with a latch armed meanwhile.
TEST(SegmentSkip, SkippingOffAndOnAgainMatches) {
  Twin t;
  set_up(t);
  Nanoseconds now{5'000'000};
  for (int k = 0; k < 5; ++k) {
    t.frame(now += Nanoseconds{11'000}, [&](TestFrame& f) { f.add(Command::Lrw, 7 * 4, le32(3)); }, "skipping");
  }
  t.fast.segment.set_skipping(false);
  t.frame(now += Nanoseconds{11'000}, [&](TestFrame& f) { f.add(Command::Fprd, fp(station(60), reg::kAlStatus), 2); },
          "first dense");
  t.compare("first dense");
  // While dense: slave 33's outputs move to logical 0x9000, slave 20's
  // firmware writes AL status with the IRQ field asking for it, slave 10's
  // receive latch is armed.
  constexpr std::uint32_t kMoved = 0x9000;
  for (Line* l : {&t.fast, &t.ref}) {
    config_fmmu(l->segment, station(33), 0, kMoved, 4, 0, 7, kSm2, 0, 2);
    transact(l->segment, Command::Fpwr, fp(station(20), reg::kEcatEventMask), le16(0x0008), now);
  }
  t.pdi_write(20, reg::kAlStatus, le16(0x0002));
  t.frame(now += Nanoseconds{11'000}, [&](TestFrame& f) { f.add(Command::Fpwr, fp(station(10), kDcReceive), le32(0)); },
          "latch while dense");
  t.fast.segment.set_skipping(true);
  for (int k = 0; k < 5; ++k) {
    t.frame(now += Nanoseconds{11'000}, [&](TestFrame& f) {
      f.add(Command::Lrw, kMoved, le32(0xA0B0C0D0u + static_cast<std::uint32_t>(k)));
      f.add(Command::Lrd, kInputs + 2 * 4, 4);
    }, "skipping again");
    t.compare("skipping again " + std::to_string(k));
  }
  // Skipping resumed: one more such frame enters slave 2 (LRD), 33 (LRW),
  // 20 (IRQ field: not passive) and the last slave (it turns the frame back).
  for (std::uint64_t& w : t.fast.segment.entered()) w = 0;
  t.frame(now += Nanoseconds{11'000}, [&](TestFrame& f) {
    f.add(Command::Lrw, kMoved, le32(1));
    f.add(Command::Lrd, kInputs + 2 * 4, 4);
  }, "counted");
  const std::span<std::uint64_t> entered = t.fast.segment.entered();
  EXPECT_EQ(entered[0], (std::uint64_t{1} << 2) | (std::uint64_t{1} << 20) | (std::uint64_t{1} << 33));
  EXPECT_EQ(entered[1], std::uint64_t{1} << (kSlaves - 1 - 64));
  t.compare("counted");
}

// A process image in one piece (outputs at 4 i, inputs after all outputs)
// and one LRW over all of it, as a typical cycle's frame: every ESC is
// mapped, so the skipping line takes the dense loop for it (no index kept),
// and the next frame that skips reads every ESC into the index again
// without entering it. Between the frames: a PDI write asking for the IRQ
// field, an FMMU moved by a frame, the receive latch armed - each seen by
// the next skipping frame as by the line that enters every ESC.
TEST(SegmentSkip, LrwOverEveryEscIsDenseAndTheNextFrameStillSkips) {
  Twin t;
  constexpr std::uint32_t kWholeImage = 2 * kImage;  // outputs, then inputs
  set_up(t, kImage);
  Nanoseconds now{1'000'000};
  auto whole = [&](std::uint32_t seed) {
    return [seed](TestFrame& f) {
      Data image(kWholeImage);
      for (std::size_t b = 0; b < image.size(); ++b) image[b] = static_cast<std::uint8_t>(seed + b);
      f.add(Command::Lrw, 0, image);
    };
  };
  auto one = [&](std::uint32_t v) { return [v](TestFrame& f) { f.add(Command::Lrw, 33 * 4, le32(v)); }; };
  auto clear = [](std::span<std::uint64_t> bits) {
    for (std::uint64_t& w : bits) w = 0;
  };
  for (int k = 0; k < 4; ++k) {
    t.at(now += Nanoseconds{11'000});
    clear(t.fast.segment.entered());
    t.frame(now, whole(static_cast<std::uint32_t>(k)), "whole image " + std::to_string(k));
    // Every ESC entered (all mapped).
    for (std::size_t i = 0; i < kSlaves; ++i) {
      EXPECT_NE(t.fast.segment.entered()[i / 64] & (std::uint64_t{1} << (i % 64)), 0u) << "slave " << i;
    }
    t.compare("whole image " + std::to_string(k));
    clear(t.fast.segment.entered());
    t.at(now += Nanoseconds{11'000});
    t.frame(now, one(0x11223344u + static_cast<std::uint32_t>(k)), "slave 33 " + std::to_string(k));
    // Skipping again at once: slave 33 and the last one only.
    EXPECT_EQ(t.fast.segment.entered()[0], std::uint64_t{1} << 33) << k;
    EXPECT_EQ(t.fast.segment.entered()[1], std::uint64_t{1} << (kSlaves - 1 - 64)) << k;
    t.compare("slave 33 " + std::to_string(k));
  }
  // Changes made by the dense frames themselves, which keep no index: an
  // ECAT event mask broadcast to every ESC (slave 20 then raises an event
  // by its PDI), the receive latch armed by a broadcast write, slave 33's
  // FMMU moved by an FPWR riding in a frame with the whole image.
  t.frame(now += Nanoseconds{11'000}, [&](TestFrame& f) {
    whole(7)(f);
    f.add(Command::Bwr, reg::kEcatEventMask, le16(0x0008));
  }, "mask broadcast");
  t.pdi_write(20, reg::kAlStatus, le16(0x0002));
  t.frame(now += Nanoseconds{11'000}, one(1), "slave 20's IRQ field");
  t.compare("slave 20's IRQ field");
  t.frame(now += Nanoseconds{11'000}, [&](TestFrame& f) { f.add(Command::Bwr, kDcReceive, le32(0)); }, "latch broadcast");
  t.frame(now += Nanoseconds{11'000}, one(2), "receive times of every ESC");
  t.compare("receive times of every ESC");
  constexpr std::uint32_t kMoved = 0x9000;
  t.frame(now += Nanoseconds{11'000}, [&](TestFrame& f) {
    whole(9)(f);
    f.add(Command::Fpwr, fp(station(33), reg::fmmu(0)), fmmu_bytes(kMoved, 4, 0, 7, kSm2, 0, 2));
  }, "FMMU moved in a dense frame");
  for (int k = 0; k < 3; ++k) {
    t.frame(now += Nanoseconds{11'000}, [&](TestFrame& f) {
      f.add(Command::Lrw, kMoved, le32(0xA0B0C0D0u + static_cast<std::uint32_t>(k)));
      f.add(Command::Lrd, kImage + 2 * 4, 4);
    }, "moved " + std::to_string(k));
    t.frame(now += Nanoseconds{11'000}, one(5), "slave 33's old place " + std::to_string(k));
    t.compare("after the changes " + std::to_string(k));
  }
  clear(t.fast.segment.entered());
  t.frame(now += Nanoseconds{11'000}, [&](TestFrame& f) { f.add(Command::Lrw, kMoved, le32(1)); }, "counted");
  // Slave 33 (and slave 20 while its event is pending) - not all of them.
  EXPECT_NE(t.fast.segment.entered()[0] & (std::uint64_t{1} << 33), 0u);
  EXPECT_LE(std::popcount(t.fast.segment.entered()[0] & ~(std::uint64_t{1} << 20)), 1);
  t.compare("counted");
}

// An LRW over the outputs of half the slaves (35 of 70, one span each of
// the 70 ESCs' two inside) takes the dense loop too: every ESC is entered.
// One slave fewer, and it skips: the 34 mapped ESCs and the last one, which
// turns the frame back. Bytes, WKC and every ESC's state match the line that
// enters every ESC either way, and the skipping frames after a dense one
// still see what changed.
TEST(SegmentSkip, LrwOverHalfTheEscsIsDenseAndOneSlaveLessSkips) {
  Twin t;
  set_up(t);
  Nanoseconds now{1'000'000};
  auto outputs_of = [](std::size_t slaves, std::uint32_t seed) {
    return [slaves, seed](TestFrame& f) {
      Data image(4 * slaves);
      for (std::size_t b = 0; b < image.size(); ++b) image[b] = static_cast<std::uint8_t>(seed + b);
      f.add(Command::Lrw, 0, image);
    };
  };
  auto entered = [&]() {
    std::size_t n = 0;
    for (const std::uint64_t w : t.fast.segment.entered()) n += static_cast<std::size_t>(std::popcount(w));
    return n;
  };
  auto clear = [&]() {
    for (std::uint64_t& w : t.fast.segment.entered()) w = 0;
  };
  for (std::uint32_t k = 0; k < 3; ++k) {
    clear();
    t.frame(now += Nanoseconds{11'000}, outputs_of(kSlaves / 2, k), "half " + std::to_string(k));
    EXPECT_EQ(entered(), kSlaves) << k;
    t.compare("half " + std::to_string(k));
    clear();
    t.frame(now += Nanoseconds{11'000}, outputs_of(kSlaves / 2 - 1, k + 10), "half less one " + std::to_string(k));
    EXPECT_EQ(entered(), kSlaves / 2) << k;
    EXPECT_NE(t.fast.segment.entered()[1] & (std::uint64_t{1} << (kSlaves - 1 - 64)), 0u) << k;
    t.compare("half less one " + std::to_string(k));
  }
}

// What the skip index keeps of an ESC's addressing and ports (read again
// only when the ESC's address epoch moved, issue 30 item 1): each change
// made between two frames - a station address written by a frame, an alias
// written by the PDI and then enabled in DL control, a port closed and
// opened again by its loop bits, a cable cut and restored - is seen by the
// next frame exactly as by the line that enters every ESC. Frames that pass
// the changed ESC by come before and after each change.
// A frame that enters every ESC (a broadcast) sets the entered bits of the
// ESCs up to the one that turns it back, and no others, whether that is the
// first ESC, one inside a word of the index or at its edges (the dense loop
// sets them in one go after the pass; segments of one ESC take their own path).
TEST(SegmentSkip, BroadcastEntersTheEscsUpToTheOneThatTurnsItBack) {
  for (const std::size_t turn : {std::size_t{0}, std::size_t{1}, std::size_t{62}, std::size_t{63}, std::size_t{64},
                                 kSlaves - 2, kSlaves - 1}) {
    Line line(kSlaves);
    // Port 1 of ESC `turn` closed (DL control 0x0101 loop bits 3:2 = 11).
    ASSERT_EQ(transact(line.segment, Command::Apwr, ap(static_cast<std::uint16_t>(turn), reg::kDlControl + 1),
                       Data{0x0C}).wkc, 1);
    for (std::uint64_t& w : line.segment.entered()) w = 0;
    EXPECT_EQ(transact(line.segment, Command::Brd, reg::kAlStatus, 2).wkc, turn + 1) << "turned at " << turn;
    const std::span<std::uint64_t> entered = line.segment.entered();
    for (std::size_t i = 0; i < kSlaves; ++i) {
      const bool bit = (entered[i / 64] >> (i % 64) & 1) != 0;
      EXPECT_EQ(bit, i <= turn) << "slave " << i << ", turned at " << turn;
    }
  }
  Line one(1);
  for (std::uint64_t& w : one.segment.entered()) w = 0;
  EXPECT_EQ(transact(one.segment, Command::Brd, reg::kAlStatus, 2).wkc, 1);
  EXPECT_EQ(one.segment.entered()[0], 1u);
}

TEST(SegmentSkip, AddressingChangedBetweenFramesIsSeenByTheNextFrame) {
  Twin t;
  set_up(t);
  Nanoseconds now{1'000'000};
  auto answers = [&](const std::string& what, auto fill) {
    now += Nanoseconds{20'000};
    t.at(now);
    return t.answers(now, fill, what);
  };
  // The outputs of slave 33 (LRW over FMMU 0 only: +2), which every frame
  // below passes the other slaves by for.
  auto pass = [&](const std::string& what) {
    const auto a = answers(what, [](TestFrame& f) { f.add(Command::Lrw, 33 * 4, le32(0x01020304)); });
    ASSERT_EQ(a.size(), 1u) << what;
    EXPECT_EQ(a[0].first, 2) << what;
  };
  // LRW of slave 50's outputs: 2 while the frame reaches it, 0 when a port
  // before it turns the frame back.
  auto lrw_of_50 = [&](const std::string& what) {
    const auto a = answers(what, [](TestFrame& f) { f.add(Command::Lrw, 50 * 4, le32(0x0A0B0C0D)); });
    return a.empty() ? std::uint16_t{0xFFFF} : a[0].first;
  };
  pass("every slave read once");
  pass("passing them by");

  // Station address 0x0010: slave 20 moves from 0x1015 to 0x2020.
  constexpr std::uint16_t kMoved = 0x2020;
  auto a = answers("station written", [](TestFrame& f) {
    f.add(Command::Fpwr, fp(station(20), reg::kConfiguredStationAddress), le16(kMoved));
  });
  ASSERT_EQ(a.size(), 1u);
  EXPECT_EQ(a[0].first, 1);
  pass("after the station write");
  a = answers("the new station", [](TestFrame& f) {
    f.add(Command::Fprd, fp(kMoved, reg::kConfiguredStationAddress), 2);
    f.add(Command::Fprd, fp(station(20), reg::kConfiguredStationAddress), 2);
  });
  ASSERT_EQ(a.size(), 2u);
  EXPECT_EQ(a[0], std::make_pair(std::uint16_t{1}, le16(kMoved)));
  EXPECT_EQ(a[1], std::make_pair(std::uint16_t{0}, le16(0)));

  // Alias 0x0012, written by the PDI: no address until DL control 0x0103
  // bit 0 (0x0100 bit 24) enables it, then slave 45 answers to it too.
  constexpr std::uint16_t kAlias = 0x0777;
  t.pdi_write(45, reg::kConfiguredStationAlias, le16(kAlias));
  pass("after the alias write");
  a = answers("alias not enabled", [](TestFrame& f) { f.add(Command::Fprd, fp(kAlias, reg::kConfiguredStationAddress), 2); });
  ASSERT_EQ(a.size(), 1u);
  EXPECT_EQ(a[0], std::make_pair(std::uint16_t{0}, le16(0)));
  a = answers("alias enabled", [](TestFrame& f) {
    f.add(Command::Fpwr, fp(station(45), reg::kDlControl + 3), Data{0x01});
  });
  ASSERT_EQ(a.size(), 1u);
  EXPECT_EQ(a[0].first, 1);
  pass("after the alias was enabled");
  a = answers("the alias", [](TestFrame& f) { f.add(Command::Fprd, fp(kAlias, reg::kConfiguredStationAddress), 2); });
  ASSERT_EQ(a.size(), 1u);
  EXPECT_EQ(a[0], std::make_pair(std::uint16_t{1}, le16(station(45))));

  // DL control loop bits 0x0101: port 1 of slave 30 closed (bits 3:2 = 11),
  // then back to Auto (00) with its link up.
  EXPECT_EQ(lrw_of_50("before the loop write"), 2);
  a = answers("port 1 closed", [](TestFrame& f) { f.add(Command::Fpwr, fp(station(30), reg::kDlControl + 1), Data{0x0C}); });
  ASSERT_EQ(a.size(), 1u);
  EXPECT_EQ(a[0].first, 1);
  EXPECT_EQ(lrw_of_50("port 1 of slave 30 closed"), 0);
  a = answers("slave 33 behind the closed port", [](TestFrame& f) { f.add(Command::Lrw, 33 * 4, le32(0x01020304)); });
  ASSERT_EQ(a.size(), 1u);
  EXPECT_EQ(a[0].first, 0);
  a = answers("port 1 auto", [](TestFrame& f) { f.add(Command::Fpwr, fp(station(30), reg::kDlControl + 1), Data{0x00}); });
  ASSERT_EQ(a.size(), 1u);
  EXPECT_EQ(a[0].first, 1);
  EXPECT_EQ(lrw_of_50("port 1 of slave 30 auto again"), 2);

  // A cable cut after slave 40 (its port 1 in Auto closes), then restored.
  EXPECT_TRUE(t.fast.segment.set_link(40, kDownstreamPort, false));
  EXPECT_TRUE(t.ref.segment.set_link(40, kDownstreamPort, false));
  EXPECT_EQ(lrw_of_50("cable after slave 40 cut"), 0);
  pass("slave 33 before the cut");
  EXPECT_TRUE(t.fast.segment.set_link(40, kDownstreamPort, true));
  EXPECT_TRUE(t.ref.segment.set_link(40, kDownstreamPort, true));
  EXPECT_EQ(lrw_of_50("cable restored"), 2);
  pass("after the cable came back");
  t.compare("end");
}

// Random frames, PDI accesses, polls, link cuts and times, compared step by step.
TEST(SegmentSkip, RandomSequencesMatchTheFullPass) {
  Twin t;
  set_up(t);
  std::mt19937 rng(16);  // fixed: the sequence is the same every run
  auto pick = [&](std::size_t n) { return static_cast<std::size_t>(rng() % n); };
  const std::array<std::uint16_t, 14> registers{reg::kAlStatus,      reg::kAlControl,     reg::kConfiguredStationAddress,
                                                reg::kEcatEventMask, reg::kDlStatus,      reg::kWatchdogDivider,
                                                reg::kWatchdogTimeProcessData, kDcReceive, kDcSystemTime,
                                                reg::kEscResetEcat,      kSm2,                kIn,
                                                reg::kDlControl + 1, reg::fmmu(0)};
  Nanoseconds now{10'000'000};
  std::size_t cut = kSlaves;  // slave whose port 1 is cut, if any
  for (int step = 0; step < 1500; ++step) {
    const std::string what = "step " + std::to_string(step);
    // Time mostly forward, sometimes back (a frame may start before the last one).
    if (pick(20) == 0) {
      now -= Nanoseconds{static_cast<std::int64_t>(pick(30'000))};
    } else {
      now += Nanoseconds{static_cast<std::int64_t>(pick(40'000))};
    }
    t.at(now);
    const std::size_t op = pick(100);
    if (op < 70) {
      // A frame of 1-4 datagrams; broadcasts and xRMW are rarer.
      const std::size_t count = 1 + pick(4);
      std::vector<std::uint32_t> seeds;
      for (std::size_t k = 0; k < 4 * count; ++k) seeds.push_back(static_cast<std::uint32_t>(rng()));
      t.frame(now, [&](TestFrame& f) {
        for (std::size_t k = 0; k < count; ++k) {
          const std::uint32_t* s = &seeds[4 * k];
          const std::uint16_t reg_addr = registers[s[1] % registers.size()];
          const std::uint16_t who = s[0] % 8 == 0 ? static_cast<std::uint16_t>(s[0] >> 8) : station(s[0] % kSlaves);
          const Data data{static_cast<std::uint8_t>(s[2]), static_cast<std::uint8_t>(s[2] >> 8),
                          static_cast<std::uint8_t>(s[3]), static_cast<std::uint8_t>(s[3] >> 8)};
          switch (s[1] % 23) {
            case 0: case 1: case 2: f.add(Command::Lrw, s[2] % (kImage + 8), data); break;
            case 3: case 4: f.add(Command::Lrd, kInputs + s[2] % kImage, 4); break;
            case 5: f.add(Command::Lwr, s[2] % kImage, data); break;
            case 6: case 7: f.add(Command::Fprd, fp(who, reg_addr), 2); break;
            // Writes only to registers that do not move the station addresses or FMMUs too often.
            case 8: f.add(Command::Fpwr, fp(who, reg::kAlControl), le16(static_cast<std::uint16_t>(s[3] % 9))); break;
            case 9: f.add(Command::Fpwr, fp(who, reg::kEcatEventMask), le16(static_cast<std::uint16_t>(s[3] & 0x000C))); break;
            case 10: f.add(Command::Fpwr, fp(who, reg::kWatchdogTimeProcessData), le16(static_cast<std::uint16_t>(s[3] % 40))); break;
            case 11: f.add(Command::Fpwr, fp(who, kDcReceive), le32(0)); break;
            case 12: f.add(Command::Fpwr, fp(who, reg::kEscResetEcat), Data{static_cast<std::uint8_t>("RES"[s[3] % 3])}); break;
            case 13: f.add(Command::Aprd, ap(static_cast<std::uint16_t>(s[0] % (kSlaves + 4)), reg_addr), 2); break;
            case 14: f.add(Command::Apwr, ap(static_cast<std::uint16_t>(s[0] % (kSlaves + 4)), kIn), data); break;
            case 15: f.add(Command::Fprw, fp(who, kIn), data); break;
            case 16: f.add(Command::Aprw, ap(static_cast<std::uint16_t>(s[0] % kSlaves), kIn), data); break;
            case 17: f.add(Command::Nop, 0, 2); break;
            case 18: if (s[3] % 3 == 0) f.add(Command::Brd, device_address(0, reg::kAlStatus), 2); else f.add(Command::Lrd, kInputs, 4); break;
            case 19: if (s[3] % 3 == 0) f.add(Command::Frmw, fp(station(0), kDcSystemTime), 8); else f.add(Command::Fprd, fp(who, kIn), 4); break;
            case 20: f.add(Command::Fpwr, fp(who, reg::kDlControl + 1), Data{static_cast<std::uint8_t>(s[3] % 8 == 0 ? 0x0C : 0x00)}); break;
            case 21: f.add(Command::Fpwr, fp(who, reg::kWatchdogDivider), le16(static_cast<std::uint16_t>(s[3] % 200))); break;
            default: f.add(Command::Lrw, kInputs + s[2] % kImage, data); break;
          }
        }
      }, what);
    } else if (op < 82) {
      const std::size_t i = pick(kSlaves);
      const std::uint16_t a = pick(2) ? kSm2 : registers[pick(registers.size())];
      if (pick(2)) {
        t.pdi_read(i, a, 4, what);
      } else {
        t.pdi_write(i, a == reg::kEscResetEcat ? static_cast<std::uint16_t>(reg::kAlStatus) : a,
                    le16(static_cast<std::uint16_t>(rng())));
      }
    } else if (op < 90) {
      const std::size_t i = pick(kSlaves);
      EXPECT_EQ(t.fast[i].poll(now), t.ref[i].poll(now)) << what;
    } else if (op < 92) {
      EXPECT_EQ(t.fast.segment.poll(now), t.ref.segment.poll(now)) << what;
    } else if (op < 94) {
      // Cut the line after a slave, or restore the cut.
      if (cut == kSlaves) {
        cut = pick(kSlaves - 1);
        EXPECT_TRUE(t.fast.segment.set_link(cut, kDownstreamPort, false));
        EXPECT_TRUE(t.ref.segment.set_link(cut, kDownstreamPort, false));
      } else {
        EXPECT_TRUE(t.fast.segment.set_link(cut, kDownstreamPort, true));
        EXPECT_TRUE(t.ref.segment.set_link(cut, kDownstreamPort, true));
        cut = kSlaves;
      }
    } else {
      t.compare(what);  // looking only now and then: unobserved stretches too
    }
    if (::testing::Test::HasFailure()) return;
  }
  t.compare("end");
  EXPECT_GT(t.frames, 900u);
}

}  // namespace
}  // namespace ecat::esc::test
