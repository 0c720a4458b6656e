// Writes the seed corpora of the fuzz targets into fuzz/corpus/<target>/:
// frame sequences a master sends from scan to Op, mailbox sessions (SDO,
// SDO information, FoE - also with bad names), SII images and ESI files made
// from every shipped device, and the shipped device files themselves.
// Run by scripts/fuzz --seed; the output is committed.
//   fuzz_corpus_gen <repo root>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <string>
#include <vector>

#include "common/frame_builder.hpp"
#include "esc/registers.hpp"
#include "esi/device_loader.hpp"
#include "esi/esi_writer.hpp"
#include "esi/sii_writer.hpp"

namespace fs = std::filesystem;
using namespace ecat;
using Bytes8 = std::vector<std::uint8_t>;

namespace {

constexpr std::uint16_t kStation = 0x1001;

void put16(Bytes8& v, std::uint16_t x) {
  v.push_back(static_cast<std::uint8_t>(x));
  v.push_back(static_cast<std::uint8_t>(x >> 8));
}
void put32(Bytes8& v, std::uint32_t x) {
  put16(v, static_cast<std::uint16_t>(x));
  put16(v, static_cast<std::uint16_t>(x >> 16));
}
// Appends one record ([u16 length][bytes], fuzz_input.hpp).
void record(Bytes8& out, const Bytes8& r) {
  put16(out, static_cast<std::uint16_t>(r.size()));
  out.insert(out.end(), r.begin(), r.end());
}

struct Dg {
  Command cmd;
  std::uint32_t address;
  Bytes8 data;
};

Bytes8 frame(const std::vector<Dg>& dgs, bool vlan = false) {
  Bytes8 buf(1600);
  FrameBuilder b(buf);
  std::uint8_t index = 0;
  for (const auto& d : dgs) (void)b.append(d.cmd, index++, d.address, d.data);
  auto f = b.finish();
  Bytes8 out(f.begin(), f.end());
  if (vlan) {
    const Bytes8 tag{0x81, 0x00, 0x00, 0x05};
    out.insert(out.begin() + 2 * kMacSize, tag.begin(), tag.end());
  }
  return out;
}
std::uint32_t fp(std::uint16_t ado) { return device_address(kStation, ado); }
std::uint32_t ap(std::uint16_t pos, std::uint16_t ado) { return device_address(auto_increment_adp(pos), ado); }
Bytes8 le16(std::uint16_t v) { Bytes8 b; put16(b, v); return b; }
Bytes8 le32(std::uint32_t v) { Bytes8 b; put32(b, v); return b; }
Bytes8 zeros(std::size_t n) { return Bytes8(n, 0); }
Bytes8 sm(std::uint16_t start, std::uint16_t len, std::uint8_t control) {
  Bytes8 b;
  put16(b, start);
  put16(b, len);
  b.push_back(control);
  b.push_back(0);
  b.push_back(1);
  b.push_back(0);
  return b;
}
Bytes8 fmmu(std::uint32_t logical, std::uint16_t len, std::uint16_t physical, std::uint8_t type,
            std::uint8_t start_bit = 0, std::uint8_t stop_bit = 7) {
  Bytes8 b;
  put32(b, logical);
  put16(b, len);
  b.push_back(start_bit);
  b.push_back(stop_bit);
  put16(b, physical);
  b.push_back(0);
  b.push_back(type);
  b.push_back(1);
  b.resize(16, 0);
  return b;
}

void write_file(const fs::path& p, const Bytes8& b) {
  std::ofstream(p, std::ios::binary).write(reinterpret_cast<const char*>(b.data()), static_cast<std::streamsize>(b.size()));
}
void write_text(const fs::path& p, const std::string& s) { std::ofstream(p, std::ios::binary) << s; }

void frames(const fs::path& dir) {
  using esc::reg::sync_manager;
  namespace r = esc::reg;
  auto seq = [&](const std::string& name, const std::vector<Bytes8>& fs_) {
    Bytes8 out;
    for (const auto& f : fs_) record(out, f);
    write_file(dir / name, out);
  };
  // Scan as SOEM/IgH do: count, addresses, identity from the SII.
  seq("scan", {frame({{Command::Brd, device_address(0, r::kType), zeros(2)}}),
               frame({{Command::Apwr, ap(0, r::kConfiguredStationAddress), le16(kStation)},
                      {Command::Apwr, ap(1, r::kConfiguredStationAddress), le16(kStation + 1)}}),
               frame({{Command::Fprd, fp(r::kAlStatus), zeros(2)}, {Command::Fprd, fp(r::kDlStatus), zeros(2)}}),
               frame({{Command::Fpwr, fp(r::kEepromControlStatus), Bytes8{0x00, 0x01, 0x08, 0x00, 0, 0}}}),
               frame({{Command::Fprd, fp(r::kEepromControlStatus), zeros(2)}, {Command::Fprd, fp(r::kEepromData), zeros(8)}})});
  // Init -> PreOp -> SafeOp -> Op with mailbox and process-data SMs and FMMUs.
  seq("bring_up", {frame({{Command::Apwr, ap(0, r::kConfiguredStationAddress), le16(kStation)}}),
                   frame({{Command::Fpwr, fp(sync_manager(0)), sm(0x1000, 128, 0x26)},
                          {Command::Fpwr, fp(sync_manager(1)), sm(0x1080, 128, 0x22)}}),
                   frame({{Command::Fpwr, fp(r::kAlControl), le16(2)}}),
                   frame({{Command::Fpwr, fp(sync_manager(2)), sm(0x1100, 14, 0x64)},
                          {Command::Fpwr, fp(sync_manager(3)), sm(0x1400, 16, 0x20)},
                          {Command::Fpwr, fp(r::fmmu(0)), fmmu(0, 14, 0x1100, 2)},
                          {Command::Fpwr, fp(r::fmmu(1)), fmmu(14, 16, 0x1400, 1)},
                          {Command::Fpwr, fp(r::fmmu(2)), fmmu(0x9000, 1, 0x080D, 1, 0, 0)}}),
                   frame({{Command::Fpwr, fp(r::kAlControl), le16(4)}}),
                   frame({{Command::Lrw, 0, zeros(30)}, {Command::Armw, ap(0, r::kDcBase + 0x10), zeros(8)},
                          {Command::Brd, device_address(0, r::kAlStatus), zeros(2)}}),
                   frame({{Command::Fpwr, fp(r::kAlControl), le16(8)}}),
                   frame({{Command::Lrd, 0x9000, zeros(1)}, {Command::Lwr, 0, zeros(14)}})});
  // DC set-up: latch receive times, read them, offset, delay, SYNC0 activation.
  seq("dc", {frame({{Command::Bwr, device_address(0, r::kDcBase), zeros(4)}}),
             frame({{Command::Fprd, fp(r::kDcBase), zeros(16)}, {Command::Fprd, fp(r::kDcBase + 0x18), zeros(8)}}),
             frame({{Command::Fpwr, fp(r::kDcBase + 0x20), zeros(8)}, {Command::Fpwr, fp(r::kDcBase + 0x28), le32(500)}}),
             frame({{Command::Frmw, fp(r::kDcBase + 0x10), zeros(8)}}),
             frame({{Command::Fpwr, fp(r::kDcBase + 0xA0), le32(1000000)},
                    {Command::Fpwr, fp(r::kDcBase + 0x90), zeros(8)},
                    {Command::Fpwr, fp(r::kDcBase + 0x81), Bytes8{0x03}}})});
  // Watchdog, write protection, ESC reset sequence, all commands once.
  seq("registers", {frame({{Command::Fpwr, fp(r::kWatchdogTimeProcessData), le16(10)},
                           {Command::Fpwr, fp(r::kRegisterWriteEnable), Bytes8{1}},
                           {Command::Fpwr, fp(r::kEscResetEcat), Bytes8{'R'}},
                           {Command::Fpwr, fp(r::kEscResetEcat), Bytes8{'E'}},
                           {Command::Fpwr, fp(r::kEscResetEcat), Bytes8{'S'}}}),
                    frame({{Command::Nop, 0, zeros(2)}, {Command::Aprd, ap(0, 0), zeros(4)},
                           {Command::Aprw, ap(0, 0x1800), zeros(4)}, {Command::Fprw, fp(0x1800), zeros(4)},
                           {Command::Brw, device_address(0, 0x1800), zeros(4)}, {Command::Bwr, device_address(0, 0x1800), zeros(4)}}),
                    frame({{Command::Fprd, fp(r::kAlStatus), zeros(2)}}, true)});
  // One full-size LRW over a bit-granular FMMU.
  seq("lrw_bits", {frame({{Command::Apwr, ap(0, r::kConfiguredStationAddress), le16(kStation)},
                          {Command::Fpwr, fp(r::fmmu(0)), fmmu(0x10, 2, 0x1800, 3, 3, 4)}}),
                   frame({{Command::Lrw, 0x10, zeros(1486)}})});
}

// Mailbox sessions: first byte = ESM state selector, then records with op 0
// (write SM0), 1 (read SM1), 2 (toggle repeat).
Bytes8 mbx(std::uint8_t type, std::uint8_t counter, const Bytes8& payload) {
  Bytes8 f{0};
  put16(f, static_cast<std::uint16_t>(payload.size()));
  put16(f, 0);
  f.push_back(0);
  f.push_back(static_cast<std::uint8_t>(type | (counter << 4)));
  f.insert(f.end(), payload.begin(), payload.end());
  return f;
}
Bytes8 sdo(std::uint8_t cmd, std::uint16_t index, std::uint8_t sub, std::uint32_t data = 0) {
  Bytes8 f{0x00, 0x20, cmd};
  put16(f, index);
  f.push_back(sub);
  put32(f, data);
  return f;
}
Bytes8 info(std::uint8_t opcode, const Bytes8& rest) {
  Bytes8 f{0x00, 0x80, opcode, 0};
  put16(f, 0);
  f.insert(f.end(), rest.begin(), rest.end());
  return f;
}
Bytes8 foe(std::uint8_t opcode, std::uint32_t arg, const std::string& text) {
  Bytes8 f{opcode, 0};
  put32(f, arg);
  f.insert(f.end(), text.begin(), text.end());
  return f;
}

void mailboxes(const fs::path& dir) {
  constexpr std::uint8_t kCoe = 3, kFoe = 4;
  const Bytes8 read{1};
  const Bytes8 toggle{2};
  auto session = [&](const std::string& name, std::uint8_t state, const std::vector<Bytes8>& ops) {
    Bytes8 out{state};
    for (const auto& o : ops) record(out, o);
    write_file(dir / name, out);
  };
  session("sdo_expedited", 0, {mbx(kCoe, 1, sdo(0x40, 0x1000, 0)), read, mbx(kCoe, 2, sdo(0x2F, 0x6060, 0, 8)), read,
                               mbx(kCoe, 3, sdo(0x23, 0x607A, 0, 1000)), read, mbx(kCoe, 3, sdo(0x23, 0x607A, 0, 1000)), read});
  session("sdo_segmented", 0, {mbx(kCoe, 1, sdo(0x40, 0x1008, 0)), read, mbx(kCoe, 2, sdo(0x60, 0, 0)), read,
                               mbx(kCoe, 3, sdo(0x70, 0, 0)), read, toggle, read});
  session("sdo_complete_access", 0, {mbx(kCoe, 1, sdo(0x50, 0x1018, 0)), read, mbx(kCoe, 2, sdo(0x51, 0x1C12, 1)), read});
  Bytes8 seg_download = sdo(0x21, 0x1008, 0, 20);
  session("sdo_download_segments", 0, {mbx(kCoe, 1, seg_download), read,
                                       mbx(kCoe, 2, Bytes8{0x00, 0x20, 0x00, 'a', 'b', 'c', 'd', 'e', 'f', 'g'}), read,
                                       mbx(kCoe, 3, sdo(0x80, 0x1008, 0, 0x06040043)), read});
  Bytes8 list;
  put16(list, 1);
  Bytes8 object;
  put16(object, 0x1018);
  Bytes8 entry = object;
  entry.push_back(1);
  entry.push_back(0x7F);
  session("sdo_info", 1, {mbx(kCoe, 1, info(1, list)), read, read, read, mbx(kCoe, 2, info(3, object)), read,
                          mbx(kCoe, 3, info(5, entry)), read});
  session("foe", 3, {mbx(kFoe, 1, foe(2, 0, "fw.bin")), read, mbx(kFoe, 2, foe(3, 1, "hello")), read,
                     mbx(kFoe, 3, foe(1, 0, "fw.bin")), read, mbx(kFoe, 4, foe(4, 1, "")), read,
                     mbx(kFoe, 5, foe(1, 0, "../etc/passwd")), read, mbx(kFoe, 6, foe(2, 0, "a/b")), read});
  session("mailbox_errors", 2, {mbx(0x7, 1, Bytes8{1, 2, 3}), read, mbx(kCoe, 0, Bytes8{}), read,
                                mbx(kCoe, 1, Bytes8{0x00, 0x10}), read});
}

}  // namespace

