// Cutting a face's grid mesh at its trim loops, so an STL of trimmed faces ends on the trims
// instead of in a staircase of whole triangles that overlap or miss the neighbouring face.
#include "host/geometry/face_mesh.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <tuple>

namespace dg::host {

namespace {

double cross(const Point2& o, const Point2& a, const Point2& b) {
  return (a.x - o.x) * (b.y - o.y) - (a.y - o.y) * (b.x - o.x);
}

// Where edge p-q meets loop segment r-s: t along p-q, w along r-s. Half-open in both, so a
// crossing exactly at a vertex is counted on one edge and one segment only; `closed_end` also
// takes the segment's end (a segment that ends on the domain's edge, whose next one is left out).
// Loop corners lie on a triangle's edge only on the domain's edge (the loops are moved off the
// grid lines elsewhere), so the segment's ends are matched within 1e-9 of its length.
bool crossing(const Point2& p, const Point2& q, const Point2& r, const Point2& s, bool closed_end, double* t, double* w) {
  const double d = (q.x - p.x) * (s.y - r.y) - (q.y - p.y) * (s.x - r.x);
  if (d == 0) return false;
  *t = ((r.x - p.x) * (s.y - r.y) - (r.y - p.y) * (s.x - r.x)) / d;
  *w = ((r.x - p.x) * (q.y - p.y) - (r.y - p.y) * (q.x - p.x)) / d;
  constexpr double kEnd = 1e-9;
  if (*w > -kEnd && *w < 0) *w = 0;
  if (closed_end && *w >= 1 - kEnd && *w <= 1 + kEnd) *w = 0.5 * (1 - kEnd) + 0.5;  // inside [0, 1)
  return *t >= 0 && *t < 1 && *w >= 0 && *w < 1;
}

bool strictly_inside_triangle(const Point2& p, const Point2& a, const Point2& b, const Point2& c) {
  const double s = cross(a, b, c) > 0 ? 1 : -1;
  return s * cross(a, b, p) > 0 && s * cross(b, c, p) > 0 && s * cross(c, a, p) > 0;
}

// Ear clipping of a simple polygon (counter-clockwise); indices into `polygon`. False when no ear
// is found (a polygon that is not simple).
bool triangulate(const std::vector<Point2>& polygon, std::vector<std::array<size_t, 3>>& triangles) {
  std::vector<size_t> left(polygon.size());
  for (size_t i = 0; i < left.size(); ++i) left[i] = i;
  while (left.size() > 3) {
    bool clipped = false;
    for (size_t k = 0, n = left.size(); k < n && !clipped; ++k) {
      const size_t i0 = left[(k + n - 1) % n], i1 = left[k], i2 = left[(k + 1) % n];
      const Point2 &a = polygon[i0], &b = polygon[i1], &c = polygon[i2];
      if (cross(a, b, c) <= 0) continue;  // reflex or flat: not an ear
      bool empty = true;
      for (size_t m : left) {
        if (m != i0 && m != i1 && m != i2 && strictly_inside_triangle(polygon[m], a, b, c)) {
          empty = false;
          break;
        }
      }
      if (!empty) continue;
      triangles.push_back({i0, i1, i2});
      left.erase(left.begin() + static_cast<std::ptrdiff_t>(k));
      clipped = true;
    }
    if (!clipped) return false;
  }
  if (left.size() == 3 && cross(polygon[left[0]], polygon[left[1]], polygon[left[2]]) > 0) {
    triangles.push_back({left[0], left[1], left[2]});
  }
  return true;
}

// A vertex of the cut mesh: a grid vertex, a loop crossing a grid edge, or a loop corner.
using VertexKey = std::tuple<int, size_t, size_t, size_t, size_t>;

// Loops are moved by this much (mm) before they cut: region loops run through the scan's half
// steps, which are grid lines of the mesh, and a loop corner exactly on a triangle's edge or a loop
// along one would make the cut's topology ambiguous. A tenth of a micrometre is far below any
// gauge's step and the fit's uncertainty, yet some 25 steps of an STL's 32-bit float at 40 mm, so
// the thin triangles it leaves beside grid lines keep their area in the file. Every face moves its
// loops alike, so faces that share a boundary still share it.
constexpr double kShiftX_mm = 0.7e-4, kShiftY_mm = 0.3e-4;

class FaceCutter {
 public:
  FaceCutter(const TrimmedFace& face, const Mesh& grid, int nu, int nv, Mesh& out)
      : face_(face), grid_(grid), nu_(nu), nv_(nv), out_(out), grid_index_(grid.vertices.size(), UINT32_MAX) {
    x0_ = grid.vertices[0].x;
    y0_ = grid.vertices[0].y;
    x1_ = grid.vertices[static_cast<size_t>(nu - 1) * nv].x;
    y1_ = grid.vertices[static_cast<size_t>(nv - 1)].y;
    dx_ = (x1_ - x0_) / (nu - 1);
    dy_ = (y1_ - y0_) / (nv - 1);
    // A corner on the edge of the domain stays on it (moved along it only), so the loop still
    // meets the edge there.
    shifted_.loops = face.loops;
    for (TrimLoop& loop : shifted_.loops) {
      for (Point2& p : loop) {
        p = Point2{on_x_edge(p.x) ? p.x : p.x + kShiftX_mm, on_y_edge(p.y) ? p.y : p.y + kShiftY_mm};
      }
    }
    index_segments();
  }

