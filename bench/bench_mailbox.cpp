// Mailbox throughput in-process (issue 8 item 1): CPU time per SDO
// expedited transaction and MB/s of a segmented upload of 1 MiB. Everything
// is real except the wire: a master-side loop writes the request into SM0 by
// FPWR and reads the reply from SM1 by FPRD through esc::Segment, the
// firmware side is coe::MailboxServer + CoeProtocol + SdoServer over the
// Esc's PDI, with the built-in generic servo dictionary plus a 1 MiB octet
// string at 2100h. Mailbox size is the argument (128 bytes as the seed
// devices, 1024 as a large-mailbox device); the master always writes and
// reads the whole SM, as SOEM and IgH do.
#include <benchmark/benchmark.h>

#include <cstring>
#include <stdexcept>

#include "bench/bench_options.hpp"
#include "bench/mini_master.hpp"
#include "coe/coe_protocol.hpp"
#include "coe/mailbox_server.hpp"
#include "coe/object_store.hpp"
#include "coe/sdo_info.hpp"
#include "coe/sdo_server.hpp"
#include "esi/device_loader.hpp"

namespace ecat::bench {
namespace {

constexpr std::uint16_t kSm0Start = 0x1000;
constexpr std::uint16_t kSm1Start = 0x1800;
constexpr std::uint8_t kSm0Control = 0x26;  // mailbox, ECAT writes (ETG.1000.4 §6.7.2)
constexpr std::uint8_t kSm1Control = 0x22;  // mailbox, ECAT reads
constexpr std::uint16_t kBlobIndex = 0x2100;
constexpr std::uint32_t kBlobBytes = 1u << 20;
constexpr std::size_t kMailboxHeader = 6;
constexpr std::uint8_t kTypeCoe = 3;
constexpr std::size_t kCoeHeader = 2;
constexpr std::uint8_t kCoeServiceSdoRequest = 0x20;  // service 2 in bits 15:12 (high byte)
// SDO command bytes (CiA 301 §7.2.4.3; coe-mailbox.md §5).
constexpr std::uint8_t kInitiateUpload = 0x40;
constexpr std::uint8_t kUploadSegment = 0x60;
constexpr std::uint8_t kToggle = 0x10;
constexpr std::uint8_t kLastSegment = 0x01;
constexpr std::uint8_t kAbort = 0x80;
constexpr std::size_t kSdoHeader = 8;          // cmd, index, sub, 4 data bytes
constexpr std::size_t kSegmentOverhead = 3;    // CoE header + cmd byte
constexpr std::size_t kMinSegmentData = 7;

od::DeviceDescription make_device() {
  auto d = esi::load_default_device();
  if (!d) throw std::runtime_error(d.error().to_string());
  od::Object blob;
  blob.index = kBlobIndex;
  blob.name = "Benchmark blob";
  blob.type = od::DataType::OctetString;
  od::Entry e;
  e.name = blob.name;
  e.type = od::DataType::OctetString;
  e.bit_length = 0;  // variable: capacity from ObjectStore::Options
  e.access.bits = od::Access::kRo;
  blob.entries.push_back(e);
  if (auto r = d->dictionary.put(blob); !r) throw std::runtime_error(r.error());
  return std::move(*d);
}

// One slave: ESC + mailbox firmware, and the master's two reusable frames.
struct MailboxRig {
  explicit MailboxRig(std::uint16_t mailbox_bytes)
      : size(mailbox_bytes),
        line(1),
        device(make_device()),
        store(device.dictionary, coe::ObjectStore::Options{kBlobBytes}),
        sdo(store),
        info(store),
        coe(sdo, &info),
        mailbox(*line.escs[0], mailbox_bytes) {
    config_sm(line.segment, station(0), 0, kSm0Start, size, kSm0Control);
    config_sm(line.segment, station(0), 1, kSm1Start, size, kSm1Control);
    line.escs[0]->write_u8(esc::reg::kAlStatus, static_cast<std::uint8_t>(od::EsmState::PreOp));
    mailbox.add_service(coe);
    Data blob(kBlobBytes);
    for (std::size_t i = 0; i < blob.size(); ++i) blob[i] = static_cast<std::uint8_t>(i * 7);
    if (!store.assign(kBlobIndex, 0, blob)) throw std::runtime_error("blob assign");
    write.add(Command::Fpwr, device_address(station(0), kSm0Start), size);
    write.finish();
    read.add(Command::Fprd, device_address(station(0), kSm1Start), size);
    read.finish();
    mailbox.poll(now);
  }

