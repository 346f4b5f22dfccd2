// Away is +1 mm along x (or -1 mm at the table's far end); back always ends in the same direction
// as the point was first reached, so backlash takes the same side every time.
#include "firmware/core/repeatability.h"

namespace dg {

bool RepeatabilityRun::start(uint32_t count, uint32_t request_id) {
  if (count < 2 || count > 64 || motion_.busy() || active()) return false;
  count_ = count;
  taken_ = 0;
  request_id_ = request_id;
  failed_ = false;
  sum_ = 0;
  sum_deviation_ = sum_squared_deviation_ = 0;
  home_x_ = motion_.x_steps();
  home_y_ = motion_.y_steps();
  const int32_t one_mm = static_cast<int32_t>(1000000 / motion_.config().nm_per_step);
  away_x_ = home_x_ + one_mm <= motion_.config().x_max_steps ? home_x_ + one_mm : home_x_ - one_mm;
  return move_away();
}

bool RepeatabilityRun::move_away() {
  phase_ = Phase::kAway;
  if (motion_.move_to(away_x_, home_y_, 0) == Status::kOk) return true;
  cancel();
  return false;
}

void RepeatabilityRun::cancel() {
  phase_ = Phase::kIdle;
  failed_ = true;
}

void RepeatabilityRun::finish() {
  phase_ = Phase::kIdle;
  const int64_t n = count_;
  result_ = digitizer_Repeatability_init_zero;
  result_.count = count_;
  result_.x_nm = static_cast<int32_t>(static_cast<int64_t>(home_x_) * motion_.config().nm_per_step);
  result_.y_nm = static_cast<int32_t>(static_cast<int64_t>(home_y_) * motion_.config().nm_per_step);
  result_.mean_nm = static_cast<int32_t>(sum_ >= 0 ? (sum_ + n / 2) / n : -((-sum_ + n / 2) / n));
  result_.min_nm = static_cast<int32_t>(min_);
  result_.max_nm = static_cast<int32_t>(max_);
  // Sample variance = (n S2 - S1^2) / (n (n - 1)); the root rounded as (isqrt(4 v) + 1) / 2.
  const int64_t spread = n * sum_squared_deviation_ - sum_deviation_ * sum_deviation_;
  const uint64_t variance = spread > 0 ? static_cast<uint64_t>(spread) / static_cast<uint64_t>(n * (n - 1)) : 0;
  result_.stddev_nm = (isqrt64(4 * variance) + 1) / 2;
}

bool RepeatabilityRun::poll() {
  if (!active()) return false;
  switch (phase_) {
    case Phase::kAway:
      if (motion_.busy()) return false;
      phase_ = Phase::kBack;
      if (motion_.move_to(home_x_, home_y_, 0) != Status::kOk) {
        cancel();
        return true;
      }
      return false;
    case Phase::kBack:
      if (motion_.busy()) return false;
      phase_ = Phase::kReading;
      probe_.start();
      return false;
    case Phase::kReading: {
      const Probe::State state = probe_.poll();
      if (state == Probe::State::kReading) return false;
      if (state == Probe::State::kFailed) {
        cancel();
        return true;
      }
      const int64_t v = probe_.value_nm();
      if (taken_ == 0) {
        first_ = v;
        min_ = max_ = v;
      }
      min_ = v < min_ ? v : min_;
      max_ = v > max_ ? v : max_;
      sum_ += v;
      sum_deviation_ += v - first_;
      sum_squared_deviation_ += (v - first_) * (v - first_);
      if (++taken_ == count_) {
        finish();
        return true;
      }
      return !move_away();
    }
    case Phase::kIdle:
      return false;
  }
  return false;
}

}  // namespace dg
