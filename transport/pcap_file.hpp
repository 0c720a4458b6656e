// Capture files through libpcap: Ethernet link type (DLT_EN10MB), nanosecond
// timestamps kept on write and read (files are written with nanosecond
// resolution; microsecond files are scaled on read). Used to record what a
// master or slave saw and to replay captures in tests (STYLE lesson 12).
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "transport/transport.hpp"

struct pcap;
struct pcap_dumper;

namespace ecat::transport {

struct PcapRecord {
  Nanoseconds timestamp{0};  // since the Unix epoch, as stored in the file
  std::vector<std::uint8_t> frame;
};

class PcapWriter {
 public:
  static Expected<PcapWriter, TransportError> create(const std::string& path);
  PcapWriter(PcapWriter&&) noexcept;
  PcapWriter& operator=(PcapWriter&&) noexcept;
  ~PcapWriter();

  Expected<void, TransportError> write(ConstBytes frame, Nanoseconds timestamp);
  // Writes what is buffered; WriteFailed when any write came up short.
  Expected<void, TransportError> flush() noexcept;
  std::size_t records() const noexcept { return records_; }

 private:
  PcapWriter(pcap* handle, pcap_dumper* dumper) noexcept : handle_(handle), dumper_(dumper) {}
  void close() noexcept;

  pcap* handle_ = nullptr;
  pcap_dumper* dumper_ = nullptr;
  std::size_t records_ = 0;
};

class PcapReader {
 public:
  static Expected<PcapReader, TransportError> open(const std::string& path);
  PcapReader(PcapReader&&) noexcept;
  PcapReader& operator=(PcapReader&&) noexcept;
  ~PcapReader();

  // The next record, or EndOfFile / InvalidFrame (not DLT_EN10MB, corrupt file).
  Expected<PcapRecord, TransportError> next();

 private:
  explicit PcapReader(pcap* handle) noexcept : handle_(handle) {}

  pcap* handle_ = nullptr;
};

// Decorator: a Transport that writes every frame it sends or receives to a
// PcapWriter, stamped with the given clock (for --pcap options of programs).
class RecordingTransport final : public Transport {
 public:
  RecordingTransport(Transport& inner, PcapWriter& writer, const Clock& clock) noexcept
      : inner_(inner), writer_(writer), clock_(clock) {}
  Expected<void, TransportError> send(ConstBytes frame) override;
  Expected<std::size_t, TransportError> receive(Bytes buffer, Nanoseconds timeout) override;

 private:
  Transport& inner_;
  PcapWriter& writer_;
  const Clock& clock_;
};

}  // namespace ecat::transport
