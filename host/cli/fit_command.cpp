// The fit subcommand: read points, parameterize, fit, measure orthogonal distances, write SURF.json.
#include "host/cli/fit_command.h"

#include "host/io/standard_output.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <map>
#include <optional>
#include <stdexcept>

#include "host/scan/point_reader.h"
#include "host/fit/bezier_ips.h"
#include "host/geometry/closest_point.h"
#include "host/fit/crease_detect.h"
#include "host/fit/noise_estimate.h"
#include "host/fit/fit_error.h"
#include "host/fit/hermite_fit.h"
#include "host/cad/surface_json.h"
#include "host/fit/tolerance_fit.h"
#include "host/fit/fit_validation.h"
#include "host/fit/site_index.h"
#include "host/fit/orthogonal_distances.h"
#include "host/scan/spatial_order.h"
#include "host/fit/regions.h"
#include "host/fit/propagated_uncertainty.h"
#include "host/fit/replica_uncertainty.h"
#include "host/fit/sigma_weights.h"
#include "host/scan/median.h"

namespace dg::host {

namespace {

void parse_ctrl(const std::string& text, int& nu, int& nv) {
  const size_t x = text.find_first_of("xX");
  try {
    size_t used = 0;
    if (x == std::string::npos) {
      nu = nv = std::stoi(text, &used);
      if (used != text.size()) throw std::invalid_argument("");
    } else {
      nu = std::stoi(text.substr(0, x), &used);
      if (used != x) throw std::invalid_argument("");
      nv = std::stoi(text.substr(x + 1), &used);
      if (used != text.size() - x - 1) throw std::invalid_argument("");
    }
  } catch (const std::exception&) {
    throw std::invalid_argument("--ctrl: expected N or NxM control points, got '" + text + "'");
  }
  if (nu < 2 || nv < 2 || nu > 4096 || nv > 4096) throw std::invalid_argument("--ctrl: control points must be 2..4096");
}

void print_stats(const FittedSurface& f) {
  const auto& d = f.distance;
  std::printf("%s %s, degree %d x %d, %d x %d control points, %s parameters\n", f.model.c_str(), f.method.c_str(),
              f.surface.degree_u, f.surface.degree_v, f.surface.count_u, f.surface.count_v, f.parameterization.c_str());
  std::printf("orthogonal distance over %zu points: mean %.4f median %.4f std %.4f rms %.4f max %.4f min %.4f mm\n",
              d.count, d.mean, d.median, d.stddev, d.rms, d.max, d.min);
  if (f.noise_sigma_mm > 0) std::printf("estimated noise sigma %.4f mm\n", f.noise_sigma_mm);
}

void print_creases(const FitArgs& a, const Parameters& params, const Creases& creases) {
  if (a.quiet || (creases.u.empty() && creases.v.empty())) return;
  const bool table = params.kind == Parameterization::kTableXy;
  for (double u : creases.u) {
    if (table) std::printf("crease or step across the scan at x = %.3f mm: knot of multiplicity %d\n", params.x_min + u * (params.x_max - params.x_min), a.degree);
    else std::printf("crease or step across the scan at u = %.4f: knot of multiplicity %d\n", u, a.degree);
  }
  for (double v : creases.v) {
    if (table) std::printf("crease or step across the scan at y = %.3f mm: knot of multiplicity %d\n", params.y_min + v * (params.y_max - params.y_min), a.degree);
    else std::printf("crease or step across the scan at v = %.4f: knot of multiplicity %d\n", v, a.degree);
  }
}

void print_validation(const FittedSurface& out) {
  const FitValidation& v = out.validation;
  if (!v.checked) return;
  if (v.held_out_points > 0) {
    std::printf("between the samples: %zu points predicted by surfaces fitted without them (%d folds of %s): "
                "rms %.4f max %.4f mm\n",
                v.held_out_points, v.folds, v.folds_of_lines ? "scan lines" : "points", v.held_out_rms_mm, v.held_out_max_mm);
  }
  if (v.neighbour_checks > 0) {
    std::printf("between neighbouring samples (%zu places): the surface leaves their range by %.4f mm at most%s\n",
                v.neighbour_checks, v.range_excess_max_mm, out.tolerance_mm > 0 ? " beyond the tolerance" : "");
  }
  if (!v.problem.empty()) std::printf("validation: %s\n", v.problem.c_str());
}

void print_uncertainty(const FittedSurface& out, const std::string& why_not) {
  const SurfaceUncertainty& u = out.uncertainty;
  if (!u.computed) {
    // Said, not left out: a reader must not take the distances above for the surface's uncertainty.
    std::printf("standard uncertainty of the surface: not computed: %s\n",
                why_not.empty() ? "no point uncertainty to propagate (no sigma column and no noise estimate)" : why_not.c_str());
    return;
  }
  std::printf("standard uncertainty of the surface u (k = 1): max %.4f mean %.4f mm; expanded U = 2u: max %.4f mean %.4f mm\n",
              u.max_mm, u.mean_mm, 2 * u.max_mm, 2 * u.mean_mm);
  std::printf("  from a point uncertainty of %.4f mm (%s); the fit's precision, not its shape error\n", u.sigma_mm,
              u.sigma_from.c_str());
}

void print_summary(const FitArgs& a, const FittedSurface& out, const std::string& why_no_uncertainty = "") {
  if (a.quiet) return;
  print_stats(out);
  print_validation(out);
  print_uncertainty(out, why_no_uncertainty);
  if (a.tolerance_mm > 0) {
    std::printf("tolerance %.4f mm %s after %d fits\n", a.tolerance_mm, out.tolerance_kept ? "kept" : "NOT kept", out.iterations);
  }
  std::printf("wrote %s\n", output_name(a.output).c_str());
}

// The points' standard uncertainties for a Monte Carlo: the sigma column (unless --ignore-sigma),
// else the noise estimated from the scan lines (parameterized by `kind`). Empty, with the reason,
// when neither is known.
std::vector<double> point_sigmas(const FitArgs& a, const PointCloud& cloud, Parameterization kind, std::string& why_not) {
  if (cloud.sigma && !a.ignore_sigma) return *cloud.sigma;
  double sigma = 0;
  try {
    sigma = estimate_gauge_noise(cloud, parameterize(cloud, kind)).reading_sigma_mm;
  } catch (const FitError& e) {
    why_not = std::string("no noise estimate (") + e.what() + ") and no sigma column";
    return {};
  }
  if (!(sigma > 0) || !std::isfinite(sigma)) {
    why_not = "no noise estimate from these points and no sigma column";
    return {};
  }
  return std::vector<double>(cloud.points.size(), sigma);
}

// The uncertainty of a method without a closed-form covariance, by refitting noisy replicas.
SurfaceUncertainty by_replicas(const FitArgs& a, const std::vector<Point3>& points, const std::vector<double>& sigmas,
                               const BSplineSurface& nominal,
                               const std::function<BSplineSurface(const std::vector<Point3>&)>& refit, std::string& why_not) {
  if (sigmas.empty()) return {};
  if (a.replicas < 2) {
    why_not = "--replicas " + std::to_string(a.replicas) + " (at least 2 refits are needed)";
    return {};
  }
  ReplicaPlan plan;
  plan.replicas = a.replicas;
  int refused = 0;
  SurfaceUncertainty u = replica_uncertainty(points, sigmas, nominal, refit, plan, &refused);
  if (!u.computed) {
    why_not = std::to_string(refused) + " of " + std::to_string(a.replicas) + " noisy replicas could not be refitted";
  } else {
    // The Monte Carlo's own relative standard uncertainty of a standard deviation from M samples.
    char text[96];
    std::snprintf(text, sizeof text, "; its own relative uncertainty about %.0f %%",
                  100.0 / std::sqrt(2.0 * (a.replicas - refused - 1)));
    u.sigma_from += text;
  }
  return u;
}

// Hamdan's (2010) method places all 16 points in space, so the patch is parametric, not a height field;
// its distances start from chord-length parameters, which also order each line.
int run_fit_ips(const FitArgs& a, const PointCloud& cloud) {
  if (a.model != SurfaceModel::kBezier) throw std::invalid_argument("--method ips fits a bicubic Bezier patch: use --model bezier");
  if (a.tolerance_mm > 0) throw std::invalid_argument("--tolerance refines B-splines; a single Bezier patch has a fixed net");
  if (!a.ctrl.empty() && a.ctrl != "4" && a.ctrl != "4x4") throw std::invalid_argument("a bicubic Bezier patch has 4x4 control points");
  const Parameters params = parameterize(cloud, Parameterization::kChordLength);
  FittedSurface out;
  out.model = model_name(a.model);
  out.method = method_name(a.method);
  out.parameterization = parameterization_name(Parameterization::kChordLength);
  out.height_field = false;
  out.has_fit = true;
  out.source = a.input;
  out.surface = fit_bezier_ips(cloud, params).surface;
  out.distance = distance_stats(orthogonal_distances(out.surface, cloud.points, params));
  std::string why_not;
  const std::vector<double> sigmas = point_sigmas(a, cloud, Parameterization::kChordLength, why_not);
  out.uncertainty = by_replicas(a, cloud.points, sigmas, out.surface, [&](const std::vector<Point3>& noisy) {
    PointCloud replica = cloud;
    replica.points = noisy;
    return fit_bezier_ips(replica, parameterize(replica, Parameterization::kChordLength)).surface;
  }, why_not);
  write_surface_json(a.output, out);
  print_summary(a, out, why_not);
  return 0;
}

// Li and Zhang 2013: interpolates a grid of points with normals; the distances are those of the points to
// the surface (zero up to rounding: it passes through them) and the normal constraints' residual.
int run_fit_hermite(const FitArgs& a, const PointCloud& cloud) {
  if (a.tolerance_mm > 0) throw std::invalid_argument("--tolerance does not apply to Hermite surfaces: they pass through every point");
  if (!a.ctrl.empty()) throw std::invalid_argument("a Hermite surface has one patch per grid cell: --ctrl does not apply");
  const HermiteGrid grid = hermite_grid(cloud, a.input);
  const HermiteResult r = fit_hermite(grid);
  FittedSurface out;
  out.model = model_name(SurfaceModel::kHermite);
  out.method = "normals";
  out.parameterization = "chord";
  out.height_field = false;
  out.has_fit = true;
  out.source = a.input;
  out.surface = r.surface;
  Parameters params;
  params.kind = Parameterization::kChordLength;
  for (int row = 0; row < grid.rows; ++row) {
    for (int c = 0; c < grid.cols; ++c) params.uv.push_back({r.u[static_cast<size_t>(c)], r.v[static_cast<size_t>(row)]});
  }
  out.distance = distance_stats(orthogonal_distances(out.surface, grid.points, params));
  // The grid's points in its own order; one standard uncertainty for all (the sigma column's median).
  std::string why_not;
  std::vector<double> sigmas = point_sigmas(a, cloud, Parameterization::kChordLength, why_not);
  if (!sigmas.empty()) sigmas.assign(grid.points.size(), median_of(sigmas));
  out.uncertainty = by_replicas(a, grid.points, sigmas, out.surface, [&](const std::vector<Point3>& noisy) {
    HermiteGrid replica = grid;
    replica.points = noisy;
    return fit_hermite(replica).surface;
  }, why_not);
  write_surface_json(a.output, out);
  if (!a.quiet) {
    std::printf("hermite through a %d x %d grid (%d x %d patches), largest |n . t| / |t| %.2g\n", grid.cols, grid.rows,
                grid.cols - 1, grid.rows - 1, r.normal_residual_max);
  }
  print_summary(a, out, why_not);
  return 0;
}

// The trimmed faces of a scan split into regions: written, and reported face by face.
int finish_regions(const FitArgs& a, const PointCloud& cloud, FittedSurface out, RegionFit r) {
  out.faces = std::move(r.faces);
  out.tolerance_mm = a.tolerance_mm;
  out.tolerance_kept = r.kept;
  out.noise_sigma_mm = r.noise_sigma_mm;
  out.validation = r.validation;
  out.distance = distance_stats(r.distances);
  write_surface_json(a.output, out);
  if (!a.quiet) {
    std::printf("%d regions between creases and steps (%zu of %zu points on a crease or step), %zu trimmed faces\n",
                r.regions, r.crease_points, cloud.points.size(), out.faces.size());
    for (size_t k = 0; k < out.faces.size(); ++k) {
      const TrimmedFace& f = out.faces[k];
      std::printf("  face %zu: degree %d x %d, %d x %d control points, %zu points, max distance %.4f mm, %zu loop%s\n", k + 1,
                  f.surface.degree_u, f.surface.degree_v, f.surface.count_u, f.surface.count_v, f.points, f.distance.max_abs,
                  f.loops.size(), f.loops.size() == 1 ? "" : "s");
    }
    if (r.unassigned_points > 0) {
      std::printf("  %zu points lie on no region's surface within the tolerance (at the creases); each is judged on the "
                  "face above it\n", r.unassigned_points);
    }
    if (out.distance.count == 0) {
      // Said, not printed as zeros: figures from no points would read as a perfect fit.
      std::printf("orthogonal distances: none measured (no face was fitted)\n");
    } else {
      std::printf("orthogonal distance to the face above each of %zu points: mean %.4f rms %.4f max %.4f min %.4f mm\n",
                  out.distance.count, out.distance.mean, out.distance.rms, out.distance.max, out.distance.min);
    }
    if (out.noise_sigma_mm > 0) std::printf("estimated noise sigma %.4f mm\n", out.noise_sigma_mm);
    print_validation(out);
    double u_max = 0, u_sum = 0;
    size_t with_u = 0;
    for (const TrimmedFace& f : out.faces) {
      if (!f.uncertainty.computed) continue;
      u_max = std::max(u_max, f.uncertainty.max_mm);
      u_sum += f.uncertainty.mean_mm;
      ++with_u;
    }
    if (with_u == out.faces.size() && with_u > 0) {
      std::printf("standard uncertainty of the faces u (k = 1): max %.4f, mean of the faces' means %.4f mm; expanded U = 2u: "
                  "max %.4f mm\n  from a point uncertainty of %.4f mm; the fit's precision, not its shape error\n",
                  u_max, u_sum / static_cast<double>(with_u), 2 * u_max, out.faces[0].uncertainty.sigma_mm);
    } else if (!out.faces.empty()) {
      std::printf("standard uncertainty of the faces: not computed for %zu of %zu faces (no noise estimate, or a net "
                  "the points cannot refit)\n", out.faces.size() - with_u, out.faces.size());
    }
    std::printf("tolerance %.4f mm %s\n", a.tolerance_mm, r.kept ? "kept" : "NOT kept");
    std::printf("wrote %s\n", output_name(a.output).c_str());
  }
  if (!r.kept) {
    std::fprintf(stderr, "digitizer: tolerance refused: %s\n", r.reason.c_str());
    return kExitToleranceRefused;
  }
  return 0;
}

}  // namespace

const char* model_name(SurfaceModel model) {
  switch (model) {
    case SurfaceModel::kBSpline: return "bspline";
    case SurfaceModel::kBezier: return "bezier";
    case SurfaceModel::kHermite: return "hermite";
  }
  return "?";
}

const char* method_name(FitMethod method) { return method == FitMethod::kIps ? "ips" : "lsq"; }

CLI::App* add_fit_command(CLI::App& app, FitArgs& a) {
  CLI::App* cmd = app.add_subcommand("fit", "fit a B-spline or Bezier surface to points (mm) and write SURF.json");
  cmd->add_option("input", a.input, ".csv, .xyz, .ply or .scan points in mm")->required()->check(CLI::ExistingFile);
  cmd->add_option("-o,--output", a.output, "surface file (.json)")->required();
  const std::map<std::string, SurfaceModel> models{
      {"bspline", SurfaceModel::kBSpline}, {"bezier", SurfaceModel::kBezier}, {"hermite", SurfaceModel::kHermite}};
  cmd->add_option("--model", a.model, "bspline (default), bezier, or hermite (through a grid of points with nx,ny,nz normals)")
      ->transform(CLI::CheckedTransformer(models, CLI::ignore_case));
  const std::map<std::string, FitMethod> methods{{"lsq", FitMethod::kLeastSquares}, {"ips", FitMethod::kIps}};
  cmd->add_option("--method", a.method, "lsq (least squares, default) or ips (inverse progressive search; bezier only, needs scan lines)")
      ->transform(CLI::CheckedTransformer(methods, CLI::ignore_case));
  cmd->add_option("--degree", a.degree, "B-spline degree in both directions")->capture_default_str()->check(CLI::Range(1, 7));
  cmd->add_option("--ctrl", a.ctrl, "control points NxM (or N); with --tolerance, the starting net");
  cmd->add_option("--param", a.param, "xy (table coordinates, a height field), uniform, chord or centripetal")
      ->capture_default_str()->check(CLI::IsMember({"xy", "uniform", "chord", "centripetal"}));
  cmd->add_option("--tolerance", a.tolerance_mm, "refine until every orthogonal distance is within this, mm")
      ->check(CLI::PositiveNumber);
  cmd->add_flag("--ignore-sigma", a.ignore_sigma, "do not weight points by 1/sigma^2 from a sigma column or a scan's repeatability");
  cmd->add_flag("--no-creases", a.no_creases, "B-splines: no multiple knots at creases and steps found across the scan");
  cmd->add_flag("--no-regions", a.no_regions,
                "with --tolerance: fit one surface even where creases and steps split the scan into regions");
  cmd->add_option("--replicas", a.replicas,
                  "ips and hermite: noisy replicas refitted for the surface's uncertainty (Monte Carlo, GUM Supplement 1)")
      ->capture_default_str()->check(CLI::Range(0, 100000));
  cmd->add_flag("-q,--quiet", a.quiet, "print nothing but errors");
  return cmd;
}

int run_fit(const FitArgs& a) {
  PointCloud cloud = read_points(a.input);
  if (a.method == FitMethod::kIps) return run_fit_ips(a, cloud);
  if (a.model == SurfaceModel::kHermite) return run_fit_hermite(a, cloud);
  const Parameterization kind = parse_parameterization(a.param);
  std::vector<double> weights;
  if (cloud.sigma && !a.ignore_sigma) {
    SigmaWeights from_sigma = sigma_weights(*cloud.sigma);
    if (!from_sigma.problem.empty()) throw FitError(a.input + ": " + from_sigma.problem);
    weights = std::move(from_sigma.weights);
  }
  // A large scattered cloud is fitted in an order where neighbours are near in memory
  // (spatial_order.h); messages still name its points by their place in the file. The results are
  // those of the file's order but for rounding and which points share a validation fold.
  std::vector<uint32_t> file_order;
  if (!cloud.line && kind == Parameterization::kTableXy && cloud.points.size() >= kSpatialOrderFrom) {
    file_order = spatial_order(cloud.points);
    if (!file_order.empty()) {
      cloud = reordered(std::move(cloud), file_order);
      if (!weights.empty()) weights = reordered(weights, file_order);
    }
  }
  const Parameters params = parameterize(cloud, kind);
  const std::vector<double>* w = weights.empty() ? nullptr : &weights;

  FittedSurface out;
  out.model = model_name(a.model);
  out.method = method_name(a.method);
  out.parameterization = a.param;
  out.height_field = params.kind == Parameterization::kTableXy;
  out.has_fit = true;
  out.source = a.input;
  int nu = a.degree + 1, nv = a.degree + 1;
  if (!a.ctrl.empty()) parse_ctrl(a.ctrl, nu, nv);
  if (a.model == SurfaceModel::kBezier) {
    if (!a.ctrl.empty() && (nu != 4 || nv != 4)) throw std::invalid_argument("a bicubic Bezier patch has 4x4 control points");
    if (a.tolerance_mm > 0) throw std::invalid_argument("--tolerance refines B-splines; a single Bezier patch has a fixed net");
    nu = nv = 4;
  }
  const int degree = a.model == SurfaceModel::kBezier ? 3 : a.degree;
  // A scan that creases and steps split into regions comes back as trimmed faces, one per region.
  if (a.tolerance_mm > 0 && a.model == SurfaceModel::kBSpline && !a.no_regions && params.kind == Parameterization::kTableXy &&
      a.ctrl.empty()) {
    RegionOptions options;
    options.tolerance.tolerance_mm = a.tolerance_mm;
    options.tolerance.degree_u = options.tolerance.degree_v = degree;
    RegionFit regions = fit_regions(cloud, w, options);
    if (regions.regions >= 2) return finish_regions(a, cloud, std::move(out), std::move(regions));
  }
  // Koivunen and Bajcsy 1992, section 6: C0 knots where a crease or step runs across the scan. A Bezier patch has
  // no interior knots to place.
  Creases creases;
  if (a.model == SurfaceModel::kBSpline && !a.no_creases) {
    creases = detect_creases(cloud, params, estimate_noise(cloud, params));
    print_creases(a, params, creases);
  }
  int exit_code = 0;
  std::vector<double> distances;
  std::optional<LeastSquaresFit> kept;  // the --ctrl fit with its equations, which its uncertainty reuses
  if (a.tolerance_mm > 0) {
    ToleranceOptions options;
    options.tolerance_mm = a.tolerance_mm;
    options.degree_u = options.degree_v = degree;
    if (!a.ctrl.empty()) {
      options.start_count_u = nu;
      options.start_count_v = nv;
    }
    options.extra_knots_u = with_crease_knots({}, creases.u, degree);
    options.extra_knots_v = with_crease_knots({}, creases.v, degree);
    if (!file_order.empty()) options.point_numbers = &file_order;
    ToleranceResult r = fit_to_tolerance(cloud, params, w, options);
    out.surface = std::move(r.surface);
    out.tolerance_mm = a.tolerance_mm;
    out.tolerance_kept = r.kept;
    out.noise_sigma_mm = r.noise_sigma_mm;
    out.iterations = r.iterations;
    out.validation = r.validation;
    distances = std::move(r.distances);
    if (!r.kept) {
      std::fprintf(stderr, "digitizer: tolerance refused: %s\n", r.reason.c_str());
      exit_code = kExitToleranceRefused;
    } else if (!r.note.empty()) {
      std::printf("refinement stopped short of the noise: %s\n", r.note.c_str());
    }
  } else {
    if (nu <= degree || nv <= degree) throw std::invalid_argument("--ctrl: a degree " + std::to_string(degree) + " net needs at least " + std::to_string(degree + 1) + " control points per direction");
    LsqSpec spec;
    spec.degree_u = spec.degree_v = degree;
    spec.knots_u = with_crease_knots(clamped_uniform_knots(nu, degree), creases.u, degree);
    spec.knots_v = with_crease_knots(clamped_uniform_knots(nv, degree), creases.v, degree);
    // The fit and its validation folds' refits from one pass over the points; the fit's equations
    // then serve its uncertainty too.
    const ValidationOptions validation;
    const FoldSupport support(cloud, params, validation.folds, validation.fill_outside);
    // Every point's sites from the support's sorted parameters: the fit's checks need not sort them.
    const SiteIndex sites(params.uv, support.all_sites_u(), support.all_sites_v(), spec.fill_outside);
    spec.sites = &sites;
    std::vector<const SiteIndex*> kept_sites;
    for (int f = 0; f < validation.folds; ++f) kept_sites.push_back(&support.kept_sites(f));
    FoldedFit folded = fit_least_squares_with_folds(cloud.points, params, w, spec,
                                                    validation_folds(cloud, validation.folds), kept_sites);
    kept = std::move(folded.fit);
    out.surface = kept->surface;
    std::vector<double> start_distances;
    distances = orthogonal_distances(out.surface, cloud.points, params, start_distances);
    // Without a tolerance the checks between the samples are measured and reported, not decided.
    out.validation = validate_fit(cloud, params, w, out.surface, validation, &support, &folded.refits, &start_distances);
  }
  out.distance = distance_stats(distances);
  out.uncertainty = propagated_uncertainty(cloud, params, w, out.surface, distances, kept ? &*kept : nullptr);
  write_surface_json(a.output, out);
  print_summary(a, out);
  return exit_code;
}

}  // namespace dg::host
