// The semi-regular hierarchy (CODEC-NOTES §1, seed 003 §5.1): a base mesh refined L times by
// 1:4 splits, vertices numbered level by level so that the mesh of level j uses exactly the
// vertex range [0, vertex_count(j)).
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <utility>
#include <vector>

#include "meshlift/mesh.h"
#include "meshlift/topology.h"

namespace meshlift {

/// Hard cap on refinement levels (4^L faces per base face).
inline constexpr int kMaxLevels = 12;

/// Element counts after `levels` 1:4 refinements of `base`: V' = V + E, E' = 2E + 3F, F' = 4F.
/// Doubles, so that absurd level counts can be checked before anything is allocated.
struct RefinedSize {
  double vertices, edges, faces;
};
RefinedSize refined_size(const TriangleTopology& base, int levels);

class SemiRegularHierarchy {
 public:
  /// \pre base is a manifold triangle topology; 0 <= levels <= kMaxLevels.
  /// \throw MeshError if levels is out of range or the refined mesh would exceed 2^32 - 1 vertices.
  /// `finest_triangles` false leaves out the finest level's faces, the largest array (24 bytes per
  /// finest vertex): for a caller that needs them only once, at the end, from copy_triangles()
  /// (a decoder's output); triangles(levels()) then throws std::logic_error.
  /// `coefficient_tree` false leaves out the stored children of children() (4 bytes per vertex):
  /// for a caller that does not ask for them (the codec's coder reads the tree off the
  /// topologies); children() then throws std::logic_error.
  /// `topology_below_finest` false leaves out topology(levels() - 1) when levels() >= 2 (48 bytes
  /// per vertex of that level; with the finest faces also left out, the hierarchy then holds
  /// levels up to levels() - 2 only): for a caller that reads that level off the level below by
  /// the refinement rule (the decoder's Loop synthesis and local frames). topology(levels() - 1)
  /// and triangles(levels() - 1) then throw std::logic_error; copy_triangles() and
  /// release_finest_triangles() make the faces of both upper levels from levels() - 2.
  SemiRegularHierarchy(TriangleTopology base, int levels, bool finest_triangles, bool coefficient_tree,
                       bool topology_below_finest);
  SemiRegularHierarchy(TriangleTopology base, int levels, bool finest_triangles = true, bool coefficient_tree = true)
      : SemiRegularHierarchy(std::move(base), levels, finest_triangles, coefficient_tree, true) {}

  int levels() const { return static_cast<int>(vertex_counts_.size()) - 1; }
  /// Number of vertices of the mesh at `level` (levels 0..levels()).
  std::uint32_t vertex_count(int level) const { return vertex_counts_[level]; }
  /// Connectivity of the mesh at `level` < levels() (and of the base when levels() == 0): the
  /// edges that level's stencils need. The finest level keeps only its triangles (its edges would
  /// be the largest arrays and nothing reads them): use triangles() for it.
  const TriangleTopology& topology(int level) const;
  /// Whether topology(level) is held (see the constructor's topology_below_finest).
  bool has_topology(int level) const { return level >= 0 && level < static_cast<int>(topologies_.size()); }
  /// Faces of the mesh at `level` (0..levels()), 3 indices each.
  const std::vector<std::uint32_t>& triangles(int level) const;
  /// The same as a new array, made from the level below if this hierarchy does not keep them.
  std::vector<std::uint32_t> copy_triangles(int level) const;
  /// The finest level's faces, moved out or made, after releasing everything else this hierarchy
  /// holds that making them does not need: a decoder's last use of its hierarchy, at the least
  /// memory (the faces and 12 bytes per finest vertex of level levels() - 1 at the peak, instead
  /// of the whole hierarchy). The hierarchy is empty afterwards.
  std::vector<std::uint32_t> release_finest_triangles() &&;
  /// copy_triangles() and release_finest_triangles() into `out`, whose storage is kept if it can
  /// hold the faces (for a caller that hands the same array over again and again, decode_into),
  /// except where the faces are held already: then `out` takes the held storage.
  void copy_triangles(int level, std::vector<std::uint32_t>& out) const;
  void release_finest_triangles(std::vector<std::uint32_t>& out) &&;
  /// The level a vertex first appears on.
  int level_of(std::uint32_t vertex) const;

