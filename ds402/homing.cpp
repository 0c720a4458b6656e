#include "ds402/homing.hpp"

#include <cmath>

namespace ecat::ds402 {

namespace {
using Kind = HomingMethod::Kind;

constexpr std::int8_t kFirstSwitchMethod = 1;
constexpr std::int8_t kLastIndexSwitchMethod = 14;
constexpr std::int8_t kFirstEdgeOnlyMethod = 17;  // 17-30 = 1-14 without the index pulse
constexpr std::int8_t kLastEdgeOnlyMethod = 30;
constexpr std::int8_t kIndexNegative = 33;
constexpr std::int8_t kIndexPositive = 34;
constexpr std::int8_t kCurrentPosition = 35;
constexpr std::int8_t kCurrentPositionNew = 37;
// Welcon manufacturer methods (seed 000 §5.4.3.33/34): move at 6099h:01 until
// the motor current rises above 2402h, i.e. the axis presses on a mechanical
// stop; that point is home.
constexpr std::int8_t kCurrentThresholdPositive = -3;
constexpr std::int8_t kCurrentThresholdNegative = -4;

HomingMethod edge(AxisSignal s, int final_direction, bool active_before) {
  HomingMethod m;
  m.kind = Kind::Edge;
  m.signal = s;
  m.final_direction = final_direction;
  m.active_before = active_before;
  return m;
}
HomingMethod window(int final_direction, bool active_before, int initial_direction) {
  HomingMethod m = edge(AxisSignal::HomeSwitch, final_direction, active_before);
  m.kind = Kind::Window;
  m.initial_direction = initial_direction;
  return m;
}
}  // namespace

// CiA 402-2 §11.2.x, Figures 44-58. "Positive home switch" (3, 4) is active
// above its edge, "negative home switch" (5, 6) below it; 7-14 use a home
// switch that is active over a stretch of travel and reverse at the limit
// switch ahead (7-10 start positive, 11-14 negative).
std::optional<HomingMethod> homing_method(std::int8_t number) noexcept {
  if (number == kCurrentPosition || number == kCurrentPositionNew) return HomingMethod{};
  if (number == kCurrentThresholdPositive || number == kCurrentThresholdNegative) {
    HomingMethod m;
    m.kind = Kind::CurrentThreshold;
    m.final_direction = number == kCurrentThresholdPositive ? 1 : -1;
    return m;
  }
  if (number == kIndexNegative || number == kIndexPositive) {
    HomingMethod m;
    m.kind = Kind::IndexOnly;
    m.final_direction = number == kIndexNegative ? -1 : 1;
    m.index = true;
    return m;
  }
  int base = number;
  bool index = true;
  if (number >= kFirstEdgeOnlyMethod && number <= kLastEdgeOnlyMethod) {
    base = number - (kFirstEdgeOnlyMethod - kFirstSwitchMethod);
    index = false;
  }
  if (base < kFirstSwitchMethod || base > kLastIndexSwitchMethod) return std::nullopt;
  HomingMethod m;
  switch (base) {
    case 1: m = edge(AxisSignal::NegativeLimit, +1, true); break;
    case 2: m = edge(AxisSignal::PositiveLimit, -1, true); break;
    case 3: m = edge(AxisSignal::HomeSwitch, -1, true); break;
    case 4: m = edge(AxisSignal::HomeSwitch, +1, false); break;
    case 5: m = edge(AxisSignal::HomeSwitch, +1, true); break;
    case 6: m = edge(AxisSignal::HomeSwitch, -1, false); break;
    case 7: m = window(-1, true, +1); break;   // left of the lower edge
    case 8: m = window(+1, false, +1); break;  // right of the lower edge
    case 9: m = window(-1, false, +1); break;  // left of the upper edge
    case 10: m = window(+1, true, +1); break;  // right of the upper edge
    case 11: m = window(+1, true, -1); break;  // mirror of 7
    case 12: m = window(-1, false, -1); break;
    case 13: m = window(+1, false, -1); break;
    default: m = window(-1, true, -1); break;  // 14
  }
  m.index = index;
  return m;
}

void Homing::fail() noexcept {
  status_ = HomingStatus::Error;
  phase_ = Phase::Done;
  stopping_ = true;
}

void Homing::interrupt() noexcept {
  if (status_ != HomingStatus::InProgress) return;
  status_ = HomingStatus::NotStarted;
  phase_ = Phase::Done;
  stopping_ = true;
}

bool Homing::limit_ahead(const Axis& axis, double pos, int direction) const noexcept {
  if (direction > 0) return m_.signal != AxisSignal::PositiveLimit && axis.active(AxisSignal::PositiveLimit, pos);
  return m_.signal != AxisSignal::NegativeLimit && axis.active(AxisSignal::NegativeLimit, pos);
}

bool Homing::start(std::int8_t method, const Axis& axis, double actual_position) noexcept {
  const auto m = homing_method(method);
  if (!m) {
    fail();
    return false;
  }
  m_ = *m;
  status_ = HomingStatus::InProgress;
  stopping_ = false;
  reversed_ = false;
  search_direction_ = m_.final_direction;
  switch (m_.kind) {
    case Kind::CurrentPosition:
      event_position_ = actual_position;
      phase_ = Phase::Done;
      break;
    case Kind::IndexOnly: phase_ = Phase::Index; break;
    case Kind::CurrentThreshold: phase_ = Phase::SearchStop; break;
    case Kind::Edge:
    case Kind::Window: {
      const bool now = axis.active(m_.signal, actual_position);
      if (m_.kind == Kind::Window && !now) {
        phase_ = Phase::SearchWindow;
        search_direction_ = m_.initial_direction;
      } else if (now == m_.active_before) {
        phase_ = Phase::Final;
      } else {
        phase_ = Phase::Exit;
        search_direction_ = -m_.final_direction;
      }
      break;
    }
  }
  return true;
}

std::optional<double> Homing::cycle(ProfileGenerator& gen, const Axis& axis, double previous, double actual,
                                    const Speeds& sp, double home_offset, double dt,
                                    const Current& current) noexcept {
  if (status_ != HomingStatus::InProgress) {
    if (stopping_ && gen.stop(sp.acceleration, dt)) stopping_ = false;
    if (!stopping_) gen.reset(gen.position(), 0.0);
    return std::nullopt;
  }
  auto event = [&](double pos) {
    event_position_ = pos;
    phase_ = Phase::Stop;
  };
  switch (phase_) {
    case Phase::SearchWindow:
      if (axis.active(AxisSignal::HomeSwitch, actual)) {
        if (m_.active_before) {
          phase_ = Phase::Final;
          search_direction_ = m_.final_direction;
        } else {
          phase_ = Phase::Exit;
          search_direction_ = -m_.final_direction;
        }
      } else if (axis.active(search_direction_ > 0 ? AxisSignal::PositiveLimit : AxisSignal::NegativeLimit,
                             actual)) {
        if (reversed_) return fail(), std::nullopt;
        reversed_ = true;
        search_direction_ = -search_direction_;
      }
      break;
    case Phase::Exit:
      if (axis.active(m_.signal, actual) == m_.active_before) {
        phase_ = Phase::Final;
        search_direction_ = m_.final_direction;
      } else if (limit_ahead(axis, actual, search_direction_)) {
        return fail(), std::nullopt;
      }
      break;
    case Phase::Final: {
      const auto e = axis.edge_between(m_.signal, previous, actual);
      if (e && (actual - previous) * m_.final_direction > 0 && axis.active(m_.signal, actual) != m_.active_before) {
        if (!m_.index) {
          event(*e);
        } else if (const auto i = axis.index_between(*e, actual); i && (actual - *e) * m_.final_direction > 0) {
          event(*i);
        } else {
          phase_ = Phase::Index;
        }
      } else if (limit_ahead(axis, actual, search_direction_)) {
        return fail(), std::nullopt;
      }
      break;
    }
    case Phase::Index:
      if (const auto i = axis.index_between(previous, actual); i && (actual - previous) * m_.final_direction > 0) {
        event(*i);
      } else if (limit_ahead(axis, actual, m_.final_direction)) {
        return fail(), std::nullopt;
      }
      break;
    case Phase::SearchStop:
      // The stop is found when the current exceeds the threshold; the
      // reference, which ran on past the stop, goes back to it.
      if (std::abs(current.actual_ma) > current.threshold_ma) {
        event_position_ = actual;
        gen.reset(gen.position(), 0.0);
        phase_ = Phase::Return;
        return std::nullopt;
      }
      if (limit_ahead(axis, actual, search_direction_)) return fail(), std::nullopt;
      gen.ramp_velocity(search_direction_ * sp.switch_search, sp.acceleration, sp.acceleration, dt);
      return std::nullopt;
    case Phase::Stop:
      if (gen.stop(sp.acceleration, dt)) phase_ = Phase::Return;
      return std::nullopt;
    case Phase::Return:
      if (gen.move_to(event_position_, sp.zero_search, sp.acceleration, sp.acceleration, dt)) phase_ = Phase::Done;
      return std::nullopt;
    case Phase::Done:
      status_ = HomingStatus::Attained;
      return home_offset - event_position_;
  }
  if (phase_ == Phase::Stop) return gen.stop(sp.acceleration, dt), std::nullopt;
  const bool fast = phase_ == Phase::SearchWindow || phase_ == Phase::Exit;
  gen.ramp_velocity(search_direction_ * (fast ? sp.switch_search : sp.zero_search), sp.acceleration,
                    sp.acceleration, dt);
  return std::nullopt;
}

}  // namespace ecat::ds402
