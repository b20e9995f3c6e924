// Untangling folded patches of a remesh by Tutte re-embedding on the input's tangent plane or
// on its own flattening, else by relaxation on the input; then vertex by vertex. See untangle.h.
#include "meshlift/untangle.h"

#include <Eigen/SparseCholesky>
#include <Eigen/SparseCore>
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <optional>
#include <queue>
#include <span>
#include <stdexcept>
#include <unordered_map>
#include <utility>
#include <vector>

#include "meshlift/surface_fit.h"
#include "adjacency.h"
#include "parallel.h"
#include "vec3.h"

namespace meshlift {
namespace {

using Vec = vec3::Vec3;
using vec3::at;
using vec3::cross;
using vec3::dot;
using vec3::sub;
using vec3::face_normal;
using vec3::unit;

/// One linear function of a 2-D offset d: g·d + h.
struct Linear2 {
  double g[2], h;
  double at(const double d[2]) const { return g[0] * d[0] + g[1] * d[1] + h; }
};

/// The offset d with |d_0|, |d_1| <= box that maximizes min_f (g_f·d + h_f), and that minimum:
/// a linear program in (d, t) whose optimum lies where three of its constraints are tight,
/// t = g_f·d + h_f for three faces, for two and a side of the box, or for one and a corner. With
/// a vertex's valence of faces there are a few hundred such points; all are tried.
std::pair<std::array<double, 2>, double> max_min_offset(const std::vector<Linear2>& faces, double box) {
  auto worst = [&](const double d[2]) {
    double t = faces[0].at(d);
    for (const Linear2& f : faces) t = std::min(t, f.at(d));
    return t;
  };
  std::array<double, 2> best{0, 0};
  double best_t = worst(best.data());
  auto consider = [&](double u, double w) {
    if (!(std::abs(u) <= box * (1 + 1e-12) && std::abs(w) <= box * (1 + 1e-12))) return;
    const double d[2] = {u, w};
    const double t = worst(d);
    if (t > best_t) best_t = t, best = {u, w};
  };
  const std::size_t k = faces.size();
  for (double u : {-box, box})
    for (double w : {-box, box}) consider(u, w);
  for (std::size_t i = 0; i < k; ++i)
    for (std::size_t j = i + 1; j < k; ++j) {
      // g_i·d + h_i = g_j·d + h_j with one coordinate on a side of the box.
      const double a = faces[i].g[0] - faces[j].g[0], b = faces[i].g[1] - faces[j].g[1], c = faces[j].h - faces[i].h;
      for (double side : {-box, box}) {
        if (b != 0) consider(side, (c - a * side) / b);
        if (a != 0) consider((c - b * side) / a, side);
      }
      // ... and with a third face.
      for (std::size_t l = j + 1; l < k; ++l) {
        const double a2 = faces[i].g[0] - faces[l].g[0], b2 = faces[i].g[1] - faces[l].g[1], c2 = faces[l].h - faces[i].h;
        const double det = a * b2 - b * a2;
        if (det != 0) consider((c * b2 - b * c2) / det, (a * c2 - c * a2) / det);
      }
    }
  return {best, best_t};
}


/// Tutte's barycentric map (Tutte 1963; Floater 1997) with uniform weights: every inner vertex at
/// the mean of its neighbours (`adjacency`), the others fixed. The system is the graph Laplacian
/// restricted to the inner vertices, symmetric positive definite; its right-hand side, one row per
/// inner vertex, sums the fixed neighbours' values. `index_of(w)`: w's row among `inner`, or kNone
/// for a fixed vertex, whose value `add_fixed(row, w)` adds to `rhs` (false if w has none: then
/// no system). Returns the factorized system (check info()).
template <class IndexOf, class AddFixed>
std::optional<Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>>> tutte_system(const Adjacency& adjacency,
                                                                            std::span<const std::uint32_t> inner,
                                                                            IndexOf&& index_of, AddFixed&& add_fixed) {
  std::vector<Eigen::Triplet<double>> entries;
  for (std::uint32_t i = 0; i < inner.size(); ++i) {
    const std::uint32_t v = inner[i], first = adjacency.neighbour_offsets[v], end = adjacency.neighbour_offsets[v + 1];
    entries.emplace_back(i, i, static_cast<double>(end - first));
    for (std::uint32_t k = first; k < end; ++k) {
      const std::uint32_t w = adjacency.neighbours[k];
      if (const std::uint32_t j = index_of(w); j != kNone) entries.emplace_back(i, j, -1.0);
      else if (!add_fixed(i, w)) return std::nullopt;
    }
  }
  const auto n = static_cast<Eigen::Index>(inner.size());
  Eigen::SparseMatrix<double> laplacian(n, n);
  laplacian.setFromTriplets(entries.begin(), entries.end());
  return std::optional<Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>>>(std::in_place, laplacian);
}

/// The input's own flattening near a patch, for patches that no plane suits (across a thin
/// part's sharp edge the input's normals turn by up to 180°, and a plane projection folds the
/// rim): the input faces with a corner within `radius` of a surface point along the input's edges
/// (Dijkstra), connected to its face through shared vertices, if they form a topological disk,
/// mapped into the unit disk by Tutte's barycentric map with the boundary on the circle by arc
/// length (a convex boundary: the map is an embedding, Floater 1997). Points of the chart's faces
/// go into the disk and back by their barycentric coordinates (to_surface() searches the faces:
/// the chart serves the rare patches that two lifts could not untangle).
class InputChart {
 public:
  /// One chart at a time of `input`, rebuilt by build(): its per-vertex and per-face marks are
  /// arrays over the input, made once and told apart from an earlier build's by a stamp.
  InputChart(const TriangleMesh& input, const Adjacency& adjacency)
      : input_(input),
        adjacency_(adjacency),
        settled_(input.vertex_count(), 0),
        vertex_stamp_(input.vertex_count(), 0),
        local_vertex_(input.vertex_count()),
        face_stamp_(input.face_count(), 0),
        local_face_(input.face_count()) {}

