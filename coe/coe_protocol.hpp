// The CoE mailbox protocol (mailbox type 3, ETG.1000.6 §5.6.2): reads the CoE
// header and hands SDO requests to the SdoServer and SDO information
// requests to SdoInfo. Other CoE services (PDO over mailbox) are answered
// with mailbox error "service not supported".
#pragma once

#include "coe/mailbox_service.hpp"
#include "coe/sdo_info.hpp"
#include "coe/sdo_server.hpp"

namespace ecat::coe {

class CoeProtocol final : public MailboxService {
 public:
  // `info` may be null when the device does not offer SDO information.
  CoeProtocol(SdoServer& sdo, SdoInfo* info) : sdo_(sdo), info_(info) {}

  MailboxType type() const noexcept override { return MailboxType::CoE; }
  Expected<std::size_t, MailboxError> handle(ConstBytes request, Bytes reply, od::EsmState state) noexcept override;
  std::size_t next_reply(Bytes reply) noexcept override { return info_ ? info_->next_fragment(reply) : 0; }
  bool busy() const noexcept override { return sdo_.busy() || (info_ && info_->busy()); }
  void reset() noexcept override {
    sdo_.reset();
    if (info_) info_->reset();
  }

 private:
  SdoServer& sdo_;
  SdoInfo* info_;
};

}  // namespace ecat::coe
