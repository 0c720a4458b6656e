// Skipping on trees and rings (issue 30 item 2, esc/segment_route.cpp): a
// segment that lets frames pass the ESCs they do not address must leave
// every frame byte, WKC, ADP, delivery (master port, time, units passed),
// every ESC's memory (DL status, error and lost-link counters included),
// DC receive times, ports, times and timers exactly as the same segment
// entering every ESC on the port walk (Segment::set_skipping(false)).
// Twin segments of each topology - a tree through junctions built out of
// route order, a ring, a ring through a tree, a line of unlike ESCs - get
// the same random frames on either master port, PDI accesses, polls, cable
// cuts and restores, loop-control writes and resets, for many seeds.
#include <gtest/gtest.h>

#include <bit>
#include <cstring>
#include <random>
#include <string>
#include <utility>

#include "esc_fixture.hpp"

namespace ecat::esc::test {
namespace {

constexpr std::size_t kSlaves = 70;  // past one 64-bit word of the skip index
constexpr auto kImage = static_cast<std::uint32_t>(4 * kSlaves);
constexpr std::uint16_t kSm2 = 0x1000;
constexpr std::uint16_t kIn = 0x1100;
constexpr std::uint32_t kInputs = 0x8000;
constexpr std::uint16_t kDcReceive = 0x0900;
constexpr std::uint16_t kDcSystemTime = 0x0910;
constexpr std::uint16_t kDcEnd = 0x0920;

enum class Kind { Tree, Ring, RingThroughTree, UnlikeLine };

std::string name(Kind k) {
  switch (k) {
    case Kind::Tree: return "tree";
    case Kind::Ring: return "ring";
    case Kind::RingThroughTree: return "ring through tree";
    case Kind::UnlikeLine: return "line of unlike ESCs";
  }
  return "?";
}

// Four ports each (junctions anywhere); every third ESC of another type
// (other times inside), so the times of the route are not one step.
EscConfig config_of(std::size_t i) {
  EscConfig c = make_config();
  c.port_count = 4;
  if (i % 3 == 1) {
    c.processing_delay = Nanoseconds{320};
    c.forwarding_delay = Nanoseconds{110};
    c.port_forwarding_delay[2] = Nanoseconds{170};
  } else if (i % 3 == 2) {
    c.processing_delay = Nanoseconds{280};
    c.forwarding_delay = Nanoseconds{90};
  }
  return c;
}

struct Net {
  explicit Net(Kind kind) {
    for (std::size_t i = 0; i < kSlaves; ++i) escs.push_back(std::make_unique<Esc>(config_of(i), clock));
    auto chain = [&](std::size_t from, std::size_t to, std::size_t parent, unsigned parent_port) {
      for (std::size_t i = from; i <= to; ++i) {
        EXPECT_EQ(segment.add(*escs[i], i == from ? parent : i - 1, i == from ? parent_port : kDownstreamPort,
                              kUpstreamPort, Nanoseconds{static_cast<std::int64_t>(700 + 37 * (i % 5))}),
                  i);
      }
    };
    segment.add(*escs[0]);
    switch (kind) {
      case Kind::Tree:
        // 0 is a junction: port 2 gets 1..15 (added first, entered last),
        // port 3 16..30, port 1 the junction 31 with 32..46 on its port 3
        // and 47..60 on its port 1; 61..69 hang off 50's port 2.
        chain(1, 15, 0, 2);
        chain(16, 30, 0, 3);
        chain(31, 31, 0, kDownstreamPort);
        chain(32, 46, 31, 3);
        chain(47, 60, 31, kDownstreamPort);
        chain(61, 69, 50, 2);
        break;
      case Kind::Ring:
        chain(1, kSlaves - 1, 0, kDownstreamPort);
        segment.connect_master(1, kSlaves - 1, kDownstreamPort);
        break;
      case Kind::RingThroughTree:
        // Coupler 0, junction 1 on its port 1; a stub 2..20 on the
        // junction's port 3; the ring's branch 21..59 on its port 2 with a
        // stub 60..64 on 40's port 3, then 65..69, back to master port 1.
        chain(1, 1, 0, kDownstreamPort);
        chain(2, 20, 1, 3);
        chain(21, 59, 1, 2);
        chain(60, 64, 40, 3);
        chain(65, 69, 59, kDownstreamPort);
        segment.connect_master(1, kSlaves - 1, kDownstreamPort);
        break;
      case Kind::UnlikeLine:
        chain(1, kSlaves - 1, 0, kDownstreamPort);
        break;
    }
  }
  Esc& operator[](std::size_t i) { return *escs[i]; }
  ManualClock clock;
  std::vector<std::unique_ptr<Esc>> escs;
  Segment segment;
};

struct Twin {
  explicit Twin(Kind k) : kind(k), fast(k), ref(k) {
    ref.segment.set_skipping(false);
    EXPECT_FALSE(fast.segment.is_line());
  }
  void at(Nanoseconds t) {
    fast.clock.set(t);
    ref.clock.set(t);
  }
  template <typename Fill>
  void frame(Nanoseconds now, Fill fill, const std::string& what, unsigned master_port = 0) {
    TestFrame a;
    TestFrame b;
    fill(a);
    fill(b);
    const Delivery x = a.send_on(fast.segment, now, master_port);
    const Delivery y = b.send_on(ref.segment, now, master_port);
    EXPECT_EQ(x.outcome, y.outcome) << what;
    EXPECT_EQ(x.master_port, y.master_port) << what;
    EXPECT_EQ(x.at, y.at) << what;
    EXPECT_EQ(x.processed, y.processed) << what;
    ASSERT_EQ(a.frame().size(), b.frame().size()) << what;
    for (std::size_t k = 0; k < a.frame().size(); ++k) {
      if (a.frame()[k] != b.frame()[k]) {
        ADD_FAILURE() << what << ": frame byte " << k << " of " << a.frame().size() << ": " << int{a.frame()[k]}
                      << " != " << int{b.frame()[k]} << " (master port " << master_port << ")";
        break;
      }
    }
    ++frames;
    if (x.returned()) ++returned;
  }
  void compare(const std::string& what) {
    EXPECT_EQ(fast.segment.frames_processed(), ref.segment.frames_processed()) << what;
    EXPECT_EQ(fast.segment.frames_dropped(), ref.segment.frames_dropped()) << what;
    for (std::size_t i = 0; i < kSlaves; ++i) {
      Esc& x = fast[i];
      Esc& y = ref[i];
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
      for (unsigned p = 0; p < kMaxPorts; ++p) {
        EXPECT_EQ(x.port_open(p), y.port_open(p)) << what << " slave " << i << " port " << p;
        EXPECT_EQ(x.link(p), y.link(p)) << what << " slave " << i << " port " << p;
      }
      for (std::uint16_t a = kDcReceive; a < kDcEnd; a += 2) {
        EXPECT_EQ(x.register_u16(a), y.register_u16(a)) << what << " slave " << i << " DC 0x" << std::hex << a;
      }
    }
  }
  Kind kind;
  Net fast;
  Net ref;
  std::size_t frames = 0;
  std::size_t returned = 0;
  std::array<std::uint16_t, kSlaves> station{};  // by slave index
};

// Station addresses by position (APWR: the frame's order through the
// units, not the slaves' indices), read back per slave; then SM2 and two
// FMMUs per slave as in esc_skip_test.cpp, by station.
void set_up(Twin& t) {
  for (Net* n : {&t.fast, &t.ref}) {
    for (std::size_t p = 0; p < kSlaves; ++p) {
      transact(n->segment, Command::Apwr, ap(static_cast<std::uint16_t>(p), reg::kConfiguredStationAddress),
               le16(static_cast<std::uint16_t>(0x1001 + p)));
    }
  }
  for (std::size_t i = 0; i < kSlaves; ++i) {
    t.station[i] = t.ref[i].register_u16(reg::kConfiguredStationAddress);
    ASSERT_EQ(t.station[i], t.fast[i].register_u16(reg::kConfiguredStationAddress)) << i;
    ASSERT_NE(t.station[i], 0) << "slave " << i << " not reached";
  }
  for (Net* n : {&t.fast, &t.ref}) {
    for (std::size_t i = 0; i < kSlaves; ++i) {
      config_sm(n->segment, t.station[i], 2, kSm2, 4, 0x64);
      config_fmmu(n->segment, t.station[i], 0, static_cast<std::uint32_t>(4 * i), 4, 0, 7, kSm2, 0, 2);
      config_fmmu(n->segment, t.station[i], 1, static_cast<std::uint32_t>(kInputs + 4 * i), 4, 0, 7, kIn, 0, 1);
    }
  }
  t.compare("set-up");
}

std::size_t count_and_clear(std::span<std::uint64_t> bits) {
  std::size_t c = 0;
  for (std::uint64_t& w : bits) {
    c += static_cast<std::size_t>(std::popcount(w));
    w = 0;
  }
  return c;
}

class SkipTopology : public ::testing::TestWithParam<Kind> {};

// The frames do pass ESCs by: an LRW of one slave's image enters that
// slave only (no other is addressed, all are passive), the reference all.
TEST_P(SkipTopology, LrwOfOneSlaveEntersOneEsc) {
  Twin t(GetParam());
  set_up(t);
  Nanoseconds now{1'000'000};
  for (int k = 0; k < 5; ++k) {
    t.frame(now += Nanoseconds{20'000}, [&](TestFrame& f) { f.add(Command::Lrw, 33 * 4, le32(7 + k)); }, "lrw");
  }
  (void)count_and_clear(t.fast.segment.entered());
  (void)count_and_clear(t.ref.segment.entered());
  t.frame(now += Nanoseconds{20'000}, [&](TestFrame& f) { f.add(Command::Lrw, 33 * 4, le32(1)); }, "counted");
  EXPECT_EQ(count_and_clear(t.fast.segment.entered()), 1u);
  EXPECT_EQ(count_and_clear(t.ref.segment.entered()), kSlaves);
  t.compare("after");
  if (t.kind == Kind::Ring || t.kind == Kind::RingThroughTree) {
    // The intact ring's frame from the redundant port passes every ESC
    // unprocessed: none is entered, all see it.
    t.frame(now += Nanoseconds{20'000}, [&](TestFrame& f) { f.add(Command::Lrw, 33 * 4, le32(2)); }, "port 1", 1);
    EXPECT_EQ(count_and_clear(t.fast.segment.entered()), 0u);
    t.compare("port 1");
  }
}

// A cut ring (and a cut tree): both master ports' frames, every ESC in reach entered by the
// APRD it addresses, times and DC latches of the frames that turn round.
TEST_P(SkipTopology, CutAndRestoreWithLatches) {
  Twin t(GetParam());
  set_up(t);
  Nanoseconds now{2'000'000};
  // Three cables between slaves, and the master's first one.
  for (const auto& cable : {std::pair<std::size_t, unsigned>{5, kDownstreamPort}, {40, kDownstreamPort},
                            {63, kDownstreamPort}, {0, kUpstreamPort}}) {
    // Not a structured binding: the frame lambda below captures it (clang
    // before 16 cannot capture a binding).
    const std::size_t cut = cable.first;
    const unsigned port = cable.second;
    for (Net* n : {&t.fast, &t.ref}) EXPECT_TRUE(n->segment.set_link(cut, port, false));
    for (int k = 0; k < 6; ++k) {
      for (unsigned mp = 0; mp < kMasterPorts; ++mp) {
        t.frame(now += Nanoseconds{15'000}, [&](TestFrame& f) {
          f.add(Command::Lrw, 0, static_cast<std::uint16_t>(kImage));
          f.add(Command::Aprd, ap(static_cast<std::uint16_t>(3 * k), reg::kAlStatus), 2);
          if (k == 2) f.add(Command::Bwr, device_address(0, kDcReceive), le32(0));
          if (k == 4) f.add(Command::Fpwr, fp(t.station[cut], kDcReceive), le32(0));
        }, "cut " + std::to_string(cut), mp);
        t.compare("cut " + std::to_string(cut) + " frame " + std::to_string(k));
      }
    }
    for (Net* n : {&t.fast, &t.ref}) EXPECT_TRUE(n->segment.set_link(cut, port, true));
  }
}

// Random frames on either master port, PDI accesses, polls, cable cuts and
// restores (any cable, up to three at once), loop-control writes (ports
// forced open, closed, Auto-close) and resets, compared step by step.
TEST_P(SkipTopology, RandomSequencesMatchThePortWalk) {
  for (std::uint32_t seed = 1; seed <= 12; ++seed) {
    SCOPED_TRACE(name(GetParam()) + " seed " + std::to_string(seed));
    Twin t(GetParam());
    set_up(t);
    std::mt19937 rng(seed);
    auto pick = [&](std::size_t n) { return static_cast<std::size_t>(rng() % n); };
    const std::array<std::uint16_t, 14> registers{reg::kAlStatus,      reg::kAlControl,     reg::kConfiguredStationAddress,
                                                  reg::kEcatEventMask, reg::kDlStatus,      reg::kWatchdogDivider,
                                                  reg::kWatchdogTimeProcessData, kDcReceive, kDcSystemTime,
                                                  reg::kEscResetEcat,  kSm2,                kIn,
                                                  reg::kDlControl + 1, reg::kLostLinkCounter};
    // Loop control (0x0101: two bits per port, 00 Auto, 01 Auto-close, 10 open, 11 closed).
    const std::array<std::uint8_t, 8> loops{0x00, 0x00, 0x00, 0x0C, 0x04, 0x30, 0xC0, 0x08};
    // Every cable, as (slave, port) seen from one end.
    std::vector<std::pair<std::size_t, unsigned>> cables;
    for (std::size_t i = 0; i < kSlaves; ++i) {
      for (unsigned p = 0; p < kMaxPorts; ++p) {
        const auto peer = t.fast.segment.peer(i, p);
        if (peer && (peer->master || peer->slave > i)) cables.emplace_back(i, p);
      }
    }
    std::vector<std::size_t> cut;  // indices into cables
    Nanoseconds now{10'000'000};
    const bool ring = t.kind == Kind::Ring || t.kind == Kind::RingThroughTree;
    for (int step = 0; step < 1200; ++step) {
      const std::string what = "step " + std::to_string(step);
      if (pick(20) == 0) {
        now -= Nanoseconds{static_cast<std::int64_t>(pick(30'000))};
      } else {
        now += Nanoseconds{static_cast<std::int64_t>(pick(40'000))};
      }
      t.at(now);
      const std::size_t op = pick(100);
      if (op < 70) {
        const std::size_t count = 1 + pick(4);
        std::vector<std::uint32_t> seeds;
        for (std::size_t k = 0; k < 4 * count; ++k) seeds.push_back(static_cast<std::uint32_t>(rng()));
        const unsigned master_port = ring && pick(3) == 0 ? 1 : 0;
        t.frame(now, [&](TestFrame& f) {
          for (std::size_t k = 0; k < count; ++k) {
            const std::uint32_t* s = &seeds[4 * k];
            const std::uint16_t reg_addr = registers[s[1] % registers.size()];
            const std::uint16_t who =
                s[0] % 8 == 0 ? static_cast<std::uint16_t>(s[0] >> 8) : t.station[s[0] % kSlaves];
            const Data data{static_cast<std::uint8_t>(s[2]), static_cast<std::uint8_t>(s[2] >> 8),
                            static_cast<std::uint8_t>(s[3]), static_cast<std::uint8_t>(s[3] >> 8)};
            switch (s[1] % 24) {
              case 0: case 1: case 2: f.add(Command::Lrw, s[2] % (kImage + 8), data); break;
              case 3: case 4: f.add(Command::Lrd, kInputs + s[2] % kImage, 4); break;
              case 5: f.add(Command::Lwr, s[2] % kImage, data); break;
              case 6: case 7: f.add(Command::Fprd, fp(who, reg_addr), 2); break;
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
              case 19: if (s[3] % 3 == 0) f.add(Command::Frmw, fp(t.station[0], kDcSystemTime), 8); else f.add(Command::Fprd, fp(who, kIn), 4); break;
              // Loop control: the ports of the ESC change under the frame (the port walk takes it on).
              case 20: if (s[3] % 4 == 0) f.add(Command::Fpwr, fp(who, reg::kDlControl + 1), Data{loops[(s[3] >> 4) % loops.size()]}); else f.add(Command::Fprd, fp(who, reg::kDlStatus), 2); break;
              case 21: f.add(Command::Fpwr, fp(who, reg::kWatchdogDivider), le16(static_cast<std::uint16_t>(s[3] % 200))); break;
              case 22: if (s[3] % 16 == 0) f.add(Command::Bwr, device_address(0, reg::kDlControl + 1), Data{0x00}); else f.add(Command::Lrw, kInputs + s[2] % kImage, data); break;
              default: f.add(Command::Lrw, kInputs + s[2] % kImage, data); break;
            }
          }
        }, what, master_port);
      } else if (op < 80) {
        const std::size_t i = pick(kSlaves);
        const std::uint16_t a = pick(2) ? kSm2 : registers[pick(registers.size())];
        if (pick(2)) {
          Data x(4);
          Data y(4);
          t.fast[i].read(a, x);
          t.ref[i].read(a, y);
          EXPECT_EQ(x, y) << what;
        } else {
          const Data d = le16(static_cast<std::uint16_t>(rng()));
          const std::uint16_t to = a == reg::kEscResetEcat ? static_cast<std::uint16_t>(reg::kAlStatus) : a;
          t.fast[i].write(to, d);
          t.ref[i].write(to, d);
        }
      } else if (op < 87) {
        const std::size_t i = pick(kSlaves);
        EXPECT_EQ(t.fast[i].poll(now), t.ref[i].poll(now)) << what;
      } else if (op < 89) {
        EXPECT_EQ(t.fast.segment.poll(now), t.ref.segment.poll(now)) << what;
      } else if (op < 94) {
        // Cut a cable, or restore one.
        if (!cut.empty() && (cut.size() == 3 || pick(2) == 0)) {
          const std::size_t k = pick(cut.size());
          const auto [slave, port] = cables[cut[k]];
          EXPECT_TRUE(t.fast.segment.set_link(slave, port, true));
          EXPECT_TRUE(t.ref.segment.set_link(slave, port, true));
          cut.erase(cut.begin() + static_cast<std::ptrdiff_t>(k));
        } else {
          const std::size_t k = pick(cables.size());
          const auto [slave, port] = cables[k];
          if (std::find(cut.begin(), cut.end(), k) == cut.end()) {
            EXPECT_TRUE(t.fast.segment.set_link(slave, port, false));
            EXPECT_TRUE(t.ref.segment.set_link(slave, port, false));
            cut.push_back(k);
          }
        }
      } else {
        t.compare(what);
      }
      if (::testing::Test::HasFailure()) return;
    }
    t.compare("end");
    EXPECT_GT(t.frames, 750u);
    EXPECT_GT(t.returned, 300u);
  }
}

INSTANTIATE_TEST_SUITE_P(Topologies, SkipTopology,
                         ::testing::Values(Kind::Tree, Kind::Ring, Kind::RingThroughTree, Kind::UnlikeLine),
                         [](const ::testing::TestParamInfo<Kind>& param) {
                           std::string n = name(param.param);
                           for (char& c : n) if (c == ' ') c = '_';
                           return n;
                         });

}  // namespace
}  // namespace ecat::esc::test