  void cut(const std::array<uint32_t, 3>& t) {
    Node corner[3];
    for (size_t k = 0; k < 3; ++k) corner[k] = Node{xy(t[k]), grid_key(t[k])};
    const Point2 centre{(corner[0].at.x + corner[1].at.x + corner[2].at.x) / 3, (corner[0].at.y + corner[1].at.y + corner[2].at.y) / 3};
    const double orientation = cross(corner[0].at, corner[1].at, corner[2].at) > 0 ? 1 : -1;
    // Where the loops cross the triangle's edges, in order round it; entering or leaving.
    std::vector<Crossing> crossings;
    for (size_t e = 0; e < 3; ++e) {
      const Point2 &p = corner[e].at, &q = corner[(e + 1) % 3].at;
      for (size_t s : segments_near(centre)) {
        const Segment& g = segments_[s];
        double te = 0, ws = 0;
        if (!crossing(p, q, g.a, g.b, g.ends_on_edge, &te, &ws)) continue;
        const Point2 point{p.x + te * (q.x - p.x), p.y + te * (q.y - p.y)};
        // Entering when the segment runs towards the inner side of the edge.
        const double inward = orientation * ((q.x - p.x) * (g.b.y - g.a.y) - (q.y - p.y) * (g.b.x - g.a.x));
        crossings.push_back({static_cast<double>(e) + te, ws, s, inward > 0, Node{point, crossing_key(t, e, s)}});
      }
    }
    if (crossings.empty()) {
      keep_whole_if_inside(t, centre);
      return;
    }
    std::sort(crossings.begin(), crossings.end(), [](const Crossing& a, const Crossing& b) { return a.at < b.at; });
    // The triangle's outline with the crossings in it, then split along each loop's run inside.
    std::vector<Node> outline;
    std::vector<size_t> outline_of(crossings.size());
    for (size_t e = 0, c = 0; e < 3; ++e) {
      outline.push_back(corner[e]);
      for (; c < crossings.size() && crossings[c].at < static_cast<double>(e + 1); ++c) {
        outline_of[c] = outline.size();
        outline.push_back(crossings[c].node);
      }
    }
    std::vector<std::vector<size_t>> pieces{std::vector<size_t>(outline.size())};
    for (size_t i = 0; i < outline.size(); ++i) pieces[0][i] = i;
    std::vector<Node> nodes = outline;  // the outline's nodes, then the loops' corners inside
    size_t splits = 0;
    for (size_t c = 0; c < crossings.size(); ++c) {
      if (!crossings[c].entering) continue;
      size_t exit = 0;
      std::vector<size_t> run;
      if (!walk_inside(crossings, c, corner, nodes, run, &exit) || !split(pieces, outline_of[c], outline_of[exit], run)) {
        keep_whole_if_inside(t, centre);
        return;
      }
      ++splits;
    }
    // Every piece triangulated before any is kept, so a piece that cannot be leaves no hole.
    std::vector<std::array<Node, 3>> parts;
    if (2 * splits != crossings.size() || !triangulate_pieces(pieces, nodes, parts)) {
      keep_whole_if_inside(t, centre);
      return;
    }
    for (const std::array<Node, 3>& part : parts) keep(part, orientation > 0);
  }

