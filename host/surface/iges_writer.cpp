// The IGES fixed-column writer (IGES 5.3, US PRO/IPO-100, sections 2.2 and 4.26 for entity 128).
#include "host/surface/iges_writer.h"

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <stdexcept>
#include <vector>

#include "host/surface/atomic_file.h"

namespace dg::host {

std::string iges_real(double value) {
  if (!std::isfinite(value)) throw std::invalid_argument("IGES cannot hold a value that is not finite");
  char text[40];
  // The shortest of 15..17 significant digits that reads back to the same double.
  for (int digits = 15; digits <= 17; ++digits) {
    std::snprintf(text, sizeof text, "%.*G", digits, value);
    if (std::strtod(text, nullptr) == value) break;
  }
  std::string s = text;
  // A real constant needs a decimal point: "3" -> "3.", "1E-05" -> "1.E-05".
  if (s.find('.') == std::string::npos) {
    const size_t e = s.find('E');
    s.insert(e == std::string::npos ? s.size() : e, ".");
  }
  return s;
}

namespace {

std::string hollerith(const std::string& text) { return std::to_string(text.size()) + "H" + text; }

// Packs parameter tokens into lines of `width` columns: each token ends with the parameter
// delimiter, the last with the record delimiter; a token never straddles two lines.
std::vector<std::string> pack(const std::vector<std::string>& tokens, size_t width) {
  std::vector<std::string> lines(1);
  for (size_t i = 0; i < tokens.size(); ++i) {
    const std::string token = tokens[i] + (i + 1 == tokens.size() ? ";" : ",");
    if (token.size() > width) throw std::invalid_argument("IGES parameter longer than a line: " + token);
    if (lines.back().size() + token.size() > width) lines.emplace_back();
    lines.back() += token;
  }
  return lines;
}

std::string pad(std::string text, size_t width) {
  text.resize(width, ' ');
  return text;
}

std::string right(const std::string& text, size_t width) {
  return text.size() >= width ? text : std::string(width - text.size(), ' ') + text;
}

std::string section_line(const std::string& data72, char section, int sequence) {
  return pad(data72, 72) + section + right(std::to_string(sequence), 7) + "\n";
}

}  // namespace

std::string iges_text(const BSplineSurface& s, const IgesOptions& options) {
  std::string why;
  if (!is_valid(s, &why)) throw std::invalid_argument("cannot write this surface as IGES: " + why);
  double max_coordinate = 0;
  for (const Point3& p : s.control) {
    max_coordinate = std::fmax(max_coordinate, std::fmax(std::fabs(p.x), std::fmax(std::fabs(p.y), std::fabs(p.z))));
  }

  std::string out;
  out += section_line("Bench digitizer: a B-spline surface fitted to measured points, mm", 'S', 1);

  const std::vector<std::string> global = {
      "1H,", "1H;", hollerith(options.file_name), hollerith(options.file_name), hollerith("bench digitizer"),
      hollerith("bench digitizer IGES writer 1"), "32", "38", "6", "308", "15", hollerith(options.file_name),
      "1.0", "2", hollerith("MM"), "1", "0.01", hollerith(options.timestamp), iges_real(options.resolution_mm),
      iges_real(max_coordinate), hollerith(options.author), hollerith(options.organization), "11", "0",
      hollerith(options.timestamp)};
  int g = 0;
  for (const std::string& line : pack(global, 72)) out += section_line(line, 'G', ++g);

  // Entity 128: K1, K2, M1, M2, PROP1..5, knots, weights, control points (u index fastest), bounds.
  std::vector<std::string> p = {"128", std::to_string(s.count_u - 1), std::to_string(s.count_v - 1),
                                std::to_string(s.degree_u), std::to_string(s.degree_v), "0", "0", "1", "0", "0"};
  for (double k : s.knots_u) p.push_back(iges_real(k));
  for (double k : s.knots_v) p.push_back(iges_real(k));
  for (size_t i = 0; i < s.control.size(); ++i) p.push_back("1.");
  for (int j = 0; j < s.count_v; ++j) {
    for (int i = 0; i < s.count_u; ++i) {
      const Point3& c = s.at(i, j);
      p.push_back(iges_real(c.x));
      p.push_back(iges_real(c.y));
      p.push_back(iges_real(c.z));
    }
  }
  p.push_back(iges_real(s.u_min()));
  p.push_back(iges_real(s.u_max()));
  p.push_back(iges_real(s.v_min()));
  p.push_back(iges_real(s.v_max()));
  const std::vector<std::string> parameter_lines = pack(p, 64);

  // Directory entry: two lines of nine 8-column fields. Status 00000000: visible, independent,
  // geometry, its own level.
  auto field = [](const std::string& v) { return right(v, 8); };
  const std::string de1 = field("128") + field("1") + field("0") + field("0") + field("0") + field("0") + field("0") +
                          field("0") + "00000000";
  const std::string de2 = field("128") + field("0") + field("0") + field(std::to_string(parameter_lines.size())) +
                          field("0") + field("") + field("") + field("SURFACE") + field("0");
  out += section_line(de1, 'D', 1);
  out += section_line(de2, 'D', 2);

  int sequence = 0;
  for (const std::string& line : parameter_lines) out += section_line(pad(line, 64) + right("1", 8), 'P', ++sequence);

  char terminate[73];
  std::snprintf(terminate, sizeof terminate, "S%7dG%7dD%7dP%7d", 1, g, 2, sequence);
  out += section_line(terminate, 'T', 1);
  return out;
}

void write_iges(const std::string& path, const BSplineSurface& surface, const IgesOptions& options) {
  write_file_atomically(path, iges_text(surface, options));
}

}  // namespace dg::host
