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

// OpenCASCADE's STEP or IGES reader builds the part (in millimetres, whatever the file's unit);
// BRepMesh meshes its faces to a deflection of 1e-4 of the part's size (0.001 to 0.05 mm). A
// point's nearest triangles name the faces that can hold its closest point; each is measured
// exactly (BRepExtrema), and the nearest wins. The sign comes from the face's normal as the part
// orients it (outward on a solid), or at an edge or a corner from the mesh's pseudo-normal. A foot
// on an edge of one face (a single face's or an open shell's border) is marked `on_border`.
// The OpenCASCADE this build links, "7.6.3", for `digitizer doctor`.
std::string opencascade_version();

class CadNominal {
 public:
  // Throws CadNominalError naming the file: unreadable, not STEP/IGES, nothing transferred, no faces,
  // or a face that cannot be meshed.
  static CadNominal read(const std::string& path);
  CadNominal(CadNominal&&) noexcept;
  ~CadNominal();

  Closest closest(const Point3& p) const;
  size_t face_count() const;
  size_t triangle_count() const;
  double deflection_mm() const;
  // The faces' mesh (to the deflection), in mm: what the report's 3D view draws.
  const Mesh& mesh() const;
  // Points whose exact distance could not be found on any candidate face: measured on the mesh
  // instead (within the deflection).
  size_t mesh_fallbacks() const;

 private:
  struct Impl;
  explicit CadNominal(std::unique_ptr<Impl> impl);
  bool local_closest(const Point3& p, size_t triangle, const Closest& on_mesh, Closest& out) const;
  std::unique_ptr<Impl> impl_;
};

}  // namespace dg::host
