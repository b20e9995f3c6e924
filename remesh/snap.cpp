// Snapping a fitted remesh onto the input's corners and creases (snap.h).
#include "meshlift/snap.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <vector>

#include "meshlift/features.h"
#include "meshlift/surface_fit.h"
#include "meshlift/topology.h"
#include "adjacency.h"
#include "parallel.h"
#include "vec3.h"

namespace meshlift {

namespace {

using vec3::Vec3;
using vec3::triangle_area;

double squared(const Vec3& v) { return vec3::dot(v, v); }

// The quadrature points of snap.h: 4 per remesh face (vec3::kFourPoints), 7 per input face:
// barycentric weights, then the point's share of the area (corners 1/12, edge midpoints 1/6,
// centroid 1/4). Exact for linear functions: the corners and the midpoints each average to the
// centroid, so the shares sum to f(centroid) = the mean of f over the face.
constexpr double kSeven[7][4] = {{1, 0, 0, 1. / 12},     {0, 1, 0, 1. / 12},     {0, 0, 1, 1. / 12},        {.5, .5, 0, 1. / 6},
                                 {0, .5, .5, 1. / 6},    {.5, 0, .5, 1. / 6},    {1. / 3, 1. / 3, 1. / 3, .25}};

// A move that leaves a face around the vertex smaller than this times its mean edge length
// squared (an equilateral face is 0.43 of it) is refused.
constexpr double kSliverArea = 1e-3;

// A move must lower the local error (an area times a squared distance) by more than this
// fraction of it plus this times the mean edge length to the fourth: gains of rounding size (a
// vertex already on a crease, its target the same point to the last bits) are not moves.
constexpr double kNegligible = 1e-12;

Vec3 combine(const Vec3& a, const Vec3& b, const Vec3& c, const double* w) {
  return {w[0] * a[0] + w[1] * b[0] + w[2] * c[0], w[0] * a[1] + w[1] * b[1] + w[2] * c[1],
          w[0] * a[2] + w[1] * b[2] + w[2] * c[2]};
}

}  // namespace

SnapReport snap_to_input(SemiRegularMesh& mesh, const SurfaceQuery& surface, const SnapOptions& options) {
  if (!(options.reach > 0) || !(options.crease_degrees >= 0 && options.crease_degrees < 180) || options.passes < 0)
    throw std::invalid_argument("snap_to_input: reach must be > 0, crease_degrees in [0, 180) and passes >= 0");
  const TriangleMesh& input = surface.mesh();
  const std::vector<std::uint32_t>& triangles = mesh.hierarchy.triangles(mesh.hierarchy.levels());
  const auto vertices = static_cast<std::uint32_t>(mesh.hierarchy.vertex_count(mesh.hierarchy.levels()));
  if (!options.fixed.empty() && options.fixed.size() != vertices)
    throw std::invalid_argument("snap_to_input: fixed must have one entry per vertex");
  std::vector<double>& x = mesh.positions;
  const Adjacency adjacency(vertices, triangles);

  // Input creases, per face corner slot: the edge from corner i to corner i + 1 of face f.
  const TriangleTopology topology = TriangleTopology::build(static_cast<std::uint32_t>(input.vertex_count()), input.triangles);
  const std::vector<double> turn_cos = edge_turn_cosines(input, topology);
  const double cos_crease = std::cos(options.crease_degrees * std::numbers::pi / 180);
  std::vector<std::uint8_t> crease(topology.face_edges.size(), 0);
  for (std::size_t slot = 0; slot < crease.size(); ++slot) crease[slot] = turn_cos[topology.face_edges[slot]] < cos_crease;

  // Each input vertex's nearest remesh vertex (a corner of the remesh face closest to it), for
  // the "each the other's nearest" test, from the remesh as it is at the start of a pass.
  std::vector<std::uint32_t> nearest_of_input(input.vertex_count(), kNone);
  std::vector<char> used(input.vertex_count(), 0);
  for (const std::uint32_t v : input.triangles) used[v] = 1;
  auto find_nearest = [&] {
    const SurfaceQuery remeshed(mesh.finest());
    parallel_blocks(input.vertex_count(), options.threads, [&](std::size_t begin, std::size_t end) {
      std::uint32_t hint = kNone;
      for (auto v = static_cast<std::uint32_t>(begin); v < end; ++v) {
        if (!used[v]) continue;
        const Vec3 p = vec3::at(input.positions, v);
        const SurfacePoint on = remeshed.closest(p, hint);
        hint = on.face;
        double best = INFINITY;
        for (int i = 0; i < 3; ++i) {
          const std::uint32_t w = triangles[3 * std::size_t{on.face} + i];
          if (const double d = squared(vec3::sub(vec3::at(x, w), p)); d < best) best = d, nearest_of_input[v] = w;
        }
      }
    });
  };

  // What happened at each vertex.
  enum Outcome : std::uint8_t { kUntried, kStayed, kOntoVertex, kOntoCrease };
  // A worker's buffers, reused from vertex to vertex.
  struct Scratch {
    std::vector<std::uint32_t> near_faces;
    std::vector<std::pair<Vec3, double>> input_points;
    std::vector<char> was_away;
  };
  // Tries vertex v (snap.h); reads the positions of v's ring and writes v's alone.
  auto try_vertex = [&](std::uint32_t v, Scratch& scratch) -> Outcome {
    const std::span<const std::uint32_t> ring(&adjacency.faces[adjacency.face_offsets[v]],
                                              adjacency.face_offsets[v + 1] - adjacency.face_offsets[v]);
    const Vec3 p = vec3::at(x, v);
    const double edge = adjacency.mean_edge_length(x, v), reach = options.reach * edge;
    if (!(edge > 0)) return kUntried;

    // The target: the input vertex nearest v if v is its nearest too, else the nearest point of
    // a crease edge of the input face closest to v.
    const SurfacePoint on = surface.closest(p);
    const std::uint32_t* t = &input.triangles[3 * std::size_t{on.face}];
    const int corner = on.heaviest_corner();
    Vec3 target{};
    Outcome onto = kUntried;
    if (nearest_of_input[t[corner]] == v && squared(vec3::sub(vec3::at(input.positions, t[corner]), p)) < reach * reach) {
      target = vec3::at(input.positions, t[corner]);
      onto = kOntoVertex;
    } else {
      double best = reach * reach;
      for (int i = 0; i < 3; ++i) {
        if (!crease[3 * std::size_t{on.face} + i]) continue;
        const Vec3 a = vec3::at(input.positions, t[i]), b = vec3::at(input.positions, t[(i + 1) % 3]);
        const double along = vec3::closest_on_segment(p, a, b);
        const Vec3 q{a[0] + along * (b[0] - a[0]), a[1] + along * (b[1] - a[1]), a[2] + along * (b[2] - a[2])};
        if (const double d = squared(vec3::sub(q, p)); d < best) best = d, target = q, onto = kOntoCrease;
      }
    }
    if (onto == kUntried) return kUntried;
    // Already there (moved by an earlier pass): nothing to weigh.
    if (squared(vec3::sub(target, p)) <= kNegligible * edge * edge) return kStayed;

    // The local error (snap.h) at the current position and at the target, over the same input
    // faces: those closest to the ring's points now.
    auto ring_face = [&](std::uint32_t f) { return &triangles[3 * std::size_t{f}]; };
    // The squared distance from q to the ring, and whether its closest point there depends on v
    // (is off the rim: v's barycentric weight in that face is not zero).
    auto distance2_to_ring = [&](const Vec3& q, bool* moves_with_v = nullptr) {
      double best = INFINITY;
      for (const std::uint32_t f : ring) {
        const std::uint32_t* c = ring_face(f);
        const TrianglePoint on_face = closest_point_on_triangle(q, vec3::at(x, c[0]), vec3::at(x, c[1]), vec3::at(x, c[2]));
        if (const double d2 = squared(vec3::sub(on_face.point, q)); d2 < best) {
          best = d2;
          if (moves_with_v) *moves_with_v = on_face.barycentric[c[0] == v ? 0 : c[1] == v ? 1 : 2] > 0;
        }
      }
      return best;
    };
    // The ring's side: its points' squared distances to the input, weighted.
    auto ring_error = [&](std::vector<std::uint32_t>* closest_faces) {
      double sum = 0;
      std::uint32_t hint = on.face;
      for (const std::uint32_t f : ring) {
        const std::uint32_t* c = ring_face(f);
        const Vec3 a = vec3::at(x, c[0]), b = vec3::at(x, c[1]), d = vec3::at(x, c[2]);
        const double quarter = triangle_area(a, b, d) / 4;
        for (const auto& w : vec3::kFourPoints) {
          const SurfacePoint s = surface.closest(combine(a, b, d, w), hint);
          hint = s.face;
          sum += quarter * s.distance * s.distance;
          if (closest_faces) closest_faces->push_back(s.face);
        }
      }
      return sum;
    };
    std::vector<std::uint32_t>& near_faces = scratch.near_faces;
    near_faces.assign(1, on.face);
    double before = ring_error(&near_faces);
    std::sort(near_faces.begin(), near_faces.end());
    near_faces.erase(std::unique(near_faces.begin(), near_faces.end()), near_faces.end());
    // The input's side: points of those faces whose closest point on the ring is off its rim
    // (elsewhere the rim, which does not move, or the faces beyond it are closest), within one
    // mean edge length of it.
    std::vector<std::pair<Vec3, double>>& input_points = scratch.input_points;
    input_points.clear();
    for (const std::uint32_t f : near_faces) {
      const std::uint32_t* c = &input.triangles[3 * std::size_t{f}];
      const Vec3 a = vec3::at(input.positions, c[0]), b = vec3::at(input.positions, c[1]), d = vec3::at(input.positions, c[2]);
      const double area = triangle_area(a, b, d);
      for (const auto& w : kSeven) {
        const Vec3 q = combine(a, b, d, w);
        bool moves_with_v = false;
        if (const double d2 = distance2_to_ring(q, &moves_with_v); moves_with_v && d2 < edge * edge) {
          input_points.push_back({q, w[3] * area});
          before += w[3] * area * d2;
        }
      }
    }
    auto place = [&](const Vec3& at) {
      for (int k = 0; k < 3; ++k) x[3 * std::size_t{v} + k] = at[k];
    };
    place(target);
    double after = ring_error(nullptr);
    for (const auto& [q, weight] : input_points) after += weight * distance2_to_ring(q);
    if (!(after < before * (1 - kNegligible) - kNegligible * edge * edge * edge * edge)) {
      place(p);
      return kStayed;
    }
    // No face around v may turn away from the input (unless it did before the move), nor
    // collapse to a sliver of no area. Tested only for a move that lowers the error: most do not.
    std::vector<char>& was_away = scratch.was_away;
    was_away.resize(ring.size());
    place(p);
    for (std::size_t i = 0; i < ring.size(); ++i) was_away[i] = faces_away(x, ring_face(ring[i]), surface);
    place(target);
    for (std::size_t i = 0; i < ring.size(); ++i) {
      const std::uint32_t* c = ring_face(ring[i]);
      if ((!was_away[i] && faces_away(x, c, surface)) ||
          !(triangle_area(vec3::at(x, c[0]), vec3::at(x, c[1]), vec3::at(x, c[2])) > kSliverArea * edge * edge)) {
        place(p);
        return kStayed;
      }
    }
    return onto;
  };

  // Vertices that share no face are tried at once: a greedy colouring in vertex order (no two
  // neighbours alike), then colour by colour, each colour's vertices in parallel. A vertex reads
  // its ring only, whose other corners have other colours: the outcome does not depend on the
  // thread count.
  std::vector<std::uint8_t> colour(vertices, 0);
  std::vector<std::vector<std::uint32_t>> by_colour;
  for (std::uint32_t v = 0; v < vertices; ++v) {
    if (adjacency.on_boundary(v) || (!options.fixed.empty() && options.fixed[v])) continue;
    std::uint64_t taken = 0;  // colours of v's neighbours coloured so far (bit c: colour c - 1)
    for (std::uint32_t k = adjacency.neighbour_offsets[v]; k < adjacency.neighbour_offsets[v + 1]; ++k)
      if (const std::uint8_t c = colour[adjacency.neighbours[k]]; c > 0 && c <= 64) taken |= std::uint64_t{1} << (c - 1);
    const int c = std::countr_one(taken) + 1;  // a valence above 63 could exhaust 64 colours:
    if (c > 64) continue;                      // such a vertex is left where it is
    colour[v] = static_cast<std::uint8_t>(c);
    if (by_colour.size() < static_cast<std::size_t>(c)) by_colour.resize(c);
    by_colour[c - 1].push_back(v);
  }
  // Per vertex, its last move's kind, or whether it was ever tried.
  std::vector<Outcome> outcome(vertices, kUntried);
  for (int pass = 0; pass < options.passes; ++pass) {
    find_nearest();
    for (const std::vector<std::uint32_t>& group : by_colour)
      parallel_blocks(group.size(), options.threads, [&](std::size_t begin, std::size_t end) {
        Scratch scratch;
        for (std::size_t i = begin; i < end; ++i)
          if (const Outcome o = try_vertex(group[i], scratch); o != kUntried && !(o == kStayed && outcome[group[i]] > kStayed))
            outcome[group[i]] = o;
      });
  }
  SnapReport report;
  for (const Outcome o : outcome) {
    report.tried += o != kUntried;
    report.onto_vertices += o == kOntoVertex;
    report.onto_creases += o == kOntoCrease;
  }
  return report;
}

}  // namespace meshlift
