// The CoE side of one slave, wired from a device description (STYLE lesson 2:
// no globals; one object per slave): object store, mailbox server with the
// CoE (SDO, SDO information) and FoE services, emergency, PDO configuration,
// process-data copy, store/restore, and the ESM hooks. See docs/coe.md.
//
//   coe::CoeOptions options;
//   options.parameter_file = "slave1.par";
//   options.foe_dir = "foe1";
//   coe::CoeServer coe(esc, device, options);
//   esm.add_hooks(coe.esm_hooks());
//   for (;;) {               // one application cycle
//     esm.poll();            // first: it consumes the SM-change event
//     coe.poll(clock.now()); // mailbox
//     if (esm.state() == esc::AlState::Op) coe.process_data().read_outputs(esc);
//     ... drive ...
//     coe.process_data().write_inputs(esc);
//   }
#pragma once

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "coe/coe_protocol.hpp"
#include "coe/diagnosis_history.hpp"
#include "coe/emergency.hpp"
#include "coe/eoe_responder.hpp"
#include "coe/eoe_server.hpp"
#include "coe/foe_server.hpp"
#include "coe/mailbox_server.hpp"
#include "coe/object_store.hpp"
#include "coe/parameter_store.hpp"
#include "coe/pdo_config.hpp"
#include "coe/process_data.hpp"
#include "coe/sdo_info.hpp"
#include "coe/sdo_server.hpp"
#include "esc/esm_hooks.hpp"
#include "esc/pdi.hpp"
#include "od/device.hpp"

namespace ecat::coe {

struct CoeOptions {
  std::string parameter_file;  // 1010h/1011h file; "" refuses them (08000021)
  std::string foe_dir;         // FoE directory; "" refuses every file
  std::size_t mailbox_queue = MailboxServer::kDefaultQueueCapacity;
  std::uint32_t variable_capacity = 65536;  // bytes for strings/domains of unbounded length
  std::size_t max_foe_file_bytes = 16u << 20;
  std::uint32_t foe_password = 0;  // FoE RRQ/WRQ password (0: none; FoeServer::Options::password)
  std::uint16_t foe_busy = 0;      // FoE BUSY replies before each RRQ/WRQ (FoeServer::Options::busy_replies)
  // Budget of the state directory, shared by the slaves that write there
  // (FoE files + parameter file); null: unbounded. Must outlive the server.
  StorageQuota* state_quota = nullptr;
  // EoE start-up IP parameters (devices that list EoE); Set IP Parameter
  // overrides them.
  eoe::IpParameters eoe_defaults = eoe::default_parameters();
};

class CoeServer {
 public:
  static constexpr std::size_t kMinMailboxBytes = 128;

  // `device` must outlive the server (the store points into its dictionary).
  // Loads the parameter file; a bad file is ignored and reported in warnings().
  CoeServer(esc::Pdi& pdi, const od::DeviceDescription& device, CoeOptions options = {});
  CoeServer(const CoeServer&) = delete;
  CoeServer& operator=(const CoeServer&) = delete;

  // Mailbox work (requests, replies, repeats). Call after esc::Esm::poll.
  void poll(Nanoseconds now) noexcept {
    diagnosis_.set_time(now);  // 10F8h, the diagnosis messages' time base
    mailbox_.poll(now);
  }

  ObjectStore& objects() noexcept { return store_; }
  const ObjectStore& objects() const noexcept { return store_; }
  Emergency& emergency() noexcept { return emergency_; }
  // 10F3h, when the device has it (present()).
  DiagnosisHistory& diagnosis() noexcept { return diagnosis_; }
  const Emergency& emergency() const noexcept { return emergency_; }
  ProcessData& process_data() noexcept { return process_data_; }
  PdoConfig& pdo() noexcept { return pdo_; }
  SdoServer& sdo() noexcept { return sdo_; }
  // EoE (serving only when the device lists EoE) and its built-in responder,
  // the Ethernet side until set_port gives it another one (a TAP).
  EoeServer& eoe() noexcept { return eoe_; }
  EoeResponder& eoe_responder() noexcept { return eoe_responder_; }
  MailboxServer& mailbox() noexcept { return mailbox_; }
  const MailboxServer& mailbox() const noexcept { return mailbox_; }
  ParameterStore& parameters() noexcept { return parameters_; }
  esc::EsmHooks& esm_hooks() noexcept { return hooks_; }
  const std::vector<std::string>& warnings() const noexcept { return warnings_; }

 private:
  // PreOp->SafeOp: the module ident list (ETG.5001.1, F030h against F050h),
  // then the PDO mapping against SM2/SM3 (ETG.1000.6 §6.4.1.3).
  class Hooks final : public esc::EsmHooks {
   public:
    explicit Hooks(CoeServer& owner) : owner_(owner) {}
    esc::AlStatusCode check_transition(esc::AlState from, esc::AlState to) noexcept override;
   private:
    CoeServer& owner_;
  };

  static std::size_t mailbox_bytes(const od::DeviceDescription& device) noexcept;

  esc::Pdi& pdi_;
  ObjectStore store_;
  DiagnosisHistory diagnosis_;
  SdoServer sdo_;
  SdoInfo info_;
  CoeProtocol coe_;
  FoeServer foe_;
  EoeServer eoe_;
  EoeResponder eoe_responder_{eoe_};
  MailboxServer mailbox_;
  Emergency emergency_;
  PdoConfig pdo_;
  ProcessData process_data_;
  ParameterStore parameters_;
  Hooks hooks_{*this};
  std::vector<std::string> warnings_;
};

}  // namespace ecat::coe
