// The STEP writer: entity instances numbered in order, product structure, units, geometry, topology.
#include "host/surface/step_writer.h"

#include <cmath>
#include <stdexcept>
#include <vector>

#include "host/surface/atomic_file.h"
#include "host/surface/clamp.h"
#include "host/surface/iges_writer.h"

namespace dg::host {
namespace {

// A STEP string: apostrophes doubled; we write ASCII only.
std::string quoted(const std::string& text) {
  std::string out = "'";
  for (char c : text) {
    if (c == '\'') out += "''";
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

std::string step_text(const BSplineSurface& input, const StepOptions& options) {
  std::string why;
  if (!is_valid(input, &why)) throw std::invalid_argument("cannot write this surface as STEP: " + why);
  const BSplineSurface s = clamp_ends(input);
  Instances e;
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
  auto point = [&](const Point3& p) {
    return e.add("CARTESIAN_POINT('',(" + real(p.x) + "," + real(p.y) + "," + real(p.z) + "))");
  };
  // The surface: control_points_list[i][j], i along u.
  std::vector<int> poles(s.control.size());
  for (int i = 0; i < s.count_u; ++i)
    for (int j = 0; j < s.count_v; ++j) poles[static_cast<size_t>(i * s.count_v + j)] = point(s.at(i, j));
  std::string net = "(";
  for (int i = 0; i < s.count_u; ++i) {
    net += i ? ",(" : "(";
    for (int j = 0; j < s.count_v; ++j) net += (j ? "," : "") + ref(poles[static_cast<size_t>(i * s.count_v + j)]);
    net += ")";
  }
  net += ")";
  std::string ku, mu, kv, mv;
  knots_and_multiplicities(s.knots_u, ku, mu);
  knots_and_multiplicities(s.knots_v, kv, mv);
  const int surface = e.add("B_SPLINE_SURFACE_WITH_KNOTS(''," + std::to_string(s.degree_u) + "," + std::to_string(s.degree_v) + "," + net +
                            ",.UNSPECIFIED.,.F.,.F.,.F.," + mu + "," + mv + "," + ku + "," + kv + ",.UNSPECIFIED.)");
  // The four edges: the first and last rows and columns of the clamped net, with its knots.
  auto curve = [&](bool along_u, int fixed) {
    std::string list = "(";
    const int n = along_u ? s.count_u : s.count_v;
    for (int k = 0; k < n; ++k) {
      const int id = along_u ? poles[static_cast<size_t>(k * s.count_v + fixed)] : poles[static_cast<size_t>(fixed * s.count_v + k)];
      list += (k ? "," : "") + ref(id);
    }
    list += ")";
    return e.add("B_SPLINE_CURVE_WITH_KNOTS(''," + std::to_string(along_u ? s.degree_u : s.degree_v) + "," + list +
                 ",.UNSPECIFIED.,.F.,.F.," + (along_u ? mu : mv) + "," + (along_u ? ku : kv) + ",.UNSPECIFIED.)");
  };
  const int last_u = s.count_u - 1, last_v = s.count_v - 1;
  auto vertex = [&](int i, int j) { return e.add("VERTEX_POINT(''," + ref(poles[static_cast<size_t>(i * s.count_v + j)]) + ")"); };
  const int v00 = vertex(0, 0), v10 = vertex(last_u, 0), v11 = vertex(last_u, last_v), v01 = vertex(0, last_v);
  auto edge = [&](int from, int to, int geometry) {
    return e.add("EDGE_CURVE(''," + ref(from) + "," + ref(to) + "," + ref(geometry) + ",.T.)");
  };
  const int bottom = edge(v00, v10, curve(true, 0));      // v = 0, u increasing
  const int right = edge(v10, v11, curve(false, last_u));  // u = 1, v increasing
  const int top = edge(v01, v11, curve(true, last_v));     // v = 1, u increasing
  const int left = edge(v00, v01, curve(false, 0));        // u = 0, v increasing
  auto oriented = [&](int edge_id, bool same) {
    return e.add("ORIENTED_EDGE('',*,*," + ref(edge_id) + "," + (same ? ".T." : ".F.") + ")");
  };
  // Counter-clockwise in (u, v): along the bottom, up the right, back along the top, down the left.
  const int loop = e.add("EDGE_LOOP('',(" + ref(oriented(bottom, true)) + "," + ref(oriented(right, true)) + "," +
                         ref(oriented(top, false)) + "," + ref(oriented(left, false)) + "))");
  const int bound = e.add("FACE_OUTER_BOUND(''," + ref(loop) + ",.T.)");
  const int face = e.add("ADVANCED_FACE('',(" + ref(bound) + ")," + ref(surface) + ",.T.)");
  const int shell = e.add("OPEN_SHELL('',(" + ref(face) + "))");
  const int model = e.add("SHELL_BASED_SURFACE_MODEL('',(" + ref(shell) + "))");
  const int origin = point(Point3{});
  const int z = e.add("DIRECTION('',(0.,0.,1.))");
  const int x = e.add("DIRECTION('',(1.,0.,0.))");
  const int placement = e.add("AXIS2_PLACEMENT_3D(''," + ref(origin) + "," + ref(z) + "," + ref(x) + ")");
  const int representation = e.add("MANIFOLD_SURFACE_SHAPE_REPRESENTATION(" + quoted(options.product) + ",(" + ref(model) + "," +
                                   ref(placement) + ")," + ref(context) + ")");
  e.add("SHAPE_DEFINITION_REPRESENTATION(" + ref(shape) + "," + ref(representation) + ")");

  std::string out = "ISO-10303-21;\nHEADER;\n";
  out += "FILE_DESCRIPTION(('B-spline surface fitted to measured points by the bench digitizer'),'2;1');\n";
  out += "FILE_NAME(" + quoted(options.file_name) + "," + quoted(options.timestamp) +
         ",('bench digitizer'),('bench digitizer'),'bench digitizer STEP writer 1','bench digitizer','');\n";
  out += "FILE_SCHEMA(('AUTOMOTIVE_DESIGN { 1 0 10303 214 1 1 1 1 }'));\nENDSEC;\nDATA;\n";
  out += e.text();
  out += "ENDSEC;\nEND-ISO-10303-21;\n";
  return out;
}

void write_step(const std::string& path, const BSplineSurface& surface, const StepOptions& options) {
  write_file_atomically(path, step_text(surface, options));
}

}  // namespace dg::host