  // Request payload (CoE header onwards) -> reply payload view; empty if none.
  std::span<const std::uint8_t> transact(std::span<const std::uint8_t> coe_request) {
    auto w = write.dg(0).data();
    store_le(w.data(), static_cast<std::uint16_t>(coe_request.size()));
    store_le(w.data() + 2, std::uint16_t{0});
    w[4] = 0;
    counter = static_cast<std::uint8_t>(counter % 7 + 1);
    w[5] = static_cast<std::uint8_t>(kTypeCoe | (counter << 4));
    std::memcpy(w.data() + kMailboxHeader, coe_request.data(), coe_request.size());
    now += Nanoseconds{1000};
    line.segment.process_frame(write.bytes(), now);
    mailbox.poll(now);
    const std::uint16_t wkc = read.wkc(0);
    line.segment.process_frame(read.bytes(), now);
    mailbox.poll(now);
    if (read.wkc(0) == wkc) return {};  // SM1 was empty
    auto r = read.dg(0).data();
    const std::size_t len = load_le<std::uint16_t>(r.data());
    return r.subspan(kMailboxHeader, std::min(len, r.size() - kMailboxHeader));
  }

  std::uint16_t size;
  EscLine line;
  od::DeviceDescription device;
  coe::ObjectStore store;
  coe::SdoServer sdo;
  coe::SdoInfo info;
  coe::CoeProtocol coe;
  coe::MailboxServer mailbox;
  Frame write;
  Frame read;
  Nanoseconds now{0};
  std::uint8_t counter = 0;
};

std::array<std::uint8_t, kCoeHeader + kSdoHeader> sdo_request(std::uint8_t cmd, std::uint16_t index,
                                                              std::uint8_t sub) {
  return {0x00, kCoeServiceSdoRequest, cmd, static_cast<std::uint8_t>(index), static_cast<std::uint8_t>(index >> 8),
          sub, 0, 0, 0, 0};
}

// Expedited upload of the vendor id (1018h:01, 4 bytes): one request, one reply.
void BM_Mailbox_SdoExpeditedUpload(benchmark::State& state) {
  MailboxRig rig(static_cast<std::uint16_t>(state.range(0)));
  const auto req = sdo_request(kInitiateUpload, 0x1018, 1);
  auto first = rig.transact(req);
  if (first.size() < kCoeHeader + kSdoHeader || (first[kCoeHeader] & kAbort) == kAbort) {
    state.SkipWithError("no expedited upload reply");
    return;
  }
  for (auto _ : state) benchmark::DoNotOptimize(rig.transact(req).data());
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations()));
}
BENCHMARK(BM_Mailbox_SdoExpeditedUpload)->Arg(128)->Arg(1024)->Apply(ecat::bench::iterations_from_env);

// Expedited download of the mode of operation (6060h, 1 byte = CSP).
void BM_Mailbox_SdoExpeditedDownload(benchmark::State& state) {
  MailboxRig rig(static_cast<std::uint16_t>(state.range(0)));
  constexpr std::uint8_t kDownload1Byte = 0x2F;
  constexpr std::uint8_t kCsp = 8;
  auto req = sdo_request(kDownload1Byte, 0x6060, 0);
  req[kCoeHeader + 4] = kCsp;
  auto first = rig.transact(req);
  if (first.size() < kCoeHeader + kSdoHeader || first[kCoeHeader] != 0x60) {
    state.SkipWithError("download refused");
    return;
  }
  for (auto _ : state) benchmark::DoNotOptimize(rig.transact(req).data());
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations()));
}
BENCHMARK(BM_Mailbox_SdoExpeditedDownload)->Arg(128)->Arg(1024)->Apply(ecat::bench::iterations_from_env);

// Segmented upload of the whole 1 MiB blob; returns the bytes received.
std::size_t upload_blob(MailboxRig& rig) {
  auto reply = rig.transact(sdo_request(kInitiateUpload, kBlobIndex, 0));
  if (reply.size() < kCoeHeader + kSdoHeader || (reply[kCoeHeader] & kAbort) == kAbort) return 0;
  std::size_t got = reply.size() - kCoeHeader - kSdoHeader;
  std::uint8_t toggle = 0;
  std::array<std::uint8_t, kCoeHeader + kSdoHeader> seg{0x00, kCoeServiceSdoRequest, 0, 0, 0, 0, 0, 0, 0, 0};
  for (;;) {
    seg[kCoeHeader] = static_cast<std::uint8_t>(kUploadSegment | toggle);
    reply = rig.transact(seg);
    if (reply.size() < kSegmentOverhead + kMinSegmentData || (reply[kCoeHeader] & kAbort) == kAbort) return 0;
    const std::uint8_t cmd = reply[kCoeHeader];
    std::size_t n = reply.size() - kSegmentOverhead;
    if (n == kMinSegmentData) n -= (cmd >> 1) & 0x07;  // unused bytes of a short segment
    got += n;
    if (cmd & kLastSegment) return got;
    toggle ^= kToggle;
  }
}

void BM_Mailbox_SegmentedUpload1MiB(benchmark::State& state) {
  MailboxRig rig(static_cast<std::uint16_t>(state.range(0)));
  if (upload_blob(rig) != kBlobBytes) {
    state.SkipWithError("upload incomplete");
    return;
  }
  for (auto _ : state) benchmark::DoNotOptimize(upload_blob(rig));
  state.SetBytesProcessed(static_cast<std::int64_t>(state.iterations()) * kBlobBytes);
}
BENCHMARK(BM_Mailbox_SegmentedUpload1MiB)->Arg(128)->Arg(1024)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace ecat::bench

BENCHMARK_MAIN();
