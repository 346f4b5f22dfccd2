// Scan progress for people: a bar with rate and ETA on a terminal, a plain line every tenth when not.
#pragma once
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <string>

namespace dg::host {

// The text of one progress report: "[#####.....]  1271/4941 points  25 %  2.1k points/s  ETA 0:03".
// `bar` false gives the same without the bar (for logs). The rate counts the points after
// `first` (those stored before a resume came at no cost).
std::string progress_text(uint32_t points, uint32_t total, double seconds, bool bar, uint32_t first = 0);

class ProgressPrinter {
 public:
  ProgressPrinter(std::FILE* out, bool terminal);
  void update(uint32_t points, uint32_t total);
  // Points already there when this run started (a resumed scan).
  void start_at(uint32_t points) { first_ = points; }
  void finish();

 private:
  std::FILE* out_;
  bool terminal_;
  std::chrono::steady_clock::time_point started_;
  std::chrono::steady_clock::time_point last_draw_{};
  int last_tenth_ = -1;
  bool drew_ = false;
  uint32_t first_ = 0;
};

}  // namespace dg::host
