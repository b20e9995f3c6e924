// Spherical parametrization by coarse-to-fine stretch minimization (Praun & Hoppe 2003, §4;
// stretch of Sander, Snyder, Gortler & Hoppe 2001, §3). See spherical_parametrization.h.
//
// 1. Simplify: OpenMesh's DecimaterT with Garland-Heckbert quadrics collapses halfedges until a
//    tetrahedron is left (is_collapse_legal keeps a closed genus-0 mesh a closed genus-0 mesh);
//    a recording module keeps each collapse (v0 removed into v1, with the wing vertices vl, vr),
//    which is a progressive mesh (Hoppe 1996).
// 2. Map the tetrahedron's vertices to a regular tetrahedron inscribed in the sphere, with the
//    orientation of its faces.
// 3. Refine: replay the collapses backwards as vertex splits. The new vertex v0 goes inside the
//    spherical kernel of its 1-ring: at the spherical centroid of its ring when that is inside,
//    else on the segment from a point just beside v1 (always inside, see place_split_vertex) to
//    that centroid. Then v0 and its ring are moved to lower the stretch; whenever the vertex count
//    has grown by sweep_growth, every vertex is moved once more (a sweep); finally final_sweeps
//    sweeps run over the full mesh.
// Each move is a guarded line search on the sphere along the negative stretch gradient: a
// position is accepted only if every chord triangle around the vertex stays counter-clockwise and
// non-degenerate and the local stretch drops, so no triangle is ever flipped.
#include "meshlift/spherical_parametrization.h"

#include <OpenMesh/Core/Utils/vector_traits.hh>  // QuadricT.hh uses it without including it
#include <OpenMesh/Core/Geometry/QuadricT.hh>
#include <OpenMesh/Tools/Decimater/DecimaterT.hh>
#include <OpenMesh/Tools/Decimater/ModQuadricT.hh>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <optional>
#include <stdexcept>
#include <string>

#include "meshlift/validate.h"
#include "halfedge_mesh.h"
#include "vec3.h"

