#include "coe/parameter_store.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <fstream>
#include <iterator>

#include <fmt/format.h>

namespace ecat::coe {
namespace {

constexpr std::size_t kFileHeader = 4 + 2 + 2 + 4;  // magic, version, reserved, count
constexpr std::size_t kRecordHeader = 2 + 1 + 4;    // index, subindex, length
constexpr std::size_t kCrcSize = 4;

bool write_all(int fd, const std::uint8_t* p, std::size_t n) noexcept {
  while (n > 0) {
    const ssize_t w = ::write(fd, p, n);
    if (w < 0) {
      if (errno == EINTR) continue;
      return false;
    }
    p += w;
    n -= static_cast<std::size_t>(w);
  }
  return true;
}

std::string directory_of(const std::string& path) {
  const auto slash = path.find_last_of('/');
  if (slash == std::string::npos) return ".";
  return slash == 0 ? "/" : path.substr(0, slash);
}

}  // namespace

std::uint32_t crc32(ConstBytes data) noexcept {
  constexpr std::uint32_t kPolynomial = 0xEDB88320u;
  std::uint32_t crc = 0xFFFFFFFFu;
  for (std::uint8_t b : data) {
    crc ^= b;
    for (int k = 0; k < 8; ++k) crc = (crc >> 1) ^ (kPolynomial & (0u - (crc & 1u)));
  }
  return ~crc;
}

ParameterStore::ParameterStore(ObjectStore& store, std::string path, StorageQuota* quota)
    : store_(store), path_(std::move(path)), quota_(quota) {
  store.set_hooks(kStoreParameters, this);
  store.set_hooks(kRestoreDefaults, this);
}

bool ParameterStore::persistent(const ObjectStore::Slot& slot, std::uint16_t index) noexcept {
  return slot.entry->access.writable() && !slot.entry->access.is_const && index != kStoreParameters &&
         index != kRestoreDefaults;
}

std::vector<std::uint8_t> ParameterStore::serialize() const {
  std::vector<std::uint8_t> out(kFileHeader);
  std::uint32_t count = 0;
  for (const ObjectStore::Slot& s : store_.slots()) {
    const std::uint16_t index = store_.index_of(s);
    if (!persistent(s, index)) continue;
    const ConstBytes v = store_.value(s);
    std::uint8_t rec[kRecordHeader];
    ByteWriter w(rec);
    w.u16(index);
    w.u8(s.entry->subindex);
    w.u32(static_cast<std::uint32_t>(v.size()));
    out.insert(out.end(), rec, rec + kRecordHeader);
    out.insert(out.end(), v.begin(), v.end());
    ++count;
  }
  ByteWriter h({out.data(), kFileHeader});
  h.u32(kMagic);
  h.u16(kVersion);
  h.u16(0);
  h.u32(count);
  std::uint8_t crc[kCrcSize];
  store_le(crc, crc32(out));
  out.insert(out.end(), crc, crc + kCrcSize);
  return out;
}

Expected<void, std::string> ParameterStore::save() const noexcept {
  if (path_.empty()) return fail(std::string("no parameter file configured"));
  try {
    const std::vector<std::uint8_t> bytes = serialize();
    const std::string tmp = path_ + ".tmp";
    StorageQuota* const q = quota_;
    if (q) {
      // A temporary left by a crash is replaced: removed first, given back.
      if (const auto old = StorageQuota::regular_file_size(tmp); old && ::unlink(tmp.c_str()) == 0) {
        q->release_file(*old);
      }
      if (!q->charge_file()) {
        return fail(fmt::format("state directory full: {} files", q->limits().max_files));
      }
      if (!q->charge_bytes(bytes.size())) {
        q->release_file(0);
        return fail(fmt::format("state directory full: {} more bytes would exceed {} bytes", bytes.size(),
                                q->limits().max_bytes));
      }
    }
    const auto give_back = [&] {
      if (q) q->release_file(bytes.size());
    };
    const int fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
    if (fd < 0) {
      const int saved = errno;
      give_back();
      return fail(fmt::format("cannot create {}: {}", tmp, std::strerror(saved)));
    }
    const bool ok = write_all(fd, bytes.data(), bytes.size()) && ::fsync(fd) == 0;
    const int saved = errno;
    ::close(fd);
    if (!ok) {
      ::unlink(tmp.c_str());
      give_back();
      return fail(fmt::format("cannot write {}: {}", tmp, std::strerror(saved)));
    }
    const auto replaced = StorageQuota::regular_file_size(path_);
    if (::rename(tmp.c_str(), path_.c_str()) != 0) {
      const int rename_errno = errno;
      ::unlink(tmp.c_str());
      give_back();
      return fail(fmt::format("cannot rename {} to {}: {}", tmp, path_, std::strerror(rename_errno)));
    }
    if (q && replaced) q->release_file(*replaced);
    // Make the rename itself durable.
    const int dir = ::open(directory_of(path_).c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
    if (dir >= 0) {
      (void)::fsync(dir);
      ::close(dir);
    }
    return {};
  } catch (const std::exception& e) {
    return fail(std::string(e.what()));
  }
}

Expected<void, std::string> ParameterStore::remove() const noexcept {
  if (path_.empty()) return fail(std::string("no parameter file configured"));
  const auto old = StorageQuota::regular_file_size(path_);
  if (::unlink(path_.c_str()) != 0) {
    if (errno == ENOENT) return {};
    return fail(fmt::format("cannot remove {}: {}", path_, std::strerror(errno)));
  }
  if (quota_ && old) quota_->release_file(*old);
  return {};
}

Expected<std::size_t, std::string> ParameterStore::load() noexcept {
  if (path_.empty()) return std::size_t{0};
  try {
    std::ifstream in(path_, std::ios::binary);
    if (!in) return std::size_t{0};  // no file: defaults
    const std::vector<std::uint8_t> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    if (bytes.size() < kFileHeader + kCrcSize) return fail(fmt::format("{}: too short", path_));
    const ConstBytes body(bytes.data(), bytes.size() - kCrcSize);
    if (crc32(body) != load_le<std::uint32_t>(bytes.data() + body.size())) {
      return fail(fmt::format("{}: checksum mismatch, file ignored", path_));
    }
    ByteReader r(body);
    if (r.u32() != kMagic) return fail(fmt::format("{}: not a parameter file", path_));
    if (const auto v = r.u16(); v != kVersion) return fail(fmt::format("{}: unsupported version {}", path_, v));
    r.skip(2);
    const std::uint32_t count = r.u32();
    // Check the whole file before applying anything.
    ByteReader check = r;
    for (std::uint32_t i = 0; i < count; ++i) {
      check.skip(3);
      check.skip(check.u32());
    }
    if (!check.ok() || check.remaining() != 0) return fail(fmt::format("{}: records malformed, file ignored", path_));
    std::size_t applied = 0;
    for (std::uint32_t i = 0; i < count; ++i) {
      const std::uint16_t index = r.u16();
      const std::uint8_t sub = r.u8();
      const ConstBytes value = r.bytes(r.u32());
      ObjectStore::Slot* s = store_.slot(index, sub);
      if (s && persistent(*s, index) && store_.assign(*s, value)) ++applied;
    }
    return applied;
  } catch (const std::exception& e) {
    return fail(fmt::format("{}: {}", path_, e.what()));
  }
}

Expected<void, SdoAbort> ParameterStore::on_write(ObjectStore&, const WriteRequest& r) noexcept {
  if (r.subindex == 0) return {};
  const auto value = static_cast<std::uint32_t>(load_bits(r.data, 32, false));
  const std::uint32_t wanted = r.index == kStoreParameters ? kSaveSignature : kLoadSignature;
  if (value != wanted) return fail(SdoAbort::DataTransfer);
  if (path_.empty()) return fail(SdoAbort::DataTransferLocalControl);
  // Sub 1 = all parameters; 2 (communication), 3 (application) and the
  // manufacturer ones store or restore the same single set.
  const auto done = r.index == kStoreParameters ? save() : remove();
  // CiA 301 §7.5.2.13 (store) and §7.5.2.14 (restore): "If the storing
  // failed, the CANopen device shall respond with ... abort code 0606 0000h".
  if (!done) return fail(SdoAbort::HardwareError);
  return {};
}

void ParameterStore::after_write(ObjectStore& store, std::uint16_t index, std::uint8_t subindex) noexcept {
  // The subs read back what the device can do, not the signature.
  if (subindex != 0) (void)store.set<std::uint32_t>(index, subindex, kStoresOnCommand);
}

void ParameterStore::on_read(ObjectStore& store, std::uint16_t index, std::uint8_t subindex) noexcept {
  if (subindex != 0) (void)store.set<std::uint32_t>(index, subindex, kStoresOnCommand);
}

}  // namespace ecat::coe
