// The inspect subcommand: read points and a surface, measure, print or write the results.
#include "host/cli/inspect_command.h"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <cstdio>
#include <functional>
#include <memory>
#include <optional>
#include <stdexcept>

#include "host/cli/device_choice.h"
#include "host/inspect/deviation_file.h"
#include "host/cli/pdf_print.h"
#include "host/cli/zone_option.h"
#include "host/io/file_name.h"
#include "host/scan/ply_reader.h"
#include "host/scan/point_reader.h"
#include "host/io/whole_file.h"
#include <ctime>

#include "host/scan/scan_facts.h"
#include "host/scan/scan_file.h"
#include "host/io/atomic_file.h"
#include "host/inspect/html_report.h"
#include "host/cad/cad_nominal.h"
#include "host/cad/mesh_reader.h"
#include "host/geometry/triangle_mesh.h"
#include "host/fit/noise_estimate.h"
#include "host/fit/parameterize.h"
#include "host/fit/rigid_align.h"
#include "host/inspect/decision.h"
#include "host/inspect/inspect.h"
#include "host/inspect/inspection_json.h"
#include "host/inspect/view_mesh.h"
#include "host/cad/surface_json.h"

namespace dg::host {

CLI::App* add_inspect_command(CLI::App& app, InspectArgs& a) {
  CLI::App* cmd = app.add_subcommand("inspect", "deviations of measured points from a surface (orthogonal, signed)");
  cmd->add_option("points", a.points, ".csv, .xyz, .ply or .scan points in mm")->required()->check(CLI::ExistingFile);
  cmd->add_option("surface", a.surface,
                  "SURF.json, a nominal part from CAD (STEP .stp, IGES .igs; read by OpenCASCADE), or a nominal mesh (.stl, .obj, .ply)")
      ->required()->check(CLI::ExistingFile);
  cmd->add_option("--band", a.bands_mm, "count the points within these deviations, mm")->capture_default_str()->check(CLI::PositiveNumber);
  cmd->add_flag("--json", a.json, "print the summary as JSON");
  cmd->add_option("--deviations", a.deviations_csv, "write x,y,z,deviation,beyond_edge per point: CSV, or .ply with the deviation as a scalar field (CloudCompare colours it)");
  cmd->add_flag("--align", a.align, "rigid best-fit alignment of the points to the surface before measuring");
  cmd->add_option("--datum", a.datums,
                  "NAME=X0:X1,Y0:Y1 (mm, the scan's x and y): a datum region; one to three, primary first, align the part "
                  "3-2-1 (the first fixes tilt and height, the second the turn and x and y, a third y) instead of --align")
      ->excludes("--align");
  cmd->add_option("-o,--report", a.report_html, "write a self-contained HTML report (and its pictures as PNG/SVG beside it)");
  cmd->add_option("--tolerance", a.tolerance_mm, "decide a profile tolerance of +-MM: pass, fail or inconclusive per point and for the part")
      ->check(CLI::PositiveNumber);
  cmd->add_option("--upper", a.upper_mm, "the tolerance's upper limit of the signed deviation, mm (with --lower)");
  cmd->add_option("--lower", a.lower_mm, "the tolerance's lower limit of the signed deviation, mm (with --upper)");
  cmd->add_option("--zone", a.zones,
                  "NAME=X0:X1,Y0:Y1,TOL (or ...,LOWER:UPPER): the points in this box (mm, the nominal's x and y) are decided "
                  "with this tolerance instead of the general one; repeat for more zones, the first that holds a point decides it");
  cmd->add_option("--point-u", a.point_u_mm,
                  "the points' standard uncertainty, mm, when the points carry no sigma column (default: the noise estimated from the scan)")
      ->check(CLI::PositiveNumber);
  cmd->add_flag("!--no-pdf", a.pdf, "with -o: no PDF of the report beside it (by default Chromium prints one, when installed)");
  cmd->add_option("--part", a.fields.part, "the part's name or drawing number, for the report and the JSON");
  cmd->add_option("--serial", a.fields.serial, "the part's serial number, for the report and the JSON");
  cmd->add_option("--operator", a.fields.operator_name, "who measured (default: `operator =` in the config file)");
  cmd->add_option("--company", a.fields.company, "for whom (default: `company =` in the config file)");
  return cmd;
}

namespace {

// What a scan file says about how the points were measured; nothing for other point files.
std::vector<std::string> facts_of(const std::string& path) {
  if (file_format(path) != FileFormat::kScan) return {};
  return scan_facts(read_scan_file(path));
}

// The alignment for the printed summary and the report.
std::string alignment_text(const AlignmentSummary& s) {
  char text[320];
  std::snprintf(text, sizeof text,
                "aligned by %s: rotation %.4f deg, translation (%.4f, %.4f, %.4f) mm, RMS %.4f -> %.4f mm "
                "in %d steps%s; %zu points beyond 3 robust sigmas left out of the fit",
                s.datums.empty() ? "a rigid best fit" : "datums (3-2-1)", s.rotation_deg, s.translation_mm.x, s.translation_mm.y,
                s.translation_mm.z, s.rms_before_mm, s.rms_after_mm, s.iterations, s.converged ? "" : " (not converged)",
                s.left_out);
  std::string out = text;
  if (s.beyond_edge > 0) {
    std::snprintf(text, sizeof text, ", and %zu beyond the nominal's edge (their distance is to the edge, not along a normal)",
                  s.beyond_edge);
    out += text;
  }
  if (s.held > 0) {
    std::snprintf(text, sizeof text,
                  "; %d of its freedoms held still: the nominal's shape does not fix them (a plane lets a part slide, a "
                  "sphere turn about its centre), so the deviations are right and those moves unmeasured",
                  s.held);
    out += text;
  }
  for (const DatumSummary& d : s.datums) {
    std::snprintf(text, sizeof text, "\n  datum %s (x %.3f..%.3f, y %.3f..%.3f mm, %zu points) fixed %s; its RMS %.4f mm",
                  d.name.c_str(), d.x0_mm, d.x1_mm, d.y0_mm, d.y1_mm, d.points, d.fixes.c_str(), d.rms_after_mm);
    out += text;
  }
  return out;
}

// The surface the report's 3D view draws under the points: the nominal's mesh, or the fitted surface's.
Mesh view_surface(const Inspection& r, const FittedSurface& surface, const MeshLocator* mesh, const CadNominal* cad) {
  if (mesh) return mesh_for_view(mesh->mesh(), r);
  if (cad) return mesh_for_view(cad->mesh(), r);
  return fitted_surface_for_view(surface, r);
}

// Returns whether the uncertainty map was drawn (the surface, or every face, carries its grid).
bool write_report(const InspectArgs& a, const Inspection& r, const FittedSurface& surface, const std::string& alignment,
                  const Decision* decision, const Mesh& view_mesh) {
  std::string svg;
  ReportInputs in;
  in.view_surface = &view_mesh;
  in.view_surface_name = surface.model == "mesh" || surface.model == "cad" ? "the nominal" : "the fitted surface";
  in.pictures = inspection_pictures(r, &svg, decision ? &decision->limits : nullptr);
  const std::time_t now = std::time(nullptr);
  char stamp[48];
  std::strftime(stamp, sizeof stamp, "%Y-%m-%d %H:%M:%S UTC", std::gmtime(&now));
  in.created = stamp;
  in.fields = a.fields;
  in.points_file = a.points;
  in.surface_file = a.surface;
  in.scan_facts = facts_of(a.points);
  if (!alignment.empty()) in.scan_facts.push_back(alignment);
  in.surface = &surface;
  in.inspection = &r;
  in.decision = decision;
  const std::string stem = without_extension(a.report_html);
  const char* names[] = {"-deviation.png", "-error-x.png", "-error-y.png", "-error-z.png"};
  for (size_t k = 0; k < in.pictures.size() && k < 4; ++k) write_file_atomically(stem + names[k], in.pictures[k].png);
  ReportPicture uncertainty = uncertainty_picture(surface);
  const bool drawn = !uncertainty.png.empty();
  if (drawn) {
    write_file_atomically(stem + "-uncertainty.png", uncertainty.png);
    in.pictures.push_back(std::move(uncertainty));
  }
  write_file_atomically(stem + "-deviation.svg", svg);
  write_file_atomically(a.report_html, html_report(in));
  return drawn;
}


// The tolerance asked, if any: --tolerance T is -T..+T; --upper and --lower go together.
std::optional<ToleranceLimits> tolerance_limits(const InspectArgs& a) {
  const bool upper = !std::isnan(a.upper_mm), lower = !std::isnan(a.lower_mm);
  if (a.tolerance_mm > 0 && (upper || lower)) throw std::invalid_argument("give --tolerance or --upper and --lower, not both");
  if (upper != lower) throw std::invalid_argument("--upper and --lower go together (or give --tolerance for +-MM)");
  if (a.tolerance_mm > 0) return ToleranceLimits{-a.tolerance_mm, a.tolerance_mm};
  if (!upper) return std::nullopt;
  if (!std::isfinite(a.upper_mm) || !std::isfinite(a.lower_mm) || !(a.lower_mm < a.upper_mm)) {
    throw std::invalid_argument("--lower must be a number below --upper");
  }
  return ToleranceLimits{a.lower_mm, a.upper_mm};
}

// The standard uncertainty of each point's deviation: the point's own (its sigma column, else
// --point-u, else the noise estimated from the scan with its reading step) combined with the
// surface's (a fit's u where the point's foot lies, on trimmed faces the u of the face that holds
// the point; a CAD nominal is exact). Throws when the points' own cannot be had.
std::vector<double> deviation_uncertainty(const InspectArgs& a, const PointCloud& cloud, const FittedSurface& surface,
                                          bool nominal, const Inspection& r, std::string* from) {
  std::vector<double> point_u(cloud.points.size(), a.point_u_mm);
  if (cloud.sigma) {
    point_u = *cloud.sigma;
    *from = cloud.sigma_from;
  } else if (a.point_u_mm > 0) {
    *from = "--point-u";
  } else {
    double sigma = 0;
    try {
      sigma = estimate_gauge_noise(cloud, parameterize(cloud, Parameterization::kTableXy)).reading_sigma_mm;
    } catch (const std::exception&) {
      sigma = 0;
    }
    if (!(sigma > 0) || !std::isfinite(sigma)) {
      throw std::runtime_error(a.points + ": no uncertainty for the points to decide the tolerance with (their noise "
                               "cannot be estimated from them): give a sigma column or --point-u");
    }
    point_u.assign(cloud.points.size(), sigma);
    char text[96];
    std::snprintf(text, sizeof text, "the noise estimated from the scan with its reading step, %.4f mm", sigma);
    *from = text;
  }
  if (nominal) {
    *from += "; the nominal is exact";
    return point_u;
  }
  std::vector<double> out(point_u.size());
  // A face's or the surface's u above (x, y); `fallback` off its grid.
  auto u_above = [](const BSplineSurface& s, const SurfaceUncertainty& u, double x, double y, double fallback) {
    double value = 0;
    return uncertainty_above(s, u, x, y, value) ? value : fallback;
  };
  double bound = 0;
  for (const TrimmedFace& f : surface.faces) bound = std::max(bound, f.uncertainty.computed ? f.uncertainty.max_mm : 0.0);
  for (size_t i = 0; i < out.size(); ++i) {
    const PointDeviation& d = r.points[i];
    double u_surface = 0;
    if (!surface.faces.empty()) {
      // The face that holds the point's XY, as inspect_faces measures it; beyond every face (or on
      // a face without a grid) the largest u of any face, a bound.
      u_surface = bound;
      for (const TrimmedFace& f : surface.faces) {
        if (!inside_face(f, d.point.x, d.point.y)) continue;
        if (f.uncertainty.computed) u_surface = u_above(f.surface, f.uncertainty, d.foot.x, d.foot.y, bound);
        break;
      }
    } else if (surface.uncertainty.computed) {
      u_surface = surface.height_field ? u_above(surface.surface, surface.uncertainty, d.foot.x, d.foot.y, surface.uncertainty.max_mm)
                                       : surface.uncertainty.max_mm;
    }
    out[i] = std::sqrt(point_u[i] * point_u[i] + u_surface * u_surface);
  }
  *from += surface.faces.empty() ? (surface.uncertainty.computed ? "; with the fitted surface's own u at each point" : "; the surface carries no uncertainty")
                                 : "; with the u of the face each point is measured to";
  return out;
}

// A PLY mesh nominal: the point reader's vertices (scan room) and its faces, as a mesh.
Mesh read_ply_mesh(const std::string& path) {
  std::string bytes;
  if (!read_whole_file(path, &bytes)) throw std::invalid_argument(path + ": cannot be read: " + std::strerror(errno));
  Mesh mesh;
  mesh.vertices = parse_ply_mesh(reinterpret_cast<const uint8_t*>(bytes.data()), bytes.size(), path, mesh.triangles).points;
  return mesh;
}

// The verdict's lines for a reader.
void print_decision(const Decision& d, const Inspection& r) {
  std::printf("%stolerance %+.4f..%+.4f mm, decided with U = 2u up to %.4f mm (u from %s): %s\n", d.zones.empty() ? "" : "general ", d.limits.lower_mm,
              d.limits.upper_mm, d.max_expanded_mm, d.uncertainty_from.c_str(), verdict_name(d.verdict));
  std::printf("  %zu pass, %zu fail, %zu inconclusive (ISO 14253-1: pass inside the tolerance shrunk by U, fail outside it "
              "widened by U)\n",
              d.pass, d.fail, d.inconclusive);
  if (d.beyond_edge > 0) std::printf("  %zu of the inconclusive lie beyond the surface's edge: nothing is proven there\n", d.beyond_edge);
  for (const ZoneDecision& z : d.zones) {
    const bool elsewhere = &z == &d.zones.back();
    std::printf("  zone %s%s: %+.4f..%+.4f mm, %zu pass, %zu fail, %zu inconclusive: %s\n", z.zone.name.c_str(),
                elsewhere ? " (in no zone)" : "", z.zone.limits.lower_mm, z.zone.limits.upper_mm, z.pass, z.fail,
                z.inconclusive, verdict_name(z.verdict));
  }
  for (size_t i : d.worst) {
    const PointDeviation& p = r.points[i];
    std::printf("  point %zu at (%.3f, %.3f, %.4f): deviation %+.4f mm, U %.4f: %s%s%s%s\n", i + 1, p.point.x, p.point.y, p.point.z,
                p.distance, d.expanded_mm[i], verdict_name(d.points[i]), d.zones.empty() ? "" : " in zone ",
                d.zones.empty() ? "" : d.zones[d.zone_of_point[i]].zone.name.c_str(),
                p.beyond_edge ? " (beyond the surface's edge; the distance is to the edge)" : "");
  }
}
}  // namespace

int run_inspect(const InspectArgs& given) {
  InspectArgs a = given;
  PointCloud cloud = read_points(a.points);
  if (cloud.points.empty()) throw std::invalid_argument(a.points + ": holds no points to inspect");
  FittedSurface surface;
  const FileFormat format = file_format(a.surface);
  const bool iges = format == FileFormat::kIges;
  const bool step = format == FileFormat::kStep;
  const bool mesh_nominal = format == FileFormat::kStl || format == FileFormat::kObj || format == FileFormat::kPly;
  // A mesh or a CAD part: measured through its closest points, not as one B-spline.
  std::optional<MeshLocator> mesh;
  std::unique_ptr<CadNominal> cad;
  std::function<Closest(const Point3&)> nominal;
  char summary[200];
  if (mesh_nominal) {
    mesh.emplace(format == FileFormat::kPly ? read_ply_mesh(a.surface) : read_mesh(a.surface));
    nominal = [&](const Point3& p) { return mesh->closest(p); };
    surface.model = "mesh";
    surface.method = format == FileFormat::kStl ? "nominal (STL)" : format == FileFormat::kObj ? "nominal (OBJ)" : "nominal (PLY)";
    std::snprintf(summary, sizeof summary, "a mesh of %zu triangles", mesh->triangle_count());
    surface.nominal_summary = summary;
    if (mesh->without_area() > 0) surface.nominal_summary += ", " + std::to_string(mesh->without_area()) + " of them without area and read past";
  } else if (iges || step) {
    cad = CadNominal::read(a.surface);
    nominal = [&](const Point3& p) { return cad->closest(p); };
    surface.model = "cad";
    surface.method = iges ? "nominal (IGES)" : "nominal (STEP)";
    std::snprintf(summary, sizeof summary, "%zu %s read by OpenCASCADE, each point measured on the exact faces (found through a mesh to %.3f mm)",
                  cad->face_count(), cad->face_count() == 1 ? "face" : "faces", cad->deflection_mm());
    surface.nominal_summary = summary;
  } else if (format == FileFormat::kJson) {
    surface = read_surface_json(a.surface);
  } else {
    throw std::invalid_argument(a.surface + ": a surface to inspect against is SURF.json, a CAD part (.stp, .step, .igs, "
                                ".iges) or a mesh (.stl, .obj, .ply); this name says none of them");
  }
  if (nominal) {
    surface.parameterization = "-";
    surface.source = a.surface;
  }
  std::optional<AlignmentSummary> aligned;
  const bool by_datums = !a.datums.empty();
  if ((a.align || by_datums) && !surface.faces.empty()) {
    throw std::invalid_argument(std::string(a.align ? "--align" : "--datum") +
                                ": aligning to trimmed faces is not supported yet; align to a single-surface fit or a nominal");
  }
  if (a.align || by_datums) {
    std::optional<SurfaceLocator> locator;
    if (!nominal) locator.emplace(surface.surface);
    const std::function<Closest(const Point3&)> closest = nominal ? nominal : [&](const Point3& p) { return locator->closest(p); };
    std::vector<DatumFit> datums;
    std::vector<ToleranceZone> boxes;
    if (by_datums && a.datums.size() > 3) throw std::invalid_argument("--datum: one, two or three datums (primary first)");
    for (const std::string& text : a.datums) {
      boxes.push_back(parse_datum_region(text));
      DatumFit d;
      d.name = boxes.back().name;
      for (const Point3& p : cloud.points) {
        if (boxes.back().contains(p.x, p.y)) d.points.push_back(p);
      }
      datums.push_back(std::move(d));
    }
    const Alignment fit = by_datums ? align_to_datums(datums, closest) : align_to_nominal(cloud.points, closest);
    for (Point3& p : cloud.points) p = fit.transform.apply(p);
    aligned = AlignmentSummary{fit.transform.rotation, fit.transform.translation, fit.transform.angle_deg(),
                               fit.rms_before_mm, fit.rms_after_mm, fit.iterations, fit.converged, fit.left_out, fit.beyond_edge, fit.held, {}};
    for (size_t k = 0; k < datums.size(); ++k) {
      aligned->datums.push_back({datums[k].name, boxes[k].x0_mm, boxes[k].x1_mm, boxes[k].y0_mm, boxes[k].y1_mm,
                                 datums[k].points.size(), datums[k].fixes_text, datums[k].rms_after_mm});
    }
  }
  const std::string alignment = aligned ? alignment_text(*aligned) : std::string();
  const std::optional<ToleranceLimits> limits = tolerance_limits(a);
  std::vector<ToleranceZone> zones;
  for (const std::string& z : a.zones) zones.push_back(parse_tolerance_zone(z));
  if (!zones.empty() && !limits) {
    throw std::invalid_argument("--zone needs the general tolerance (--tolerance, or --upper and --lower) for the points in no zone");
  }
  std::vector<double> bands = a.bands_mm;
  std::sort(bands.begin(), bands.end());
  const Inspection r = nominal                 ? inspect_nominal(cloud.points, nominal, bands, static_cast<bool>(mesh))
                       : surface.faces.empty() ? inspect(cloud.points, surface.surface, bands)
                                               : inspect_faces(cloud.points, surface.faces, bands);
  if (!a.deviations_csv.empty()) {
    const bool ply = file_format(a.deviations_csv) == FileFormat::kPly;
    write_file_atomically(a.deviations_csv, ply ? format_deviations_ply(r.points) : format_deviations_csv(r.points));
  }
  std::optional<Decision> decision;
  if (limits) {
    std::string from;
    const std::vector<double> u = deviation_uncertainty(a, cloud, surface, static_cast<bool>(nominal), r, &from);
    decision = decide(r, *limits, u, from, zones);
  }
  const int exit_code = !decision                                  ? 0
                        : decision->verdict == Verdict::kFail         ? kExitInspectionFail
                        : decision->verdict == Verdict::kInconclusive ? kExitInspectionInconclusive
                                                                      : 0;
  const bool uncertainty_drawn =
      !a.report_html.empty() && write_report(a, r, surface, alignment, decision ? &*decision : nullptr,
                                             view_surface(r, surface, mesh ? &*mesh : nullptr, cad.get()));
  // The PDF for sign-off, beside a report written to a regular file.
  std::string pdf_note;
  if (!a.report_html.empty() && a.pdf && a.report_html != "-") {
    const std::string pdf = without_extension(a.report_html) + ".pdf";
    const std::string why = print_pdf(a.report_html, pdf);
    if (why.empty()) pdf_note = "wrote " + pdf + " (the report printed by Chromium)";
    else std::fprintf(stderr, "digitizer: no PDF of the report: %s\n", why.c_str());
  }
  if (a.json) {
    NominalNote note;
    if (nominal) {
      note.summary = surface.nominal_summary;
      note.measured_on_mesh = cad ? cad->mesh_fallbacks() : 0;
      note.mesh_deflection_mm = cad ? cad->deflection_mm() : 0;
    }
    std::fputs(inspection_json_text(r, a.points, a.surface, aligned ? &*aligned : nullptr, decision ? &*decision : nullptr,
                                    a.fields, nominal ? &note : nullptr)
                   .c_str(),
               stdout);
    return exit_code;
  }
  const DistanceStats& s = r.stats;
  if (!alignment.empty()) std::printf("%s\n", alignment.c_str());
  if (nominal) {
    std::printf("%zu points against %s (%s)\n", r.points.size(), a.surface.c_str(), surface.nominal_summary.c_str());
    if (cad && cad->mesh_fallbacks() > 0) {
      std::printf("  %zu points measured on the mesh (within %.3f mm): no exact distance was found on their faces\n",
                  cad->mesh_fallbacks(), cad->deflection_mm());
    }
  } else if (surface.faces.empty()) {
    std::printf("%zu points against %s (%s, %d x %d control points)\n", r.points.size(), a.surface.c_str(), surface.model.c_str(),
                surface.surface.count_u, surface.surface.count_v);
  } else {
    std::printf("%zu points against %s (%zu trimmed %s faces; each point measured to the face above it)\n", r.points.size(),
                a.surface.c_str(), surface.faces.size(), surface.model.c_str());
  }
  // A value that prints as zero is printed as 0.0000, not -0.0000.
  auto shown = [](double v) { return std::fabs(v) < 0.00005 ? 0.0 : v; };
  if (r.beyond_edge > 0) std::printf("of the %zu points over the surface:\n", s.count);
  std::printf("orthogonal deviation: mean %.4f median %.4f std %.4f rms %.4f max %.4f min %.4f mm\n", shown(s.mean),
              shown(s.median), s.stddev, s.rms, shown(s.max), shown(s.min));
  for (const Band& b : r.bands) std::printf("within %.4f mm: %zu points (%.1f %%)\n", b.limit_mm, b.count, 100.0 * b.share);
  if (r.beyond_edge > 0) {
    size_t first = 0;
    while (!r.points[first].beyond_edge) ++first;
    const PointDeviation& d = r.points[first];
    std::printf("%zu of the points lie beyond the surface's edge and are left out of these figures: each one's distance "
                "is to the edge, not along a normal (the first: point %zu at (%.3f, %.3f, %.4f), %.4f mm); inspect them "
                "against a surface that covers them\n",
                r.beyond_edge, first + 1, d.point.x, d.point.y, d.point.z, std::fabs(d.distance));
  }
  if (decision) print_decision(*decision, r);
  if (!a.deviations_csv.empty()) std::printf("wrote %s\n", a.deviations_csv.c_str());
  if (!a.report_html.empty()) {
    std::printf("wrote %s (pictures beside it: %s-deviation.png/.svg, -error-x/y/z.png%s)\n", a.report_html.c_str(),
                without_extension(a.report_html).c_str(), uncertainty_drawn ? ", -uncertainty.png" : "");
    if (!pdf_note.empty()) std::printf("%s\n", pdf_note.c_str());
  }
  return exit_code;
}

}  // namespace dg::host
