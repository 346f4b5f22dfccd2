// Height maps. The three layouts follow the programs that read them: bCNC's Probe.save/load
// (bCNC/CNC.py), Candle's saveHeightMap/loadHeightMap (src/candle/frmmain.cpp) with rows from the
// border's y (its Interpolation::bicubicInterpolate), and Klipper's ProfileManager
// (klippy/extras/bed_mesh.py, PROFILE_VERSION 1 and PROFILE_OPTIONS).
#include "host/scan/height_map.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <stdexcept>

namespace dg::host {

namespace {

std::string number(double v) {
  char text[48];
  std::snprintf(text, sizeof text, "%.6f", v);
  return text;
}

// Sorted positions grouped where they lie within `tolerance`; each group's mean.
std::vector<double> positions(std::vector<double> values, double tolerance) {
  std::sort(values.begin(), values.end());
  std::vector<double> out;
  size_t start = 0;
  for (size_t i = 1; i <= values.size(); ++i) {
    if (i == values.size() || values[i] - values[i - 1] > tolerance) {
      double sum = 0;
      for (size_t k = start; k < i; ++k) sum += values[k];
      out.push_back(sum / static_cast<double>(i - start));
      start = i;
    }
  }
  return out;
}

// The index of `v` on the even grid min + k * step, or -1 when it is off by more than step / 100.
int node_index(double v, double min, double step, int count) {
  const double k = (v - min) / step;
  const long nearest = std::lround(k);
  if (nearest < 0 || nearest >= count || std::fabs(k - static_cast<double>(nearest)) > 0.01) return -1;
  return static_cast<int>(nearest);
}

std::vector<std::string> lines_of(const std::string& text) {
  std::vector<std::string> lines;
  size_t start = 0;
  while (start < text.size()) {
    size_t end = text.find('\n', start);
    if (end == std::string::npos) end = text.size();
    std::string line = text.substr(start, end - start);
    if (!line.empty() && line.back() == '\r') line.pop_back();
    lines.push_back(line);
    start = end + 1;
  }
  return lines;
}

std::vector<std::string> fields_of(const std::string& line, char separator) {
  std::vector<std::string> out;
  std::string field;
  for (char c : line) {
    const bool split = separator == ' ' ? (c == ' ' || c == '\t') : c == separator;
    if (!split) {
      field += c;
    } else if (separator != ' ' || !field.empty()) {
      out.push_back(field);
      field.clear();
    }
  }
  if (separator != ' ' || !field.empty()) out.push_back(field);
  return out;
}

struct Reader {
  const std::string& name;
  [[noreturn]] void fail(size_t line, const std::string& why) const {
    throw PointFileError(name + ":" + std::to_string(line) + ": " + why);
  }
  double real(const std::string& field, size_t line) const {
    size_t a = field.find_first_not_of(" \t"), b = field.find_last_not_of(" \t");
    const std::string t = a == std::string::npos ? "" : field.substr(a, b - a + 1);
    char* end = nullptr;
    const double v = t.empty() ? 0 : std::strtod(t.c_str(), &end);
    if (t.empty() || end != t.c_str() + t.size()) fail(line, "'" + t + "' is not a number");
    if (!std::isfinite(v)) fail(line, "'" + t + "' is not a finite number");
    if (std::fabs(v) > 1e6) fail(line, "'" + t + "' is beyond a million millimetres");
    return v;
  }
  int count(const std::string& field, size_t line, const char* what) const {
    const double v = real(field, line);
    if (v != std::floor(v) || v < 2 || v > 10000) fail(line, std::string(what) + " must be a whole number from 2 to 10000");
    return static_cast<int>(v);
  }
};

void check_extent(const HeightMap& m, const Reader& r, size_t line) {
  if (!(m.max_x_mm > m.min_x_mm) || !(m.max_y_mm > m.min_y_mm)) r.fail(line, "the grid's maximum must exceed its minimum");
}

}  // namespace

std::vector<Point3> HeightMap::points() const {
  std::vector<Point3> out;
  for (int j = 0; j < count_y; ++j) {
    for (int i = 0; i < count_x; ++i) out.push_back({min_x_mm + i * step_x_mm(), min_y_mm + j * step_y_mm(), z(i, j)});
  }
  return out;
}

HeightMap height_map_from_points(const std::vector<Point3>& points, const std::string& name) {
  if (points.size() < 4) throw std::invalid_argument(name + ": a height map needs a grid of at least 2 x 2 points");
  std::vector<double> xs, ys;
  for (const Point3& p : points) xs.push_back(p.x), ys.push_back(p.y);
  HeightMap m;
  // Positions that agree to 1 um are one grid line (a scan's nanometre coordinates agree exactly).
  const std::vector<double> grid_x = positions(xs, 1e-3), grid_y = positions(ys, 1e-3);
  m.count_x = static_cast<int>(grid_x.size());
  m.count_y = static_cast<int>(grid_y.size());
  if (m.count_x < 2 || m.count_y < 2) throw std::invalid_argument(name + ": a height map needs at least 2 positions in x and in y");
  if (static_cast<size_t>(m.count_x) * m.count_y != points.size()) {
    throw std::invalid_argument(name + ": " + std::to_string(points.size()) + " points are not a full " + std::to_string(m.count_x) +
                                " x " + std::to_string(m.count_y) + " grid (a scan that stopped early, or scattered points)");
  }
  m.min_x_mm = grid_x.front(), m.max_x_mm = grid_x.back(), m.min_y_mm = grid_y.front(), m.max_y_mm = grid_y.back();
  m.z_mm.assign(points.size(), std::nan(""));
  for (const Point3& p : points) {
    const int i = node_index(p.x, m.min_x_mm, m.step_x_mm(), m.count_x), j = node_index(p.y, m.min_y_mm, m.step_y_mm(), m.count_y);
    if (i < 0 || j < 0) {
      throw std::invalid_argument(name + ": the point at x " + number(p.x) + ", y " + number(p.y) +
                                  " is off an evenly spaced grid (a height map's nodes are evenly spaced)");
    }
    double& z = m.z_mm[static_cast<size_t>(j) * m.count_x + i];
    if (!std::isnan(z)) throw std::invalid_argument(name + ": two points at the node x " + number(p.x) + ", y " + number(p.y));
    z = p.z;
  }
  return m;
}

std::string format_bcnc_probe(const HeightMap& m) {
  const auto [low, high] = std::minmax_element(m.z_mm.begin(), m.z_mm.end());
  std::string out = number(m.min_x_mm) + " " + number(m.max_x_mm) + " " + std::to_string(m.count_x) + "\n";
  out += number(m.min_y_mm) + " " + number(m.max_y_mm) + " " + std::to_string(m.count_y) + "\n";
  // bCNC's probing range (1 mm beyond the heights) and its default probe feed, 10 mm/min: loading
  // the file sets bCNC's probe feed, which 0 would stop.
  out += number(*low - 1) + " " + number(*high + 1) + " 10\n\n\n";
  for (int j = 0; j < m.count_y; ++j) {
    for (int i = 0; i < m.count_x; ++i) {
      out += number(m.min_x_mm + i * m.step_x_mm()) + " " + number(m.min_y_mm + j * m.step_y_mm()) + " " + number(m.z(i, j)) + "\n";
    }
    out += "\n";
  }
  return out;
}

std::string format_candle_map(const HeightMap& m) {
  const auto [low, high] = std::minmax_element(m.z_mm.begin(), m.z_mm.end());
  std::string out = number(m.min_x_mm) + ";" + number(m.min_y_mm) + ";" + number(m.max_x_mm - m.min_x_mm) + ";" +
                    number(m.max_y_mm - m.min_y_mm) + "\r\n";
  out += std::to_string(m.count_x) + ";" + std::to_string(m.count_y) + ";" + number(*low - 1) + ";" + number(*high + 1) + "\r\n";
  out += "0;" + std::to_string(m.count_x) + ";" + std::to_string(m.count_y) + "\r\n";
  for (int j = 0; j < m.count_y; ++j) {
    for (int i = 0; i < m.count_x; ++i) out += (i ? ";" : "") + number(m.z(i, j));
    out += "\r\n";
  }
  return out;
}

std::string format_klipper_mesh(const HeightMap& m, const std::string& profile) {
  if (m.count_x < 3 || m.count_y < 3) {
    throw std::invalid_argument("a Klipper bed mesh needs at least 3 x 3 points (this grid is " + std::to_string(m.count_x) + " x " +
                                std::to_string(m.count_y) + ")");
  }
  for (char c : profile) {
    if (c == ']' || c == '\n' || c == '\r') throw std::invalid_argument("a Klipper profile name cannot hold ']' or a line break");
  }
  std::string out = "# Append below the SAVE_CONFIG line of printer.cfg; then BED_MESH_PROFILE LOAD=" + profile + "\n";
  out += "#*# [bed_mesh " + profile + "]\n#*# version = 1\n#*# points =\n";
  for (int j = 0; j < m.count_y; ++j) {
    out += "#*# \t  ";
    for (int i = 0; i < m.count_x; ++i) out += (i ? ", " : "") + number(m.z(i, j));
    out += "\n";
  }
  out += "#*# x_count = " + std::to_string(m.count_x) + "\n#*# y_count = " + std::to_string(m.count_y) + "\n";
  out += "#*# mesh_x_pps = 2\n#*# mesh_y_pps = 2\n";
  out += std::string("#*# algo = ") + (std::min(m.count_x, m.count_y) >= 4 ? "bicubic" : "lagrange") + "\n#*# tension = 0.2\n";
  out += "#*# min_x = " + number(m.min_x_mm) + "\n#*# max_x = " + number(m.max_x_mm) + "\n";
  out += "#*# min_y = " + number(m.min_y_mm) + "\n#*# max_y = " + number(m.max_y_mm) + "\n";
  return out;
}

HeightMap parse_bcnc_probe(const std::string& text, const std::string& name) {
  const Reader r{name};
  std::vector<std::pair<size_t, std::vector<std::string>>> rows;
  const std::vector<std::string> lines = lines_of(text);
  for (size_t k = 0; k < lines.size(); ++k) {
    std::vector<std::string> f = fields_of(lines[k], ' ');
    if (!f.empty()) rows.emplace_back(k + 1, f);
  }
  if (rows.size() < 3) r.fail(lines.size(), "a bCNC probe file starts with three lines: x range and count, y range and count, z range and feed");
  for (size_t k = 0; k < rows.size(); ++k) {
    if (rows[k].second.size() != 3) r.fail(rows[k].first, "expected 3 numbers, found " + std::to_string(rows[k].second.size()));
  }
  HeightMap m;
  m.min_x_mm = r.real(rows[0].second[0], rows[0].first), m.max_x_mm = r.real(rows[0].second[1], rows[0].first);
  m.count_x = r.count(rows[0].second[2], rows[0].first, "the x count");
  m.min_y_mm = r.real(rows[1].second[0], rows[1].first), m.max_y_mm = r.real(rows[1].second[1], rows[1].first);
  m.count_y = r.count(rows[1].second[2], rows[1].first, "the y count");
  check_extent(m, r, rows[1].first);
  for (const std::string& f : rows[2].second) r.real(f, rows[2].first);
  const size_t nodes = static_cast<size_t>(m.count_x) * m.count_y;
  if (rows.size() - 3 != nodes) {
    r.fail(rows.back().first, std::to_string(rows.size() - 3) + " points for a " + std::to_string(m.count_x) + " x " +
                                  std::to_string(m.count_y) + " grid");
  }
  m.z_mm.assign(nodes, std::nan(""));
  for (size_t k = 3; k < rows.size(); ++k) {
    const size_t line = rows[k].first;
    const double x = r.real(rows[k].second[0], line), y = r.real(rows[k].second[1], line), z = r.real(rows[k].second[2], line);
    const int i = node_index(x, m.min_x_mm, m.step_x_mm(), m.count_x), j = node_index(y, m.min_y_mm, m.step_y_mm(), m.count_y);
    if (i < 0 || j < 0) r.fail(line, "the point is not on the grid the first two lines give");
    double& cell = m.z_mm[static_cast<size_t>(j) * m.count_x + i];
    if (!std::isnan(cell)) r.fail(line, "a second point at the same node");
    cell = z;
  }
  return m;
}

HeightMap parse_candle_map(const std::string& text, const std::string& name) {
  const Reader r{name};
  const std::vector<std::string> lines = lines_of(text);
  auto fields = [&](size_t k, size_t expected) {
    if (k >= lines.size()) r.fail(k + 1, "the file ends early");
    const std::vector<std::string> f = fields_of(lines[k], ';');
    if (f.size() != expected) r.fail(k + 1, "expected " + std::to_string(expected) + " fields separated by ';', found " + std::to_string(f.size()));
    return f;
  };
  HeightMap m;
  const std::vector<std::string> border = fields(0, 4), grid = fields(1, 4);
  fields(2, 3);
  m.min_x_mm = r.real(border[0], 1), m.min_y_mm = r.real(border[1], 1);
  m.max_x_mm = m.min_x_mm + r.real(border[2], 1), m.max_y_mm = m.min_y_mm + r.real(border[3], 1);
  check_extent(m, r, 1);
  m.count_x = r.count(grid[0], 2, "the x count"), m.count_y = r.count(grid[1], 2, "the y count");
  r.real(grid[2], 2), r.real(grid[3], 2);
  for (int j = 0; j < m.count_y; ++j) {
    const std::vector<std::string> row = fields(3 + static_cast<size_t>(j), static_cast<size_t>(m.count_x));
    for (const std::string& f : row) m.z_mm.push_back(r.real(f, 4 + static_cast<size_t>(j)));
  }
  for (size_t k = 3 + static_cast<size_t>(m.count_y); k < lines.size(); ++k) {
    if (!lines[k].empty()) r.fail(k + 1, "more rows than the grid's " + std::to_string(m.count_y));
  }
  return m;
}

HeightMap parse_klipper_mesh(const std::string& text, const std::string& name) {
  const Reader r{name};
  const std::vector<std::string> lines = lines_of(text);
  // Each line without its auto-save prefix "#*#"; plain comments are skipped.
  auto body = [&](size_t k, bool* saved) {
    std::string line = lines[k];
    *saved = line.rfind("#*#", 0) == 0;
    if (!*saved) return line;
    // Klipper strips "#*# " (with its one space): what stays indented continues a value.
    return line.size() > 3 && line[3] == ' ' ? line.substr(4) : line.substr(3);
  };
  size_t start = lines.size();
  for (size_t k = 0; k < lines.size() && start == lines.size(); ++k) {
    bool saved = false;
    std::string b = body(k, &saved);
    b.erase(0, b.find_first_not_of(" \t"));
    if (b.rfind("[bed_mesh ", 0) == 0 && b.find(']') != std::string::npos) start = k + 1;
  }
  if (start == lines.size()) r.fail(lines.size(), "no [bed_mesh NAME] profile");
  std::map<std::string, std::pair<std::string, size_t>> values;
  std::vector<std::pair<std::string, size_t>> point_rows;
  bool in_points = false;
  for (size_t k = start; k < lines.size(); ++k) {
    bool saved = false;
    const std::string b = body(k, &saved);
    const size_t first = b.find_first_not_of(" \t");
    if (first == std::string::npos || (!saved && b[first] == '#')) continue;
    if (b[first] == '[') break;  // the next section
    if (in_points && first > 0) {
      point_rows.emplace_back(b.substr(first), k + 1);
      continue;
    }
    in_points = false;
    const size_t equals = b.find_first_of("=:");
    if (equals == std::string::npos) r.fail(k + 1, "not a `key = value` line");
    std::string key = b.substr(first, equals - first);
    key.erase(key.find_last_not_of(" \t") + 1);
    std::string value = b.substr(equals + 1);
    value.erase(0, value.find_first_not_of(" \t"));
    if (key == "points") {
      in_points = true;
      if (!value.empty()) point_rows.emplace_back(value, k + 1);
      continue;
    }
    values[key] = {value, k + 1};
  }
  auto get = [&](const char* key) -> std::pair<std::string, size_t> {
    const auto it = values.find(key);
    if (it == values.end()) r.fail(start, std::string("the profile has no `") + key + "`");
    return it->second;
  };
  if (r.real(get("version").first, get("version").second) != 1) r.fail(get("version").second, "only profile version 1 is known");
  HeightMap m;
  m.count_x = r.count(get("x_count").first, get("x_count").second, "x_count");
  m.count_y = r.count(get("y_count").first, get("y_count").second, "y_count");
  m.min_x_mm = r.real(get("min_x").first, get("min_x").second), m.max_x_mm = r.real(get("max_x").first, get("max_x").second);
  m.min_y_mm = r.real(get("min_y").first, get("min_y").second), m.max_y_mm = r.real(get("max_y").first, get("max_y").second);
  check_extent(m, r, get("max_y").second);
  if (point_rows.size() != static_cast<size_t>(m.count_y)) {
    r.fail(start, std::to_string(point_rows.size()) + " rows of points for y_count " + std::to_string(m.count_y));
  }
  for (const auto& [row, line] : point_rows) {
    const std::vector<std::string> f = fields_of(row, ',');
    if (f.size() != static_cast<size_t>(m.count_x)) r.fail(line, std::to_string(f.size()) + " points in a row of x_count " + std::to_string(m.count_x));
    for (const std::string& v : f) m.z_mm.push_back(r.real(v, line));
  }
  return m;
}

}  // namespace dg::host
