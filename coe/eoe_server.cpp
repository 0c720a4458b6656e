#include "coe/eoe_server.hpp"

#include <algorithm>
#include <cstring>
#include <new>

namespace ecat::coe {

using eoe::FrameType;
using eoe::Header;
using eoe::Result;

namespace {

constexpr std::size_t kFlagsSize = 4;       // UINT32 flags of Set/Get IP Parameter
constexpr std::size_t kIpSize = 4;
// Set IP Parameter with every field in place: flags, MAC, IP, subnet,
// gateway, DNS server, DNS name (ETG.1000.6 §5.7, 58 bytes).
constexpr std::size_t kFixedPlacesSize = kFlagsSize + eoe::kMacSize + 4 * kIpSize + eoe::kDnsNameSize;
constexpr std::size_t kFilterOptionsSize = 2;
constexpr std::uint8_t kFrameNumberMask = 0x0F;
constexpr std::uint8_t kFragmentNumberMask = 0x3F;

std::uint8_t type_of(FrameType t) noexcept { return static_cast<std::uint8_t>(t); }

std::size_t blocks(std::size_t bytes) noexcept { return (bytes + eoe::kBlock - 1) / eoe::kBlock; }

}  // namespace

Expected<std::size_t, MailboxError> EoeServer::handle(ConstBytes request, Bytes reply, od::EsmState state) noexcept {
  (void)state;
  const auto h = Header::unpack(request);
  if (!h) return fail(MailboxError::SizeTooShort);
  const ConstBytes body = request.subspan(eoe::kHeaderSize);
  switch (static_cast<FrameType>(h->type)) {
    case FrameType::FragmentData: fragment(*h, body); return std::size_t{0};
    case FrameType::SetIpRequest: return set_ip(*h, body, reply);
    case FrameType::GetIpRequest: return get_ip(*h, reply);
    case FrameType::SetAddressFilterRequest: return set_filter(*h, body, reply);
    case FrameType::GetAddressFilterRequest: return get_filter(*h, reply);
    default:
      // Response types and unknown ones: SSC answers "unsupported frame type"
      // in a Set IP Parameter response; so do we.
      ++stats_.bad_requests;
      return result(reply, FrameType::SetIpResponse, h->port, Result::UnsupportedFrameType);
  }
}

void EoeServer::drop_frame(std::uint64_t& counter) noexcept {
  ++counter;
  rx_active_ = false;
  rx_size_ = 0;
}

void EoeServer::fragment(const Header& h, ConstBytes data) noexcept {
  ++stats_.fragments_received;
  if (h.fragment == 0) {
    // A new frame: one still in progress lost its later fragments.
    if (rx_active_) drop_frame(stats_.dropped_sequence);
    rx_capacity_ = static_cast<std::size_t>(h.offset) * eoe::kBlock;
    if (rx_capacity_ == 0 || rx_capacity_ > eoe::kMaxFrame) return (void)++stats_.dropped_oversize;
    if (!has_buffers()) return (void)++stats_.dropped_no_memory;
    rx_active_ = true;
    rx_size_ = 0;
    rx_frame_ = h.frame;
    rx_fragment_ = 0;
  } else if (!rx_active_) {
    return (void)++stats_.dropped_sequence;  // a lost fragment 0, or the rest of a dropped frame
  } else if (h.fragment != rx_fragment_ || h.frame != rx_frame_ ||
             static_cast<std::size_t>(h.offset) * eoe::kBlock != rx_size_) {
    return drop_frame(stats_.dropped_sequence);
  }
  if (h.last_fragment && h.time_appended) {
    // The 32-bit time stamp follows the last fragment's data; not part of the frame.
    if (data.size() < eoe::kTimestampSize) return drop_frame(stats_.dropped_short);
    data = data.first(data.size() - eoe::kTimestampSize);
  }
  if (rx_size_ + data.size() > rx_capacity_) return drop_frame(stats_.dropped_oversize);
  if (!data.empty()) std::memcpy(buffers_->rx.data() + rx_size_, data.data(), data.size());
  rx_size_ += data.size();
  rx_fragment_ = static_cast<std::uint8_t>((rx_fragment_ + 1) & kFragmentNumberMask);
  if (!h.last_fragment) return;
  rx_active_ = false;
  if (rx_size_ < eoe::kMinFrame) return (void)++stats_.dropped_short;
  ++stats_.frames_received;
  if (port_) port_->receive({buffers_->rx.data(), rx_size_});
}

std::size_t EoeServer::result(Bytes reply, FrameType type, std::uint8_t port, Result r) noexcept {
  ByteWriter w(reply.first(eoe::kHeaderSize));
  w.u16(Header::word0(type_of(type), port, false));
  w.u16(static_cast<std::uint16_t>(r));
  return eoe::kHeaderSize;
}

std::size_t EoeServer::set_ip(const Header& h, ConstBytes body, Bytes reply) noexcept {
  if (body.size() < kFlagsSize) {
    ++stats_.bad_requests;
    return result(reply, FrameType::SetIpResponse, h.port, Result::UnspecifiedError);
  }
  ByteReader r(body);
  eoe::IpParameters p = ip_;
  const std::uint32_t flags = r.u32();
  // Two layouts are in use: the flagged fields packed one after another
  // (SOES reads them so, and older SOEM and the ENI InitCmds write them so),
  // or every field at its fixed place with only the valid ones flagged
  // (SOEM 2.x: "TwinCAT include empty entries"). A request as long as every
  // field together is read at the fixed places, which is also where a packed
  // request with every field flagged has them; any other length is packed.
  const bool fixed_places = body.size() == kFixedPlacesSize;
  auto need = [&](std::size_t n) { return r.remaining() >= n; };
  // A field that is not flagged is skipped at its fixed place, or absent.
  auto skip_unless = [&](std::uint32_t flag, std::size_t n) {
    if (fixed_places && !(flags & flag)) r.skip(n);
    return (flags & flag) != 0;
  };
  bool ok = true;
  if (skip_unless(eoe::kHasMac, eoe::kMacSize)) {
    ok = ok && need(eoe::kMacSize);
    if (ok) std::memcpy(p.mac.data(), r.bytes(eoe::kMacSize).data(), eoe::kMacSize);
  }
  const std::pair<std::uint32_t, std::uint32_t*> addresses[] = {
      {eoe::kHasIp, &p.ip}, {eoe::kHasSubnet, &p.subnet}, {eoe::kHasGateway, &p.gateway},
      {eoe::kHasDnsServer, &p.dns_server}};
  for (const auto& [flag, field] : addresses) {
    if (!ok || !skip_unless(flag, kIpSize)) continue;
    ok = need(kIpSize);
    if (ok) *field = r.u32();
  }
  if ((flags & eoe::kHasDnsName) && ok) {
    // TwinCAT and SOEM send all 32 characters; a shorter tail is taken as
    // the name up to the end of the request, zero-padded.
    const std::size_t n = std::min(r.remaining(), eoe::kDnsNameSize);
    ok = n > 0;
    p.dns_name.fill('\0');
    if (ok) std::memcpy(p.dns_name.data(), r.bytes(n).data(), n);
  }
  if (!ok) {
    ++stats_.bad_requests;
    return result(reply, FrameType::SetIpResponse, h.port, Result::UnspecifiedError);
  }
  p.flags = ip_.flags | (flags & (eoe::kHasMac | eoe::kHasIp | eoe::kHasSubnet | eoe::kHasGateway |
                                  eoe::kHasDnsServer | eoe::kHasDnsName));
  ip_ = p;
  return result(reply, FrameType::SetIpResponse, h.port, Result::Success);
}

std::size_t EoeServer::get_ip(const Header& h, Bytes reply) noexcept {
  constexpr std::size_t kFull = eoe::kHeaderSize + kFlagsSize + eoe::kMacSize + 4 * kIpSize + eoe::kDnsNameSize;
  if (reply.size() < kFull) return result(reply, FrameType::GetIpResponse, h.port, Result::UnspecifiedError);
  ByteWriter w(reply);
  w.u16(Header::word0(type_of(FrameType::GetIpResponse), h.port, false));
  w.u16(static_cast<std::uint16_t>(Result::Success));
  w.u32(ip_.flags);
  if (ip_.flags & eoe::kHasMac) w.bytes(ip_.mac);
  if (ip_.flags & eoe::kHasIp) w.u32(ip_.ip);
  if (ip_.flags & eoe::kHasSubnet) w.u32(ip_.subnet);
  if (ip_.flags & eoe::kHasGateway) w.u32(ip_.gateway);
  if (ip_.flags & eoe::kHasDnsServer) w.u32(ip_.dns_server);
  if (ip_.flags & eoe::kHasDnsName) {
    w.bytes({reinterpret_cast<const std::uint8_t*>(ip_.dns_name.data()), ip_.dns_name.size()});
  }
  return w.position();
}

std::size_t EoeServer::set_filter(const Header& h, ConstBytes body, Bytes reply) noexcept {
  if (body.size() < kFilterOptionsSize) {
    ++stats_.bad_requests;
    return result(reply, FrameType::SetAddressFilterResponse, h.port, Result::UnspecifiedError);
  }
  ByteReader r(body);
  eoe::AddressFilter f;
  f.set = true;
  f.options = r.u16();
  const std::size_t count = f.options & eoe::kFilterCountMask;
  const std::size_t masks = (f.options >> eoe::kMaskCountShift) & eoe::kMaskCountMask;
  // Filters are listed up to their count; the masks follow all 16 filter
  // slots when the request carries the full table, else right after.
  const std::size_t full = kFilterOptionsSize + eoe::kMaxMacFilters * eoe::kMacSize;
  const bool full_table = body.size() >= full + masks * eoe::kMacSize && masks > 0;
  if (r.remaining() < (count + masks) * eoe::kMacSize) {
    ++stats_.bad_requests;
    return result(reply, FrameType::SetAddressFilterResponse, h.port, Result::UnspecifiedError);
  }
  for (std::size_t i = 0; i < count; ++i) std::memcpy(f.filters[i].data(), r.bytes(eoe::kMacSize).data(), eoe::kMacSize);
  if (full_table) r = ByteReader(body.subspan(full));
  for (std::size_t i = 0; i < masks; ++i) std::memcpy(f.masks[i].data(), r.bytes(eoe::kMacSize).data(), eoe::kMacSize);
  filter_ = f;
  return result(reply, FrameType::SetAddressFilterResponse, h.port, Result::Success);
}

std::size_t EoeServer::get_filter(const Header& h, Bytes reply) noexcept {
  const std::size_t count = filter_.options & eoe::kFilterCountMask;
  const std::size_t masks = (filter_.options >> eoe::kMaskCountShift) & eoe::kMaskCountMask;
  const std::size_t n = eoe::kHeaderSize + kFilterOptionsSize + (count + masks) * eoe::kMacSize;
  if (reply.size() < n) return result(reply, FrameType::GetAddressFilterResponse, h.port, Result::UnspecifiedError);
  ByteWriter w(reply);
  w.u16(Header::word0(type_of(FrameType::GetAddressFilterResponse), h.port, false));
  w.u16(static_cast<std::uint16_t>(Result::Success));
  w.u16(filter_.options);
  for (std::size_t i = 0; i < count; ++i) w.bytes(filter_.filters[i]);
  for (std::size_t i = 0; i < masks; ++i) w.bytes(filter_.masks[i]);
  return w.position();
}

bool EoeServer::passes_filter(ConstBytes frame) const noexcept {
  if (!filter_.set) return true;
  const ConstBytes dest = frame.first(eoe::kMacSize);
  if (std::all_of(dest.begin(), dest.end(), [](std::uint8_t b) { return b == 0xFF; })) {
    return !(filter_.options & eoe::kNoBroadcasts);
  }
  if ((ip_.flags & eoe::kHasMac) && std::equal(dest.begin(), dest.end(), ip_.mac.begin())) return true;
  const std::size_t count = filter_.options & eoe::kFilterCountMask;
  const std::size_t masks = (filter_.options >> eoe::kMaskCountShift) & eoe::kMaskCountMask;
  for (std::size_t i = 0; i < count; ++i) {
    if (std::equal(dest.begin(), dest.end(), filter_.filters[i].begin())) return true;
    for (std::size_t m = 0; m < masks; ++m) {
      bool match = true;
      for (std::size_t b = 0; b < eoe::kMacSize; ++b) {
        match = match && (dest[b] & filter_.masks[m][b]) == (filter_.filters[i][b] & filter_.masks[m][b]);
      }
      if (match) return true;
    }
  }
  return false;
}

// Default-initialised (not zeroed): only the bytes a frame wrote are read,
// so the pages stay untouched until a frame comes.
bool EoeServer::has_buffers() noexcept {
  if (!buffers_) buffers_.reset(new (std::nothrow) Buffers);
  return buffers_ != nullptr;
}

bool EoeServer::transmit(ConstBytes frame) noexcept {
  if (frame.size() < eoe::kMinFrame) return ++stats_.dropped_short, false;
  if (frame.size() > eoe::kMaxFrame) return ++stats_.dropped_oversize, false;
  if (!passes_filter(frame)) return ++stats_.dropped_filtered, false;
  if (tx_count_ == eoe::kTxFrames) return ++stats_.dropped_tx_full, false;
  if (!has_buffers()) return ++stats_.dropped_no_memory, false;
  const std::size_t slot = (tx_head_ + tx_count_) % eoe::kTxFrames;
  std::memcpy(buffers_->tx[slot].data(), frame.data(), frame.size());
  tx_length_[slot] = frame.size();
  ++tx_count_;
  return true;
}

// One fragment of the front frame into `out` (SM1 room after the mailbox
// header): as much as fits, every fragment but the last a multiple of 32.
std::size_t EoeServer::next_output(Bytes out) noexcept {
  if (tx_count_ == 0 || out.size() < eoe::kHeaderSize + eoe::kBlock) return 0;
  const std::size_t length = tx_length_[tx_head_];
  const std::size_t room = out.size() - eoe::kHeaderSize;
  const std::size_t left = length - tx_offset_;
  const bool last = left <= room;
  const std::size_t n = last ? left : room / eoe::kBlock * eoe::kBlock;
  if (tx_fragment_ == 0) tx_frame_ = static_cast<std::uint8_t>((tx_frame_ + 1) & kFrameNumberMask);
  const std::size_t offset = tx_fragment_ == 0 ? blocks(length) : tx_offset_ / eoe::kBlock;
  ByteWriter w(out);
  w.u16(Header::word0(type_of(FrameType::FragmentData), 0, last));
  w.u16(Header::word1(tx_fragment_, static_cast<std::uint8_t>(offset), tx_frame_));
  w.bytes({buffers_->tx[tx_head_].data() + tx_offset_, n});
  ++stats_.fragments_sent;
  if (last) {
    ++stats_.frames_sent;
    tx_head_ = (tx_head_ + 1) % eoe::kTxFrames;
    --tx_count_;
    tx_offset_ = 0;
    tx_fragment_ = 0;
  } else {
    tx_offset_ += n;
    tx_fragment_ = static_cast<std::uint8_t>((tx_fragment_ + 1) & kFragmentNumberMask);
  }
  return eoe::kHeaderSize + n;
}

void EoeServer::reset() noexcept {
  rx_active_ = false;
  rx_size_ = 0;
  tx_count_ = 0;
  tx_offset_ = 0;
  tx_fragment_ = 0;
}

}  // namespace ecat::coe
