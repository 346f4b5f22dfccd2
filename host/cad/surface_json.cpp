// Writing and reading SURF.json with nlohmann::json; every field checked on the way in.
#include "host/cad/surface_json.h"
#include "host/io/whole_file.h"

#include <cmath>
#include <cstdio>
#include <nlohmann/json.hpp>
#include <sstream>
#include <stdexcept>

#include "host/io/atomic_file.h"
#include "host/io/text_field.h"

namespace dg::host {

namespace {

constexpr const char* kFormat = "digitizer-surface";
constexpr int kVersion = 1;

nlohmann::json finite_or_null(double v) { return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr); }

nlohmann::json distance_json(const DistanceStats& d) {
  return {{"kind", "orthogonal"}, {"count", d.count}, {"mean", d.mean}, {"median", d.median}, {"stddev", d.stddev},
          {"rms", d.rms},         {"max", d.max},     {"min", d.min},   {"max_abs", d.max_abs}};
}

// An uncertainty grid; a face's nodes outside it are null.
nlohmann::json uncertainty_json(const SurfaceUncertainty& u, const char* kind) {
  nlohmann::json grid = nlohmann::json::array();
  for (double value : u.u_mm) grid.push_back(value == kOffFace ? nlohmann::json(nullptr) : finite_or_null(value));
  return {{"kind", kind},
          {"sigma_mm", finite_or_null(u.sigma_mm)},
          {"sigma_from", u.sigma_from},
          {"coverage_factor", 2},
          {"max_mm", finite_or_null(u.max_mm)},
          {"mean_mm", finite_or_null(u.mean_mm)},
          {"grid", {u.rows, u.cols}},
          {"u_mm", std::move(grid)}};
}

void put_surface(nlohmann::json& j, const BSplineSurface& s) {
  j["degree"] = {s.degree_u, s.degree_v};
  j["control_count"] = {s.count_u, s.count_v};
  j["knots_u"] = s.knots_u;
  j["knots_v"] = s.knots_v;
  nlohmann::json control = nlohmann::json::array();
  for (const auto& p : s.control) control.push_back({p.x, p.y, p.z});
  j["control_points"] = std::move(control);
}

}  // namespace

std::string surface_json_text(const FittedSurface& f) {
  nlohmann::json j;
  j["format"] = kFormat;
  j["version"] = kVersion;
  j["units"] = "mm";
  j["model"] = f.model;
  j["method"] = f.method;
  j["parameterization"] = f.parameterization;
  j["height_field"] = f.height_field;
  if (f.faces.empty()) {
    put_surface(j, f.surface);
  } else {
    nlohmann::json faces = nlohmann::json::array();
    for (const TrimmedFace& face : f.faces) {
      nlohmann::json one;
      put_surface(one, face.surface);
      nlohmann::json loops = nlohmann::json::array();
      for (const TrimLoop& loop : face.loops) {
        nlohmann::json vertices = nlohmann::json::array();
        for (const Point2& p : loop) vertices.push_back({p.x, p.y});
        loops.push_back(std::move(vertices));
      }
      one["loops"] = std::move(loops);
      if (f.has_fit) one["distance"] = distance_json(face.distance);
      if (face.uncertainty.computed) {
        one["uncertainty"] = uncertainty_json(
            face.uncertainty, "standard uncertainty of the face, from the points' noise (k = 1); null outside the face");
      }
      faces.push_back(std::move(one));
    }
    j["faces"] = std::move(faces);
  }
  if (f.has_fit) {
    nlohmann::json fit;
    fit["source"] = f.source;
    fit["distance"] = distance_json(f.distance);
    if (f.tolerance_mm > 0) {
      fit["tolerance_mm"] = f.tolerance_mm;
      fit["tolerance_kept"] = f.tolerance_kept;
      fit["iterations"] = f.iterations;
    }
    fit["noise_sigma_mm"] = finite_or_null(f.noise_sigma_mm);
    if (f.validation.checked) {
      const FitValidation& v = f.validation;
      fit["validation"] = {
          {"passed", v.passed},
          {"problem", v.problem},
          {"hold_out", {{"folds", v.folds}, {"of", v.folds_of_lines ? "lines" : "points"}, {"points", v.held_out_points}, {"rms_mm", finite_or_null(v.held_out_rms_mm)},
                        {"max_mm", finite_or_null(v.held_out_max_mm)}}},
          {"neighbours", {{"checks", v.neighbour_checks}, {"excess_max_mm", finite_or_null(v.range_excess_max_mm)}}}};
    }
    if (f.uncertainty.computed) {
      fit["uncertainty"] = uncertainty_json(f.uncertainty, "standard uncertainty of the surface, from the points' noise (k = 1)");
    }
    j["fit"] = std::move(fit);
  }
  return j.dump(1) + "\n";
}

