// The untangling's last resort (untangle.h, search_unfolded): a random search over the vertices
// around each face still folded in the stored remesh. The untangling moves one vertex at a time
// (its vertex passes) or re-embeds a whole patch (its Tutte lifts); at L = 6 a face can stay
// folded where neither works, in a strip of long faces along a sharp input crease (docs/RESULTS.md,
// "The single folds left at L = 6"). Moving several vertices of the strip, one after the other,
// each move kept only where it leaves fewer folded faces (or as many, folded by less), mends it:
// a (1+1) evolution strategy whose step grows ×1.5 after a kept move and shrinks ×0.97 after a
// rejected one (a success rule in the manner of Rechenberg's 1/5 rule, settling where about 7 %
// of the moves are kept: ln(1/0.97) / ln(1.5/0.97)).
#include <algorithm>
#include <cmath>
#include <numeric>
#include <optional>
#include <stdexcept>

#include "adjacency.h"
#include "meshlift/mesh.h"
#include "meshlift/surface_fit.h"
#include "meshlift/untangle.h"
#include "vec3.h"

namespace meshlift {
namespace {

using namespace vec3;

/// A position as a mesh file stores it. (Turning such a point back into doubles lane by lane is
/// the pattern GCC 12.2's SLP vectorizer miscompiles at -O2 and above, dropping the rounding:
/// what keeps these floats is the build's -fno-tree-slp-vectorize, CMakeLists.txt.)
using Point = std::array<float, 3>;

Point stored(const Vec3& p) { return {static_cast<float>(p[0]), static_cast<float>(p[1]), static_cast<float>(p[2])}; }

/// splitmix64 (Steele, Lea and Flood 2014): numbers that are the same with every compiler and
/// library, which std::normal_distribution's are not.
struct SplitMix64 {
  std::uint64_t state;
  /// Uniform in [-1, 1).
  double uniform() {
    std::uint64_t z = (state += 0x9e3779b97f4a7c15ull);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    z ^= z >> 31;
    return static_cast<double>(z >> 11) * 0x1.0p-52 - 1.0;
  }
};

/// One patch: its movable vertices, the faces they touch, and per face its verdict and how far
/// it is from facing the input well.
class Patch {
 public:
  Patch(std::span<double> x, const std::vector<std::uint32_t>& triangles, const Adjacency& adjacency,
        const SurfaceQuery& surface, double diagonal, std::uint32_t face, int rings)
      : x_(x), triangles_(triangles), adjacency_(adjacency), surface_(surface), diagonal_(diagonal) {
    // The face's corners and `rings` rings of vertices around them.
    std::vector<std::uint32_t> ring(triangles.begin() + 3 * std::size_t{face}, triangles.begin() + 3 * std::size_t{face} + 3);
    for (int r = 0; r < rings; ++r) {
      std::vector<std::uint32_t> next = ring;
      for (const std::uint32_t v : ring)
        next.insert(next.end(), adjacency.neighbours.begin() + adjacency.neighbour_offsets[v],
                    adjacency.neighbours.begin() + adjacency.neighbour_offsets[v + 1]);
      std::sort(next.begin(), next.end());
      next.erase(std::unique(next.begin(), next.end()), next.end());
      ring = std::move(next);
    }
    for (const std::uint32_t v : ring)
      if (!adjacency.on_boundary(v)) vertices_.push_back(v);  // the mesh's boundary stays, as in untangle()
    for (const std::uint32_t v : vertices_)
      faces_.insert(faces_.end(), adjacency.faces.begin() + adjacency.face_offsets[v],
                    adjacency.faces.begin() + adjacency.face_offsets[v + 1]);
    std::sort(faces_.begin(), faces_.end());
    faces_.erase(std::unique(faces_.begin(), faces_.end()), faces_.end());
    double sum = 0;
    for (const std::uint32_t v : vertices_) sum += adjacency.mean_edge_length(x, v);
    edge_ = vertices_.empty() ? 0 : sum / static_cast<double>(vertices_.size());
    for (const std::uint32_t v : vertices_) start_.push_back(at(x, v));
    folded_.resize(faces_.size());
    shortfall_.resize(faces_.size());
    for (std::size_t i = 0; i < faces_.size(); ++i) judge(i);
  }

