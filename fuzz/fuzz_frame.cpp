// libFuzzer target: the frame/datagram parser with ESCs behind it. The input
// is a sequence of Ethernet frames ([u16 length][bytes], fuzz_input.hpp) sent
// through a line of two ESCs with Segment::process_frame, 100 µs apart, with
// the ESCs' timers polled between frames - so a fuzzed master can configure
// sync managers and FMMUs with early frames and exercise them with later ones.
// Any crash, hang, sanitizer report or broken invariant is a finding.
#include <cstdint>
#include <cstdlib>
#include <vector>

#include "common/frame.hpp"
#include "esc/esc.hpp"
#include "esc/segment.hpp"
#include "esc/sii_interface.hpp"
#include "fuzz/fuzz_input.hpp"

namespace {

using namespace ecat;

constexpr Nanoseconds kFrameGap{100'000};
constexpr std::size_t kMaxFrame = kEthernetHeaderSize + kVlanTagSize + kMaxEthernetPayload;

std::vector<std::uint8_t> make_sii() {
  std::vector<std::uint8_t> s(256, 0);
  s[esc::kSiiConfigAreaBytes] = esc::sii_crc(std::span(s.data(), esc::kSiiConfigAreaBytes));
  return s;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const std::vector<std::uint8_t> sii = make_sii();
  esc::EscConfig cfg;
  cfg.sii = sii;
  ManualClock clock;
  esc::Esc a(cfg, clock);
  esc::Esc b(cfg, clock);
  esc::Segment segment;
  segment.add(a);
  segment.add(b);

  std::vector<std::uint8_t> frame;
  std::vector<std::uint8_t> before;
  frame.reserve(kMaxFrame);
  before.reserve(kMaxFrame);
  fuzz::Records records(data, size);
  std::span<const std::uint8_t> rec;
  Nanoseconds now{0};
  while (records.next(rec, kMaxFrame)) {
    frame.assign(rec.begin(), rec.end());
    before = frame;
    const bool carried = segment.process_frame(frame, now);
    // A malformed frame leaves every byte as it was (esc/segment.hpp contract).
    if (!carried && !parse_frame(before) && frame != before) std::abort();
    now += kFrameGap;
    clock.set(now);
    (void)segment.poll(now);
  }
  return 0;
}