 private:
  struct Segment {
    size_t loop, index;  // from loop vertex `index` to the next
    Point2 a, b;
    bool ends_on_edge;   // b lies on the edge of the grid's domain
  };
  struct Node {
    Point2 at;
    VertexKey key;
  };
  struct Crossing {
    double at;       // edge index + position along the edge
    double along;    // position along the loop's segment
    size_t segment;
    bool entering;   // the loop runs into the triangle here
    Node node;
  };

  Point2 xy(uint32_t v) const { return Point2{grid_.vertices[v].x, grid_.vertices[v].y}; }

  size_t cell_i(double x) const {
    const double f = dx_ != 0 ? (x - x0_) / dx_ : 0;
    return static_cast<size_t>(std::clamp(f, 0.0, static_cast<double>(nu_ - 2)));
  }
  size_t cell_j(double y) const {
    const double f = dy_ != 0 ? (y - y0_) / dy_ : 0;
    return static_cast<size_t>(std::clamp(f, 0.0, static_cast<double>(nv_ - 2)));
  }

  bool on_x_edge(double x) const { return std::fabs(x - x0_) <= 1e-9 || std::fabs(x - x1_) <= 1e-9; }
  bool on_y_edge(double y) const { return std::fabs(y - y0_) <= 1e-9 || std::fabs(y - y1_) <= 1e-9; }
  bool on_domain_edge(const Point2& p) const { return on_x_edge(p.x) || on_y_edge(p.y); }
  // A segment along the edge of the grid's domain cuts nothing inside it.
  bool along_domain_edge(const Point2& a, const Point2& b) const {
    auto same = [](double u, double v) { return std::fabs(u - v) <= 1e-9; };
    return (same(a.x, x0_) && same(b.x, x0_)) || (same(a.x, x1_) && same(b.x, x1_)) ||
           (same(a.y, y0_) && same(b.y, y0_)) || (same(a.y, y1_) && same(b.y, y1_));
  }

  // Every moved loop segment listed in each grid cell its bounding box touches (one cell of margin).
  void index_segments() {
    cells_.assign(static_cast<size_t>(nu_ - 1) * (nv_ - 1), {});
    segment_of_.assign(face_.loops.size(), {});
    for (size_t k = 0; k < face_.loops.size(); ++k) {
      const TrimLoop& loop = shifted_.loops[k];
      segment_of_[k].assign(loop.size(), kNone);
      for (size_t i = 0; i < loop.size(); ++i) {
        const size_t next = (i + 1) % loop.size();
        if (along_domain_edge(face_.loops[k][i], face_.loops[k][next])) continue;
        segment_of_[k][i] = segments_.size();
        // A segment that ends on the domain's edge leaves there: the segment after it (along the
        // edge) is left out, so this one counts its end as a crossing.
        const Segment s{k, i, loop[i], loop[next], on_domain_edge(face_.loops[k][next])};
        const size_t ia = cell_i(s.a.x), ib = cell_i(s.b.x), ja = cell_j(s.a.y), jb = cell_j(s.b.y);
        const size_t i0 = std::min(ia, ib) > 0 ? std::min(ia, ib) - 1 : 0, i1 = std::min(std::max(ia, ib) + 1, static_cast<size_t>(nu_ - 2));
        const size_t j0 = std::min(ja, jb) > 0 ? std::min(ja, jb) - 1 : 0, j1 = std::min(std::max(ja, jb) + 1, static_cast<size_t>(nv_ - 2));
        for (size_t ci = i0; ci <= i1; ++ci)
          for (size_t cj = j0; cj <= j1; ++cj) cells_[ci * static_cast<size_t>(nv_ - 1) + cj].push_back(segments_.size());
        segments_.push_back(s);
      }
    }
  }
  const std::vector<size_t>& segments_near(const Point2& p) const {
    return cells_[cell_i(p.x) * static_cast<size_t>(nv_ - 1) + cell_j(p.y)];
  }

