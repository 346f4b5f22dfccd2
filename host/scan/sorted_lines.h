// A scan's lines sorted along their direction, and for a point the nearest point of another line:
// its neighbour across the lines (the slope estimate and the fit's between-the-samples check).
#pragma once
#include <algorithm>
#include <cstddef>
#include <utility>
#include <vector>

namespace dg::host {

// `Along(i)` gives point i's coordinate along the lines (table x or y, or the fit's parameter u).
template <typename Along>
class SortedLines {
 public:
  SortedLines(std::vector<std::vector<size_t>> lines, Along along) : sorted_(std::move(lines)), along_(along) {
    for (auto& line : sorted_) {
      std::sort(line.begin(), line.end(), [&](size_t a, size_t b) { return along_(a) < along_(b); });
    }
  }

  size_t size() const { return sorted_.size(); }
  // Line l's points, sorted along it.
  const std::vector<size_t>& line(size_t l) const { return sorted_[l]; }

  // The point of line l nearest point i along the lines (the later one on a tie); -1 when line
  // l is empty. Found by halves.
  long nearest_on(size_t l, size_t i) const {
    const std::vector<size_t>& other = sorted_[l];
    if (other.empty()) return -1;
    const double t = along_(i);
    auto it = std::lower_bound(other.begin(), other.end(), t, [&](size_t a, double value) { return along_(a) < value; });
    if (it == other.end()) return static_cast<long>(other.back());
    if (it != other.begin() && t - along_(*(it - 1)) < along_(*it) - t) return static_cast<long>(*(it - 1));
    return static_cast<long>(*it);
  }

 private:
  std::vector<std::vector<size_t>> sorted_;
  Along along_;
};

}  // namespace dg::host
