#include "coe/foe_server.hpp"

#include <sys/stat.h>
#include <unistd.h>

#include <cstdio>

namespace ecat::coe {
namespace {

bool name_char(char c) noexcept {
  return (c >= 'A' && c <= 'Z') || (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '.' || c == '_' ||
         c == '-';
}

constexpr mode_t kDirectoryMode = 0755;

}  // namespace

bool FoeServer::safe_name(std::string_view name) const noexcept {
  if (name.empty() || name.size() > options_.max_name_length || name.front() == '.') return false;
  for (char c : name) {
    if (!name_char(c)) return false;
  }
  return true;
}

void FoeServer::reset() noexcept {
  if (file_) {
    std::fclose(file_);
    file_ = nullptr;
  }
  if (state_ == State::Writing) ::unlink(temp_path_.c_str());
  if (temp_charged_ && options_.quota) options_.quota->release_file(size_);
  temp_charged_ = false;
  state_ = State::Idle;
}

std::size_t FoeServer::header(Bytes reply, std::uint8_t opcode, std::uint32_t value) noexcept {
  ByteWriter w(reply);
  w.u8(opcode);
  w.u8(0);
  w.u32(value);
  return w.position();
}

std::size_t FoeServer::error(Bytes reply, foe::FoeError code) noexcept {
  reset();
  return header(reply, foe::kError, static_cast<std::uint32_t>(code));
}

Expected<std::size_t, MailboxError> FoeServer::handle(ConstBytes request, Bytes reply, od::EsmState) noexcept {
  if (request.size() < foe::kHeaderSize) return fail(MailboxError::SizeTooShort);
  if (reply.size() <= foe::kHeaderSize) return fail(MailboxError::NoMoreMemory);
  ByteReader r(request);
  const std::uint8_t opcode = r.u8();
  r.skip(1);
  const std::uint32_t value = r.u32();  // password, packet number or error code
  const ConstBytes rest = r.rest();
  const std::string_view name(reinterpret_cast<const char*>(rest.data()), rest.size());
  switch (opcode) {
    case foe::kReadRequest: return read_request(value, name, reply);
    case foe::kWriteRequest: return write_request(value, name, reply);
    case foe::kData: return data(value, rest, reply);
    case foe::kAck: return ack(value, reply);
    case foe::kError: reset(); return std::size_t{0};  // the master gave up: no answer
    case foe::kBusy: return error(reply, foe::FoeError::Illegal);
    default: return fail(MailboxError::ServiceNotSupported);
  }
}

std::size_t FoeServer::busy(Bytes reply) noexcept {
  if (busy_given_ >= options_.busy_replies) {
    busy_given_ = 0;
    return 0;
  }
  const std::uint32_t progress = busy_given_ | (std::uint32_t{options_.busy_replies} << foe::kBusyEntireShift);
  ++busy_given_;
  return header(reply, foe::kBusy, progress);
}

std::size_t FoeServer::read_request(std::uint32_t password, std::string_view name, Bytes reply) noexcept {
  reset();
  if (options_.directory.empty() || !safe_name(name)) return error(reply, foe::FoeError::AccessDenied);
  if (password != options_.password) return error(reply, foe::FoeError::NoRights);
  if (const std::size_t n = busy(reply)) return n;
  try {
    path_ = options_.directory + "/" + std::string(name);
  } catch (...) {
    return error(reply, foe::FoeError::NotDefined);
  }
  file_ = std::fopen(path_.c_str(), "rb");
  if (!file_) return error(reply, foe::FoeError::NotFound);
  state_ = State::Reading;
  packet_ = 0;
  return send_data(reply);
}

std::size_t FoeServer::send_data(Bytes reply) noexcept {
  ++packet_;
  const std::size_t room = reply.size() - foe::kHeaderSize;
  const std::size_t n = std::fread(reply.data() + foe::kHeaderSize, 1, room, file_);
  if (n < room && std::ferror(file_)) return error(reply, foe::FoeError::ProgramError);
  last_short_ = n < room;
  header(reply, foe::kData, packet_);
  return foe::kHeaderSize + n;
}

std::size_t FoeServer::ack(std::uint32_t packet, Bytes reply) noexcept {
  if (state_ != State::Reading) return error(reply, foe::FoeError::Illegal);
  if (packet != packet_) return error(reply, foe::FoeError::PacketNumber);
  if (last_short_) {
    reset();  // the short packet was the end of the file
    return 0;
  }
  return send_data(reply);
}

std::size_t FoeServer::write_request(std::uint32_t password, std::string_view name, Bytes reply) noexcept {
  reset();
  if (options_.directory.empty() || !safe_name(name)) return error(reply, foe::FoeError::AccessDenied);
  if (password != options_.password) return error(reply, foe::FoeError::NoRights);
  if (const std::size_t n = busy(reply)) return n;
  try {
    path_ = options_.directory + "/" + std::string(name);
    temp_path_ = path_ + ".part";
  } catch (...) {
    return error(reply, foe::FoeError::NotDefined);
  }
  // The slave's FoE directory is made on first use (its parent is --state-dir).
  (void)::mkdir(options_.directory.c_str(), kDirectoryMode);
  StorageQuota* quota = options_.quota;
  if (quota) {
    // A <name>.part left by a crash is replaced: it is removed first and
    // what it held given back.
    if (const auto old = StorageQuota::regular_file_size(temp_path_); old && ::unlink(temp_path_.c_str()) == 0) {
      quota->release_file(*old);
    }
    if (!quota->charge_file()) return error(reply, foe::FoeError::DiskFull);
  }
  size_ = 0;
  temp_charged_ = quota != nullptr;
  file_ = std::fopen(temp_path_.c_str(), "wb");
  if (!file_) return error(reply, foe::FoeError::AccessDenied);
  state_ = State::Writing;
  packet_ = 0;
  return header(reply, foe::kAck, 0);
}

std::size_t FoeServer::data(std::uint32_t packet, ConstBytes bytes, Bytes reply) noexcept {
  if (state_ != State::Writing) return error(reply, foe::FoeError::Illegal);
  if (packet != packet_ + 1) return error(reply, foe::FoeError::PacketNumber);
  if (size_ + bytes.size() > options_.max_file_bytes) return error(reply, foe::FoeError::DiskFull);
  // Charged before the write, so the disk never holds more than the quota.
  if (options_.quota && !options_.quota->charge_bytes(bytes.size())) return error(reply, foe::FoeError::DiskFull);
  size_ += bytes.size();  // written or about to be: reset() gives back size_ bytes
  if (!bytes.empty() && std::fwrite(bytes.data(), 1, bytes.size(), file_) != bytes.size()) {
    return error(reply, foe::FoeError::DiskFull);
  }
  packet_ = packet;
  // A packet shorter than the mailbox allows is the last one.
  if (bytes.size() + foe::kHeaderSize < request_payload_) {
    const bool flushed = std::fflush(file_) == 0 && ::fsync(fileno(file_)) == 0;
    std::fclose(file_);
    file_ = nullptr;
    const auto replaced = StorageQuota::regular_file_size(path_);
    if (!flushed || std::rename(temp_path_.c_str(), path_.c_str()) != 0) {
      state_ = State::Writing;  // so reset() removes the temporary file
      return error(reply, foe::FoeError::DiskFull);
    }
    // The .part's charge is now the file's; the file it replaced is gone.
    if (options_.quota && replaced) options_.quota->release_file(*replaced);
    temp_charged_ = false;
    state_ = State::Idle;
  }
  return header(reply, foe::kAck, packet);
}

}  // namespace ecat::coe
