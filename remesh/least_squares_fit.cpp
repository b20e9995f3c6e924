// Least-squares fitting of a semi-regular mesh to the input surface. See least_squares_fit.h.
//
// Each round: (1) closest points both ways — the input's area samples onto the current mesh
// (a BVH of the mesh, rebuilt per round) and four points of each mesh face onto the input;
// (2) the normal equations of E(V) with those correspondences fixed, assembled straight into a
// CSR matrix whose pattern is the mesh's vertex adjacency (every sample's three corners are the
// corners of one face, so every product b_i b_j lands on an edge or the diagonal); (3) conjugate
// gradients from the current positions, x, y and z against the same matrix; (4) each vertex's
// move is limited to a fraction of its edges' length; (5) the move of any face it would turn
// away from the input is undone. Assembly runs in sample order on one thread and the
// queries write per-sample results, so the result does not depend on the thread count.
#include "meshlift/least_squares_fit.h"

#include <Eigen/IterativeLinearSolvers>
#include <Eigen/SparseCore>
#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>

#include "meshlift/metric.h"
#include "adjacency.h"
#include "parallel.h"
#include "vec3.h"

namespace meshlift {
namespace {

using Vec = vec3::Vec3;
using vec3::at;
using vec3::cross;
using vec3::dot;
using vec3::face_normal;
using vec3::sub;

/// The symmetric pattern "v and its neighbours" of a triangle mesh as CSR (rows sorted), and for
/// each face the positions of its 9 corner pairs (i, j) in the value array.
struct Pattern {
  std::vector<int> offsets, columns;
  std::vector<std::array<int, 9>> face_slots;

  Pattern(const Adjacency& adjacency, const std::vector<std::uint32_t>& triangles) {
    const std::size_t vertices = adjacency.neighbour_offsets.size() - 1;
    offsets.assign(vertices + 1, 0);
    columns.reserve(adjacency.neighbours.size() + vertices);
    for (std::uint32_t v = 0; v < vertices; ++v) {
      const auto first = adjacency.neighbours.begin() + adjacency.neighbour_offsets[v];
      const auto end = adjacency.neighbours.begin() + adjacency.neighbour_offsets[v + 1];
      const auto diagonal = std::lower_bound(first, end, v);
      columns.insert(columns.end(), first, diagonal);
      columns.push_back(static_cast<int>(v));
      columns.insert(columns.end(), diagonal, end);
      offsets[v + 1] = static_cast<int>(columns.size());
    }
    face_slots.resize(triangles.size() / 3);
    for (std::size_t f = 0; f < face_slots.size(); ++f)
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) face_slots[f][3 * i + j] = slot(triangles[3 * f + i], triangles[3 * f + j]);
  }
  int slot(std::uint32_t row, std::uint32_t column) const {
    const auto begin = columns.begin() + offsets[row], end = columns.begin() + offsets[row + 1];
    return static_cast<int>(std::lower_bound(begin, end, static_cast<int>(column)) - columns.begin());
  }
};

}  // namespace

