// The base mesh of the remeshing stage, by quadric-error halfedge collapse (seed 002 §8.3.5,
// Garland & Heckbert 1997) through OpenMesh's Decimater.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "meshlift/mesh.h"

namespace meshlift {

struct FeatureLines;

struct DecimateOptions {
  /// Vertices the base mesh should keep (counting only vertices that some face uses).
  /// 0 chooses automatically so that `levels` Loop refinements of the base (each roughly
  /// quadruples the vertex count) give about as many vertices as the input has:
  ///   target = max(ceil(V_input / 4^levels), Σ_components min(V_c, 8 + 6·genus_c + 3·loops_c)).
  /// The per-component floor leaves each handle and each boundary loop a few vertices to be
  /// shaped by (a torus needs 7 vertices at least; 8 + 6·genus is a comfortable margin).
  std::size_t target_vertices = 0;
  /// Refinement levels the base will get (only used by the automatic target); 0..15.
  int levels = 4;
  /// A collapse is refused when a face around the removed vertex would turn by more than this
  /// angle, in degrees, relative to its normal *before that collapse* (OpenMesh's
  /// ModNormalFlippingT: per collapse, not accumulated against the input). In (0, 180].
  double max_normal_deviation_degrees = 60;
  /// OpenMesh ModAspectRatioT's threshold. A triangle's aspect ratio is its longest edge divided
  /// by the height onto that edge (2/√3 ≈ 1.155 for an equilateral triangle, growing without
  /// bound for slivers). A collapse is refused when the worst ratio among the faces around the
  /// removed vertex after the collapse exceeds this value *and* is worse than the worst ratio
  /// there before (collapses that improve bad triangles stay allowed). Despite the name it is an
  /// upper bound on the ratio; OpenMesh calls it "min aspect" because it stores 1/ratio. >= 1.
  double min_aspect_ratio = 5;
  /// Feature lines of the input to keep (features.h; over the input's vertices), or none. Their
  /// corners stay in the base, and their other vertices collapse only along them, so the base
  /// keeps each line as a chain of its own vertices. Not owned: must outlive the call.
  const FeatureLines* feature_lines = nullptr;
  /// Input vertices the base must keep (never collapsed away); each below the input's vertex
  /// count. remesh() keeps those of parts a first remesh missed.
  std::vector<std::uint32_t> keep{};
};

struct DecimateResult {
  /// The decimated mesh: manifold, consistently oriented like the input, same genus and
  /// boundary loops per component. Vertices keep their input positions exactly.
  TriangleMesh base;
  /// For each base vertex, the index of the input vertex it is (halfedge collapses keep a subset
  /// of the vertices), increasing with the base index.
  std::vector<std::uint32_t> original_vertex;
  /// Collapses performed (= referenced input vertices − base vertices).
  std::size_t collapses = 0;
};

/// Decimates `mesh` by halfedge collapses v0 → v1 (v0 is removed, v1 keeps its position), the
/// cheapest first by the quadric error of v1's position against the planes of the faces that
/// v0 and v1 have absorbed (Garland & Heckbert 1997), with boundary-edge constraint planes
/// (perpendicular to the face, through the edge) so boundaries keep their shape.
///
/// Collapses are refused when they would
/// - change the topology (OpenMesh's link condition, is_collapse_ok, and no collapse of a
///   tetrahedron): genus and component count are kept, boundary loops keep >= 3 vertices;
/// - move a boundary vertex off the boundary (a boundary vertex only collapses along a boundary
///   edge into its boundary neighbour), so boundary loops are kept in their input order;
/// - bring a component below min(V_c, 4) vertices, or below its topological floor (see
///   DecimateOptions::target_vertices) when the target is automatic;
/// - make a face whose normal is at 90° or more from the input's area-weighted vertex normal at
///   one of its corners (so no face of the base is turned away from the input surface where its
///   corners are; faces taken over unchanged from the input are not judged);
/// - turn a face too far in one collapse or create a sliver (see DecimateOptions).
/// It stops at the target or when no collapse is allowed any more, whichever comes first, so
/// the base may keep more vertices than asked for. Isolated input vertices are dropped.
/// Deterministic: the same input gives the same output.
///
/// \throw MeshError with first_problem_for_triangle_codec()'s message if the input is not a
///        manifold, consistently oriented triangle mesh with finite coordinates.
/// \throw std::invalid_argument if an option is out of its range.
DecimateResult decimate(const TriangleMesh& mesh, const DecimateOptions& options = {});

/// decimate() with target_vertices = each of `targets` (> 0, in any order), one result per
/// target in their order, from one run: the collapses towards a smaller target go on from those
/// that made a larger one, exactly as decimate() would make them (the decimater takes its
/// collapses in the same order whatever its target), so each result is decimate()'s, byte for
/// byte, for the cost of one decimation to the smallest target. options.target_vertices is
/// ignored. \throw as decimate(), and std::invalid_argument for a target of 0.
std::vector<DecimateResult> decimate_each(const TriangleMesh& mesh, const DecimateOptions& options,
                                          std::span<const std::size_t> targets);

/// The automatic target of DecimateOptions::target_vertices for `mesh` and `levels`.
/// \throw as decimate().
std::size_t automatic_base_vertices(const TriangleMesh& mesh, int levels);

}  // namespace meshlift
