// Any triangle mesh -> semi-regular mesh (CODEC-NOTES §5): recognize subdivision connectivity
// when the input already has it, else decimate to a base mesh, optionally fit the base by Loop
// interpolation (seed 000), refine L times and move the refined vertices onto the input surface.
// Where the decimation keeps half the input's vertices or more although fewer were asked for (a
// small input, at its topology's floor), the base is the input itself and the remesh its
// midpoint refinement, exact but for the rounding to floats (RemeshResult::input_refined). A deep hierarchy whose base is that
// of a level fewer is placed a level at a time (RemeshOptions::level_by_level_from).
#pragma once

#include <cstddef>
#include <functional>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "meshlift/mesh.h"
#include "meshlift/semi_regular.h"
#include "meshlift/untangle.h"

namespace meshlift {

/// How the base mesh is shaped before refinement.
enum class BaseFit {
  none,  ///< base vertices stay where decimation left them (on the input surface)
  loop,  ///< the base's Loop limit surface passes through the decimated points (seed 000); the
         ///< refinement is placed from that guide and from one that takes the unfitted limit where
         ///< it is closer to the input, and the one with fewer folds (or as many and closer) goes on
};

/// Which remesher makes the semi-regular mesh.
enum class RemeshMethod {
  decimate,  ///< any genus, boundaries, components: decimated base, fitted refinement
  sphere,    ///< closed genus-0 meshes in one piece: octahedral spherical geometry image
             ///< (geometry_image.h); `levels` counts refinements of the octahedron
  best,      ///< sphere when it applies and its remesh is closer to the input (metric.h) than
             ///< the decimation remesh; the decimation remesh otherwise
};

struct RemeshOptions {
  RemeshMethod method = RemeshMethod::decimate;
  /// Refinements of the base mesh, 0..kMaxLevels (3: measured the best remesh error at a given
  /// vertex count on the corpus, docs/RESULTS.md). For `best`, the sphere remesh gets the level
  /// whose vertex count 4^(L+1) + 2 is nearest the decimation remesh's.
  int levels = 3;
  /// Base vertices; 0 chooses automatic_remesh_base() for `density`.
  std::size_t base_vertices = 0;
  /// Vertices of the remesh per input vertex that the automatic base size aims at, in [1, 1024],
  /// or 0: automatic: 2x if its remesh reaches auto_density_psnr against the input (metric.h)
  /// and folds no face (but where the input passes through itself: no orientation faces both of
  /// its sheets there); else 3x if that one reaches middle_density_psnr and folds none; else the
  /// closest to the input of 2x, 3x and 4x, then of denser ones where those all fall short of
  /// dense_density_psnr. Where the 2x remesh as first placed reaches sparsest_density_psnr (or
  /// one of its guides sparsest_guide_psnr), the kSparserAutoDensities come first, in turn, the
  /// first that qualifies kept. Measured (docs/RESULTS.md): 4x gives the
  /// closer remesh (about 4-9 dB above 2x where both work); 2x codes the 55-75 dB range in
  /// fewer bits (BD-rate against Draco: armadillo -70 % instead of -61 %, bear_bis -74 % instead
  /// of -64 %) but misses limbs on some meshes (camel 59 dB, elephant 49 dB at 2x).
  double density = 0;
  /// The remesh error (PSNR, dB) a 2x remesh must reach for the automatic density to keep it.
  double auto_density_psnr = 75;
  /// When the 2x remesh reaches this (dB) as first placed (before the least-squares fit and the
  /// last untangling, which added 1.0-5.0 dB to placements this close on the corpus), the
  /// automatic density sets it aside and makes the kSparserAutoDensities in turn, keeping the
  /// first that reaches auto_density_psnr with no fold; the 2x remesh is finished only if none
  /// does. 76: of 25 corpus meshes, the 2x placements are 77.2 dB or closer (finished: 81.8 or
  /// closer) or 74.7 or farther (finished: 77.7 or farther), so the choices are those of the
  /// rule before (sparser only where the finished 2x remesh reached 80 dB with no fold, 1.5x
  /// before 1x) but for diplodocus (its 2x remesh folds: 3x before, now 1x) and fandisk_large
  /// (1.5x before, now 1x), both coded in fewer bits at 55-75 dB (docs/RESULTS.md).
  double sparsest_density_psnr = 76;
  /// The 2x remesh is also set aside, before it is placed, when one of its guides (the Loop limit
  /// surface of its base, before anything is put on the input; remesh.cpp) is this close (dB)
  /// already: its placement would be far within. On the 25 corpus meshes the 2x guides of 58 dB
  /// or closer (blade 69.9, the 104k armadillo 63.3, bunny00 61.3, diplodocus 60.4) were placed at
  /// 85 dB or closer, those of the meshes that stay at 2× or denser at 54.2 or farther
  /// (armadillo): the same choices, without the 2x placement (the 104k armadillo 2.6 s less).
  /// Applies where sparsest_density_psnr can set the 2x remesh aside (infinity there turns both
  /// off); infinity here turns this one off.
  double sparsest_guide_psnr = 58;
  /// Where the 2x remesh falls short, the automatic density keeps the 3x one if it reaches this
  /// (dB) with no fold, before trying 4x. Above auto_density_psnr by a margin: a 3x remesh just
  /// within 75 dB bends the codec's curve below 4x's at the top of 55-75 dB (homer, 75.3 dB:
  /// BD-rate +8 %), one with a margin codes it in fewer bits (lion-head, 80.0 dB: -18 %; camel,
  /// 81.8 dB: -6 %; docs/RESULTS.md).
  double middle_density_psnr = 77;
  /// Where the closest of the 2x, 3x and 4x remeshes stays below this (dB), the automatic
  /// density also makes the kDenserAutoDensities remeshes in turn while the closest is still
  /// below it, each kept if closer and folding nowhere but at the input's crossings. The top of
  /// the 55-75 dB range: a remesh farther from the input caps the codec's curve below it
  /// (elephant 69.9 dB at 4x, 75.9 at 6x: BD-rate against Draco -30.2 -> -39.2 %; cow 66.1 at
  /// 4x, 74.5 at 8x: -18.8 -> -32.4 %; docs/RESULTS.md).
  double dense_density_psnr = 75;
  /// A candidate of the automatic density that must reach some PSNR to be kept (auto_density_psnr
  /// at 2x, middle_density_psnr at 3x, the closest so far at 4x and denser) is given up after
  /// its first placement when that placement's PSNR plus this margin (dB) falls short and a
  /// later candidate will be made: the later stages (least-squares fit, untangling) could not
  /// bring it there. Over the 32 remeshes the automatic density makes of the twelve corpus meshes
  /// they added 5.9 dB at the most (homer at 2x: 64.97 -> 70.91). A given-up candidate is finished
  /// after all wherever the choice could depend on it, so the choice is the one every candidate
  /// finished would give as long as the margin holds; infinity never gives up. Mannequin-devil's
  /// remesh 11.0 -> 5.3 s, cow's 2.4 -> 1.8 s, same bytes (docs/RESULTS.md).
  double give_up_margin = 10;
  BaseFit fit = BaseFit::loop;
  /// Rounds of least-squares fitting of the decimation remesh to the input (least_squares_fit.h);
  /// 0 leaves every vertex on the input surface where the fitting stage placed it.
  int least_squares_rounds = 4;
  /// Last (after the least-squares fit and the untangling), move the decimation remesh's vertices
  /// onto the input's own corners and crease edges wherever that brings the two surfaces closer
  /// locally and turns no face away from the input (snap.h). For a remesh used as a mesh: 0.2-8.6
  /// dB closer on the development meshes (at ~16x knot1 84.1 -> 86.5, elephant 83.3 -> 87.3, cow
  /// 82.5 -> 86.4), never a fold more, at 1.6-1.8x the time; but the
  /// moves are along the surface, and the codec pays for tangential details: BD-rate against
  /// Draco camel -66.9 -> -51.9 %, knot1 -49.3 -> -35.9 % (docs/RESULTS.md). Off by default. The
  /// sphere method snaps its geometry-image remesh the same way.
  bool snap = false;
  /// Feature lines (features.h): edges whose faces turn by more than feature_angle (degrees; 0
  /// turns them off), in chains of at least feature_min_edges edges that turn by at most
  /// feature_max_turn at a vertex and whose sides (the other edges of their faces) turn by at
  /// most feature_max_side (median over the chain), are kept by the decimation and followed by
  /// the remesh. With the automatic density they are used where their 2x remesh qualifies (as
  /// below), else the remesh goes on without them. Measured (docs/RESULTS.md): fandisk 76.0 dB
  /// at 2x without, 81.9 with (85.1 against 77.7 at 4x); the side limit keeps the sharp edges of
  /// coarse organic meshes (camel, cow, elephant) out.
  double feature_angle = 60;
  std::size_t feature_min_edges = 5;
  double feature_max_turn = 30;
  double feature_max_side = 10;
  /// Parts the base missed: where the decimation stops above the base size asked for (its checks
  /// refuse every further collapse: deep hierarchies, small inputs), a larger density cannot
  /// give a different base, and a thin part collapsed away is missing from the remesh
  /// (elephant's feet at L = 4: 59.7 dB), or a base face spans a gap that the remesh then
  /// fills with a sheet (turbine's blades at L = 4: 53.7 dB, 17 folds). Then, up to this many
  /// rounds: the input vertices farther than missing_part_distance (of the bounding-box
  /// diagonal) from the remesh, and the input vertices nearest the remesh faces farther than
  /// that from the input, at most 8 a round and 5 % of the diagonal apart, are kept in the base
  /// (DecimateOptions::keep) and the remesh made again, kept if it is closer to the input and
  /// folds no more away from the input's own crossings than the one kept; a round whose remesh
  /// is not kept still passes its vertices on to the next (at L = 4 elephant 59.7 -> 77.0 dB,
  /// turbine 53.7 -> 84.0 dB with 1 fold instead of 9; docs/RESULTS.md). 0 turns it off.
  int missing_part_rounds = 3;
  double missing_part_distance = 2e-3;
  /// With the automatic density, where no density makes a remesh within auto_density_psnr of the
  /// input without a fold (but at its crossings), the input's own midpoint refinement (exact:
  /// RemeshResult::input_refined) is taken instead if it has at most this many vertices (4^L
  /// times the input's: small inputs, up to 1,024 vertices at L = 3; docs/RESULTS.md, "Small
  /// inputs"), or at most 16 times as many where the remesh kept folds away from the input's
  /// crossings (a failed remesh: up to 16,384 input vertices at L = 3). 0 turns it off. (Where the decimation keeps half the input's vertices or more
  /// although fewer were asked for, the refinement is taken whatever this is.)
  double input_refinement_vertices = 65'536;
  /// The last resort for the faces still folded in the remesh returned, and in the remesh of a
  /// level fewer that a deep hierarchy refines once more (level_by_level_from): a search over the
  /// vertices around each (untangle.h, search_unfolded()), first around those more than two
  /// rings of input faces away from the input's crossings, then around those at or next to
  /// them, up to its cap on faces (max_faces) in all; `evaluations = 0` turns it off.
  /// folds_searched and folds_mended_by_search count the search of the remesh returned.
  FoldSearchOptions fold_search{};
  /// Deep hierarchies, level by level: a remesh of this many levels or more whose base is the
  /// one its remesh of a level fewer has (the base size given, or a decimation that stops at its
  /// floor above both levels' targets: with the automatic density, above the ~4x target of a
  /// level fewer, and that remesh keeps it) is made as that remesh refined once more. Its new
  /// vertices are shot onto the input from their butterfly predictions while all the others
  /// hold, then the least-squares fit and the untangling run over all of them, as for a remesh
  /// placed from its base; vertices on feature lines are placed and held on them at the new level
  /// too. Placed from the base directly, the deep levels part from the input where the base is
  /// far coarser than it (turbine at L = 5: 56.6 dB and 79 folded faces; from its L = 4 remesh:
  /// 89.2 dB, none; docs/RESULTS.md, "Deep hierarchies a level at a time"). 0 turns it off; else
  /// >= 1.
  int level_by_level_from = 4;
  /// Accept an input that already has subdivision connectivity as it is (its hierarchy is
  /// recovered, nothing is moved) when it has at least min(levels, 2) levels: a single 1:4 split
  /// (the corpus's camel is one) leaves too coarse a base for the wavelets, so such a mesh is
  /// remeshed. When false the input is always remeshed.
  bool recognize = true;
  /// Called with a fraction in [0, 1] as work progresses (for a progress bar); may be empty.
  std::function<void(double)> progress;
};

/// The densities the automatic choice tries, sparser first.
inline constexpr double kAutoDensities[] = {2, 3, 4};
/// The denser densities tried, in turn, while the closest remesh is below dense_density_psnr.
inline constexpr double kDenserAutoDensities[] = {6, 8};
/// The sparser densities tried, in turn (the sparsest first), where the 2x remesh is far within
/// the threshold (smooth meshes, and CAD meshes that follow their feature lines).
inline constexpr double kSparserAutoDensities[] = {1, 1.5};

struct RemeshResult {
  /// The remesh. Unless the input was taken over as it is (`recognized`), its positions are
  /// 32-bit floats (each double holds a float's value): what a mesh file stores (mesh_io.h), so
  /// that the figures below are those of the file written.
  SemiRegularMesh mesh;
  /// The density the base was sized for (RemeshOptions::density, or the automatic choice); 0
  /// when the base size was given or the input was taken over or remeshed through the sphere.
  double density = 0;
  /// True when the input already was semi-regular and was taken over as it is.
  bool recognized = false;
  /// The remesher that made `mesh` (decimate or sphere; also when `best` chose).
  RemeshMethod method = RemeshMethod::decimate;
  std::size_t base_vertices = 0;
  /// The base size the decimation was asked for (RemeshOptions::base_vertices, or the density's,
  /// automatic_remesh_base()); base_vertices is larger where the decimation stopped above it. 0
  /// when the input was taken over, refined as it is, or remeshed through the sphere.
  std::size_t target_base_vertices = 0;
  /// True when the base is the input itself and `mesh` its midpoint refinement, on the input
  /// but for the rounding of its positions to floats (`mesh`): a small input
  /// (RemeshOptions::input_refinement_vertices, remesh.h's header).
  bool input_refined = false;
  /// Levels placed from the base directly; each level above them was placed on the finished
  /// remesh of the level below (RemeshOptions::level_by_level_from). Equal to the hierarchy's
  /// levels where none was; 0 when the input was taken over, refined as it is, or remeshed
  /// through the sphere.
  int direct_levels = 0;
  /// Where a remesh a level at a time over an explicit density's floor base folded faces away
  /// from the input's crossings (RemeshOptions::level_by_level_from), how many; the remesh
  /// placed from the base was then made too and kept if it folds fewer there (or as few, and is
  /// closer). 0 where none was set aside.
  std::size_t set_aside_refinement_folds = 0;
  /// For each base vertex, the input vertex it is (the decimation keeps a subset of the input's
  /// vertices, DecimateResult::original_vertex); empty where the input was taken over or remeshed
  /// through the sphere.
  std::vector<std::uint32_t> base_input_vertex{};
  /// Input edges on feature lines, and vertices of the result placed on them (features.h).
  std::size_t feature_edges = 0, feature_vertices = 0;
  /// Triangles of the result whose normal points away (> 90°) from the normal of the input face
  /// closest to their centroid, and triangles of zero area (surface_fit.h: find_fold_overs):
  /// both 0 in a good remesh; docs/RESULTS.md counts them on the corpus.
  std::size_t flipped_triangles = 0;
  std::size_t degenerate_triangles = 0;
  /// Faces still folded once the remesh was rounded to floats that the last resort searched
  /// around (RemeshOptions::fold_search), and how many of those
  /// searches left their patch without a fold (counted in flipped_triangles no more).
  std::size_t folds_searched = 0, folds_mended_by_search = 0;
  /// Pairs of the input's faces that cut through each other (self_intersection.h), and how many
  /// of the flipped triangles have one of those faces as the closest to their centroid. Where a
  /// surface passes through itself, the closest face near the crossing may belong to either
  /// sheet: no orientation of a face there agrees with both, and the flip test cannot be met.
  std::size_t input_crossing_pairs = 0;
  std::size_t flipped_where_input_crosses = 0;
  /// Of the other flipped triangles, those whose closest input face lies within two rings of a
  /// crossing face (self_intersection.h: faces_near_marked), where the remesh turns from one
  /// sheet to the other too. Reported only: the remesher's choices count the ones above.
  std::size_t flipped_near_input_crossings = 0;
  /// Of all the flipped triangles, those turned over on the remesh itself: more than 90° from a
  /// face that shares an edge with them (surface_fit.h: count_turned_over). The others lie in
  /// line with their neighbours and face away only from the input's closest point (at a
  /// crossing, on the other sheet). Reported only.
  std::size_t flipped_turned_over = 0;
  /// Input vertices at exactly the position of another (validate.h's duplicate_vertices): an
  /// unwelded seam or pieces, which the remesh keeps apart (each side of a seam a boundary).
  std::size_t coincident_vertices = 0;
  /// Input vertices kept in the base because a first remesh missed their part
  /// (RemeshOptions::missing_part_rounds); 0 when none were.
  std::size_t kept_vertices = 0;
  /// With RemeshOptions::snap: remesh vertices moved onto an input vertex and onto an input
  /// crease edge (snap.h's report; the untangling after it may move a few again).
  std::size_t snapped_to_vertices = 0, snapped_to_creases = 0;
  /// Wall-clock seconds per stage, in pipeline order ("decimate", "fit base", "guides", "place
  /// and compare", "least squares and untangle" (with snap: "least squares, untangle and snap"),
  /// then "choose density" with the automatic
  /// density, whose remeshes each list their stages, "decimate" only where a decimation ran (one
  /// for all its densities, with the feature lines and one without: decimate_each), and "place,
  /// then give up" instead of the last two for a candidate given up (give_up_margin); then, per
  /// round of missing_part_rounds, "missing parts: decimate" and that remesh's stages; "sphere"
  /// for a sphere remesh; for one placed level by level (level_by_level_from), the stages of the
  /// remesh of a level fewer, then "refine once more", and where that remesh was made but not
  /// refined (another base), "a level fewer, not refined" first): where a remesh spends its time
  /// (docs/RESULTS.md).
  std::vector<std::pair<std::string, double>> stage_seconds{};
};

/// The base size remesh() chooses: about `density` x the input's vertices after `levels`
/// refinements, max(ceil(density V / 4^levels), automatic_base_vertices(mesh, levels)) (decimate.h).
/// \throw MeshError as decimate(), or if density is not in [1, 1024].
std::size_t automatic_remesh_base(const TriangleMesh& mesh, int levels, double density = 4);

/// The semi-regular remesh of `mesh`.
/// \throw MeshError if the input is not a manifold, consistently oriented triangle mesh with
///        finite coordinates (validate.h's message), is a polygon soup (fewer than 2 faces per
///        connected piece), is unsuitable for `sphere` (not closed, genus 0 and in one piece),
///        or an option is out of range.
RemeshResult remesh(const TriangleMesh& mesh, const RemeshOptions& options = {});

/// Recovers the hierarchy of a mesh that has subdivision connectivity — a 1:4 refinement of
/// some base mesh, L >= 1 times — with its vertices and faces in any order. The result's
/// vertices are renumbered level by level (the finest positions are the input's, permuted) and
/// its finest faces are the input's faces (same orientation), reordered. Returns the recovery
/// with the most levels; nullopt when the mesh is not a refinement at all.
/// \pre every face index is below the vertex count (validate.h), as for remesh().
std::optional<SemiRegularMesh> recover_semi_regular(const TriangleMesh& mesh);

/// recover_semi_regular()'s first route alone, for a mesh whose top levels are in level order
/// (a remesh or a decoded file, as recover_level_ordered() finds them), with any further splits
/// below its base undone too; nullopt for any other mesh. Takes any arrays (no precondition):
/// the faces must equal the refinement of a base that TriangleTopology::build() accepts and in
/// which no two faces have the same three corners, so a mesh it recognizes is a manifold,
/// consistently oriented triangle mesh without repeated corners, its positions a whole number
/// of vertices.
std::optional<SemiRegularMesh> recover_in_level_order(const TriangleMesh& mesh);

}  // namespace meshlift
