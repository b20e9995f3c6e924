// Fitting a refined base mesh to the input surface. See surface_fit.h.
//
// Coarse to fine. Level j's new (odd) vertices start at the guide (j <= guide_levels) or at the
// butterfly prediction from level j-1's placed vertices, and are placed on the input by normal
// shooting (shoot(): along ±the vertex normal of the current level-j mesh, the nearest hit on a
// face that faces the same way, within two mean edge lengths; the closest point when there is
// none). Optional rounds then move each new vertex by a fraction of the tangential part of its
// umbrella vector and place it again (off by default: measured, they fold more faces). On the
// coarsest levels, the normal-line placement then moves each new vertex, where that is safe, to
// the surface point on the line through its butterfly prediction along the codec's frame normal
// (a normal mesh: as placed its detail has no tangential part, so the codec spends few bits on
// one; the later fitting moves it a little). Last,
// untangling: the corners of faces that face away from the input, and their neighbours, take
// full umbrella steps and are placed again, until no face of the level folds or the count stops
// falling. Boundary vertices move along the boundary only (the mean of their two boundary
// neighbours) and are placed on the input's boundary curves. Every round is a Jacobi update (all
// new positions from the old ones), so the result does not depend on the thread count. Closest
// point plus smoothing is the fitting of MPEG V-DMC's test model (CODEC-NOTES §8); normal
// shooting, coarse to fine, is how normal meshes place their vertices (Guskov et al. 2000).
#include "meshlift/surface_fit.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <thread>
#include <vector>

#include "meshlift/lifting.h"
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

/// Closest points on the input's boundary edges (brute force: boundaries are short).
struct BoundaryCurves {
  std::vector<std::array<Vec, 2>> segments;

  explicit BoundaryCurves(const TriangleMesh& mesh) {
    const Adjacency adjacency(static_cast<std::uint32_t>(mesh.vertex_count()), mesh.triangles);
    for (std::uint32_t v = 0; v < mesh.vertex_count(); ++v)
      for (std::uint32_t k = adjacency.boundary_neighbour_offsets[v]; k < adjacency.boundary_neighbour_offsets[v + 1]; ++k)
        if (adjacency.boundary_neighbours[k] > v)
          segments.push_back({at(mesh.positions, v), at(mesh.positions, adjacency.boundary_neighbours[k])});
  }
  Vec closest(const Vec& p) const {
    Vec best = p;
    double best_d = INFINITY;
    for (const auto& [a, b] : segments) {
      const Vec ab = sub(b, a);
      const double len2 = dot(ab, ab);
      const double t = len2 > 0 ? std::clamp(dot(sub(p, a), ab) / len2, 0.0, 1.0) : 0.0;
      const Vec q{a[0] + t * ab[0], a[1] + t * ab[1], a[2] + t * ab[2]};
      const Vec d = sub(p, q);
      if (dot(d, d) < best_d) best_d = dot(d, d), best = q;
    }
    return best;
  }
};

/// Area-weighted vertex normal (not normalized) of v in the current positions.
Vec vertex_normal(const Adjacency& adjacency, const std::vector<std::uint32_t>& triangles, std::span<const double> x,
                  std::uint32_t v) {
  Vec n{0, 0, 0};
  for (std::uint32_t k = adjacency.face_offsets[v]; k < adjacency.face_offsets[v + 1]; ++k) {
    const std::uint32_t f = adjacency.faces[k];
    const Vec a = at(x, triangles[3 * f]), b = at(x, triangles[3 * f + 1]), c = at(x, triangles[3 * f + 2]);
    const Vec fn = cross(sub(b, a), sub(c, a));
    for (int i = 0; i < 3; ++i) n[i] += fn[i];
  }
  return n;
}