  const std::vector<std::uint32_t>& vertices() const { return vertices_; }
  double edge() const { return edge_; }
  const Vec3& start(std::size_t i) const { return start_[i]; }
  /// The input's closest point to p.
  Vec3 closest(const Vec3& p) const { return surface_.closest(p).point; }
  int folded() const { return static_cast<int>(std::count(folded_.begin(), folded_.end(), std::uint8_t{1})); }
  double shortfall() const { return std::accumulate(shortfall_.begin(), shortfall_.end(), 0.0); }

  /// Moves vertex i to p (a mesh file stores floats); the patch's folded count and shortfall
  /// change with its faces'.
  void move(std::size_t i, const Point& p) { put(i, {p[0], p[1], p[2]}); }
  /// Puts vertex i back where it was, exactly.
  void restore(std::size_t i) { put(i, start_[i]); }

 private:
  void put(std::size_t i, const Vec3& p) {
    const std::uint32_t v = vertices_[i];
    for (std::size_t k = 0; k < 3; ++k) x_[3 * std::size_t{v} + k] = p[k];
    for (std::uint32_t a = adjacency_.face_offsets[v]; a < adjacency_.face_offsets[v + 1]; ++a)
      judge(static_cast<std::size_t>(std::lower_bound(faces_.begin(), faces_.end(), adjacency_.faces[a]) - faces_.begin()));
  }
  /// Face i's verdict (is_folded(), find_fold_overs()'s) and its shortfall: how far the cosine
  /// between its normal and the input's at its centroid's closest point is below 0.2, squared,
  /// plus a hundredth of that point's squared distance in mean edge lengths (so that among
  /// equal verdicts the search prefers faces that face the input well and stay on it).
  void judge(std::size_t i) {
    const std::uint32_t* t = &triangles_[3 * std::size_t{faces_[i]}];
    SurfacePoint s;  // the verdict's closest point, one query for both
    folded_[i] = is_folded(x_, t, surface_, diagonal_, nullptr, &s) ? 1 : 0;
    if (s.face == kNone) {  // degenerate: judged without a query
      const Vec3 a = at(x_, t[0]), b = at(x_, t[1]), c = at(x_, t[2]);
      s = surface_.closest({(a[0] + b[0] + c[0]) / 3, (a[1] + b[1] + c[1]) / 3, (a[2] + b[2] + c[2]) / 3});
    }
    const TriangleMesh& input = surface_.mesh();
    const Vec3 n = unit(face_normal(x_, t)), m = unit(face_normal(input.positions, &input.triangles[3 * std::size_t{s.face}]));
    const double missing = std::max(0.0, 0.2 - dot(n, m));
    const double off = edge_ > 0 ? s.distance / edge_ : 0;
    shortfall_[i] = missing * missing + 1e-2 * off * off;
  }

