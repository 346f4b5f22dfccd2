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
  j["degree"] = {f.surface.degree_u, f.surface.degree_v};
  j["control_count"] = {f.surface.count_u, f.surface.count_v};
  j["knots_u"] = f.surface.knots_u;
  j["knots_v"] = f.surface.knots_v;
  nlohmann::json control = nlohmann::json::array();
  for (const auto& p : f.surface.control) control.push_back({p.x, p.y, p.z});
  j["control_points"] = std::move(control);
  if (f.has_fit) {
    nlohmann::json fit;
    fit["source"] = f.source;
    fit["distance"] = {{"kind", "orthogonal"},          {"count", f.distance.count},
                       {"mean", f.distance.mean},       {"median", f.distance.median},
                       {"stddev", f.distance.stddev},   {"rms", f.distance.rms},
                       {"max", f.distance.max},         {"min", f.distance.min},
                       {"max_abs", f.distance.max_abs}};
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
          {"hold_out", {{"folds", v.folds}, {"points", v.held_out_points}, {"rms_mm", finite_or_null(v.held_out_rms_mm)},
                        {"max_mm", finite_or_null(v.held_out_max_mm)}}},
          {"neighbours", {{"checks", v.neighbour_checks}, {"excess_max_mm", finite_or_null(v.range_excess_max_mm)}}}};
    }
    if (f.uncertainty.computed) {
      const SurfaceUncertainty& u = f.uncertainty;
      nlohmann::json grid = nlohmann::json::array();
      for (double value : u.u_mm) grid.push_back(finite_or_null(value));
      fit["uncertainty"] = {{"kind", "standard uncertainty of the surface, from the points' noise (k = 1)"},
                            {"sigma_mm", finite_or_null(u.sigma_mm)},
                            {"sigma_from", u.sigma_from},
                            {"coverage_factor", 2},
                            {"max_mm", finite_or_null(u.max_mm)},
                            {"mean_mm", finite_or_null(u.mean_mm)},
                            {"grid", {u.rows, u.cols}},
                            {"u_mm", std::move(grid)}};
    }
    j["fit"] = std::move(fit);
  }
  return j.dump(1) + "\n";
}

void write_surface_json(const std::string& path, const FittedSurface& file) {
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
    const auto degree = whole_pair(j.at("degree"), name, "degree", 1, 15);
    const auto count = whole_pair(j.at("control_count"), name, "control_count", 1, 1000000);
    if (degree.size() != 2 || count.size() != 2) throw fail("\"degree\" and \"control_count\" need two numbers");
    f.surface.degree_u = degree[0];
    f.surface.degree_v = degree[1];
    f.surface.count_u = count[0];
    f.surface.count_v = count[1];
    f.surface.knots_u = j.at("knots_u").get<std::vector<double>>();
    f.surface.knots_v = j.at("knots_v").get<std::vector<double>>();
    const auto& control = j.at("control_points");
    if (!control.is_array()) throw fail("\"control_points\" is not an array");
    for (size_t i = 0; i < control.size(); ++i) {
      const auto p = control[i].get<std::vector<double>>();
      if (p.size() != 3) throw fail("control point " + std::to_string(i) + " does not have 3 coordinates");
      f.surface.control.push_back(Point3{p[0], p[1], p[2]});
    }
    if (j.contains("fit")) {
      const auto& fit = j["fit"];
      f.has_fit = true;
      f.source = fit.value("source", "");
      const auto& d = fit.at("distance");
      f.distance.count = static_cast<size_t>(whole(d.at("count"), name, "count", 0, 1LL << 48));
      f.distance.mean = d.at("mean").get<double>();
      f.distance.median = d.at("median").get<double>();
      f.distance.stddev = d.at("stddev").get<double>();
      f.distance.rms = d.at("rms").get<double>();
      f.distance.max = d.at("max").get<double>();
      f.distance.min = d.at("min").get<double>();
      f.distance.max_abs = d.at("max_abs").get<double>();
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
        f.validation.held_out_points = static_cast<size_t>(whole(h.at("points"), name, "points", 0, 1LL << 48));
        f.validation.held_out_rms_mm = h.at("rms_mm").get<double>();
        f.validation.held_out_max_mm = h.at("max_mm").get<double>();
        const auto& n = v.at("neighbours");
        f.validation.neighbour_checks = static_cast<size_t>(whole(n.at("checks"), name, "checks", 0, 1LL << 48));
        f.validation.range_excess_max_mm = n.at("excess_max_mm").get<double>();
      }
      if (fit.contains("uncertainty")) {
        const auto& u = fit["uncertainty"];
        SurfaceUncertainty& out = f.uncertainty;
        out.computed = true;
        out.sigma_mm = u.at("sigma_mm").get<double>();
        out.sigma_from = u.value("sigma_from", "");
        out.max_mm = u.at("max_mm").get<double>();
        out.mean_mm = u.at("mean_mm").get<double>();
        const auto grid = whole_pair(u.at("grid"), name, "grid", 2, 4096);
        out.rows = grid[0];
        out.cols = grid[1];
        out.u_mm = u.at("u_mm").get<std::vector<double>>();
        if (out.u_mm.size() != static_cast<size_t>(out.rows) * out.cols) throw fail("\"uncertainty\": \"u_mm\" does not fill its grid");
        for (double value : out.u_mm) {
          if (!(value >= 0) || !std::isfinite(value)) throw fail("\"uncertainty\": a value that is not a finite, non-negative number");
        }
      }
    }
  } catch (const nlohmann::json::exception& e) {
    throw fail(std::string("missing or mistyped field: ") + e.what());
  }
  std::string why;
  if (!is_valid(f.surface, &why)) throw fail(why);
  return f;
}

FittedSurface read_surface_json(const std::string& path) {
  std::string text;
  if (!read_whole_file(path, &text)) throw std::runtime_error(path + ": cannot open");
  return parse_surface_json(text, path);
}

}  // namespace dg::host
