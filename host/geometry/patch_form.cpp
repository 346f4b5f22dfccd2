// Power-form patches of a B-spline surface: built by sampling each span's basis, evaluated by Horner sums.
#include "host/geometry/patch_form.h"

#include <algorithm>
#include <cmath>

#include "common/fit/bspline_basis.h"
#include "host/geometry/vec3.h"

namespace dg::host {

namespace {

constexpr int kMax = fit::kMaxDegree + 1;

// The inverse of the Vandermonde matrix V[q][a] = (q / degree)^a, by Gauss-Jordan elimination with
// partial pivoting: the basis sampled at those nodes gives its power coefficients as inverse x values.
void inverse_vandermonde(int degree, double inverse[kMax][kMax]) {
  const int n = degree + 1;
  double m[kMax][2 * kMax] = {};
  for (int q = 0; q < n; ++q) {
    const double t = static_cast<double>(q) / degree;
    double power = 1;
    for (int a = 0; a < n; ++a, power *= t) m[q][a] = power;
    m[q][n + q] = 1;
  }
  for (int col = 0; col < n; ++col) {
    int pivot = col;
    for (int r = col + 1; r < n; ++r) {
      if (std::fabs(m[r][col]) > std::fabs(m[pivot][col])) pivot = r;
    }
    for (int c = 0; c < 2 * n; ++c) std::swap(m[col][c], m[pivot][c]);
    const double d = m[col][col];
    for (int c = 0; c < 2 * n; ++c) m[col][c] /= d;
    for (int r = 0; r < n; ++r) {
      if (r == col || m[r][col] == 0) continue;
      const double f = m[r][col];
      for (int c = 0; c < 2 * n; ++c) m[r][c] -= f * m[col][c];
    }
  }
  for (int a = 0; a < n; ++a) {
    for (int q = 0; q < n; ++q) inverse[a][q] = m[a][n + q];
  }
}

PatchForm::Spans spans_of(const std::vector<double>& knots, int degree, int count) {
  PatchForm::Spans s;
  for (int k = degree; k < count; ++k) {
    if (knots[static_cast<size_t>(k) + 1] > knots[static_cast<size_t>(k)]) {
      s.knot.push_back(k);
      s.ends.push_back(knots[static_cast<size_t>(k)]);
    }
  }
  s.ends.push_back(knots[static_cast<size_t>(count)]);
  const int spans = static_cast<int>(s.knot.size());
  const int cells = 4 * spans;
  s.scale = cells / (s.ends.back() - s.ends.front());
  s.first.resize(static_cast<size_t>(cells) + 1);
  int span = 0;
  for (int c = 0; c <= cells; ++c) {
    const double start = s.ends.front() + c / s.scale;
    while (span + 1 < spans && s.ends[static_cast<size_t>(span) + 1] <= start) ++span;
    s.first[static_cast<size_t>(c)] = span;
  }
  return s;
}

// One span's basis in power form: c[r][a] is basis function r's (span - degree + r) coefficient of
// t^a on the span.
struct SpanPolynomials {
  double c[kMax][kMax];
};

SpanPolynomials span_polynomials(const std::vector<double>& knots, int degree, int knot, double lo, double hi,
                                 const double inverse[kMax][kMax]) {
  SpanPolynomials out{};
  double value[kMax][kMax];  // value[r][q]: basis r at node q
  for (int q = 0; q <= degree; ++q) {
    double n[kMax];
    const double t = static_cast<double>(q) / degree;
    fit::bspline_basis(knot, degree, q == degree ? hi : lo + t * (hi - lo), knots.data(), n);
    for (int r = 0; r <= degree; ++r) value[r][q] = n[r];
  }
  for (int r = 0; r <= degree; ++r) {
    for (int a = 0; a <= degree; ++a) {
      double c = 0;
      for (int q = 0; q <= degree; ++q) c += inverse[a][q] * value[r][q];
      out.c[r][a] = c;
    }
  }
  return out;
}

}  // namespace

int PatchForm::Spans::find(double x) const {
  const int spans = static_cast<int>(knot.size());
  const double cell = (x - ends.front()) * scale;
  const int last_cell = static_cast<int>(first.size()) - 1;
  const int c = cell >= 0 ? (cell < last_cell ? static_cast<int>(cell) : last_cell) : 0;
  int s = first[static_cast<size_t>(c)];
  while (s + 1 < spans && ends[static_cast<size_t>(s) + 1] <= x) ++s;
  while (s > 0 && x < ends[static_cast<size_t>(s)]) --s;  // rounding of the cell only
  return s;
}

PatchForm::PatchForm(const BSplineSurface& surface)
    : degree_u_(surface.degree_u), degree_v_(surface.degree_v),
      u_(spans_of(surface.knots_u, surface.degree_u, surface.count_u)),
      v_(spans_of(surface.knots_v, surface.degree_v, surface.count_v)) {
  const int p = degree_u_, q = degree_v_;
  spans_v_ = v_.knot.size();
  per_patch_ = static_cast<size_t>((p + 1) * (q + 1) * 3);
  coefficients_.assign(u_.knot.size() * spans_v_ * per_patch_, 0.0);
  double inverse_u[kMax][kMax], inverse_v[kMax][kMax];
  inverse_vandermonde(p, inverse_u);
  inverse_vandermonde(q, inverse_v);
  std::vector<SpanPolynomials> along_v(spans_v_);
  for (size_t j = 0; j < spans_v_; ++j) along_v[j] = span_polynomials(surface.knots_v, q, v_.knot[j], v_.ends[j], v_.ends[j + 1], inverse_v);
  for (size_t i = 0; i < u_.knot.size(); ++i) {
    const SpanPolynomials along_u = span_polynomials(surface.knots_u, p, u_.knot[i], u_.ends[i], u_.ends[i + 1], inverse_u);
    const auto& cu = along_u.c;
    for (size_t j = 0; j < spans_v_; ++j) {
      const auto& cv = along_v[j].c;
      double* c = &coefficients_[(i * spans_v_ + j) * per_patch_];
      for (int r = 0; r <= p; ++r) {
        for (int s = 0; s <= q; ++s) {
          const Point3& point = surface.at(u_.knot[i] - p + r, v_.knot[j] - q + s);
          for (int a = 0; a <= p; ++a) {
            for (int b = 0; b <= q; ++b) {
              const double weight = cu[r][a] * cv[s][b];
              double* k = c + (a * (q + 1) + b) * 3;
              k[0] += weight * point.x;
              k[1] += weight * point.y;
              k[2] += weight * point.z;
            }
          }
        }
      }
    }
  }
}

// The patch's point at (t, w), and its derivatives along t and w when asked. P and Q are the
// degrees when known at compile time (the bicubic every fit makes: the loops unroll), else 0.
template <int P, int Q>
void PatchForm::sum(int i, int j, double t, double w, Point3& s, Point3* st, Point3* sw) const {
  const int p = P > 0 ? P : degree_u_, q = Q > 0 ? Q : degree_v_;
  const double* c = patch(i, j);
  Point3 value, along_t, along_w;
  for (int a = p; a >= 0; --a) {
    const double* row = c + a * (q + 1) * 3;
    Point3 r{row[q * 3], row[q * 3 + 1], row[q * 3 + 2]}, dr;
    for (int b = q - 1; b >= 0; --b) {
      if (sw) dr = w * dr + r;
      r = w * r + Point3{row[b * 3], row[b * 3 + 1], row[b * 3 + 2]};
    }
    if (st) along_t = t * along_t + value;
    value = t * value + r;
    if (sw) along_w = t * along_w + dr;
  }
  s = value;
  if (st) *st = along_t;
  if (sw) *sw = along_w;
}

Point3 PatchForm::evaluate(double u, double v) const {
  const int i = u_.find(u), j = v_.find(v);
  const double t = (u - u_.ends[static_cast<size_t>(i)]) / (u_.ends[static_cast<size_t>(i) + 1] - u_.ends[static_cast<size_t>(i)]);
  const double w = (v - v_.ends[static_cast<size_t>(j)]) / (v_.ends[static_cast<size_t>(j) + 1] - v_.ends[static_cast<size_t>(j)]);
  Point3 s;
  if (degree_u_ == 3 && degree_v_ == 3) {
    sum<3, 3>(i, j, t, w, s, nullptr, nullptr);
  } else {
    sum<0, 0>(i, j, t, w, s, nullptr, nullptr);
  }
  return s;
}

void PatchForm::evaluate(double u, double v, Point3& s, Point3& su, Point3& sv) const {
  const int i = u_.find(u), j = v_.find(v);
  const double width_u = u_.ends[static_cast<size_t>(i) + 1] - u_.ends[static_cast<size_t>(i)];
  const double width_v = v_.ends[static_cast<size_t>(j) + 1] - v_.ends[static_cast<size_t>(j)];
  const double t = (u - u_.ends[static_cast<size_t>(i)]) / width_u, w = (v - v_.ends[static_cast<size_t>(j)]) / width_v;
  Point3 st, sw;
  if (degree_u_ == 3 && degree_v_ == 3) {
    sum<3, 3>(i, j, t, w, s, &st, &sw);
  } else {
    sum<0, 0>(i, j, t, w, s, &st, &sw);
  }
  su = (1.0 / width_u) * st;
  sv = (1.0 / width_v) * sw;
}

bool patch_form_pays(const BSplineSurface& surface, size_t evaluations) {
  // A patch costs about as much to build as a few dozen evaluations save.
  const size_t patches = static_cast<size_t>(std::max(surface.count_u - surface.degree_u, 1)) *
                         static_cast<size_t>(std::max(surface.count_v - surface.degree_v, 1));
  return evaluations >= 64 * patches;
}

}  // namespace dg::host
