// Copies the drive's objects between the CoE object store and the plain
// DriveInputs/DriveOutputs each cycle, and forwards the drive's emergency
// requests to CoE. Every entry is looked up once at set-up; an object the
// device does not have is skipped (its DriveInputs field keeps its default).
// No allocation and no lookup per cycle.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <span>

#include "coe/emergency.hpp"
#include "coe/object_store.hpp"
#include "coe/process_data_image.hpp"
#include "common/clock.hpp"
#include "ds402/drive_config.hpp"
#include "ds402/faults.hpp"
#include "ds402/objects.hpp"
#include "ds402/od_hooks.hpp"
#include "od/axis_layout.hpp"

namespace ecat::ds402 {

// Notes SDO writes of 60C1h:01 in `written` (the binding's flag, which its
// cycle reads with its other per-cycle members): each is a record for the
// interpolation buffer (60C4h). PDO writes do not pass the hooks;
// DriveBinding counts a record per cycle for an RxPDO that maps 60C1h:01.
class IpRecordHook final : public coe::ObjectHooks {
 public:
  explicit IpRecordHook(bool& written) noexcept : written_(written) {}
  Expected<void, coe::SdoAbort> on_write(coe::ObjectStore& store, const coe::WriteRequest& request) noexcept override;

 private:
  bool& written_;
};

class DriveBinding {
 public:
  static constexpr std::size_t kInputCount = 69;
  static constexpr std::size_t kOutputCount = 22;

  // `emergency` may be null (then 1001h is written from DriveOutputs instead).
  DriveBinding(coe::ObjectStore& store, coe::Emergency* emergency = nullptr) noexcept;
  // Axis `axis` (1-based) of a multi-axis device: its objects where `layout`
  // puts them (CiA 402-1 §6, +800h per axis), 1001h shared with the other
  // axes (see write()), and EMCY byte 3 = the axis number (docs/ds402.md
  // "Several axes"). Set-up allocates nothing here either.
  DriveBinding(coe::ObjectStore& store, coe::Emergency* emergency, const od::AxisLayout& layout,
               unsigned axis) noexcept;
  // The store keeps a pointer to the hooks inside: the binding stays put.
  DriveBinding(const DriveBinding&) = delete;
  DriveBinding& operator=(const DriveBinding&) = delete;

  // Writes what the drive offers: 6502h supported modes and 60E3h supported
  // homing methods (as many as the array has room for), binds the
  // personality's homing current threshold object, and installs the SDO checks of DriveObjectHooks on 6060h, 6098h, 605Ah-605Eh. Set-up only.
  void publish(const DriveConfig& config);

  // Store -> inputs, before Drive::step: every bound entry. `in.sync_lost`
  // and `in.ip_record_new` are not touched (read_cycle sets the latter).
  void read(DriveInputs& in) const noexcept;
  // The same for a cycle (issue 8): every bound entry when the store was
  // written through anything but storage() since the last call or write()
  // (ObjectStore::generation: SDO downloads, parameters, the application)
  // or when `rx_pdo` changed, else only the entries mapped in `rx_pdo` - the
  // ones the RxPDO copy (coe::ProcessData::read_outputs) writes each cycle.
  // `in` must hold what the last call left in it. Sets `in.ip_record_new`
  // when 60C1h:01 was written by SDO since the last call or `rx_pdo` maps it.
  void read_cycle(DriveInputs& in, std::span<const coe::PdoItem> rx_pdo) noexcept;
  // The next read_cycle() copies every entry (the caller changed `in`).
  void invalidate() noexcept { seen_ = kNotRead; }
  // Outputs -> store, after Drive::step, then the emergency requests.
  void write(const DriveOutputs& out, EmcyQueue& emergencies, Nanoseconds now = Nanoseconds{0}) noexcept;
  // The same for one axis of a multi-axis device, without the read_cycle
  // bookkeeping (see inputs_current()). `other_axes` is the OR of the other
  // axes' error registers: 1001h and each EMCY's error register byte are the
  // device's, this axis' bits together with theirs (CiA 301 §7.5.2.2: one
  // 1001h); EMCY byte 3 is the axis number.
  void write_axis(const DriveOutputs& out, EmcyQueue& emergencies, Nanoseconds now,
                  std::uint8_t other_axes) noexcept;
  // Whether the inputs read_cycle() last saw are still those in the store;
  // mark_current() records the store as seen. A multi-axis application asks
  // every axis before the writes of the cycle and marks those that were
  // current after them, so one axis' outputs do not make the others re-read
  // every entry.
  bool inputs_current() const noexcept { return store_.generation() == seen_; }
  void mark_current() noexcept { seen_ = store_.generation(); }
  unsigned axis() const noexcept { return axis_; }

