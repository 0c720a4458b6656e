#include "coe/module_ident_check.hpp"

#include "od/modular_device.hpp"

namespace ecat::coe {

esc::AlStatusCode check_module_idents(const ObjectStore& store) noexcept {
  if (!store.contains(od::kConfiguredModuleIdentList) || !store.contains(od::kDetectedModuleIdentList)) {
    return esc::AlStatusCode::NoError;
  }
  const auto configured = store.get<std::uint8_t>(od::kConfiguredModuleIdentList, 0);
  if (configured == 0) return esc::AlStatusCode::NoError;  // the master did not configure the modules
  if (configured != store.get<std::uint8_t>(od::kDetectedModuleIdentList, 0)) {
    return esc::AlStatusCode::DetectedModuleIdentListMismatch;
  }
  for (unsigned sub = 1; sub <= configured; ++sub) {
    const auto s = static_cast<std::uint8_t>(sub);
    if (store.get<std::uint32_t>(od::kConfiguredModuleIdentList, s) !=
        store.get<std::uint32_t>(od::kDetectedModuleIdentList, s)) {
      return esc::AlStatusCode::DetectedModuleIdentListMismatch;
    }
  }
  return esc::AlStatusCode::NoError;
}

}  // namespace ecat::coe
