// Loop and Catmull-Clark limit-point stencils (CODEC-NOTES §5, seeds 004 and 000).
#include "meshlift/limit.h"

#include <cmath>
#include <stdexcept>
#include <string>

#include "meshlift/lifting.h"
#include "meshlift/polygon_subdivision.h"

namespace meshlift {

namespace {

// Cubic B-spline limit mask (seed 004 eigen-analysis): v∞ = (b1 + 4 v + b2) / 6.
void append_boundary_row(LimitStencil& stencil, const PolygonMesh& mesh, const PolygonTopology& topology,
                         std::uint32_t v) {
  const std::uint32_t start = topology.outgoing[v];
  std::uint32_t last = start;
  while (topology.rotate(last) != kNone) last = topology.rotate(last);
  const std::uint32_t b1 = mesh.face_indices[topology.next[start]];
  const std::uint32_t b2 = mesh.face_indices[topology.prev[last]];
  stencil.indices.insert(stencil.indices.end(), {v, b1, b2});
  stencil.weights.insert(stencil.weights.end(), {4.0 / 6.0, 1.0 / 6.0, 1.0 / 6.0});
}

void append_isolated_row(LimitStencil& stencil, std::uint32_t v) {
  stencil.indices.push_back(v);
  stencil.weights.push_back(1.0);
}

void close_row(LimitStencil& stencil) {
  stencil.row_offsets.push_back(static_cast<std::uint32_t>(stencil.indices.size()));
}

void check_sizes(const LimitStencil& stencil, std::span<const double> control, std::span<double> limit) {
  const std::size_t expected = 3 * stencil.vertex_count();
  if (control.size() != expected || limit.size() != expected)
    throw std::invalid_argument("limit stencil: expected " + std::to_string(expected) + " coordinates, got " +
                                std::to_string(control.size()) + " in and " + std::to_string(limit.size()) + " out");
}

/// One row per vertex: isolated and boundary vertices by the shared rules above, an interior
/// vertex by `interior(stencil, v, start)`, which appends its entries walking the fan from
/// half-edge `start`.
template <class InteriorRow>
LimitStencil build_rows(const PolygonMesh& mesh, const PolygonTopology& topology, std::size_t entries,
                        InteriorRow interior) {
  LimitStencil stencil;
  const std::size_t vertex_count = mesh.vertex_count();
  stencil.row_offsets.reserve(vertex_count + 1);
  stencil.indices.reserve(entries);
  stencil.weights.reserve(entries);
  for (std::uint32_t v = 0; v < vertex_count; ++v) {
    const std::uint32_t start = topology.outgoing[v];
    if (start == kNone)
      append_isolated_row(stencil, v);
    else if (topology.boundary[v])
      append_boundary_row(stencil, mesh, topology, v);
    else
      interior(stencil, v, start);
    close_row(stencil);
  }
  return stencil;
}

}  // namespace

void LimitStencil::apply(std::span<const double> control, std::span<double> limit) const {
  check_sizes(*this, control, limit);
  const std::size_t rows = vertex_count();
  for (std::size_t v = 0; v < rows; ++v) {
    double sum[3] = {0, 0, 0};
    for (std::uint32_t r = row_offsets[v]; r < row_offsets[v + 1]; ++r) {
      const double w = weights[r];
      const double* c = control.data() + 3 * std::size_t{indices[r]};
      for (int k = 0; k < 3; ++k) sum[k] += w * c[k];
    }
    for (int k = 0; k < 3; ++k) limit[3 * v + k] = sum[k];
  }
}

LimitStencil loop_limit_stencil(const TriangleMesh& mesh) {
  if (mesh.triangles.size() % 3 != 0) throw MeshError("mesh: triangle index array length is not a multiple of 3");
  const PolygonMesh polygons = to_polygon_mesh(mesh);
  const PolygonTopology topology = build_topology(polygons);

  // Interior weights per valence n, computed once each (CODEC-NOTES §5, correcting seed 004):
  // v∞ = (3 v + 8β_n Σ v_i) / (3 + 8nβ_n), β_n = (1/n)(5/8 − (3/8 + ¼ cos(2π/n))²).
  struct Weights {
    double self, ring;
  };
  std::vector<Weights> table;
  auto weights_for = [&table](std::uint32_t n) -> const Weights& {
    while (table.size() <= n) {
      const double k = static_cast<double>(table.size());
      if (k == 0) {
        table.push_back({1, 0});
        continue;
      }
      const double beta = loop_beta(static_cast<unsigned>(k));
      const double denominator = 3 + 8 * k * beta;
      table.push_back({3 / denominator, 8 * beta / denominator});
    }
    return table[n];
  };

  return build_rows(polygons, topology, mesh.vertex_count() + polygons.face_indices.size(),
                    [&](LimitStencil& stencil, std::uint32_t v, std::uint32_t start) {
                      const Weights& w = weights_for(topology.face_count_at[v]);
                      stencil.indices.push_back(v);
                      stencil.weights.push_back(w.self);
                      std::uint32_t h = start;
                      do {
                        stencil.indices.push_back(polygons.face_indices[topology.next[h]]);
                        stencil.weights.push_back(w.ring);
                        h = topology.rotate(h);
                      } while (h != start);
                    });
}

LimitStencil catmull_clark_limit_stencil(const PolygonMesh& quad_mesh) {
  const PolygonTopology topology = build_topology(quad_mesh);
  for (std::size_t f = 0; f < quad_mesh.face_count(); ++f)
    if (quad_mesh.face_size(f) != 4)
      throw MeshError("mesh: face " + std::to_string(f) + " has " + std::to_string(quad_mesh.face_size(f)) +
                      " corners; the Catmull-Clark limit stencil needs quads");

  // Interior weights per valence n, computed once each (seed 000, the limit formula after eq. 4):
  // v∞ = (n² v + 4 Σ e_i + Σ f_i) / (n(n+5)).
  struct Weights {
    double self, edge, diagonal;
  };
  std::vector<Weights> table;
  auto weights_for = [&table](std::uint32_t n) -> const Weights& {
    while (table.size() <= n) {
      const double k = static_cast<double>(table.size());
      const double denominator = k * (k + 5);
      table.push_back(k == 0 ? Weights{1, 0, 0} : Weights{k * k / denominator, 4 / denominator, 1 / denominator});
    }
    return table[n];
  };

  const auto& index = quad_mesh.face_indices;
  return build_rows(quad_mesh, topology, quad_mesh.vertex_count() + 2 * index.size(),
                    [&](LimitStencil& stencil, std::uint32_t v, std::uint32_t start) {
                      const Weights& w = weights_for(topology.face_count_at[v]);
                      stencil.indices.push_back(v);
                      stencil.weights.push_back(w.self);
                      std::uint32_t h = start;
                      do {
                        // Quad (v, e_i, f_i, e_{i+1}) seen from its half-edge h = (v -> e_i).
                        stencil.indices.insert(stencil.indices.end(),
                                               {index[topology.next[h]], index[topology.next[topology.next[h]]]});
                        stencil.weights.insert(stencil.weights.end(), {w.edge, w.diagonal});
                        h = topology.rotate(h);
                      } while (h != start);
                    });
}

TriangleMesh loop_limit(const TriangleMesh& mesh) {
  const LimitStencil stencil = loop_limit_stencil(mesh);
  TriangleMesh out = mesh;
  stencil.apply(mesh.positions, out.positions);
  return out;
}

PolygonMesh catmull_clark_limit(const PolygonMesh& mesh) {
  bool all_quads = true;
  for (std::size_t f = 0; f < mesh.face_count() && all_quads; ++f) all_quads = mesh.face_size(f) == 4;
  PolygonMesh out = all_quads ? mesh : catmull_clark(mesh, 1);
  const LimitStencil stencil = catmull_clark_limit_stencil(out);
  const std::vector<double> control = out.positions;
  stencil.apply(control, out.positions);
  return out;
}

void apply_loop_limit(const TriangleMesh& connectivity, std::span<const double> control, std::span<double> limit) {
  loop_limit_stencil(connectivity).apply(control, limit);
}

void apply_catmull_clark_limit(const PolygonMesh& connectivity, std::span<const double> control,
                               std::span<double> limit) {
  catmull_clark_limit_stencil(connectivity).apply(control, limit);
}

}  // namespace meshlift