  /// False if the faces found are not a disk (a tube, a handle, a pinched boundary) or too many.
  bool build(const SurfacePoint& from, double radius) {
    constexpr std::size_t kMaxFaces = 20000;  // far above what a patch of 8 rings needs
    if (++stamp_ == 0) {  // after 2^32 builds: every mark is from an earlier one
      std::fill(settled_.begin(), settled_.end(), 0);
      std::fill(vertex_stamp_.begin(), vertex_stamp_.end(), 0);
      std::fill(face_stamp_.begin(), face_stamp_.end(), 0);
      stamp_ = 1;
    }
    const TriangleMesh& input = input_;
    const Adjacency& adjacency = adjacency_;
    const std::vector<std::uint32_t>& t = input.triangles;
    const std::uint32_t seed = from.face;
    // Distances along the input's edges from the point `from` (Dijkstra, to `radius`): a ball
    // along the surface, which follows a thin part around its edge where a ball in space would
    // take in its far side.
    std::size_t settled = 0;
    using Entry = std::pair<double, std::uint32_t>;
    std::priority_queue<Entry, std::vector<Entry>, std::greater<Entry>> queue;
    for (int i = 0; i < 3; ++i) {
      const std::uint32_t v = t[3 * std::size_t{seed} + i];
      const Vec d = sub(at(input.positions, v), from.point);
      queue.emplace(std::sqrt(dot(d, d)), v);
    }
    while (!queue.empty()) {
      const auto [d, v] = queue.top();
      queue.pop();
      if (d > radius || settled_[v] == stamp_) continue;
      settled_[v] = stamp_;  // within the radius along the edges
      if (++settled > kMaxFaces) return false;
      for (std::uint32_t k = adjacency.neighbour_offsets[v]; k < adjacency.neighbour_offsets[v + 1]; ++k) {
        const std::uint32_t w = adjacency.neighbours[k];
        if (settled_[w] == stamp_) continue;
        const Vec e = sub(at(input.positions, w), at(input.positions, v));
        queue.emplace(d + std::sqrt(dot(e, e)), w);
      }
    }
    auto within = [&](std::uint32_t f) {  // a corner within the radius (input faces may be larger than it)
      for (int i = 0; i < 3; ++i)
        if (settled_[t[3 * std::size_t{f} + i]] == stamp_) return true;
      return false;
    };
    if (!within(seed)) return false;
    faces_ = {seed};
    face_stamp_[seed] = stamp_, local_face_[seed] = 0;
    for (std::size_t i = 0; i < faces_.size(); ++i)
      for (int k = 0; k < 3; ++k) {
        const std::uint32_t v = t[3 * std::size_t{faces_[i]} + k];
        for (std::uint32_t j = adjacency.face_offsets[v]; j < adjacency.face_offsets[v + 1]; ++j) {
          const std::uint32_t f = adjacency.faces[j];
          if (face_stamp_[f] == stamp_ || !within(f)) continue;
          if (faces_.size() == kMaxFaces) return false;
          face_stamp_[f] = stamp_, local_face_[f] = static_cast<std::uint32_t>(faces_.size());
          faces_.push_back(f);
        }
      }
    // Local vertices, edges and the boundary (directed as its face runs along it).
    vertices_.clear();
    // Each face side (face i's side k is 3 i + k) under its undirected edge's key, sorted: a run
    // of one is a boundary side, of two an inner edge, of more a non-manifold edge.
    std::vector<std::pair<std::uint64_t, std::uint32_t>> sides;
    sides.reserve(3 * faces_.size());
    for (std::size_t i = 0; i < faces_.size(); ++i)
      for (int k = 0; k < 3; ++k) {
        const std::uint32_t a = t[3 * std::size_t{faces_[i]} + k], b = t[3 * std::size_t{faces_[i]} + (k + 1) % 3];
        if (vertex_stamp_[a] != stamp_) {
          vertex_stamp_[a] = stamp_, local_vertex_[a] = static_cast<std::uint32_t>(vertices_.size());
          vertices_.push_back(a);
        }
        sides.emplace_back(std::uint64_t{std::min(a, b)} << 32 | std::max(a, b), static_cast<std::uint32_t>(3 * i + k));
      }
    std::sort(sides.begin(), sides.end());
    std::vector<std::uint8_t> on_boundary(sides.size(), 0);
    std::size_t edges = 0;
    for (std::size_t i = 0, j = 0; i < sides.size(); i = j, ++edges) {
      while (j < sides.size() && sides[j].first == sides[i].first) ++j;
      if (j - i > 2) return false;
      if (j - i == 1) on_boundary[sides[i].second] = 1;
    }
    std::unordered_map<std::uint32_t, std::uint32_t> next;  // boundary vertex -> the next along the boundary
    for (std::size_t i = 0; i < faces_.size(); ++i)
      for (int k = 0; k < 3; ++k) {
        const std::uint32_t a = t[3 * std::size_t{faces_[i]} + k], b = t[3 * std::size_t{faces_[i]} + (k + 1) % 3];
        if (on_boundary[3 * i + k] && !next.emplace(a, b).second) return false;  // pinched
      }
    const auto euler = static_cast<long long>(vertices_.size()) - static_cast<long long>(edges) +
                       static_cast<long long>(faces_.size());
    if (euler != 1 || next.empty()) return false;
    // One boundary loop, walked from any of its vertices, to the circle by arc length.
    std::vector<std::uint32_t> loop{next.begin()->first};
    std::vector<double> arc{0};
    while (true) {
      const auto step = next.find(loop.back());
      if (step == next.end()) return false;
      const Vec d = sub(at(input.positions, step->second), at(input.positions, loop.back()));
      arc.push_back(arc.back() + std::sqrt(dot(d, d)));
      if (step->second == loop.front()) break;
      if (loop.size() > next.size()) return false;
      loop.push_back(step->second);
    }
    if (loop.size() != next.size() || !(arc.back() > 0)) return false;
    constexpr double kTwoPi = 6.283185307179586;
    uv_.assign(2 * vertices_.size(), 0.0);
    std::vector<std::uint32_t> inner_index(vertices_.size(), kNone);
    for (std::size_t i = 0; i < loop.size(); ++i) {
      const std::uint32_t l = local_vertex_[loop[i]];
      uv_[2 * l] = std::cos(kTwoPi * arc[i] / arc.back());
      uv_[2 * l + 1] = std::sin(kTwoPi * arc[i] / arc.back());
      inner_index[l] = kNone - 1;  // on the boundary
    }
    std::vector<std::uint32_t> inner;
    for (std::uint32_t l = 0; l < vertices_.size(); ++l)
      if (inner_index[l] == kNone) inner_index[l] = static_cast<std::uint32_t>(inner.size()), inner.push_back(l);
    if (!inner.empty()) {
      // An inner vertex's neighbours are all chart vertices (all its faces are in the chart, else
      // one of its edges would be on the boundary); its rows and the boundary's values by input
      // vertex.
      std::vector<std::uint32_t> inner_input(inner.size());
      for (std::uint32_t i = 0; i < inner.size(); ++i) inner_input[i] = vertices_[inner[i]];
      Eigen::MatrixXd rhs = Eigen::MatrixXd::Zero(static_cast<Eigen::Index>(inner.size()), 2);
      const auto solver = tutte_system(
          adjacency, inner_input,
          [&](std::uint32_t w) {
            return vertex_stamp_[w] == stamp_ && inner_index[local_vertex_[w]] < kNone - 1 ? inner_index[local_vertex_[w]]
                                                                                           : kNone;
          },
          [&](std::uint32_t row, std::uint32_t w) {
            if (vertex_stamp_[w] != stamp_) return false;
            rhs(row, 0) += uv_[2 * local_vertex_[w]], rhs(row, 1) += uv_[2 * local_vertex_[w] + 1];
            return true;
          });
      if (!solver || solver->info() != Eigen::Success) return false;
      const Eigen::MatrixXd mapped = solver->solve(rhs);
      for (std::uint32_t i = 0; i < inner.size(); ++i) uv_[2 * inner[i]] = mapped(i, 0), uv_[2 * inner[i] + 1] = mapped(i, 1);
    }
    // Each face's corners in the chart, for to_chart() and to_surface().
    face_uv_.resize(faces_.size());
    for (std::size_t f = 0; f < faces_.size(); ++f)
      for (int i = 0; i < 3; ++i) {
        const std::uint32_t l = local_vertex_[t[3 * std::size_t{faces_[f]} + i]];
        face_uv_[f][2 * i] = uv_[2 * l], face_uv_[f][2 * i + 1] = uv_[2 * l + 1];
      }
    return true;
  }

