// Writing and reading SURF.json with nlohmann::json; every field checked on the way in.
#include "host/cad/surface_json.h"
#include "host/io/whole_file.h"

#include <cmath>
#include <cstdio>
#include <nlohmann/json.hpp>
#include <sstream>
#include <stdexcept>

#include "host/io/atomic_file.h"

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
    j["fit"] = std::move(fit);
  }
  return j.dump(1) + "\n";
}

void write_surface_json(const std::string& path, const FittedSurface& file) {
  write_file_atomically(path, surface_json_text(file));
}

FittedSurface parse_surface_json(const std::string& text, const std::string& name) {
  nlohmann::json j;
  try {
    j = nlohmann::json::parse(text);
  } catch (const nlohmann::json::parse_error& e) {
    throw std::runtime_error(name + ": not valid JSON (byte " + std::to_string(e.byte) + ")");
  }
  auto fail = [&](const std::string& what) { return std::runtime_error(name + ": " + what); };
  if (!j.is_object() || j.value("format", "") != kFormat) throw fail("not a digitizer surface file (\"format\" is missing)");
  if (!j["version"].is_number_integer() || j["version"].get<int>() != kVersion) throw fail("unsupported version");
  FittedSurface f;
  try {
    f.model = j.at("model").get<std::string>();
    f.method = j.value("method", "lsq");
    f.parameterization = j.value("parameterization", "xy");
    f.height_field = j.value("height_field", false);
    const auto degree = j.at("degree").get<std::vector<int>>();
    const auto count = j.at("control_count").get<std::vector<int>>();
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
      f.distance.count = d.at("count").get<size_t>();
      f.distance.mean = d.at("mean").get<double>();
      f.distance.median = d.at("median").get<double>();
      f.distance.stddev = d.at("stddev").get<double>();
      f.distance.rms = d.at("rms").get<double>();
      f.distance.max = d.at("max").get<double>();
      f.distance.min = d.at("min").get<double>();
      f.distance.max_abs = d.at("max_abs").get<double>();
      f.tolerance_mm = fit.value("tolerance_mm", 0.0);
      f.tolerance_kept = fit.value("tolerance_kept", false);
      f.iterations = fit.value("iterations", 0);
      f.noise_sigma_mm = fit["noise_sigma_mm"].is_number() ? fit["noise_sigma_mm"].get<double>() : 0.0;
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
