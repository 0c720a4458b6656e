// Per-index behaviour hooks (STYLE lesson 5, after CANopenNode's
// OD_extension_t): registered once at start-up for one object index, called
// by the SDO server for every access to that object's entries, whether the
// access is expedited, segmented or complete access. Virtual calls on plain
// objects; no std::function, no allocation.
#pragma once

#include <cstdint>

#include "coe/sdo_abort.hpp"
#include "common/expected.hpp"
#include "common/le.hpp"
#include "od/access.hpp"

namespace ecat::coe {

class ObjectStore;

// One write about to be committed: the new bytes and the ESM state the
// request arrived in.
struct WriteRequest {
  std::uint16_t index = 0;
  std::uint8_t subindex = 0;
  ConstBytes data;
  od::EsmState state = od::EsmState::PreOp;
};

class ObjectHooks {
 public:
  virtual ~ObjectHooks() = default;
  // Before an entry is read over the mailbox: may refresh the stored value
  // (e.g. a measured quantity) with ObjectStore::assign/set.
  virtual void on_read(ObjectStore& store, std::uint16_t index, std::uint8_t subindex) noexcept {
    (void)store;
    (void)index;
    (void)subindex;
  }
  // Before a write is committed (after the store's own length and range
  // checks). Return an abort to refuse it; the stored value is then unchanged.
  virtual Expected<void, SdoAbort> on_write(ObjectStore& store, const WriteRequest& request) noexcept {
    (void)store;
    (void)request;
    return {};
  }
  // After the new value was committed.
  virtual void after_write(ObjectStore& store, std::uint16_t index, std::uint8_t subindex) noexcept {
    (void)store;
    (void)index;
    (void)subindex;
  }
};

}  // namespace ecat::coe
