// File names as the commands read them: the extension picks a format, messages name the file.
#pragma once
#include <string>

namespace dg::host {

// Every format a command reads or writes, known by its extension.
enum class FileFormat {
  kUnknown,
  kScan,   // .scan
  kCsv,    // .csv
  kXyz,    // .xyz
  kText,   // .txt (read as whitespace XYZ)
  kPly,    // .ply (points or a mesh)
  kJson,   // .json (SURF.json, curves)
  kIges,   // .igs, .iges
  kStep,   // .stp, .step
  kStl,    // .stl
  kObj,    // .obj
  kHtml,   // .html, .htm
  kBcncProbe,    // .probe (bCNC's autolevel height map)
  kCandleMap,    // .map (Candle's height map)
  kKlipperMesh,  // .cfg (a Klipper bed_mesh profile, as SAVE_CONFIG writes it)
};

// The format a path names by its extension, ignoring case (PART.IGS is IGES).
FileFormat file_format(const std::string& path);

// Suffix test that ignores ASCII case: ends_with("PART.igs", ".igs").
bool ends_with(const std::string& text, const char* suffix);

// The last component of a path: base_name("out/part.igs") is "part.igs".
std::string base_name(const std::string& path);

// The path without its extension: stem("out/report.html") is "out/report".
std::string without_extension(const std::string& path);

}  // namespace dg::host
