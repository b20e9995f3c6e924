// Interpolation by iterated limit differences (seed 000 eq. 1-3, CODEC-NOTES §5).
#include "meshlift/interpolate.h"

#include <cmath>
#include <stdexcept>
#include <string>

#include "meshlift/limit.h"
#include "meshlift/polygon_subdivision.h"

namespace meshlift {

namespace {

void check_options(const FitOptions& options) {
  if (options.max_iterations < 0)
    throw std::invalid_argument("fit: max_iterations must be >= 0, got " + std::to_string(options.max_iterations));
  if (!(std::isfinite(options.tolerance) && options.tolerance >= 0))
    throw std::invalid_argument("fit: tolerance must be a finite number >= 0");
}

void check_finite(const std::vector<double>& positions) {
  for (std::size_t i = 0; i < positions.size(); ++i)
    if (!std::isfinite(positions[i]))
      throw MeshError("vertex " + std::to_string(i / 3) + " has a coordinate that is not a finite number");
}

/// Runs the iteration on `result.control.positions` (which holds P on entry) and fills
/// residuals and converged.
void iterate(const LimitStencil& limit_operator, const FitOptions& options, FitResult& result) {
  const std::vector<double> targets = result.control.positions;
  std::vector<double>& control = result.control.positions;
  std::vector<double> limit(targets.size());
  result.diagonal = bounding_box_diagonal(targets);
  const double threshold = options.tolerance * result.diagonal;
  result.residuals.reserve(static_cast<std::size_t>(options.max_iterations) + 1);
  for (int k = 0;; ++k) {
    // Seed 000 eq. 1-3: M_0 = P, M_{i+1} = M_i - A M_i = (E - A)^{i+1} P, control = Σ M_i = A^-1 P.
    // With C_k = M_0 + ... + M_k, the next term is M_{k+1} = P - A C_k (induction on k), so
    // C_{k+1} = C_k + (P - A C_k): the difference is also the residual that decides when to stop.
    limit_operator.apply(control, limit);
    double residual = 0;
    for (std::size_t v = 0; 3 * v < targets.size(); ++v) {
      const double d[3] = {targets[3 * v] - limit[3 * v], targets[3 * v + 1] - limit[3 * v + 1],
                           targets[3 * v + 2] - limit[3 * v + 2]};
      residual = std::max(residual, std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]));
    }
    result.residuals.push_back(residual);
    result.converged = residual <= threshold;
    if (result.converged || k == options.max_iterations) return;
    for (std::size_t i = 0; i < targets.size(); ++i) control[i] += targets[i] - limit[i];
  }
}

}  // namespace

FitResult fit_loop(const TriangleMesh& targets, const FitOptions& options) {
  check_options(options);
  check_finite(targets.positions);
  const LimitStencil limit_operator = loop_limit_stencil(targets);
  FitResult result;
  result.control = to_polygon_mesh(targets);
  iterate(limit_operator, options, result);
  return result;
}

FitResult fit_catmull_clark(const PolygonMesh& targets, const FitOptions& options) {
  check_options(options);
  check_finite(targets.positions);
  FitResult result;
  for (std::size_t f = 0; f < targets.face_count() && !result.subdivided_first; ++f)
    result.subdivided_first = targets.face_size(f) != 4;
  // The limit formula (seed 000, after eq. 4) needs quads: the appendix subdivides once first.
  result.control = result.subdivided_first ? catmull_clark(targets, 1) : targets;
  const LimitStencil limit_operator = catmull_clark_limit_stencil(result.control);
  iterate(limit_operator, options, result);
  return result;
}

}  // namespace meshlift
