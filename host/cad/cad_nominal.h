// A nominal part from CAD as users have it (STEP or IGES, any number of faces: planes, cylinders,
// cones, trimmed and rational B-splines), read by OpenCASCADE, measured on its exact faces.
#pragma once
#include <cstddef>
#include <memory>
#include <stdexcept>
#include <string>

#include "host/geometry/closest_point.h"
#include "host/geometry/tessellate.h"

namespace dg::host {

class CadNominalError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// The OpenCASCADE the module was built with, "7.6.3", for `digitizer doctor`. Throws CadNominalError
// when the module cannot be loaded (cad_module.h).
std::string opencascade_version();

// OpenCASCADE's STEP or IGES reader builds the part (in millimetres, whatever the file's unit);
// BRepMesh meshes its faces to a deflection of 1e-4 of the part's size (0.001 to 0.05 mm). A
// point's nearest triangles name the faces that can hold its closest point; each is measured
// exactly (BRepExtrema), and the nearest wins. The sign comes from the face's normal as the part
// orients it (outward on a solid), or at an edge or a corner from the mesh's pseudo-normal. A foot
// on an edge of one face (a single face's or an open shell's border) is marked `on_border`.
// The kernel is in a module of its own, loaded by the first read (cad_module.h).
class CadNominal {
 public:
  // Throws CadNominalError naming the file: unreadable, not STEP/IGES, nothing transferred, no faces,
  // or a face that cannot be meshed; or naming the module when it cannot be loaded.
  static std::unique_ptr<CadNominal> read(const std::string& path);
  virtual ~CadNominal() = default;

  virtual Closest closest(const Point3& p) const = 0;
  virtual size_t face_count() const = 0;
  virtual size_t triangle_count() const = 0;
  virtual double deflection_mm() const = 0;
  // The faces' mesh (to the deflection), in mm: what the report's 3D view draws.
  virtual const Mesh& mesh() const = 0;
  // Points whose exact distance could not be found on any candidate face: measured on the mesh
  // instead (within the deflection).
  virtual size_t mesh_fallbacks() const = 0;
};

}  // namespace dg::host
