// The IGES fixed-column writer (IGES 5.3, US PRO/IPO-100, sections 2.2 and 4.26 for entity 128).
#include "host/cad/iges_writer.h"

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <stdexcept>
#include <vector>

#include "host/io/atomic_file.h"

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

namespace {

struct Entity {
  int type;
  std::string label;
  std::vector<std::string> parameters;
  // Blank, subordinate, use, hierarchy: 00010000 for geometry another entity uses (physically
  // dependent), 00010500 for a curve in a surface's parameter space.
  std::string status = "00000000";
};

// The whole file for a list of independent geometry entities.
std::string document(const std::vector<Entity>& entities, double max_coordinate, const IgesOptions& options,
                     const std::string& start) {
  std::string out = section_line(start, 'S', 1);
  const std::vector<std::string> global = {
      "1H,", "1H;", hollerith(options.product), hollerith(options.file_name), hollerith("bench digitizer"),
      hollerith("bench digitizer IGES writer 1"), "32", "38", "6", "308", "15", hollerith(options.product),
      "1.0", "2", hollerith("MM"), "1", "0.01", hollerith(options.timestamp), iges_real(options.resolution_mm),
      iges_real(max_coordinate), hollerith(options.author), hollerith(options.organization), "11", "0",
      hollerith(options.timestamp)};
  int g = 0;
  for (const std::string& line : pack(global, 72)) out += section_line(line, 'G', ++g);
  // Directory entries: two lines of nine 8-column fields each. Status 00000000: visible,
  // independent, geometry. Parameter lines carry their entry's directory line in columns 66-72.
  auto field = [](const std::string& v) { return right(v, 8); };
  std::string directory, parameters;
  int d = 0, p = 0;
  for (const Entity& e : entities) {
    const std::vector<std::string> lines = pack(e.parameters, 64);
    const int first_d = d + 1;
    directory += section_line(field(std::to_string(e.type)) + field(std::to_string(p + 1)) + field("0") + field("0") +
                                  field("0") + field("0") + field("0") + field("0") + e.status,
                              'D', ++d);
    directory += section_line(field(std::to_string(e.type)) + field("0") + field("0") + field(std::to_string(lines.size())) +
                                  field("0") + field("") + field("") + field(e.label) + field("0"),
                              'D', ++d);
    for (const std::string& line : lines) parameters += section_line(pad(line, 64) + right(std::to_string(first_d), 8), 'P', ++p);
  }
  out += directory + parameters;
  char terminate[73];
  std::snprintf(terminate, sizeof terminate, "S%7dG%7dD%7dP%7d", 1, g, d, p);
  out += section_line(terminate, 'T', 1);
  return out;
}

double largest_coordinate(const std::vector<Point3>& points, double so_far) {
  for (const Point3& p : points) so_far = std::fmax(so_far, std::fmax(std::fabs(p.x), std::fmax(std::fabs(p.y), std::fabs(p.z))));
  return so_far;
}

}  // namespace

namespace {

Entity surface_entity(const BSplineSurface& s) {
  std::string why;
  if (!is_valid(s, &why)) throw std::invalid_argument("cannot write this surface as IGES: " + why);
  // Entity 128: K1, K2, M1, M2, PROP1..5, knots, weights, control points (u index fastest), bounds.
  Entity e{128, "SURFACE", {"128", std::to_string(s.count_u - 1), std::to_string(s.count_v - 1), std::to_string(s.degree_u),
                            std::to_string(s.degree_v), "0", "0", "1", "0", "0"}};
  auto& p = e.parameters;
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
  return e;
}

// A closed polyline as entity 126 of degree 1: the first point repeated at the end, knots 0..n-1.
Entity polyline_entity(const std::vector<Point3>& points, bool planar) {
  const int n = static_cast<int>(points.size()) + 1;
  Entity e{126, planar ? "PCURVE" : "TRIMCRV", {"126", std::to_string(n - 1), "1", planar ? "1" : "0", "1", "1", "0"}};
  e.status = planar ? "00010500" : "00010000";
  e.parameters.push_back("0.");
  for (int k = 0; k < n; ++k) e.parameters.push_back(iges_real(k));
  e.parameters.push_back(iges_real(n - 1));
  for (int k = 0; k < n; ++k) e.parameters.push_back("1.");
  for (int k = 0; k < n; ++k) {
    const Point3& q = points[static_cast<size_t>(k % (n - 1))];
    e.parameters.push_back(iges_real(q.x));
    e.parameters.push_back(iges_real(q.y));
    e.parameters.push_back(iges_real(q.z));
  }
  e.parameters.push_back("0.");
  e.parameters.push_back(iges_real(n - 1));
  for (const char* v : {"0.", "0.", "1."}) e.parameters.push_back(v);
  return e;
}

}  // namespace

