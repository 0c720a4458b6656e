// Ethernet over EtherCAT, the slave side (mailbox type 2, ETG.1000.6 §5.7;
// header bits in coe/eoe_header.hpp; docs/eoe.md).
//  - Frames from the master come in fragments (frame type 0): fragment 0
//    carries the complete size in 32-byte units, later ones their offset in
//    32-byte units; all of one frame share the frame number. They are put
//    together in one fixed buffer and the whole frame goes to the Ethernet
//    side (EthernetPort: the built-in responder or a TAP). A fragment out of
//    sequence, with a wrong offset or frame number, or past the announced
//    size or the buffer, drops the frame in progress; the drop is counted
//    (Stats) and the mailbox goes on. Fragments get no reply.
//  - Frames toward the master (transmit()) wait in a fixed ring of frame
//    buffers and leave one fragment per free SM1, as big as SM1 allows
//    (every fragment but the last a multiple of 32 bytes); the mailbox server
//    interleaves them with the replies to requests (next_output()).
//  - Set IP Parameter (type 2) sets each field whose flag is set and answers
//    type 3 with result 0; Get IP Parameter (6) answers 7 with every field
//    that is set; Set Address Filter (4) answers 5; Get Address Filter (8)
//    answers 9. Other request types: type 3 with "unsupported frame type"
//    (0x0002), as SSC answers them.
// The frame buffers (one for reassembly, kTxFrames toward the master, about
// 7.5 KiB) are allocated once, on the first fragment or transmit(): a slave
// whose master never uses EoE does not carry them (docs/performance-log.md,
// "Session 14: memory per servo"). No allocation after that first one.
#pragma once

#include <array>
#include <cstdint>
#include <memory>

#include "coe/eoe_header.hpp"
#include "coe/mailbox_service.hpp"

namespace ecat::coe {

namespace eoe {
inline constexpr std::size_t kMacSize = 6;
inline constexpr std::size_t kDnsNameSize = 32;
// Largest frame put together or sent: 1514 bytes (Ethernet without FCS) fit
// in 48 blocks of 32; bigger announced sizes are dropped as oversize.
inline constexpr std::size_t kMaxFrame = 48 * kBlock;
inline constexpr std::size_t kMinFrame = 14;  // destination, source, EtherType
inline constexpr std::size_t kTxFrames = 4;   // frames waiting for the master
inline constexpr std::size_t kMaxMacFilters = 16;
inline constexpr std::size_t kMaxMacFilterMasks = 4;

using Mac = std::array<std::uint8_t, kMacSize>;

// Set/Get IP Parameter flags (UINT32 in front of the fields).
inline constexpr std::uint32_t kHasMac = 1u << 0;
inline constexpr std::uint32_t kHasIp = 1u << 1;
inline constexpr std::uint32_t kHasSubnet = 1u << 2;
inline constexpr std::uint32_t kHasGateway = 1u << 3;
inline constexpr std::uint32_t kHasDnsServer = 1u << 4;
inline constexpr std::uint32_t kHasDnsName = 1u << 5;

// Addresses as UINT32 values, first octet in the most significant byte
// (192.168.1.10 = 0xC0A8010A); on the wire little-endian like every EoE
// field, so the octets travel last first (0A 01 A8 C0), as SOEM writes them.
struct IpParameters {
  std::uint32_t flags = 0;  // which fields are set
  Mac mac{};
  std::uint32_t ip = 0;
  std::uint32_t subnet = 0;
  std::uint32_t gateway = 0;
  std::uint32_t dns_server = 0;
  std::array<char, kDnsNameSize> dns_name{};
};

// Start-up values: a locally administered MAC (02:00:00:00:00:01), no IP, so
// the built-in responder stays silent until an address is set.
inline IpParameters default_parameters() noexcept {
  IpParameters p;
  p.flags = kHasMac;
  p.mac = {0x02, 0x00, 0x00, 0x00, 0x00, 0x01};
  return p;
}

// Address filter (Set Address Filter): UINT16 options (bits 0-3 filter
// count, 4-5 mask count, 7 no broadcasts), then the filters, then masks.
inline constexpr std::uint16_t kFilterCountMask = 0x000F;
inline constexpr unsigned kMaskCountShift = 4;
inline constexpr std::uint16_t kMaskCountMask = 0x0003;
inline constexpr std::uint16_t kNoBroadcasts = 1u << 7;

struct AddressFilter {
  bool set = false;  // never set: every frame goes to the master
  std::uint16_t options = 0;
  std::array<Mac, kMaxMacFilters> filters{};
  std::array<Mac, kMaxMacFilterMasks> masks{};
};

struct Stats {
  std::uint64_t frames_received = 0;    // complete frames from the master
  std::uint64_t frames_sent = 0;        // complete frames to the master
  std::uint64_t fragments_received = 0;
  std::uint64_t fragments_sent = 0;
  std::uint64_t dropped_sequence = 0;   // fragment/frame number or offset out of sequence
  std::uint64_t dropped_oversize = 0;   // past the announced size or kMaxFrame
  std::uint64_t dropped_short = 0;      // shorter than an Ethernet header
  std::uint64_t dropped_tx_full = 0;    // transmit() while every frame buffer waited
  std::uint64_t dropped_filtered = 0;   // transmit() refused by the address filter
  std::uint64_t bad_requests = 0;       // too short for their type, unknown types
  std::uint64_t dropped_no_memory = 0;  // the frame buffers could not be allocated
};
}  // namespace eoe

// The Ethernet side of the slave: gets every frame the master sent.
class EthernetPort {
 public:
  virtual ~EthernetPort() = default;
  virtual void receive(ConstBytes frame) noexcept = 0;
};

class EoeServer final : public MailboxService {
 public:
  EoeServer() = default;
  EoeServer(const EoeServer&) = delete;
  EoeServer& operator=(const EoeServer&) = delete;

