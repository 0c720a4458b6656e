#include "coe/coe_protocol.hpp"

#include "coe/coe_header.hpp"

namespace ecat::coe {

Expected<std::size_t, MailboxError> CoeProtocol::handle(ConstBytes request, Bytes reply,
                                                        od::EsmState state) noexcept {
  if (request.size() < CoeHeader::kSize) return fail(MailboxError::SizeTooShort);
  const CoeHeader h = CoeHeader::unpack(load_le<std::uint16_t>(request.data()));
  const ConstBytes body = request.subspan(CoeHeader::kSize);
  switch (static_cast<CoeService>(h.service)) {
    case CoeService::SdoRequest: return sdo_.handle(body, reply, state);
    case CoeService::SdoInformation:
      if (info_) return info_->handle(body, reply);
      return fail(MailboxError::ServiceNotSupported);
    default: return fail(MailboxError::ServiceNotSupported);
  }
}

}  // namespace ecat::coe
