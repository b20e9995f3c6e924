// Vertex adjacency of a triangle list, shared by remesh/'s fitting stages (not installed).
#pragma once

#include <cstdint>
#include <span>
#include <vector>

namespace meshlift {

/// Vertex -> incident faces (in face order) and vertex -> neighbours (sorted, each once) of a
/// triangle list (CSR), plus which neighbours are across a boundary edge.
struct Adjacency {
  std::vector<std::uint32_t> face_offsets, faces;
  std::vector<std::uint32_t> neighbour_offsets, neighbours;
  std::vector<std::uint32_t> boundary_neighbour_offsets, boundary_neighbours;

  Adjacency(std::uint32_t vertices, const std::vector<std::uint32_t>& triangles);
  /// Mean distance from v to its neighbours in the xyz array x (0 for a vertex without any).
  double mean_edge_length(std::span<const double> x, std::uint32_t v) const;
  bool on_boundary(std::uint32_t v) const { return boundary_neighbour_offsets[v + 1] > boundary_neighbour_offsets[v]; }
};

}  // namespace meshlift
