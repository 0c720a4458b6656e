// examples/dio16-slave: your own slave on the ecatslave stack.
//
// The DIO16 terminal (dio16.xml + Dio16Application) as a virtual slave:
//   dio16-slave DEVICE.xml              in-process: the ecatslave master library
//                                       brings it to Op and checks the loopback
//   dio16-slave DEVICE.xml --udp PORT   serve it as EtherCAT-in-UDP on 127.0.0.1:PORT
//                                       for `ecat-master --udp 127.0.0.1:PORT` (until SIGTERM)
#include <algorithm>
#include <array>
#include <atomic>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <memory>
#include <span>
#include <string>

#include "dio16_application.hpp"
#include "esi/device_loader.hpp"
#include "master/coe_client.hpp"
#include "master/master.hpp"
#include "slave/chain.hpp"
#include "transport/in_memory_transport.hpp"
#include "transport/udp_transport.hpp"

namespace {

using namespace std::chrono_literals;

constexpr ecat::Nanoseconds kCyclePeriod = 1ms;

// Puts a DIO16 built from `file` on `chain` with our application in place of
// the one the stack would choose (none: the device is not a drive).
dio16::Dio16Application* add_terminal(ecat::slave::Chain& chain, const char* file) {
  auto device = ecat::esi::load_device_file(file);
  if (!device) {
    std::fprintf(stderr, "dio16-slave: %s\n", device.error().to_string().c_str());
    return nullptr;
  }
  if (auto ok = chain.add(std::move(*device), ecat::slave::SlaveOptions{}); !ok) {
    std::fprintf(stderr, "dio16-slave: %s\n", ok.error().c_str());
    return nullptr;
  }
  auto& firmware = chain[chain.size() - 1].firmware();
  auto app = std::make_unique<dio16::Dio16Application>(firmware.coe().objects());
  auto* raw = app.get();
  firmware.set_application(std::move(app));
  return raw;
}

bool step(const char* what, bool ok) {
  if (!ok) std::fprintf(stderr, "dio16-slave: %s failed\n", what);
  return ok;
}

// The master's side: Init -> PreOp (mailbox) -> SafeOp (process data) -> Op,
// then a walking one over the 16 outputs, each read back through the inputs.
int run_in_process(const char* file) {
  ecat::ManualClock clock;
  ecat::slave::Chain chain(clock);
  const auto* app = add_terminal(chain, file);
  if (!app) return 1;
  ecat::transport::InMemoryTransport wire;
  wire.set_processor([&](ecat::Bytes frame) {
    clock.advance(10us);  // the frame's time on the wire
    if (!chain.process_frame(frame, clock.now())) wire.drop_next(1);
  });

  ecat::master::Master master(wire, clock);
  // One cycle of the master's task: the process data frame, then the rest of
  // the cycle period, in which the slave runs its timers - in free run (the
  // default sync mode, 1C32h:01 = 0) that is when the application runs.
  auto cycle = [&] {
    auto r = master.exchange_process_data();
    clock.advance(kCyclePeriod);
    (void)chain.poll(clock.now());
    return r && r->ok();
  };
  auto count = master.scan();
  if (!step("scan", count && *count == 1)) return 1;
  if (!step("mailbox set-up", master.configure_mailbox(0).has_value())) return 1;
  auto preop = master.request_state(0, ecat::master::AlState::PreOp);
  if (!step("Init -> PreOp", preop && !preop->error())) return 1;
  ecat::master::CoeClient coe(master, 0);
  if (!step("PDO sizes from 1C12h/1C13h", coe.read_pdo_sizes().has_value())) return 1;
  if (!step("process data set-up", master.configure_process_data().has_value())) return 1;
  auto safeop = master.request_state(0, ecat::master::AlState::SafeOp);
  if (!step("PreOp -> SafeOp", safeop && !safeop->error())) return 1;
  (void)cycle();  // valid outputs before Op
  auto op = master.request_state(0, ecat::master::AlState::Op);
  if (!step("SafeOp -> Op", op && !op->error())) return 1;
  std::printf("DIO16 in Op: %u output bytes, %u input bytes\n", unsigned{master.slave(0).pd.output_bytes},
              unsigned{master.slave(0).pd.input_bytes});

  for (unsigned channel = 0; channel < dio16::kChannels; ++channel) {
    const auto pattern = static_cast<std::uint16_t>(1u << channel);
    auto out = master.outputs(0);
    out[0] = static_cast<std::uint8_t>(pattern);
    out[1] = static_cast<std::uint8_t>(pattern >> 8);
    // The application runs between two frames: the outputs of one come back
    // as inputs in the next.
    for (int frame = 0; frame < 2; ++frame) {
      if (!step("cyclic exchange (working counter)", cycle())) return 1;
    }
    const auto in = master.inputs(0);
    const auto seen = static_cast<std::uint16_t>(in[0] | (in[1] << 8));
    if (seen != pattern) {
      std::fprintf(stderr, "dio16-slave: channel %u: outputs 0x%04X, inputs 0x%04X\n", channel + 1, pattern, seen);
      return 1;
    }
  }
  std::printf("walking one over 16 channels read back; %llu application cycles\n",
              static_cast<unsigned long long>(app->cycles()));
  return 0;
}

std::atomic<bool> g_stop{false};
void on_signal(int) { g_stop = true; }

// A live slave: frames from UDP through the chain and back, its timers in between.
int serve_udp(const char* file, const std::string& port) {
  ecat::SteadyClock clock;
  ecat::slave::Chain chain(clock);
  const auto* app = add_terminal(chain, file);
  if (!app) return 1;
  auto endpoint = ecat::transport::parse_udp_endpoint("127.0.0.1:" + port);
  if (!endpoint) {
    std::fprintf(stderr, "dio16-slave: port %s: %s\n", port.c_str(),
                 std::string(ecat::transport::describe(endpoint.error())).c_str());
    return 2;
  }
  auto udp = ecat::transport::UdpTransport::bind(*endpoint);
  if (!udp) {
    std::fprintf(stderr, "dio16-slave: UDP %s: %s\n", port.c_str(),
                 std::string(ecat::transport::describe(udp.error())).c_str());
    return 1;
  }
  std::signal(SIGINT, on_signal);
  std::signal(SIGTERM, on_signal);
  std::printf("DIO16 serving EtherCAT-in-UDP on 127.0.0.1:%s\n", port.c_str());
  std::fflush(stdout);
  std::array<std::uint8_t, ecat::transport::kMaxFrameSize> buffer{};
  while (!g_stop) {
    const auto next = chain.poll(clock.now());
    const auto wait = next ? std::clamp(*next - clock.now(), ecat::Nanoseconds{0}, ecat::Nanoseconds{10ms})
                           : ecat::Nanoseconds{10ms};
    auto n = udp->receive(buffer, wait);
    if (!n) continue;  // timeout: run the timers
    std::span<std::uint8_t> frame(buffer.data(), *n);
    if (chain.process_frame(frame, clock.now())) (void)udp->send(frame);
  }
  const auto status = chain[0].status();
  std::printf("DIO16 stopped: %llu application cycles, AL state 0x%02X\n",
              static_cast<unsigned long long>(app->cycles()), static_cast<unsigned>(status.state));
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc == 2) return run_in_process(argv[1]);
  if (argc == 4 && std::string(argv[2]) == "--udp") return serve_udp(argv[1], argv[3]);
  std::fprintf(stderr, "usage: dio16-slave DEVICE.xml [--udp PORT]\n");
  return 2;
}
