#include "transport/transport.hpp"

namespace ecat::transport {

std::string_view describe(TransportError e) noexcept {
  switch (e) {
    case TransportError::Timeout: return "timeout";
    case TransportError::BufferTooSmall: return "receive buffer too small";
    case TransportError::FrameTooLarge: return "frame too large";
    case TransportError::InvalidFrame: return "not an EtherCAT frame";
    case TransportError::NotOpen: return "transport not open";
    case TransportError::EndOfFile: return "end of file";
    case TransportError::OpenFailed: return "open failed";
    case TransportError::SendFailed: return "send failed";
    case TransportError::ReceiveFailed: return "receive failed";
    case TransportError::PermissionDenied: return "permission denied";
    case TransportError::Dropped: return "datagram dropped (source not allowed or length mismatch)";
    case TransportError::WriteFailed: return "write to the output file failed";
  }
  return "unknown transport error";
}

}  // namespace ecat::transport