  // From the entering crossing `from`, follows its loop through the triangle: the loop's corners
  // inside become nodes (their indices in `run`), and *exit is the crossing where it leaves.
  bool walk_inside(const std::vector<Crossing>& crossings, size_t from, const Node* corner, std::vector<Node>& nodes,
                   std::vector<size_t>& run, size_t* exit) const {
    const Segment& first = segments_[crossings[from].segment];
    const TrimLoop& loop = shifted_.loops[first.loop];
    size_t segment = crossings[from].segment;
    double after = crossings[from].along;
    for (size_t steps = 0; steps <= loop.size(); ++steps) {
      // The nearest leaving crossing further along this segment ends the run.
      double best = HUGE_VAL;
      for (size_t c = 0; c < crossings.size(); ++c) {
        if (crossings[c].segment == segment && !crossings[c].entering && crossings[c].along > after && crossings[c].along < best) {
          best = crossings[c].along;
          *exit = c;
        }
      }
      if (best != HUGE_VAL) return true;
      // Else the segment ends inside: its end is a corner of the loop in the triangle.
      const size_t v = (segments_[segment].index + 1) % loop.size();
      if (!strictly_inside_triangle(loop[v], corner[0].at, corner[1].at, corner[2].at)) return false;
      run.push_back(nodes.size());
      nodes.push_back(Node{loop[v], VertexKey{2, first.loop, v, 0, 0}});
      // On along the loop (a segment on the domain's edge has none: the run cannot go on).
      segment = segment_of_[first.loop][v];
      if (segment == kNone) return false;
      after = -1;
    }
    return false;
  }

  // Splits the piece whose outline holds both `entry` and `exit` along entry, run..., exit.
  static bool split(std::vector<std::vector<size_t>>& pieces, size_t entry, size_t exit, const std::vector<size_t>& run) {
    for (size_t p = 0; p < pieces.size(); ++p) {
      const std::vector<size_t>& piece = pieces[p];
      const auto i = std::find(piece.begin(), piece.end(), entry), j = std::find(piece.begin(), piece.end(), exit);
      if (i == piece.end() || j == piece.end()) continue;
      const size_t a = static_cast<size_t>(i - piece.begin()), b = static_cast<size_t>(j - piece.begin()), n = piece.size();
      std::vector<size_t> one, other;
      for (size_t k = a;; k = (k + 1) % n) {  // entry round to exit, then back along the run
        one.push_back(piece[k]);
        if (k == b) break;
      }
      one.insert(one.end(), run.rbegin(), run.rend());
      for (size_t k = b;; k = (k + 1) % n) {  // exit round to entry, then along the run
        other.push_back(piece[k]);
        if (k == a) break;
      }
      other.insert(other.end(), run.begin(), run.end());
      pieces[p] = std::move(one);
      pieces.push_back(std::move(other));
      return true;
    }
    return false;
  }

  VertexKey grid_key(uint32_t v) const { return VertexKey{0, v, 0, 0, 0}; }
  VertexKey crossing_key(const std::array<uint32_t, 3>& t, size_t edge, size_t segment) const {
    const uint32_t p = t[edge], q = t[(edge + 1) % 3];
    return VertexKey{1, std::min(p, q), std::max(p, q), segments_[segment].loop, segments_[segment].index};
  }

  uint32_t vertex(const VertexKey& key, const Point2& at) {
    if (std::get<0>(key) == 0) {
      const size_t g = std::get<1>(key);
      if (grid_index_[g] == UINT32_MAX) {
        grid_index_[g] = static_cast<uint32_t>(out_.vertices.size());
        out_.vertices.push_back(grid_.vertices[g]);
      }
      return grid_index_[g];
    }
    const auto found = made_.find(key);
    if (found != made_.end()) return found->second;
    const uint32_t index = static_cast<uint32_t>(out_.vertices.size());
    out_.vertices.push_back(point_above(face_.surface, at.x, at.y));
    made_.emplace(key, index);
    return index;
  }