  void set_port(EthernetPort* port) noexcept { port_ = port; }
  // Start-up defaults (command line, ENI InitCmds); Set IP Parameter overrides.
  void set_ip_parameters(const eoe::IpParameters& p) noexcept { ip_ = p; }
  const eoe::IpParameters& ip_parameters() const noexcept { return ip_; }
  const eoe::AddressFilter& address_filter() const noexcept { return filter_; }
  const eoe::Stats& stats() const noexcept { return stats_; }

  // A frame from the Ethernet side toward the master. False (counted) when
  // it is too short or too long, the address filter refuses it, or all
  // kTxFrames buffers are waiting.
  bool transmit(ConstBytes frame) noexcept;
  std::size_t tx_waiting() const noexcept { return tx_count_; }

  MailboxType type() const noexcept override { return MailboxType::EoE; }
  Expected<std::size_t, MailboxError> handle(ConstBytes request, Bytes reply, od::EsmState state) noexcept override;
  bool has_output() const noexcept override { return tx_count_ > 0; }
  bool starts_messages() const noexcept override { return true; }
  std::size_t next_output(Bytes out) noexcept override;
  void reset() noexcept override;

 private:
  void fragment(const eoe::Header& h, ConstBytes data) noexcept;
  void drop_frame(std::uint64_t& counter) noexcept;
  std::size_t set_ip(const eoe::Header& h, ConstBytes body, Bytes reply) noexcept;
  std::size_t get_ip(const eoe::Header& h, Bytes reply) noexcept;
  std::size_t set_filter(const eoe::Header& h, ConstBytes body, Bytes reply) noexcept;
  std::size_t get_filter(const eoe::Header& h, Bytes reply) noexcept;
  static std::size_t result(Bytes reply, eoe::FrameType type, std::uint8_t port, eoe::Result r) noexcept;
  bool passes_filter(ConstBytes frame) const noexcept;
  // The frame buffers, allocated on first use; false when that failed.
  bool has_buffers() noexcept;

  // First, on the cache line of the object's vtable pointer: has_output()
  // reads it at every firmware poll of a slave with EoE (the mailbox
  // server asks its streamers), and the ring's kilobytes lie between.
  std::size_t tx_count_ = 0;  // frames in the ring toward the master (tx_ below)
  EthernetPort* port_ = nullptr;
  eoe::IpParameters ip_;
  eoe::AddressFilter filter_;
  eoe::Stats stats_;

  struct Buffers {
    std::array<std::uint8_t, eoe::kMaxFrame> rx;  // reassembly of the frame coming from the master
    std::array<std::array<std::uint8_t, eoe::kMaxFrame>, eoe::kTxFrames> tx;  // frames toward the master
  };
  std::unique_ptr<Buffers> buffers_;

  // Reassembly of the frame coming from the master (in buffers_->rx).
  bool rx_active_ = false;
  std::size_t rx_size_ = 0;      // bytes received so far
  std::size_t rx_capacity_ = 0;  // announced complete size, rounded to 32
  std::uint8_t rx_fragment_ = 0; // next fragment number expected
  std::uint8_t rx_frame_ = 0;

  // Frames toward the master: a ring in buffers_->tx; the front one is being fragmented.
  std::array<std::size_t, eoe::kTxFrames> tx_length_{};
  std::size_t tx_head_ = 0;
  std::size_t tx_offset_ = 0;       // bytes of the front frame already sent
  std::uint8_t tx_fragment_ = 0;
  std::uint8_t tx_frame_ = 0;       // frame number of the front frame
};

}  // namespace ecat::coe