int main(int argc, char** argv) {
  const fs::path root = argc > 1 ? argv[1] : ECAT_SOURCE_DIR;
  const fs::path corpus = root / "fuzz" / "corpus";
  for (const char* t : {"fuzz_frame", "fuzz_mailbox", "fuzz_sii", "fuzz_device_xml", "fuzz_esi"}) {
    fs::create_directories(corpus / t);
  }
  frames(corpus / "fuzz_frame");
  mailboxes(corpus / "fuzz_mailbox");
  int failures = 0;
  for (const auto& e : fs::directory_iterator(root / "xml" / "devices")) {
    if (e.path().extension() != ".xml") continue;
    const std::string stem = e.path().stem().string();
    fs::copy_file(e.path(), corpus / "fuzz_device_xml" / e.path().filename(), fs::copy_options::overwrite_existing);
    auto dev = esi::load_device_file(e.path());
    if (!dev) {
      std::cerr << dev.error().to_string() << '\n';
      ++failures;
      continue;
    }
    if (auto sii = esi::write_sii(*dev)) write_file(corpus / "fuzz_sii" / (stem + ".bin"), *sii);
    write_text(corpus / "fuzz_esi" / (stem + ".xml"), esi::write_esi(*dev));
  }
  for (const auto& e : fs::directory_iterator(root / "tests" / "data" / "devices")) {
    fs::copy_file(e.path(), corpus / "fuzz_device_xml" / ("test-" + e.path().filename().string()),
                  fs::copy_options::overwrite_existing);
  }
  for (const auto& e : fs::directory_iterator(root / "tests" / "data" / "esi")) {
    fs::copy_file(e.path(), corpus / "fuzz_esi" / e.path().filename(), fs::copy_options::overwrite_existing);
  }
  return failures == 0 ? 0 : 1;
}
