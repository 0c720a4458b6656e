#include "esi/device_build.hpp"

#include <fmt/format.h>

#include "esi/device_failure.hpp"

namespace ecat::esi {

od::DeviceDescription build_device(DeviceSpec spec) {
  od::DeviceDescription dev;
  derive_objects(spec);
  build_layout(spec, dev);
  for (const auto& [index, obj] : spec.objects) {
    if (auto ok = dev.dictionary.put(build_object(index, obj)); !ok) fail_at(obj.where, ok.error());
  }
  build_pdos(spec, dev);
  build_modules(spec, dev);
  check_sync_manager_memory(spec, dev);
  return dev;
}

}  // namespace ecat::esi
