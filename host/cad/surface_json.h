// The surface file (SURF.json, docs/surface-json.md): a fitted surface written and read as JSON.
#pragma once
#include <string>

#include "host/geometry/fitted_surface.h"

namespace dg::host {


// Throws std::runtime_error naming the file on I/O errors.
void write_surface_json(const std::string& path, const FittedSurface& file);
std::string surface_json_text(const FittedSurface& file);
// Throws std::runtime_error naming the file and what is wrong: malformed JSON, a missing or
// mistyped field, an invalid knot vector or net.
FittedSurface read_surface_json(const std::string& path);
FittedSurface parse_surface_json(const std::string& text, const std::string& name);

}  // namespace dg::host
