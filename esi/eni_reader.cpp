#include "esi/eni_reader.hpp"

#include <algorithm>
#include <cctype>
#include <fstream>
#include <limits>
#include <span>
#include <sstream>
#include <utility>

#include <fmt/format.h>
#include <pugixml.hpp>

#include "esi/device_failure.hpp"
#include "esi/device_values.hpp"
#include "esi/esi_reader_context.hpp"
#include "esi/esi_writer_names.hpp"

namespace ecat::esi {
namespace {

// ETG.2100: ProcessData has Sm0..Sm7 (one per sync manager of the ESC).
constexpr unsigned kMaxSyncManagers = 8;
// ETG.2100 CoE InitCmd Ccs: 1 or 2 (which of them is the download depends on
// the writer of the file; see EniCoeInitCmd::download).
constexpr std::uint8_t kCcsOne = 1;
constexpr std::uint8_t kCcsTwo = 2;
// ETG.1000.6 §5.6.7: RxPDO mapping objects 1600h-17FFh, TxPDO 1A00h-1BFFh.
constexpr std::uint16_t kRxPdoFirst = 0x1600;
constexpr std::uint16_t kTxPdoFirst = 0x1A00;
constexpr std::uint16_t kPdoAreaSpan = 0x1FF;

class EniReader {
 public:
  explicit EniReader(const EsiContext& ctx) : ctx_(ctx) {}

  EniNetwork read(const pugi::xml_node& root) {
    EniNetwork net;
    net.file = ctx_.file();
    auto config = root.child("Config");
    if (!config) fail(root, "EtherCATConfig has no Config element");
    for (auto s : config.children("Slave")) net.slaves.push_back(slave(s));
    if (net.slaves.empty()) fail(config, "Config lists no Slave");
    for (auto cyclic : config.children("Cyclic")) {
      for (auto frame : cyclic.children("Frame")) {
        for (auto cmd : frame.children("Cmd")) {
          EniCyclicCmd c;
          c.line = ctx_.line(cmd);
          c.cmd = number<std::uint8_t>(cmd, "Cmd");
          c.cnt = cmd.child("Cnt") ? number<std::uint16_t>(cmd, "Cnt") : 0;
          net.cyclic.push_back(c);
        }
      }
    }
    return net;
  }

 private:
  [[noreturn]] void fail(const pugi::xml_node& n, std::string message) const {
    throw LoadFailure{ctx_.error(n, std::move(message))};
  }

  static std::string trimmed(const pugi::xml_node& n) {
    std::string_view t = n.child_value();
    while (!t.empty() && std::isspace(static_cast<unsigned char>(t.front()))) t.remove_prefix(1);
    while (!t.empty() && std::isspace(static_cast<unsigned char>(t.back()))) t.remove_suffix(1);
    return std::string(t);
  }

  // A number child that must fit T; xs:int values written negative (an
  // AutoIncAddr of -1, an identity with the top bit set) are taken as the
  // two's complement of T's width, as ETG.2100 writes them.
  template <typename T>
  T number(const pugi::xml_node& parent, const char* child) const {
    auto n = parent.child(child);
    if (!n) fail(parent, fmt::format("{}: {} missing", parent.name(), child));
    const std::string text = trimmed(n);
    auto lit = parse_integer(text);
    constexpr std::uint64_t max = std::numeric_limits<T>::max();
    if (!lit || lit->magnitude > max || (lit->negative && lit->magnitude > (max >> 1) + 1)) {
      fail(n, fmt::format("{}: '{}' is not a number that fits {} bits", child, text, sizeof(T) * 8));
    }
    const std::uint64_t v = lit->negative ? (max + 1 - lit->magnitude) & max : lit->magnitude;
    return static_cast<T>(v);
  }

  template <typename T>
  std::optional<T> optional_number(const pugi::xml_node& parent, const char* child) const {
    if (!parent.child(child)) return std::nullopt;
    return number<T>(parent, child);
  }

  bool boolean(const pugi::xml_node& n, bool fallback) const {
    if (!n) return fallback;
    auto b = parse_bool(trimmed(n));
    if (!b) fail(n, fmt::format("{}: '{}' is not a boolean", n.name(), trimmed(n)));
    return *b;
  }

  od::Value hex(const pugi::xml_node& n) const {
    std::string text;
    for (char c : trimmed(n)) {
      if (!std::isspace(static_cast<unsigned char>(c))) text.push_back(c);
    }
    auto v = parse_hex_binary(text);
    if (!v) fail(n, fmt::format("{}: '{}' is not hex binary (two hex digits per byte)", n.name(), text));
    return *v;
  }