/// Normal shooting (as normal meshes place their vertices): the nearer of the first hits of the
/// rays from p along n and along -n, within `reach`, if it is on a face that faces the way n
/// does; face = kNone otherwise. Unlike the closest point, nearby points with similar normals
/// land on nearby, equally ordered points, also across the input's convex edges (where closest
/// points pile up on the edge and fold the triangles between them).
SurfacePoint shoot(const SurfaceQuery& surface, const Vec& p, const Vec& n, double reach) {
  const TriangleMesh& input = surface.mesh();
  SurfacePoint best;
  for (double sign : {1.0, -1.0}) {
    const SurfacePoint hit = surface.first_hit(p, {sign * n[0], sign * n[1], sign * n[2]}, reach);
    if (hit.face != kNone && (best.face == kNone || hit.distance < best.distance)) best = hit;
  }
  if (best.face == kNone) return best;
  if (dot(face_normal(input.positions, &input.triangles[3 * std::size_t{best.face}]), n) <= 0) return SurfacePoint{};
  return best;
}

}  // namespace

void fit_to_surface(SemiRegularMesh& mesh, std::span<const double> guide, const SurfaceQuery& surface,
                    const SurfaceFitOptions& options) {
  const SemiRegularHierarchy& h = mesh.hierarchy;
  const int levels = h.levels();
  const std::size_t total = h.vertex_count(levels);
  if (guide.size() != 3 * total) throw std::invalid_argument("fit_to_surface: guide must hold one xyz per vertex");
  if (options.relax_iterations < 0 || !(options.relax_step > 0 && options.relax_step <= 1) ||
      options.normal_line_levels < 0 || !(options.stray_distance >= 0))
    throw std::invalid_argument(
        "fit_to_surface: relax_iterations >= 0, relax_step in (0, 1], normal_line_levels >= 0 and stray_distance >= 0");
  const unsigned threads = options.threads ? options.threads : std::max(1u, std::thread::hardware_concurrency());
  const BoundaryCurves boundary(surface.mesh());
  const TriangleMesh& input = surface.mesh();
  auto is_fixed = [&](std::uint32_t v) { return v < options.fixed.size() && options.fixed[v] != 0; };

  mesh.positions.assign(guide.begin(), guide.end());
  std::span<double> x(mesh.positions);
  // The input face each vertex was projected on (its normal tells which way the surface faces).
  std::vector<std::uint32_t> face_of(total, kNone);
  for (std::uint32_t v = 0; v < h.vertex_count(0); ++v) face_of[v] = surface.closest(at(x, v)).face;
  auto input_normal = [&](std::uint32_t f) { return unit(face_normal(input.positions, &input.triangles[3 * std::size_t{f}])); };

  std::vector<double> next;
  std::vector<std::uint32_t> next_face;
  const double work_total = static_cast<double>(total - h.vertex_count(0)) * (1 + options.relax_iterations);
  double work_done = 0;

  for (int j = 1; j <= levels; ++j) {
    const std::uint32_t first = h.vertex_count(j - 1), end = h.vertex_count(j);
    const std::vector<std::uint32_t>& triangles = h.triangles(j);
    const Adjacency adjacency(end, triangles);

    // The codec's local-frame normal of each new vertex (FORMAT.md §5): the sum of the
    // area-weighted normals of level j-1 at the ends of its edge, normalized. Shooting along it
    // from the butterfly prediction leaves the vertex's detail along that normal only (a normal
    // mesh, Guskov et al. 2000): no tangential components to code.
    const std::vector<Vec> frame_normal = j <= options.normal_line_levels ? edge_frame_normals(h.topology(j - 1), x) : std::vector<Vec>{};

    // A face of the level is folded when it faces away from the input normals under its corners.
    auto folded = [&](std::size_t f) {
      const std::uint32_t* t = &triangles[3 * f];
      Vec reference{0, 0, 0};
      for (int i = 0; i < 3; ++i) {
        const Vec m = input_normal(face_of[t[i]]);
        for (int c = 0; c < 3; ++c) reference[c] += m[c];
      }
      return dot(face_normal(x, t), reference) <= 0;
    };

    // The midpoint of a new vertex's edge, and whether p is a stray there: farther from it than
    // stray_distance lengths of the edge. A stray has landed on another part of the input: from
    // a start off the surface (the guide's point at a thin part), or, far more often, from an
    // untangling step that carried it into a thin part, whence the projection finds the
    // opposite wall (turbine at ~16x, L = 3: moves of up to 21 edge lengths; the placement was
    // 82 dB from the input before its untangling rounds and 49 after, faces spanning the inside
    // of the disk). Measured at 1 and 2 edge lengths (docs/RESULTS.md): 1 also stops moves that
    // thin parts need at ~4x (turbine 80.9 -> 73.5 dB); 2 gives turbine 81.9 at ~4x, 86.0 at ~16x
    // (was 56.5, 58 folds; now 10), the other meshes within 0.1 dB.
    // (The untangling below moves the new vertices of the levels before too: any odd vertex.)
    auto edge_of = [&](std::uint32_t v) {
      int k = 1;
      while (v >= h.vertex_count(k)) ++k;
      return &h.topology(k - 1).edge_vertices[2 * std::size_t{v - h.vertex_count(k - 1)}];
    };
    auto midpoint = [&](std::uint32_t v) {
      const std::uint32_t* e = edge_of(v);
      const Vec a = at(x, e[0]), b = at(x, e[1]);
      return Vec{(a[0] + b[0]) / 2, (a[1] + b[1]) / 2, (a[2] + b[2]) / 2};
    };
    auto stray = [&](std::uint32_t v, const Vec& p) {
      if (!(options.stray_distance > 0) || v < h.vertex_count(0)) return false;
      const std::uint32_t* e = edge_of(v);
      const Vec d = sub(p, midpoint(v)), ab = sub(at(x, e[1]), at(x, e[0]));
      return dot(d, d) > options.stray_distance * options.stray_distance * dot(ab, ab);
    };

    // One Jacobi round over `vertices`: optionally a tangential umbrella move of `step`, then
    // projection on the input (boundary vertices: on its boundary curves). A stray is placed
    // again from its edge's midpoint, or, a stray from there too, left at the midpoint.
    auto round = [&](const std::vector<std::uint32_t>& vertices, bool smooth, double step) {
      next.assign(3 * vertices.size(), 0.0);
      next_face.assign(vertices.size(), kNone);
      parallel_blocks(vertices.size(), threads, [&](std::size_t begin, std::size_t stop) {
        for (std::size_t i = begin; i < stop; ++i) {
          const std::uint32_t v = vertices[i];
          Vec p = at(x, v);
          const bool on_boundary = adjacency.on_boundary(v);
          Vec n = vertex_normal(adjacency, triangles, x, v);
          const double n_len = std::sqrt(dot(n, n));
          if (n_len > 0)
            for (double& c : n) c /= n_len;
          const double reach = adjacency.mean_edge_length(x, v);  // the scale of the vertex's moves
          if (smooth) {
            Vec mean{0, 0, 0};
            const auto& offsets = on_boundary ? adjacency.boundary_neighbour_offsets : adjacency.neighbour_offsets;
            const auto& list = on_boundary ? adjacency.boundary_neighbours : adjacency.neighbours;
            const double m_count = offsets[v + 1] - offsets[v];
            for (std::uint32_t k = offsets[v]; k < offsets[v + 1]; ++k) {
              const Vec q = at(x, list[k]);
              for (int c = 0; c < 3; ++c) mean[c] += q[c] / m_count;
            }
            Vec move = sub(mean, p);
            if (!on_boundary && n_len > 0) {
              const double along = dot(move, n);
              for (int c = 0; c < 3; ++c) move[c] -= along * n[c];
            }
            for (int c = 0; c < 3; ++c) p[c] += step * move[c];
          }
          auto place = [&](Vec& q) {  // onto the input; returns where
            SurfacePoint s;
            if (on_boundary && !boundary.segments.empty()) {
              q = boundary.closest(q);
              s = surface.closest(q);
            } else {
              s = n_len > 0 ? shoot(surface, q, n, 2 * reach) : SurfacePoint{};
              if (s.face == kNone) s = surface.closest(q);  // no facing hit near: the closest point
              q = s.point;
            }
            return s;
          };
          SurfacePoint s = place(p);
          if (stray(v, p)) {
            const Vec mid = midpoint(v);
            p = mid;
            s = place(p);
            if (stray(v, p)) p = mid, s = surface.closest(mid);
          }
          next[3 * i] = p[0], next[3 * i + 1] = p[1], next[3 * i + 2] = p[2];
          next_face[i] = s.face;
        }
      });
      for (std::size_t i = 0; i < vertices.size(); ++i) {
        for (int c = 0; c < 3; ++c) x[3 * vertices[i] + c] = next[3 * i + c];
        face_of[vertices[i]] = next_face[i];
      }
    };

    // Start positions: the guide on the coarsest levels; further up, the butterfly prediction
    // from the level below, already on the surface (closer to it than the guide, which knows
    // only the base). Measured against Loop's positive edge rule (3/8, 3/8, 1/8, 1/8), which
    // cannot overshoot: butterfly folded fewer faces on the corpus (armadillo, L = 4: 136 vs
    // 428; cow 617 vs 828) at no loss (cow 69.6 dB both, fandisk 73.2 vs 70.4 dB).
    if (j > options.guide_levels) {
      std::fill(x.begin() + 3 * std::ptrdiff_t{first}, x.begin() + 3 * std::ptrdiff_t{end}, 0.0);
      synthesize_level(h, {Scheme::butterfly}, j - 1, x, 3);  // no tables: the same bits
    }
    // Round 0 projects the start positions; rounds 1.. smooth tangentially, then project. Fixed
    // vertices keep the guide's position (on a feature line).
    std::vector<std::uint32_t> fresh, fresh_index(end - first, kNone);
    for (std::uint32_t v = first; v < end; ++v) {
      if (!is_fixed(v)) {
        fresh_index[v - first] = static_cast<std::uint32_t>(fresh.size());
        fresh.push_back(v);
        continue;
      }
      std::copy_n(guide.begin() + 3 * std::ptrdiff_t{v}, 3, x.begin() + 3 * std::ptrdiff_t{v});
      face_of[v] = surface.closest(at(x, v)).face;
    }
    for (int r = 0; r <= options.relax_iterations; ++r) {
      round(fresh, r > 0, options.relax_step);
      work_done += static_cast<double>(fresh.size());
      if (options.progress) options.progress(work_done / work_total);
    }

    // Normal-line placement: each new vertex shot along its frame normal from the point of the
    // normal line through its butterfly prediction at the start's height (the guide's, or the
    // prediction itself), kept where it lands near the placement above (not on another sheet
    // or part): there the vertex's detail has no tangential part (a normal mesh).
    if (j <= options.normal_line_levels) {
      std::vector<double> predicted(x.begin(), x.begin() + 3 * std::ptrdiff_t{end});
      std::fill(predicted.begin() + 3 * std::ptrdiff_t{first}, predicted.end(), 0.0);
      synthesize_level(h, {Scheme::butterfly}, j - 1, predicted, 3);
      next.assign(3 * fresh.size(), 0.0);
      next_face.assign(fresh.size(), kNone);
      parallel_blocks(fresh.size(), threads, [&](std::size_t begin, std::size_t stop) {
        for (std::size_t i = begin; i < stop; ++i) {
          const std::uint32_t v = fresh[i];
          const Vec& n = frame_normal[v - first];
          if (adjacency.on_boundary(v) || n == Vec{0, 0, 0}) continue;
          const Vec p = at(x, v), start_from = j <= options.guide_levels ? at(guide, v) : at(predicted, v);
          const double reach = adjacency.mean_edge_length(x, v);  // the scale of the vertex's moves
          const Vec q = at(predicted, v);
          const double height = dot(sub(start_from, q), n);
          const SurfacePoint s = shoot(surface, {q[0] + height * n[0], q[1] + height * n[1], q[2] + height * n[2]}, n, 2 * reach);
          if (s.face == kNone) continue;
          const Vec moved = sub(s.point, p);
          if (dot(moved, moved) > reach * reach || stray(v, s.point)) continue;
          next[3 * i] = s.point[0], next[3 * i + 1] = s.point[1], next[3 * i + 2] = s.point[2];
          next_face[i] = s.face;
        }
      });
      // Moved vertices keep their placement above to undo with; a face that faced the input
      // and would face away after the moves gets its moved corners back, until none does.
      std::vector<std::uint8_t> folded_before(triangles.size() / 3);
      for (std::size_t f = 0; f < folded_before.size(); ++f) folded_before[f] = folded(f);
      std::vector<double> old_position(3 * fresh.size());
      std::vector<std::uint32_t> old_face(fresh.size());
      for (std::size_t i = 0; i < fresh.size(); ++i) {
        const std::uint32_t v = fresh[i];
        for (int c = 0; c < 3; ++c) old_position[3 * i + c] = x[3 * v + c];
        old_face[i] = face_of[v];
        if (next_face[i] == kNone) continue;
        for (int c = 0; c < 3; ++c) x[3 * v + c] = next[3 * i + c];
        face_of[v] = next_face[i];
      }
      for (bool changed = true; changed;) {
        changed = false;
        for (std::size_t f = 0; f < folded_before.size(); ++f) {
          if (folded_before[f] || !folded(f)) continue;
          for (int k = 0; k < 3; ++k) {
            const std::uint32_t v = triangles[3 * f + k];
            if (v < first || fresh_index[v - first] == kNone || next_face[fresh_index[v - first]] == kNone) continue;
            const std::size_t i = fresh_index[v - first];
            for (int c = 0; c < 3; ++c) x[3 * v + c] = old_position[3 * i + c];
            face_of[v] = old_face[i];
            next_face[i] = kNone;
            changed = true;
          }
        }
      }
    }

    // Untangling: the corners of folded faces and their neighbours (base vertices excepted)
    // take full umbrella steps until no face of the level is folded, or the count stops falling.
    std::size_t best = SIZE_MAX;
    for (int attempt = 0, stalled = 0; attempt < options.untangle_rounds && stalled < 5; ++attempt) {
      std::vector<std::uint8_t> marked(end, 0);
      std::size_t folded_faces = 0;
      for (std::size_t f = 0; f < triangles.size() / 3; ++f) {
        if (!folded(f)) continue;
        ++folded_faces;
        const std::uint32_t* t = &triangles[3 * f];
        for (int i = 0; i < 3; ++i) {
          marked[t[i]] = 1;
          for (std::uint32_t k = adjacency.neighbour_offsets[t[i]]; k < adjacency.neighbour_offsets[t[i] + 1]; ++k)
            marked[adjacency.neighbours[k]] = 1;
        }
      }
      if (folded_faces == 0) break;
      stalled = folded_faces < best ? 0 : stalled + 1;
      best = std::min(best, folded_faces);
      std::vector<std::uint32_t> tangled;
      for (std::uint32_t v = h.vertex_count(0); v < end; ++v)
        if (marked[v] && !is_fixed(v)) tangled.push_back(v);
      round(tangled, true, 1.0);
    }
  }
}

