// Feature lines (creases) of the input, kept through the decimation remesh: the base mesh keeps
// their vertices in order along them (decimate.h), and the semi-regular mesh's vertices on the
// refined base edges that follow them are placed on them, evenly by arc length, and stay there
// (remesh.cpp). Without them the remesh's edges cut across the creases of CAD meshes (fandisk),
// and the error sits along every crease at every density.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "meshlift/mesh.h"
#include "meshlift/semi_regular.h"
#include "meshlift/topology.h"

namespace meshlift {

/// The input's feature edges as a graph: per vertex, its neighbours along feature edges (CSR).
/// A corner, which the decimation keeps, is a vertex with one (a line's end) or three or more
/// (where lines meet), or a kink (find_feature_lines); the other vertices with two are inside a
/// line.
struct FeatureLines {
  std::vector<std::uint32_t> offsets{0}, neighbours;
  std::vector<std::uint8_t> kink;  ///< per vertex (or empty): 1 for a kink with two neighbours

  /// The graph of the undirected `edges` (each once) over `vertices` vertices, neighbours
  /// sorted, no kinks.
  static FeatureLines from_edges(std::size_t vertices, const std::vector<std::array<std::uint32_t, 2>>& edges);
  bool empty() const { return neighbours.empty(); }
  std::size_t edge_count() const { return neighbours.size() / 2; }
  std::uint32_t degree(std::uint32_t v) const { return v + 1 < offsets.size() ? offsets[v + 1] - offsets[v] : 0; }
  bool is_corner(std::uint32_t v) const {
    return degree(v) != 0 && (degree(v) != 2 || (v < kink.size() && kink[v] != 0));
  }
};

/// Feature edges of `mesh`: interior edges whose two faces' normals differ by more than
/// `min_angle_degrees`, kept only in chains of at least `min_chain_edges` edges. A chain runs
/// between corners of the graph of such edges and kinks (where it turns by more than
/// `max_turn_degrees`), or round a closed loop. Chain length and smoothness keep out the sharp
/// edges of scans and coarse organic meshes, which are noise, not lines. An empty result for
/// min_angle_degrees <= 0 or >= 180. \throw MeshError if `mesh` is not a manifold, consistently
/// oriented triangle mesh (TriangleTopology::build()).
/// The cosine of the angle between the unit normals of the two faces of each edge of
/// `topology` (built from `mesh`'s faces): 1 on a boundary edge or where either face has no
/// area (no turn to measure). find_feature_lines() and snap.h read their creases off it.
std::vector<double> edge_turn_cosines(const TriangleMesh& mesh, const TriangleTopology& topology);

FeatureLines find_feature_lines(const TriangleMesh& mesh, double min_angle_degrees, std::size_t min_chain_edges,
                                double max_turn_degrees = 180, double max_side_degrees = 180);

/// A base edge that follows a feature line: base vertices a and b, and the input polyline
/// between them (input vertex indices, from original_vertex[a] to original_vertex[b]).
struct BaseFeatureEdge {
  std::uint32_t a, b;
  std::vector<std::uint32_t> path;
};

/// The feature edges of a base decimated with `lines` kept (decimate.h): consecutive base
/// vertices along each line. `original_vertex` maps base vertices to input vertices (increasing).
std::vector<BaseFeatureEdge> base_feature_edges(const FeatureLines& lines, const std::vector<std::uint32_t>& original_vertex);

/// The semi-regular vertices that lie on the feature lines and where: the base vertices on a
/// line (their own positions), and every vertex the refinement makes on a base feature edge (at
/// the arc length of the input polyline that its place on the edge gives: the vertex k of the
/// 2^j − 1 that level j has made there sits at fraction k / 2^j of the polyline's length).
struct FeaturePlacement {
  std::vector<std::uint8_t> fixed;  ///< per vertex of the finest level: 1 if on a feature line
  std::vector<double> positions;    ///< xyz per vertex; meaningful where fixed
  std::size_t count() const;
};
FeaturePlacement place_on_features(const SemiRegularHierarchy& hierarchy, const TriangleMesh& input,
                                   const TriangleMesh& base, const std::vector<BaseFeatureEdge>& edges);

}  // namespace meshlift
