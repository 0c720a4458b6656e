#include "slave/drive_application.hpp"

#include <chrono>
#include <filesystem>
#include <string_view>

#include "common/cache_line.hpp"
#include "ds402/drive.hpp"
#include "ds402/drive_config.hpp"
#include "ds402/motion_trace.hpp"
#include "ds402/od_binding.hpp"
#include "ds402/plant.hpp"
#include "ds402/svg_plot.hpp"
#include "slave/multi_axis_application.hpp"

namespace ecat::slave {
namespace {

// Rows kept for --plot: one minute of a 1 kHz cycle.
constexpr std::size_t kTraceRows = 60000;
// Length of the step that fills the inputs before the first cycle.
constexpr Nanoseconds kFirstStep = std::chrono::milliseconds(1);

// The seed drive a device file describes, by its file name
// ("welcon-servo.xml" -> "welcon"); the generic drive otherwise.
ds402::DriveConfig personality_for(const od::DeviceDescription& device) {
  const std::string stem = std::filesystem::path(device.source_file).stem().string();
  for (std::string_view name : ds402::personality_names()) {
    if (!stem.empty() && std::string_view(stem).substr(0, name.size()) == name) {
      if (auto p = ds402::drive_personality(name)) return ds402::apply_device(*p, device);
    }
  }
  return ds402::apply_device(ds402::generic_drive(), device);
}

class DriveApplication final : public Application {
 public:
  DriveApplication(ds402::DriveConfig config, const ds402::PlantParameters& plant, coe::CoeServer& coe,
                   bool trace)
      : process_data_(coe.process_data()),
        tracing_(trace),
        drive_(std::move(config), plant),
        binding_(coe.objects(), &coe.emergency()),
        trace_(trace ? kTraceRows : 0) {
    binding_.publish(drive_.config());
    // Inputs are valid from the first SafeOp cycle: fill them once now.
    binding_.read(in_);
    drive_.step(in_, out_, kFirstStep);
    binding_.write(out_, drive_.emergencies());
  }

  void cycle(Nanoseconds dt, bool outputs_valid) noexcept override {
    // The mapped inputs every cycle, the others when something else wrote
    // the dictionary (DriveBinding::read_cycle).
    binding_.read_cycle(in_, process_data_.output_items());
    if (!outputs_valid) {
      // SafeOp: outputs are kept in their safe state (ETG.1000.6 §6.4.1):
      // the drive sees no enable command. A full copy next cycle restores
      // the controlword if it is not mapped.
      in_.controlword = 0;
      binding_.invalidate();
    }
    drive_.step(in_, out_, dt);
    binding_.write(out_, drive_.emergencies(), elapsed_);
    elapsed_ += dt;
    if (tracing_) trace_.record(std::chrono::duration<double>(elapsed_).count(), in_, out_);
  }

  ds402::Drive* drive(std::size_t axis) noexcept override { return axis == 0 ? &drive_ : nullptr; }
  bool has_motion_trace() const noexcept override { return tracing_; }
  Expected<void, std::string> write_plot(const std::string& path) const override {
    return ds402::write_svg_plot(trace_.rows(), path);
  }

 private:
  // In the order a cycle reads them (issue 30 item 1: at 1000 drives each
  // line a drive's cycle reads is a cache miss): the small members in the
  // object's first line (with its vtable pointer), the drive (its own
  // lines), then the outputs and what a cycle reads of the inputs in three
  // lines (the drive ends on a line's end: ds402/objects.hpp), and the
  // binding, whose cycle data fills the first three lines of its own.
  coe::ProcessData& process_data_;
  Nanoseconds elapsed_{0};
  bool tracing_;
  ds402::Drive drive_;
  ds402::DriveOutputs out_{};
  ds402::DriveInputs in_{};
  alignas(kCacheLineBytes) ds402::DriveBinding binding_;
  ds402::MotionTrace trace_;
};

}  // namespace

Expected<void, std::string> check_drive(const od::DeviceDescription& device) {
  if (!device.drive) return {};
  auto plant = ds402::plant_parameters_from(device.drive->plant);
  if (!plant) return fail(plant.error());
  return {};
}

std::unique_ptr<Application> make_drive_application(const od::DeviceDescription& device, coe::CoeServer& coe,
                                                    bool motion_trace) {
  if (!device.drive) return nullptr;
  auto plant = ds402::plant_parameters_from(device.drive->plant);
  if (!plant) return nullptr;  // refused earlier by check_drive
  if (device.drive->axes.axes > 1) {
    return make_multi_axis_application(personality_for(device), *plant, device.drive->axes, coe, motion_trace);
  }
  return std::make_unique<DriveApplication>(personality_for(device), *plant, coe, motion_trace);
}

}  // namespace ecat::slave