  /// The chart coordinates of the point with barycentric coordinates `b` on input face f; false
  /// if f is not in the chart.
  bool to_chart(std::uint32_t f, const std::array<double, 3>& b, double uv[2]) const {
    if (face_stamp_[f] != stamp_) return false;
    const std::array<double, 6>& corners = face_uv_[local_face_[f]];
    uv[0] = uv[1] = 0;
    for (int i = 0; i < 3; ++i) uv[0] += b[i] * corners[2 * i], uv[1] += b[i] * corners[2 * i + 1];
    return true;
  }

  /// The input point at chart coordinates uv; false if uv is outside the chart.
  bool to_surface(const double uv[2], Vec& p) const {
    for (std::size_t local = 0; local < faces_.size(); ++local) {
      const std::uint32_t* t = &input_.triangles[3 * std::size_t{faces_[local]}];
      const std::array<double, 6>& corner = face_uv_[local];
      const double u[3] = {corner[0], corner[2], corner[4]}, w[3] = {corner[1], corner[3], corner[5]};
      const double area = (u[1] - u[0]) * (w[2] - w[0]) - (u[2] - u[0]) * (w[1] - w[0]);
      if (!(area > 0)) continue;
      const double b1 = ((uv[0] - u[0]) * (w[2] - w[0]) - (u[2] - u[0]) * (uv[1] - w[0])) / area;
      const double b2 = ((u[1] - u[0]) * (uv[1] - w[0]) - (uv[0] - u[0]) * (w[1] - w[0])) / area;
      const double b0 = 1 - b1 - b2;
      constexpr double kSlack = -1e-9;
      if (b0 < kSlack || b1 < kSlack || b2 < kSlack) continue;
      const Vec a = at(input_.positions, t[0]), b = at(input_.positions, t[1]), c = at(input_.positions, t[2]);
      for (int k = 0; k < 3; ++k) p[k] = b0 * a[k] + b1 * b[k] + b2 * c[k];
      return true;
    }
    return false;
  }

