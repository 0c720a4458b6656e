// The register space right after power-up (Context::power_up_registers): the
// reset values of ESC Section II are what a master finds before it has
// written anything, so the slave is read by its position (APRD: the station
// address is 0 again after power-up) and only then addressed again.
#include "common/frame.hpp"
#include "master/conformance/suite.hpp"

namespace ecat::master::conformance {

namespace {
constexpr std::size_t kChunk = 1024;  // bytes per APRD (fits one datagram)
}  // namespace

std::optional<Expected<const std::vector<std::uint8_t>*, std::string>> Context::power_up_registers() {
  if (!power_up_.empty()) return Expected<const std::vector<std::uint8_t>*, std::string>(&power_up_);
  if (!options_.power_cycle || !options_.power_cycle()) return std::nullopt;
  const SlaveInfo& s = info();
  std::vector<std::uint8_t> regs(kRegisterSpace);
  for (std::size_t at = 0; at < regs.size(); at += kChunk) {
    auto wkc = master_.transact(Command::Aprd,
                                device_address(auto_increment_adp(s.position), static_cast<std::uint16_t>(at)),
                                Bytes(regs.data() + at, kChunk));
    if (!wkc || *wkc != 1) {
      return Expected<const std::vector<std::uint8_t>*, std::string>(
          fail("APRD of the registers after power-up: " + (wkc ? "WKC " + std::to_string(*wkc) : std::string(describe(wkc.error())))));
    }
  }
  // Protection a power-up left on would stop the addressing (the scan clears it too).
  (void)master_.clear_write_protection();
  if (auto r = master_.readdress(slave()); !r) {
    return Expected<const std::vector<std::uint8_t>*, std::string>(
        fail("station address after power-up: " + std::string(describe(r.error()))));
  }
  dc_configured_ = false;
  power_up_ = std::move(regs);
  return Expected<const std::vector<std::uint8_t>*, std::string>(&power_up_);
}

}  // namespace ecat::master::conformance
