// Cycle order and adaptive f_T steps of a palpation sweep (see palpation.hpp).
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "inhap/core/error.hpp"
#include "inhap/friction/palpation.hpp"

namespace inhap::friction {

namespace {

void check_config(const PalpationConfig& c, double max_force) {
  auto bad = [](const std::string& what) { throw Error("palpation: " + what); };
  if (c.normal_forces.empty()) bad("expected at least one normal force level");
  for (std::size_t i = 0; i < c.normal_forces.size(); ++i)
    if (!(c.normal_forces[i] > 0) || !std::isfinite(c.normal_forces[i]) ||
        (i && !(c.normal_forces[i] > c.normal_forces[i - 1])))
      bad(fmt::format("expected increasing normal forces > 0 N, got {}", c.normal_forces[i]));
  if (c.directions < 1 || c.directions > 64)
    bad(fmt::format("expected 1..64 tangential directions, got {}", c.directions));
  if (c.plateaus.empty()) bad("expected at least one plateau duration");
  for (double t : c.plateaus)
    if (!(t >= 0) || !std::isfinite(t)) bad(fmt::format("expected plateaus >= 0 s, got {}", t));
  if (!(c.tangential_step > 0) || !(c.max_ratio >= c.tangential_step))
    bad("expected 0 < tangential_step <= max_ratio");
  if (!(c.rates.normal_rate > 0) || !(c.rates.tangential_rate > 0))
    bad("expected loading rates > 0 N/s");
  if (!(c.hover > 0) || !(c.travel_speed > 0) || !(c.approach_speed > 0))
    bad("expected hover, travel_speed and approach_speed > 0");
  if (c.steps_below < 1) bad("expected steps_below >= 1");
  if (!(max_force > 0)) bad("expected a device with a max force > 0 N");
}

}  // namespace

SweepSchedule::SweepSchedule(const PalpationConfig& config, double max_force)
    : cfg_(&config), cap_(config.load_fraction_max * max_force) {
  check_config(config, max_force);
  const std::size_t nl = config.normal_forces.size();
  max_h_.assign(nl, 0);
  est_sum_.assign(nl, 0.0);
  est_n_.assign(nl, 0);
  for (std::size_t l = 0; l < nl; ++l) {
    int h = 0;
    while (!std::isnan(f_tangential(l, h + 2))) h += 2;
    max_h_[l] = h;
  }
  while (lvl_ < nl && max_h_[lvl_] == 0) ++lvl_;
  done_ = lvl_ >= nl;
  if (!done_) begin_direction();
}

double SweepSchedule::f_normal() const {
  return cfg_->normal_forces[std::min(lvl_, cfg_->normal_forces.size() - 1)];
}
double SweepSchedule::plateau() const {
  return cfg_->plateaus[pl_];
}

double SweepSchedule::f_tangential(std::size_t level, int half_steps) const {
  const double fn = cfg_->normal_forces[level];
  const double ratio = 0.5 * half_steps * cfg_->tangential_step;
  const double ft = fn * ratio;
  if (half_steps < 1 || ratio > cfg_->max_ratio + 1e-9 || ft > cfg_->tangential_force_max ||
      std::hypot(fn, ft) > cap_)
    return std::numeric_limits<double>::quiet_NaN();
  return ft;
}

double SweepSchedule::predicted_ratio() const {
  if (est_n_[lvl_] > 0) return est_sum_[lvl_] / est_n_[lvl_];
  double s = 0;
  int n = 0;
  for (std::size_t l = 0; l < est_n_.size(); ++l) {
    s += est_sum_[l];
    n += est_n_[l];
  }
  return n > 0 ? s / n : std::numeric_limits<double>::quiet_NaN();
}

void SweepSchedule::begin_direction() {
  const int top = max_h_[lvl_] / 2;  // lattice points
  int start = 1;
  const double rho = predicted_ratio();
  if (cfg_->adaptive && std::isfinite(rho)) {
    // Lattice points strictly below the predicted border, then steps_below of them.
    const int below = static_cast<int>(std::ceil(rho / cfg_->tangential_step - 1e-9)) - 1;
    start = std::max(1, below - cfg_->steps_below + 1);
    if (start > top) start = std::max(1, top - cfg_->steps_below + 1);
  }
  h_ = first_h_ = 2 * start;
  pl_ = 0;
  run_ = 0;
  elastic_h_ = sliding_h_ = -1;
  backtracked_ = half_done_ = false;
}

bool SweepSchedule::end_direction() {
  if (sliding_h_ > 0) {  // border ratio: middle of the bracket seen
    const double lo = std::max(0, elastic_h_) * 0.5, hi = sliding_h_ * 0.5;
    est_sum_[lvl_] += 0.5 * (lo + hi) * cfg_->tangential_step;
    ++est_n_[lvl_];
  }
  if (++dir_ >= cfg_->directions) {
    dir_ = 0;
    do ++lvl_;
    while (lvl_ < max_h_.size() && max_h_[lvl_] == 0);
    if (lvl_ >= max_h_.size()) {
      done_ = true;
      return false;
    }
  }
  begin_direction();
  return true;
}

bool SweepSchedule::half_step_or_end() {
  if (cfg_->half_step && !half_done_ && sliding_h_ > 0) {
    const int h = sliding_h_ - 1;
    if (h > elastic_h_ && h >= 1 && !std::isnan(f_tangential(lvl_, h))) {
      h_ = h;
      half_done_ = true;
      return true;
    }
  }
  return end_direction();
}

bool SweepSchedule::next(double up_tangential) {
  if (done_) return false;
  if (pl_ == 0) short_up_ = up_tangential;
  if (pl_ + 1 < cfg_->plateaus.size()) {
    ++pl_;
    return true;
  }
  pl_ = 0;
  const double growth = cfg_->plateaus.size() >= 2 ? up_tangential - short_up_ : 0.0;
  const bool sliding = growth > cfg_->slide_threshold;
  if (sliding && cfg_->adaptive && h_ == first_h_ && first_h_ > 2 && !backtracked_) {
    // Started above the border: start again lower.
    backtracked_ = true;
    h_ = first_h_ = std::max(2, first_h_ - 2 * (cfg_->steps_below + 1));
    run_ = 0;
    sliding_h_ = -1;
    return true;
  }
  if (sliding) {
    ++run_;
    sliding_h_ = sliding_h_ < 0 ? h_ : std::min(sliding_h_, h_);
  } else {
    run_ = 0;
    elastic_h_ = std::max(elastic_h_, h_);
  }
  if (half_done_) return end_direction();
  const int needed =
      dir_ == 0 ? std::max(cfg_->stop_after_sliding, cfg_->slope_steps) : cfg_->stop_after_sliding;
  const bool stop = cfg_->stop_after_sliding > 0 && run_ >= needed;
  if (stop || h_ + 2 > max_h_[lvl_]) return half_step_or_end();
  h_ += 2;
  return true;
}

double SweepSchedule::progress() const {
  const double total = static_cast<double>(max_h_.size()) * cfg_->directions;
  return done_ ? 1.0 : (static_cast<double>(lvl_) * cfg_->directions + dir_) / total;
}

std::size_t SweepSchedule::max_cycles() const {
  std::size_t n = 0;
  for (int m : max_h_)
    n += static_cast<std::size_t>(cfg_->directions) *
         static_cast<std::size_t>(m / 2 + cfg_->steps_below + 3);
  return n * cfg_->plateaus.size();
}

}  // namespace inhap::friction
