// Progress and cancellation of a long call, one type for every stage.
#pragma once

#include <chrono>
#include <functional>
#include <string>

namespace shadecut {

/// The caller's callback: `fraction` in [0, 1] of the whole call and the running `stage`. Returning
/// false cancels the call (it throws Cancelled).
using ProgressCallback = std::function<bool(double fraction, const std::string& stage)>;

/// A ProgressCallback seen through a part [begin, end] of the whole call, so that a stage reports
/// its own fraction 0..1 without knowing where it sits in the call. Empty = nobody listens.
class Progress {
 public:
  Progress() = default;
  explicit Progress(ProgressCallback callback) : callback_(std::move(callback)) {}

  /// The part [from, to] (fractions 0..1 of this range) of this range.
  Progress range(double from, double to) const {
    Progress part = *this;
    part.begin_ = begin_ + (end_ - begin_) * from;
    part.end_ = begin_ + (end_ - begin_) * to;
    return part;
  }

  /// Reports that `within` (0..1) of this range is done in `stage`; throws Cancelled when the
  /// callback answers false.
  void report(double within, const std::string& stage) const;

  explicit operator bool() const { return bool(callback_); }

 private:
  ProgressCallback callback_;
  double begin_ = 0.0;
  double end_ = 1.0;
};

/// When a loop of many short steps reports next: once kInterval of work has passed since the last
/// report, so that a call answers a cancel (or Ctrl+C) within about that long whatever its step count.
/// A step count alone cannot promise it: a hundredth of 10^9 sweeps runs for minutes.
class ReportClock {
 public:
  static constexpr std::chrono::milliseconds kInterval{100};

  /// Whether kInterval has passed since the last time this answered true (or since construction).
  bool due() {
    const auto now = std::chrono::steady_clock::now();
    if (now - last_ < kInterval) return false;
    last_ = now;
    return true;
  }

 private:
  std::chrono::steady_clock::time_point last_ = std::chrono::steady_clock::now();
};

}  // namespace shadecut
