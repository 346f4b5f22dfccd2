// HTML assembly: escaped text, tables, and pictures as data: URIs so the file stands alone.
#include "host/inspect/html_report.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>

#include "host/inspect/deviation_map.h"
#include "host/inspect/histogram.h"
#include "host/inspect/number_text.h"
#include "host/inspect/view3d.h"

namespace dg::host {

namespace {

std::string escape(const std::string& text) {
  std::string out;
  for (char c : text) {
    switch (c) {
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '&': out += "&amp;"; break;
      case '"': out += "&quot;"; break;
      default: out += c;
    }
  }
  return out;
}

std::string number(double v, const char* format = "%.4f") { return number_text(v, format); }

std::string row(const std::string& name, const std::string& value) {
  return "<tr><th>" + escape(name) + "</th><td>" + escape(value) + "</td></tr>\n";
}

}  // namespace

std::string base64(const std::string& bytes) {
  static const char* kAlphabet = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  out.reserve((bytes.size() + 2) / 3 * 4);
  for (size_t i = 0; i < bytes.size(); i += 3) {
    const uint32_t b0 = static_cast<uint8_t>(bytes[i]);
    const uint32_t b1 = i + 1 < bytes.size() ? static_cast<uint8_t>(bytes[i + 1]) : 0;
    const uint32_t b2 = i + 2 < bytes.size() ? static_cast<uint8_t>(bytes[i + 2]) : 0;
    const uint32_t n = b0 << 16 | b1 << 8 | b2;
    out += kAlphabet[n >> 18 & 63];
    out += kAlphabet[n >> 12 & 63];
    out += i + 1 < bytes.size() ? kAlphabet[n >> 6 & 63] : '=';
    out += i + 2 < bytes.size() ? kAlphabet[n & 63] : '=';
  }
  return out;
}

ColourScale deviation_scale(const ToleranceLimits* limits) {
  ColourScale scale;
  if (limits) scale.lower_mm = limits->lower_mm, scale.upper_mm = limits->upper_mm;
  return scale;
}

std::vector<ReportPicture> inspection_pictures(const Inspection& inspection, std::string* svg, const ToleranceLimits* limits) {
  std::vector<MapPoint> deviation, ex, ey, ez;
  for (const PointDeviation& d : inspection.points) {
    // A point beyond the surface's edge is grey: its distance is to the edge, and on the scale it
    // would stretch the colours past the part's own deviations (or, under a tolerance, show as
    // out of it where nothing is proven).
    deviation.push_back({d.point.x, d.point.y, d.distance, d.beyond_edge});
    ex.push_back({d.point.x, d.point.y, d.point.x - d.foot.x, d.beyond_edge});
    ey.push_back({d.point.x, d.point.y, d.point.y - d.foot.y, d.beyond_edge});
    ez.push_back({d.point.x, d.point.y, d.point.z - d.foot.z, d.beyond_edge});
  }
  MapPicture picture;
  picture.scale = deviation_scale(limits);
  MapPicture small;
  small.width = 600;
  small.height = 400;
  const std::string colours =
      limits ? "colours fixed to the tolerance " + number(limits->lower_mm) + ".." + number(limits->upper_mm) +
                   " mm: green near the nominal, graded to red at the upper limit and to blue at the lower; magenta "
                   "above the upper limit and violet below the lower: out of tolerance"
             : "red: material above the surface, blue: below";
  const std::string beyond =
      inspection.beyond_edge > 0 ? "; grey: points beyond the surface's edge, whose distance is to the edge" : "";
  std::vector<ReportPicture> out = {
      {"Signed orthogonal deviation over the part (" + colours + beyond + ")",
       deviation_map_png(deviation, picture), deviation_map_svg(deviation, picture, "signed orthogonal deviation, mm")},
      {"X error map: x of each point minus x of its closest surface point" + beyond, deviation_map_png(ex, small),
       deviation_map_svg(ex, small, "X error, mm")},
      {"Y error map: y of each point minus y of its closest surface point" + beyond, deviation_map_png(ey, small),
       deviation_map_svg(ey, small, "Y error, mm")},
      {"Z error map: z of each point minus z of its closest surface point" + beyond, deviation_map_png(ez, small),
       deviation_map_svg(ez, small, "Z error, mm")}};
  if (svg) *svg = out[0].svg;
  return out;
}

ReportPicture uncertainty_picture(const FittedSurface& f) {
  ReportPicture out;
  std::vector<MapPoint> points;
  const int samples = 160;  // per direction: the grid's 21 or 41 nodes would show as dots
  double sigma_mm = 0;
  std::string sigma_from;
  if (f.faces.empty()) {
    const SurfaceUncertainty& u = f.uncertainty;
    if (!has_uncertainty_grid(u)) return out;
    const BSplineSurface& s = f.surface;
    for (int r = 0; r <= samples; ++r) {
      for (int c = 0; c <= samples; ++c) {
        const double a = static_cast<double>(c) / samples, b = static_cast<double>(r) / samples;
        double value = 0;
        if (!uncertainty_at(u, a, b, value)) continue;
        const Point3 p = s.evaluate(s.u_min() + a * (s.u_max() - s.u_min()), s.v_min() + b * (s.v_max() - s.v_min()));
        points.push_back({p.x, p.y, 2 * value});
      }
    }
    sigma_mm = u.sigma_mm;
    sigma_from = u.sigma_from;
  } else {
    // Trimmed faces: each table point takes the face whose loops hold it, and that face's grid at
    // the point's parameters. Every face must carry its grid, or the map would be blank there.
    double x0 = HUGE_VAL, x1 = -HUGE_VAL, y0 = HUGE_VAL, y1 = -HUGE_VAL;
    for (const TrimmedFace& face : f.faces) {
      if (!has_uncertainty_grid(face.uncertainty)) return out;
      for (const TrimLoop& loop : face.loops) {
        for (const Point2& q : loop) x0 = std::min(x0, q.x), x1 = std::max(x1, q.x), y0 = std::min(y0, q.y), y1 = std::max(y1, q.y);
      }
    }
    if (!(x1 > x0) || !(y1 > y0)) return out;
    for (int r = 0; r <= samples; ++r) {
      for (int c = 0; c <= samples; ++c) {
        const double x = x0 + (x1 - x0) * c / samples, y = y0 + (y1 - y0) * r / samples;
        for (const TrimmedFace& face : f.faces) {
          if (!inside_face(face, x, y)) continue;
          double value = 0;
          if (uncertainty_above(face.surface, face.uncertainty, x, y, value)) points.push_back({x, y, 2 * value});
          break;
        }
      }
    }
    sigma_mm = f.faces[0].uncertainty.sigma_mm;
    sigma_from = f.faces[0].uncertainty.sigma_from;
  }
  if (points.empty()) return out;
  MapPicture picture;
  picture.scale.magnitude = true;
  out.caption = "Expanded uncertainty U = 2u of the fitted surface" + std::string(f.faces.empty() ? "" : "'s faces") +
                " (k = 2), from a point uncertainty of " + number(sigma_mm) + " mm (" + sigma_from +
                "): the fit's precision, not its shape error";
  out.png = deviation_map_png(points, picture);
  out.svg = deviation_map_svg(points, picture, "expanded uncertainty U, mm");
  return out;
}

std::string html_report(const ReportInputs& in) {
  std::string h = "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\"><title>" + escape(in.title) +
                  "</title>\n<style>body{font-family:sans-serif;margin:2em;max-width:1000px}"
                  "table{border-collapse:collapse;margin:1em 0}th,td{border:1px solid #ccc;padding:4px 10px;text-align:left}"
                  "th{background:#f3f3f3}figure{margin:1.5em 0}figcaption{color:#444}img{max-width:100%}</style>"
                  "</head><body>\n";
  h += "<h1>" + escape(in.title) + "</h1>\n<p>" + escape(in.created) + "</p>\n";
  h += "<h2>What was measured</h2>\n<table>\n";
  for (const auto& [name, value] : {std::pair<const char*, const std::string*>{"part", &in.fields.part},
                                    {"serial number", &in.fields.serial},
                                    {"operator", &in.fields.operator_name},
                                    {"company", &in.fields.company}}) {
    if (!value->empty()) h += row(name, *value);
  }
  h += row("points", in.points_file) + row("surface", in.surface_file);
  for (const std::string& fact : in.scan_facts) h += "<tr><td colspan=\"2\">" + escape(fact) + "</td></tr>\n";
  h += "</table>\n";
  if (in.inspection && in.decision) {
    const Decision& d = *in.decision;
    const char* colour = d.verdict == Verdict::kPass ? "#1a7f37" : d.verdict == Verdict::kFail ? "#c62828" : "#b26a00";
    std::string verdict = verdict_name(d.verdict);
    for (char& c : verdict) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
    h += "<h2>Verdict: <span style=\"color:" + std::string(colour) + "\">" + verdict + "</span></h2>\n<table>\n" +
         row(d.zones.empty() ? "tolerance (mm)" : "general tolerance (mm)", number(d.limits.lower_mm) + " to " + number(d.limits.upper_mm)) +
         row("decision rule", "ISO 14253-1: pass inside the tolerance shrunk by U, fail outside it widened by U") +
         row("expanded uncertainty U = 2u, largest (mm)", number(d.max_expanded_mm)) + row("u from", d.uncertainty_from) +
         row("points pass / fail / inconclusive",
             std::to_string(d.pass) + " / " + std::to_string(d.fail) + " / " + std::to_string(d.inconclusive)) +
         (d.beyond_edge > 0 ? row("of them inconclusive because beyond the surface's edge", std::to_string(d.beyond_edge))
                            : std::string()) +
         "</table>\n";
    if (!d.zones.empty()) {
      h += "<table><tr><th>zone</th><th>x (mm)</th><th>y (mm)</th><th>tolerance (mm)</th><th>pass / fail / inconclusive</th>"
           "<th>verdict</th></tr>\n";
      for (size_t k = 0; k < d.zones.size(); ++k) {
        const ZoneDecision& z = d.zones[k];
        const bool boxed = k + 1 < d.zones.size();
        h += "<tr><td>" + escape(z.zone.name) + "</td><td>" +
             (boxed ? number(z.zone.x0_mm) + " to " + number(z.zone.x1_mm) : std::string("in no zone")) + "</td><td>" +
             (boxed ? number(z.zone.y0_mm) + " to " + number(z.zone.y1_mm) : std::string()) + "</td><td>" +
             number(z.zone.limits.lower_mm) + " to " + number(z.zone.limits.upper_mm) + "</td><td>" + std::to_string(z.pass) +
             " / " + std::to_string(z.fail) + " / " + std::to_string(z.inconclusive) + "</td><td>" + verdict_name(z.verdict) +
             "</td></tr>\n";
      }
      h += "</table>\n";
    }
    if (!d.worst.empty()) {
      h += "<table><tr><th>point</th><th>x</th><th>y</th><th>z</th><th>deviation</th><th>U</th><th>verdict</th></tr>\n";
      for (size_t i : d.worst) {
        const PointDeviation& p = in.inspection->points[i];
        h += "<tr><td>" + std::to_string(i + 1) + "</td><td>" + number(p.point.x) + "</td><td>" + number(p.point.y) + "</td><td>" +
             number(p.point.z) + "</td><td>" + number(p.distance) + "</td><td>" + number(d.expanded_mm[i]) + "</td><td>" +
             verdict_name(d.points[i]) + "</td></tr>\n";
      }
      h += "</table>\n";
    }
  }
  if (in.inspection) {
    h += "<h2>Histogram of the deviations</h2>\n<figure>" + deviation_histogram_svg(*in.inspection, in.decision) +
         "<figcaption>" +
         std::string(in.decision ? "Red lines: the tolerance's limits; shaded: within U of a limit, where a point is inconclusive."
                                 : "No tolerance was given (inspect --tolerance).") +
         "</figcaption></figure>\n";
    const DistanceStats& s = in.inspection->stats;
    // The points in 3D, coloured as the deviation map (fixed to the tolerance when one was asked).
    const bool surface = in.view_surface && !in.view_surface->triangles.empty();
    const std::string view = view3d_html(*in.inspection, deviation_scale(in.decision ? &in.decision->limits : nullptr),
                                         surface ? in.view_surface : nullptr);
    if (!view.empty()) {
      h += "<h2>The measured points in 3D</h2>\n<figure>" + view +
           "<figcaption>Each point coloured by its signed deviation, on the deviation map's scale" +
           std::string(in.inspection->beyond_edge > 0 ? " (grey beyond the surface's edge)" : "") +
           (surface ? ", over " + escape(in.view_surface_name) + " in translucent grey (" +
                          std::to_string(in.view_surface->triangles.size()) + " triangles)"
                    : std::string()) +
           ".</figcaption></figure>\n";
    }
    const char* points_row = in.inspection->beyond_edge > 0 ? "points over the surface" : "points";
    h += "<h2>Orthogonal deviation (mm)</h2>\n<table>\n" + row(points_row, std::to_string(s.count)) + row("mean", number(s.mean)) +
         row("median", number(s.median)) + row("standard deviation", number(s.stddev)) + row("RMS", number(s.rms)) +
         row("max", number(s.max)) + row("min", number(s.min)) +
         (in.inspection->beyond_edge > 0
              ? row("beyond the surface's edge, left out of these figures (their distance is to the edge, not along a normal)",
                    std::to_string(in.inspection->beyond_edge))
              : std::string()) +
         "</table>\n";
    if (!in.inspection->bands.empty()) {
      h += "<h2>Within tolerance bands</h2>\n<table><tr><th>|deviation| &le; mm</th><th>points</th><th>share</th></tr>\n";
      for (const Band& b : in.inspection->bands) {
        h += "<tr><td>" + number(b.limit_mm) + "</td><td>" + std::to_string(b.count) + "</td><td>" + number(100 * b.share, "%.1f") +
             " %</td></tr>\n";
      }
      h += "</table>\n";
    }
  }
  if (in.surface) {
    const FittedSurface& f = *in.surface;
    h += "<h2>The surface</h2>\n<table>\n" + row("model", f.model) + row("method", f.method);
    if (!f.nominal_summary.empty()) {
      h += row("nominal", f.nominal_summary);
    } else if (f.faces.empty()) {
      h += row("degree", std::to_string(f.surface.degree_u) + " x " + std::to_string(f.surface.degree_v)) +
           row("control points", std::to_string(f.surface.count_u) + " x " + std::to_string(f.surface.count_v));
    } else {
      // One row per trimmed face: the regions between the part's creases and steps.
      for (size_t k = 0; k < f.faces.size(); ++k) {
        const BSplineSurface& s = f.faces[k].surface;
        h += row("face " + std::to_string(k + 1), "degree " + std::to_string(s.degree_u) + " x " + std::to_string(s.degree_v) +
                                                     ", " + std::to_string(s.count_u) + " x " + std::to_string(s.count_v) +
                                                     " control points, " + std::to_string(f.faces[k].loops.size()) + " loop(s)");
      }
    }
    h += row("parameterization", f.parameterization);
    if (f.tolerance_mm > 0) {
      h += row("tolerance", number(f.tolerance_mm) + " mm, " + (f.tolerance_kept ? "kept" : "NOT kept"));
    }
    if (f.noise_sigma_mm > 0) h += row("estimated noise (sigma)", number(f.noise_sigma_mm) + " mm");
    const FitValidation& v = f.validation;
    if (v.checked && v.held_out_points > 0) {
      h += row("between the samples (hold-out)", std::to_string(v.held_out_points) + " points predicted without them: RMS " +
                                                     number(v.held_out_rms_mm) + " mm, max " + number(v.held_out_max_mm) + " mm");
    }
    if (v.checked && !v.problem.empty()) h += row("validation", v.problem);
    const SurfaceUncertainty& u = f.uncertainty;
    if (u.computed) {
      h += row("standard uncertainty u (k = 1)", "max " + number(u.max_mm) + " mm, mean " + number(u.mean_mm) + " mm");
      h += row("expanded uncertainty U = 2u", "max " + number(2 * u.max_mm) + " mm, mean " + number(2 * u.mean_mm) + " mm");
    }
    for (size_t k = 0; k < f.faces.size(); ++k) {
      const SurfaceUncertainty& fu = f.faces[k].uncertainty;
      const std::string face = "face " + std::to_string(k + 1) + ": ";
      h += row(face + "expanded uncertainty U = 2u", fu.computed ? "max " + number(2 * fu.max_mm) + " mm, mean " +
                                                                       number(2 * fu.mean_mm) + " mm"
                                                                 : std::string("not computed"));
    }
    if (!f.source.empty()) h += row("fitted from", f.source);
    h += "</table>\n";
  }
  for (const ReportPicture& p : in.pictures) {
    const std::string source = p.svg.empty() ? "data:image/png;base64," + base64(p.png) : "data:image/svg+xml;base64," + base64(p.svg);
    h += "<figure><img alt=\"" + escape(p.caption) + "\" src=\"" + source + "\"><figcaption>" + escape(p.caption) +
         "</figcaption></figure>\n";
  }
  h += "<p>Written by the bench digitizer.</p>\n</body></html>\n";
  return h;
}

}  // namespace dg::host