  std::vector<std::string> transitions(const pugi::xml_node& cmd) const {
    std::vector<std::string> out;
    for (auto t : cmd.children("Transition")) out.push_back(trimmed(t));
    if (out.empty()) fail(cmd, "InitCmd without Transition");
    return out;
  }

  EniSlave slave(const pugi::xml_node& s) {
    EniSlave out;
    out.line = ctx_.line(s);
    auto info = s.child("Info");
    if (!info) fail(s, "Slave without Info");
    out.info_line = ctx_.line(info);
    out.name = trimmed(info.child("Name"));
    out.vendor_id = number<std::uint32_t>(info, "VendorId");
    out.product_code = number<std::uint32_t>(info, "ProductCode");
    out.revision = number<std::uint32_t>(info, "RevisionNo");
    out.serial = optional_number<std::uint32_t>(info, "SerialNo").value_or(0);
    out.phys_addr = optional_number<std::uint16_t>(info, "PhysAddr");
    out.auto_inc_addr = optional_number<std::uint16_t>(info, "AutoIncAddr");
    if (auto pd = s.child("ProcessData")) process_data(pd, out);
    if (auto mbx = s.child("Mailbox")) mailbox(mbx, out);
    for (auto cmd : s.child("InitCmds").children("InitCmd")) out.init_cmds.push_back(register_cmd(cmd));
    if (auto dc = s.child("DC")) {
      EniDc d;
      d.line = ctx_.line(dc);
      d.reference_clock = trimmed(dc.child("ReferenceClock")) == "true" || trimmed(dc.child("ReferenceClock")) == "1";
      d.cycle_time0 = optional_number<std::uint32_t>(dc, "CycleTime0").value_or(0);
      d.cycle_time1 = optional_number<std::uint32_t>(dc, "CycleTime1").value_or(0);
      d.shift_time = static_cast<std::int32_t>(optional_number<std::uint32_t>(dc, "ShiftTime").value_or(0));
      out.dc = d;
    }
    for (auto child : s.children()) {
      const std::string_view n = child.name();
      if (n != "Info" && n != "ProcessData" && n != "Mailbox" && n != "InitCmds" && n != "DC" &&
          child.type() == pugi::node_element) {
        ctx_.warn(child, "not used by the virtual chain; ignored");
      }
    }
    return out;
  }

  void process_data(const pugi::xml_node& pd, EniSlave& out) {
    if (auto send = pd.child("Send")) out.send_bit_length = optional_number<std::uint32_t>(send, "BitLength");
    if (auto recv = pd.child("Recv")) out.recv_bit_length = optional_number<std::uint32_t>(recv, "BitLength");
    for (unsigned i = 0; i < kMaxSyncManagers; ++i) {
      auto sm = pd.child(fmt::format("Sm{}", i).c_str());
      if (!sm) continue;
      EniSyncManager m;
      m.number = static_cast<std::uint8_t>(i);
      m.line = ctx_.line(sm);
      const std::string type = trimmed(sm.child("Type"));
      if (type == "Outputs") {
        m.outputs = true;
      } else if (type == "Inputs") {
        m.outputs = false;
      } else {
        fail(sm.child("Type") ? sm.child("Type") : sm,
             fmt::format("Sm{}: Type '{}' is neither Outputs nor Inputs", i, type));
      }
      m.start = optional_number<std::uint16_t>(sm, "StartAddress");
      m.control = optional_number<std::uint8_t>(sm, "ControlByte");
      m.enable = boolean(sm.child("Enable"), true);
      for (auto p : sm.children("Pdo")) {
        auto v = parse_unsigned(trimmed(p), std::numeric_limits<std::uint16_t>::max());
        if (!v) fail(p, fmt::format("Sm{}: Pdo '{}' is not a PDO index", i, trimmed(p)));
        m.pdos.push_back(static_cast<std::uint16_t>(*v));
      }
      out.sync_managers.push_back(std::move(m));
    }
    for (auto p : pd.children("RxPdo")) out.rx_pdos.push_back(pdo(p, true));
    for (auto p : pd.children("TxPdo")) out.tx_pdos.push_back(pdo(p, false));
  }