std::vector<std::array<double, 3>> edge_frame_normals(const TriangleTopology& coarse, std::span<const double> x) {
  std::vector<Vec> area_normal(coarse.vertex_count, Vec{0, 0, 0});
  for (std::size_t f = 0; f < coarse.triangles.size() / 3; ++f) {
    const Vec fn = face_normal(x, &coarse.triangles[3 * f]);
    for (int i = 0; i < 3; ++i)
      for (int c = 0; c < 3; ++c) area_normal[coarse.triangles[3 * f + i]][c] += fn[c];
  }
  std::vector<Vec> normals(coarse.edge_count());
  for (std::size_t e = 0; e < coarse.edge_count(); ++e) {
    const Vec& na = area_normal[coarse.edge_vertices[2 * e]];
    const Vec& nb = area_normal[coarse.edge_vertices[2 * e + 1]];
    const Vec n{na[0] + nb[0], na[1] + nb[1], na[2] + nb[2]};
    const double length = std::sqrt(dot(n, n));
    normals[e] = length > 0 && std::isfinite(length) ? Vec{n[0] / length, n[1] / length, n[2] / length} : Vec{0, 0, 0};
  }
  return normals;
}

bool faces_away(std::span<const double> x, const std::uint32_t* t, const SurfaceQuery& surface, std::uint32_t* hint,
                SurfacePoint* closest) {
  const Vec a = at(x, t[0]), b = at(x, t[1]), c = at(x, t[2]);
  const SurfacePoint s = surface.closest({(a[0] + b[0] + c[0]) / 3, (a[1] + b[1] + c[1]) / 3, (a[2] + b[2] + c[2]) / 3},
                                         hint ? *hint : kNone);
  if (hint) *hint = s.face;
  if (closest) *closest = s;
  const TriangleMesh& input = surface.mesh();
  return dot(cross(sub(b, a), sub(c, a)), face_normal(input.positions, &input.triangles[3 * std::size_t{s.face}])) < 0;
}

