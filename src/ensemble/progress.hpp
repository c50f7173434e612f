// Progress of the ensemble on rank 0: samples done of the total, samples per
// second, estimated time left. A live line on a terminal, else a log line
// every `interval` seconds.
#pragma once

#include <chrono>
#include <cstdint>
#include <cstdio>
#include <string>

namespace treedyn::ensemble {

class Progress {
 public:
  Progress(std::uint64_t total, double interval_seconds, bool enabled);
  void update(std::uint64_t done, std::uint64_t failed);
  void finish(std::uint64_t done, std::uint64_t failed);
  // Samples a resume restored: counted as done, not in the rate (nor in the time left).
  void restored(std::uint64_t samples) { restored_ = samples; }
  // A design whose waves are decided as it goes (subset simulation's
  // levels): the line counts towards the end of the wave running now, named
  // `wave`, with `total` as the most; the time left is that wave's.
  void wave(std::uint64_t end, const std::string& name) { wave_end_ = end, wave_name_ = name; }

 private:
  void print(std::uint64_t done, std::uint64_t failed, bool final_line);

  std::uint64_t total_;
  double interval_;
  bool enabled_, terminal_;
  std::chrono::steady_clock::time_point start_, last_;
  std::uint64_t last_printed_ = 0;
  std::uint64_t restored_ = 0;
  bool printed_ = false;
  std::uint64_t wave_end_ = 0;  // 0: one wave of total_
  std::string wave_name_;
};

}  // namespace treedyn::ensemble
