// One mailbox protocol (CoE, FoE, ...) as the mailbox server sees it
// (ETG.1000.6 §5.6): it gets the payload of each request of its type and
// writes the payload of its reply; long answers (SDO information fragments,
// ETG.1000.6 §5.6.3.6) come out one reply at a time through next_reply.
#pragma once

#include <cstddef>

#include "coe/mailbox_header.hpp"
#include "common/expected.hpp"
#include "common/le.hpp"
#include "od/access.hpp"

namespace ecat::coe {

class MailboxService {
 public:
  virtual ~MailboxService() = default;
  virtual MailboxType type() const noexcept = 0;
  // CoE is offered in PreOp/SafeOp/Op; FoE also in Bootstrap (ETG.1000.6 §5.6.1).
  virtual bool active_in(od::EsmState state) const noexcept {
    return state == od::EsmState::PreOp || state == od::EsmState::SafeOp || state == od::EsmState::Op;
  }
  // Handles one request (the payload after the mailbox header) and writes the
  // reply payload into `reply` (sized SM1 length - 6). Returns the reply
  // length (0: no reply) or a mailbox error to answer with.
  virtual Expected<std::size_t, MailboxError> handle(ConstBytes request, Bytes reply,
                                                     od::EsmState state) noexcept = 0;
  // Further replies to the last request, written when the read mailbox is
  // free; 0 when there are none.
  virtual std::size_t next_reply(Bytes reply) noexcept {
    (void)reply;
    return 0;
  }
  // Messages the service starts itself (EoE frames toward the master), one
  // payload per free SM1, interleaved fairly with replies by the mailbox
  // server. next_output writes the next one into `out` (SM1 room); 0: none.
  virtual bool has_output() const noexcept { return false; }
  // Whether the service ever starts messages (overrides has_output): asked
  // once when it is registered, so the mailbox server polls only those.
  virtual bool starts_messages() const noexcept { return false; }
  virtual std::size_t next_output(Bytes out) noexcept {
    (void)out;
    return 0;
  }
  // Payload room of SM0 (requests) and SM1 (replies) as the master set them;
  // told before every request (FoE needs it to see a file's last packet).
  virtual void set_sizes(std::size_t request_payload, std::size_t reply_payload) noexcept {
    (void)request_payload;
    (void)reply_payload;
  }
  // True while a multi-request transfer is in progress (SDO segments, SDO
  // information fragments): unsolicited messages wait until it ends.
  virtual bool busy() const noexcept { return false; }
  // The mailbox was closed (state fell back to Init): drop transfers.
  virtual void reset() noexcept {}
};

}  // namespace ecat::coe
