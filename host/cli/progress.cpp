// Progress formatting and pacing: at most ten redraws a second on a terminal.
#include "host/cli/progress.h"

#include <algorithm>
#include <cmath>

namespace dg::host {

std::string progress_text(uint32_t points, uint32_t total, double seconds, bool bar, uint32_t first) {
  char text[160];
  // A scan on the fly has as many points as the gauge's cycle gives: its total is an estimate,
  // which the count may pass.
  if (total > 0 && points > total) total = points;
  const double rate = seconds > 0 && points > first ? (points - first) / seconds : 0;
  const double share = total > 0 ? std::min(1.0, static_cast<double>(points) / total) : 0;
  std::string eta = "-";
  if (rate > 0 && total > points) {
    const long left = std::lround((total - points) / rate);
    char t[32];
    std::snprintf(t, sizeof t, "%ld:%02ld", left / 60, left % 60);
    eta = t;
  }
  char speed[32];
  if (rate >= 1000) std::snprintf(speed, sizeof speed, "%.1fk", rate / 1000);
  else std::snprintf(speed, sizeof speed, "%.0f", rate);
  std::string prefix;
  if (bar) {
    const int filled = static_cast<int>(share * 30);
    prefix = "[" + std::string(static_cast<size_t>(filled), '#') + std::string(static_cast<size_t>(30 - filled), '.') + "]  ";
  }
  std::snprintf(text, sizeof text, "%u/%u points  %3.0f %%  %s points/s  ETA %s", points, total, 100 * share, speed, eta.c_str());
  return prefix + text;
}

ProgressPrinter::ProgressPrinter(std::FILE* out, bool terminal)
    : out_(out), terminal_(terminal), started_(std::chrono::steady_clock::now()) {}

void ProgressPrinter::update(uint32_t points, uint32_t total) {
  const auto now = std::chrono::steady_clock::now();
  const double seconds = std::chrono::duration<double>(now - started_).count();
  if (terminal_) {
    if (drew_ && now - last_draw_ < std::chrono::milliseconds(100) && points < total) return;
    std::fprintf(out_, "\r%s", progress_text(points, total, seconds, true, first_).c_str());
    std::fflush(out_);
    last_draw_ = now;
    drew_ = true;
    return;
  }
  const int tenth = total > 0 ? static_cast<int>(10.0 * points / total) : 0;
  if (tenth == last_tenth_) return;
  last_tenth_ = tenth;
  std::fprintf(out_, "scan: %s\n", progress_text(points, total, seconds, false, first_).c_str());
}

void ProgressPrinter::finish() {
  if (terminal_ && drew_) std::fprintf(out_, "\n");
  drew_ = false;  // once: an adaptive scan finishes its bar before its rounds
}

}  // namespace dg::host