namespace meshlift {

namespace {

using Vec = std::array<double, 3>;

Vec sub(const Vec& a, const Vec& b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
Vec add(const Vec& a, const Vec& b) { return {a[0] + b[0], a[1] + b[1], a[2] + b[2]}; }
Vec scale(const Vec& a, double s) { return {a[0] * s, a[1] * s, a[2] * s}; }
double dot(const Vec& a, const Vec& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
Vec cross(const Vec& a, const Vec& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
double norm(const Vec& a) { return std::sqrt(dot(a, a)); }
Vec normalized(const Vec& a) { return scale(a, 1.0 / norm(a)); }

/// det(a, b, c) written as a · ((b − a) × (c − a)): equal, and accurate for small triangles,
/// whose corners are nearly parallel vectors.
double chord_det(const Vec& a, const Vec& b, const Vec& c) { return dot(a, cross(sub(b, a), sub(c, a))); }

double max_edge_squared(const Vec& a, const Vec& b, const Vec& c) {
  const Vec ab = sub(b, a), bc = sub(c, b), ca = sub(a, c);
  return std::max({dot(ab, ab), dot(bc, bc), dot(ca, ca)});
}

/// Counter-clockwise seen from outside and not degenerate (kSphereDegenerateDet).
bool valid_chord_triangle(const Vec& a, const Vec& b, const Vec& c) {
  return chord_det(a, b, c) > kSphereDegenerateDet * max_edge_squared(a, b, c);
}

/// Squared L2 stretch of the affine map from flat triangle p to surface triangle q
/// (Sander et al. 2001, §3, in the cotangent form of the header); +inf for a flat p.
double squared_stretch(const Vec& p0, const Vec& p1, const Vec& p2, const Vec& q0, const Vec& q1, const Vec& q2) {
  const Vec e01 = sub(p1, p0), e02 = sub(p2, p0), e12 = sub(p2, p1);
  const Vec n = cross(e01, e02);
  const double four_area_squared = dot(n, n);  // (2 A_p)²
  if (!(four_area_squared > 0)) return std::numeric_limits<double>::infinity();
  const Vec d12 = sub(q2, q1), d20 = sub(q0, q2), d01 = sub(q1, q0);
  const double sum = dot(e01, e02) * dot(d12, d12)                      // corner 0: (p1−p0)·(p2−p0) |q1−q2|²
                     + dot(scale(e01, -1.0), e12) * dot(d20, d20)       // corner 1: (p0−p1)·(p2−p1) |q2−q0|²
                     + dot(e02, e12) * dot(d01, d01);                   // corner 2: (p0−p2)·(p1−p2) |q0−q1|²
  return sum / (2.0 * four_area_squared);  // Σ / (8 A_p²)
}

/// The spherical triangle as a flat one: its gnomonic projection g_i = p_i / (p_i · c) onto the
/// plane tangent at its centre direction c = (p0 + p1 + p2)/|p0 + p1 + p2|. Great circles stay
/// straight, so a spherical sliver stays a sliver (its chord triangle need not: three points
/// near one great circle span a fat chord triangle through the sphere's inside). Small triangles
/// project to almost their chord triangles. False when a corner is 87° or more from c.
bool gnomonic(const Vec& p0, const Vec& p1, const Vec& p2, Vec g[3]) {
  const Vec c = add(add(p0, p1), p2);
  const double length = norm(c);
  if (!(length > 0)) return false;
  const Vec* p[3] = {&p0, &p1, &p2};
  for (int i = 0; i < 3; ++i) {
    const double h = dot(*p[i], c) / length;
    if (!(h > 0.05)) return false;
    g[i] = scale(*p[i], 1.0 / h);
  }
  return true;
}

/// squared_stretch() of the gnomonic projection of spherical triangle p; +inf where it has none.
double spherical_squared_stretch(const Vec& p0, const Vec& p1, const Vec& p2, const Vec& q0, const Vec& q1, const Vec& q2) {
  Vec g[3];
  if (!gnomonic(p0, p1, p2, g)) return std::numeric_limits<double>::infinity();
  return squared_stretch(g[0], g[1], g[2], q0, q1, q2);
}

using vec3::triangle_area;


/// One halfedge collapse v0 -> v1 with its left and right wing vertices.
struct Collapse {
  int v0, v1, vl, vr;
};

/// Binary decimater module that allows every collapse and records each one performed.
template <typename MeshT>
class ModRecordCollapsesT : public OpenMesh::Decimater::ModBaseT<MeshT> {
 public:
  DECIMATING_MODULE(ModRecordCollapsesT, MeshT, RecordCollapses);
  explicit ModRecordCollapsesT(MeshT& mesh) : Base(mesh, true) {}
  void preprocess_collapse(const CollapseInfo& info) override {
    if (records != nullptr) records->push_back({info.v0.idx(), info.v1.idx(), info.vl.idx(), info.vr.idx()});
  }
  std::vector<Collapse>* records = nullptr;
};

/// Step 1: collapses down to 4 vertices, in order; the faces left.
std::vector<Collapse> simplify_to_tetrahedron(const TriangleMesh& mesh, std::vector<int>& base_faces,
                                              std::size_t& base_vertices) {
  HalfedgeMesh half_edge;
  std::vector<HalfedgeMesh::VertexHandle> handle(mesh.vertex_count());
  for (std::size_t v = 0; v < mesh.vertex_count(); ++v)
    handle[v] = half_edge.add_vertex({mesh.positions[3 * v], mesh.positions[3 * v + 1], mesh.positions[3 * v + 2]});
  for (std::size_t f = 0; f < mesh.face_count(); ++f)
    if (!half_edge
             .add_face(handle[mesh.triangles[3 * f]], handle[mesh.triangles[3 * f + 1]], handle[mesh.triangles[3 * f + 2]])
             .is_valid())
      throw MeshError("face " + std::to_string(f) + " cannot enter a half-edge mesh (non-manifold)");
  half_edge.request_vertex_status();
  half_edge.request_edge_status();
  half_edge.request_halfedge_status();
  half_edge.request_face_status();

  std::vector<Collapse> collapses;
  collapses.reserve(mesh.vertex_count());
  std::size_t remaining = mesh.vertex_count();
  {
    OpenMesh::Decimater::DecimaterT<HalfedgeMesh> decimater(half_edge);
    OpenMesh::Decimater::ModQuadricT<HalfedgeMesh>::Handle quadric;
    typename ModRecordCollapsesT<HalfedgeMesh>::Handle record;
    decimater.add(quadric);
    decimater.add(record);
    decimater.module(record).records = &collapses;
    if (!decimater.initialize()) throw std::logic_error("parametrize_sphere: OpenMesh's decimater did not initialize");
    remaining -= decimater.decimate_to(4);
  }
  // The decimater drops a vertex from its queue when its collapse is illegal and looks again only
  // when a neighbour changes, so it can stop early; every sphere triangulation with more than 4
  // vertices has a contractible edge, so scan all halfedges until none is left.
  bool progress = true;
  while (remaining > 4 && progress) {
    progress = false;
    for (const auto h : half_edge.halfedges()) {
      if (remaining <= 4) break;
      if (half_edge.status(h).deleted() || !half_edge.is_collapse_ok(h)) continue;
      const auto v0 = half_edge.from_vertex_handle(h), v1 = half_edge.to_vertex_handle(h);
      const auto vl = half_edge.to_vertex_handle(half_edge.next_halfedge_handle(h));
      const auto vr = half_edge.to_vertex_handle(half_edge.next_halfedge_handle(half_edge.opposite_halfedge_handle(h)));
      // DecimaterT's extra rule: never collapse a tetrahedron onto a triangle.
      if (half_edge.find_halfedge(vl, vr).is_valid() && half_edge.valence(vl) == 3 && half_edge.valence(vr) == 3)
        continue;
      collapses.push_back({v0.idx(), v1.idx(), vl.idx(), vr.idx()});
      half_edge.collapse(h);
      --remaining;
      progress = true;
    }
  }
  base_vertices = remaining;
  if (remaining != 4)
    throw MeshError("the simplification to a tetrahedron stopped at " + std::to_string(remaining) +
                    " vertices; use --remesh decimate");
  base_faces.clear();
  for (const auto f : half_edge.faces()) {
    if (half_edge.status(f).deleted()) continue;
    for (const auto v : half_edge.fv_range(f)) base_faces.push_back(v.idx());
  }
  return collapses;
}

/// Steps 2-3 state: the mesh being refined, surface (q) and sphere (p) positions per vertex.
class Refiner {
 public:
  Refiner(const TriangleMesh& mesh, std::vector<Vec>& sphere, int line_searches)
      : sphere_(sphere), line_searches_(std::max(1, line_searches)) {
    surface_.resize(mesh.vertex_count());
    for (std::size_t v = 0; v < surface_.size(); ++v)
      surface_[v] = {mesh.positions[3 * v], mesh.positions[3 * v + 1], mesh.positions[3 * v + 2]};
    double total = 0;
    for (std::size_t f = 0; f < mesh.face_count(); ++f)
      total += triangle_area(surface_[mesh.triangles[3 * f]], surface_[mesh.triangles[3 * f + 1]],
                             surface_[mesh.triangles[3 * f + 2]]);
    // Weight floor: a zero-area surface face would otherwise put no barrier against its chord
    // triangle collapsing; 1e-3 of the mean face area changes nothing else measurably.
    area_floor_ = 1e-3 * total / static_cast<double>(std::max<std::size_t>(1, mesh.face_count()));
    for (std::size_t v = 0; v < surface_.size(); ++v) mesh_.add_vertex({0, 0, 0});
  }

  /// Step 2: the base tetrahedron on the sphere, face (a, b, c) counter-clockwise from outside.
  void start(const std::vector<int>& base_faces) {
    const double s = 1.0 / std::sqrt(3.0);
    const Vec corners[4] = {{s, s, s}, {s, -s, -s}, {-s, s, -s}, {-s, -s, s}};
    const int a = base_faces[0], b = base_faces[1], c = base_faces[2];
    int d = -1;
    for (const int v : base_faces)
      if (v != a && v != b && v != c) d = v;
    sphere_[a] = corners[0];
    sphere_[b] = corners[1];
    sphere_[c] = corners[2];
    if (chord_det(corners[0], corners[1], corners[2]) < 0) std::swap(sphere_[b], sphere_[c]);
    sphere_[d] = corners[3];
    for (std::size_t f = 0; f + 2 < base_faces.size(); f += 3)
      mesh_.add_face(HalfedgeMesh::VertexHandle(base_faces[f]), HalfedgeMesh::VertexHandle(base_faces[f + 1]),
                     HalfedgeMesh::VertexHandle(base_faces[f + 2]));
    present_ = {a, b, c, d};
    std::sort(present_.begin(), present_.end());
    for (int k = 0; k < 10; ++k) sweep();
  }

  /// Step 3 for one collapse, undone.
  void split(const Collapse& c) {
    mesh_.vertex_split(HalfedgeMesh::VertexHandle(c.v0), HalfedgeMesh::VertexHandle(c.v1),
                       HalfedgeMesh::VertexHandle(c.vl), HalfedgeMesh::VertexHandle(c.vr));
    present_.push_back(c.v0);
    place_split_vertex(c.v0, c.v1);
    for (int k = 0; k < 2; ++k) optimize(c.v0);
    std::vector<int> neighbours;
    for (const auto w : mesh_.vv_range(HalfedgeMesh::VertexHandle(c.v0))) neighbours.push_back(w.idx());
    for (const int w : neighbours) optimize(w);
  }

  /// Every present vertex: up to line_searches moves while each lowers its energy by 1e-4 or more.
  void sweep() {
    for (const int v : present_)
      for (int k = 0; k < line_searches_ && optimize(v); ++k) {
      }
  }
  std::size_t present() const { return present_.size(); }

 private:
  /// Faces around v as the other two corners (a, b), each face (v, a, b) counter-clockwise.
  void gather(int v) {
    ring_.clear();
    for (const auto h : mesh_.voh_range(HalfedgeMesh::VertexHandle(v))) {
      if (!mesh_.face_handle(h).is_valid()) continue;
      ring_.push_back({mesh_.to_vertex_handle(h).idx(), mesh_.to_vertex_handle(mesh_.next_halfedge_handle(h)).idx()});
    }
  }

  bool valid_at(const Vec& p) const {
    for (const auto& [a, b] : ring_)
      if (!valid_chord_triangle(p, sphere_[a], sphere_[b])) return false;
    return true;
  }

  /// Σ over the ring of w_T L2²(T), w_T = A_q(T) + floor; +inf where a triangle is invalid.
  double energy_at(int v, const Vec& p) const {
    double e = 0;
    for (const auto& [a, b] : ring_) {
      if (!valid_chord_triangle(p, sphere_[a], sphere_[b])) return std::numeric_limits<double>::infinity();
      const Vec &qv = surface_[v], &qa = surface_[a], &qb = surface_[b];
      e += (triangle_area(qv, qa, qb) + area_floor_) * spherical_squared_stretch(p, sphere_[a], sphere_[b], qv, qa, qb);
    }
    return e;
  }

  /// Kernel placement of a split vertex v0 next to v1 (its 1-ring's faces (v0, a, b) must all be
  /// counter-clockwise). First choice, the spherical centroid of the ring. Else the centroid of the
  /// kernel: in the gnomonic projection centred at v1 great circles are lines, so the kernel is the
  /// convex intersection of the half-planes left of each a -> b, found by clipping a large square.
  /// Last resort, a point just beside v1: there the faces v0 took over from v1 are as valid as
  /// they were, and the two new faces (v0, v1, b) and (v0, a, v1) are counter-clockwise when the
  /// offset direction d has d·(p1 × p_b) > 0 and d·(p_a × p1) > 0, which the sum of the two unit
  /// normals satisfies unless they are opposite.
  void place_split_vertex(int v0, int v1) {
    gather(v0);
    Vec centroid{0, 0, 0};
    for (const auto& [a, b] : ring_) centroid = add(centroid, sphere_[a]);
    centroid = normalized(centroid);
    if (valid_at(centroid)) {
      sphere_[v0] = centroid;
      return;
    }
    const Vec& p1 = sphere_[v1];
    if (const auto kernel = kernel_centroid(p1); kernel && valid_at(*kernel)) {
      sphere_[v0] = *kernel;
      return;
    }
    Vec d{0, 0, 0};
    double shortest = std::numeric_limits<double>::infinity();
    for (const auto& [a, b] : ring_) {
      if (a == v1) d = add(d, normalized(cross(p1, sphere_[b])));
      if (b == v1) d = add(d, normalized(cross(sphere_[a], p1)));
      if (a != v1) shortest = std::min(shortest, norm(sub(sphere_[a], p1)));
    }
    d = sub(d, scale(p1, dot(d, p1)));
    const double length = norm(d);
    if (!(length > 0)) throw std::logic_error("parametrize_sphere: no kernel direction for a split vertex");
    d = scale(d, 1.0 / length);
    for (double s = 0.25 * shortest; s > 1e-17 * shortest; s *= 0.5) {
      const Vec near = normalized(add(p1, scale(d, s)));
      if (valid_at(near)) {
        sphere_[v0] = near;
        return;
      }
    }
    throw std::logic_error("parametrize_sphere: empty kernel for a split vertex");
  }

  /// Centroid of the ring's kernel in the gnomonic projection centred at `centre`, back on the
  /// sphere; nothing if a ring vertex is not in centre's open hemisphere or the kernel is empty.
  std::optional<Vec> kernel_centroid(const Vec& centre) const {
    const Vec axis = std::fabs(centre[0]) < 0.6 ? Vec{1, 0, 0} : Vec{0, 1, 0};
    const Vec t1 = normalized(cross(centre, axis)), t2 = cross(centre, t1);  // (t1, t2, centre) right-handed
    auto project = [&](const Vec& x) -> std::optional<std::array<double, 2>> {
      const double h = dot(x, centre);
      if (!(h > 1e-6)) return std::nullopt;
      return std::array<double, 2>{dot(x, t1) / h, dot(x, t2) / h};
    };
    double extent = 0;
    std::vector<std::array<double, 2>> polygon;
    std::vector<std::array<double, 4>> lines;  // a, b per face
    for (const auto& [a, b] : ring_) {
      const auto pa = project(sphere_[a]), pb = project(sphere_[b]);
      if (!pa || !pb) return std::nullopt;
      lines.push_back({(*pa)[0], (*pa)[1], (*pb)[0], (*pb)[1]});
      extent = std::max({extent, std::fabs((*pa)[0]), std::fabs((*pa)[1])});
    }
    extent = 2 * extent + 1;
    polygon = {{-extent, -extent}, {extent, -extent}, {extent, extent}, {-extent, extent}};
    std::vector<std::array<double, 2>> clipped;
    for (const auto& l : lines) {
      // Keep the side where orientation(a, b, x) = (b − a) × (x − a) > 0 (Sutherland-Hodgman).
      auto side = [&](const std::array<double, 2>& x) { return (l[2] - l[0]) * (x[1] - l[1]) - (l[3] - l[1]) * (x[0] - l[0]); };
      clipped.clear();
      for (std::size_t i = 0; i < polygon.size(); ++i) {
        const auto& x = polygon[i];
        const auto& y = polygon[(i + 1) % polygon.size()];
        const double sx = side(x), sy = side(y);
        if (sx > 0) clipped.push_back(x);
        if ((sx > 0) != (sy > 0)) {
          const double t = sx / (sx - sy);
          clipped.push_back({x[0] + t * (y[0] - x[0]), x[1] + t * (y[1] - x[1])});
        }
      }
      polygon.swap(clipped);
      if (polygon.size() < 3) return std::nullopt;
    }
    // Area centroid of the convex polygon.
    double area = 0, cx = 0, cy = 0;
    for (std::size_t i = 0; i < polygon.size(); ++i) {
      const auto& x = polygon[i];
      const auto& y = polygon[(i + 1) % polygon.size()];
      const double w = x[0] * y[1] - y[0] * x[1];
      area += w;
      cx += (x[0] + y[0]) * w;
      cy += (x[1] + y[1]) * w;
    }
    if (!(area > 0)) return std::nullopt;
    cx /= 3 * area;
    cy /= 3 * area;
    return normalized(add(centre, add(scale(t1, cx), scale(t2, cy))));
  }

  /// One guarded line search for vertex v along the negative stretch gradient on the sphere
  /// (central differences in a tangent frame); moves only to a valid position of lower energy.
  bool optimize(int v) {
    gather(v);
    if (ring_.empty()) return false;
    const Vec p = sphere_[v];
    const double e0 = energy_at(v, p);
    double shortest = std::numeric_limits<double>::infinity(), mean = 0;
    for (const auto& [a, b] : ring_) {
      const double l = norm(sub(sphere_[a], p));
      shortest = std::min(shortest, l);
      mean += l;
    }
    mean /= static_cast<double>(ring_.size());
    // Tangent frame at p.
    const Vec axis = std::fabs(p[0]) < 0.6 ? Vec{1, 0, 0} : Vec{0, 1, 0};
    const Vec t1 = normalized(cross(p, axis)), t2 = cross(p, t1);
    const double h = 1e-4 * shortest;
    double g[2];
    const Vec* frame[2] = {&t1, &t2};
    for (int k = 0; k < 2; ++k) {
      const double plus = energy_at(v, normalized(add(p, scale(*frame[k], h))));
      const double minus = energy_at(v, normalized(sub(p, scale(*frame[k], h))));
      if (std::isfinite(plus) && std::isfinite(minus))
        g[k] = (plus - minus) / (2 * h);
      else if (std::isfinite(plus))
        g[k] = (plus - e0) / h;
      else if (std::isfinite(minus))
        g[k] = (e0 - minus) / h;
      else
        return false;
    }
    Vec direction = add(scale(t1, -g[0]), scale(t2, -g[1]));
    const double length = norm(direction);
    if (!(length > 0)) return false;
    direction = scale(direction, 1.0 / length);
    double step = 0.5 * mean, best = e0;
    Vec best_p = p;
    for (int k = 0; k < 16; ++k, step *= 0.5) {
      const Vec candidate = normalized(add(p, scale(direction, step)));
      const double e = energy_at(v, candidate);
      if (e < best) {
        best = e;
        best_p = candidate;
        // Backtracking found a decrease; a first full step may go further.
        for (int grow = 0; k == 0 && grow < 4; ++grow) {
          step *= 2;
          const Vec further = normalized(add(p, scale(direction, step)));
          const double ef = energy_at(v, further);
          if (!(ef < best)) break;
          best = ef;
          best_p = further;
        }
        break;
      }
    }
    sphere_[v] = best_p;
    return best < e0 * (1 - 1e-4) || (!std::isfinite(e0) && std::isfinite(best));
  }

  HalfedgeMesh mesh_;
  std::vector<Vec> surface_;
  std::vector<Vec>& sphere_;
  std::vector<int> present_;
  std::vector<std::pair<int, int>> ring_;
  double area_floor_ = 0;
  int line_searches_ = 1;
};

/// Signed solid angle of spherical triangle abc (Van Oosterom & Strackee 1983):
/// tan(Ω/2) = det(a, b, c) / (1 + a·b + b·c + c·a) for unit vectors.
double solid_angle(const Vec& a, const Vec& b, const Vec& c) {
  return 2.0 * std::atan2(chord_det(a, b, c), 1.0 + dot(a, b) + dot(b, c) + dot(c, a));
}

Vec at(std::span<const double> xyz, std::uint32_t v) { return {xyz[3 * v], xyz[3 * v + 1], xyz[3 * v + 2]}; }

}  // namespace

std::string sphere_parametrization_problem(const TriangleMesh& mesh) {
  const MeshReport report = validate_mesh(mesh);
  if (!report.structure_error.empty()) return report.structure_error;
  std::string problems;
  auto add_problem = [&](const std::string& p) { problems += (problems.empty() ? "" : "; ") + p; };
  if (report.invalid_index_faces > 0) add_problem(std::to_string(report.invalid_index_faces) + " faces with invalid vertex indices");
  if (report.degenerate_faces > 0) add_problem(std::to_string(report.degenerate_faces) + " faces repeating a vertex");
  if (report.non_finite_vertices > 0) add_problem(std::to_string(report.non_finite_vertices) + " vertices with non-finite coordinates");
  if (report.faces == 0) add_problem("no faces");
  if (report.boundary_edges > 0)
    add_problem("not closed (" + std::to_string(report.boundary_edges) + " boundary edges in " +
                std::to_string(report.boundary_loops) + " loops)");
  if (!report.is_manifold())
    add_problem("not manifold (" + std::to_string(report.non_manifold_edges) + " non-manifold edges, " +
                std::to_string(report.non_manifold_vertices) + " non-manifold vertices)");
  if (!report.consistently_oriented)
    add_problem("not consistently oriented (" + std::to_string(report.inconsistent_edges) + " edges)");
  if (report.connected_components > 1)
    add_problem("not one component (" + std::to_string(report.connected_components) + " components)");
  if (problems.empty() && report.euler_characteristic != 2) {
    const std::int64_t genus = (2 - report.euler_characteristic) / 2;
    add_problem("genus " + std::to_string(genus) + ", not 0 (Euler characteristic " +
                std::to_string(report.euler_characteristic) + ")");
  }
  if (problems.empty()) return "";
  return problems + ": the sphere remesher needs a closed, manifold, genus-0 surface in one piece; use --remesh decimate";
}

SphereMapCheck check_sphere_map(const TriangleMesh& mesh, std::span<const double> sphere) {
  SphereMapCheck check;
  double total = 0;
  for (std::size_t f = 0; f < mesh.face_count(); ++f) {
    const Vec a = at(sphere, mesh.triangles[3 * f]), b = at(sphere, mesh.triangles[3 * f + 1]),
              c = at(sphere, mesh.triangles[3 * f + 2]);
    const double det = chord_det(a, b, c);
    const bool on_sphere = std::fabs(dot(a, a) - 1) < 1e-9 && std::fabs(dot(b, b) - 1) < 1e-9 && std::fabs(dot(c, c) - 1) < 1e-9;
    if (det < 0) ++check.flipped_triangles;
    if (!on_sphere || std::fabs(det) <= kSphereDegenerateDet * max_edge_squared(a, b, c)) ++check.degenerate_triangles;
    total += solid_angle(a, b, c);
  }
  check.coverage = total / (4 * M_PI);
  return check;
}

double spherical_stretch(const TriangleMesh& mesh, std::span<const double> sphere) {
  double weighted = 0, surface_area = 0, sphere_area = 0;
  for (std::size_t f = 0; f < mesh.face_count(); ++f) {
    const std::uint32_t i = mesh.triangles[3 * f], j = mesh.triangles[3 * f + 1], k = mesh.triangles[3 * f + 2];
    const Vec p0 = at(sphere, i), p1 = at(sphere, j), p2 = at(sphere, k);
    const Vec q0 = at(mesh.positions, i), q1 = at(mesh.positions, j), q2 = at(mesh.positions, k);
    const double aq = triangle_area(q0, q1, q2);
    weighted += aq * spherical_squared_stretch(p0, p1, p2, q0, q1, q2);
    surface_area += aq;
    sphere_area += solid_angle(p0, p1, p2);
  }
  if (!(surface_area > 0)) return std::numeric_limits<double>::infinity();
  return std::sqrt(weighted / surface_area) * std::sqrt(sphere_area / surface_area);
}

SphericalParametrization parametrize_sphere(const TriangleMesh& mesh, const SphericalParametrizationOptions& options) {
  if (const std::string problem = sphere_parametrization_problem(mesh); !problem.empty()) throw MeshError(problem);
  // Only referenced vertices take part (isolated ones are allowed by the contract).
  std::vector<std::uint32_t> compact(mesh.vertex_count(), kNone), original;
  TriangleMesh used;
  used.triangles.reserve(mesh.triangles.size());
  for (const std::uint32_t v : mesh.triangles) {
    if (compact[v] == kNone) {
      compact[v] = static_cast<std::uint32_t>(original.size());
      original.push_back(v);
      used.positions.insert(used.positions.end(), {mesh.positions[3 * v], mesh.positions[3 * v + 1], mesh.positions[3 * v + 2]});
    }
    used.triangles.push_back(compact[v]);
  }

  SphericalParametrization result;
  std::vector<int> base_faces;
  const std::vector<Collapse> collapses = simplify_to_tetrahedron(used, base_faces, result.base_vertices);
  result.collapses = collapses.size();

  std::vector<Vec> sphere(used.vertex_count(), Vec{0, 0, 1});
  Refiner refiner(used, sphere, options.line_searches);
  refiner.start(base_faces);
  std::size_t last_sweep = refiner.present();
  const double total_work = static_cast<double>(collapses.size()) + 1.0;
  for (std::size_t k = collapses.size(); k-- > 0;) {
    refiner.split(collapses[k]);
    if (static_cast<double>(refiner.present()) >= options.sweep_growth * static_cast<double>(last_sweep)) {
      refiner.sweep();
      last_sweep = refiner.present();
    }
    if (options.progress && k % 1024 == 0)
      options.progress(0.8 * static_cast<double>(collapses.size() - k) / total_work);
  }
  for (int s = 0; s < options.final_sweeps; ++s) {
    refiner.sweep();
    if (options.progress) options.progress(0.8 + 0.2 * (s + 1) / std::max(1, options.final_sweeps));
  }

  result.sphere.assign(3 * mesh.vertex_count(), 0.0);
  for (std::size_t v = 0; v < mesh.vertex_count(); ++v) result.sphere[3 * v + 2] = 1.0;
  for (std::size_t c = 0; c < original.size(); ++c)
    for (int k = 0; k < 3; ++k) result.sphere[3 * original[c] + k] = sphere[c][k];
  result.check = check_sphere_map(mesh, result.sphere);
  result.stretch = spherical_stretch(mesh, result.sphere);
  return result;
}

}  // namespace meshlift