  EniPdo pdo(const pugi::xml_node& p, bool rx) {
    EniPdo out;
    out.rx = rx;
    out.line = ctx_.line(p);
    out.index = number<std::uint16_t>(p, "Index");
    const std::uint16_t first = rx ? kRxPdoFirst : kTxPdoFirst;
    if (out.index < first || out.index > first + kPdoAreaSpan) {
      fail(p.child("Index"), fmt::format("{} index #x{:04X} outside #x{:04X}..#x{:04X}", p.name(), out.index,
                                         first, first + kPdoAreaSpan));
    }
    out.name = esi_name(p);
    out.fixed = esi_bool(p.attribute("Fixed"));
    if (auto sm = p.attribute("Sm")) {
      auto v = parse_unsigned(sm.value(), kMaxSyncManagers - 1);
      if (!v) fail(p, fmt::format("{}@Sm '{}' is not a sync manager number", p.name(), sm.value()));
      out.sm = static_cast<std::uint8_t>(*v);
    }
    for (auto e : p.children("Entry")) {
      EniPdoEntry entry;
      entry.line = ctx_.line(e);
      entry.index = number<std::uint16_t>(e, "Index");
      entry.subindex = entry.index == 0 ? optional_number<std::uint8_t>(e, "SubIndex").value_or(0)
                                        : number<std::uint8_t>(e, "SubIndex");
      entry.bit_length = number<std::uint8_t>(e, "BitLen");
      entry.name = esi_name(e);
      entry.data_type = trimmed(e.child("DataType"));
      out.entries.push_back(std::move(entry));
    }
    return out;
  }

  void mailbox(const pugi::xml_node& mbx, EniSlave& out) {
    EniMailbox m;
    m.line = ctx_.line(mbx);
    auto send = mbx.child("Send");
    // ETG.2100 names the slave -> master mailbox "Recv"; SOEM's sample ENI
    // writes "Receive", which is read the same way.
    auto recv = mbx.child("Recv") ? mbx.child("Recv") : mbx.child("Receive");
    if (!send || !recv) fail(mbx, "Mailbox needs Send and Recv (start and length of both mailboxes)");
    m.out_start = number<std::uint16_t>(send, "Start");
    m.out_length = number<std::uint16_t>(send, "Length");
    m.in_start = number<std::uint16_t>(recv, "Start");
    m.in_length = number<std::uint16_t>(recv, "Length");
    for (auto p : mbx.children("Protocol")) {
      const std::string name = trimmed(p);
      if (name == "CoE") m.coe = true;
      else if (name == "FoE") m.foe = true;
      else if (name == "EoE") m.eoe = true;
      else if (name == "SoE") m.soe = true;
      else if (name == "AoE") m.aoe = true;
      else if (name == "VoE") m.voe = true;
      else ctx_.warn(p, fmt::format("mailbox protocol '{}' unknown; ignored", name));
    }
    if (mbx.child("CoE")) m.coe = true;
    for (auto cmd : mbx.child("CoE").child("InitCmds").children("InitCmd")) {
      if (boolean(cmd.child("Disabled"), false)) continue;
      out.coe_init_cmds.push_back(coe_cmd(cmd));
    }
    for (auto cmd : mbx.child("EoE").child("InitCmds").children("InitCmd")) {
      if (boolean(cmd.child("Disabled"), false)) continue;
      out.eoe_init_cmds.push_back(eoe_cmd(cmd));
    }
    for (const char* other : {"SoE", "FoE", "AoE", "VoE"}) {
      if (auto n = mbx.child(other).child("InitCmds")) {
        ctx_.warn(n, fmt::format("{} InitCmds are not sent to the virtual slave's model; ignored", other));
      }
    }
    out.mailbox = m;
  }

  EniCoeInitCmd coe_cmd(const pugi::xml_node& cmd) const {
    EniCoeInitCmd c;
    c.line = ctx_.line(cmd);
    c.transitions = transitions(cmd);
    c.ccs = number<std::uint8_t>(cmd, "Ccs");
    if (c.ccs != kCcsOne && c.ccs != kCcsTwo) {
      fail(cmd.child("Ccs"), fmt::format("Ccs {} is neither 1 nor 2", c.ccs));
    }
    c.index = number<std::uint16_t>(cmd, "Index");
    c.subindex = number<std::uint8_t>(cmd, "SubIndex");
    c.complete_access = esi_bool(cmd.attribute("CompleteAccess"));
    if (auto d = cmd.child("Data")) c.data = hex(d);
    c.download = c.ccs == kCcsTwo;  // ETG.2100's table; settled per file in settle_ccs()
    c.comment = trimmed(cmd.child("Comment"));
    return c;
  }

