// STEP and IGES parts through OpenCASCADE: read, meshed to find candidate faces, measured exactly.
// Built as the module the digitizer loads when a command first reads a CAD nominal (cad_module.h).

#include <BRepAdaptor_Curve.hxx>
#include <BRepAdaptor_Surface.hxx>
#include <BRepBndLib.hxx>
#include <BRepTopAdaptor_FClass2d.hxx>
#include <Extrema_GenLocateExtPS.hxx>
#include <Extrema_POnSurf.hxx>
#include <BRepBuilderAPI_MakeVertex.hxx>
#include <BRepExtrema_DistShapeShape.hxx>
#include <BRepGProp_Face.hxx>
#include <BRepMesh_IncrementalMesh.hxx>
#include <BRep_Tool.hxx>
#include <Bnd_Box.hxx>
#include <IFSelect_ReturnStatus.hxx>
#include <IGESControl_Reader.hxx>
#include <Message.hxx>
#include <Message_Messenger.hxx>
#include <Message_PrinterOStream.hxx>
#include <Poly_Triangulation.hxx>
#include <STEPControl_Reader.hxx>
#include <Standard_Failure.hxx>
#include <Standard_Version.hxx>
#include <TopExp.hxx>
#include <TopExp_Explorer.hxx>
#include <Geom2d_Curve.hxx>
#include <gp_Vec2d.hxx>
#include <TopLoc_Location.hxx>
#include <TopTools_IndexedDataMapOfShapeListOfShape.hxx>
#include <TopTools_IndexedMapOfShape.hxx>
#include <TopTools_ListOfShape.hxx>
#include <TopoDS.hxx>
#include <TopoDS_Edge.hxx>
#include <TopoDS_Face.hxx>
#include <TopoDS_Shape.hxx>
#include <TopoDS_Vertex.hxx>
#include <XSControl_Reader.hxx>
#include <algorithm>
#include <array>
#include <cmath>
#include <fstream>
#include <set>
#include <type_traits>
#include <utility>
#include <vector>

#include "host/cad/cad_module.h"
#include "host/cad/cad_nominal.h"
#include "host/cad/trim_grid.h"
#include "host/cad/vertex_welder.h"
#include "host/geometry/triangle_mesh.h"
#include "host/geometry/vec3.h"
#include "host/io/file_name.h"