LeastSquaresFitReport fit_least_squares(SemiRegularMesh& mesh, const SurfaceQuery& surface,
                                        const LeastSquaresFitOptions& options) {
  if (options.iterations < 0 || !(options.samples_per_face > 0) || !(options.stiffness >= 0) ||
      !(options.max_step > 0))
    throw std::invalid_argument(
        "fit_least_squares: iterations >= 0, samples_per_face > 0, stiffness >= 0, max_step > 0");
  LeastSquaresFitReport report;
  const SemiRegularHierarchy& h = mesh.hierarchy;
  const std::vector<std::uint32_t>& triangles = h.triangles(h.levels());
  const std::uint32_t n = h.vertex_count(h.levels());
  const std::size_t faces = triangles.size() / 3;
  if (options.iterations == 0 || faces == 0) return report;

  const Adjacency adjacency(n, triangles);
  Pattern pattern(adjacency, triangles);
  // Boundary vertices stay where the fitting stage put them, on the input's boundary curves:
  // pinned in the solve (a large weight to their position) and then put back exactly.
  std::vector<std::uint32_t> pinned;
  for (std::uint32_t v = 0; v < n; ++v)
    if (adjacency.on_boundary(v) || (v < options.fixed.size() && options.fixed[v])) pinned.push_back(v);
  const TriangleMesh& input = surface.mesh();
  const std::size_t sample_count = static_cast<std::size_t>(std::ceil(options.samples_per_face * faces));
  std::vector<std::uint32_t> sample_faces;
  const std::vector<double> samples = area_samples(input, sample_count, options.seed, options.threads, &sample_faces);
  // The input's face normals (length: twice the area), for the normal tests and the area.
  std::vector<Vec> input_normals(input.face_count());
  double input_area = 0;
  for (std::size_t f = 0; f < input.face_count(); ++f) {
    input_normals[f] = face_normal(input.positions, &input.triangles[3 * f]);
    input_area += 0.5 * std::sqrt(dot(input_normals[f], input_normals[f]));
  }
  const double sample_weight = samples.empty() ? 0 : input_area / static_cast<double>(samples.size() / 3);

  // Four points per mesh face: the centroid and the midpoints between it and each corner.
  // Measured against the centroid alone: armadillo, camel, cow, lion-head and mannequin-devil
  // (L = 3) within -3.8..+3.8 dB of each other, the four points steadier on the corpus.
  constexpr int kPoints = 4;
  // Mean length of the edges at each vertex, for the step limit.
  auto mean_edge = [&](std::span<const double> p, std::uint32_t v) {
    double sum = 0;
    int count = 0;
    for (int e = pattern.offsets[v]; e < pattern.offsets[v + 1]; ++e) {
      const auto k = static_cast<std::uint32_t>(pattern.columns[e]);
      if (k == v) continue;
      const Vec d = sub(at(p, k), at(p, v));
      sum += std::sqrt(dot(d, d)), ++count;
    }
    return count > 0 ? sum / count : 0.0;
  };

  std::vector<double>& x = mesh.positions;
  std::vector<double> values(pattern.columns.size());
  std::vector<SurfacePoint> on_mesh(samples.size() / 3), on_input(kPoints * faces);
  using Matrix = Eigen::SparseMatrix<double, Eigen::RowMajor, int>;

  for (int round = 0; round < options.iterations; ++round) {
    const std::vector<double> before = x;
    // (1) Correspondences.
    const SurfaceQuery mesh_query(TriangleMesh{x, triangles});
    parallel_blocks(on_mesh.size(), options.threads, [&](std::size_t begin, std::size_t end) {
      // Hints (the answers do not depend on them): the face the sample found last round (the
      // mesh moved little), else the previous sample's (samples follow the input's faces).
      std::uint32_t previous = kNone;
      for (std::size_t s = begin; s < end; ++s) {
        on_mesh[s] = mesh_query.closest({samples[3 * s], samples[3 * s + 1], samples[3 * s + 2]},
                                        round > 0 ? on_mesh[s].face : previous);
        previous = on_mesh[s].face;
      }
    });
    parallel_blocks(faces, options.threads, [&](std::size_t begin, std::size_t end) {
      std::uint32_t previous = kNone;
      for (std::size_t f = begin; f < end; ++f) {
        const Vec a = at(x, triangles[3 * f]), b = at(x, triangles[3 * f + 1]), c = at(x, triangles[3 * f + 2]);
        for (int k = 0; k < kPoints; ++k) {
          Vec p;
          const double* w = vec3::kFourPoints[k];
          for (int i = 0; i < 3; ++i) p[i] = w[0] * a[i] + w[1] * b[i] + w[2] * c[i];
          on_input[kPoints * f + k] = surface.closest(p, round > 0 ? on_input[kPoints * f + k].face : previous);
          previous = on_input[kPoints * f + k].face;
        }
      }
    });

    // Which way each face should face: the input's normal at the closest point of its centroid.
    std::vector<Vec> normals(faces), reference(faces);
    std::vector<std::uint8_t> facing_before(faces);
    std::size_t folded = 0;
    for (std::size_t f = 0; f < faces; ++f) {
      normals[f] = face_normal(x, &triangles[3 * f]);
      reference[f] = input_normals[on_input[kPoints * f].face];
      facing_before[f] = dot(normals[f], reference[f]) > 0;
      folded += !facing_before[f];
    }
    report.folded_faces.push_back(folded);

    // (2) Normal equations: M V = r, M = Σ w B^T B + κ L, in sample order.
    std::fill(values.begin(), values.end(), 0.0);
    Eigen::MatrixXd rhs = Eigen::MatrixXd::Zero(n, 3);
    auto add = [&](std::size_t f, const double* b, double w, const double* target) {
      const std::uint32_t* t = &triangles[3 * f];
      for (int i = 0; i < 3; ++i) {
        for (int j = 0; j < 3; ++j) values[pattern.face_slots[f][3 * i + j]] += w * b[i] * b[j];
        for (int c = 0; c < 3; ++c) rhs(t[i], c) += w * b[i] * target[c];
      }
    };
    double input_sum = 0, mesh_sum = 0, mesh_area = 0;
    std::size_t used_samples = 0;
    for (std::size_t s = 0; s < on_mesh.size(); ++s) {
      // A sample whose closest mesh face faces the other way belongs to another sheet of the
      // surface (the far side of a thin part): it would pull that face through (ICP's normal
      // compatibility test).
      if (dot(normals[on_mesh[s].face], input_normals[sample_faces[s]]) <= 0) continue;
      add(on_mesh[s].face, on_mesh[s].barycentric.data(), sample_weight, &samples[3 * s]);
      input_sum += on_mesh[s].distance * on_mesh[s].distance;
      ++used_samples;
    }
    for (std::size_t f = 0; f < faces; ++f) {
      const double area = 0.5 * std::sqrt(dot(normals[f], normals[f]));
      mesh_area += area;
      for (int k = 0; k < kPoints; ++k) {
        add(f, vec3::kFourPoints[k], area / kPoints, on_input[kPoints * f + k].point.data());
        mesh_sum += area / kPoints * on_input[kPoints * f + k].distance * on_input[kPoints * f + k].distance;
      }
    }
    report.input_to_mesh_rms.push_back(std::sqrt(input_sum / std::max<double>(1, static_cast<double>(used_samples))));
    report.mesh_to_input_rms.push_back(mesh_area > 0 ? std::sqrt(mesh_sum / mesh_area) : 0);
    // Membrane around V⁰: κ Σ |(V_j − V_k) − (V⁰_j − V⁰_k)|² over the edges (each once: j < k).
    const double kappa = options.stiffness * mesh_area / static_cast<double>(faces);
    for (std::uint32_t j = 0; j < n; ++j)
      for (int e = pattern.offsets[j]; e < pattern.offsets[j + 1]; ++e) {
        const auto k = static_cast<std::uint32_t>(pattern.columns[e]);
        if (k <= j) continue;
        values[pattern.slot(j, j)] += kappa, values[pattern.slot(k, k)] += kappa;
        values[e] -= kappa, values[pattern.slot(k, j)] -= kappa;
        for (int c = 0; c < 3; ++c) {
          const double d = x[3 * j + c] - x[3 * k + c];
          rhs(j, c) += kappa * d, rhs(k, c) -= kappa * d;
        }
      }

    const double pin = 1e6 * mesh_area / static_cast<double>(faces);
    for (std::uint32_t v : pinned) {
      values[pattern.slot(v, v)] += pin;
      for (int c = 0; c < 3; ++c) rhs(v, c) += pin * x[3 * v + c];
    }

    // (3) Conjugate gradients from the current positions (Jacobi preconditioner).
    const Eigen::Map<Matrix> m(n, n, static_cast<int>(values.size()), pattern.offsets.data(), pattern.columns.data(),
                               values.data());
    Eigen::ConjugateGradient<Matrix, Eigen::Lower | Eigen::Upper> cg;
    cg.setTolerance(1e-8);
    cg.setMaxIterations(1000);
    cg.compute(m);
    for (int c = 0; c < 3; ++c) {
      Eigen::VectorXd guess(n);
      for (std::uint32_t v = 0; v < n; ++v) guess[v] = x[3 * v + c];
      const Eigen::VectorXd solved = cg.solveWithGuess(rhs.col(c), guess);
      for (std::uint32_t v = 0; v < n; ++v)
        if (std::isfinite(solved[v])) x[3 * v + c] = solved[v];
    }

    for (std::uint32_t v : pinned)
      for (int c = 0; c < 3; ++c) x[3 * v + c] = before[3 * v + c];
    // (4) A step limit: no vertex moves by more than max_step × its mean edge length per round.
    // Where the mesh is on the surface the moves are fractions of the sag, far below it; where a
    // face spans a gap between two parts of the input the data terms would stretch it further
    // (measured: mannequin-devil 69.3 dB instead of 76.2 without the limit).
    for (std::uint32_t v = 0; v < n; ++v) {
      const Vec move = sub(at(x, v), at(before, v));
      const double length = std::sqrt(dot(move, move)), limit = options.max_step * mean_edge(before, v);
      if (length > limit)
        for (int c = 0; c < 3; ++c) x[3 * v + c] = before[3 * v + c] + move[c] * (limit / length);
    }
    // (5) Undo the move of every face that faced the input before the solve and would face away
    // from it after (the input normal at the closest point of its centroid, as
    // find_fold_overs() judges), until none does.
    std::size_t reverted = 0;
    for (bool changed = true; changed;) {
      changed = false;
      for (std::size_t f = 0; f < faces; ++f) {
        const std::uint32_t* t = &triangles[3 * f];
        if (!facing_before[f] || dot(face_normal(x, t), reference[f]) > 0) continue;
        bool moved = false;
        for (int i = 0; i < 3; ++i)
          for (int c = 0; c < 3; ++c)
            if (x[3 * t[i] + c] != before[3 * t[i] + c]) x[3 * t[i] + c] = before[3 * t[i] + c], moved = true;
        if (moved) ++reverted, changed = true;
      }
    }
    report.reverted_faces.push_back(reverted);
  }
  return report;
}

}  // namespace meshlift