  EniEoeInitCmd eoe_cmd(const pugi::xml_node& cmd) const {
    EniEoeInitCmd c;
    c.line = ctx_.line(cmd);
    c.transitions = transitions(cmd);
    c.comment = trimmed(cmd.child("Comment"));
    auto data = cmd.child("Data");
    if (!data) fail(cmd, "EoE InitCmd without Data");
    c.data = hex(data);
    const std::span<const std::uint8_t> d(c.data);
    const unsigned type = d.size() >= kEoeHeaderSize ? (d[0] & kEoeFrameTypeMask) : kEoeSetIpRequest;
    if (type == kEoeSetIpRequest && d.size() >= kEoeHeaderSize + kFlagsBytes && fits_body(d.subspan(kEoeHeaderSize))) {
      c.ip = set_ip_body(d.subspan(kEoeHeaderSize));
    } else if (fits_body(d)) {
      c.ip = set_ip_body(d);
    } else if (type != kEoeSetIpRequest) {
      ctx_.warn(cmd, fmt::format("EoE InitCmd of frame type {} (not a Set IP Parameter request, type {}): "
                                 "answered by the slave when the master sends it, not checked",
                                 type, kEoeSetIpRequest));
      return c;
    } else {
      fail(data, fmt::format("EoE InitCmd Data of {} bytes is no Set IP Parameter request (UINT32 flags, then the "
                             "flagged fields, with or without the 4-byte EoE header of frame type 2)",
                             c.data.size()));
    }
    if (c.ip.flags & ~kKnownIpFlags) {
      ctx_.warn(data, fmt::format("EoE Set IP Parameter flags #x{:08X} have bits ETG.1000.6 does not define; "
                                  "they are ignored", c.ip.flags));
    }
    c.set_ip = true;
    for (const auto& t : c.transitions) {
      if (t != "IP" && t != "PS" && t != "SO") {
        ctx_.warn(cmd, fmt::format("EoE InitCmd on transition {}: the virtual slave checks those of IP, PS and SO "
                                   "only (the master sends them before SafeOp or Op); not checked there", t));
      }
    }
    return c;
  }

  // ETG.1000.6 EoE header: word 0 bits 0-3 frame type; Set IP Parameter
  // request = 2. Data is the request with its header when it starts with
  // type 2 and the rest is as long as the body its flags announce; else the
  // body alone when it is as long as its own flags announce; else, starting
  // with another request type, that request (passed on, not checked).
  static constexpr std::size_t kEoeHeaderSize = 4;
  static constexpr unsigned kEoeSetIpRequest = 2;
  static constexpr std::uint8_t kEoeFrameTypeMask = 0x0F;
  static constexpr std::size_t kMacBytes = 6, kAddressBytes = 4, kDnsNameBytes = 32, kFlagsBytes = 4;
  static constexpr std::uint32_t kKnownIpFlags = EniEoeIpParameters::kMac | EniEoeIpParameters::kIp |
                                                 EniEoeIpParameters::kSubnet | EniEoeIpParameters::kGateway |
                                                 EniEoeIpParameters::kDnsServer | EniEoeIpParameters::kDnsName;

  static std::uint32_t le32(std::span<const std::uint8_t> d) {
    return static_cast<std::uint32_t>(d[0]) | (static_cast<std::uint32_t>(d[1]) << 8) |
           (static_cast<std::uint32_t>(d[2]) << 16) | (static_cast<std::uint32_t>(d[3]) << 24);
  }
  // Bytes of a Set IP Parameter body with `flags` (a DNS name, the last
  // field, may be shorter than its 32 bytes: min..max).
  static std::pair<std::size_t, std::size_t> body_size(std::uint32_t flags) {
    std::size_t n = kFlagsBytes;
    if (flags & EniEoeIpParameters::kMac) n += kMacBytes;
    for (std::uint32_t f : {EniEoeIpParameters::kIp, EniEoeIpParameters::kSubnet, EniEoeIpParameters::kGateway,
                            EniEoeIpParameters::kDnsServer}) {
      if (flags & f) n += kAddressBytes;
    }
    if (flags & EniEoeIpParameters::kDnsName) return {n + 1, n + kDnsNameBytes};
    return {n, n};
  }
  static bool fits_body(std::span<const std::uint8_t> d) {
    if (d.size() < kFlagsBytes) return false;
    auto [lo, hi] = body_size(le32(d));
    return d.size() >= lo && d.size() <= hi;
  }

