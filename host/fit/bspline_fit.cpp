// Banded assembly of the B-spline normal equations and their sparse solution with Eigen.
#include "host/fit/bspline_fit.h"

#include <Eigen/Sparse>
#include <Eigen/SparseCholesky>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <optional>
#include <string>

#include "common/fit/bspline_basis.h"
#include "host/fit/fit_error.h"
#include "host/fit/knot_support.h"
#include "host/geometry/patch_form.h"
#include "host/geometry/vec3.h"
#include "host/parallel/parallel_for.h"

namespace dg::host {

// The normal equations of a net, reduced by the ramps' elimination (x = map y when `eliminate`),
// and their factorization, checked for vanishing pivots.
struct NormalSystem {
  BSplineSurface shape;  // knots, degrees and counts; no control points yet
  Eigen::SparseMatrix<double> map;
  bool eliminate = false;
  Eigen::MatrixXd rhs;   // reduced
  std::unique_ptr<Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>, Eigen::Lower>> solver;
};

namespace {

constexpr int kMaxBasis = fit::kMaxDegree + 1;

// The (degree_u + 1) x (degree_v + 1) basis products at (u, v) into c, row by row, and the first
// control point they weigh: cell.u, cell.v are the knot spans' first control point in u and v.
struct Cell {
  int u, v;
};
Cell tensor_basis(const BSplineSurface& s, double u, double v, double* c) {
  const int su = fit::find_span(s.count_u, s.degree_u, u, s.knots_u.data());
  const int sv = fit::find_span(s.count_v, s.degree_v, v, s.knots_v.data());
  double nu[kMaxBasis], nv[kMaxBasis];
  fit::bspline_basis(su, s.degree_u, u, s.knots_u.data(), nu);
  fit::bspline_basis(sv, s.degree_v, v, s.knots_v.data(), nv);
  const int pv = s.degree_v + 1;
  for (int a = 0; a <= s.degree_u; ++a) {
    for (int b = 0; b < pv; ++b) c[a * pv + b] = nu[a] * nv[b];
  }
  return {su - s.degree_u, sv - s.degree_v};
}

// The coefficients' weights in S(u, v) as a vector over the whole net.
void node_basis(const BSplineSurface& s, double u, double v, Eigen::VectorXd& b) {
  double c[kMaxBasis * kMaxBasis];
  const Cell cell = tensor_basis(s, u, v, c);
  const int pv = s.degree_v + 1;
  b.setZero();
  for (int a = 0; a <= s.degree_u; ++a) {
    for (int e = 0; e < pv; ++e) b((cell.u + a) * s.count_v + cell.v + e) = c[a * pv + e];
  }
}

// Every row and column of control points needs points in its support, or nothing determines it.
// The points' distinct sites along the direction (SiteIndex) stand for them: a few hundred lines, not
// a million points.
void check_support(const std::vector<double>& knots, int degree, int count, const std::vector<double>& sites,
                   bool along_u, const Parameters& params) {
  std::vector<int> hits(static_cast<size_t>(count), 0);
  for (const double t : sites) {
    const int span = fit::find_span(count, degree, t, knots.data());
    for (int k = span - degree; k <= span; ++k) ++hits[k];
  }
  for (int i = 0; i < count; ++i) {
    if (hits[i] > 0) continue;
    const char* axis = along_u ? "u" : "v";
    std::string where = std::string(axis) + " " + std::to_string(knots[i]) + ".." + std::to_string(knots[i + degree + 1]);
    if (params.kind == Parameterization::kTableXy) {
      const double lo = along_u ? params.x_min : params.y_min, hi = along_u ? params.x_max : params.y_max;
      where = std::string(along_u ? "x " : "y ") + std::to_string(lo + (hi - lo) * knots[i]) + ".." +
              std::to_string(lo + (hi - lo) * knots[i + degree + 1]) + " mm";
    }
    throw FitError("not enough points for " + std::to_string(count) + " control points along " + axis +
                   ": no point in the support of control point " + std::to_string(i) + " (" + where + ")");
  }
}

// The lower band of a symmetric matrix: entry (row, row - d) for d = 0..width.
// The normal equations' band, its copy as a sparse matrix and the Cholesky factor take about 40
// bytes per band entry; a net that needs more than 80 % of the machine's memory is refused before
// the allocation (a 1000 x 1000 net died with a bare std::bad_alloc).
void check_memory(int unknowns, int width, int count_u, int count_v) {
  const double needed = 40.0 * unknowns * (width + 1.0);
  const double pages = static_cast<double>(sysconf(_SC_PHYS_PAGES)), page = static_cast<double>(sysconf(_SC_PAGESIZE));
  const double available = pages > 0 && page > 0 ? pages * page : 0;
  if (available > 0 && needed > 0.8 * available) {
    char text[200];
    std::snprintf(text, sizeof text,
                  "a %d x %d net needs about %.1f GB for its normal equations and their factor; this machine has %.1f GB: "
                  "use fewer control points",
                  count_u, count_v, needed / 1e9, available / 1e9);
    throw FitError(text);
  }
}

class Band {
 public:
  Band(int n, int width) : n_(n), width_(width), data_(static_cast<size_t>(n) * (width + 1), 0.0) {}
  double& operator()(int row, int col) { return data_[static_cast<size_t>(row) * (width_ + 1) + (row - col)]; }
  Eigen::SparseMatrix<double> lower() const {
    std::vector<Eigen::Triplet<double>> entries;
    entries.reserve(data_.size() / 2);
    for (int row = 0; row < n_; ++row) {
      for (int d = 0; d <= width_ && d <= row; ++d) {
        const double value = data_[static_cast<size_t>(row) * (width_ + 1) + d];
        if (value != 0.0) entries.emplace_back(row, row - d, value);
      }
    }
    Eigen::SparseMatrix<double> m(n_, n_);
    m.setFromTriplets(entries.begin(), entries.end());
    return m;
  }

