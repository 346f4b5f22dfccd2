// `digitizer export`: a scan's points as CSV, XYZ, PLY or a height map; a surface as IGES, STEP or a mesh.
#pragma once
#include <CLI/CLI.hpp>
#include <string>

namespace dg::host {

struct ExportArgs {
  std::string input, output;
  double chord_mm = 0.01;  // meshes: largest distance from the surface to its triangles
  double angle_deg = 0;    // meshes of one surface: largest triangle-to-surface normal angle (0: none)
  bool edges = false;      // IGES/STEP: the surface's four edges as curves instead
  std::string name;        // IGES/STEP: the part's name (Klipper: the profile's); empty: the input's file name
  bool relative = false;   // height maps: heights relative to the grid's first point
  std::string format;      // a scan's points: csv, xyz, ply, bcnc, candle or klipper; empty: by extension
};

CLI::App* add_export_command(CLI::App& app, ExportArgs& args);
int run_export(const ExportArgs& args);

}  // namespace dg::host
