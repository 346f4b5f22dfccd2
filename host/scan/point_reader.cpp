// Strict point readers: every value must be a finite number, every row complete, so a
// fit never silently runs on damaged data.
#include "host/scan/point_reader.h"
#include "host/scan/height_map.h"
#include "host/io/whole_file.h"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <cstdio>
#include <cstring>
#include <exception>
#include <functional>
#include <map>
#include <sstream>
#include <string_view>

#include "host/io/file_name.h"
#include "host/io/text_field.h"
#include "host/parallel/parallel_for.h"
#include "host/scan/ply_reader.h"
#include "host/scan/position_uncertainty.h"
#include "host/scan/drift_removal.h"
#include "host/scan/fly_correction.h"
#include "host/scan/scan_file.h"
#include "host/scan/scan_uncertainty.h"
#include "host/scan/table_calibration.h"

namespace dg::host {
namespace {

std::string where(const std::string& name, size_t line) { return name + ":" + std::to_string(line); }

double parse_number(std::string_view field, const std::string& name, size_t line, const std::string& column) {
  double v = 0;
  if (!parse_decimal(field, &v)) {
    throw PointFileError(where(name, line) + ": column " + quoted(column) + " is not a finite decimal number: " + quoted(field));
  }
  return v;
}

// A coordinate or a normal's component: a number within kCoordinateLimitMm.
double parse_coordinate(std::string_view field, const std::string& name, size_t line, const std::string& column) {
  const double v = parse_number(field, name, line, column);
  if (!plausible_coordinate(v)) throw PointFileError(where(name, line) + ": column " + quoted(column) + " is " + quoted(field) + ": " + kCoordinateRule);
  return v;
}

// Text point files hold no NUL: one is damage (or a binary file), named by its line.
void check_no_nul(std::string_view text, const std::string& name) {
  const size_t at = text.find('\0');
  if (at == std::string::npos) return;
  const size_t line = 1 + static_cast<size_t>(std::count(text.begin(), text.begin() + static_cast<std::ptrdiff_t>(at), '\n'));
  throw PointFileError(where(name, line) + ": a NUL byte (byte " + std::to_string(at + 1) + "): not a text point file");
}

std::vector<std::string> split(const std::string& row, char separator) {
  std::vector<std::string> fields;
  std::string field;
  std::istringstream in(row);
  while (std::getline(in, field, separator)) fields.push_back(field);
  if (!row.empty() && row.back() == separator) fields.emplace_back();
  return fields;
}

// A row split at `separator`, or at runs of spaces and tabs when it is ' '.
std::vector<std::string> split_fields(const std::string& row, char separator) {
  if (separator != ' ') return split(row, separator);
  std::vector<std::string> fields;
  std::string field;
  std::istringstream in(row);
  while (in >> field) fields.push_back(field);
  return fields;
}

std::string lower_case(std::string s) {
  for (char& c : s) c = static_cast<char>(c >= 'A' && c <= 'Z' ? c - 'A' + 'a' : c);
  return s;
}

// Columns other tools write that carry nothing a surface needs (colours, intensity, CloudCompare's
// scalar fields): read past, not refused.
bool ignored_column(const std::string& name) {
  static const char* kIgnored[] = {"r", "g", "b", "a", "red", "green", "blue", "alpha", "intensity"};
  for (const char* k : kIgnored) {
    if (name == k) return true;
  }
  return name.rfind("scalar", 0) == 0 || name.rfind("sf", 0) == 0;
}

std::string trim(std::string s) {
  while (!s.empty() && (s.back() == ' ' || s.back() == '\r' || s.back() == '\t')) s.pop_back();
  size_t start = 0;
  while (start < s.size() && (s[start] == ' ' || s[start] == '\t')) ++start;
  return s.substr(start);
}

bool is_blank(char c) { return c == ' ' || c == '\t' || c == '\r'; }

std::string_view trim_view(std::string_view s) {
  while (!s.empty() && is_blank(s.back())) s.remove_suffix(1);
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
  return s;
}

// The next row of `text` from `at` (without its '\n'), moving `at` past it; false at the end.
bool next_row(std::string_view text, size_t& at, std::string_view& row) {
  if (at >= text.size()) return false;
  const size_t end = std::min(text.find('\n', at), text.size());
  row = text.substr(at, end - at);
  at = end + 1;
  return true;
}

// split_fields() without a copy: a million rows spent more time in string streams than in the fit.
void split_views(std::string_view row, char separator, std::vector<std::string_view>& fields) {
  fields.clear();
  if (separator != ' ') {
    size_t start = 0;
    for (;;) {
      const size_t end = row.find(separator, start);
      fields.push_back(row.substr(start, end == std::string_view::npos ? std::string_view::npos : end - start));
      if (end == std::string_view::npos) return;
      start = end + 1;
    }
  }
  auto space = [](char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\v' || c == '\f' || c == '\n'; };
  size_t i = 0;
  while (i < row.size()) {
    while (i < row.size() && space(row[i])) ++i;
    const size_t start = i;
    while (i < row.size() && !space(row[i])) ++i;
    if (i > start) fields.push_back(row.substr(start, i - start));
  }
}

}  // namespace

namespace {

uint64_t mixed(uint64_t v) {
  // SplitMix64's finalizer: every bit of the coordinate moves every bit of the hash.
  v ^= v >> 30;
  v *= 0xbf58476d1ce4e5b9ULL;
  v ^= v >> 27;
  v *= 0x94d049bb133111ebULL;
  return v ^ (v >> 31);
}

uint64_t coordinate_bits(double c) {
  c += 0.0;  // -0.0 becomes 0.0: equal coordinates, equal bits (NaN never reaches here)
  uint64_t bits;
  std::memcpy(&bits, &c, sizeof bits);
  return bits;
}

}  // namespace

void check_duplicate_points(const PointCloud& cloud, const std::function<std::string(size_t)>& where_is) {
  // Equal points hash alike, so the points are dealt by their hash's top bits into parts small
  // enough that each part's open-addressing table stays in the cache (one table over a million
  // points missed it at nearly every probe), and the parts share the cores. Within a part the
  // points go in file order: the first one found already in the table is the part's earliest
  // repeat, and the earliest over all parts is the file's, with the table holding the number of
  // the point it repeats. A sort of the numbers by coordinates did the same in 0.2 s on a million
  // points; one table, in 0.04 s; this, in less.
  const std::vector<Point3>& p = cloud.points;
  if (p.size() < 2) return;
  std::vector<uint64_t> hash(p.size());
  parallel_for(p.size(), [&](size_t begin, size_t end, unsigned) {
    for (size_t i = begin; i < end; ++i) {
      hash[i] = mixed(coordinate_bits(p[i].x) ^ mixed(coordinate_bits(p[i].y) ^ mixed(coordinate_bits(p[i].z))));
    }
  }, 16384);
  // About 8k points a part (a 256 KB table), at most 4096 parts.
  int part_bits = 0;
  while (part_bits < 12 && (p.size() >> part_bits) > 8192) ++part_bits;
  const size_t parts = size_t{1} << part_bits;
  auto part_of = [&](size_t i) { return part_bits == 0 ? size_t{0} : static_cast<size_t>(hash[i] >> (64 - part_bits)); };
  std::vector<size_t> start(parts + 1, 0), members(p.size());
  for (size_t i = 0; i < p.size(); ++i) ++start[part_of(i) + 1];
  for (size_t q = 1; q <= parts; ++q) start[q] += start[q - 1];
  {
    std::vector<size_t> fill(start.begin(), start.end() - 1);
    for (size_t i = 0; i < p.size(); ++i) members[fill[part_of(i)]++] = i;
  }
  std::vector<std::pair<size_t, size_t>> repeat(parts, {SIZE_MAX, SIZE_MAX});  // (point, the earlier one)
  parallel_for(parts, [&](size_t first, size_t last, unsigned) {
    // A slot holds a point's hash beside its number: the points themselves, scattered over the
    // file, are read only where the whole hash matches.
    std::vector<std::pair<uint64_t, size_t>> slot;
    for (size_t q = first; q < last; ++q) {
      const size_t count = start[q + 1] - start[q];
      size_t capacity = 16;
      while (capacity < 2 * count) capacity *= 2;
      slot.assign(capacity, {0, SIZE_MAX});
      for (size_t m = start[q]; m < start[q + 1] && repeat[q].first == SIZE_MAX; ++m) {
        const size_t i = members[m];
        for (size_t s = static_cast<size_t>(hash[i]) & (capacity - 1);; s = (s + 1) & (capacity - 1)) {
          const size_t held = slot[s].second;
          if (held == SIZE_MAX) {
            slot[s] = {hash[i], i};
            break;
          }
          if (slot[s].first == hash[i] && p[held].x == p[i].x && p[held].y == p[i].y && p[held].z == p[i].z) {
            repeat[q] = {i, held};
            break;
          }
        }
      }
    }
  }, 1);
  const auto earliest = std::min_element(repeat.begin(), repeat.end());
  if (earliest->first != SIZE_MAX) throw PointFileError(where_is(earliest->first) + ": the same point as " + where_is(earliest->second));
}

PointCloud parse_csv_points(std::string_view text, const std::string& name) {
  check_no_nul(text, name);
  size_t at = 0;
  std::string_view row;
  size_t line_no = 0;
  std::vector<std::string> columns;
  bool have_header = false;
  while (next_row(text, at, row)) {
    ++line_no;
    if (!trim_view(row).empty()) {
      have_header = true;
      break;
    }
  }
  if (!have_header) throw PointFileError(name + ": empty file");
  // CloudCompare's ASCII export starts its header with "//" and may separate by spaces, tabs or
  // semicolons; names are matched ignoring case (X, Nx). The header's separator is the rows'.
  std::string header(trim_view(row));
  if (header.rfind("//", 0) == 0) header = trim(header.substr(2));
  const char separator = header.find(',') != std::string::npos   ? ','
                         : header.find(';') != std::string::npos ? ';'
                                                                 : ' ';
  std::vector<std::string> as_written;
  for (auto& c : split_fields(header, separator)) {
    as_written.push_back(trim(c));
    columns.push_back(lower_case(as_written.back()));
  }
  static const char* kKnown[] = {"x", "y", "z", "line", "nx", "ny", "nz", "sigma"};
  std::map<std::string, size_t> index;
  for (size_t i = 0; i < columns.size(); ++i) {
    bool known = false;
    for (const char* k : kKnown) known = known || columns[i] == k;
    if (!known && ignored_column(columns[i])) continue;
    if (!known) {
      throw PointFileError(where(name, line_no) + ": unknown column " + quoted(as_written[i]) +
                           " (known: x,y,z,line,nx,ny,nz,sigma; colours, intensity and scalar fields are read past)");
    }
    if (!index.emplace(columns[i], i).second) {
      throw PointFileError(where(name, line_no) + ": column " + quoted(as_written[i]) + " appears twice");
    }
  }
  for (const char* required : {"x", "y", "z"}) {
    if (index.count(required) == 0) {
      throw PointFileError(where(name, line_no) + ": header has no '" + required + "' column");
    }
  }
  const bool has_normals = index.count("nx") + index.count("ny") + index.count("nz") > 0;
  if (has_normals && index.count("nx") + index.count("ny") + index.count("nz") != 3) {
    throw PointFileError(where(name, line_no) + ": normals need all of nx, ny, nz");
  }
  PointCloud cloud;
  if (index.count("line")) cloud.line.emplace();
  if (has_normals) cloud.normal.emplace();
  if (index.count("sigma")) cloud.sigma.emplace();
  // Each column's field number, looked up once rather than by name in every row.
  auto column_of = [&](const char* column) { return index.count(column) ? index.at(column) : SIZE_MAX; };
  const size_t cx = column_of("x"), cy = column_of("y"), cz = column_of("z"), cline = column_of("line");
  const size_t cnx = column_of("nx"), cny = column_of("ny"), cnz = column_of("nz"), csigma = column_of("sigma");
  // The rows in pieces on every core, each piece from a row's start: with its first row's line
  // number known (the newlines before it counted first), each names its own errors, and the first
  // piece in the file with one holds the file's first. One core took 0.1 s for a million rows.
  struct Piece {
    size_t begin = 0, end = 0, first_line = 0;
    PointCloud cloud;
    std::vector<size_t> source_lines;
    std::exception_ptr error;
  };
  const size_t body = text.size() - std::min(at, text.size());
  const size_t piece_count = body < (size_t{1} << 20) ? 1 : std::max(1u, worker_count());
  std::vector<Piece> pieces(piece_count);
  for (size_t p = 0; p < piece_count; ++p) {
    size_t begin = p == 0 ? at : pieces[p - 1].end;
    size_t end = p + 1 == piece_count ? text.size() : std::max(begin, at + body * (p + 1) / piece_count);
    if (end < text.size()) {
      const size_t newline = text.find('\n', end);
      end = newline == std::string_view::npos ? text.size() : newline + 1;
    }
    pieces[p].begin = std::min(begin, text.size());
    pieces[p].end = end;
  }
  std::vector<size_t> newlines(piece_count, 0);
  parallel_for(piece_count, [&](size_t first, size_t last, unsigned) {
    for (size_t p = first; p < last; ++p) {
      newlines[p] = static_cast<size_t>(std::count(text.begin() + static_cast<std::ptrdiff_t>(pieces[p].begin),
                                                   text.begin() + static_cast<std::ptrdiff_t>(pieces[p].end), '\n'));
    }
  }, 1);
  size_t total_newlines = 0;
  for (size_t p = 0; p < piece_count; ++p) {
    pieces[p].first_line = line_no + total_newlines;
    total_newlines += newlines[p];
  }
  parallel_for(piece_count, [&](size_t first, size_t last, unsigned) {
    for (size_t p = first; p < last; ++p) {
      Piece& piece = pieces[p];
      PointCloud& part = piece.cloud;
      if (cloud.line) part.line.emplace();
      if (cloud.normal) part.normal.emplace();
      if (cloud.sigma) part.sigma.emplace();
      // A row to a newline at most (and one after the last): each vector is allocated once, and the
      // first piece's hold the others' rows too, appended below without moving (growing them was a
      // third of the reading, the kernel zeroing the new pages and the copies).
      const size_t rows_at_most = (p == 0 ? total_newlines : newlines[p]) + 1;
      part.points.reserve(rows_at_most);
      if (part.line) part.line->reserve(rows_at_most);
      if (part.normal) part.normal->reserve(rows_at_most);
      if (part.sigma) part.sigma->reserve(rows_at_most);
      piece.source_lines.reserve(rows_at_most);
      const std::string_view rows = text.substr(piece.begin, piece.end - piece.begin);
      size_t row_at = 0, row_line = piece.first_line;
      std::string_view row_text;
      std::vector<std::string_view> fields;
      try {
        while (next_row(rows, row_at, row_text)) {
          ++row_line;
          if (trim_view(row_text).empty()) continue;
          split_views(row_text, separator, fields);
          if (fields.size() != columns.size()) {
            throw PointFileError(where(name, row_line) + ": " + std::to_string(fields.size()) +
                                 " values, the header has " + std::to_string(columns.size()));
          }
          auto value = [&](size_t field, const char* column) { return parse_number(fields[field], name, row_line, column); };
          auto coordinate = [&](size_t field, const char* column) { return parse_coordinate(fields[field], name, row_line, column); };
          part.points.push_back({coordinate(cx, "x"), coordinate(cy, "y"), coordinate(cz, "z")});
          if (part.line) {
            uint32_t l = 0;
            if (!line_number_of(value(cline, "line"), l)) throw PointFileError(where(name, row_line) + ": " + kLineNumberRule);
            part.line->push_back(l);
          }
          if (part.normal) part.normal->push_back({coordinate(cnx, "nx"), coordinate(cny, "ny"), coordinate(cnz, "nz")});
          if (part.sigma) {
            const double s = value(csigma, "sigma");
            if (!valid_sigma(s)) throw PointFileError(where(name, row_line) + ": " + kSigmaRule);
            part.sigma->push_back(s);
          }
          piece.source_lines.push_back(row_line);
        }
      } catch (...) {
        piece.error = std::current_exception();
      }
    }
  }, 1);
  for (const Piece& piece : pieces) {
    if (piece.error) std::rethrow_exception(piece.error);
  }
  std::vector<size_t> source_lines = std::move(pieces[0].source_lines);
  {
    PointCloud& first = pieces[0].cloud;
    cloud.points = std::move(first.points);
    if (cloud.line) cloud.line = std::move(first.line);
    if (cloud.normal) cloud.normal = std::move(first.normal);
    if (cloud.sigma) cloud.sigma = std::move(first.sigma);
  }
  auto append = [](auto& to, const auto& from) { to.insert(to.end(), from.begin(), from.end()); };
  for (size_t p = 1; p < piece_count; ++p) {
    const PointCloud& part = pieces[p].cloud;
    append(cloud.points, part.points);
    if (cloud.line) append(*cloud.line, *part.line);
    if (cloud.normal) append(*cloud.normal, *part.normal);
    if (cloud.sigma) append(*cloud.sigma, *part.sigma);
    append(source_lines, pieces[p].source_lines);
  }
  check_duplicate_points(cloud, [&](size_t i) { return where(name, source_lines[i]); });
  return cloud;
}

PointCloud parse_xyz_points(std::string_view text, const std::string& name) {
  check_no_nul(text, name);
  // A CloudCompare export names its columns on a first line starting "//": read by those names.
  {
    std::istringstream first{std::string(text)};
    std::string row;
    while (std::getline(first, row) && trim(row).empty()) {
    }
    if (trim(row).rfind("//", 0) == 0) return parse_csv_points(text, name);
  }
  std::istringstream in{std::string(text)};
  std::string row;
  size_t line_no = 0;
  PointCloud cloud;
  std::vector<size_t> source_lines;
  while (std::getline(in, row)) {
    ++line_no;
    const std::string t = trim(row);
    if (t.empty() || t[0] == '#') continue;
    std::istringstream fields(t);
    std::vector<std::string> values;
    std::string v;
    while (fields >> v) values.push_back(v);
    if (values.size() != 3) {
      throw PointFileError(where(name, line_no) + ": expected 3 values (x y z), found " +
                           std::to_string(values.size()));
    }
    cloud.points.push_back({parse_coordinate(values[0], name, line_no, "x"),
                            parse_coordinate(values[1], name, line_no, "y"),
                            parse_coordinate(values[2], name, line_no, "z")});
    source_lines.push_back(line_no);
  }
  check_duplicate_points(cloud, [&](size_t i) { return where(name, source_lines[i]); });
  return cloud;
}

PointCloud read_points(const std::string& path, bool as_measured) {
  const FileFormat format = file_format(path);
  if (format == FileFormat::kScan) {
    ScanData data = read_scan_file(path);
    if (as_measured) data.calibration_json.reset();
    ScanPointSigmas sigmas = scan_point_sigmas(data);
    // The reference readings leave the points, and correct them for the gauge's drift first (the
    // drift is in time; the calibration after it is in place).
    const std::optional<DriftRemoval> drift = remove_drift(data, &sigmas.sigma_mm, path, !as_measured);
    // On the fly: each point where the gauge latched it, and the readings taken in the air left out.
    const std::optional<FlyCorrection> fly = as_measured ? std::nullopt : correct_fly_scan(data, &sigmas.sigma_mm, path);
    // The scan's own calibration record corrects the raw points it keeps.
    const std::optional<TableCalibration> calibration = correct_by_record(data, &sigmas.sigma_mm, path);
    // Where the part slopes, the table's own position uncertainty reaches the height too.
    const double position_mm = add_position_uncertainty(data, table_position(data, calibration), sigmas.sigma_mm);
    PointCloud cloud;
    cloud.line.emplace();
    if (data.device && data.device->gauge_resolution_nm > 0) cloud.resolution_mm = data.device->gauge_resolution_nm * 1e-6;
    for (const auto& p : data.points) {
      cloud.points.push_back({p.x_nm * 1e-6, p.y_nm * 1e-6, p.z_nm * 1e-6});
      cloud.line->push_back(p.line);
    }
    if (!sigmas.sigma_mm.empty()) {
      cloud.sigma = std::move(sigmas.sigma_mm);
      cloud.sigma_from = sigmas.from + (drift ? ", the drift removal" : "") + (calibration ? " and the table calibration's map" : "");
      if (position_mm > 0) {
        char text[160];
        std::snprintf(text, sizeof text, ", and the table's position times the part's slope (adds u <= %.4f mm)", position_mm);
        cloud.sigma_from += text;
      }
    }
    if (calibration) cloud.calibration = "the table calibration of " + (calibration->created_utc.empty() ? std::string("unknown date") : calibration->created_utc);
    if (fly) {
      cloud.fly = fly_summary(*fly);
      std::fprintf(stderr, "digitizer: %s: %s\n", path.c_str(), cloud.fly.c_str());
      if (cloud.sigma) cloud.sigma_from += ", and the latch delay's correction times the slope";
    }
    if (drift) {
      char text[160];
      std::snprintf(text, sizeof text, "drift removed by %zu reference readings (up to %.4f mm; adds u <= %.4f mm)",
                    drift->readings, drift->largest_mm, drift->u_max_mm);
      cloud.drift = text;
    }
    return cloud;
  }
  FileBytes file;
  if (!file.read(path)) throw PointFileError(path + ": cannot open: " + std::strerror(errno));
  const std::string_view bytes = file.view();
  if (format == FileFormat::kCsv) return parse_csv_points(bytes, path);
  if (format == FileFormat::kXyz || format == FileFormat::kText) return parse_xyz_points(bytes, path);
  if (format == FileFormat::kPly) {
    return parse_ply_points(reinterpret_cast<const uint8_t*>(bytes.data()), bytes.size(), path);
  }
  if (format == FileFormat::kBcncProbe || format == FileFormat::kCandleMap || format == FileFormat::kKlipperMesh) {
    const std::string text(bytes);
    const HeightMap map = format == FileFormat::kBcncProbe ? parse_bcnc_probe(text, path)
                          : format == FileFormat::kCandleMap ? parse_candle_map(text, path)
                                                             : parse_klipper_mesh(text, path);
    PointCloud cloud;
    cloud.points = map.points();
    for (size_t k = 0; k < cloud.points.size(); ++k) {
      const Point3& p = cloud.points[k];
      if (!plausible_coordinate(p.x) || !plausible_coordinate(p.y) || !plausible_coordinate(p.z)) {
        throw PointFileError(path + ": the map's point " + std::to_string(k + 1) + ": " + kCoordinateRule);
      }
    }
    return cloud;
  }
  throw PointFileError(path + ": unknown point format (.csv, .xyz, .txt, .ply, .scan, or a height map .probe, .map, .cfg)");
}

}  // namespace dg::host