  /// The odd vertex of level j+1 on edge e of level j is vertex_count(j) + e; its endpoints:
  std::uint32_t odd_vertex(int level, std::uint32_t edge) const { return vertex_count(level) + edge; }

  /// Coefficient tree (PGC): parent of an odd vertex of level >= 2 is the odd vertex on the
  /// coarser edge its edge came from (a half of it, or an inner edge parallel to it);
  /// kNone for base vertices and level-1 odd vertices (the tree roots). Computed, not stored.
  std::uint32_t parent(std::uint32_t vertex) const;
  /// Children of a vertex in the coefficient tree, in ascending order (4 for an interior edge's
  /// odd vertex, 3 on a boundary; none for base vertices and the finest level).
  /// \throw std::logic_error if this hierarchy was built without its coefficient tree.
  std::span<const std::uint32_t> children(std::uint32_t vertex) const;

  /// Bytes held by this hierarchy (topologies and tree).
  std::size_t memory_bytes() const;

 private:
  std::vector<std::uint32_t> vertex_counts_;
  std::vector<TriangleTopology> topologies_;  ///< levels 0 .. levels() - 1
  std::vector<std::uint32_t> finest_triangles_;  ///< faces of level levels() >= 1 (if kept)
  bool has_finest_triangles_ = true;
  bool has_children_ = true;
  /// 4 slots per vertex of levels 1 .. levels() - 1 (from vertex_count(0) on): its children, the
  /// 4th kNone for a boundary edge's vertex. Fixed slots need no offsets array.
  std::vector<std::uint32_t> children_;
};

/// Values carried per vertex along with the geometry and coded by the same wavelets and coder
/// (a scalar function, a colour; FORMAT.md §3, §5): `components` values per vertex, vertex-major,
/// for the same vertices in the same order as the positions they go with.
struct VertexChannel {
  int components = 1;
  std::vector<double> values;
  /// The vertices' colour: red, green, blue in [0, 1] (3 components; the first channel only).
  /// A stream marks it (FORMAT.md §3, flag bit 3), so that a decoder knows what the values are.
  bool colour = false;
};

/// A semi-regular mesh: hierarchy plus positions of the finest level (xyz, ordered by level),
/// and optionally extra per-vertex channels.
struct SemiRegularMesh {
  SemiRegularHierarchy hierarchy;
  std::vector<double> positions;
  std::vector<VertexChannel> channels;

  /// The triangle mesh of `level` (positions of its vertices taken from `values`, which must hold
  /// at least vertex_count(level) xyz triples: e.g. the output of a synthesis stopped at `level`).
  TriangleMesh mesh_at(int level, std::span<const double> values) const;
  TriangleMesh finest() const { return mesh_at(hierarchy.levels(), positions); }
};

/// Regular refinement of a base triangle mesh: the hierarchy, and the finest positions by
/// midpoint (linear) subdivision. Other schemes: synthesize with zero details.
SemiRegularMesh refine_linear(const TriangleMesh& base, int levels);

}  // namespace meshlift

namespace meshlift {

/// Recovers the hierarchy of a mesh whose vertices and faces are in meshlift's own level order
/// (as `refine_linear`, `meshlift subdivide` and the decoder write them): the base corners are
/// read off the finest faces, the base is refined, and the result must reproduce the faces
/// exactly. Returns the mesh with the most levels that does; nullopt if none (levels >= 1).
std::optional<SemiRegularMesh> recover_level_ordered(const TriangleMesh& mesh);

}  // namespace meshlift
