// Export: points keep their nanometre values; surfaces go to CAD or a mesh, chosen by the extension.
#include "host/cli/export_command.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <map>
#include <stdexcept>

#include "host/cad/iges_writer.h"
#include "host/cad/mesh_writer.h"
#include "host/cad/step_writer.h"
#include "host/cad/surface_json.h"
#include "host/geometry/bspline_curve.h"
#include "host/geometry/clamp.h"
#include "host/io/file_name.h"
#include "host/io/standard_output.h"
#include "host/io/atomic_file.h"
#include "host/scan/height_map.h"
#include "host/scan/point_export.h"
#include "host/scan/position_uncertainty.h"
#include "host/scan/scan_uncertainty.h"
#include "host/scan/table_calibration.h"
#include "host/scan/drift_removal.h"
#include "host/scan/fly_correction.h"
#include "host/scan/scan_file.h"

namespace dg::host {
namespace {

// The name a CAD file records for itself: the output's, or the part's with the extension when the
// output is standard output.
std::string recorded_file_name(const std::string& output, const std::string& part) {
  if (!is_standard_output(output)) return base_name(output);
  const size_t dot = output.find('.');
  return part + (dot == std::string::npos ? "" : output.substr(dot));
}

// Now, in UTC, as `format` (strftime) says.
std::string utc_stamp(const char* format) {
  const std::time_t now = std::time(nullptr);
  char stamp[32];
  std::strftime(stamp, sizeof stamp, format, std::gmtime(&now));
  return stamp;
}

// IGES's and STEP's time stamps; nullptr keeps the writer's default.
constexpr const char* kIgesStamp = "%Y%m%d.%H%M%S";
constexpr const char* kStepStamp = "%Y-%m-%dT%H:%M:%S";

// IgesOptions or StepOptions naming the file and the part, and stamped with the time as `stamp`.
template <typename Options>
Options cad_options(const std::string& output, const std::string& part, const char* stamp) {
  Options options;
  options.file_name = recorded_file_name(output, part);
  options.product = part;
  if (stamp != nullptr) options.timestamp = utc_stamp(stamp);
  return options;
}

// Curves to IGES (entity 126) or STEP (a curve set).
void write_curves(const std::string& output, const std::string& part, bool iges, const std::vector<BSplineCurve>& curves) {
  if (iges) {
    write_iges_curves(output, curves, cad_options<IgesOptions>(output, part, nullptr));
  } else {
    write_step_curves(output, curves, cad_options<StepOptions>(output, part, nullptr));
  }
}

// Trimmed faces (a scan split at creases and steps): IGES entity 144, a STEP shell of advanced
// faces, a mesh of the triangles inside the faces, or the faces' boundaries as curves.
int export_faces(const FittedSurface& surface, const std::string& output, const std::string& part, FileFormat format, double chord_mm,
                 bool edges) {
  const bool iges = format == FileFormat::kIges, step = format == FileFormat::kStep;
  if (format == FileFormat::kStl || format == FileFormat::kObj || format == FileFormat::kPly) {
    if (edges) throw std::invalid_argument("--edges writes curves: give an .igs or .stp output");
    // Triangles of a 200th of the part's size in XY (0.1 mm at least): the mesh follows each trim to that.
    double extent = 0;
    for (const TrimmedFace& f : surface.faces) {
      const Point3& a = f.surface.at(0, 0);
      const Point3& b = f.surface.at(f.surface.count_u - 1, f.surface.count_v - 1);
      extent = std::max({extent, std::fabs(b.x - a.x), std::fabs(b.y - a.y)});
    }
    const Mesh mesh = tessellate_faces(surface.faces, chord_mm, std::max(0.1, extent / 200));
    write_mesh(output, mesh);
    std::printf("wrote %zu triangles of %zu trimmed faces (chord error %.4f mm, asked %.4f) to %s\n", mesh.triangles.size(),
                surface.faces.size(), mesh.chord_error_mm, chord_mm, output_name(output).c_str());
    return 0;
  }
  if (!iges && !step) {
    throw std::invalid_argument("a surface exports to .igs/.iges, .stp/.step, .stl, .obj or .ply (got " + output + ")");
  }
  if (edges) {
    // Each face's loops on its surface, as degree-1 curves through the points above their vertices.
    std::vector<BSplineCurve> curves;
    for (const TrimmedFace& f : surface.faces) {
      for (const TrimLoop& loop : f.loops) {
        BSplineCurve c;
        c.degree = 1;
        for (const Point2& p : densified(loop, 0.25)) c.control.push_back(point_above(f.surface, p.x, p.y));
        c.control.push_back(c.control.front());
        c.knots.push_back(0);
        for (size_t k = 0; k < c.control.size(); ++k) c.knots.push_back(static_cast<double>(k));
        c.knots.push_back(static_cast<double>(c.control.size() - 1));
        curves.push_back(std::move(c));
      }
    }
    write_curves(output, part, iges, curves);
    std::printf("wrote the %zu boundaries of %zu trimmed faces as curves to %s\n", curves.size(), surface.faces.size(),
                output_name(output).c_str());
    return 0;
  }
  if (iges) {
    write_iges_faces(output, surface.faces, cad_options<IgesOptions>(output, part, kIgesStamp));
  } else {
    write_step_faces(output, surface.faces, cad_options<StepOptions>(output, part, kStepStamp));
  }
  std::printf("wrote %zu trimmed faces to %s\n", surface.faces.size(), output_name(output).c_str());
  return 0;
}

// A surface file to CAD (IGES 5.3 entity 128, STEP AP214) or a mesh (STL, OBJ, PLY), in millimetres.
int run_export_surface(const std::string& input, const std::string& output, const std::string& part, double chord_mm, double angle_deg,
                       bool edges) {
  const FileFormat format = file_format(output);
  const FittedSurface surface = read_surface_json(input);
  const bool iges = format == FileFormat::kIges;
  const bool step = format == FileFormat::kStep;
  if (!surface.faces.empty()) return export_faces(surface, output, part, format, chord_mm, edges);
  if (format == FileFormat::kStl || format == FileFormat::kObj || format == FileFormat::kPly) {
    const Mesh mesh = tessellate(surface.surface, chord_mm, kMaxMeshTriangles, angle_deg);
    write_mesh(output, mesh);
    std::printf("wrote %zu triangles (chord error %.4f mm, asked %.4f%s) to %s\n", mesh.triangles.size(), mesh.chord_error_mm,
                chord_mm, angle_deg > 0 ? (", normals within " + std::to_string(angle_deg).substr(0, 4) + " degrees").c_str() : "",
                output_name(output).c_str());
    return 0;
  }
  if (!iges && !step) {
    throw std::invalid_argument("a surface exports to .igs/.iges, .stp/.step, .stl, .obj or .ply (got " + output + ")");
  }
  if (edges) {
    // The four edges as curves: IGES entity 126 or a STEP curve set, for trimming or sketching in CAD.
    const std::vector<BSplineCurve> curves = boundary_curves(clamp_ends(surface.surface));
    write_curves(output, part, iges, curves);
    std::printf("wrote the surface's 4 edges as B-spline curves to %s\n", output_name(output).c_str());
    return 0;
  }
  if (iges) {
    write_iges(output, surface.surface, cad_options<IgesOptions>(output, part, kIgesStamp));
  } else {
    write_step(output, surface.surface, cad_options<StepOptions>(output, part, kStepStamp));
  }
  std::printf("wrote %s surface (%d x %d control points, degree %d x %d) to %s\n", surface.model.c_str(),
              surface.surface.count_u, surface.surface.count_v, surface.surface.degree_u, surface.surface.degree_v,
              output_name(output).c_str());
  return 0;
}

// A scan on an even grid as a height map for bCNC (.probe), Candle (.map) or Klipper (.cfg, a
// bed_mesh profile named after the part).
int export_height_map(const ScanData& data, const std::string& input, const std::string& output, FileFormat format,
                      const std::string& part, bool relative) {
  std::vector<Point3> points;
  for (const PointSample& p : data.points) points.push_back({p.x_nm * 1e-6, p.y_nm * 1e-6, p.z_nm * 1e-6});
  HeightMap map = height_map_from_points(points, input);
  const double zero = relative ? map.z(0, 0) : 0.0;
  for (double& z : map.z_mm) z -= zero;
  const std::string text = format == FileFormat::kBcncProbe   ? format_bcnc_probe(map)
                           : format == FileFormat::kCandleMap ? format_candle_map(map)
                                                              : format_klipper_mesh(map, part);
  write_file_atomically(output, text);
  std::printf("wrote a %d x %d height map (x %.3f..%.3f, y %.3f..%.3f mm%s) for %s to %s\n", map.count_x, map.count_y, map.min_x_mm,
              map.max_x_mm, map.min_y_mm, map.max_y_mm, relative ? ", heights relative to the first point" : "",
              format == FileFormat::kBcncProbe ? "bCNC" : format == FileFormat::kCandleMap ? "Candle" : "Klipper",
              output_name(output).c_str());
  return 0;
}

// The part's name in IGES and STEP: --name, else the input's file name without its extension.
std::string part_name(const ExportArgs& a) {
  const std::string name = a.name.empty() ? without_extension(base_name(a.input)) : a.name;
  if (name.empty() || name.size() > 64) throw std::invalid_argument("--name: a part name of 1 to 64 characters");
  for (char c : name) {
    if (c < 0x20 || c > 0x7e) throw std::invalid_argument("--name: a part name of printable ASCII characters (IGES and STEP carry no other)");
  }
  return name;
}

}  // namespace

CLI::App* add_export_command(CLI::App& app, ExportArgs& a) {
  CLI::App* cmd = app.add_subcommand("export", "write a scan's points as CSV, XYZ, PLY or a height map (bCNC, Candle, Klipper), or a surface as IGES, STEP or a mesh (STL, OBJ, PLY)");
  cmd->add_option("input", a.input, "scan file, or SURF.json")->required()->check(CLI::ExistingFile);
  cmd->add_option("-o,--output", a.output,
                  "points: .csv, .xyz or .ply, or a height map for bCNC (.probe), Candle (.map) or Klipper (.cfg); a surface: .igs, .stp, or a mesh .stl, .obj, .ply; - is standard output "
                  "(points as CSV; -.EXT picks the format)")
      ->required();
  cmd->add_option("--chord", a.chord_mm, "meshes: largest distance from the surface to its triangles, mm")
      ->capture_default_str()->check(CLI::PositiveNumber);
  cmd->add_option("--angle", a.angle_deg,
                  "meshes of one surface: largest angle between a triangle and the surface's normal, degrees (0: none)")
      ->capture_default_str()->check(CLI::Range(0.0, 89.0));
  cmd->add_flag("--edges", a.edges, "IGES/STEP: write the surface's four edges as B-spline curves instead");
  cmd->add_option("--name", a.name, "IGES/STEP: the part's name; Klipper: the bed_mesh profile's (default: the input's file name without its extension)");
  cmd->add_option("--format", a.format, "a scan's points in this format whatever the extension: csv, xyz, ply, bcnc, candle, klipper")
      ->check(CLI::IsMember({"csv", "xyz", "ply", "bcnc", "candle", "klipper"}));
  cmd->add_flag("--relative", a.relative, "height maps: heights relative to the grid's first point (min x, min y), where Z was zeroed");
  return cmd;
}

int run_export(const ExportArgs& a) {
  const std::string& input = a.input;
  if (file_format(input) == FileFormat::kJson) {
    if (a.output == "-") {
      throw std::invalid_argument("a surface to standard output needs its format: -o -.igs, -.stp, -.stl, -.obj or -.ply");
    }
    return run_export_surface(input, a.output, part_name(a), a.chord_mm, a.angle_deg, a.edges);
  }
  const std::string output = with_default_format(a.output, ".csv");
  if (a.edges) throw std::invalid_argument("--edges exports a surface's edges: give a SURF.json");
  ScanData data = read_scan_file(input);
  for (const auto& w : data.warnings) std::fprintf(stderr, "digitizer: warning: %s\n", w.c_str());
  // The points as the scan's reference readings and calibration correct them (the raw ones stay
  // in the scan file); the readings themselves are no points.
  ScanPointSigmas sigmas = scan_point_sigmas(data);
  remove_drift(data, &sigmas.sigma_mm, input);
  if (const auto fly = correct_fly_scan(data, &sigmas.sigma_mm, input)) std::printf("%s\n", fly_summary(*fly).c_str());
  const std::optional<TableCalibration> calibration = correct_by_record(data, &sigmas.sigma_mm, input);
  add_position_uncertainty(data, table_position(data, calibration), sigmas.sigma_mm);
  // --format names the format whatever the output's extension (a Klipper profile saved as .txt, say).
  static const std::map<std::string, FileFormat> kNamed = {{"csv", FileFormat::kCsv},          {"xyz", FileFormat::kXyz},
                                                           {"ply", FileFormat::kPly},          {"bcnc", FileFormat::kBcncProbe},
                                                           {"candle", FileFormat::kCandleMap}, {"klipper", FileFormat::kKlipperMesh}};
  const FileFormat format = a.format.empty() ? file_format(output) : kNamed.at(a.format);
  if (format == FileFormat::kBcncProbe || format == FileFormat::kCandleMap || format == FileFormat::kKlipperMesh) {
    return export_height_map(data, input, output, format, part_name(a), a.relative);
  }
  if (a.relative) throw std::invalid_argument("--relative is for height maps (.probe, .map, .cfg)");
  // The points' standard uncertainty goes with them into a CSV, which is read back with it.
  write_points(output, data.points, format, sigmas.sigma_mm.empty() ? nullptr : &sigmas.sigma_mm);
  std::printf("wrote %zu points to %s%s\n", data.points.size(), output_name(output).c_str(),
              !sigmas.sigma_mm.empty() && format == FileFormat::kCsv ? " with each point's standard uncertainty (sigma)" : "");
  return 0;
}

}  // namespace dg::host
