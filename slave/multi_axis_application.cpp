#include "slave/multi_axis_application.hpp"

#include <array>
#include <chrono>
#include <string>
#include <vector>

#include "ds402/drive.hpp"
#include "ds402/motion_trace.hpp"
#include "ds402/od_binding.hpp"
#include "ds402/svg_plot_axes.hpp"

namespace ecat::slave {
namespace {

// Rows kept per axis for --plot: one minute of a 1 kHz cycle.
constexpr std::size_t kTraceRows = 60000;
// Length of the step that fills the inputs before the first cycle.
constexpr Nanoseconds kFirstStep = std::chrono::milliseconds(1);

struct AxisRun {
  AxisRun(const ds402::DriveConfig& config, const ds402::PlantParameters& plant, coe::CoeServer& coe,
          const od::AxisLayout& layout, unsigned axis, bool tracing)
      : drive(config, plant), binding(coe.objects(), &coe.emergency(), layout, axis), trace(tracing ? kTraceRows : 0) {}
  ds402::Drive drive;
  ds402::DriveBinding binding;
  ds402::MotionTrace trace;
  ds402::DriveInputs in{};
  ds402::DriveOutputs out{};
};

class MultiAxisApplication final : public Application {
 public:
  MultiAxisApplication(const ds402::DriveConfig& config, const ds402::PlantParameters& plant,
                       const od::AxisLayout& layout, coe::CoeServer& coe, bool trace)
      : process_data_(coe.process_data()), tracing_(trace) {
    axes_.reserve(layout.axes);
    for (unsigned a = 1; a <= layout.axes; ++a) {
      axes_.push_back(std::make_unique<AxisRun>(config, plant, coe, layout, a, trace));
    }
    for (auto& x : axes_) x->binding.publish(x->drive.config());
    // Inputs are valid from the first SafeOp cycle: fill them once now.
    for (auto& x : axes_) {
      x->binding.read(x->in);
      x->drive.step(x->in, x->out, kFirstStep);
    }
    write_all();
  }

  void cycle(Nanoseconds dt, bool outputs_valid) noexcept override {
    for (auto& x : axes_) {
      x->binding.read_cycle(x->in, process_data_.output_items());
      if (!outputs_valid) {
        // SafeOp: outputs in their safe state (ETG.1000.6 §6.4.1), as for one axis.
        x->in.controlword = 0;
        x->binding.invalidate();
      }
      x->drive.step(x->in, x->out, dt);
    }
    write_all();
    elapsed_ += dt;
    if (tracing_) {
      const double t = std::chrono::duration<double>(elapsed_).count();
      for (auto& x : axes_) x->trace.record(t, x->in, x->out);
    }
  }

  ds402::Drive* drive(std::size_t axis) noexcept override {
    return axis < axes_.size() ? &axes_[axis]->drive : nullptr;
  }
  bool has_motion_trace() const noexcept override { return tracing_; }
  Expected<void, std::string> write_plot(const std::string& path) const override {
    if (!tracing_) return fail(path + ": this slave records no motion trace");
    std::vector<ds402::AxisTrace> traces;
    for (const auto& x : axes_) traces.push_back({"axis " + std::to_string(x->binding.axis()), x->trace.rows()});
    return ds402::write_svg_plot_axes(traces, path);
  }

 private:
  // Every axis' outputs and emergencies; 1001h is the device's: each axis'
  // error register with the others' bits (CiA 301 §7.5.2.2).
  void write_all() noexcept {
    current_.fill(false);
    for (std::size_t k = 0; k < axes_.size() && k < current_.size(); ++k) current_[k] = axes_[k]->binding.inputs_current();
    for (std::size_t k = 0; k < axes_.size(); ++k) {
      std::uint8_t others = 0;
      for (std::size_t j = 0; j < axes_.size(); ++j) {
        if (j != k) others = static_cast<std::uint8_t>(others | axes_[j]->out.error_register);
      }
      axes_[k]->binding.write_axis(axes_[k]->out, axes_[k]->drive.emergencies(), elapsed_, others);
    }
    // One axis' outputs are no input of another: those that had read the
    // store as it was keep it as seen (no full re-read next cycle).
    for (std::size_t k = 0; k < axes_.size() && k < current_.size(); ++k) {
      if (current_[k]) axes_[k]->binding.mark_current();
    }
  }

  std::vector<std::unique_ptr<AxisRun>> axes_;
  coe::ProcessData& process_data_;
  std::array<bool, 8> current_{};  // CiA 402-1 §6: at most eight axes
  Nanoseconds elapsed_{0};
  bool tracing_;
};

}  // namespace

std::unique_ptr<Application> make_multi_axis_application(const ds402::DriveConfig& config,
                                                         const ds402::PlantParameters& plant,
                                                         const od::AxisLayout& layout, coe::CoeServer& coe,
                                                         bool motion_trace) {
  return std::make_unique<MultiAxisApplication>(config, plant, layout, coe, motion_trace);
}

}  // namespace ecat::slave