 private:
  int n_, width_;
  std::vector<double> data_;
};

// One direction's x = T y for its ramp points: free control points map to themselves, a ramp point
// to its span's two ends. Rows: control points; columns: the free ones, in order.
struct DirectionMap {
  int free_count = 0;
  std::vector<std::vector<std::pair<int, double>>> rows;
};

DirectionMap ramp_map(int count, const std::vector<RampPoint>& ramps) {
  DirectionMap m;
  std::vector<int> column(static_cast<size_t>(count), -1);
  std::vector<const RampPoint*> ramp_of(static_cast<size_t>(count), nullptr);
  for (const RampPoint& r : ramps) ramp_of[static_cast<size_t>(r.index)] = &r;
  for (int i = 0; i < count; ++i) {
    if (!ramp_of[static_cast<size_t>(i)]) column[static_cast<size_t>(i)] = m.free_count++;
  }
  m.rows.resize(static_cast<size_t>(count));
  for (int i = 0; i < count; ++i) {
    const RampPoint* r = ramp_of[static_cast<size_t>(i)];
    if (!r) {
      m.rows[static_cast<size_t>(i)] = {{column[static_cast<size_t>(i)], 1.0}};
    } else {
      m.rows[static_cast<size_t>(i)] = {{column[static_cast<size_t>(r->left)], 1.0 - r->weight_right},
                                        {column[static_cast<size_t>(r->right)], r->weight_right}};
    }
  }
  return m;
}

// The tensor product of the two directions' maps, on unknown k = i * count_v + j.
Eigen::SparseMatrix<double> elimination_map(const DirectionMap& u, const DirectionMap& v) {
  std::vector<Eigen::Triplet<double>> entries;
  const int count_v = static_cast<int>(v.rows.size());
  for (size_t i = 0; i < u.rows.size(); ++i) {
    for (size_t j = 0; j < v.rows.size(); ++j) {
      for (const auto& [a, wa] : u.rows[i]) {
        for (const auto& [b, wb] : v.rows[j]) {
          entries.emplace_back(static_cast<int>(i) * count_v + static_cast<int>(j), a * v.free_count + b, wa * wb);
        }
      }
    }
  }
  Eigen::SparseMatrix<double> t(static_cast<int>(u.rows.size()) * count_v, u.free_count * v.free_count);
  t.setFromTriplets(entries.begin(), entries.end());
  return t;
}


// The membrane that places a region net's outside control points (LsqSpec::fill_outside): for every
// pair of neighbouring control points with at least one outside, lambda (P_a - P_b)^2. Only the
// outside points lack data, so it decides them and leaves the fitted ones where the data put them.
void add_membrane(Band& band, const BSplineSurface& s, const std::vector<char>& outside) {
  double largest = 0;
  const int n = s.count_u * s.count_v;
  for (int k = 0; k < n; ++k) largest = std::max(largest, band(k, k));
  const double lambda = 1e-8 * (largest > 0 ? largest : 1.0);
  auto edge = [&](int a, int b) {
    if (!outside[static_cast<size_t>(a)] && !outside[static_cast<size_t>(b)]) return;
    band(a, a) += lambda;
    band(b, b) += lambda;
    band(std::max(a, b), std::min(a, b)) -= lambda;
  };
  for (int i = 0; i < s.count_u; ++i) {
    for (int j = 0; j < s.count_v; ++j) {
      const int k = i * s.count_v + j;
      if (i + 1 < s.count_u) edge(k, k + s.count_v);
      if (j + 1 < s.count_v) edge(k, k + 1);
    }
  }
}


// The net of `spec`, checked against points whose distinct sites `sites` holds (`point_count` of
// them): degrees, knots and counts, no control points yet; for a region's net (fill_outside) the
// control points left outside into *outside. Throws FitError where the points cannot determine it.
// The net the spec asks for, without control points: its degrees, knots and counts.
BSplineSurface net_shape(const LsqSpec& spec) {
  BSplineSurface s;
  s.degree_u = spec.degree_u;
  s.degree_v = spec.degree_v;
  s.knots_u = spec.knots_u;
  s.knots_v = spec.knots_v;
  s.count_u = static_cast<int>(spec.knots_u.size()) - spec.degree_u - 1;
  s.count_v = static_cast<int>(spec.knots_v.size()) - spec.degree_v - 1;
  if (spec.degree_u < 1 || spec.degree_v < 1 || spec.degree_u > fit::kMaxDegree || spec.degree_v > fit::kMaxDegree) {
    throw FitError("degree must be 1.." + std::to_string(fit::kMaxDegree));
  }
  if (s.count_u <= s.degree_u || s.count_v <= s.degree_v) throw FitError("a net needs at least degree + 1 control points per direction");
  return s;
}

// Throws the reason when `point_count` points at `sites` cannot determine the net; fills
// `outside` with the control points no point measures when the spec fills them.
void check_net(const LsqSpec& spec, const BSplineSurface& s, size_t point_count, const SiteIndex& sites,
               const Parameters& params, std::vector<char>* outside) {
  const size_t unknowns = static_cast<size_t>(s.count_u) * s.count_v;
  size_t fitted = unknowns;
  outside->clear();
  if (spec.fill_outside) {
    *outside = outside_control_points(s.knots_u, s.degree_u, s.knots_v, s.degree_v, sites, spec.outside_below);
    fitted = static_cast<size_t>(std::count(outside->begin(), outside->end(), 0));
  }
  if (point_count < fitted) {
    throw FitError("not enough points: " + std::to_string(point_count) + " points for " + std::to_string(s.count_u) +
                   " x " + std::to_string(s.count_v) + " control points");
  }
  check_memory(static_cast<int>(unknowns), s.degree_u * s.count_v + s.degree_v, s.count_u, s.count_v);
  if (!spec.fill_outside) {
    check_support(s.knots_u, s.degree_u, s.count_u, sites.sites_u(), true, params);
    check_support(s.knots_v, s.degree_v, s.count_v, sites.sites_v(), false, params);
  }
  const std::string problem = net_support_problem(s.knots_u, s.degree_u, s.knots_v, s.degree_v, sites, params,
                                                  spec.fill_outside ? outside : nullptr);
  if (!problem.empty()) throw FitError("the points cannot determine this net: " + problem);
}

// Every point of a cell (a pair of knot spans) touches the same m unknowns, so each cell sums its
// points' products in a small dense block of its own, contiguous and vectorisable, and the blocks
// go into the band at the end. The blocks take about as much memory as the band for nets of
// 40 x 40 and less for larger ones. A block: the lower triangle of the m x m products, then m x 3
// right-hand sides.
size_t block_size(const BSplineSurface& s) {
  const size_t m = static_cast<size_t>(s.degree_u + 1) * (s.degree_v + 1);
  return m * (m + 1) / 2 + m * 3;
}
size_t blocks_total(const BSplineSurface& s) {
  return static_cast<size_t>(s.count_u - s.degree_u) * (s.count_v - s.degree_v) * block_size(s);
}

// Each group's sums of its points' products, cell by cell: point k belongs to group group_of(k)
// in [0, groups), or to none when that is negative.
template <typename GroupOf>
std::vector<std::vector<double>> cell_sums(const std::vector<Point3>& points, const Parameters& params,
                                           const std::vector<double>* weights, const BSplineSurface& s, int groups,
                                           GroupOf group_of) {
  const bool height_field = params.kind == Parameterization::kTableXy;
  const int rhs_count = height_field ? 1 : 3;
  const int m = (s.degree_u + 1) * (s.degree_v + 1);
  const int cells_v = s.count_v - s.degree_v;
  const size_t size = block_size(s), total = blocks_total(s) * static_cast<size_t>(groups);
  // Large scans: fixed slices of the points, each summed into blocks of its own on whichever core
  // takes it, then added in slice order, so the sums do not depend on the number of threads. At
  // most 8 slices, 64 MB of blocks, and one slice per 64k points (a small scan is one slice).
  const size_t slices = std::clamp<size_t>(
      std::min<size_t>(points.size() / 65536, (size_t{64} << 20) / (total * sizeof(double) + 1)), 1, 8);
  std::vector<std::vector<double>> slice_blocks(slices);
  parallel_for(slices, [&](size_t first, size_t last, unsigned) {
    for (size_t slice = first; slice < last; ++slice) {
      std::vector<double>& blocks = slice_blocks[slice];
      blocks.assign(total, 0.0);
      const size_t begin = points.size() * slice / slices, end = points.size() * (slice + 1) / slices;
      for (size_t k = begin; k < end; ++k) {
        const int group = group_of(k);
        if (group < 0) continue;
        const double w = weights ? (*weights)[k] : 1.0;
        double c[kMaxBasis * kMaxBasis];
        const Cell cell = tensor_basis(s, params.uv[k].u, params.uv[k].v, c);
        const Point3& p = points[k];
        const double value[3] = {height_field ? p.z : p.x, p.y, p.z};
        double* row = &blocks[static_cast<size_t>(group) * (total / static_cast<size_t>(groups)) +
                              (static_cast<size_t>(cell.u) * cells_v + cell.v) * size];
        double* block_rhs = row + static_cast<size_t>(m) * (m + 1) / 2;
        for (int a = 0; a < m; ++a) {
          const double wc = w * c[a];
          for (int b = 0; b <= a; ++b) row[b] += wc * c[b];
          row += a + 1;
          for (int r = 0; r < rhs_count; ++r) block_rhs[a * 3 + r] += wc * value[r];
        }
      }
    }
  }, 1);
  std::vector<double>& blocks = slice_blocks[0];
  for (size_t slice = 1; slice < slices; ++slice) {
    for (size_t e = 0; e < total; ++e) blocks[e] += slice_blocks[slice][e];
  }
  std::vector<std::vector<double>> sums(static_cast<size_t>(groups));
  for (int g = 0; g < groups; ++g) {
    const auto from = blocks.begin() + static_cast<std::ptrdiff_t>(static_cast<size_t>(g) * (total / static_cast<size_t>(groups)));
    sums[static_cast<size_t>(g)].assign(from, from + static_cast<std::ptrdiff_t>(total / static_cast<size_t>(groups)));
  }
  return sums;
}

// The normal equations of `shape` from its cells' sums, reduced by the ramps' elimination and
// factorized.
NormalSystem solve_system(const BSplineSurface& shape, const std::vector<double>& blocks, const std::vector<char>& outside,
                          bool fill_outside, const SiteIndex& sites, bool height_field) {
  NormalSystem system;
  system.shape = shape;
  const BSplineSurface& s = system.shape;
  const int rhs_count = height_field ? 1 : 3;
  const int n = s.count_u * s.count_v;
  const int width = s.degree_u * s.count_v + s.degree_v;
  Band band(n, width);
  Eigen::MatrixXd rhs = Eigen::MatrixXd::Zero(n, rhs_count);
  const int pu = s.degree_u + 1, pv = s.degree_v + 1, m = pu * pv;
  const int cells_u = s.count_u - s.degree_u, cells_v = s.count_v - s.degree_v;
  const size_t size = block_size(s);
  // Block unknown a of cell (cu, cv) is control point (cu + a / pv, cv + a % pv); indices ascend with
  // a, so (a, b <= a) lies in the lower band.
  for (int cu = 0; cu < cells_u; ++cu) {
    for (int cv = 0; cv < cells_v; ++cv) {
      const double* row = &blocks[(static_cast<size_t>(cu) * cells_v + cv) * size];
      const double* block_rhs = row + static_cast<size_t>(m) * (m + 1) / 2;
      int index[kMaxBasis * kMaxBasis];
      for (int a = 0; a < m; ++a) index[a] = (cu + a / pv) * s.count_v + (cv + a % pv);
      for (int a = 0; a < m; ++a) {
        for (int b = 0; b <= a; ++b) band(index[a], index[b]) += row[b];
        row += a + 1;
        for (int r = 0; r < rhs_count; ++r) rhs(index[a], r) += block_rhs[a * 3 + r];
      }
    }
  }
  if (fill_outside && std::count(outside.begin(), outside.end(), 1) > 0) add_membrane(band, s, outside);
  // No regularization: a net the points do not determine is refused, not smoothed into shape. The
  // pivots of the factorization say whether it is determined; one far below the largest (relative
  // to the rounding of a double over the matrix's size) means a control point the data leaves free.
  // Steps' ramps (knot_support.h): control points no point measures are eliminated, x = T y.
  const std::vector<RampPoint> ramps_u = ramp_points(s.knots_u, s.degree_u, sites.sites_u());
  const std::vector<RampPoint> ramps_v = ramp_points(s.knots_v, s.degree_v, sites.sites_v());
  const bool eliminate = !ramps_u.empty() || !ramps_v.empty();
  Eigen::SparseMatrix<double> normal = band.lower(), map;
  Eigen::MatrixXd reduced_rhs = rhs;
  if (eliminate) {
    map = elimination_map(ramp_map(s.count_u, ramps_u), ramp_map(s.count_v, ramps_v));
    const Eigen::SparseMatrix<double> full = normal.selfadjointView<Eigen::Lower>();
    const Eigen::SparseMatrix<double> reduced = map.transpose() * full * map;
    normal = reduced.triangularView<Eigen::Lower>();
    reduced_rhs = map.transpose() * rhs;
  }
  system.solver = std::make_unique<Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>, Eigen::Lower>>(normal);
  auto& solver = *system.solver;
  if (solver.info() != Eigen::Success) throw FitError("the normal equations are singular: the points do not determine the net");
  const Eigen::VectorXd pivots = solver.vectorD();
  const double largest = pivots.cwiseAbs().maxCoeff();
  for (int k = 0; k < pivots.size(); ++k) {
    if (!(std::fabs(pivots(k)) > 1e-12 * largest)) {
      const int i = k / s.count_v, j = k % s.count_v;
      throw FitError("the points do not determine control point (" + std::to_string(i) + ", " + std::to_string(j) +
                     ") of the " + std::to_string(s.count_u) + " x " + std::to_string(s.count_v) +
                     " net: too few points under its support (a hole in the scan?); use fewer control points");
    }
  }
  system.map = std::move(map);
  system.eliminate = eliminate;
  system.rhs = std::move(reduced_rhs);
  return system;
}

// The net's checks on every point's sites (the spec's index where it indexes these parameters, or
// one built here), then the system from its sums: `make_sums` is called once the checks have
// passed, so a net that the points cannot determine costs no pass over them.
template <typename MakeSums>
NormalSystem checked_system(const std::vector<Point3>& points, const Parameters& params, const LsqSpec& spec,
                            const BSplineSurface& shape, MakeSums make_sums) {
  std::optional<SiteIndex> own_index;
  const SiteIndex& sites =
      spec.sites && &spec.sites->uv() == &params.uv && !spec.sites->subset() ? *spec.sites : own_index.emplace(params.uv, spec.fill_outside);
  std::vector<char> outside;
  check_net(spec, shape, points.size(), sites, params, &outside);
  return solve_system(shape, make_sums(), outside, spec.fill_outside, sites, params.kind == Parameterization::kTableXy);
}

// The points' sums in one group.
std::vector<double> all_sums(const std::vector<Point3>& points, const Parameters& params, const std::vector<double>* weights,
                             const BSplineSurface& shape) {
  return std::move(cell_sums(points, params, weights, shape, 1, [](size_t) { return 0; })[0]);
}

NormalSystem assemble(const std::vector<Point3>& points, const Parameters& params, const std::vector<double>* weights,
                      const LsqSpec& spec) {
  const BSplineSurface shape = net_shape(spec);
  return checked_system(points, params, spec, shape, [&] { return all_sums(points, params, weights, shape); });
}

// The system's solution as the net's control points.
BSplineSurface solved_surface(const NormalSystem& system, const Parameters& params) {
  BSplineSurface s = system.shape;
  const bool height_field = params.kind == Parameterization::kTableXy;
  const size_t unknowns = static_cast<size_t>(s.count_u) * s.count_v;
  auto& solver = *system.solver;
  const Eigen::MatrixXd reduced_solution = solver.solve(system.rhs);
  if (solver.info() != Eigen::Success || !reduced_solution.allFinite()) throw FitError("solving the normal equations failed");
  const Eigen::MatrixXd solution = system.eliminate ? Eigen::MatrixXd(system.map * reduced_solution) : reduced_solution;
  s.control.resize(unknowns);
  for (int i = 0; i < s.count_u; ++i) {
    for (int j = 0; j < s.count_v; ++j) {
      const int k = i * s.count_v + j;
      Point3& q = s.at(i, j);
      if (height_field) {
        q.x = params.x_min + (params.x_max - params.x_min) * greville(s.knots_u, s.degree_u, i);
        q.y = params.y_min + (params.y_max - params.y_min) * greville(s.knots_v, s.degree_v, j);
        q.z = solution(k, 0);
      } else {
        q = Point3{solution(k, 0), solution(k, 1), solution(k, 2)};
      }
    }
  }
  return s;
}

}  // namespace

BSplineSurface fit_least_squares(const std::vector<Point3>& points, const Parameters& params,
                                 const std::vector<double>* weights, const LsqSpec& spec) {
  return solved_surface(assemble(points, params, weights, spec), params);
}

namespace {

// The system's surface, kept with the system for its uncertainty.
LeastSquaresFit kept_fit(NormalSystem system, const Parameters& params, const std::vector<double>* weights) {
  LeastSquaresFit fit;
  auto shared = std::make_shared<NormalSystem>(std::move(system));
  fit.surface = solved_surface(*shared, params);
  fit.system = std::move(shared);
  fit.weighted = weights != nullptr;
  return fit;
}

}  // namespace

LeastSquaresFit fit_least_squares_kept(const std::vector<Point3>& points, const Parameters& params,
                                       const std::vector<double>* weights, const LsqSpec& spec) {
  return kept_fit(assemble(points, params, weights, spec), params, weights);
}

namespace {

// Each fold's checks, before any sums: a net its remaining points cannot determine is its answer
// (in `refits`); for the others, the control points left outside (a region's net).
struct FoldChecks {
  std::vector<std::vector<char>> outside;
  std::vector<char> ready;
  bool any() const { return std::count(ready.begin(), ready.end(), 1) > 0; }
};
FoldChecks check_folds(const std::vector<Point3>& points, const Parameters& params, const LsqSpec& spec,
                       const BSplineSurface& shape, const std::vector<int>& fold,
                       const std::vector<const SiteIndex*>& kept_sites, std::vector<FoldRefit>& refits) {
  const size_t folds = kept_sites.size();
  std::vector<size_t> held(folds, 0);
  for (int f : fold) {
    if (f >= 0 && static_cast<size_t>(f) < folds) ++held[static_cast<size_t>(f)];
  }
  FoldChecks checks;
  checks.outside.resize(folds);
  checks.ready.assign(folds, 0);
  for (size_t f = 0; f < folds; ++f) {
    try {
      check_net(spec, shape, points.size() - held[f], *kept_sites[f], params, &checks.outside[f]);
      checks.ready[f] = 1;
    } catch (const FitError& e) {
      refits[f].error = e.what();
    }
  }
  return checks;
}

// The refits of the folds that passed their checks, each from the other groups' sums (group f + 1
// holds fold f's points, group 0 those of no fold), or from a pass of its own when `sums` is empty.
void solve_refits(const std::vector<Point3>& points, const Parameters& params, const std::vector<double>* weights,
                  const LsqSpec& spec, const BSplineSurface& shape, const std::vector<int>& fold,
                  const std::vector<const SiteIndex*>& kept_sites, const FoldChecks& checks,
                  const std::vector<std::vector<double>>& sums, std::vector<FoldRefit>& refits) {
  const bool height_field = params.kind == Parameterization::kTableXy;
  // Each fold on whichever core is free: a fold writes only its own refit (five solves of a 32 x 32
  // net took 20 ms one after another).
  parallel_for(kept_sites.size(), [&](size_t first, size_t last, unsigned) {
    for (size_t f = first; f < last; ++f) {
      if (!checks.ready[f]) continue;
      std::vector<double> blocks;
      if (!sums.empty()) {
        blocks.assign(sums[0].size(), 0.0);
        for (size_t g = 0; g < sums.size(); ++g) {
          if (g == f + 1) continue;
          for (size_t e = 0; e < blocks.size(); ++e) blocks[e] += sums[g][e];
        }
      } else {
        const int left_out = static_cast<int>(f);
        blocks = std::move(
            cell_sums(points, params, weights, shape, 1, [&](size_t k) { return fold[k] == left_out ? -1 : 0; })[0]);
      }
      try {
        const NormalSystem system =
            solve_system(shape, blocks, checks.outside[f], spec.fill_outside, *kept_sites[f], height_field);
        refits[f].surface = solved_surface(system, params);
      } catch (const FitError& e) {
        refits[f].error = e.what();
      }
    }
  }, 1);
}

// The sums of every group (fold f + 1, or 0 for the points of no fold) in one pass, or nothing
// when they would take more than `one_pass_bytes`.
std::vector<std::vector<double>> group_sums(const std::vector<Point3>& points, const Parameters& params,
                                            const std::vector<double>* weights, const BSplineSurface& shape,
                                            const std::vector<int>& fold, int folds, size_t one_pass_bytes) {
  const int groups = folds + 1;
  if (blocks_total(shape) * static_cast<size_t>(groups) * sizeof(double) > one_pass_bytes) return {};
  return cell_sums(points, params, weights, shape, groups, [&](size_t k) { return std::max(fold[k], -1) + 1; });
}

}  // namespace

std::vector<FoldRefit> fit_least_squares_by_folds(const std::vector<Point3>& points, const Parameters& params,
                                                  const std::vector<double>* weights, const LsqSpec& spec,
                                                  const std::vector<int>& fold,
                                                  const std::vector<const SiteIndex*>& kept_sites,
                                                  size_t one_pass_bytes) {
  const int folds = static_cast<int>(kept_sites.size());
  std::vector<FoldRefit> refits(static_cast<size_t>(folds));
  // Every fold refits the same net.
  BSplineSurface shape;
  try {
    shape = net_shape(spec);
  } catch (const FitError& e) {
    for (FoldRefit& refit : refits) refit.error = e.what();
    return refits;
  }
  const FoldChecks checks = check_folds(points, params, spec, shape, fold, kept_sites, refits);
  if (!checks.any()) return refits;
  solve_refits(points, params, weights, spec, shape, fold, kept_sites, checks,
               group_sums(points, params, weights, shape, fold, folds, one_pass_bytes), refits);
  return refits;
}

FoldedFit fit_least_squares_with_folds(const std::vector<Point3>& points, const Parameters& params,
                                       const std::vector<double>* weights, const LsqSpec& spec,
                                       const std::vector<int>& fold, const std::vector<const SiteIndex*>& kept_sites,
                                       size_t one_pass_bytes) {
  const int folds = static_cast<int>(kept_sites.size());
  const BSplineSurface shape = net_shape(spec);
  // Each group's sums, kept for the refits once the checks have let the pass be made.
  std::vector<std::vector<double>> sums;
  FoldedFit out;
  out.fit = kept_fit(checked_system(points, params, spec, shape, [&] {
    sums = group_sums(points, params, weights, shape, fold, folds, one_pass_bytes);
    if (sums.empty()) return all_sums(points, params, weights, shape);
    // The whole fit's sums are the groups' together.
    std::vector<double> all(sums[0].size(), 0.0);
    for (const std::vector<double>& group : sums) {
      for (size_t e = 0; e < all.size(); ++e) all[e] += group[e];
    }
    return all;
  }), params, weights);
  out.refits.resize(static_cast<size_t>(folds));
  const FoldChecks checks = check_folds(points, params, spec, shape, fold, kept_sites, out.refits);
  solve_refits(points, params, weights, spec, shape, fold, kept_sites, checks, sums, out.refits);
  return out;
}

namespace {

// The least-squares problem whose solution `surface` is: its degrees and knots.
LsqSpec spec_of(const BSplineSurface& surface, bool fill_outside) {
  LsqSpec spec;
  spec.degree_u = surface.degree_u;
  spec.degree_v = surface.degree_v;
  spec.knots_u = surface.knots_u;
  spec.knots_v = surface.knots_v;
  spec.fill_outside = fill_outside;
  return spec;
}

// u(u, v) on a grid x grid of the parameter domain: `variance(b)` is Var S for the basis vector b
// (in units of the points' variance when `weights` is null). Nodes `counts` rejects hold kOffFace
// and enter neither max nor mean.
template <typename Variance>
SurfaceUncertainty uncertainty_on_grid(const BSplineSurface& s, double sigma_mm, int grid, bool weighted,
                                       const std::function<bool(double, double)>* counts, Variance variance) {
  SurfaceUncertainty out;
  out.computed = true;
  out.sigma_mm = sigma_mm;
  out.rows = out.cols = std::max(2, grid);
  out.u_mm.assign(static_cast<size_t>(out.rows) * out.cols, 0.0);
  // With weights 1 / sigma_i^2 the variance is the coefficients' covariance itself; without, it
  // is scaled by the points' common variance.
  const double scale = weighted ? 1.0 : sigma_mm * sigma_mm;
  // Each node is a solve of its own: the rows on every core, then summed in order.
  std::vector<char> on_face(out.u_mm.size(), 1);
  parallel_for(static_cast<size_t>(out.rows), [&](size_t first, size_t last, unsigned) {
    Eigen::VectorXd b(s.count_u * s.count_v);
    for (size_t r = first; r < last; ++r) {
      for (int c = 0; c < out.cols; ++c) {
        const size_t node = r * static_cast<size_t>(out.cols) + static_cast<size_t>(c);
        const double u = static_cast<double>(c) / (out.cols - 1), v = static_cast<double>(r) / (out.rows - 1);
        if (counts && !(*counts)(u, v)) {
          out.u_mm[node] = kOffFace;
          on_face[node] = 0;
          continue;
        }
        node_basis(s, u, v, b);
        out.u_mm[node] = std::sqrt(std::max(scale * variance(b), 0.0));
      }
    }
  }, 1);
  double sum = 0;
  size_t counted = 0;
  for (size_t node = 0; node < out.u_mm.size(); ++node) {
    if (!on_face[node]) continue;
    out.max_mm = std::max(out.max_mm, out.u_mm[node]);
    sum += out.u_mm[node];
    ++counted;
  }
  out.mean_mm = counted > 0 ? sum / static_cast<double>(counted) : 0.0;
  return out;
}

}  // namespace

namespace {

SurfaceUncertainty uncertainty_of(const NormalSystem& system, bool weighted, double sigma_mm, int grid) {
  // Var S(u, v) = b^T Cov(x) b with x = T y and Cov(y) = scale (T^T A T)^-1.
  return uncertainty_on_grid(system.shape, sigma_mm, grid, weighted, nullptr, [&](const Eigen::VectorXd& b) {
    const Eigen::VectorXd reduced = system.eliminate ? Eigen::VectorXd(system.map.transpose() * b) : b;
    return reduced.dot(system.solver->solve(reduced));
  });
}

}  // namespace

SurfaceUncertainty fit_uncertainty(const std::vector<Point3>& points, const Parameters& params,
                                   const std::vector<double>* weights, const BSplineSurface& surface, double sigma_mm,
                                   int grid) {
  return uncertainty_of(assemble(points, params, weights, spec_of(surface, false)), weights != nullptr, sigma_mm, grid);
}

SurfaceUncertainty fit_uncertainty(const LeastSquaresFit& fit, double sigma_mm, int grid) {
  return uncertainty_of(*fit.system, fit.weighted, sigma_mm, grid);
}

SurfaceUncertainty region_fit_uncertainty(const std::vector<Point3>& points, const Parameters& params,
                                          const std::vector<double>* weights, const BSplineSurface& surface,
                                          double sigma_mm, int grid, const std::function<bool(double, double)>& counts) {
  const NormalSystem system = assemble(points, params, weights, spec_of(surface, true));
  const BSplineSurface& s = system.shape;
  if (system.eliminate) throw FitError("a region's net has no ramps to eliminate");
  // Each point's basis values and the unknowns they touch, once.
  const int pu = s.degree_u + 1, pv = s.degree_v + 1, m = pu * pv;
  std::vector<int> first(points.size());
  std::vector<double> basis(points.size() * static_cast<size_t>(m));
  for (size_t k = 0; k < points.size(); ++k) {
    const Cell cell = tensor_basis(s, params.uv[k].u, params.uv[k].v, &basis[k * static_cast<size_t>(m)]);
    first[k] = cell.u * s.count_v + cell.v;
  }
  // Var S = b^T K^-1 (C^T W C) K^-1 b = sum over points of w_k (c_k . y)^2 with y = K^-1 b.
  return uncertainty_on_grid(s, sigma_mm, grid, weights != nullptr, &counts, [&](const Eigen::VectorXd& b) {
    const Eigen::VectorXd y = system.solver->solve(b);
    double variance = 0;
    for (size_t k = 0; k < points.size(); ++k) {
      double dot = 0;
      const double* row = &basis[k * static_cast<size_t>(m)];
      for (int a = 0; a < pu; ++a)
        for (int e = 0; e < pv; ++e) dot += row[a * pv + e] * y(first[k] + a * s.count_v + e);
      variance += (weights ? (*weights)[k] : 1.0) * dot * dot;
    }
    return variance;
  });
}

std::vector<double> parameter_distances(const BSplineSurface& surface, const std::vector<Point3>& points,
                                        const Parameters& params) {
  std::vector<double> d(points.size());
  with_fast_form(surface, points.size(), [&](const auto& form) {
    parallel_for(points.size(), [&](size_t begin, size_t end, unsigned) {
      for (size_t k = begin; k < end; ++k) d[k] = norm(points[k] - form.evaluate(params.uv[k].u, params.uv[k].v));
    }, 4096);
  });
  return d;
}

}  // namespace dg::host
