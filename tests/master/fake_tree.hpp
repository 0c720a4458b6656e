// A tree of FakeEsc slaves with the DC port receive times a real tree would
// latch, for tests of the master's topology and DC delay computation
// independent of the emulated ESC (esc/). Each node states its parent and the
// parent's port it hangs on, the cable delay to its parent and the offset of
// its local clock. `latch(now)` walks the frame through the tree as an ESC
// forwards it (ESC datasheet Section I: port 0 -> processing unit -> 3 -> 1
// -> 2 -> 0, absent ports skipped, every hop from a receive port to the next
// transmit port takes `forward_ns`) and stores what every ESC latches: the
// local time of arrival at each active port in 0x0900-0x090F, the 64-bit
// arrival at port 0 in 0x0918. DL status 0x0110 is set from the active ports
// (link, loop open and communication on active ports; loop closed elsewhere).
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <vector>

#include "common/frame_parser.hpp"
#include "fake_esc.hpp"
#include "test_sii_image.hpp"

namespace ecat::master::test {

struct TreeNode {
  std::optional<std::size_t> parent;  // position; empty = on the master
  unsigned parent_port = 0;
  std::uint8_t ports = 0x01;          // bit n: port n connected (port 0 = in)
  std::int64_t cable_ns = 0;          // one way, to the parent
  std::uint32_t local_offset = 0;     // local clock = global time + offset (mod 2^32 for the port times)
};

class FakeTree {
 public:
  static constexpr std::uint16_t kDlPdiOperational = 0x0001;
  static constexpr std::uint16_t kDlWatchdogOk = 0x0002;
  static constexpr std::uint16_t kFeatureDc = 0x0004;
  static constexpr std::array<unsigned, 4> kOrder{0, 3, 1, 2};

  explicit FakeTree(std::vector<TreeNode> nodes, std::int64_t forward_ns = 200)
      : nodes_(std::move(nodes)), forward_ns_(forward_ns), escs_(nodes_.size()),
        arrival_(nodes_.size()), times_(nodes_.size()) {
    for (std::size_t i = 0; i < nodes_.size(); ++i) {
      escs_[i].sii = test_sii_image();
      store_le(escs_[i].mem.data() + reg::kDlStatus, dl_status(nodes_[i].ports));
      store_le(escs_[i].mem.data() + 0x0008, kFeatureDc);
    }
  }

  // DL status as an ESC with these ports connected shows it.
  static std::uint16_t dl_status(std::uint8_t ports) {
    std::uint16_t s = kDlPdiOperational | kDlWatchdogOk;
    for (unsigned n = 0; n < 4; ++n) {
      if (ports & (1u << n)) {
        s = static_cast<std::uint16_t>(s | (1u << (4 + n)) | (1u << (9 + 2 * n)));
      } else {
        s = static_cast<std::uint16_t>(s | (1u << (8 + 2 * n)));
      }
    }
    return s;
  }

  // Every slave in position order processes the frame; a BWR to 0x0900 latches.
  void process(Bytes frame, std::int64_t now_ns) {
    bool latches = false;
    if (auto v = parse_frame(frame)) {
      v->for_each([&](DatagramView d) {
        if (d.command() == Command::Bwr && d.ado() == reg::kDcPortReceiveTime) latches = true;
      });
    }
    for (auto& e : escs_) e.process(frame);
    if (latches) latch(now_ns);
  }

  void latch(std::int64_t now_ns) {
    for (auto& t : times_) t = {};
    for (std::size_t i = 0; i < nodes_.size(); ++i) {
      if (!nodes_[i].parent) walk(i, now_ns);
    }
    for (std::size_t i = 0; i < nodes_.size(); ++i) {
      auto& m = escs_[i].mem;
      for (unsigned p = 0; p < 4; ++p) {
        store_le(m.data() + reg::kDcPortReceiveTime + 4 * p, local32(i, times_[i][p]));
      }
      store_le(m.data() + reg::kDcProcessingUnitReceiveTime,
               static_cast<std::uint64_t>(arrival_[i] + nodes_[i].local_offset));
    }
  }

  // Global time the frame reached slave i (what its delay should be, relative to the reference).
  std::int64_t arrival(std::size_t i) const { return arrival_.at(i); }
  FakeEsc& esc(std::size_t i) { return escs_.at(i); }
  std::size_t size() const { return nodes_.size(); }

 private:
  std::uint32_t local32(std::size_t i, std::int64_t t) const {
    return static_cast<std::uint32_t>(static_cast<std::uint64_t>(t) + nodes_[i].local_offset);
  }
  std::optional<std::size_t> child_on(std::size_t i, unsigned port) const {
    for (std::size_t c = 0; c < nodes_.size(); ++c) {
      if (nodes_[c].parent == i && nodes_[c].parent_port == port) return c;
    }
    return std::nullopt;
  }
  // The frame arrives on port 0 at `t`; returns when it leaves port 0 again.
  std::int64_t walk(std::size_t i, std::int64_t t) {
    arrival_[i] = t;
    times_[i][0] = t;
    for (unsigned k = 1; k < 4; ++k) {
      const unsigned p = kOrder[k];
      if ((nodes_[i].ports & (1u << p)) == 0) continue;
      t += forward_ns_;
      if (auto c = child_on(i, p)) {
        t = walk(*c, t + nodes_[*c].cable_ns) + nodes_[*c].cable_ns;
      }
      times_[i][p] = t;
    }
    return t + forward_ns_;
  }

  std::vector<TreeNode> nodes_;
  std::int64_t forward_ns_;
  std::vector<FakeEsc> escs_;
  std::vector<std::int64_t> arrival_;
  std::vector<std::array<std::int64_t, 4>> times_;
};

}  // namespace ecat::master::test