void write_surface_json(const std::string& path, const FittedSurface& file) {
  // Never a number that is not one: SURF.json would hold null where a result should be, and the
  // command that made it would end as if all were well.
  const std::string bad = non_finite_result(file);
  if (!bad.empty()) {
    throw std::runtime_error(path + ": not written: " + bad +
                             " came out as no finite number (the computation overflowed or had no defined result)");
  }
  write_file_atomically(path, surface_json_text(file));
}

namespace {

// An integer field: a JSON integer in [lo, hi]. Converting a float such as 2e59 to an int is
// undefined behaviour (found by fuzzing), so the type and range are checked first.
long long whole(const nlohmann::json& v, const std::string& name, const std::string& field, long long lo, long long hi) {
  if (!v.is_number_integer()) throw std::runtime_error(name + ": \"" + field + "\" must be a whole number");
  const long long value = v.is_number_unsigned() && v.get<unsigned long long>() > static_cast<unsigned long long>(hi)
                              ? hi + 1
                              : v.get<long long>();
  if (value < lo || value > hi) {
    throw std::runtime_error(name + ": \"" + field + "\" must be " + std::to_string(lo) + ".." + std::to_string(hi));
  }
  return value;
}

std::vector<int> whole_pair(const nlohmann::json& v, const std::string& name, const std::string& field, int lo, int hi) {
  if (!v.is_array() || v.size() != 2) throw std::runtime_error(name + ": \"" + field + "\" needs two numbers");
  return {static_cast<int>(whole(v[0], name, field, lo, hi)), static_cast<int>(whole(v[1], name, field, lo, hi))};
}

// An uncertainty grid as uncertainty_json writes it. On a face (`where` names it) a null node is
// off the face; a face written before faces carried grids has none (rows and cols 0).
SurfaceUncertainty get_uncertainty(const nlohmann::json& u, const std::string& name, const std::string& where, bool face) {
  auto fail = [&](const std::string& what) { return std::runtime_error(name + ": " + where + "\"uncertainty\": " + what); };
  SurfaceUncertainty out;
  out.computed = true;
  out.sigma_mm = u.at("sigma_mm").get<double>();
  out.sigma_from = u.value("sigma_from", "");
  out.max_mm = u.at("max_mm").get<double>();
  out.mean_mm = u.at("mean_mm").get<double>();
  for (double value : {out.sigma_mm, out.max_mm, out.mean_mm}) {
    if (!(value >= 0) || !std::isfinite(value)) throw fail("a value that is not a finite, non-negative number");
  }
  if (face && !u.contains("grid")) return out;
  const auto grid = whole_pair(u.at("grid"), name, "grid", 2, 4096);
  out.rows = grid[0];
  out.cols = grid[1];
  const auto& values = u.at("u_mm");
  if (!values.is_array() || values.size() != static_cast<size_t>(out.rows) * out.cols) throw fail("\"u_mm\" does not fill its grid");
  for (const auto& v : values) {
    if (face && v.is_null()) {
      out.u_mm.push_back(kOffFace);
      continue;
    }
    const double value = v.is_number() ? v.get<double>() : -1.0;
    if (!(value >= 0) || !std::isfinite(value)) throw fail("a value that is not a finite, non-negative number");
    out.u_mm.push_back(value);
  }
  return out;
}

BSplineSurface get_surface(const nlohmann::json& j, const std::string& name) {
  BSplineSurface s;
  const auto degree = whole_pair(j.at("degree"), name, "degree", 1, 15);
  const auto count = whole_pair(j.at("control_count"), name, "control_count", 1, 1000000);
  s.degree_u = degree[0];
  s.degree_v = degree[1];
  s.count_u = count[0];
  s.count_v = count[1];
  s.knots_u = j.at("knots_u").get<std::vector<double>>();
  s.knots_v = j.at("knots_v").get<std::vector<double>>();
  const auto& control = j.at("control_points");
  if (!control.is_array()) throw std::runtime_error(name + ": \"control_points\" is not an array");
  for (size_t i = 0; i < control.size(); ++i) {
    const auto p = control[i].get<std::vector<double>>();
    if (p.size() != 3) throw std::runtime_error(name + ": control point " + std::to_string(i) + " does not have 3 coordinates");
    s.control.push_back(Point3{p[0], p[1], p[2]});
  }
  std::string why;
  if (!is_valid(s, &why)) throw std::runtime_error(name + ": " + why);
  return s;
}

DistanceStats get_distance(const nlohmann::json& d, const std::string& name) {
  DistanceStats out;
  out.count = static_cast<size_t>(whole(d.at("count"), name, "count", 0, 1LL << 48));
  out.mean = d.at("mean").get<double>();
  out.median = d.at("median").get<double>();
  out.stddev = d.at("stddev").get<double>();
  out.rms = d.at("rms").get<double>();
  out.max = d.at("max").get<double>();
  out.min = d.at("min").get<double>();
  out.max_abs = d.at("max_abs").get<double>();
  return out;
}

// A trimmed face's loops: the outer one counter-clockwise, holes clockwise, all inside the
// surface's box (a height field's parameters are read from table XY, and a loop beyond the box
// would ask for the surface where it is not defined).
void check_face(const TrimmedFace& face, const std::string& name) {
  const Point3& first = face.surface.at(0, 0);
  const Point3& last = face.surface.at(face.surface.count_u - 1, face.surface.count_v - 1);
  const double x0 = std::min(first.x, last.x), x1 = std::max(first.x, last.x);
  const double y0 = std::min(first.y, last.y), y1 = std::max(first.y, last.y);
  const double slack = 1e-6 * (1 + (x1 - x0) + (y1 - y0));
  for (size_t k = 0; k < face.loops.size(); ++k) {
    const double area = twice_signed_area(face.loops[k]);
    if (k == 0 && !(area > 0)) throw std::runtime_error(name + ": the outer loop must run counter-clockwise");
    if (k > 0 && !(area < 0)) throw std::runtime_error(name + ": loop " + std::to_string(k + 1) + " (a hole) must run clockwise");
    for (const Point2& p : face.loops[k]) {
      if (p.x < x0 - slack || p.x > x1 + slack || p.y < y0 - slack || p.y > y1 + slack) {
        throw std::runtime_error(name + ": a loop vertex lies outside the face's surface");
      }
    }
  }
}

}  // namespace