std::size_t count_at_crossings(const TriangleMesh& remeshed, std::span<const std::uint32_t> flipped,
                               const SurfaceQuery& surface, std::span<const std::uint8_t> crossing) {
  std::size_t count = 0;
  for (const std::uint32_t f : flipped)
    count += closest_is_marked(remeshed.positions, &remeshed.triangles[3 * std::size_t{f}], surface, crossing);
  return count;
}

std::size_t count_turned_over(const TriangleMesh& remeshed, std::span<const std::uint32_t> faces) {
  if (faces.empty()) return 0;
  const Adjacency adjacency(static_cast<std::uint32_t>(remeshed.vertex_count()), remeshed.triangles);
  std::size_t count = 0;
  for (const std::uint32_t f : faces) {
    const std::uint32_t* t = &remeshed.triangles[3 * std::size_t{f}];
    const Vec normal = face_normal(remeshed.positions, t);
    bool turned = false;
    // The faces across each edge (a, b): those around a that also have b as a corner.
    for (int i = 0; i < 3 && !turned; ++i) {
      const std::uint32_t a = t[i], b = t[(i + 1) % 3];
      for (std::uint32_t k = adjacency.face_offsets[a]; k < adjacency.face_offsets[a + 1] && !turned; ++k) {
        const std::uint32_t g = adjacency.faces[k];
        const std::uint32_t* u = &remeshed.triangles[3 * std::size_t{g}];
        if (g == f || (u[0] != b && u[1] != b && u[2] != b)) continue;
        turned = dot(normal, face_normal(remeshed.positions, u)) < 0;
      }
    }
    count += turned;
  }
  return count;
}

