// PDO configuration (ETG.1000.6 §5.6.7.4.7-9, CiA 301 §7.5.2.35-36): hooks on
// the mapping objects 1600h-17FFh / 1A00h-1BFFh and the assignments
// 1C12h/1C13h that
//  - refuse writes outside PreOp (08000022),
//  - check each write: entries only while sub 0 = 0 (06010003), entries
//    existing and mappable in the PDO's direction with their own bit length
//    (06040041), sub 0 not above the entries (06090031), assigned PDOs in the
//    right range (06090030), total length within the SM's maximum (06040042),
//  - recompute the process-data layout after each accepted write;
// and the PreOp->SafeOp check against the SM2/SM3 settings the master made
// (AL 001Dh/001Eh for SM length or enable, 0025h/0024h for a bad mapping).
#pragma once

#include <cstdint>

#include "coe/object_hooks.hpp"
#include "coe/object_store.hpp"
#include "coe/pdo_mapping.hpp"
#include "coe/process_data_image.hpp"
#include "esc/al_status_code.hpp"
#include "esc/pdi.hpp"
#include "od/device.hpp"

namespace ecat::coe {

class PdoConfig final : public ObjectHooks {
 public:
  // Registers itself as the hooks of every mapping/assignment object present.
  PdoConfig(ObjectStore& store, const od::DeviceDescription& device);

  Expected<void, SdoAbort> on_write(ObjectStore& store, const WriteRequest& request) noexcept override;
  void after_write(ObjectStore& store, std::uint16_t index, std::uint8_t subindex) noexcept override;

  // Layout from the current object values.
  void rebuild() noexcept;
  const ProcessDataImage& outputs() const noexcept { return outputs_; }
  const ProcessDataImage& inputs() const noexcept { return inputs_; }

  // Whole-direction check of the current values (as at PreOp->SafeOp).
  Expected<void, SdoAbort> validate(PdoDirection d) const noexcept;
  // PreOp->SafeOp: mapping valid, SM2/SM3 enabled with the image's length
  // (or unused when the image is empty).
  esc::AlStatusCode check_safeop(esc::Pdi& pdi) noexcept;

  // Largest SM2/SM3 payload in bytes (the SM's max size, else the ESC RAM).
  std::uint32_t max_bytes(PdoDirection d) const noexcept { return d == PdoDirection::Rx ? max_rx_ : max_tx_; }

 private:
  // `fixed`: an entry of a read-only mapping (the device's own fixed PDO),
  // which may map the low bits of a longer object (docs/twins.md,
  // alternative PDOs of two lengths); an entry a master writes must match.
  Expected<void, SdoAbort> check_entry(PdoDirection d, std::uint32_t value, bool fixed = false) const noexcept;
  // Bits of a mapping object with `count` entries, one entry replaced if `sub` != 0.
  Expected<std::uint32_t, SdoAbort> mapping_bits(PdoDirection d, std::uint16_t index, std::uint8_t count,
                                                 std::uint8_t sub = 0, std::uint32_t value = 0) const noexcept;
  // Bits of the assigned PDOs, with one mapping's length replaced.
  Expected<std::uint32_t, SdoAbort> assigned_bits(PdoDirection d, std::uint8_t count, std::uint8_t sub = 0,
                                                  std::uint16_t pdo = 0, std::uint16_t changed_mapping = 0,
                                                  std::uint32_t changed_bits = 0) const noexcept;
  Expected<void, SdoAbort> check_mapping_write(PdoDirection d, const WriteRequest& r) const noexcept;
  Expected<void, SdoAbort> check_assign_write(PdoDirection d, const WriteRequest& r) const noexcept;
  void build(PdoDirection d, ProcessDataImage& image) noexcept;

  ObjectStore& store_;
  std::uint32_t max_rx_ = 0;
  std::uint32_t max_tx_ = 0;
  ProcessDataImage outputs_;
  ProcessDataImage inputs_;
};

}  // namespace ecat::coe
