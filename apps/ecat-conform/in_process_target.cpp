#include <fmt/format.h>

#include "apps/ecat-conform/target.hpp"
#include "esi/device_loader.hpp"
#include "slave/chain.hpp"
#include "slave/fault_catalogue.hpp"
#include "transport/in_memory_transport.hpp"

namespace ecat::conform {

namespace {

// Simulated wire + processing time per frame on the in-process bus.
constexpr Nanoseconds kFrameTime = std::chrono::microseconds(50);
// Longest step of simulated time while waiting, so the slaves' timers run often.
constexpr Nanoseconds kMaxWaitStep = std::chrono::milliseconds(1);

class InProcessTarget final : public Target {
 public:
  explicit InProcessTarget(std::string description)
      : chain_(clock_), transport_([this](Bytes f) { process(f); }), description_(std::move(description)) {}

  Expected<void, std::string> add(od::DeviceDescription device, slave::PdiKind pdi) {
    identity_ = master::conformance::ExpectedIdentity{device.identity.vendor_id, device.identity.product_code,
                                                      device.identity.revision};
    device_ = device;
    slave::SlaveOptions options;
    options.name = "conform";
    options.pdi = pdi;
    return chain_.add(std::move(device), options);
  }
  const od::DeviceDescription* device() const override { return &device_; }

  transport::Transport& transport() override { return transport_; }
  const Clock& clock() const override { return clock_; }
  std::optional<master::conformance::ExpectedIdentity> identity() const override { return identity_; }
  std::string description() const override { return description_; }

  // The fault catalogue's power_cycle (docs/faults.md): off, then on with
  // the ESC's power-up register values and the firmware started afresh.
  bool power_cycle() override {
    slave::FaultCatalogue faults(chain_);
    auto id = faults.engage({"power_cycle", 0, {}, {}});
    if (!id) return false;
    if (!faults.clear(*id)) return false;
    (void)chain_.poll(clock_.now());
    return true;
  }

  void wait(Nanoseconds d) override {
    const Nanoseconds end = clock_.now() + d;
    while (clock_.now() < end) {
      const auto next = chain_.poll(clock_.now());
      Nanoseconds step = std::min(kMaxWaitStep, end - clock_.now());
      if (next && *next > clock_.now()) step = std::min(step, *next - clock_.now());
      clock_.advance(step);
    }
    (void)chain_.poll(clock_.now());
  }

 private:
  void process(Bytes frame) {
    if (!chain_.process_frame(frame, clock_.now())) transport_.drop_next(1);
    clock_.advance(kFrameTime);
  }

  ManualClock clock_;
  slave::Chain chain_;
  transport::InMemoryTransport transport_;
  std::string description_;
  std::optional<master::conformance::ExpectedIdentity> identity_;
  od::DeviceDescription device_;
};

}  // namespace

Expected<std::unique_ptr<Target>, std::string> make_in_process_target(const std::string& device_file,
                                                                      slave::PdiKind pdi) {
  auto device = esi::load_device_file(device_file);
  if (!device) return fail(device.error().to_string());
  const char* over = pdi == slave::PdiKind::Lan9252     ? " (firmware over SPI to an emulated LAN9252)"
                     : pdi == slave::PdiKind::Et1100Spi ? " (firmware over SPI to an emulated ET1100)"
                                                         : "";
  auto target = std::make_unique<InProcessTarget>(fmt::format("in-process {}{}", device_file, over));
  if (auto r = target->add(std::move(*device), pdi); !r) return fail(r.error());
  return std::unique_ptr<Target>(std::move(target));
}

}  // namespace ecat::conform