  // The fields of a Set IP Parameter body that fits_body() accepted.
  static EniEoeIpParameters set_ip_body(std::span<const std::uint8_t> d) {
    EniEoeIpParameters p;
    p.flags = le32(d);
    std::size_t at = kFlagsBytes;
    if (p.flags & EniEoeIpParameters::kMac) {
      std::copy_n(d.begin() + static_cast<std::ptrdiff_t>(at), kMacBytes, p.mac.begin());
      at += kMacBytes;
    }
    for (auto [flag, field] : {std::pair{EniEoeIpParameters::kIp, &p.ip}, std::pair{EniEoeIpParameters::kSubnet, &p.subnet},
                               std::pair{EniEoeIpParameters::kGateway, &p.gateway},
                               std::pair{EniEoeIpParameters::kDnsServer, &p.dns_server}}) {
      if (p.flags & flag) {
        *field = le32(d.subspan(at));
        at += kAddressBytes;
      }
    }
    if (p.flags & EniEoeIpParameters::kDnsName) {
      auto name = d.subspan(at);
      std::size_t len = 0;
      while (len < name.size() && name[len] != 0) ++len;
      p.dns_name.assign(reinterpret_cast<const char*>(name.data()), len);
    }
    return p;
  }

  EniRegisterInitCmd register_cmd(const pugi::xml_node& cmd) const {
    EniRegisterInitCmd c;
    c.line = ctx_.line(cmd);
    c.transitions = transitions(cmd);
    c.cmd = number<std::uint8_t>(cmd, "Cmd");
    c.adp = optional_number<std::uint16_t>(cmd, "Adp").value_or(0);
    c.ado = optional_number<std::uint16_t>(cmd, "Ado").value_or(0);
    if (auto d = cmd.child("Data")) {
      c.data = hex(d);
    } else if (auto len = optional_number<std::uint16_t>(cmd, "DataLength")) {
      c.data.assign(*len, 0);
    }
    c.cnt = optional_number<std::uint16_t>(cmd, "Cnt");
    if (auto v = cmd.child("Validate")) {
      if (v.child("Data")) c.validate_data = hex(v.child("Data"));
      if (v.child("DataMask")) c.validate_mask = hex(v.child("DataMask"));
    }
    c.comment = trimmed(cmd.child("Comment"));
    return c;
  }

  const EsiContext& ctx_;
};

// Which Ccs is the download, decided for the whole file (EniCoeInitCmd::download):
// a file that writes any CoE InitCmd with Ccs 2 follows ETG.2100's table and
// SOEM (2 download, 1 upload); a file that writes only Ccs 1 is a configurator
// export, whose Ccs 1 commands with Data are downloads (the CiA 301 specifier),
// and that choice is a warning at the first such command.
void settle_ccs(EniNetwork& net, const EsiContext& ctx) {
  const EniCoeInitCmd* first_one = nullptr;
  for (const auto& s : net.slaves) {
    for (const auto& c : s.coe_init_cmds) {
      if (c.ccs == kCcsTwo) return;
      if (!first_one && !c.data.empty()) first_one = &c;
    }
  }
  if (!first_one) return;
  ctx.warn_at("InitCmd", first_one->line,
              "every CoE InitCmd of this file has Ccs 1: those with Data are taken as SDO downloads "
              "(the configurators' convention, CiA 301 'initiate download'), those without as uploads");
  for (auto& s : net.slaves) {
    for (auto& c : s.coe_init_cmds) c.download = !c.data.empty();
  }
}

}  // namespace

Expected<EniNetwork, LoadError> read_eni_string(std::string_view xml, std::string_view name,
                                                std::vector<EsiWarning>* warnings) {
  EsiContext ctx(std::string(name), xml, warnings);
  pugi::xml_document doc;
  auto parsed_root = parse_root(doc, xml, name, "EtherCATConfig", "ENI");
  if (!parsed_root) return ecat::fail(parsed_root.error());
  auto root = *parsed_root;
  try {
    auto net = EniReader(ctx).read(root);
    settle_ccs(net, ctx);
    return net;
  } catch (const LoadFailure& f) {
    return ecat::fail(f.error);
  }
}

Expected<EniNetwork, LoadError> read_eni(const std::filesystem::path& path, std::vector<EsiWarning>* warnings) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return ecat::fail(LoadError{path.string(), 0, "cannot open file"});
  std::ostringstream text;
  text << in.rdbuf();
  return read_eni_string(text.str(), path.string(), warnings);
}

}  // namespace ecat::esi
