#include "transport/pcap_file.hpp"

#include <pcap/pcap.h>

#include <utility>

namespace ecat::transport {

namespace {
constexpr int kSnapLength = 65535;
constexpr std::int64_t kNanosPerSecond = 1'000'000'000;
}  // namespace

Expected<PcapWriter, TransportError> PcapWriter::create(const std::string& path) {
  pcap* handle = ::pcap_open_dead_with_tstamp_precision(DLT_EN10MB, kSnapLength, PCAP_TSTAMP_PRECISION_NANO);
  if (handle == nullptr) return fail(TransportError::OpenFailed);
  pcap_dumper* dumper = ::pcap_dump_open(handle, path.c_str());
  if (dumper == nullptr) {
    ::pcap_close(handle);
    return fail(TransportError::OpenFailed);
  }
  return PcapWriter(handle, dumper);
}

PcapWriter::PcapWriter(PcapWriter&& o) noexcept
    : handle_(std::exchange(o.handle_, nullptr)),
      dumper_(std::exchange(o.dumper_, nullptr)),
      records_(o.records_) {}

PcapWriter& PcapWriter::operator=(PcapWriter&& o) noexcept {
  if (this != &o) {
    close();
    handle_ = std::exchange(o.handle_, nullptr);
    dumper_ = std::exchange(o.dumper_, nullptr);
    records_ = o.records_;
  }
  return *this;
}

PcapWriter::~PcapWriter() { close(); }

void PcapWriter::close() noexcept {
  if (dumper_ != nullptr) ::pcap_dump_close(dumper_);
  if (handle_ != nullptr) ::pcap_close(handle_);
  dumper_ = nullptr;
  handle_ = nullptr;
}

Expected<void, TransportError> PcapWriter::write(ConstBytes frame, Nanoseconds timestamp) {
  if (dumper_ == nullptr) return fail(TransportError::NotOpen);
  if (frame.size() > static_cast<std::size_t>(kSnapLength)) return fail(TransportError::FrameTooLarge);
  const std::int64_t ns = timestamp.count();
  pcap_pkthdr header{};
  header.ts.tv_sec = static_cast<time_t>(ns / kNanosPerSecond);
  // With nanosecond precision the "usec" field carries nanoseconds.
  header.ts.tv_usec = static_cast<suseconds_t>(ns % kNanosPerSecond);
  header.caplen = static_cast<bpf_u_int32>(frame.size());
  header.len = static_cast<bpf_u_int32>(frame.size());
  ::pcap_dump(reinterpret_cast<u_char*>(dumper_), &header, frame.data());
  ++records_;
  return {};
}

Expected<void, TransportError> PcapWriter::flush() noexcept {
  if (dumper_ == nullptr) return fail(TransportError::NotOpen);
  // pcap_dump() reports nothing: a short write shows in the flush or the
  // stream's error flag.
  if (::pcap_dump_flush(dumper_) != 0 || std::ferror(::pcap_dump_file(dumper_))) {
    return fail(TransportError::WriteFailed);
  }
  return {};
}

Expected<PcapReader, TransportError> PcapReader::open(const std::string& path) {
  char err[PCAP_ERRBUF_SIZE] = {};
  pcap* handle = ::pcap_open_offline_with_tstamp_precision(path.c_str(), PCAP_TSTAMP_PRECISION_NANO, err);
  if (handle == nullptr) return fail(TransportError::OpenFailed);
  if (::pcap_datalink(handle) != DLT_EN10MB) {
    ::pcap_close(handle);
    return fail(TransportError::InvalidFrame);
  }
  return PcapReader(handle);
}

PcapReader::PcapReader(PcapReader&& o) noexcept : handle_(std::exchange(o.handle_, nullptr)) {}

PcapReader& PcapReader::operator=(PcapReader&& o) noexcept {
  if (this != &o) {
    if (handle_ != nullptr) ::pcap_close(handle_);
    handle_ = std::exchange(o.handle_, nullptr);
  }
  return *this;
}

PcapReader::~PcapReader() {
  if (handle_ != nullptr) ::pcap_close(handle_);
}

Expected<PcapRecord, TransportError> PcapReader::next() {
  if (handle_ == nullptr) return fail(TransportError::NotOpen);
  pcap_pkthdr* header = nullptr;
  const u_char* data = nullptr;
  const int r = ::pcap_next_ex(handle_, &header, &data);
  if (r == PCAP_ERROR_BREAK) return fail(TransportError::EndOfFile);
  if (r != 1 || header == nullptr || data == nullptr) return fail(TransportError::InvalidFrame);
  PcapRecord rec;
  rec.timestamp = Nanoseconds{static_cast<std::int64_t>(header->ts.tv_sec) * kNanosPerSecond +
                              static_cast<std::int64_t>(header->ts.tv_usec)};
  rec.frame.assign(data, data + header->caplen);
  return rec;
}

Expected<void, TransportError> RecordingTransport::send(ConstBytes frame) {
  auto r = inner_.send(frame);
  if (r) (void)writer_.write(frame, clock_.now());
  return r;
}

Expected<std::size_t, TransportError> RecordingTransport::receive(Bytes buffer, Nanoseconds timeout) {
  auto r = inner_.receive(buffer, timeout);
  if (r) (void)writer_.write(buffer.first(*r), clock_.now());
  return r;
}

}  // namespace ecat::transport
