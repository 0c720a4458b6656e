#include <cstdio>

#include <fmt/format.h>

#include "apps/ecat-slave/chain_setup.hpp"
#include "apps/ecat-slave/runners.hpp"
#include "transport/pcap_file.hpp"

namespace ecat::app {

// Replays a master's capture: the frames it sent (its own, unprocessed ones;
// frames already processed by a slave carry the ESC mark in the source MAC
// and are skipped), each processed by the chain at its recorded time and
// written as the segment returns it, with the same timestamp.
int run_pcap(const SlaveProgramOptions& o, std::vector<od::DeviceDescription> devices) {
  auto reader = transport::PcapReader::open(o.pcap_in);
  if (!reader) {
    std::fprintf(stderr, "ecat-slave: %s: %s\n", o.pcap_in.c_str(),
                 std::string(transport::describe(reader.error())).c_str());
    return 1;
  }
  auto writer = transport::PcapWriter::create(o.pcap_out);
  if (!writer) {
    std::fprintf(stderr, "ecat-slave: %s: %s\n", o.pcap_out.c_str(),
                 std::string(transport::describe(writer.error())).c_str());
    return 1;
  }
  ManualClock clock;
  auto chain = make_chain(o, std::move(devices), clock);
  if (!chain) {
    std::fprintf(stderr, "ecat-slave: %s\n", chain.error().c_str());
    return 1;
  }
  slave::Chain& line = **chain;
  if (auto ok = start_firmware_threads(line, o); !ok) {
    std::fprintf(stderr, "ecat-slave: %s\n", ok.error().c_str());
    return 1;
  }
  std::size_t skipped = 0;
  for (;;) {
    auto rec = reader->next();
    if (!rec) {
      if (rec.error() == transport::TransportError::EndOfFile) break;
      std::fprintf(stderr, "ecat-slave: %s: %s\n", o.pcap_in.c_str(),
                   std::string(transport::describe(rec.error())).c_str());
      return 1;
    }
    auto& frame = rec->frame;
    if (frame.size() > kEthernetHeaderSize && (frame[kMacSize] & kSourceMacProcessedBit) != 0) {
      ++skipped;  // a reply in the capture, not a master frame
      continue;
    }
    if (rec->timestamp > clock.now()) clock.set(rec->timestamp);
    line.poll(clock.now());
    if (line.process_frame(frame, clock.now())) {
      if (auto w = writer->write(frame, rec->timestamp); !w) {
        std::fprintf(stderr, "ecat-slave: %s: %s\n", o.pcap_out.c_str(),
                     std::string(transport::describe(w.error())).c_str());
        return 1;
      }
    }
  }
  if (auto w = writer->flush(); !w) {
    std::fprintf(stderr, "ecat-slave: %s: %s\n", o.pcap_out.c_str(), std::string(transport::describe(w.error())).c_str());
    return 1;
  }
  if (auto ok = line.shutdown(); !ok) {
    std::fprintf(stderr, "ecat-slave: %s\n", ok.error().c_str());
    return 1;
  }
  if (!o.quiet) {
    std::fprintf(stderr, "ecat-slave: replayed %s -> %s (%zu replies in the capture skipped)\n%s",
                 o.pcap_in.c_str(), o.pcap_out.c_str(), skipped, format_stats(line).c_str());
  }
  return 0;
}

}  // namespace ecat::app
