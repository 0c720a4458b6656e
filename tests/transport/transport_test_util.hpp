#pragma once

#include <cstdint>
#include <vector>

#include "transport/transport.hpp"

namespace ecat::transport::test {

// A 30-byte EtherCAT frame (SOEM on a veth): broadcast, source 01:01:01:01:01:01,
// one BRD 0x0000:2 datagram, index `idx`.
inline std::vector<std::uint8_t> brd_frame(std::uint8_t idx) {
  return {0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0x01, 0x01, 0x01, 0x01, 0x01, 0x01, 0x88, 0xA4,
          0x0E, 0x10,                                      // EtherCAT header: 14 bytes, type 1
          0x07, idx, 0x00, 0x00, 0x00, 0x00, 0x02, 0x00,  // BRD, idx, ADP 0, ADO 0, len 2
          0x00, 0x00, 0x00, 0x00, 0x00, 0x00};            // IRQ, data, WKC
}

}  // namespace ecat::transport::test