  std::size_t bound_inputs() const noexcept;
  std::size_t bound_outputs() const noexcept;
  // Emergencies CoE could not queue (mailbox closed or full).
  std::uint32_t emergencies_lost() const noexcept { return emergencies_lost_; }

 private:
  // What read_cycle() and write_objects() read every cycle, together at the
  // front of the object (issue 30 item 1: at 1000 drives each line a drive's
  // cycle touches is a cache miss; these were spread over ten), in three
  // cache lines when the binding starts one (slave::DriveApplication).
  coe::ObjectStore& store_;
  std::uint8_t* values_;  // store_.values()
  // read_cycle: the generation the inputs were last read at (kNotRead:
  // never), the RxPDO table they were read for, and the inputs it maps.
  std::uint64_t seen_ = kNotRead;
  std::span<const coe::PdoItem> rx_pdo_;
  coe::Emergency* emergency_ = nullptr;
  std::uint8_t mapped_count_ = 0;
  bool ip_record_mapped_ = false;  // rx_pdo_ maps 60C1h:01
  bool ip_record_written_ = false;  // by SDO since the last read_cycle (ip_record_hook_)
  // Where each bound entry's value bytes are (an offset into values_) when
  // they are read and written in place each cycle (the entry's width is its
  // field's); kConvert where the value needs conversion (another width: it
  // goes through the store), kAbsent where the device lacks the entry.
  static constexpr std::uint32_t kAbsent = ~std::uint32_t{0};
  static constexpr std::uint32_t kConvert = kAbsent - 1;
  std::array<std::uint32_t, kOutputCount> out_at_{};
  // A mapped input: where its value bytes are, the field they go to and
  // their size (0: another width, the typed reader is called), and its index
  // (into in_ and the reader table).
  struct Mapped {
    std::uint32_t at = kAbsent;
    std::uint16_t field_offset = 0;
    std::uint8_t size = 0;
    std::uint8_t input = 0;
  };
  static_assert(kInputCount <= 0x100, "Mapped::input and mapped_count_ are one byte");
  std::array<Mapped, kInputCount> mapped_{};

  std::array<coe::ObjectStore::Slot*, kInputCount> in_{};
  std::array<coe::ObjectStore::Slot*, kOutputCount> out_{};
  std::array<std::uint32_t, kInputCount> in_at_{};  // as out_at_
  template <typename T>
  std::uint32_t value_at(const coe::ObjectStore::Slot* s) const noexcept;  // set-up: out_at_'s encoding
  coe::ObjectStore::Slot* error_register_ = nullptr;
  // The personality's homing current threshold (Welcon 2402h), bound in publish().
  coe::ObjectStore::Slot* homing_current_threshold_ = nullptr;
  template <std::size_t N>
  void read_input(DriveInputs& in) const noexcept;
  [[gnu::noinline]] void read_all(DriveInputs& in, std::span<const coe::PdoItem> rx_pdo) noexcept;
  void write_objects(const DriveOutputs& out, EmcyQueue& emergencies, Nanoseconds now) noexcept;
  static constexpr std::uint64_t kNotRead = ~std::uint64_t{0};
  template <std::size_t N>
  static void read_one(const DriveBinding& b, DriveInputs& in) noexcept;
  using Reader = void (*)(const DriveBinding&, DriveInputs&) noexcept;
  static Reader reader(std::size_t i) noexcept;
  DriveObjectHooks hooks_;
  IpRecordHook ip_record_hook_{ip_record_written_};
  const coe::ObjectStore::Slot* ip_record_ = nullptr;  // 60C1h:01 of this axis
  od::AxisLayout layout_;  // set-up only (publish)
  unsigned axis_ = 1;
  bool multi_axis_ = false;
  std::uint32_t emergencies_lost_ = 0;
};

}  // namespace ecat::ds402