  void keep_whole(const std::array<uint32_t, 3>& t) {
    std::array<uint32_t, 3> kept{};
    for (size_t k = 0; k < 3; ++k) kept[k] = vertex(grid_key(t[k]), xy(t[k]));
    out_.triangles.push_back(kept);
  }

  // Each piece's triangles inside the face, as nodes; false when a piece cannot be triangulated.
  bool triangulate_pieces(const std::vector<std::vector<size_t>>& pieces, const std::vector<Node>& nodes,
                          std::vector<std::array<Node, 3>>& parts) const {
    for (const std::vector<size_t>& piece : pieces) {
      TrimLoop polygon;
      std::vector<const Node*> at;
      for (size_t k : piece) {
        // A loop through a corner of the triangle puts the corner in twice: keep it once.
        if (!polygon.empty() && std::fabs(polygon.back().x - nodes[k].at.x) + std::fabs(polygon.back().y - nodes[k].at.y) <= 1e-12) continue;
        polygon.push_back(nodes[k].at);
        at.push_back(&nodes[k]);
      }
      while (polygon.size() > 3 && std::fabs(polygon.back().x - polygon.front().x) + std::fabs(polygon.back().y - polygon.front().y) <= 1e-12) {
        polygon.pop_back();
        at.pop_back();
      }
      if (polygon.size() < 3) continue;
      if (twice_signed_area(polygon) < 0) {
        std::reverse(polygon.begin(), polygon.end());
        std::reverse(at.begin(), at.end());
      }
      std::vector<std::array<size_t, 3>> triangles;
      if (!triangulate(polygon, triangles)) return false;
      for (const auto& tri : triangles) {
        const Point2 &a = polygon[tri[0]], &b = polygon[tri[1]], &c = polygon[tri[2]];
        if (inside_face(shifted_, (a.x + b.x + c.x) / 3, (a.y + b.y + c.y) / 3)) parts.push_back({*at[tri[0]], *at[tri[1]], *at[tri[2]]});
      }
    }
    return true;
  }

  // Keeps a part (counter-clockwise in XY), wound as the grid's triangles are.
  void keep(const std::array<Node, 3>& part, bool grid_counter_clockwise) {
    std::array<uint32_t, 3> v{vertex(part[0].key, part[0].at), vertex(part[1].key, part[1].at), vertex(part[2].key, part[2].at)};
    if (!grid_counter_clockwise) std::swap(v[1], v[2]);
    out_.triangles.push_back(v);
  }

  // The rule for a triangle the cut cannot untangle: whole when its centre is inside.
  void keep_whole_if_inside(const std::array<uint32_t, 3>& t, const Point2& centre) {
    if (inside_face(shifted_, centre.x, centre.y)) keep_whole(t);
  }

  const TrimmedFace& face_;
  TrimmedFace shifted_;  // the loops, moved (kShiftX_mm, kShiftY_mm)
  const Mesh& grid_;
  int nu_, nv_;
  Mesh& out_;
  std::vector<uint32_t> grid_index_;
  std::map<VertexKey, uint32_t> made_;
  double x0_ = 0, y0_ = 0, x1_ = 0, y1_ = 0, dx_ = 0, dy_ = 0;
  std::vector<Segment> segments_;
  std::vector<std::vector<size_t>> segment_of_;  // [loop][vertex]: the segment from that vertex (kNone: left out)
  static constexpr size_t kNone = SIZE_MAX;
  std::vector<std::vector<size_t>> cells_;
};

}  // namespace

void append_face_mesh(const TrimmedFace& face, const Mesh& grid, int nu, int nv, Mesh& out) {
  FaceCutter cutter(face, grid, nu, nv, out);
  for (const auto& t : grid.triangles) cutter.cut(t);
}

}  // namespace dg::host