std::string iges_text(const BSplineSurface& s, const IgesOptions& options) {
  return document({surface_entity(s)}, largest_coordinate(s.control, 0), options,
                  "Bench digitizer: a B-spline surface fitted to measured points, mm");
}

std::string iges_faces_text(const std::vector<TrimmedFace>& faces, const IgesOptions& options) {
  if (faces.empty()) throw std::invalid_argument("no faces to write");
  std::vector<Entity> entities;
  double largest = 0;
  auto de = [&]() { return std::to_string(2 * entities.size() + 1); };  // the next entity's directory line
  for (const TrimmedFace& face : faces) {
    if (face.loops.empty()) throw std::invalid_argument("a trimmed face without a boundary");
    const std::string surface = de();
    Entity se = surface_entity(face.surface);
    se.status = "00010000";
    entities.push_back(std::move(se));
    largest = largest_coordinate(face.surface.control, largest);
    std::vector<std::string> boundaries;
    for (const TrimLoop& loop : face.loops) {
      const TrimLoop fine = densified(loop, 0.25);
      std::vector<Point3> in_parameters, on_surface;
      for (const Point2& p : fine) {
        double u, v;
        table_to_parameters(face.surface, p.x, p.y, u, v);
        in_parameters.push_back({u, v, 0});
        on_surface.push_back(point_above(face.surface, p.x, p.y));
      }
      largest = largest_coordinate(on_surface, largest);
      const std::string pcurve = de();
      entities.push_back(polyline_entity(in_parameters, true));
      const std::string curve = de();
      entities.push_back(polyline_entity(on_surface, false));
      boundaries.push_back(de());
      // CRTN 0 (unspecified), the surface, the parameter-space curve, the model-space one, PREF 1.
      Entity on{142, "BOUNDARY", {"142", "0", surface, pcurve, curve, "1"}};
      on.status = "00010000";
      entities.push_back(std::move(on));
    }
    Entity trimmed{144, "TRIMSRF", {"144", surface, "1", std::to_string(boundaries.size() - 1), boundaries[0]}};
    for (size_t k = 1; k < boundaries.size(); ++k) trimmed.parameters.push_back(boundaries[k]);
    entities.push_back(std::move(trimmed));
  }
  return document(entities, largest, options, "Bench digitizer: trimmed B-spline surfaces fitted to measured points, mm");
}

void write_iges_faces(const std::string& path, const std::vector<TrimmedFace>& faces, const IgesOptions& options) {
  write_file_atomically(path, iges_faces_text(faces, options));
}

std::string iges_curves_text(const std::vector<BSplineCurve>& curves, const IgesOptions& options) {
  std::vector<Entity> entities;
  double largest = 0;
  for (const BSplineCurve& c : curves) {
    const int n = static_cast<int>(c.control.size());
    if (c.degree < 1 || n <= c.degree || c.knots.size() != static_cast<size_t>(n + c.degree + 1)) {
      throw std::invalid_argument("cannot write a curve as IGES: its knots, degree and control points disagree");
    }
    // Entity 126: K, M, PROP1..4 (planar, closed, polynomial, periodic), knots, weights, control
    // points, parameter range, and the unit normal (unused for a non-planar curve).
    Entity e{126, "CURVE", {"126", std::to_string(n - 1), std::to_string(c.degree), "0", "0", "1", "0"}};
    for (double k : c.knots) e.parameters.push_back(iges_real(k));
    for (int i = 0; i < n; ++i) e.parameters.push_back("1.");
    for (const Point3& q : c.control) {
      e.parameters.push_back(iges_real(q.x));
      e.parameters.push_back(iges_real(q.y));
      e.parameters.push_back(iges_real(q.z));
    }
    for (const char* v : {"", "", "0.", "0.", "1."}) e.parameters.push_back(v);
    e.parameters[e.parameters.size() - 5] = iges_real(c.t_min());
    e.parameters[e.parameters.size() - 4] = iges_real(c.t_max());
    entities.push_back(e);
    largest = largest_coordinate(c.control, largest);
  }
  return document(entities, largest, options, "Bench digitizer: B-spline curves, mm");
}

void write_iges_curves(const std::string& path, const std::vector<BSplineCurve>& curves, const IgesOptions& options) {
  write_file_atomically(path, iges_curves_text(curves, options));
}

void write_iges(const std::string& path, const BSplineSurface& surface, const IgesOptions& options) {
  write_file_atomically(path, iges_text(surface, options));
}

}  // namespace dg::host