  std::span<double> x_;
  const std::vector<std::uint32_t>& triangles_;
  const Adjacency& adjacency_;
  const SurfaceQuery& surface_;
  double diagonal_;
  std::vector<std::uint32_t> vertices_, faces_;
  std::vector<Vec3> start_;
  double edge_ = 0;
  std::vector<std::uint8_t> folded_;
  std::vector<double> shortfall_;
};

/// The search on one patch; true where it leaves no face of the patch folded (its vertices then
/// pulled back towards where they were as far as that stays so), else the patch as it was.
bool search_patch(Patch& patch, int evaluations, double reach, std::uint64_t seed) {
  const std::size_t n = patch.vertices().size();
  // Nothing of the patch folds where its face's corners are all on the boundary (a face whose
  // vertices all stay is in no patch): nothing to search.
  if (n == 0 || !(patch.edge() > 0) || patch.folded() == 0) return false;
  int best = patch.folded();
  double best_shortfall = patch.shortfall();
  double step = 0.3;  // in mean edge lengths
  SplitMix64 random{seed};
  // Where each vertex is: where it was (exact) until a move of it is kept.
  std::vector<std::optional<Point>> moved(n);
  auto where = [&](std::size_t i) { return moved[i] ? Vec3{(*moved[i])[0], (*moved[i])[1], (*moved[i])[2]} : patch.start(i); };
  auto put_back = [&](std::size_t i) {
    if (moved[i]) patch.move(i, *moved[i]);
    else patch.restore(i);
  };
  const double h = patch.edge(), limit = reach * h;
  for (int e = 0; e < evaluations && best > 0; ++e) {
    const std::size_t i = static_cast<std::size_t>((random.uniform() + 1) * 0.5 * static_cast<double>(n)) % n;
    Vec3 p = where(i);
    for (double& c : p) c += step * h * random.uniform();
    const Point q = stored(p);
    const Vec3 d = sub({q[0], q[1], q[2]}, patch.start(i));
    if (dot(d, d) > limit * limit) {  // farther than `reach` from where it was: not tried
      step = std::max(1e-3, step * 0.97);
      continue;
    }
    patch.move(i, q);
    const int folded = patch.folded();
    const double shortfall = patch.shortfall();
    if (folded < best || (folded == best && shortfall < best_shortfall)) {
      best = folded;
      best_shortfall = shortfall;
      moved[i] = q;
      step = std::min(1.0, step * 1.5);
    } else {
      put_back(i);
      step = std::max(1e-3, step * 0.97);
    }
  }
  if (best > 0) {
    for (std::size_t i = 0; i < n; ++i) patch.restore(i);
    return false;
  }
  // Each moved vertex back towards where it was, all the way or part of it, else onto the
  // input's closest point, where no fold comes back.
  for (int pass = 0; pass < 2; ++pass)
    for (std::size_t i = 0; i < n; ++i) {
      if (!moved[i]) continue;
      if (patch.restore(i), patch.folded() == 0) {
        moved[i].reset();
        continue;
      }
      for (const double t : {0.75, 0.5, 0.25, -1.0}) {
        const Vec3 a = where(i), b = patch.start(i);
        const Point q = stored(t > 0 ? Vec3{a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1]), a[2] + t * (b[2] - a[2])}
                                     : patch.closest(a));
        const Vec3 d = sub({q[0], q[1], q[2]}, b);
        if (dot(d, d) > limit * limit) continue;  // the closest point can lie beyond the reach
        patch.move(i, q);
        if (patch.folded() == 0) {
          moved[i] = q;
          break;
        }
      }
      if (patch.folded() > 0) put_back(i);
    }
  return true;
}

}  // namespace

std::string out_of_range(const FoldSearchOptions& options) {
  if (options.evaluations < 0 || options.first_rings < 1 || options.max_rings < options.first_rings ||
      options.attempts < 1 || !(options.reach > 0))
    return "evaluations must be >= 0, 1 <= first_rings <= max_rings, attempts >= 1 and reach > 0";
  return {};
}

FoldSearchReport search_unfolded(SemiRegularMesh& mesh, const SurfaceQuery& surface,
                                 std::span<const std::uint32_t> faces, const FoldSearchOptions& options) {
  if (const std::string problem = out_of_range(options); !problem.empty())
    throw std::invalid_argument("search_unfolded: " + problem);
  FoldSearchReport report;
  if (faces.empty() || options.evaluations == 0) return report;
  const int L = mesh.hierarchy.levels();
  const std::vector<std::uint32_t>& triangles = mesh.hierarchy.triangles(L);
  const Adjacency adjacency(mesh.hierarchy.vertex_count(L), triangles);
  const double diagonal = bounding_box_diagonal(mesh.positions);  // find_fold_overs()'s
  for (const std::uint32_t face : faces) {
    if (report.tried == options.max_faces) break;
    if (!is_folded(mesh.positions, &triangles[3 * std::size_t{face}], surface, diagonal)) continue;  // mended with another
    ++report.tried;
    bool mended = false;
    for (int rings = options.first_rings; rings <= options.max_rings && !mended; ++rings) {
      Patch patch(mesh.positions, triangles, adjacency, surface, diagonal, face, rings);
      for (int attempt = 0; attempt < (rings == options.max_rings ? options.attempts : 1) && !mended; ++attempt)
        mended = search_patch(patch, options.evaluations, options.reach,
                              options.seed + 0x5eedull * (face + 1) + 0x100ull * static_cast<std::uint64_t>(attempt) +
                                  static_cast<std::uint64_t>(rings));
    }
    report.mended += mended && !is_folded(mesh.positions, &triangles[3 * std::size_t{face}], surface, diagonal);
  }
  return report;
}

}  // namespace meshlift
