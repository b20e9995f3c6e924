// Vertex adjacency of a triangle list. See adjacency.h.
#include "adjacency.h"

#include <algorithm>
#include <cmath>

#include "vec3.h"

namespace meshlift {

Adjacency::Adjacency(std::uint32_t vertices, const std::vector<std::uint32_t>& triangles) {
  face_offsets.assign(vertices + 1, 0);
  for (std::uint32_t v : triangles) ++face_offsets[v + 1];
  for (std::uint32_t v = 0; v < vertices; ++v) face_offsets[v + 1] += face_offsets[v];
  faces.resize(triangles.size());
  std::vector<std::uint32_t> fill(face_offsets.begin(), face_offsets.end() - 1);
  for (std::size_t f = 0; f < triangles.size() / 3; ++f)
    for (int i = 0; i < 3; ++i) faces[fill[triangles[3 * f + i]]++] = static_cast<std::uint32_t>(f);
  // Neighbours (sorted): every face around v names two of them; a neighbour named by one face
  // only is across a boundary edge.
  neighbour_offsets.assign(vertices + 1, 0);
  boundary_neighbour_offsets.assign(vertices + 1, 0);
  std::vector<std::uint32_t> ring;
  for (std::uint32_t v = 0; v < vertices; ++v) {
    ring.clear();
    for (std::uint32_t k = face_offsets[v]; k < face_offsets[v + 1]; ++k) {
      const std::uint32_t f = faces[k];
      int i = 0;
      while (triangles[3 * f + i] != v) ++i;
      const std::uint32_t next = triangles[3 * f + (i + 1) % 3], prev = triangles[3 * f + (i + 2) % 3];
      ring.push_back(next), ring.push_back(prev);
    }
    std::sort(ring.begin(), ring.end());
    for (std::size_t k = 0; k < ring.size(); ++k) {
      if (k > 0 && ring[k] == ring[k - 1]) continue;
      neighbours.push_back(ring[k]);
      if (k + 1 == ring.size() || ring[k + 1] != ring[k]) boundary_neighbours.push_back(ring[k]);  // in one face only
    }
    neighbour_offsets[v + 1] = static_cast<std::uint32_t>(neighbours.size());
    boundary_neighbour_offsets[v + 1] = static_cast<std::uint32_t>(boundary_neighbours.size());
  }
}

double Adjacency::mean_edge_length(std::span<const double> x, std::uint32_t v) const {
  double mean = 0;
  const double count = neighbour_offsets[v + 1] - neighbour_offsets[v];
  for (std::uint32_t k = neighbour_offsets[v]; k < neighbour_offsets[v + 1]; ++k) {
    const vec3::Vec3 d = vec3::sub(vec3::at(x, neighbours[k]), vec3::at(x, v));
    mean += std::sqrt(vec3::dot(d, d)) / count;
  }
  return mean;
}

}  // namespace meshlift
