#include "ensemble/progress.hpp"

#include <unistd.h>

namespace treedyn::ensemble {

Progress::Progress(std::uint64_t total, double interval, bool enabled)
    : total_(total),
      interval_(interval),
      enabled_(enabled),
      terminal_(isatty(STDERR_FILENO) != 0),
      start_(std::chrono::steady_clock::now()),
      last_(start_) {}

void Progress::update(std::uint64_t done, std::uint64_t failed) {
  if (!enabled_) return;
  const auto now = std::chrono::steady_clock::now();
  const double since = std::chrono::duration<double>(now - last_).count();
  if (since < (terminal_ ? 0.5 : interval_)) return;
  last_ = now;
  print(done, failed, false);
}

void Progress::finish(std::uint64_t done, std::uint64_t failed) {
  // The last line once: on a terminal it ends the live line; in a log it is
  // skipped when the newest line already says the same.
  if (enabled_ && (terminal_ || !printed_ || last_printed_ != done)) print(done, failed, true);
}

void Progress::print(std::uint64_t done, std::uint64_t failed, bool final_line) {
  printed_ = true;
  last_printed_ = done;
  const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  const double run_here = done > restored_ ? static_cast<double>(done - restored_) : 0.0;
  const double rate = elapsed > 0.0 ? run_here / elapsed : 0.0;
  const std::uint64_t towards = wave_end_ > 0 ? wave_end_ : total_;
  const double left = rate > 0.0 && towards > done ? static_cast<double>(towards - done) / rate : 0.0;
  // The last line has no time left: a stopping rule or a signal may end the
  // run before the total.
  char ending[48] = "", wave[96] = "";
  if (!final_line) std::snprintf(ending, sizeof ending, "  left %.1f s%s", left, wave_end_ > 0 ? " in it" : "");
  if (wave_end_ > 0)
    std::snprintf(wave, sizeof wave, " through %s (at most %llu)", wave_name_.c_str(),
                  static_cast<unsigned long long>(total_));
  std::fprintf(stderr, "%ssamples %llu/%llu%s (%llu failed)  %.2f samples/s  elapsed %.1f s%s%s", terminal_ ? "\r" : "",
               static_cast<unsigned long long>(done), static_cast<unsigned long long>(towards), wave,
               static_cast<unsigned long long>(failed), rate, elapsed, ending, terminal_ && !final_line ? "   " : "\n");
  std::fflush(stderr);
}

}  // namespace treedyn::ensemble