 private:
  const TriangleMesh& input_;
  const Adjacency& adjacency_;
  /// Per input vertex: reached within the radius, in the chart and its local index; per input
  /// face: in the chart and its local index. A mark holds where it equals stamp_.
  std::vector<std::uint32_t> settled_, vertex_stamp_, local_vertex_, face_stamp_, local_face_;
  std::uint32_t stamp_ = 0;  ///< of the last build
  std::vector<std::uint32_t> faces_, vertices_;
  std::vector<double> uv_;  ///< per local vertex
  std::vector<std::array<double, 6>> face_uv_;  ///< per chart face: its corners' u, v
};


/// The third try at a patch (untangle()): where neither plane lift suits it, its Tutte map
/// (`solver`, the patch's system) inside the input's own flattening around it (InputChart): the
/// rim where the closest points of its vertices fall in the chart, the inner vertices then at
/// the input points of their chart coordinates. The rim need not be convex in the chart, so this
/// too may fold; the caller keeps it on the same condition as the others. The chart's radius
/// along the surface is twice the patch's (its farthest vertex from `origin`), else smaller (a
/// ball that takes in a thin part's whole section is a tube, not a disk), else larger (one that
/// misses rim vertices' closest points). Returns the inner vertices' new positions (xyz, in
/// `inner`'s order), or nullopt where no chart holds the patch. `hint`: as SurfaceQuery::closest.
std::optional<std::vector<double>> lift_through_chart(InputChart& chart, const SurfaceQuery& surface,
                                                      const Adjacency& adjacency, const std::vector<double>& x,
                                                      std::span<const std::uint32_t> vertices,
                                                      std::span<const std::uint32_t> inner,
                                                      std::span<const std::uint32_t> local, const Vec& origin,
                                                      const Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>>& solver,
                                                      std::uint32_t& hint) {
  double reach = 0;
  for (const std::uint32_t v : vertices) {
    const Vec d = sub(at(x, v), origin);
    reach = std::max(reach, std::sqrt(dot(d, d)));
  }
  Eigen::MatrixXd rim = Eigen::MatrixXd::Zero(static_cast<Eigen::Index>(inner.size()), 2);
  bool inside = false;
  const SurfacePoint middle = surface.closest(origin, hint);
  for (const double scale : {2.0, 1.25, 3.0}) {
    if (!chart.build(middle, scale * reach)) continue;
    rim.setZero();
    inside = true;
    for (std::uint32_t i = 0; i < inner.size() && inside; ++i)
      for (std::uint32_t k = adjacency.neighbour_offsets[inner[i]]; k < adjacency.neighbour_offsets[inner[i] + 1] && inside; ++k) {
        const std::uint32_t w = adjacency.neighbours[k];
        if (local[w] != kNone) continue;
        const SurfacePoint on = surface.closest(at(x, w), hint);
        hint = on.face;
        double uv[2] = {0, 0};
        inside = chart.to_chart(on.face, on.barycentric, uv);
        rim(i, 0) += uv[0], rim(i, 1) += uv[1];
      }
    if (inside) break;
  }
  if (!inside) return std::nullopt;
  const Eigen::MatrixXd charted = solver.solve(rim);
  std::vector<double> placed(3 * inner.size());
  for (std::uint32_t i = 0; i < inner.size(); ++i) {
    const double uv[2] = {charted(i, 0), charted(i, 1)};
    Vec p{0, 0, 0};
    if (!chart.to_surface(uv, p)) return std::nullopt;
    for (int c = 0; c < 3; ++c) placed[3 * i + c] = p[c];
  }
  return placed;
}

}  // namespace

namespace {

/// The vertex passes' direct search (untangle()): a grid of (2 kDirectSearchSteps + 1)^2 offsets
/// in units of the ring's reach / kDirectSearchSteps, nearest first (the centre left out), and
/// how few vertices a pass may have left for it to run.
constexpr int kDirectSearchSteps = 8;
constexpr std::size_t kDirectSearchVertices = 64;
const std::vector<std::pair<int, int>>& direct_search_grid() {
  static const std::vector<std::pair<int, int>> grid = [] {
    std::vector<std::pair<int, int>> g;
    for (int i = -kDirectSearchSteps; i <= kDirectSearchSteps; ++i)
      for (int j = -kDirectSearchSteps; j <= kDirectSearchSteps; ++j)
        if (i != 0 || j != 0) g.emplace_back(i, j);
    std::stable_sort(g.begin(), g.end(), [](const auto& a, const auto& b) {
      return a.first * a.first + a.second * a.second < b.first * b.first + b.second * b.second;
    });
    return g;
  }();
  return grid;
}

}  // namespace

UntangleReport untangle(SemiRegularMesh& mesh, const SurfaceQuery& surface, const UntangleOptions& options) {
  if (options.first_rings < 1 || options.max_rings < options.first_rings || options.passes < 0 || options.vertex_passes < 0 ||
      options.rounds < 1 || options.relaxation_steps < 0 || !(options.max_patch_queries_per_face > 0))
    throw std::invalid_argument(
        "untangle: first_rings >= 1, max_rings >= first_rings, passes >= 0, vertex_passes >= 0, rounds >= 1, "
        "relaxation_steps >= 0, max_patch_queries_per_face > 0");
  UntangleReport report;
  const SemiRegularHierarchy& h = mesh.hierarchy;
  const std::vector<std::uint32_t>& triangles = h.triangles(h.levels());
  const std::uint32_t n = h.vertex_count(h.levels());
  const std::size_t faces = triangles.size() / 3;
  const TriangleMesh& input = surface.mesh();
  std::vector<double>& x = mesh.positions;

  // Vertex -> faces and neighbours. The mesh's own boundary vertices stay on the input's boundary
  // curves, where the fitting put them, and fixed vertices on the feature lines.
  const Adjacency adjacency(n, triangles);
  auto stays = [&](std::uint32_t v) {
    return adjacency.on_boundary(v) || (v < options.fixed.size() && options.fixed[v] != 0);
  };
  const std::vector<std::uint32_t>& offsets = adjacency.face_offsets;
  const std::vector<std::uint32_t>& incident = adjacency.faces;

  auto input_normal = [&](std::uint32_t f) {
    return unit(face_normal(input.positions, &input.triangles[3 * std::size_t{f}]));
  };
  auto centroid = [&](std::size_t f) {
    const std::uint32_t* t = &triangles[3 * f];
    const Vec a = at(x, t[0]), b = at(x, t[1]), c = at(x, t[2]);
    return Vec{(a[0] + b[0] + c[0]) / 3, (a[1] + b[1] + c[1]) / 3, (a[2] + b[2] + c[2]) / 3};
  };
  // find_fold_overs()'s tests: a degenerate face (its area at most 1e-14 of the squared
  // diagonal: surface_fit.h) counts as folded too. Counting only faces of zero area, the
  // untangling left alone a face of three corners on one input crease (mannequin-devil at ~16x).
  const double diagonal = bounding_box_diagonal(x);
  auto face_folds = [&](std::size_t f, std::uint32_t* hint = nullptr) {
    return is_folded(x, &triangles[3 * f], surface, diagonal, hint);
  };
  // The patch passes' fold tests and closest-point queries, against their budget
  // (UntangleOptions::max_patch_queries_per_face).
  const double patch_budget = options.max_patch_queries_per_face * static_cast<double>(faces);
  double patch_queries = 0;
  auto patch_budget_spent = [&] {
    if (patch_queries > patch_budget) report.patch_budget_spent = true;
    return report.patch_budget_spent;
  };
  // Per face, the input face closest to its centroid where known (kNone: not yet), as of the
  // epoch in centroid_epoch (below): the patches' planes read it for the same faces again and again.
  std::vector<std::uint32_t> centroid_face(faces, kNone);
  std::vector<std::uint64_t> centroid_epoch(faces, 0);
  std::vector<std::uint8_t> folded(faces);
  parallel_blocks(faces, 0, [&](std::size_t begin, std::size_t end) {
    std::uint32_t hint = kNone;  // consecutive faces are neighbours in a semi-regular mesh
    for (std::size_t f = begin; f < end; ++f) {
      if (is_degenerate(face_normal(x, &triangles[3 * f]), diagonal)) {
        folded[f] = 1;  // as face_folds() counts it, without a query
        continue;
      }
      folded[f] = faces_away(x, &triangles[3 * f], surface, &hint);
      centroid_face[f] = hint;  // the face faces_away() found closest
    }
  });
  report.folded_before = static_cast<std::size_t>(std::count(folded.begin(), folded.end(), 1));

  std::vector<std::uint32_t> stamp(faces, 0), vertex_stamp(n, 0), local(n, kNone);
  std::optional<Adjacency> input_adjacency;  // made when a patch first needs an InputChart
  std::optional<InputChart> chart;
  std::uint32_t generation = 0;
  // Attempts that failed are not repeated while nothing they read has moved. An attempt, on a
  // patch or at a vertex, is a function of the positions of the vertices it reads (a patch's
  // largest region; a vertex and its neighbours), of the folded flags of their faces (which
  // change only when one of those vertices moves) and of the input: repeated unchanged, it fails
  // again. So each move is stamped with a new epoch, a failure records the epoch it saw, and an
  // attempt is skipped when none of its vertices has moved since: the same result, without the
  // closest-point queries that the hopeless patches (at the input's own crossings) used to repeat
  // at every pass and round (mannequin-devil: ~45 % of its remesh time).
  std::vector<std::uint64_t> moved_at(n, 0);
  std::uint64_t epoch = 0;
  auto unmoved_since = [&](std::span<const std::uint32_t> vertices, std::uint64_t since) {
    return std::all_of(vertices.begin(), vertices.end(), [&](std::uint32_t v) { return moved_at[v] <= since; });
  };
  struct FailedPatch {
    std::vector<std::uint32_t> faces;  ///< the patch as it was found
    std::vector<std::uint32_t> read;   ///< the vertices of its largest region
    std::uint64_t epoch = 0;
  };
  std::unordered_map<std::uint32_t, FailedPatch> failed_patches;  // by seed face
  // First, patch by patch.
  auto patch_passes = [&] {
    for (int pass = 0; pass < options.passes; ++pass) {
      std::size_t kept_this_pass = 0;
      std::vector<std::uint8_t> seen(faces, 0);
      for (std::size_t seed = 0; seed < faces && !patch_budget_spent(); ++seed) {
        if (!folded[seed] || seen[seed]) continue;
        // The patch: folded faces connected to `seed` through shared vertices.
        std::vector<std::uint32_t> patch{static_cast<std::uint32_t>(seed)};
        seen[seed] = 1;
        for (std::size_t i = 0; i < patch.size(); ++i)
          for (int k = 0; k < 3; ++k) {
            const std::uint32_t v = triangles[3 * std::size_t{patch[i]} + k];
            for (std::uint32_t j = offsets[v]; j < offsets[v + 1]; ++j)
              if (folded[incident[j]] && !seen[incident[j]]) seen[incident[j]] = 1, patch.push_back(incident[j]);
          }

        if (const auto failed = failed_patches.find(patch[0]);
            failed != failed_patches.end() && failed->second.faces == patch && unmoved_since(failed->second.read, failed->second.epoch))
          continue;
        bool kept = false;
        std::vector<std::uint32_t> read;  // the vertices of the largest region tried
        for (int rings = options.first_rings; rings <= options.max_rings; rings += (rings + 1) / 2) {
          // The region: the patch grown by `rings` rings of faces.
          ++generation;
          std::vector<std::uint32_t> region = patch;
          for (std::uint32_t f : region) stamp[f] = generation;
          for (int r = 0, begin = 0; r < rings; ++r) {
            const int end = static_cast<int>(region.size());
            for (int i = begin; i < end; ++i)
              for (int k = 0; k < 3; ++k) {
                const std::uint32_t v = triangles[3 * std::size_t{region[i]} + k];
                for (std::uint32_t j = offsets[v]; j < offsets[v + 1]; ++j)
                  if (stamp[incident[j]] != generation) stamp[incident[j]] = generation, region.push_back(incident[j]);
              }
            begin = end;
          }
          // Inner vertices: every face around them is in the region; the rest of the region's
          // vertices form its rim and stay.
          std::vector<std::uint32_t> vertices, inner;
          for (std::uint32_t f : region)
            for (int k = 0; k < 3; ++k) {
              const std::uint32_t v = triangles[3 * std::size_t{f} + k];
              if (vertex_stamp[v] == generation) continue;
              vertex_stamp[v] = generation;
              vertices.push_back(v);
              bool all_in = !stays(v);
              for (std::uint32_t j = offsets[v]; all_in && j < offsets[v + 1]; ++j) all_in = stamp[incident[j]] == generation;
              if (all_in) local[v] = static_cast<std::uint32_t>(inner.size()), inner.push_back(v);
              else local[v] = kNone;
            }
          read = vertices;
          if (inner.empty()) continue;

          // The plane: the mean input normal over the region (by the closest points of its
          // face centroids) through the mean of its vertices.
          // Closest-point queries here and below start from the face found for the previous
          // face or vertex (the region grows ring by ring: neighbours follow each other), which
          // makes them faster and does not change their answers (closest_point.h).
          Vec normal{0, 0, 0}, origin{0, 0, 0};
          std::uint32_t hint = kNone;
          for (std::uint32_t f : region) {
            const std::uint32_t* t = &triangles[3 * std::size_t{f}];
            if (centroid_face[f] == kNone || std::max({moved_at[t[0]], moved_at[t[1]], moved_at[t[2]]}) > centroid_epoch[f])
              centroid_face[f] = surface.closest(centroid(f), hint).face, centroid_epoch[f] = epoch, ++patch_queries;
            hint = centroid_face[f];
            const Vec m = input_normal(hint);
            for (int c = 0; c < 3; ++c) normal[c] += m[c];
          }
          normal = unit(normal);
          if (dot(normal, normal) == 0) break;
          for (std::uint32_t v : vertices)
            for (int c = 0; c < 3; ++c) origin[c] += x[3 * v + c] / static_cast<double>(vertices.size());

          // Tutte's map (tutte_system), the rim fixed. The map is linear, so solving it on the
          // world coordinates (relative to the origin) gives, projected on the plane, the planar
          // Tutte embedding of the projected rim, and along the normal a harmonic height.
          Eigen::MatrixXd rhs = Eigen::MatrixXd::Zero(static_cast<Eigen::Index>(inner.size()), 3);
          const auto solver = tutte_system(
              adjacency, inner, [&](std::uint32_t w) { return local[w]; },
              [&](std::uint32_t row, std::uint32_t w) {
                const Vec d = sub(at(x, w), origin);
                for (int c = 0; c < 3; ++c) rhs(row, c) += d[c];
                return true;
              });
          if (!solver || solver->info() != Eigen::Success) continue;
          const Eigen::MatrixXd mapped = solver->solve(rhs);
          double radius = 0;
          for (const std::uint32_t v : inner) {
            const Vec d = sub(at(x, v), origin);
            radius = std::max(radius, std::sqrt(dot(d, d)));
          }

          // Lift each inner vertex back onto the input: along the plane's normal (the nearer hit on
          // a face facing the same way within the region's radius), or, second try, to the closest
          // point (a patch around a thin tube has no plane, but the harmonic map shrinks it
          // towards the axis and the closest points spread it back around in order).
          std::vector<double> saved(3 * inner.size());
          for (std::uint32_t i = 0; i < inner.size(); ++i)
            for (int c = 0; c < 3; ++c) saved[3 * i + c] = x[3 * inner[i] + c];
          // The relaxation's positions (lifts 3 and on) and its next step's, in `inner`'s order.
          std::vector<double> relaxed, next;
          for (int lift = 0; lift < 3 + options.relaxation_steps && !kept; ++lift) {
            if (lift >= 3) {
              // Last tries (UntangleOptions::relaxation_steps): relaxation on the input, from
              // where the patch was, one step more a try: each inner vertex to the input's
              // closest point to the mean of its neighbours (Jacobi; the rim stays): Laplacian
              // (umbrella) smoothing, then the closest point, as surface_fit.cpp's untangling
              // rounds and the fitting of MPEG V-DMC's test model do (CODEC-NOTES §8). A patch
              // across a corner of the input (cow's, at L = 4) has no plane, and no chart holds
              // it, but its own shape can smooth out (docs/RESULTS.md, "Relaxation").
              if (relaxed.empty()) relaxed = saved;
              next.resize(relaxed.size());
              for (std::uint32_t i = 0; i < inner.size(); ++i) {
                const std::uint32_t v = inner[i];
                Vec mean{0, 0, 0};
                const std::uint32_t first = adjacency.neighbour_offsets[v], end = adjacency.neighbour_offsets[v + 1];
                for (std::uint32_t k = first; k < end; ++k) {
                  const std::uint32_t w = adjacency.neighbours[k];
                  for (int c = 0; c < 3; ++c)
                    mean[c] += (local[w] != kNone ? relaxed[3 * local[w] + c] : x[3 * w + c]) / (end - first);
                }
                const SurfacePoint on = surface.closest(mean, hint);
                ++patch_queries;
                hint = on.face;
                for (int c = 0; c < 3; ++c) next[3 * i + c] = on.point[c];
              }
              relaxed.swap(next);
              for (std::uint32_t i = 0; i < inner.size(); ++i)
                for (int c = 0; c < 3; ++c) x[3 * inner[i] + c] = relaxed[3 * i + c];
            } else if (lift == 2) {  // third try: inside the input's own flattening (lift_through_chart)
              if (!input_adjacency) {
                input_adjacency.emplace(static_cast<std::uint32_t>(input.vertex_count()), input.triangles);
                chart.emplace(input, *input_adjacency);
              }
              const std::optional<std::vector<double>> placed =
                  lift_through_chart(*chart, surface, adjacency, x, vertices, inner, local, origin, *solver, hint);
              if (!placed) continue;
              for (std::uint32_t i = 0; i < inner.size(); ++i)
                for (int c = 0; c < 3; ++c) x[3 * inner[i] + c] = (*placed)[3 * i + c];
            } else {
              for (std::uint32_t i = 0; i < inner.size(); ++i) {
                const std::uint32_t v = inner[i];
                const Vec p{origin[0] + mapped(i, 0), origin[1] + mapped(i, 1), origin[2] + mapped(i, 2)};
                SurfacePoint best;
                for (double sign : {1.0, -1.0}) {
                  if (lift == 1 || !(radius > 0)) break;
                  const SurfacePoint hit = surface.first_hit(p, {sign * normal[0], sign * normal[1], sign * normal[2]}, 2 * radius);
                  if (hit.face != kNone && dot(input_normal(hit.face), normal) > 0 && (best.face == kNone || hit.distance < best.distance))
                    best = hit;
                }
                if (best.face == kNone) best = surface.closest(p, hint);
                patch_queries += 3;  // two rays and a closest point at most
                hint = best.face;
                for (int c = 0; c < 3; ++c) x[3 * v + c] = best.point[c];
              }
            }
            // Keep the new patch only if it has fewer folded faces than the old one. Only faces
            // with an inner vertex have moved; the count stops as soon as it cannot end below
            // `before` (a patch that stays folded fails after its own faces, which come first).
            std::size_t before = 0, after = 0;
            for (const std::uint32_t f : region) before += folded[f];
            std::vector<std::uint8_t> now(region.size());
            for (std::size_t i = 0; i < region.size() && after < before; ++i) {
              const std::uint32_t* t = &triangles[3 * std::size_t{region[i]}];
              const bool moved = local[t[0]] != kNone || local[t[1]] != kNone || local[t[2]] != kNone;
              now[i] = moved ? (++patch_queries, face_folds(region[i], &hint)) : folded[region[i]];
              after += now[i];
            }
            ++report.patches_tried;
            if (after < before) {
              for (std::size_t i = 0; i < region.size(); ++i) folded[region[i]] = now[i];
              for (const std::uint32_t v : inner) moved_at[v] = ++epoch;
              ++report.patches_kept, ++kept_this_pass;
              kept = true;
            } else {
              for (std::uint32_t i = 0; i < inner.size(); ++i)
                for (int c = 0; c < 3; ++c) x[3 * inner[i] + c] = saved[3 * i + c];
            }
          }
          if (kept) break;
        }
        const std::uint32_t seed_face = patch[0];
        if (kept) failed_patches.erase(seed_face);
        else failed_patches[seed_face] = FailedPatch{std::move(patch), std::move(read), epoch};
      }
      if (kept_this_pass == 0 || patch_budget_spent()) break;
    }
  };

  // Second, vertex by vertex, what the patches left (Freitag and Plassmann 2000, local
  // optimization-based untangling): each free vertex of a folded face moves, in a plane through
  // it (the input's tangent plane, or two others below), to the point that maximizes the
  // smallest signed area of its faces. For a fixed normal n, a face (p, b, c) has the signed
  // area ½ n·((b − p) × (c − p)), linear in p: with B = b − x, C = c − x and p = x + d, it is
  //   ½ n·(B × C) + ½ d·(n × (C − B)),
  // so the best point is a small linear program (max_min_offset). The vertex goes to the best
  // point of a plane or to the input's closest point to it, whichever leaves fewest of its faces
  // folded, and only if that is fewer than now, or as many with a larger smallest area (along
  // the input's normal at the vertex). Returns the moves kept.
  std::vector<std::uint64_t> vertex_failed_at(n, std::numeric_limits<std::uint64_t>::max());
  auto vertex_passes = [&] {
    std::size_t moved_in_all = 0;
    for (int pass = 0; pass < options.vertex_passes && std::count(folded.begin(), folded.end(), 1) != 0; ++pass) {
      std::vector<std::uint32_t> candidates;
      for (std::size_t f = 0; f < faces; ++f)
        if (folded[f])
          for (int k = 0; k < 3; ++k)
            if (!stays(triangles[3 * f + k])) candidates.push_back(triangles[3 * f + k]);
      std::sort(candidates.begin(), candidates.end());
      candidates.erase(std::unique(candidates.begin(), candidates.end()), candidates.end());
      std::size_t moved = 0;
      for (std::uint32_t v : candidates) {
        const std::span<const std::uint32_t> neighbours(adjacency.neighbours.data() + adjacency.neighbour_offsets[v],
                                                        adjacency.neighbour_offsets[v + 1] - adjacency.neighbour_offsets[v]);
        if (const std::uint64_t since = vertex_failed_at[v];
            since != std::numeric_limits<std::uint64_t>::max() && moved_at[v] <= since && unmoved_since(neighbours, since))
          continue;
        const Vec xv = at(x, v);
        // The plane: the input's normal at the vertex's closest point, then, where they differ
        // from it, the mean of those at its neighbours and the mean of those at its faces'
        // centroids (find_fold_overs()'s reference). A vertex fallen onto the far sheet of a thin
        // part has the far sheet's normal; its neighbours and faces mostly do not. Measured (L = 3,
        // ~4x, camel / cow / turbine / mannequin-devil folds): the first alone 9 / 16 / 19 / 21,
        // the first two 7 / 12 / 10 / 14, all three 8 / 9 / 8 / 12.
        const std::uint32_t here = surface.closest(xv).face;  // the hint of the queries below
        const Vec n = input_normal(here);
        auto add_input_normal = [&](Vec& sum, const Vec& p) {
          const Vec m = input_normal(surface.closest(p, here).face);
          for (int c = 0; c < 3; ++c) sum[c] += m[c];
        };
        Vec mean_normal{0, 0, 0}, face_normal_mean{0, 0, 0};
        for (std::uint32_t k = adjacency.neighbour_offsets[v]; k < adjacency.neighbour_offsets[v + 1]; ++k)
          add_input_normal(mean_normal, at(x, adjacency.neighbours[k]));
        for (std::uint32_t j = offsets[v]; j < offsets[v + 1]; ++j) add_input_normal(face_normal_mean, centroid(incident[j]));
        mean_normal = unit(mean_normal);
        face_normal_mean = unit(face_normal_mean);

        auto ring_folds = [&] {
          std::size_t count = 0;
          for (std::uint32_t j = offsets[v]; j < offsets[v + 1]; ++j) {
            std::uint32_t hint = here;
            count += face_folds(incident[j], &hint);
          }
          return count;
        };
        auto ring_min_area = [&] {  // along n
          double smallest = std::numeric_limits<double>::infinity();
          for (std::uint32_t j = offsets[v]; j < offsets[v + 1]; ++j)
            smallest = std::min(smallest, 0.5 * dot(n, face_normal(x, &triangles[3 * std::size_t{incident[j]}])));
          return smallest;
        };
        Vec best = xv;
        std::size_t best_folds = ring_folds();
        double best_area = ring_min_area();
        // How far the ring reaches from the vertex: the linear program's box, and the direct
        // search's grid below.
        double reach = 0;
        for (std::uint32_t j = offsets[v]; j < offsets[v + 1]; ++j)
          for (int k = 0; k < 3; ++k) {
            const Vec d = sub(at(x, triangles[3 * std::size_t{incident[j]} + k]), xv);
            reach = std::max(reach, std::sqrt(dot(d, d)));
          }
        const Vec planes[] = {n, mean_normal, face_normal_mean};
        for (int which = 0; which < 3; ++which) {
          const Vec& plane = planes[which];
          if (which > 0 && !(dot(plane, plane) > 0 && dot(plane, n) < 0.99)) continue;
          const auto [e1, e2] = vec3::tangent_basis(plane);
          std::vector<Linear2> ring;
          for (std::uint32_t j = offsets[v]; j < offsets[v + 1]; ++j) {
            const std::uint32_t* t = &triangles[3 * std::size_t{incident[j]}];
            const int corner = t[0] == v ? 0 : t[1] == v ? 1 : 2;
            const Vec B = sub(at(x, t[(corner + 1) % 3]), xv), C = sub(at(x, t[(corner + 2) % 3]), xv);
            const Vec m = cross(plane, sub(C, B));
            ring.push_back({{0.5 * dot(e1, m), 0.5 * dot(e2, m)}, 0.5 * dot(plane, cross(B, C))});
          }
          const auto [d, best_min] = max_min_offset(ring, reach);
          const double zero[2] = {0, 0};
          double now_min = ring[0].at(zero);
          for (const Linear2& f : ring) now_min = std::min(now_min, f.at(zero));
          if (!(best_min > now_min)) continue;
          const Vec planar{xv[0] + d[0] * e1[0] + d[1] * e2[0], xv[1] + d[0] * e1[1] + d[1] * e2[1],
                           xv[2] + d[0] * e1[2] + d[1] * e2[2]};
          for (const Vec& q : {surface.closest(planar, here).point, planar}) {
            for (int c = 0; c < 3; ++c) x[3 * v + c] = q[c];
            const std::size_t folds = ring_folds();
            const double area = ring_min_area();
            if (folds < best_folds || (folds == best_folds && area > best_area)) best = q, best_folds = folds, best_area = area;
          }
        }
        // Where the linear program finds no fewer folds (it maximizes the smallest area along
        // one normal, which is not the fold test's own measure: each face against the input face
        // closest to its centroid), a direct search on that measure: the points of a grid over
        // the tangent plane within half the ring's reach, nearest first, each taken to the input
        // and then as it is, and the first with fewer folded faces around the vertex kept. An
        // input point on another sheet (the input's normal there more than 90° from n) or farther
        // than half the reach is skipped: without those guards turbine at ~16x fell from 85.8 to
        // 81.7 dB. Only while few vertices are left to try (up to 288 points, ~7 queries each,
        // twice, a vertex). Measured at ~16x: turbine 5 folded faces -> 0, cow 3 -> 0,
        // mannequin-devil 6 and a degenerate one -> 0 (docs/RESULTS.md, "Direct search").
        if (best_folds > 0 && best == xv && candidates.size() <= kDirectSearchVertices) {
          const auto [e1, e2] = vec3::tangent_basis(n);
          for (const auto& [i, j] : direct_search_grid()) {
            const double s = 0.5 * reach * i / kDirectSearchSteps, t = 0.5 * reach * j / kDirectSearchSteps;
            const Vec planar{xv[0] + s * e1[0] + t * e2[0], xv[1] + s * e1[1] + t * e2[1], xv[2] + s * e1[2] + t * e2[2]};
            // The input point only where it is on the vertex's own sheet (the input's normal
            // there within 90° of the one at the vertex) and within half the reach: no jump to
            // another part of the input.
            const SurfacePoint on = surface.closest(planar, here);
            const Vec step = sub(on.point, xv);
            const bool on_sheet = dot(input_normal(on.face), n) > 0 && dot(step, step) <= 0.25 * reach * reach;
            bool found = false;
            for (int which = on_sheet ? 0 : 1; which < 2 && !found; ++which) {
              const Vec& q = which == 0 ? on.point : planar;
              for (int c = 0; c < 3; ++c) x[3 * v + c] = q[c];
              if (const std::size_t folds = ring_folds(); folds < best_folds)
                best = q, best_folds = folds, best_area = ring_min_area(), found = true;
            }
            if (found) break;
          }
        }
        for (int c = 0; c < 3; ++c) x[3 * v + c] = best[c];
        if (best != xv) {
          ++moved;
          moved_at[v] = ++epoch;
          for (std::uint32_t j = offsets[v]; j < offsets[v + 1]; ++j) {
            std::uint32_t hint = here;
            folded[incident[j]] = face_folds(incident[j], &hint);
          }
        } else {
          vertex_failed_at[v] = epoch;
        }
      }
      moved_in_all += moved;
      if (moved == 0) break;
    }
    return moved_in_all;
  };

  // Rounds of patches then vertices: a vertex moved by the second can make a patch untangle.
  for (int round = 0; round < options.rounds; ++round) {
    patch_passes();
    const std::size_t moved = vertex_passes();
    report.vertices_moved += moved;
    if (moved == 0) break;
  }
  report.folded_after = static_cast<std::size_t>(std::count(folded.begin(), folded.end(), 1));
  return report;
}

}  // namespace meshlift
