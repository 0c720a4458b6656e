// Pre-defined error field 1003h (CiA 301 §7.5.2.3): the errors signalled by
// emergency, newest first. 1003h:00 is the number of errors kept, 1003h:01
// the newest (bits 0-15 the emergency error code, bits 16-31 additional
// information: here the first two manufacturer bytes of the EMCY). A new
// error moves the older ones one subindex up; beyond the last subindex the
// oldest is lost. Writing 0 to 1003h:00 clears the field; any other value is
// refused with 06090030h (value range). Active only on a device whose
// dictionary has 1003h with at least one entry subindex (the depth is the
// device's); "error reset" (code 0000h) is not an error and is not kept.
#pragma once

#include <array>
#include <cstdint>

#include "coe/object_hooks.hpp"
#include "coe/object_store.hpp"

namespace ecat::coe {

class ErrorField final : public ObjectHooks {
 public:
  static constexpr std::uint16_t kIndex = 0x1003;

  explicit ErrorField(ObjectStore& store) noexcept;
  ErrorField(const ErrorField&) = delete;
  ErrorField& operator=(const ErrorField&) = delete;

  bool active() const noexcept { return depth_ > 0; }
  std::size_t depth() const noexcept { return depth_; }
  // Records one error (an emergency other than 0000h).
  void add(std::uint16_t error_code, std::uint16_t additional = 0) noexcept;

  Expected<void, SdoAbort> on_write(ObjectStore& store, const WriteRequest& request) noexcept override;
  void after_write(ObjectStore& store, std::uint16_t index, std::uint8_t subindex) noexcept override;

 private:
  void clear() noexcept;

  ObjectStore& store_;
  std::size_t depth_ = 0;
};

}  // namespace ecat::coe
