#include "coe/coe_server.hpp"

#include <algorithm>

#include "coe/module_ident_check.hpp"

namespace ecat::coe {

std::size_t CoeServer::mailbox_bytes(const od::DeviceDescription& device) noexcept {
  std::size_t n = kMinMailboxBytes;
  for (std::size_t sm = 0; sm < device.sync_managers.size() && sm <= MailboxServer::kReadMailboxSm; ++sm) {
    n = std::max<std::size_t>({n, device.sync_managers[sm].default_size, device.sync_managers[sm].max_size});
  }
  return n;
}

CoeServer::CoeServer(esc::Pdi& pdi, const od::DeviceDescription& device, CoeOptions options)
    : pdi_(pdi),
      store_(device.dictionary, ObjectStore::Options{options.variable_capacity}),
      diagnosis_(store_),
      sdo_(store_, device.mailbox.complete_access),
      info_(store_),
      coe_(sdo_, device.mailbox.sdo_info ? &info_ : nullptr),
      foe_(FoeServer::Options{options.foe_dir, options.max_foe_file_bytes, 64, options.state_quota, options.foe_password,
                                options.foe_busy}),
      mailbox_(pdi, mailbox_bytes(device), options.mailbox_queue),
      emergency_(mailbox_, store_, &diagnosis_),
      pdo_(store_, device),
      process_data_(store_, pdo_),
      parameters_(store_, options.parameter_file, options.state_quota) {
  if (device.mailbox.coe) mailbox_.add_service(coe_);
  if (device.mailbox.foe) mailbox_.add_service(foe_);
  if (device.mailbox.eoe) {
    eoe_.set_ip_parameters(options.eoe_defaults);
    eoe_.set_port(&eoe_responder_);
    mailbox_.add_service(eoe_);
  }
  if (auto loaded = parameters_.load(); !loaded) warnings_.push_back(loaded.error());
  pdo_.rebuild();
}

esc::AlStatusCode CoeServer::Hooks::check_transition(esc::AlState from, esc::AlState to) noexcept {
  if (from != esc::AlState::PreOp || to != esc::AlState::SafeOp) return esc::AlStatusCode::NoError;
  // ETG.5001.1: the configured modules (F030h) first, then the PDO mapping
  // that those modules' PDOs make up.
  if (auto code = check_module_idents(owner_.store_); code != esc::AlStatusCode::NoError) return code;
  return owner_.pdo_.check_safeop(owner_.pdi_);
}

}  // namespace ecat::coe
