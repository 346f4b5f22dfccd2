// The STEP writer: entity instances numbered in order, product structure, units, geometry, topology.
#include "host/cad/step_writer.h"

#include <cmath>
#include <stdexcept>
#include <vector>

#include "host/io/atomic_file.h"
#include "host/geometry/clamp.h"
#include "host/cad/iges_writer.h"

namespace dg::host {
namespace {

// A STEP string: apostrophes and backslashes (the escape character) doubled; we write ASCII only.
std::string quoted(const std::string& text) {
  std::string out = "'";
  for (char c : text) {
    if (c == '\'') out += "''";
    else if (c == '\\') out += "\\\\";
    else if (c >= 32 && c < 127) out += c;
  }
  return out + "'";
}

// iges_real's digits serve STEP too: a decimal point and an upper-case exponent.
std::string real(double value) { return iges_real(value); }

class Instances {
 public:
  int add(const std::string& body) {
    lines_ += "#" + std::to_string(++count_) + "=" + body + ";\n";
    return count_;
  }
  const std::string& text() const { return lines_; }

 private:
  std::string lines_;
  int count_ = 0;
};

std::string ref(int id) { return "#" + std::to_string(id); }

// Distinct knot values and their multiplicities.
void knots_and_multiplicities(const std::vector<double>& knots, std::string& values, std::string& counts) {
  values = "(";
  counts = "(";
  for (size_t i = 0; i < knots.size();) {
    size_t j = i;
    while (j < knots.size() && knots[j] == knots[i]) ++j;
    if (i > 0) {
      values += ",";
      counts += ",";
    }
    values += real(knots[i]);
    counts += std::to_string(j - i);
    i = j;
  }
  values += ")";
  counts += ")";
}

}  // namespace

namespace {

struct Preamble {
  int shape = 0;    // the PRODUCT_DEFINITION_SHAPE a representation belongs to
  int context = 0;  // the geometric representation context (units, uncertainty)
};

// Product, units and context: what every exchange file of ours starts with.
Preamble preamble(Instances& e, const StepOptions& options) {
  const int app = e.add("APPLICATION_CONTEXT('automotive design')");
  e.add("APPLICATION_PROTOCOL_DEFINITION('international standard','automotive_design',2000," + ref(app) + ")");
  const int product_context = e.add("PRODUCT_CONTEXT(''," + ref(app) + ",'mechanical')");
  const int product = e.add("PRODUCT(" + quoted(options.product) + "," + quoted(options.product) + ",'measured and fitted by the bench digitizer',(" + ref(product_context) + "))");
  const int formation = e.add("PRODUCT_DEFINITION_FORMATION('',''," + ref(product) + ")");
  const int definition_context = e.add("PRODUCT_DEFINITION_CONTEXT('part definition'," + ref(app) + ",'design')");
  const int definition = e.add("PRODUCT_DEFINITION('design',''," + ref(formation) + "," + ref(definition_context) + ")");
  const int shape = e.add("PRODUCT_DEFINITION_SHAPE(''," + std::string("''") + "," + ref(definition) + ")");
  const int length = e.add("(LENGTH_UNIT()NAMED_UNIT(*)SI_UNIT(.MILLI.,.METRE.))");
  const int angle = e.add("(NAMED_UNIT(*)PLANE_ANGLE_UNIT()SI_UNIT($,.RADIAN.))");
  const int solid = e.add("(NAMED_UNIT(*)SI_UNIT($,.STERADIAN.)SOLID_ANGLE_UNIT())");
  const int uncertainty = e.add("UNCERTAINTY_MEASURE_WITH_UNIT(LENGTH_MEASURE(" + real(options.uncertainty_mm) + ")," + ref(length) +
                                ",'distance_accuracy_value','the fit is meant to this distance')");
  const int context = e.add("(GEOMETRIC_REPRESENTATION_CONTEXT(3)GLOBAL_UNCERTAINTY_ASSIGNED_CONTEXT((" + ref(uncertainty) +
                            "))GLOBAL_UNIT_ASSIGNED_CONTEXT((" + ref(length) + "," + ref(angle) + "," + ref(solid) +
                            "))REPRESENTATION_CONTEXT('',''))");
  return {shape, context};
}

int point_instance(Instances& e, const Point3& p) {
  return e.add("CARTESIAN_POINT('',(" + real(p.x) + "," + real(p.y) + "," + real(p.z) + "))");
}

int curve_instance(Instances& e, int degree, const std::vector<int>& poles, const std::vector<double>& knots) {
  std::string list = "(";
  for (size_t k = 0; k < poles.size(); ++k) list += (k ? "," : "") + ref(poles[k]);
  list += ")";
  std::string values, counts;
  knots_and_multiplicities(knots, values, counts);
  return e.add("B_SPLINE_CURVE_WITH_KNOTS(''," + std::to_string(degree) + "," + list + ",.UNSPECIFIED.,.F.,.F.," + counts + "," +
               values + ",.UNSPECIFIED.)");
}

std::string exchange_file(const Instances& e, const StepOptions& options, const std::string& description) {
  std::string out = "ISO-10303-21;\nHEADER;\n";
  out += "FILE_DESCRIPTION((" + quoted(description) + "),'2;1');\n";
  out += "FILE_NAME(" + quoted(options.file_name) + "," + quoted(options.timestamp) +
         ",('bench digitizer'),('bench digitizer'),'bench digitizer STEP writer 1','bench digitizer','');\n";
  out += "FILE_SCHEMA(('AUTOMOTIVE_DESIGN { 1 0 10303 214 1 1 1 1 }'));\nENDSEC;\nDATA;\n";
  out += e.text();
  out += "ENDSEC;\nEND-ISO-10303-21;\n";
  return out;
}

int placement_instance(Instances& e) {
  const int origin = point_instance(e, Point3{});
  const int z = e.add("DIRECTION('',(0.,0.,1.))");
  const int x = e.add("DIRECTION('',(1.,0.,0.))");
  return e.add("AXIS2_PLACEMENT_3D(''," + ref(origin) + "," + ref(z) + "," + ref(x) + ")");
}

}  // namespace

namespace {

// The surface: control_points_list[i][j], i along u. `poles` receives the control points' instances.
int surface_instance(Instances& e, const BSplineSurface& s, std::vector<int>& poles) {
  poles.assign(s.control.size(), 0);
  for (int i = 0; i < s.count_u; ++i)
    for (int j = 0; j < s.count_v; ++j) poles[static_cast<size_t>(i * s.count_v + j)] = point_instance(e, s.at(i, j));
  auto pole = [&](int i, int j) { return poles[static_cast<size_t>(i * s.count_v + j)]; };
  std::string net = "(";
  for (int i = 0; i < s.count_u; ++i) {
    net += i ? ",(" : "(";
    for (int j = 0; j < s.count_v; ++j) net += (j ? "," : "") + ref(pole(i, j));
    net += ")";
  }
  net += ")";
  std::string ku, mu, kv, mv;
  knots_and_multiplicities(s.knots_u, ku, mu);
  knots_and_multiplicities(s.knots_v, kv, mv);
  const int surface = e.add("B_SPLINE_SURFACE_WITH_KNOTS(''," + std::to_string(s.degree_u) + "," + std::to_string(s.degree_v) + "," + net +
                            ",.UNSPECIFIED.,.F.,.F.,.F.," + mu + "," + mv + "," + ku + "," + kv + ",.UNSPECIFIED.)");
  return surface;
}

// The shell of faces as a surface model, tied to the product.
void shell_model(Instances& e, const Preamble& pre, const std::vector<int>& faces, const StepOptions& options) {
  std::string list = "(";
  for (size_t k = 0; k < faces.size(); ++k) list += (k ? "," : "") + ref(faces[k]);
  const int shell = e.add("OPEN_SHELL(''," + list + "))");
  const int model = e.add("SHELL_BASED_SURFACE_MODEL('',(" + ref(shell) + "))");
  const int placement = placement_instance(e);
  const int representation = e.add("MANIFOLD_SURFACE_SHAPE_REPRESENTATION(" + quoted(options.product) + ",(" + ref(model) + "," +
                                   ref(placement) + ")," + ref(pre.context) + ")");
  e.add("SHAPE_DEFINITION_REPRESENTATION(" + ref(pre.shape) + "," + ref(representation) + ")");
}

}  // namespace

std::string step_text(const BSplineSurface& input, const StepOptions& options) {
  std::string why;
  if (!is_valid(input, &why)) throw std::invalid_argument("cannot write this surface as STEP: " + why);
  const BSplineSurface s = clamp_ends(input);
  Instances e;
  const Preamble pre = preamble(e, options);
  std::vector<int> poles;
  const int surface = surface_instance(e, s, poles);
  auto pole = [&](int i, int j) { return poles[static_cast<size_t>(i * s.count_v + j)]; };
  // The four edges: the first and last rows and columns of the clamped net, with its knots.
  auto edge_curve = [&](bool along_u, int fixed) {
    std::vector<int> ids;
    const int n = along_u ? s.count_u : s.count_v;
    for (int k = 0; k < n; ++k) ids.push_back(along_u ? pole(k, fixed) : pole(fixed, k));
    return curve_instance(e, along_u ? s.degree_u : s.degree_v, ids, along_u ? s.knots_u : s.knots_v);
  };
  const int last_u = s.count_u - 1, last_v = s.count_v - 1;
  auto vertex = [&](int i, int j) { return e.add("VERTEX_POINT(''," + ref(pole(i, j)) + ")"); };
  const int v00 = vertex(0, 0), v10 = vertex(last_u, 0), v11 = vertex(last_u, last_v), v01 = vertex(0, last_v);
  auto edge = [&](int from, int to, int geometry) {
    return e.add("EDGE_CURVE(''," + ref(from) + "," + ref(to) + "," + ref(geometry) + ",.T.)");
  };
  const int bottom = edge(v00, v10, edge_curve(true, 0));      // v = 0, u increasing
  const int right = edge(v10, v11, edge_curve(false, last_u));  // u = 1, v increasing
  const int top = edge(v01, v11, edge_curve(true, last_v));     // v = 1, u increasing
  const int left = edge(v00, v01, edge_curve(false, 0));        // u = 0, v increasing
  auto oriented = [&](int edge_id, bool same) {
    return e.add("ORIENTED_EDGE('',*,*," + ref(edge_id) + "," + (same ? ".T." : ".F.") + ")");
  };
  // Counter-clockwise in (u, v): along the bottom, up the right, back along the top, down the left.
  const int loop = e.add("EDGE_LOOP('',(" + ref(oriented(bottom, true)) + "," + ref(oriented(right, true)) + "," +
                         ref(oriented(top, false)) + "," + ref(oriented(left, false)) + "))");
  const int bound = e.add("FACE_OUTER_BOUND(''," + ref(loop) + ",.T.)");
  const int face = e.add("ADVANCED_FACE('',(" + ref(bound) + ")," + ref(surface) + ",.T.)");
  shell_model(e, pre, {face}, options);
  return exchange_file(e, options, "B-spline surface fitted to measured points by the bench digitizer");
}

std::string step_faces_text(const std::vector<TrimmedFace>& faces, const StepOptions& options) {
  if (faces.empty()) throw std::invalid_argument("no faces to write");
  Instances e;
  const Preamble pre = preamble(e, options);
  std::vector<int> face_ids;
  // Parameter-space curves live in a 2D context of their own.
  const int plane = e.add("(GEOMETRIC_REPRESENTATION_CONTEXT(2)PARAMETRIC_REPRESENTATION_CONTEXT()REPRESENTATION_CONTEXT('2D SPACE',''))");
  for (const TrimmedFace& f : faces) {
    std::string why;
    if (!is_valid(f.surface, &why)) throw std::invalid_argument("cannot write this surface as STEP: " + why);
    if (f.loops.empty()) throw std::invalid_argument("a trimmed face without a boundary");
    std::vector<int> poles;
    const int surface = surface_instance(e, clamp_ends(f.surface), poles);
    std::string bounds = "(";
    for (size_t k = 0; k < f.loops.size(); ++k) {
      // One closed edge per loop: a degree-1 curve through the surface points above the loop's
      // vertices (edges cut to 0.25 mm), starting and ending at one vertex.
      const TrimLoop fine = densified(f.loops[k], 0.25);
      std::vector<int> points, uv_points;
      for (const Point2& p : fine) {
        points.push_back(point_instance(e, point_above(f.surface, p.x, p.y)));
        double u, v;
        table_to_parameters(f.surface, p.x, p.y, u, v);
        uv_points.push_back(e.add("CARTESIAN_POINT('',(" + real(u) + "," + real(v) + "))"));
      }
      points.push_back(points.front());
      uv_points.push_back(uv_points.front());
      std::vector<double> knots{0.0};
      for (size_t i = 0; i < points.size(); ++i) knots.push_back(static_cast<double>(i));
      knots.push_back(static_cast<double>(points.size() - 1));
      // The edge is the loop on the surface, given both ways: in space and in the surface's
      // parameters (a surface curve with its pcurve), so a reader need not project one onto it.
      const int space_curve = curve_instance(e, 1, points, knots);
      const int uv_curve = curve_instance(e, 1, uv_points, knots);
      const int uv_representation = e.add("DEFINITIONAL_REPRESENTATION('',(" + ref(uv_curve) + ")," + ref(plane) + ")");
      const int pcurve = e.add("PCURVE(''," + ref(surface) + "," + ref(uv_representation) + ")");
      const int curve = e.add("SURFACE_CURVE(''," + ref(space_curve) + ",(" + ref(pcurve) + "),.PCURVE_S1.)");
      const int vertex = e.add("VERTEX_POINT(''," + ref(points.front()) + ")");
      const int edge = e.add("EDGE_CURVE(''," + ref(vertex) + "," + ref(vertex) + "," + ref(curve) + ",.T.)");
      const int oriented = e.add("ORIENTED_EDGE('',*,*," + ref(edge) + ",.T.)");
      const int loop = e.add("EDGE_LOOP('',(" + ref(oriented) + "))");
      bounds += (k ? "," : "") + ref(e.add(std::string(k == 0 ? "FACE_OUTER_BOUND" : "FACE_BOUND") + "(''," + ref(loop) + ",.T.)"));
    }
    face_ids.push_back(e.add("ADVANCED_FACE(''," + bounds + ")," + ref(surface) + ",.T.)"));
  }
  shell_model(e, pre, face_ids, options);
  return exchange_file(e, options, "trimmed B-spline surfaces fitted to measured points by the bench digitizer");
}

void write_step_faces(const std::string& path, const std::vector<TrimmedFace>& faces, const StepOptions& options) {
  write_file_atomically(path, step_faces_text(faces, options));
}

std::string step_curves_text(const std::vector<BSplineCurve>& curves, const StepOptions& options) {
  Instances e;
  const Preamble pre = preamble(e, options);
  std::string set = "(";
  for (size_t c = 0; c < curves.size(); ++c) {
    const BSplineCurve& curve = curves[c];
    if (curve.degree < 1 || curve.control.size() <= static_cast<size_t>(curve.degree) ||
        curve.knots.size() != curve.control.size() + static_cast<size_t>(curve.degree) + 1) {
      throw std::invalid_argument("cannot write a curve as STEP: its knots, degree and control points disagree");
    }
    std::vector<int> ids;
    for (const Point3& q : curve.control) ids.push_back(point_instance(e, q));
    set += (c ? "," : "") + ref(curve_instance(e, curve.degree, ids, curve.knots));
  }
  set += ")";
  const int curve_set = e.add("GEOMETRIC_CURVE_SET(''," + set + ")");
  const int placement = placement_instance(e);
  const int representation = e.add("GEOMETRICALLY_BOUNDED_WIREFRAME_SHAPE_REPRESENTATION(" + quoted(options.product) + ",(" +
                                   ref(curve_set) + "," + ref(placement) + ")," + ref(pre.context) + ")");
  e.add("SHAPE_DEFINITION_REPRESENTATION(" + ref(pre.shape) + "," + ref(representation) + ")");
  return exchange_file(e, options, "B-spline curves from the bench digitizer");
}

void write_step_curves(const std::string& path, const std::vector<BSplineCurve>& curves, const StepOptions& options) {
  write_file_atomically(path, step_curves_text(curves, options));
}

void write_step(const std::string& path, const BSplineSurface& surface, const StepOptions& options) {
  write_file_atomically(path, step_text(surface, options));
}

}  // namespace dg::host
