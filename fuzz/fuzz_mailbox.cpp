// libFuzzer target: the mailbox server with CoE (SDO, SDO information) and
// FoE behind a real ESC. The ESC's SM0/SM1 are set up by datagrams as a
// master does; the AL status is set through the PDI as the ESM would. The
// first input byte picks the ESM state; then each record is one operation:
//   op 0: write the rest into SM0 (padded to the SM length) by FPWR;
//   op 1: read SM1 by FPRD (frees it);
//   op 2: toggle the SM1 repeat request (0x080E bit 1) by FPWR;
// with MailboxServer::poll after every operation.
#include <array>
#include <cstdint>
#include <cstdlib>
#include <string>
#include <sys/stat.h>
#include <unistd.h>
#include <vector>

#include "coe/coe_protocol.hpp"
#include "coe/foe_server.hpp"
#include "coe/mailbox_server.hpp"
#include "coe/object_store.hpp"
#include "coe/sdo_info.hpp"
#include "coe/sdo_server.hpp"
#include "common/frame_builder.hpp"
#include "esc/esc.hpp"
#include "esc/registers.hpp"
#include "esc/segment.hpp"
#include "esc/sii_interface.hpp"
#include "esi/device_loader.hpp"
#include "fuzz/fuzz_input.hpp"

namespace {

using namespace ecat;

constexpr std::uint16_t kStation = 0x1001;
constexpr std::uint16_t kSm0Start = 0x1000;
constexpr std::uint16_t kSm1Start = 0x1080;
constexpr std::uint16_t kMailboxBytes = 128;
constexpr std::uint8_t kSm0Control = 0x26;  // mailbox, ECAT writes, PDI IRQ
constexpr std::uint8_t kSm1Control = 0x22;  // mailbox, ECAT reads, PDI IRQ
constexpr std::uint8_t kSmActivate = 0x01;
constexpr std::uint8_t kSmRepeatRequest = 0x02;
constexpr std::array<od::EsmState, 4> kStates{od::EsmState::PreOp, od::EsmState::SafeOp, od::EsmState::Op,
                                              od::EsmState::Bootstrap};

enum Op : std::uint8_t { kWriteSm0 = 0, kReadSm1 = 1, kToggleRepeat = 2 };

// Sends one datagram through the segment; returns its WKC.
std::uint16_t transact(esc::Segment& s, Command c, std::uint16_t ado, std::span<const std::uint8_t> data,
                       std::span<std::uint8_t> result = {}) {
  std::array<std::uint8_t, 2 * kMailboxBytes + 64> buf{};
  FrameBuilder b(buf);
  auto at = b.append(c, 0, device_address(kStation, ado), data);
  if (!at) std::abort();
  if (!s.process_frame(b.finish(), Nanoseconds{0})) std::abort();
  auto d = b.datagram_at(*at);
  std::copy_n(d.data().begin(), std::min(result.size(), d.data().size()), result.begin());
  return d.wkc();
}

void config_sm(esc::Segment& s, unsigned n, std::uint16_t start, std::uint8_t control) {
  const std::array<std::uint8_t, 8> d{static_cast<std::uint8_t>(start), static_cast<std::uint8_t>(start >> 8),
                                      static_cast<std::uint8_t>(kMailboxBytes), 0, control, 0, kSmActivate, 0};
  transact(s, Command::Fpwr, esc::reg::sync_manager(n), d);
}

const od::DeviceDescription& device() {
  static const od::DeviceDescription d = [] {
    auto r = esi::load_default_device();
    if (!r) std::abort();
    return std::move(*r);
  }();
  return d;
}

std::string foe_directory() {
  std::string dir = "/tmp/ecat-fuzz-foe-" + std::to_string(::getpid());
  (void)::mkdir(dir.c_str(), 0700);
  return dir;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  static const std::string foe_dir = foe_directory();
  static const std::vector<std::uint8_t> sii = [] {
    std::vector<std::uint8_t> s(256, 0);
    s[esc::kSiiConfigAreaBytes] = esc::sii_crc(std::span(s.data(), esc::kSiiConfigAreaBytes));
    return s;
  }();
  esc::EscConfig cfg;
  cfg.sii = sii;
  ManualClock clock;
  esc::Esc esc(cfg, clock);
  esc::Segment segment;
  segment.add(esc);
  const std::array<std::uint8_t, 2> st{static_cast<std::uint8_t>(kStation), static_cast<std::uint8_t>(kStation >> 8)};
  transact(segment, Command::Apwr, esc::reg::kConfiguredStationAddress, st);
  config_sm(segment, 0, kSm0Start, kSm0Control);
  config_sm(segment, 1, kSm1Start, kSm1Control);
  esc.write_u8(esc::reg::kAlStatus, static_cast<std::uint8_t>(kStates[data[0] % kStates.size()]));

  coe::ObjectStore store(device().dictionary);
  coe::SdoServer sdo(store);
  coe::SdoInfo info(store);
  coe::CoeProtocol coe(sdo, &info);
  coe::FoeServer::Options foe_options;
  foe_options.directory = foe_dir;
  foe_options.max_file_bytes = 4096;
  coe::FoeServer foe(foe_options);
  coe::MailboxServer mailbox(esc, kMailboxBytes);
  mailbox.add_service(coe);
  mailbox.add_service(foe);

  std::array<std::uint8_t, kMailboxBytes> sm{};
  std::uint8_t repeat = 0;
  Nanoseconds now{0};
  fuzz::Records records(data + 1, size - 1);
  std::span<const std::uint8_t> rec;
  mailbox.poll(now);
  while (records.next(rec, kMailboxBytes + 1)) {
    if (rec.empty()) continue;
    switch (rec[0] % 3) {
      case kWriteSm0:
        sm.fill(0);
        std::copy(rec.begin() + 1, rec.end(), sm.begin());
        transact(segment, Command::Fpwr, kSm0Start, sm);
        break;
      case kReadSm1:
        transact(segment, Command::Fprd, kSm1Start, std::array<std::uint8_t, kMailboxBytes>{}, sm);
        break;
      case kToggleRepeat: {
        repeat ^= kSmRepeatRequest;
        const std::array<std::uint8_t, 1> act{static_cast<std::uint8_t>(kSmActivate | repeat)};
        transact(segment, Command::Fpwr, static_cast<std::uint16_t>(esc::reg::sync_manager(1) + esc::reg::sm::kActivate),
                 act);
        break;
      }
    }
    now += Nanoseconds{1000};
    clock.set(now);
    mailbox.poll(now);
  }
  return 0;
}
