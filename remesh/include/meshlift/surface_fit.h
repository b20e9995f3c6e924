// Placing the vertices of a refined base mesh on the input surface (the fitting stage of
// remeshing, CODEC-NOTES §5): coarse to fine, each new level's vertices start on a smooth guide
// (or the butterfly prediction from the level below), are placed on the input by normal
// shooting, and folded faces are untangled; vertices of coarser levels stay where they were
// placed unless they are next to a fold. No fold-free guarantee: docs/RESULTS.md counts them.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <span>
#include <vector>

#include "meshlift/closest_point.h"
#include "meshlift/semi_regular.h"

namespace meshlift {

struct SurfaceFitOptions {
  /// Smoothing + projection rounds per level for that level's new vertices (>= 0). Off by
  /// default: measured, 4 rounds folded more faces (bumpy sphere: 26 instead of 0; armadillo,
  /// L = 4: 740 instead of 136) for +0.9 dB on armadillo and -2.4 to -3.4 dB on cow and fandisk.
  int relax_iterations = 0;
  /// Fraction of the tangential umbrella move applied per round, in (0, 1].
  double relax_step = 0.5;
  /// Most untangling rounds per level (full umbrella steps for the vertices around folded
  /// faces, until none is left); >= 0.
  int untangle_rounds = 50;
  /// Levels 1..guide_levels start their new vertices at the guide, the finer ones at the
  /// butterfly prediction from the level below (>= 0).
  int guide_levels = 1;
  /// Levels 1..normal_line_levels also try the normal-line placement (surface_fit.cpp): each new
  /// vertex shot along its codec frame normal (edge_frame_normals) from the line through its
  /// butterfly prediction, kept where it lands within a mean edge length of the placement by
  /// the vertex normal and folds no face that did not fold. Such a vertex's detail has no
  /// tangential part as placed. Measured (docs/RESULTS.md): level 1 is where the tangential details were
  /// (the guide's points are far off those lines), the finer levels gain nothing; >= 0.
  int normal_line_levels = 1;
  /// A new vertex placed farther than this many lengths of its edge from the edge's midpoint is
  /// placed again from the midpoint, or left there (surface_fit.cpp: strays); 0 turns it off;
  /// >= 0.
  double stray_distance = 2.0;
  /// Threads for the projections (results do not depend on it); 0 = hardware concurrency.
  unsigned threads = 0;
  std::function<void(double)> progress;
  /// Per vertex of the finest level, or empty: 1 where the vertex keeps its guide position (on a
  /// feature line, features.h): never placed, smoothed or untangled.
  std::span<const std::uint8_t> fixed;
};

/// Fills `mesh.positions` (all levels) from `guide`, one xyz triple per vertex of the finest
/// level: guide positions, smooth, near the surface, whose base vertices lie on it. Base
/// vertices keep their guide positions; every other vertex ends on the surface of `surface`.
/// \throw std::invalid_argument if guide has the wrong size or an option is out of range.
void fit_to_surface(SemiRegularMesh& mesh, std::span<const double> guide, const SurfaceQuery& surface,
                    const SurfaceFitOptions& options = {});

/// The unit normal of the codec's local frame (FORMAT.md §5) for the new vertex on each edge of
/// `coarse`, from the positions x of its vertices: the sum of the area-weighted vertex normals at
/// the edge's ends, normalized (0 where that sum is 0). A new vertex placed on the line through
/// its butterfly prediction along this normal has a detail along the normal only (normal
/// meshes, Guskov et al. 2000): no tangential components to code.
std::vector<std::array<double, 3>> edge_frame_normals(const TriangleTopology& coarse, std::span<const double> x);

/// Faces of `remeshed` facing away from `surface`: a face is flipped when its normal makes more
/// than 90° with the normal of the surface face closest to its centroid; degenerate when its
/// area is below 1e-14 of the squared bounding-box diagonal.
/// find_fold_overs()'s degenerate test for a face whose edge vectors' cross product is `normal`
/// (its length twice the face's area), in a mesh of bounding-box diagonal `diagonal`. The
/// untangling (untangle.h) counts such faces as folded, so that it moves their vertices too.
bool is_degenerate(const std::array<double, 3>& normal, double diagonal);

struct FoldOvers {
  std::vector<std::uint32_t> flipped;     ///< face indices
  std::vector<std::uint32_t> degenerate;  ///< face indices
};
FoldOvers find_fold_overs(const TriangleMesh& remeshed, const SurfaceQuery& surface);

/// How many of the faces `flipped` of `remeshed` have as the surface face closest to their
/// centroid (find_fold_overs()'s reference) one marked in `crossing` (per surface face: 1 if it
/// cuts through another face, self_intersection.h).
std::size_t count_at_crossings(const TriangleMesh& remeshed, std::span<const std::uint32_t> flipped,
                               const SurfaceQuery& surface, std::span<const std::uint8_t> crossing);

/// How many of the faces `faces` of `remeshed` are turned over on the remesh itself: their normal
/// makes more than 90° with the normal of a face that shares an edge with them (a visible fold).
/// A flipped face (find_fold_overs()) that is not lies in line with its neighbours and faces away
/// only from the input's normal at its closest point: where the input passes through itself,
/// the other sheet's.
std::size_t count_turned_over(const TriangleMesh& remeshed, std::span<const std::uint32_t> faces);

/// Whether the surface face closest to the centroid of face t of the xyz array x (the flip
/// test's reference, faces_away()) is marked in `marked` (per surface face): count_at_crossings()
/// for one face.
bool closest_is_marked(std::span<const double> x, const std::uint32_t* t, const SurfaceQuery& surface,
                       std::span<const std::uint8_t> marked);

/// The flip test of find_fold_overs() for face t (three vertex indices) of the xyz array x: its
/// normal makes more than 90° with that of the surface face closest to its centroid. `hint`, if
/// given, holds a surface face likely near (kNone: none) and receives the closest one: a query
/// started there is faster when faces are tested in an order that keeps neighbours together
/// (the answer does not depend on it: closest_point.h). `closest`, if given, receives the surface
/// point closest to the centroid that the test read.
bool faces_away(std::span<const double> x, const std::uint32_t* t, const SurfaceQuery& surface,
                std::uint32_t* hint = nullptr, SurfacePoint* closest = nullptr);

/// Rounds the positions of `mesh` to 32-bit floats, the values a mesh file stores (mesh_io.h),
/// and returns the folds (find_fold_overs()) of the rounded finest level. Rounding moves a
/// coordinate by at most 2^-24 of its magnitude, yet it can turn a face whose centroid is closest
/// to an input vertex or edge: which input face there is the closest is then decided by the last
/// bits of the distances (homer remeshed at L = 6: 1 folded face in double, 4 rounded). Each face
/// that folds once rounded but not in double gets its corners rounded the other way where that
/// folds none of their faces (the first of the 2^9 ways to take, for each of its 9 coordinates,
/// one of the two floats around it); a face no way mends keeps its corners as rounded, and is
/// counted. (Untangling the whole mesh again instead left homer at 3.)
FoldOvers round_to_float(SemiRegularMesh& mesh, const SurfaceQuery& surface);

/// find_fold_overs()'s verdict on face t of the xyz array x, in a mesh of bounding-box diagonal
/// `diagonal`: degenerate (is_degenerate()) or facing away (faces_away(), with its `hint` and
/// `closest`; a degenerate face is judged without the query, and `closest` is left as it was).
bool is_folded(std::span<const double> x, const std::uint32_t* t, const SurfaceQuery& surface, double diagonal,
               std::uint32_t* hint = nullptr, SurfacePoint* closest = nullptr);

}  // namespace meshlift
