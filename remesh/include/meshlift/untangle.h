// Untangling the folds a remesh has left (the fitting stage has no fold-free guarantee,
// surface_fit.h): each connected patch of folded faces, grown by a few rings, is flattened onto
// the plane of the input's normals there, its inner vertices re-embedded by Tutte's barycentric
// mapping with the patch's rim fixed (Tutte 1963; Floater 1997: a convex rim gives an embedding
// without fold-overs), and lifted back onto the input along that normal, or to the closest
// points, or, third, placed by the same map inside the input's own flattening around the patch
// (a disk of input faces along the surface, mapped to the unit disk by Tutte's map: for patches
// across a thin part's edge, where no plane suits). A patch is kept only if it has fewer folded
// faces than before; else it grows (1, 2, 3, 5, 8 rings) and is tried again. A patch or vertex
// that failed is not tried again while none of the vertices its try reads has moved.
// What patches leave is untangled vertex by vertex (Freitag and Plassmann 2000): each vertex of a
// folded face moves, in the input's tangent plane (or the plane of its neighbours' or faces'
// input normals), to where the smallest signed area of its faces is largest, if that leaves fewer
// of its faces folded.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <string>

#include "meshlift/closest_point.h"
#include "meshlift/semi_regular.h"

namespace meshlift {

struct UntangleOptions {
  /// Rings of faces added around a patch of folded faces at the first try (>= 1) and at most
  /// (>= first_rings); each failed try adds half as many again (1, 2, 3, 5, 8). Measured on the
  /// corpus (L = 3, ~4x): one ring more per try left camel 28 folded faces, cow 52, turbine 71,
  /// mannequin-devil 70 in 2-2.5x the time; doubling (1, 2, 4, 8) left 20, 53, 88, 67 but one
  /// on armadillo at ~2x; this sequence leaves 27, 52, 63, 78 and none on armadillo.
  int first_rings = 1;
  int max_rings = 8;
  /// Passes over all patches (>= 0); they stop early when a pass keeps no patch.
  int passes = 8;
  /// A patch's last tries, after its Tutte maps lifted onto the plane and into the input's own
  /// flattening (>= 0): steps of relaxation on the input, one more a try, from where the patch
  /// was (each inner vertex to the input's closest point to the mean of its neighbours), kept
  /// as the other tries are, where the region folds fewer faces. Measured at L = 4: cow's folded
  /// face at a corner of its input and turbine's two go. That acceptance is greedy: on a badly
  /// tangled mesh (half its faces folded) the untangling then often ends with more folded than
  /// without relaxation (docs/RESULTS.md, "Relaxation"); 0 turns it off.
  int relaxation_steps = 4;
  /// Passes of per-vertex untangling over the vertices of the faces still folded (>= 0); they
  /// stop early when a pass moves no vertex.
  int vertex_passes = 16;
  /// Rounds of patch passes then vertex passes (>= 1). Measured (L = 3, ~4x, after the
  /// least-squares fit, the tangent plane alone): one round left camel 9 (was 27 with patches
  /// alone), cow 27 (52), turbine 20 (63), mannequin-devil 27 (78); three rounds 9, 16, 19, 21;
  /// eight as three.
  int rounds = 3;
  /// The most fold tests and closest-point queries the patch passes may make, per face of the
  /// mesh (> 0), over all rounds: where the budget runs out they stop, and the vertex passes
  /// still run. The development meshes' remeshes make at most 1.7 fold tests a face (and never
  /// reach the budget: their remeshes are the same with it); an input that is crumpled all over
  /// (every coordinate of a grid moved by more than its spacing: half the remesh's faces folded,
  /// and each query visits many nearby sheets) made 30-90 in each of many calls and kept a
  /// 676-vertex remesh running for over an hour. This bounds it (docs/RESULTS.md).
  double max_patch_queries_per_face = 16;
  /// Per vertex of the finest level, or empty: 1 where the vertex stays (on a feature line,
  /// features.h), as the mesh's boundary vertices do.
  std::span<const std::uint8_t> fixed;
};

struct UntangleReport {
  std::size_t folded_before = 0, folded_after = 0;
  std::size_t patches_tried = 0, patches_kept = 0;
  std::size_t vertices_moved = 0;  ///< moves kept by the per-vertex untangling, over all passes
  bool patch_budget_spent = false;  ///< the patch passes stopped at max_patch_queries_per_face
};

/// Untangles the finest level of `mesh` (all its vertices may move, boundary vertices of the
/// mesh excepted) against the input `surface`. A face counts as folded as find_fold_overs()
/// judges: its normal more than 90° from the input's normal at the closest point of its
/// centroid. \throw std::invalid_argument if an option is out of range.
UntangleReport untangle(SemiRegularMesh& mesh, const SurfaceQuery& surface, const UntangleOptions& options = {});

/// search_unfolded(): its effort. Measured on the folds left at L = 6 (docs/RESULTS.md, "The
/// folds left at L = 6, mended by a search"): turbine's and cow's go within one ring in a few
/// hundred moves, homer's and armadillo's need two rings and a few thousand.
struct FoldSearchOptions {
  /// Moves tried per patch (>= 0; 0 turns the search off).
  int evaluations = 20000;
  /// Rings of vertices around the folded face's corners that may move: first_rings, then one
  /// more a try up to max_rings (1 <= first_rings <= max_rings).
  int first_rings = 1;
  int max_rings = 3;
  /// Searches at max_rings, each from its own random numbers (>= 1): one succeeds about half
  /// the time on armadillo's fold at L = 6, so four leave it folded about once in sixteen.
  int attempts = 4;
  /// How far a vertex may go from where it was, in mean edge lengths of the patch (> 0).
  double reach = 1.0;
  /// Faces tried at most (a remesh with more folds has failed in other ways; 0: none).
  std::size_t max_faces = 32;
  /// Where the search's random numbers start (with the face's index): another seed, another
  /// search.
  std::uint64_t seed = 0;
};

/// Empty where `options` are in range, else what is out of range (search_unfolded() throws it;
/// remesh() checks RemeshOptions::fold_search with it before any work).
std::string out_of_range(const FoldSearchOptions& options);

struct FoldSearchReport {
  std::size_t tried = 0;   ///< faces searched around (a face mended by another's search is not)
  std::size_t mended = 0;  ///< of those, the ones no longer folded, their patch folding no face
};

/// The untangling's last resort, for the few faces still folded in a finished remesh: around
/// each of `faces` (finest-level faces of `mesh`), a random search moves the vertices within one
/// to three rings of its corners (first_rings to max_rings), one at a time, each move kept where the faces they touch fold
/// fewer (find_fold_overs()'s verdict) or fold by less, until none folds. Each vertex then goes
/// back towards where it was as far as no fold comes back. Positions are rounded to floats as
/// they move (a mesh file stores floats: round_to_float()), boundary vertices stay, and a patch
/// the search cannot unfold is put back as it was. Deterministic (its own random numbers).
/// \throw std::invalid_argument if an option is out of range.
FoldSearchReport search_unfolded(SemiRegularMesh& mesh, const SurfaceQuery& surface, std::span<const std::uint32_t> faces,
                                 const FoldSearchOptions& options = {});

}  // namespace meshlift
