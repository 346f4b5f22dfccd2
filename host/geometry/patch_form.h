// A B-spline surface as one polynomial patch per pair of knot spans, for evaluating it millions of times.
#pragma once
#include <vector>

#include "host/geometry/bspline_surface.h"

namespace dg::host {

// Over each pair of knot spans the surface is a polynomial of degree (p, q) in the spans' local
// coordinates (t, w) on [0, 1]. Kept in that power form, a point costs a span lookup in each
// direction and a nested Horner sum, where the B-spline form works out the basis again (a dozen
// divisions for a bicubic) and sums the control points at every point: on a million points the
// evaluations are about 2.5 times faster. The values agree with BSplineSurface::evaluate to
// rounding (parts in 1e15 of the coordinates). Building one costs about a microsecond a patch, so
// it pays from some thousands of evaluations. Parameters outside the domain extend the first or
// last patch, as BSplineSurface::evaluate does.
class PatchForm {
 public:
  explicit PatchForm(const BSplineSurface& surface);

  double u_min() const { return u_.ends.front(); }
  double u_max() const { return u_.ends.back(); }
  double v_min() const { return v_.ends.front(); }
  double v_max() const { return v_.ends.back(); }

  Point3 evaluate(double u, double v) const;
  // The point and its first partial derivatives.
  void evaluate(double u, double v, Point3& s, Point3& su, Point3& sv) const;

  // One direction's non-empty spans, and a table that finds the span of a parameter in a step or two.
  struct Spans {
    std::vector<double> ends;  // the distinct knots from the domain's start to its end
    std::vector<int> knot;     // per span, the index of its first knot in the knot vector
    std::vector<int> first;    // per table cell, the last span starting at or before the cell
    double scale = 0;          // table cells per unit of parameter
    int find(double x) const;  // the span holding x (the first or last one beyond the ends)
  };

 private:
  const double* patch(int i, int j) const { return &coefficients_[(static_cast<size_t>(i) * spans_v_ + j) * per_patch_]; }
  template <int P, int Q>
  void sum(int i, int j, double t, double w, Point3& s, Point3* st, Point3* sw) const;

  int degree_u_ = 3, degree_v_ = 3;
  Spans u_, v_;
  size_t spans_v_ = 0, per_patch_ = 0;
  // Per patch, for a = 0..p and b = 0..q in turn, the x, y and z coefficients of t^a w^b.
  std::vector<double> coefficients_;
};

// Whether evaluating `surface` at `evaluations` places is worth building its PatchForm first.
bool patch_form_pays(const BSplineSurface& surface, size_t evaluations);

// use(form) with the surface's PatchForm when `evaluations` pay for building it, else use(surface):
// `use` takes either (a generic lambda), and both give the same values to rounding.
template <typename Use>
decltype(auto) with_fast_form(const BSplineSurface& surface, size_t evaluations, Use&& use) {
  if (patch_form_pays(surface, evaluations)) {
    const PatchForm form(surface);
    return use(form);
  }
  return use(surface);
}

}  // namespace dg::host
