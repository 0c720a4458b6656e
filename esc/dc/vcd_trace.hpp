// Value Change Dump (IEEE 1364 §18) of what a slave's timing looks like:
// SYNC0/SYNC1 outputs, SM2/SM3 events, application cycle and ESM state, per
// slave, viewable in GTKWave (`--trace FILE.vcd`). Signals are declared at
// construction; values are written as they come, clamped to be monotonic.
// Writes go through a fixed buffer to a caller-owned FILE (no heap per event).
#pragma once

#include <array>
#include <cstdint>
#include <cstdio>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "common/clock.hpp"
#include "esc/al_status_code.hpp"
#include "esc/dc/dc_unit.hpp"
#include "esc/esm_hooks.hpp"

namespace ecat::esc {

class VcdTrace;

// One slave's signals; hand it to DcUnit::set_observer and Esm::add_hooks.
class VcdProbe final : public DcObserver, public EsmHooks {
 public:
  // Width of the marker pulse drawn for instantaneous events (SM events).
  static constexpr Nanoseconds kEventWidth{200};

  void on_sync(unsigned signal, bool level, Nanoseconds t) noexcept override;
  void on_state_changed(AlState from, AlState to, AlStatusCode code) noexcept override;
  void sm_event(unsigned sm, Nanoseconds t) noexcept;       // SM2 or SM3
  void app_cycle(bool running, Nanoseconds t) noexcept;

 private:
  friend class VcdTrace;
  VcdTrace* trace_ = nullptr;
  unsigned index_ = 0;
};

class VcdTrace {
 public:
  enum Signal : unsigned { kSync0, kSync1, kSm2, kSm3, kAppCycle, kEsmState, kSignals };

  // `out` stays owned by the caller; `clock` timestamps ESM changes.
  VcdTrace(std::FILE* out, std::span<const std::string> slave_names, const Clock& clock);
  ~VcdTrace();
  VcdTrace(const VcdTrace&) = delete;
  VcdTrace& operator=(const VcdTrace&) = delete;

  VcdProbe& probe(std::size_t slave) noexcept { return probes_[slave]; }
  // Writes a value change (and any marker pulse ends due before t).
  void change(unsigned slave, Signal s, std::uint32_t value, Nanoseconds t) noexcept;
  void marker(unsigned slave, Signal s, Nanoseconds t) noexcept;
  // Writes what is buffered; false once any write to the file has failed or
  // come up short.
  bool flush() noexcept;
  // The last flush; the file is not touched again (the caller closes it).
  bool finish() noexcept;
  const Clock& clock() const noexcept { return clock_; }

 private:
  void header(std::span<const std::string> names);
  void advance(Nanoseconds t) noexcept;
  void put(std::string_view text) noexcept;
  void put_id(unsigned slave, Signal s) noexcept;
  void end_markers_before(Nanoseconds t) noexcept;

  static constexpr std::size_t kBufferSize = 8192;
  std::FILE* out_;
  const Clock& clock_;
  std::vector<VcdProbe> probes_;
  std::vector<std::array<std::int64_t, kSignals>> marker_end_;  // -1 = none pending
  std::array<char, kBufferSize> buffer_{};
  std::size_t used_ = 0;
  std::int64_t now_ = -1;
  bool failed_ = false;
};

}  // namespace ecat::esc
