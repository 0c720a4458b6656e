// ecat-sdo: a test tool that reads and writes CoE objects of one slave over
// a raw interface with the master library (scan, mailbox set-up, PreOp,
// SDO upload/download; ETG.1000.6 §5.6.2). Used by the fault scripts, e.g.
// to store parameters (1010h:01 = "save") and read them back after a crash.
//   ecat-sdo --iface IF [--slave N] OP...
//   OP: r:INDEX:SUB            upload, prints "INDEX:SUB = 0xVALUE (decimal)"
//       w:INDEX:SUB:SIZE:VALUE expedited download of SIZE (1..4) bytes
// Numbers are hexadecimal for INDEX/SUB, decimal or 0x-hex for VALUE.
// Exit 0: every operation done; 1: a failure (SDO abort printed); 2: usage.
#include <time.h>

#include <cstdio>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>
#include <fmt/format.h>

#include "master/coe_client.hpp"
#include "master/master.hpp"
#include "transport/raw_socket_transport.hpp"

namespace {

constexpr int kExitUsage = 2;
constexpr int kExitFailure = 1;
constexpr int kHex = 16;

struct Op {
  bool write = false;
  std::uint16_t index = 0;
  std::uint8_t subindex = 0;
  std::size_t size = 0;
  std::uint32_t value = 0;
};

bool parse_op(const std::string& text, Op& op) {
  std::vector<std::string> f;
  std::size_t start = 0;
  for (std::size_t c = text.find(':'); ; c = text.find(':', start)) {
    f.push_back(text.substr(start, c == std::string::npos ? std::string::npos : c - start));
    if (c == std::string::npos) break;
    start = c + 1;
  }
  try {
    if (f.size() == 3 && f[0] == "r") {
      op.write = false;
    } else if (f.size() == 5 && f[0] == "w") {
      op.write = true;
      op.size = std::stoul(f[3]);
      op.value = static_cast<std::uint32_t>(std::stoul(f[4], nullptr, 0));
      if (op.size < 1 || op.size > 4) return false;
    } else {
      return false;
    }
    op.index = static_cast<std::uint16_t>(std::stoul(f[1], nullptr, kHex));
    op.subindex = static_cast<std::uint8_t>(std::stoul(f[2], nullptr, kHex));
  } catch (const std::exception&) {
    return false;
  }
  return true;
}

std::string sdo_text(const ecat::master::SdoError& e) {
  if (e.from_slave) return fmt::format("SDO abort 0x{:08X}", static_cast<std::uint32_t>(e.code));
  return std::string(ecat::master::describe(e.cause));
}

}  // namespace

int main(int argc, char** argv) {
  std::string iface;
  std::size_t slave = 1;
  std::vector<std::string> op_texts;
  CLI::App cli{"ecat-sdo: read/write CoE objects of one slave (test tool)"};
  cli.add_option("--iface", iface, "Network interface of the segment")->required();
  cli.add_option("--slave", slave, "Slave position, 1 = first")->check(CLI::PositiveNumber);
  cli.add_option("ops", op_texts, "r:INDEX:SUB or w:INDEX:SUB:SIZE:VALUE")->required();
  try {
    cli.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return cli.exit(e);
  } catch (const CLI::ParseError& e) {
    std::fprintf(stderr, "ecat-sdo: %s (see --help)\n", e.what());
    return kExitUsage;
  }
  std::vector<Op> ops(op_texts.size());
  for (std::size_t i = 0; i < ops.size(); ++i) {
    if (!parse_op(op_texts[i], ops[i])) {
      std::fprintf(stderr, "ecat-sdo: bad operation '%s' (see --help)\n", op_texts[i].c_str());
      return kExitUsage;
    }
  }

  auto t = ecat::transport::RawSocketTransport::open(iface);
  if (!t) {
    std::fprintf(stderr, "ecat-sdo: cannot open %s: %s\n", iface.c_str(),
                 std::string(ecat::transport::describe(t.error())).c_str());
    return kExitFailure;
  }
  ecat::SteadyClock clock;
  ecat::master::Master master(*t, clock);
  auto n = master.scan();
  if (!n || *n < slave) {
    std::fprintf(stderr, "ecat-sdo: scan: %s\n",
                 n ? fmt::format("{} slave(s), no slave {}", *n, slave).c_str()
                   : std::string(ecat::master::describe(n.error())).c_str());
    return kExitFailure;
  }
  const std::size_t s = slave - 1;
  if (auto ok = master.configure_mailbox(s); !ok) {
    std::fprintf(stderr, "ecat-sdo: mailbox: %s\n", std::string(ecat::master::describe(ok.error())).c_str());
    return kExitFailure;
  }
  auto st = master.request_state(s, ecat::master::AlState::PreOp);
  if (!st || st->error()) {
    std::fprintf(stderr, "ecat-sdo: PreOp not reached\n");
    return kExitFailure;
  }
  ecat::master::CoeClient coe(master, s);
  for (const Op& op : ops) {
    if (op.write) {
      if (auto ok = coe.download_value(op.index, op.subindex, op.value, op.size); !ok) {
        std::fprintf(stderr, "ecat-sdo: write %04X:%02X: %s\n", op.index, op.subindex, sdo_text(ok.error()).c_str());
        return kExitFailure;
      }
      std::printf("%04X:%02X := 0x%08X\n", op.index, op.subindex, op.value);
    } else {
      auto v = coe.upload_value(op.index, op.subindex);
      if (!v) {
        std::fprintf(stderr, "ecat-sdo: read %04X:%02X: %s\n", op.index, op.subindex, sdo_text(v.error()).c_str());
        return kExitFailure;
      }
      std::printf("%04X:%02X = 0x%08X (%u)\n", op.index, op.subindex, *v, *v);
    }
    std::fflush(stdout);
  }
  return 0;
}
