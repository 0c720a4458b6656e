// Per-ESC-type inner delay figures (docs/esc.md "Forwarding delay figures per
// ESC type": what was searched, what was found, and why every entry below is
// still empty).
#include "esc/inner_delay_figures.hpp"

namespace ecat::esc {
namespace {

// Section I §9.1.2 Table 30 defines t_P (processing delay, "through the
// EtherCAT processing unit"), t_F (forwarding delay, "alongside" it) and
// t_Diff = t_P - t_F ("ESC specific information, part of the ESI. Refer to
// section III for actual figures"). No section III table, ESI or vendor
// datasheet giving those figures could be read for this project; no figure
// is written here from memory or estimate.
constexpr InnerDelayFigures kTable[] = {
    {kEscTypeEsc20, "ESC10/ESC20", {}, {}, {}, {}, "not found (no ESC20 section III consulted)"},
    {kEscTypeIpCore, "EtherCAT IP core", {}, {}, {}, {}, "not found (IP core section III not consulted)"},
    {kEscTypeEt1100, "ET1100/ET1150", {}, {}, {}, {},
     "not found (ET1100 section III v2.1 is cited by public repositories but its delay table was not readable)"},
    {kEscTypeEt1200, "ET1200", {}, {}, {}, {}, "not found (ET1200 section III not consulted)"},
    {kEscTypeTi, "TI (PRU-ICSS, C2000)", {}, {}, {}, {}, "not found (TI SDK/datasheet pages read give no figure)"},
    {kEscTypeInfineon, "Infineon XMC4x00", {}, {}, {}, {}, "not found"},
    {kEscTypeRenesas, "Renesas RZ/T, RZ/N", {}, {}, {}, {}, "not found"},
    {kEscTypeMicrochip, "Microchip LAN9252/LAN9253", {}, {}, {}, {}, "not found"},
};

Nanoseconds figure(const std::optional<Nanoseconds>& ebus, const std::optional<Nanoseconds>& mii, PortType t) {
  if (t == PortType::Ebus) return ebus.value_or(Nanoseconds{0});
  if (t == PortType::Mii) return mii.value_or(Nanoseconds{0});
  return Nanoseconds{0};  // not implemented / not configured: no frame enters there
}

}  // namespace

std::span<const InnerDelayFigures> datasheet_inner_delays() noexcept { return kTable; }

const InnerDelayFigures* find_inner_delays(std::span<const InnerDelayFigures> table, std::uint8_t esc_type) noexcept {
  for (const InnerDelayFigures& f : table) {
    if (f.esc_type == esc_type) return &f;
  }
  return nullptr;
}

std::array<PortType, kMaxPorts> port_types(std::uint8_t port_descriptor) noexcept {
  std::array<PortType, kMaxPorts> t{};
  for (unsigned p = 0; p < kMaxPorts; ++p) {
    t[p] = port_type_in(port_descriptor, p);
  }
  return t;
}

InnerDelays inner_delays_for(const InnerDelayFigures* figures, const std::array<PortType, kMaxPorts>& ports) noexcept {
  InnerDelays d;
  if (figures == nullptr) return d;
  d.processing = figure(figures->processing_ebus, figures->processing_mii, ports[0]);
  for (unsigned p = 1; p < kMaxPorts; ++p) {
    d.forwarding[p] = figure(figures->forwarding_ebus, figures->forwarding_mii, ports[p]);
  }
  return d;
}

}  // namespace ecat::esc
