// SDO complete access (ETG.1000.6 §5.6.2.1.2/§5.6.2.2.2; shared/spec/coe-mailbox.md
// §5.3): a whole ARRAY/RECORD in one transfer. Starting at subindex 0, sub 0
// sits in a 16-bit slot (value + pad byte); starting at 1 it is left out.
// Entries whose bit length is a multiple of 8 start on a byte boundary;
// shorter ones (BOOLEAN, BITn) are packed LSB first. Entries up to the value
// of sub 0 are transferred; missing subindices take no room.
#pragma once

#include <cstdint>

#include "coe/object_store.hpp"
#include "coe/sdo_abort.hpp"
#include "common/expected.hpp"
#include "od/access.hpp"

namespace ecat::coe {

// Bytes of the image of `object` with entries 1..`count`.
Expected<std::size_t, SdoAbort> complete_access_size(const od::Object& object, bool from_sub0,
                                                     std::uint8_t count) noexcept;

// The largest image of any object in the dictionary (for buffer sizing).
std::size_t max_complete_access_size(const od::Dictionary& dictionary) noexcept;

// Reads the object into `out`; write-only entries read as 0; an entry not
// readable in `state` but readable in another gives 08000022.
Expected<std::size_t, SdoAbort> complete_access_upload(ObjectStore& store, std::uint16_t index,
                                                       bool from_sub0, Bytes out,
                                                       od::EsmState state) noexcept;

// Writes the object from `data`: sub 0 (if from_sub0 and writable) is set to
// 0 first and to its new value last, so mapping rules (sub 0 = 0 while
// entries change) hold; read-only entries are skipped. `scratch` (at least
// the object's total capacity) keeps the old values: on any refusal they are
// put back and the abort returned.
Expected<void, SdoAbort> complete_access_download(ObjectStore& store, std::uint16_t index, bool from_sub0,
                                                  ConstBytes data, od::EsmState state,
                                                  Bytes scratch) noexcept;

}  // namespace ecat::coe
