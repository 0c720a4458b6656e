// How the logical process image travels on the wire: split into logical
// datagrams of at most the maximum data size, the datagrams packed into as
// few Ethernet frames as fit, and the WKC each datagram must come back with.
//
// Sources (shared/spec/masters.md §1.4, §2.4): SOEM `ecx_config_map_group`
// cuts the image into segments of at most EC_MAXLRWDATA = 1486 bytes (the
// first 20 bytes shorter for the FRMW of the DC reference clock in the same
// frame); a slave's span that fits one segment is not split, a larger one is
// cut at the segment size. IgH sends one datagram per domain chunk. Logical
// addresses run on without gaps from one datagram to the next.
//
// Expected WKC per datagram (ETG.1000.4 §5.4.3; masters.md §6 #4): every ESC
// counts a logical datagram once per direction, whatever the number of its
// FMMUs the datagram hits: +1 if any read FMMU overlaps it, +2 (LRW) or +1
// (LWR) if any write FMMU overlaps it. A slave whose span is cut over two
// datagrams therefore counts in both.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "common/command.hpp"
#include "common/expected.hpp"
#include "common/frame.hpp"
#include "master/master_error.hpp"

namespace ecat::master {

// One FMMU's window into the logical image.
struct FmmuSpan {
  std::uint32_t logical = 0;
  std::uint32_t length = 0;
  std::uint32_t slave = 0;  // position, to count each ESC once per datagram
  bool write = false;       // outputs (FMMU type write) or inputs/status (read)
};

// One datagram of the cyclic exchange.
struct PdDatagram {
  Command command = Command::Lrw;
  std::uint32_t logical = 0;
  std::uint16_t length = 0;
  std::uint16_t expected_wkc = 0;  // in the datagram's own counting (LWR: 1 per slave)
  std::uint32_t frame = 0;         // 0-based frame of the cycle it travels in
};

struct ProcessImagePlan {
  std::vector<PdDatagram> datagrams;
  std::size_t frames = 0;
};

struct PlanLimits {
  std::size_t max_datagram_data = kMaxDatagramData;  // data bytes per logical datagram
  std::size_t first_frame_reserved = 0;              // bytes of other datagrams in frame 0 (DC FRMW: 20)
};

// Bytes a frame offers to datagrams (headers, data, WKCs): the Ethernet
// payload less the EtherCAT frame header.
inline constexpr std::size_t kFrameDatagramRoom = kMaxEthernetPayload - kFrameHeaderSize;
// What SOEM keeps free in the first frame for `FRMW 0x0910:8` (EC_FIRSTDCDATAGRAM).
inline constexpr std::size_t kDcDatagramBytes = kDatagramOverhead + 8;

// `spans` must cover [0, total_bytes) contiguously in logical order (the
// master's layout: all outputs, then all inputs, then the SM1 status bytes).
// `use_lrw`: one region of LRW datagrams; otherwise LWR over [0,
// output_bytes) and LRD over [output_bytes, total_bytes).
Expected<ProcessImagePlan, MasterError> plan_process_image(std::span<const FmmuSpan> spans,
                                                           std::uint32_t output_bytes, std::uint32_t total_bytes,
                                                           bool use_lrw, PlanLimits limits = {});

}  // namespace ecat::master
