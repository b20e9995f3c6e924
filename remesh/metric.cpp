// Metro-style symmetric surface distance (Cignoni, Rocchini, Scopigno 1998; CODEC-NOTES §7):
// area samples + vertices of each surface, exact distances to the other through SurfaceQuery.
#include "meshlift/metric.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <thread>

#include "parallel.h"

namespace meshlift {

namespace {

/// SplitMix64 (Steele, Lea, Flood 2014): a counter-based generator, so sample i's numbers depend
/// only on (seed, i), not on which thread draws them or in what order.
std::uint64_t splitmix64(std::uint64_t& state) {
  std::uint64_t z = (state += 0x9E3779B97F4A7C15ULL);
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
  return z ^ (z >> 31);
}
/// Uniform in [0, 1) with 53 random bits.
double unit(std::uint64_t& state) { return static_cast<double>(splitmix64(state) >> 11) * 0x1p-53; }

std::array<double, 3> corner(const TriangleMesh& mesh, std::size_t face, int i) {
  const std::size_t v = mesh.triangles[3 * face + i];
  return {mesh.positions[3 * v], mesh.positions[3 * v + 1], mesh.positions[3 * v + 2]};
}

double triangle_area(const TriangleMesh& mesh, std::size_t face) {
  const auto a = corner(mesh, face, 0), b = corner(mesh, face, 1), c = corner(mesh, face, 2);
  const double ab[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]}, ac[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
  const double n[3] = {ab[1] * ac[2] - ab[2] * ac[1], ab[2] * ac[0] - ab[0] * ac[2], ab[0] * ac[1] - ab[1] * ac[0]};
  return 0.5 * std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
}

OneSidedDistance one_sided(const SampledSurface& from, const SurfaceQuery& to, unsigned threads) {
  const std::vector<double>& points = from.points();
  const std::size_t count = points.size() / 3;
  std::vector<double> distances(count);
  parallel_blocks(count, threads, [&](std::size_t begin, std::size_t end) {
    // Consecutive samples are close together (they follow the faces' order), so each query starts
    // from the face the previous one found; the answer does not depend on the hint.
    std::uint32_t hint = kNone;
    for (std::size_t i = begin; i < end; ++i) {
      const SurfacePoint found = to.closest({points[3 * i], points[3 * i + 1], points[3 * i + 2]}, hint);
      distances[i] = found.distance;
      hint = found.face;
    }
  });
  // Fixed-order reductions. RMS and mean are area integrals, estimated from the area samples
  // alone (vertices are not spread by area); the maximum also looks at every vertex, where the
  // largest deviation of two polyhedra often sits. A surface of zero area has only its vertices.
  OneSidedDistance result;
  result.area_samples = from.area_samples();
  result.vertex_samples = count - from.area_samples();
  const std::size_t averaged = result.area_samples > 0 ? result.area_samples : count;
  double sum = 0, sum_squares = 0;
  for (std::size_t i = 0; i < averaged; ++i) {
    sum += distances[i];
    sum_squares += distances[i] * distances[i];
  }
  for (double d : distances) result.max = std::max(result.max, d);
  result.mean = sum / static_cast<double>(averaged);
  result.rms = std::sqrt(sum_squares / static_cast<double>(averaged));
  return result;
}

}  // namespace

std::size_t default_sample_count(std::size_t reference_faces, std::size_t test_faces) {
  return std::clamp<std::size_t>(10 * std::max(reference_faces, test_faces), 100'000, 1'000'000);
}

double SurfaceDistance::psnr_db() const {
  return rms > 0 ? 20 * std::log10(diagonal / rms) : std::numeric_limits<double>::infinity();
}

std::vector<double> area_samples(const TriangleMesh& m, std::size_t samples, std::uint64_t seed, unsigned threads,
                                 std::vector<std::uint32_t>* sample_faces) {
  const std::size_t faces = m.face_count();
  // Stratified sampling by area: the cumulative areas A_0 ≤ A_1 ≤ ... ≤ A_F laid end to end,
  // sample i at t_i = (i + u_i)/N · A_F lands in the face f with A_f ≤ t_i < A_{f+1}. Each face
  // receives its area's share of the N samples (±1), with less clumping than N independent draws.
  std::vector<double> cumulative(faces + 1, 0.0);
  for (std::size_t f = 0; f < faces; ++f) cumulative[f + 1] = cumulative[f] + triangle_area(m, f);
  const double total = cumulative[faces];
  if (!(total > 0)) return {};
  std::vector<double> points(3 * samples);
  if (sample_faces) sample_faces->resize(samples);
  parallel_blocks(samples, threads, [&](std::size_t begin, std::size_t end) {
    for (std::size_t i = begin; i < end; ++i) {
      std::uint64_t state = seed ^ (0xD1B54A32D192ED03ULL * (i + 1));
      const double t = (static_cast<double>(i) + unit(state)) / static_cast<double>(samples) * total;
      const auto it = std::upper_bound(cumulative.begin() + 1, cumulative.end(), t);
      std::size_t f = std::min<std::size_t>(static_cast<std::size_t>(it - cumulative.begin()) - 1, faces - 1);
      while (f > 0 && cumulative[f + 1] == cumulative[f]) --f;  // never a zero-area face
      // Uniform point in a triangle (Osada et al. 2002): r1 = sqrt(u1), weights
      // (1 − r1, r1(1 − u2), r1·u2).
      const double r1 = std::sqrt(unit(state)), u2 = unit(state);
      const double wa = 1 - r1, wb = r1 * (1 - u2), wc = r1 * u2;
      const auto a = corner(m, f, 0), b = corner(m, f, 1), c = corner(m, f, 2);
      for (int k = 0; k < 3; ++k) points[3 * i + k] = wa * a[k] + wb * b[k] + wc * c[k];
      if (sample_faces) (*sample_faces)[i] = static_cast<std::uint32_t>(f);
    }
  });
  return points;
}

SampledSurface::SampledSurface(const TriangleMesh& mesh, std::size_t samples, std::uint64_t seed, unsigned threads,
                               bool vertices)
    : query_(mesh) {
  const TriangleMesh& m = query_.mesh();

  std::vector<char> used(m.vertex_count(), 0);
  for (std::uint32_t v : m.triangles) used[v] = 1;
  std::size_t used_count = 0;
  for (char u : used) used_count += u;
  points_ = meshlift::area_samples(m, samples, seed, threads);
  area_samples_ = points_.size() / 3;
  const bool vertex_points = vertices || area_samples_ == 0;
  if (vertex_points) points_.resize(3 * (area_samples_ + used_count));

  double low[3], high[3];
  for (int k = 0; k < 3; ++k) low[k] = std::numeric_limits<double>::infinity(), high[k] = -low[k];
  std::size_t next = area_samples_;
  for (std::size_t v = 0; v < used.size(); ++v) {
    if (!used[v]) continue;
    for (int k = 0; k < 3; ++k) {
      const double x = m.positions[3 * v + k];
      if (vertex_points) points_[3 * next + k] = x;
      low[k] = std::min(low[k], x);
      high[k] = std::max(high[k], x);
    }
    ++next;
  }
  diagonal_ = std::sqrt((high[0] - low[0]) * (high[0] - low[0]) + (high[1] - low[1]) * (high[1] - low[1]) +
                        (high[2] - low[2]) * (high[2] - low[2]));
}

SurfaceDistance surface_distance(const SampledSurface& reference, const SampledSurface& test, unsigned threads) {
  SurfaceDistance result;
  result.reference_to_test = one_sided(reference, test.query(), threads);
  result.test_to_reference = one_sided(test, reference.query(), threads);
  result.rms = std::max(result.reference_to_test.rms, result.test_to_reference.rms);
  result.mean = std::max(result.reference_to_test.mean, result.test_to_reference.mean);
  result.hausdorff = std::max(result.reference_to_test.max, result.test_to_reference.max);
  result.diagonal = reference.diagonal();
  const double small = std::min(reference.diagonal(), test.diagonal());
  const double large = std::max(reference.diagonal(), test.diagonal());
  if (large > 100 * small) {
    result.warning = "the bounding-box diagonals differ by more than 100x (reference " +
                     std::to_string(reference.diagonal()) + ", test " + std::to_string(test.diagonal()) +
                     "): different units or the wrong file?";
  }
  return result;
}

namespace {

/// The samples of one side of surface_distance(reference, test), errors named by the side.
SampledSurface sampled(const TriangleMesh& mesh, const char* which, std::size_t samples, std::uint64_t seed,
                       const MetricOptions& options) {
  try {
    return SampledSurface(mesh, samples, seed, options.threads, options.vertices);
  } catch (const MeshError& e) {
    throw MeshError(std::string(which) + " mesh: " + e.what());
  }
}

std::size_t sample_count(const TriangleMesh& reference, const TriangleMesh& test, const MetricOptions& options) {
  return options.samples > 0 ? options.samples : default_sample_count(reference.face_count(), test.face_count());
}

// Different seeds for the two surfaces, so identical meshes are not sampled at identical points.
constexpr std::uint64_t kTestSeed = 0x5555555555555555ULL;

}  // namespace

SurfaceDistance surface_distance(const SampledSurface& reference, const TriangleMesh& test, const MetricOptions& options) {
  if (test.face_count() == 0) throw MeshError("test mesh has no faces");
  const SampledSurface test_surface =
      sampled(test, "test", sample_count(reference.mesh(), test, options), options.seed ^ kTestSeed, options);
  return surface_distance(reference, test_surface, options.threads);
}

SurfaceDistance surface_distance(const TriangleMesh& reference, const TriangleMesh& test, const MetricOptions& options) {
  if (reference.face_count() == 0) throw MeshError("reference mesh has no faces");
  if (test.face_count() == 0) throw MeshError("test mesh has no faces");
  const SampledSurface reference_surface =
      sampled(reference, "reference", sample_count(reference, test, options), options.seed, options);
  return surface_distance(reference_surface, test, options);
}

}  // namespace meshlift
