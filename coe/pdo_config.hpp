// PDO configuration (ETG.1000.6 §5.6.7.4.7-9, CiA 301 §7.5.2.35-36): hooks on
// the mapping objects 1600h-17FFh / 1A00h-1BFFh and the assignments
// 1C12h/1C13h that
//  - refuse writes outside PreOp (08000022),
//  - check each write: entries only while sub 0 = 0 (06010003), entries
//    existing and mappable in the PDO's direction with their own bit length
//    (06040041), sub 0 not above the entries (06090031), assigned PDOs in the
//    right range (06090030), total length within the SM's maximum (06040042),
//  - recompute the process-data layout after each accepted write;
// and the PreOp->SafeOp check against the SM settings the master made
// (AL 001Dh/001Eh for SM length or enable, 0025h/0024h for a bad mapping).
// One layout per process-data SM: SM n carries the PDOs its assignment
// object 1C10h+n lists (ETG.1000.6 §5.6.7.4.2), SM2/SM3 (1C12h/1C13h) on
// most devices, several SMs per direction on some (Beckhoff EK1828: outputs
// on SM0 and SM1, 1C10h/1C11h; inputs on SM2, 1C12h).
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "coe/object_hooks.hpp"
#include "coe/object_store.hpp"
#include "coe/pdo_mapping.hpp"
#include "coe/process_data_image.hpp"
#include "common/cache_line.hpp"
#include "esc/al_status_code.hpp"
#include "esc/pdi.hpp"
#include "od/device.hpp"

namespace ecat::coe {

// One process-data SM and the layout of what it carries. One cache line,
// aligned to one (issue 30 item 1): coe::ProcessData reads its image's
// items, bit length and generation when the PdoConfig rebuilt (it read
// them every cycle until session 29; docs/performance-log.md).
struct alignas(kCacheLineBytes) SmLayout {
  std::uint8_t sm = 0;
  PdoDirection direction = PdoDirection::Rx;
  std::uint16_t assign = 0;      // 1C10h + sm
  std::uint32_t max_bytes = 0;   // the SM's maximum size, else the ESC RAM
  // False for a direction the device has no PDOs for (an inputs-only NI
  // 9144's SM2): not checked, nothing copied (od::has_process_data).
  bool checked = true;
  ProcessDataImage image;
};
static_assert(sizeof(void*) != 8 || sizeof(SmLayout) == kCacheLineBytes, "one cache line");

class PdoConfig final : public ObjectHooks {
 public:
  // Registers itself as the hooks of every mapping/assignment object present.
  PdoConfig(ObjectStore& store, const od::DeviceDescription& device);

  Expected<void, SdoAbort> on_write(ObjectStore& store, const WriteRequest& request) noexcept override;
  void after_write(ObjectStore& store, std::uint16_t index, std::uint8_t subindex) noexcept override;

  // Layout from the current object values.
  void rebuild() noexcept;
  // Each rebuild() adds one to `*counter` (the images may have changed):
  // coe::ProcessData looks at its images again only then, rather than at
  // each image's generation every cycle (issue 30 item 1: their lines).
  // The counter outlives this PdoConfig's rebuilds; nullptr: none.
  void count_rebuilds_in(std::uint64_t* counter) noexcept { rebuilds_ = counter; }
  // The first SM of each direction (SM2/SM3 on most devices); an empty
  // layout when the device has none.
  const ProcessDataImage& outputs() const noexcept;
  const ProcessDataImage& inputs() const noexcept;
  // Every process-data SM, in SM order.
  std::span<const SmLayout> sms() const noexcept { return sms_; }

  // Whole-direction check of the current values (as at PreOp->SafeOp).
  Expected<void, SdoAbort> validate(PdoDirection d) const noexcept;
  // PreOp->SafeOp: mappings valid, each process-data SM enabled with its
  // image's length (or unused when the image is empty).
  esc::AlStatusCode check_safeop(esc::Pdi& pdi) noexcept;

  // Largest payload in bytes of an SM of the direction (the SM's max size,
  // else the ESC RAM).
  std::uint32_t max_bytes(PdoDirection d) const noexcept;

 private:
  // `fixed`: an entry of a read-only mapping (the device's own fixed PDO),
  // which may map the low bits of a longer object (docs/twins.md,
  // alternative PDOs of two lengths); an entry a master writes must match.
  Expected<void, SdoAbort> check_entry(PdoDirection d, std::uint32_t value, bool fixed = false) const noexcept;
  // Bits of a mapping object with `count` entries, one entry replaced if `sub` != 0.
  Expected<std::uint32_t, SdoAbort> mapping_bits(PdoDirection d, std::uint16_t index, std::uint8_t count,
                                                 std::uint8_t sub = 0, std::uint32_t value = 0) const noexcept;
  // Bits of the PDOs an SM's assignment lists, with one mapping's length replaced.
  Expected<std::uint32_t, SdoAbort> assigned_bits(const SmLayout& sm, std::uint8_t count, std::uint8_t sub = 0,
                                                  std::uint16_t pdo = 0, std::uint16_t changed_mapping = 0,
                                                  std::uint32_t changed_bits = 0) const noexcept;
  Expected<void, SdoAbort> check_mapping_write(PdoDirection d, const WriteRequest& r) const noexcept;
  Expected<void, SdoAbort> check_assign_write(const SmLayout& sm, const WriteRequest& r) const noexcept;
  Expected<void, SdoAbort> validate(const SmLayout& sm) const noexcept;
  const SmLayout* sm_of_assign(std::uint16_t index) const noexcept;
  void build(SmLayout& sm) noexcept;

  ObjectStore& store_;
  std::vector<SmLayout> sms_;  // fixed after construction: images stay in place
  ProcessDataImage empty_;
  std::uint64_t* rebuilds_ = nullptr;
};

}  // namespace ecat::coe