FittedSurface parse_surface_json(const std::string& text, const std::string& name) {
  nlohmann::json j;
  try {
    j = nlohmann::json::parse(text);
  } catch (const nlohmann::json::parse_error& e) {
    throw std::runtime_error(name + ": not valid JSON (byte " + std::to_string(e.byte) + ")");
  } catch (const nlohmann::json::exception&) {
    // A number too large for a double (1e23089) is out_of_range, not a parse_error.
    throw std::runtime_error(name + ": a number beyond the range of a double");
  }
  auto fail = [&](const std::string& what) { return std::runtime_error(name + ": " + what); };
  if (!j.is_object() || !j.contains("format") || !j.at("format").is_string() || j.at("format").get<std::string>() != kFormat) {
    throw fail("not a digitizer surface file (\"format\" is missing)");
  }
  if (!j["version"].is_number_integer() || j["version"].get<int>() != kVersion) throw fail("unsupported version");
  FittedSurface f;
  try {
    f.model = j.at("model").get<std::string>();
    f.method = j.value("method", "lsq");
    f.parameterization = j.value("parameterization", "xy");
    // Only what the format defines (docs/surface-json.md): a "nurbs" surface would be read as a
    // non-rational one, its weights ignored.
    auto one_of = [&](const std::string& field, const std::string& value, std::initializer_list<const char*> known) {
      for (const char* k : known) {
        if (value == k) return;
      }
      std::string list;
      for (const char* k : known) list += std::string(list.empty() ? "" : ", ") + k;
      throw fail("\"" + field + "\" is " + quoted(value) + "; known: " + list);
    };
    one_of("model", f.model, {"bspline", "bezier", "hermite", "revolution"});
    one_of("method", f.method, {"lsq", "ips", "normals", "superquadric", "device"});
    one_of("parameterization", f.parameterization, {"xy", "uniform", "chord", "centripetal", "axis"});
    f.height_field = j.value("height_field", false);
    if (j.contains("faces")) {
      const auto& faces = j.at("faces");
      if (!faces.is_array() || faces.empty()) throw fail("\"faces\" must be a non-empty array");
      if (!f.height_field || f.parameterization != "xy") throw fail("trimmed faces are height fields over table XY");
      for (size_t k = 0; k < faces.size(); ++k) {
        const std::string where = name + ": face " + std::to_string(k + 1);
        TrimmedFace face;
        face.surface = get_surface(faces[k], where);
        const auto& loops = faces[k].at("loops");
        if (!loops.is_array() || loops.empty()) throw fail("face " + std::to_string(k + 1) + " has no \"loops\"");
        for (const auto& loop : loops) {
          TrimLoop l;
          if (!loop.is_array()) throw fail("face " + std::to_string(k + 1) + ": a loop is not an array");
          for (const auto& v : loop) {
            const auto xy = v.get<std::vector<double>>();
            if (xy.size() != 2 || !std::isfinite(xy[0]) || !std::isfinite(xy[1])) {
              throw fail("face " + std::to_string(k + 1) + ": a loop vertex is not two finite numbers");
            }
            l.push_back({xy[0], xy[1]});
          }
          if (l.size() < 3) throw fail("face " + std::to_string(k + 1) + ": a loop has fewer than 3 vertices");
          face.loops.push_back(std::move(l));
        }
        check_face(face, where);
        if (faces[k].contains("distance")) face.distance = get_distance(faces[k].at("distance"), where);
        face.points = face.distance.count;
        if (faces[k].contains("uncertainty")) {
          face.uncertainty = get_uncertainty(faces[k].at("uncertainty"), name, "face " + std::to_string(k + 1) + ": ", true);
        }
        f.faces.push_back(std::move(face));
      }
    } else {
      f.surface = get_surface(j, name);
    }
    if (j.contains("fit")) {
      const auto& fit = j["fit"];
      f.has_fit = true;
      f.source = fit.value("source", "");
      f.distance = get_distance(fit.at("distance"), name);
      f.tolerance_mm = fit.value("tolerance_mm", 0.0);
      f.tolerance_kept = fit.value("tolerance_kept", false);
      f.iterations = fit.contains("iterations") ? static_cast<int>(whole(fit.at("iterations"), name, "iterations", 0, 1000000)) : 0;
      // (A const json's operator[] on a missing key is undefined: found by fuzzing.)
      f.noise_sigma_mm = fit.contains("noise_sigma_mm") && fit.at("noise_sigma_mm").is_number()
                             ? fit.at("noise_sigma_mm").get<double>()
                             : 0.0;
      if (fit.contains("validation")) {
        const auto& v = fit["validation"];
        f.validation.checked = true;
        f.validation.passed = v.at("passed").get<bool>();
        f.validation.problem = v.value("problem", "");
        const auto& h = v.at("hold_out");
        f.validation.folds = static_cast<int>(whole(h.at("folds"), name, "folds", 0, 1000));
        f.validation.folds_of_lines = h.value("of", std::string("lines")) != "points";
        f.validation.held_out_points = static_cast<size_t>(whole(h.at("points"), name, "points", 0, 1LL << 48));
        f.validation.held_out_rms_mm = h.at("rms_mm").get<double>();
        f.validation.held_out_max_mm = h.at("max_mm").get<double>();
        const auto& n = v.at("neighbours");
        f.validation.neighbour_checks = static_cast<size_t>(whole(n.at("checks"), name, "checks", 0, 1LL << 48));
        f.validation.range_excess_max_mm = n.at("excess_max_mm").get<double>();
      }
      if (fit.contains("uncertainty")) f.uncertainty = get_uncertainty(fit.at("uncertainty"), name, "", false);
    }
  } catch (const nlohmann::json::exception& e) {
    throw fail(std::string("missing or mistyped field: ") + e.what());
  }
  return f;
}

FittedSurface read_surface_json(const std::string& path) {
  std::string text;
  if (!read_whole_file(path, &text)) throw std::runtime_error(path + ": cannot open");
  return parse_surface_json(text, path);
}

}  // namespace dg::host
