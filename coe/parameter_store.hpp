// Store parameters 1010h / restore default parameters 1011h (CiA 301
// §7.5.2.13-14; shared/spec/coe-mailbox.md §11.5). Writing "save"
// (0x65766173) to 1010h sub >= 1 writes the values of every writable entry
// to the parameter file; writing "load" (0x64616F6C) to 1011h removes it, so
// the defaults apply from the next start, as CiA 301 says. Any other value
// is refused with 08000020; without a configured file, 08000021. A store
// or restore that fails (I/O error, or the state directory's StorageQuota
// would be exceeded) aborts with 06060000 "access failed due to a hardware
// error", as CiA 301 §7.5.2.13/§7.5.2.14 prescribes for a failed store or
// restore; the previous file is then untouched and no temporary is left.
//
// File: "ECPS", version, count, records (index, subindex, length, bytes),
// CRC-32 of everything before it. Written atomically (temporary file, fsync,
// rename, fsync of the directory). A file that fails its checks is ignored
// with a warning and left on disk; the values stay as they were.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "coe/object_hooks.hpp"
#include "coe/object_store.hpp"
#include "coe/storage_quota.hpp"
#include "common/expected.hpp"

namespace ecat::coe {

class ParameterStore final : public ObjectHooks {
 public:
  static constexpr std::uint16_t kStoreParameters = 0x1010;
  static constexpr std::uint16_t kRestoreDefaults = 0x1011;
  static constexpr std::uint32_t kSaveSignature = 0x65766173;  // "save"
  static constexpr std::uint32_t kLoadSignature = 0x64616F6C;  // "load"
  static constexpr std::uint32_t kStoresOnCommand = 0x00000001;  // read value of 1010h/1011h subs
  static constexpr std::uint32_t kMagic = 0x53504345;            // "ECPS"
  static constexpr std::uint16_t kVersion = 1;

  // Registers itself on 1010h and 1011h. An empty path disables storing.
  // `quota` (may be null) is charged for the file and must outlive this.
  ParameterStore(ObjectStore& store, std::string path, StorageQuota* quota = nullptr);

  // Applies the file's values (start-up). Returns how many were applied, or
  // why the file was ignored ("" when there is no file).
  Expected<std::size_t, std::string> load() noexcept;
  Expected<void, std::string> save() const noexcept;
  Expected<void, std::string> remove() const noexcept;

  // Entries that go into the file: writable, not const, not 1010h/1011h.
  static bool persistent(const ObjectStore::Slot& slot, std::uint16_t index) noexcept;

  Expected<void, SdoAbort> on_write(ObjectStore& store, const WriteRequest& request) noexcept override;
  void after_write(ObjectStore& store, std::uint16_t index, std::uint8_t subindex) noexcept override;
  void on_read(ObjectStore& store, std::uint16_t index, std::uint8_t subindex) noexcept override;

  const std::string& path() const noexcept { return path_; }

 private:
  std::vector<std::uint8_t> serialize() const;

  ObjectStore& store_;
  std::string path_;
  StorageQuota* quota_ = nullptr;
};

// CRC-32 (IEEE 802.3 polynomial, reflected), as zlib computes it.
std::uint32_t crc32(ConstBytes data) noexcept;

}  // namespace ecat::coe