bool closest_is_marked(std::span<const double> x, const std::uint32_t* t, const SurfaceQuery& surface,
                       std::span<const std::uint8_t> marked) {
  std::uint32_t closest = kNone;
  faces_away(x, t, surface, &closest);
  return closest < marked.size() && marked[closest] != 0;
}

bool is_degenerate(const std::array<double, 3>& normal, double diagonal) {
  return 0.5 * std::sqrt(dot(normal, normal)) <= 1e-14 * diagonal * diagonal;
}

bool is_folded(std::span<const double> x, const std::uint32_t* t, const SurfaceQuery& surface, double diagonal,
               std::uint32_t* hint, SurfacePoint* closest) {
  return is_degenerate(face_normal(x, t), diagonal) || faces_away(x, t, surface, hint, closest);
}

FoldOvers find_fold_overs(const TriangleMesh& remeshed, const SurfaceQuery& surface) {
  const double diagonal = bounding_box_diagonal(remeshed.positions);
  enum : std::uint8_t { kGood, kDegenerate, kFlipped };
  std::vector<std::uint8_t> kind(remeshed.face_count());
  parallel_blocks(kind.size(), 0, [&](std::size_t begin, std::size_t end) {
    std::uint32_t hint = kNone;  // consecutive faces are neighbours in a semi-regular mesh
    for (std::size_t f = begin; f < end; ++f) {
      const std::uint32_t* t = &remeshed.triangles[3 * f];
      const Vec n = face_normal(remeshed.positions, t);
      kind[f] = is_degenerate(n, diagonal) ? kDegenerate
                : faces_away(remeshed.positions, t, surface, &hint) ? kFlipped
                                                                    : kGood;
    }
  });
  FoldOvers result;
  for (std::size_t f = 0; f < kind.size(); ++f)
    if (kind[f] != kGood) (kind[f] == kDegenerate ? result.degenerate : result.flipped).push_back(static_cast<std::uint32_t>(f));
  return result;
}

