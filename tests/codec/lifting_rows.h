// A lifting step's rows written out, for tests that compare a fast path with the plain rule.
#pragma once

#include <cstdint>
#include <vector>

#include "meshlift/lifting.h"

namespace meshlift::test {

/// A step's rows written out: target, scale, then (source, weight) pairs.
inline std::vector<std::vector<double>> expand_rows(const LiftingStep& s) {
  std::vector<std::vector<double>> rows;
  const std::uint32_t* source = s.indices.data();
  std::uint32_t target = s.first_target;
  for (const LiftingStep::Run& run : s.runs) {
    const LiftingStep::Pattern& p = s.patterns[run.pattern];
    for (std::uint32_t r = 0; r < run.rows; ++r, ++target) {
      std::vector<double> row{static_cast<double>(target), p.scale};
      for (std::uint32_t k = 0; k < p.arity; ++k) {
        row.push_back(*source++);
        row.push_back(s.pattern_weights[p.first_weight + k]);
      }
      rows.push_back(std::move(row));
    }
  }
  return rows;
}

}  // namespace meshlift::test
