// The superquadric subcommand: fit, classify, check a rotational symmetry, write OUT.json.
#include "host/cli/superquadric_command.h"

#include <cstdio>
#include <nlohmann/json.hpp>

#include "host/scan/point_reader.h"
#include "host/io/atomic_file.h"
#include "host/io/standard_output.h"
#include "host/fit/superquadric.h"
#include "host/cad/surface_json.h"

namespace dg::host {

namespace {

nlohmann::json point_json(Point3 p) { return {p.x, p.y, p.z}; }

}  // namespace

CLI::App* add_superquadric_command(CLI::App& app, SuperquadricArgs& a) {
  CLI::App* cmd = app.add_subcommand("superquadric", "fit a superquadric to the whole part (Levenberg-Marquardt): size, shape, position, axes");
  cmd->add_option("input", a.input, ".csv, .xyz, .ply or .scan points in mm")->required()->check(CLI::ExistingFile);
  cmd->add_option("-o,--output", a.output, "OUT.json")->required();
  cmd->add_option("--slices", a.slices, "slices across the axis for the rotational check")->capture_default_str()->check(CLI::Range(2, 1000));
  cmd->add_option("--revolution", a.revolution, "for a rotationally symmetric part: its surface of revolution as SURF.json (export takes it to CAD)");
  cmd->add_flag("-q,--quiet", a.quiet, "print nothing but errors");
  return cmd;
}

int run_superquadric(const SuperquadricArgs& a) {
  const std::vector<Point3> points = read_points(a.input).points;
  const SuperquadricFit fit = fit_superquadric(points);
  const Superquadric& m = fit.model;
  nlohmann::json j;
  j["format"] = "digitizer-superquadric";
  j["version"] = 1;
  j["units"] = "mm";
  j["source"] = a.input;
  j["size"] = {m.a[0], m.a[1], m.a[2]};
  j["squareness"] = {{"e1", m.e1}, {"e2", m.e2}};
  j["center"] = point_json(m.center);
  j["axes"] = {point_json({m.axes[0][0], m.axes[0][1], m.axes[0][2]}), point_json({m.axes[1][0], m.axes[1][1], m.axes[1][2]}),
               point_json({m.axes[2][0], m.axes[2][1], m.axes[2][2]})};
  j["fit"] = {{"points", points.size()},         {"iterations", fit.iterations},         {"objective", fit.objective},
              {"goodness", fit.goodness},        {"rms_radial_mm", fit.rms_radial_mm}};
  if (fit.uncertainty.computed) {
    const SuperquadricUncertainty& u = fit.uncertainty;
    j["uncertainty"] = {{"kind", "standard uncertainty (k = 1), from the points' scatter about the shape"},
                        {"a_mm", {u.a_mm[0], u.a_mm[1], u.a_mm[2]}},
                        {"e1", u.e1},
                        {"e2", u.e2},
                        {"center_mm", {u.center_mm[0], u.center_mm[1], u.center_mm[2]}}};
  }
  j["shape"] = shape_name(fit.shape);
  j["rotationally_symmetric"] = fit.rotationally_symmetric;
  if (!a.quiet) {
    std::printf("superquadric: size %.4f x %.4f x %.4f mm, e1 %.3f e2 %.3f, centre (%.4f, %.4f, %.4f)\n", m.a[0], m.a[1], m.a[2],
                m.e1, m.e2, m.center.x, m.center.y, m.center.z);
    if (fit.uncertainty.computed) {
      const SuperquadricUncertainty& u = fit.uncertainty;
      std::printf("standard uncertainty (k = 1): size %.4f, %.4f, %.4f mm, e1 %.4f e2 %.4f, centre %.4f, %.4f, %.4f mm\n",
                  u.a_mm[0], u.a_mm[1], u.a_mm[2], u.e1, u.e2, u.center_mm[0], u.center_mm[1], u.center_mm[2]);
    } else {
      std::printf("standard uncertainty: the points do not determine it\n");
    }
    std::printf("%s; goodness (eq. 10 per point) %.3g, RMS radial distance %.4f mm, %d iterations\n", fit.description.c_str(),
                fit.goodness, fit.rms_radial_mm, fit.iterations);
  }
  if (fit.rotationally_symmetric) {
    // Verified as Koivunen and Bajcsy 1992, section 6 does for its pin: circles across the axis.
    const RevolutionFit rev = fit_revolution(points, m, a.slices);
    nlohmann::json slices = nlohmann::json::array();
    for (const RevolutionSlice& s : rev.slices) {
      slices.push_back({{"s_mm", s.s_mm}, {"center", point_json(s.center)}, {"radius_mm", s.radius_mm}, {"rms_mm", s.rms_mm}, {"points", s.points}});
    }
    j["revolution"] = {{"axis_point", point_json(rev.axis_point)}, {"axis_direction", point_json(rev.axis_direction)},
                       {"rms_mm", rev.rms_mm}, {"profile", slices}};
    if (!a.quiet) {
      std::printf("surface of revolution: axis through (%.4f, %.4f, %.4f) along (%.5f, %.5f, %.5f), %zu slice circles, RMS %.4f mm\n",
                  rev.axis_point.x, rev.axis_point.y, rev.axis_point.z, rev.axis_direction.x, rev.axis_direction.y,
                  rev.axis_direction.z, rev.slices.size(), rev.rms_mm);
      for (const RevolutionSlice& s : rev.slices) std::printf("  at %.3f mm along the axis: radius %.4f mm (RMS %.4f)\n", s.s_mm, s.radius_mm, s.rms_mm);
    }
    if (!a.revolution.empty()) {
      FittedSurface surface;
      surface.model = "revolution";
      surface.method = "superquadric";
      surface.parameterization = "axis";
      surface.height_field = false;
      surface.source = a.input;
      surface.surface = revolution_surface(rev);
      write_surface_json(a.revolution, surface);
      if (!a.quiet) std::printf("wrote the surface of revolution to %s\n", a.revolution.c_str());
    }
  } else if (!a.revolution.empty()) {
    std::fprintf(stderr, "digitizer: the part is not rotationally symmetric (e2 %.3f, a1 %.3f, a2 %.3f): no surface of revolution written\n",
                 m.e2, m.a[0], m.a[1]);
    return 1;
  }
  write_file_atomically(a.output, j.dump(1) + "\n");
  if (!a.quiet) std::printf("wrote %s\n", output_name(a.output).c_str());
  return 0;
}

}  // namespace dg::host