FoldOvers round_to_float(SemiRegularMesh& mesh, const SurfaceQuery& surface) {
  std::vector<double>& x = mesh.positions;
  const std::vector<std::uint32_t>& triangles = mesh.hierarchy.triangles(mesh.hierarchy.levels());
  const std::vector<double> exact = x;
  for (double& c : x) c = static_cast<float>(c);
  const double diagonal = bounding_box_diagonal(x);  // find_fold_overs()'s, of the rounded mesh
  auto folds = [&](std::span<const double> at, std::uint32_t f) {
    return is_folded(at, &triangles[3 * std::size_t{f}], surface, diagonal);
  };
  FoldOvers stored = find_fold_overs(mesh.finest(), surface);
  std::vector<std::uint32_t> rounding_folded;  // folded once rounded, not in double
  for (const auto* list : {&stored.flipped, &stored.degenerate})
    for (const std::uint32_t f : *list)
      if (!folds(exact, f)) rounding_folded.push_back(f);
  if (!rounding_folded.empty()) {
    const Adjacency adjacency(mesh.hierarchy.vertex_count(mesh.hierarchy.levels()), triangles);
    for (const std::uint32_t f : rounding_folded) {
      if (!folds(x, f)) continue;  // mended with a neighbour
      const std::uint32_t* t = &triangles[3 * std::size_t{f}];
      std::vector<std::uint32_t> around;  // the corners' faces (f too) that do not fold in double
      for (int i = 0; i < 3; ++i)
        for (std::uint32_t k = adjacency.face_offsets[t[i]]; k < adjacency.face_offsets[t[i] + 1]; ++k)
          if (const std::uint32_t g = adjacency.faces[k];
              std::find(around.begin(), around.end(), g) == around.end() && !folds(exact, g))
            around.push_back(g);
      // Coordinate i (0..8) of the face: corner i / 3, axis i % 3; bit i of `other` rounds it to
      // the float on the other side of its exact value.
      auto at = [&](int i) { return 3 * std::size_t{t[i / 3]} + static_cast<std::size_t>(i % 3); };
      double before[9];
      for (int i = 0; i < 9; ++i) before[i] = x[at(i)];  // a corner an earlier face's mend moved, too
      bool mended = false;
      for (unsigned other = 1; other < 512 && !mended; ++other) {
        for (int i = 0; i < 9; ++i) {
          const double e = exact[at(i)];
          const float nearest = static_cast<float>(e);
          const float beyond = std::nextafter(nearest, e < nearest ? -std::numeric_limits<float>::infinity()
                                                                    : std::numeric_limits<float>::infinity());
          x[at(i)] = (other >> i & 1) != 0 && nearest != e ? beyond : nearest;
        }
        mended = std::none_of(around.begin(), around.end(), [&](std::uint32_t g) { return folds(x, g); });
      }
      if (!mended)
        for (int i = 0; i < 9; ++i) x[at(i)] = before[i];
    }
    stored = find_fold_overs(mesh.finest(), surface);
  }
  return stored;
}

}  // namespace meshlift
