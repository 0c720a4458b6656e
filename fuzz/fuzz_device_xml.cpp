// libFuzzer target: the device-XML loader (esi/device_loader.hpp,
// load_device_string) on arbitrary text. It must return a device or a
// "file:line: message" error; an exception escaping it is a finding too
// (errors are values past the XML edge).
#include <cstdint>
#include <string_view>

#include "esi/device_loader.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view xml(reinterpret_cast<const char*>(data), size);
  // The name places relative includes in xml/devices/, so "../profiles/..."
  // resolves to the built-in profiles as for a shipped device.
  auto device = ecat::esi::load_device_string(xml, "fuzz/devices/input.xml");
  if (!device && device.error().message.empty()) __builtin_trap();
  return 0;
}
