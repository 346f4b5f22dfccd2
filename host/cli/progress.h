// Scan progress for people: a bar with rate and ETA on a terminal, a plain line every tenth when not.
#pragma once
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <string>

namespace dg::host {

// The text of one progress report: "[#####.....]  1271/4941 points  25 %  2.1k points/s  ETA 0:03".
// `bar` false gives the same without the bar (for logs).
std::string progress_text(uint32_t points, uint32_t total, double seconds, bool bar);

class ProgressPrinter {
 public:
  ProgressPrinter(std::FILE* out, bool terminal);
  void update(uint32_t points, uint32_t total);
  void finish();

 private:
  std::FILE* out_;
  bool terminal_;
  std::chrono::steady_clock::time_point started_;
  std::chrono::steady_clock::time_point last_draw_{};
  int last_tenth_ = -1;
  bool drew_ = false;
};

}  // namespace dg::host
