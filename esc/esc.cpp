// Esc construction, reset and the PDI entry points.
#include "esc/esc.hpp"

#include <algorithm>
#include <cstring>

namespace ecat::esc {

Esc::Esc(EscConfig config, const Clock& clock)
    : config_(std::move(config)), clock_(clock), mem_(new std::uint8_t[kAddressSpace]()) {
  reset();
}

Esc::~Esc() = default;

void Esc::reset() noexcept { std::memset(mem_.get(), 0, kAddressSpace); }

void Esc::read(std::uint16_t address, std::span<std::uint8_t> out) noexcept {
  std::size_t n = std::min<std::size_t>(out.size(), kAddressSpace - address);
  std::memcpy(out.data(), mem_.get() + address, n);
}

void Esc::write(std::uint16_t address, std::span<const std::uint8_t> in) noexcept {
  std::size_t n = std::min<std::size_t>(in.size(), kAddressSpace - address);
  std::memcpy(mem_.get() + address, in.data(), n);
}

void Esc::process(const FrameView& frame, Nanoseconds now) noexcept {
  (void)frame;
  now_ = now;
}

std::optional<Nanoseconds> Esc::poll(Nanoseconds now) noexcept {
  now_ = now;
  return std::nullopt;
}

void Esc::set_link(unsigned port, bool l) noexcept { link_[port] = l; }
bool Esc::link(unsigned port) const noexcept { return link_[port]; }
bool Esc::port_open(unsigned port) const noexcept { return link_[port]; }
std::uint16_t Esc::register_u16(std::uint16_t address) const noexcept { return load_le<std::uint16_t>(mem_.get() + address); }
bool Esc::irq() const noexcept { return false; }

}  // namespace ecat::esc
