// Symmetric surface-to-surface distance between two triangle meshes, Metro-style (Cignoni,
// Rocchini, Scopigno 1998), as CODEC-NOTES §7 uses it for rate-distortion figures: points
// sampled uniformly by area on each surface, the exact distance of each to the other surface
// (closest_point.h), RMS / mean / max each way and symmetric, relative to the reference's
// bounding-box diagonal, and PSNR = 20·log10(diagonal / RMS). docs/METRIC.md has the definition.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "meshlift/closest_point.h"
#include "meshlift/mesh.h"

namespace meshlift {

struct MetricOptions {
  /// Area samples on each surface; 0 chooses default_sample_count() of the two meshes.
  std::size_t samples = 0;
  /// Worker threads; 0 uses std::thread::hardware_concurrency(). Results do not depend on it.
  unsigned threads = 0;
  /// Seed of the sample positions (a counter-based generator: sample i depends only on seed, i).
  std::uint64_t seed = 0x6d657472696300ULL;
  /// Whether the vertices are points too. They enter the maxima only (Hausdorff): a caller that
  /// needs the RMS, mean or PSNR alone gets the same values without them, for fewer queries.
  bool vertices = true;
};

/// Default area samples per surface: 10 per face of the larger mesh (Metro's default density),
/// at least 100,000 and at most 1,000,000. Measured spread of the PSNR over sample seeds (camel
/// against its Draco qp 8 decode, 65.1 dB): ±0.012 dB at 100k samples, ±0.005 dB at 1M; the
/// cap keeps two 100k-face meshes within about 1.5 s of CPU (bench/bench_metric.cpp).
std::size_t default_sample_count(std::size_t reference_faces, std::size_t test_faces);

/// `samples` points spread uniformly by area over a mesh's faces (stratified: each face gets its
/// area's share, ±1), as xyz triples; empty if the mesh has no area. Point i depends only on
/// (seed, i): the same for any thread count (0 = hardware concurrency). `sample_faces`, if
/// given, receives the face of each point.
std::vector<double> area_samples(const TriangleMesh& mesh, std::size_t samples, std::uint64_t seed,
                                 unsigned threads = 0, std::vector<std::uint32_t>* sample_faces = nullptr);

/// Distances from the points of one surface to the other surface.
struct OneSidedDistance {
  double rms = 0;   ///< sqrt(mean of d²) over the area samples (estimates the L2 surface integral)
  double mean = 0;  ///< mean of d over the area samples (L1)
  double max = 0;   ///< max of d over the area samples and every vertex used by a face
  std::size_t area_samples = 0;
  std::size_t vertex_samples = 0;
};

struct SurfaceDistance {
  OneSidedDistance reference_to_test;  ///< points of the reference, distance to the test surface
  OneSidedDistance test_to_reference;
  /// Symmetric values: the larger of the two directions (Metro's Hausdorff convention, which
  /// PGC and Normal Mesh Compression also use for the L2 distance).
  double rms = 0, mean = 0, hausdorff = 0;
  double diagonal = 0;  ///< bounding-box diagonal of the reference (its vertices used by faces)
  double rms_relative() const { return rms / diagonal; }
  double mean_relative() const { return mean / diagonal; }
  double hausdorff_relative() const { return hausdorff / diagonal; }
  /// 20·log10(diagonal / rms); +infinity when rms is 0.
  double psnr_db() const;
  /// Non-empty when the comparison is suspect (bounding-box diagonals differing by more than
  /// 100×: probably different units or the wrong file); the numbers are still computed.
  std::string warning;
};

/// One mesh prepared for comparisons: its BVH, its area samples and its vertices. Building it
/// once lets one reference be compared with many test meshes (the rate-distortion sweep).
class SampledSurface {
 public:
  /// With `vertices` false the vertices are not points (MetricOptions::vertices), unless the
  /// mesh has no area (then they are its only points).
  /// \throw MeshError if the mesh has no faces or bad coordinates / indices (SurfaceQuery).
  SampledSurface(const TriangleMesh& mesh, std::size_t samples, std::uint64_t seed, unsigned threads = 0,
                 bool vertices = true);

  const SurfaceQuery& query() const { return query_; }
  const TriangleMesh& mesh() const { return query_.mesh(); }
  /// Area samples as xyz triples, then the vertices used by faces, in index order (if they are points).
  const std::vector<double>& points() const { return points_; }
  std::size_t area_samples() const { return area_samples_; }
  double diagonal() const { return diagonal_; }

 private:
  SurfaceQuery query_;
  std::vector<double> points_;
  std::size_t area_samples_ = 0;
  double diagonal_ = 0;
};

/// Surface distance between two prepared surfaces (same sample counts are not required).
/// Bit-identical for any thread count: every point's distance is computed on its own and the
/// sums run in point order.
SurfaceDistance surface_distance(const SampledSurface& reference, const SampledSurface& test, unsigned threads = 0);

/// surface_distance(reference's mesh, test, options) with the reference's samples made already
/// (SampledSurface(mesh, samples, options.seed, threads, options.vertices), the same samples
/// the two-mesh form makes): for a caller that measures many meshes against one.
/// \throw MeshError as the two-mesh form, for the test mesh.
SurfaceDistance surface_distance(const SampledSurface& reference, const TriangleMesh& test, const MetricOptions& options);

/// Surface distance between two meshes.
/// \throw MeshError if either mesh has no faces or has non-finite coordinates / bad indices
///        (the message names which mesh).
SurfaceDistance surface_distance(const TriangleMesh& reference, const TriangleMesh& test,
                                 const MetricOptions& options = {});

}  // namespace meshlift
