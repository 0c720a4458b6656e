// libFuzzer target: the ESI reader (esi/esi_reader.hpp, read_esi_string) on
// arbitrary text: a device model or a LoadError, never a crash; warnings are
// collected as a caller would.
#include <cstdint>
#include <string_view>
#include <vector>

#include "esi/esi_reader.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view xml(reinterpret_cast<const char*>(data), size);
  std::vector<ecat::esi::EsiWarning> warnings;
  auto device = ecat::esi::read_esi_string(xml, "fuzz.xml", {}, &warnings);
  if (!device && device.error().message.empty()) __builtin_trap();
  for (const auto& w : warnings) (void)w.to_string("fuzz.xml");
  return 0;
}