namespace dg::host {

namespace {

struct Impl {
  std::vector<TopoDS_Face> faces;
  std::vector<std::unique_ptr<BRepAdaptor_Surface>> surfaces;     // per face
  std::vector<std::unique_ptr<BRepTopAdaptor_FClass2d>> inside;  // per face: (u, v) in its trims
  // Per face, loaded once: building one for each point measured took most of the time a point took.
  std::vector<std::unique_ptr<BRepGProp_Face>> normals;
  std::vector<size_t> face_of_triangle;
  std::vector<std::array<gp_Pnt2d, 3>> uv_of_corner;  // per triangle, when the face's mesh has them
  // Per face: where (u, v) is inside its trims for sure, so the classifier (a point-in-polygon
  // test over every trim curve: on a plate with 24 holes two thirds of a point's time) is asked
  // only near the face's edges.
  std::vector<TrimGrid> trim_grids;
  std::unique_ptr<MeshLocator> mesh;
  // The part's border: edges of one face (not a seam, not degenerate), and their vertices. A single
  // face, or an open shell, has one; a solid has none.
  TopTools_IndexedMapOfShape border_edges, border_vertices;
  double deflection_mm = 0;
  mutable size_t fallbacks = 0;
};

// OpenCASCADE reports through its default messenger on standard output, where our results go.
void silence_opencascade() {
  const Handle(Message_Messenger)& messenger = Message::DefaultMessenger();
  messenger->RemovePrinters(STANDARD_TYPE(Message_PrinterOStream));
}

// The unit normal of a face at (u, v) as the part orients the face (outward on a solid); false,
// and `normal` untouched, where the face has none.
bool oriented_normal(const BRepGProp_Face& face, double u, double v, Point3& normal) {
  gp_Pnt at;
  gp_Vec n;
  face.Normal(u, v, at, n);
  if (!(n.Magnitude() > 0)) return false;
  normal = (1.0 / n.Magnitude()) * Point3{n.X(), n.Y(), n.Z()};
  return true;
}

// The face's trims as (u, v) polygons from its edges' curves on the surface, 32 pieces an edge, and
// how far the true curves stray from them: measured at each piece's middle parameter, doubled.
TrimGrid trim_grid_of(const TopoDS_Face& face, const BRepTopAdaptor_FClass2d& classifier) {
  std::vector<TrimGrid::Segment> segments;
  double sagitta = 0;
  for (TopExp_Explorer e(face, TopAbs_EDGE); e.More(); e.Next()) {
    const TopoDS_Edge& edge = TopoDS::Edge(e.Current());
    Standard_Real first = 0, last = 0;
    const Handle(Geom2d_Curve) curve = BRep_Tool::CurveOnSurface(edge, face, first, last);
    if (curve.IsNull() || !std::isfinite(first) || !std::isfinite(last)) return {};
    constexpr int kPieces = 32;
    gp_Pnt2d from = curve->Value(first);
    for (int k = 1; k <= kPieces; ++k) {
      const double t0 = first + (last - first) * (k - 1) / kPieces, t1 = first + (last - first) * k / kPieces;
      const gp_Pnt2d to = curve->Value(t1), middle = curve->Value(0.5 * (t0 + t1));
      const gp_Vec2d chord(from, to);
      const double length = chord.Magnitude();
      const gp_Vec2d off(from, middle);
      const double stray = length > 0 ? std::fabs(chord.Crossed(off)) / length : off.Magnitude();
      sagitta = std::max(sagitta, 2 * stray);
      segments.push_back({from.X(), from.Y(), to.X(), to.Y()});
      from = to;
    }
  }
  return TrimGrid(segments, sagitta, [&](double u, double v) { return classifier.Perform(gp_Pnt2d(u, v)) == TopAbs_IN; });
}

// How far an edge of one face may run from another face and still be taken as their seam: IGES
// parts are often unsewn, each face with edges of its own, which meet the neighbour's within the
// writer's tolerance; an open part's border runs along no other face.
constexpr double kSeamGapMm = 0.05;

// The part's border into `edges` and their vertices into `vertices`: edges of one face (a seam, an
// edge its closed face meets twice, and a degenerate edge, a sphere's pole, aside) that no other
// face runs along: at 8 points along the edge, no other face's triangle comes within kSeamGapMm
// (plus the mesh's deflection and the edge's tolerance).
void map_border(const TopoDS_Shape& shape, const TopTools_IndexedMapOfShape& face_map, const std::vector<size_t>& face_of_triangle,
                const MeshLocator& mesh, double deflection_mm, TopTools_IndexedMapOfShape& edges,
                TopTools_IndexedMapOfShape& vertices) {
  TopTools_IndexedDataMapOfShapeListOfShape faces_of_edge;
  TopExp::MapShapesAndAncestors(shape, TopAbs_EDGE, TopAbs_FACE, faces_of_edge);
  std::vector<size_t> near;
  for (int k = 1; k <= faces_of_edge.Extent(); ++k) {
    const TopoDS_Edge& edge = TopoDS::Edge(faces_of_edge.FindKey(k));
    if (BRep_Tool::Degenerated(edge)) continue;
    TopTools_IndexedMapOfShape faces;
    for (const TopoDS_Shape& face : faces_of_edge(k)) faces.Add(face);
    if (faces.Extent() != 1 || BRep_Tool::IsClosed(edge, TopoDS::Face(faces(1)))) continue;
    const size_t own = static_cast<size_t>(face_map.FindIndex(faces(1)) - 1);
    const BRepAdaptor_Curve curve(edge);
    const double radius_mm = kSeamGapMm + 2 * deflection_mm + BRep_Tool::Tolerance(edge);
    bool along_another = true;
    for (int i = 0; i < 8 && along_another; ++i) {
      const gp_Pnt q = curve.Value(curve.FirstParameter() + (curve.LastParameter() - curve.FirstParameter()) * (i + 0.5) / 8);
      mesh.triangles_within({q.X(), q.Y(), q.Z()}, radius_mm, near);
      along_another = std::any_of(near.begin(), near.end(), [&](size_t t) { return face_of_triangle[t] != own; });
    }
    if (along_another) continue;
    edges.Add(edge);
    TopExp::MapShapes(edge, TopAbs_VERTEX, vertices);
  }
}

TopoDS_Shape read_shape(const std::string& path) {
  if (!std::ifstream(path)) throw CadNominalError(path + ": cannot be read");
  const FileFormat format = file_format(path);
  if (format != FileFormat::kStep && format != FileFormat::kIges) {
    throw CadNominalError(path + ": a CAD nominal must be STEP (.stp, .step) or IGES (.igs, .iges)");
  }
  silence_opencascade();
  STEPControl_Reader step;
  IGESControl_Reader iges;
  XSControl_Reader& reader = format == FileFormat::kStep ? static_cast<XSControl_Reader&>(step) : iges;
  const char* kind = format == FileFormat::kStep ? "STEP" : "IGES";
  if (reader.ReadFile(path.c_str()) != IFSelect_RetDone) {
    throw CadNominalError(path + ": OpenCASCADE cannot read it as " + kind + " (damaged, or not " + kind + ")");
  }
  if (reader.TransferRoots() == 0) throw CadNominalError(path + ": the " + kind + " file holds no geometry OpenCASCADE can build");
  return reader.OneShape();
}

// The part as the digitizer measures against it, through the interface of cad_nominal.h.
class OcctNominal final : public CadNominal {
 public:
  explicit OcctNominal(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
  Closest closest(const Point3& p) const override;
  size_t face_count() const override { return impl_->faces.size(); }
  size_t triangle_count() const override { return impl_->mesh->triangle_count(); }
  double deflection_mm() const override { return impl_->deflection_mm; }
  const Mesh& mesh() const override { return impl_->mesh->mesh(); }
  size_t mesh_fallbacks() const override { return impl_->fallbacks; }

 private:
  bool local_closest(const Point3& p, size_t triangle, const Closest& on_mesh, Closest& out) const;
  std::unique_ptr<Impl> impl_;
};

std::unique_ptr<CadNominal> read_nominal(const std::string& path) {
  auto impl = std::make_unique<Impl>();
  try {
    const TopoDS_Shape shape = read_shape(path);
    TopTools_IndexedMapOfShape faces;
    TopExp::MapShapes(shape, TopAbs_FACE, faces);
    if (faces.Extent() == 0) throw CadNominalError(path + ": the part has no faces (only curves or points)");
    Bnd_Box box;
    BRepBndLib::Add(shape, box);
    double x0, y0, z0, x1, y1, z1;
    box.Get(x0, y0, z0, x1, y1, z1);
    const double size_mm = std::sqrt((x1 - x0) * (x1 - x0) + (y1 - y0) * (y1 - y0) + (z1 - z0) * (z1 - z0));
    impl->deflection_mm = std::clamp(1e-4 * size_mm, 0.001, 0.05);
    BRepMesh_IncrementalMesh mesher(shape, impl->deflection_mm, false, 0.2, false);
    Mesh mesh;
    VertexWelder welder(mesh);
    for (int k = 1; k <= faces.Extent(); ++k) {
      const TopoDS_Face face = TopoDS::Face(faces(k));
      TopLoc_Location location;
      const Handle(Poly_Triangulation) triangulation = BRep_Tool::Triangulation(face, location);
      if (triangulation.IsNull()) throw CadNominalError(path + ": face " + std::to_string(k) + " of the part cannot be meshed");
      const gp_Trsf move = location.Transformation();
      std::vector<uint32_t> vertex(static_cast<size_t>(triangulation->NbNodes()) + 1);
      for (int n = 1; n <= triangulation->NbNodes(); ++n) {
        const gp_Pnt q = triangulation->Node(n).Transformed(move);
        vertex[static_cast<size_t>(n)] = welder.add({q.X(), q.Y(), q.Z()});
      }
      // A reversed face's triangles turn the other way: their corners swap to face outward.
      const bool reversed = face.Orientation() == TopAbs_REVERSED;
      const bool has_uv = triangulation->HasUVNodes();
      for (int t = 1; t <= triangulation->NbTriangles(); ++t) {
        int a, b, c;
        triangulation->Triangle(t).Get(a, b, c);
        if (reversed) std::swap(b, c);
        const uint32_t va = vertex[static_cast<size_t>(a)], vb = vertex[static_cast<size_t>(b)], vc = vertex[static_cast<size_t>(c)];
        if (va == vb || vb == vc || vc == va) continue;
        mesh.triangles.push_back({va, vb, vc});
        impl->face_of_triangle.push_back(impl->faces.size());
        impl->uv_of_corner.push_back(has_uv ? std::array<gp_Pnt2d, 3>{triangulation->UVNode(a), triangulation->UVNode(b),
                                                                       triangulation->UVNode(c)}
                                            : std::array<gp_Pnt2d, 3>{gp_Pnt2d(NAN, NAN), gp_Pnt2d(NAN, NAN), gp_Pnt2d(NAN, NAN)});
      }
      impl->faces.push_back(face);
      impl->surfaces.push_back(std::make_unique<BRepAdaptor_Surface>(face));
      impl->inside.push_back(std::make_unique<BRepTopAdaptor_FClass2d>(face, 1e-7));
      impl->normals.push_back(std::make_unique<BRepGProp_Face>(face));
      impl->trim_grids.push_back(trim_grid_of(face, *impl->inside.back()));
    }
    if (mesh.triangles.empty()) throw CadNominalError(path + ": the part's faces give no triangles");
    impl->mesh = std::make_unique<MeshLocator>(std::move(mesh));
    map_border(shape, faces, impl->face_of_triangle, *impl->mesh, impl->deflection_mm, impl->border_edges, impl->border_vertices);
  } catch (const Standard_Failure& e) {
    throw CadNominalError(path + ": OpenCASCADE failed on it: " + std::string(e.GetMessageString() ? e.GetMessageString() : "?"));
  } catch (const std::invalid_argument& e) {
    throw CadNominalError(path + ": " + e.what());
  }
  return std::make_unique<OcctNominal>(std::move(impl));
}

// The local search on the face of mesh triangle t from the (u, v) of the mesh foot.
bool OcctNominal::local_closest(const Point3& p, size_t t, const Closest& on_mesh, Closest& out) const {
  const auto& uv = impl_->uv_of_corner[t];
  if (std::isnan(uv[0].X())) return false;
  // The mesh foot's barycentric coordinates in its triangle carry over to (u, v).
  const auto& tri = impl_->mesh->triangle(t);
  const Point3 a = impl_->mesh->vertex(tri[0]), b = impl_->mesh->vertex(tri[1]), c = impl_->mesh->vertex(tri[2]);
  const Point3 ab = b - a, ac = c - a, aq = on_mesh.point - a;
  const double d00 = dot(ab, ab), d01 = dot(ab, ac), d11 = dot(ac, ac), d20 = dot(aq, ab), d21 = dot(aq, ac);
  const double det = d00 * d11 - d01 * d01;
  if (!(det > 0)) return false;
  const double wb = (d11 * d20 - d01 * d21) / det, wc = (d00 * d21 - d01 * d20) / det, wa = 1 - wb - wc;
  const double u0 = wa * uv[0].X() + wb * uv[1].X() + wc * uv[2].X(), v0 = wa * uv[0].Y() + wb * uv[1].Y() + wc * uv[2].Y();
  const size_t f = impl_->face_of_triangle[t];
  Extrema_GenLocateExtPS locate(*impl_->surfaces[f]);
  locate.Perform(gp_Pnt(p.x, p.y, p.z), u0, v0, Standard_True);
  if (!locate.IsDone()) return false;
  Standard_Real u = 0, v = 0;
  locate.Point().Parameter(u, v);
  // A foot on the trim (ON, not IN) is left to the global search too: it names the edge the foot is on.
  if (!impl_->trim_grids[f].surely_inside(u, v) && impl_->inside[f]->Perform(gp_Pnt2d(u, v)) != TopAbs_IN) return false;
  const gp_Pnt foot = locate.Point().Value();
  const double distance = std::sqrt(locate.SquareDistance());
  if (!(std::fabs(distance - std::fabs(on_mesh.distance)) <= 2 * impl_->deflection_mm)) return false;
  if (!oriented_normal(*impl_->normals[f], u, v, out.normal)) return false;
  out.point = {foot.X(), foot.Y(), foot.Z()};
  out.distance = dot(p - out.point, out.normal) < 0 ? -distance : distance;
  return std::isfinite(out.distance);
}

Closest OcctNominal::closest(const Point3& p) const {
  size_t nearest = 0;
  const Closest on_mesh = impl_->mesh->closest(p, &nearest);
  // Every face that has a triangle within the mesh's distance plus twice its deflection may hold
  // the closest point on the exact part.
  std::vector<size_t> triangles;
  impl_->mesh->triangles_within(p, std::fabs(on_mesh.distance) + 2 * impl_->deflection_mm, triangles);
  std::set<size_t> candidates = {impl_->face_of_triangle[nearest]};
  for (size_t t : triangles) candidates.insert(impl_->face_of_triangle[t]);
  Closest best;
  bool found = false;
  // One candidate face: Newton from the mesh foot's (u, v) on that face finds the closest point in
  // microseconds where the global search takes milliseconds. Kept when it lands inside the face's
  // trims and agrees with the mesh's distance to within the mesh's deflection; else the global one.
  if (candidates.size() == 1) {
    try {
      if (local_closest(p, nearest, on_mesh, best)) return best;
    } catch (const Standard_Failure&) {
    }
  }
  try {
    const TopoDS_Vertex vertex = BRepBuilderAPI_MakeVertex(gp_Pnt(p.x, p.y, p.z));
    for (size_t f : candidates) {
      BRepExtrema_DistShapeShape extrema(vertex, impl_->faces[f], Extrema_ExtFlag_MIN);
      if (!extrema.IsDone() || extrema.NbSolution() < 1) continue;
      const double distance = extrema.Value();
      if (found && distance >= std::fabs(best.distance)) continue;
      const gp_Pnt foot = extrema.PointOnShape2(1);
      Closest c;
      c.point = {foot.X(), foot.Y(), foot.Z()};
      c.normal = on_mesh.normal;
      if (extrema.SupportTypeShape2(1) == BRepExtrema_IsInFace) {
        // Inside the face its own normal, as the part orients the face, gives the side.
        Standard_Real u = 0, v = 0;
        extrema.ParOnFaceS2(1, u, v);
        oriented_normal(*impl_->normals[f], u, v, c.normal);
      }
      c.distance = dot(p - c.point, c.normal) < 0 ? -distance : distance;
      const BRepExtrema_SupportType support = extrema.SupportTypeShape2(1);
      c.on_border = (support == BRepExtrema_IsOnEdge && impl_->border_edges.Contains(extrema.SupportOnShape2(1))) ||
                    (support == BRepExtrema_IsVertex && impl_->border_vertices.Contains(extrema.SupportOnShape2(1)));
      best = c;
      found = true;
    }
  } catch (const Standard_Failure&) {
    found = false;
  }
  if (!found || !std::isfinite(best.distance)) {
    ++impl_->fallbacks;
    // The tessellation's faces need not share their seams' vertices: a seam can look like a
    // border on the mesh, so the mesh's foot marks none.
    Closest fallback = on_mesh;
    fallback.on_border = false;
    return fallback;
  }
  return best;
}

}  // namespace
}  // namespace dg::host

// The module's entry points. Nothing thrown crosses them: the error comes back as its message.
extern "C" __attribute__((visibility("default"))) dg::host::CadNominal* dg_cad_read_nominal(const std::string* path,
                                                                                          std::string* error) {
  try {
    return dg::host::read_nominal(*path).release();
  } catch (const std::exception& e) {
    *error = e.what();
  } catch (...) {
    *error = *path + ": OpenCASCADE failed on it";
  }
  return nullptr;
}

extern "C" __attribute__((visibility("default"))) const char* dg_cad_opencascade_version() {
  return OCC_VERSION_COMPLETE;
}

// The program calls them through cad_module.h's types: they must be those exactly.
static_assert(std::is_same_v<decltype(&dg_cad_read_nominal), dg::host::cad_module::ReadNominal>);
static_assert(std::is_same_v<decltype(&dg_cad_opencascade_version), dg::host::cad_module::OpencascadeVersion>);
