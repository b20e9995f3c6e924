// Builds the lifting steps of one level (level j -> j+1) as index+weight tables, one rule per
// scheme, each formula beside the code that applies it. Internal to codec/.
#pragma once

#include <cstdint>
#include <functional>

#include "meshlift/lifting.h"
#include "meshlift/topology.h"

namespace meshlift::stencils {

/// Predict step: one row per odd vertex V_j + e (edge e of level j), sources are even vertices.
/// Synthesis adds the prediction to the stored detail: odd = detail + P(even).
LiftingStep predict(const TriangleTopology& topology, Scheme scheme);

/// The rows of predict(topology, scheme) for linear or butterfly, the same rows in the same
/// order, as consecutive blocks of `block_rows` rows (one step per block, its targets
/// consecutive), handed to `apply` one at a time in one reused buffer: applying each block as it
/// comes is the synthesis of the whole step (its rows are independent), without its table in
/// memory. \throw std::invalid_argument for Scheme::loop (loop_refined_blocks).
void predict_blocks(const TriangleTopology& topology, Scheme scheme, std::uint32_t block_rows,
                    const std::function<void(const LiftingStep&)>& apply);

/// Loop's vertex rule written over the odd vertices (CODEC-NOTES §3): one row per even vertex,
/// synthesis even' = s_n even + w_n sum(adjacent odd); boundary even' = even/2 + (odd_l + odd_r)/4.
LiftingStep loop_update(const TriangleTopology& topology);

/// predict(fine, Scheme::loop) and loop_update(fine) for a level that is the 1:4 refinement of
/// `coarse` (fine == coarse.refined(), as in a SemiRegularHierarchy): the same rows, read off the
/// coarse level's faces by the refinement rule instead of searched for in the fine level, in
/// about a quarter of the random memory accesses.
LiftingStep loop_predict_refined(const TriangleTopology& coarse, const TriangleTopology& fine);
LiftingStep loop_update_refined(const TriangleTopology& coarse, const TriangleTopology& fine);

/// The rows of loop_predict_refined and then of loop_update_refined, the same rows in the same
/// order, as consecutive blocks of about `block_rows` rows each (one step per block, its targets
/// consecutive), handed to `apply` one at a time in one reused buffer: applying each block as it
/// comes is the synthesis of the whole steps (a step's rows are independent: targets and sources
/// are disjoint), without their tables in memory, and with each block's rows still in cache.
void loop_refined_blocks(const TriangleTopology& coarse, const TriangleTopology& fine, std::uint32_t block_rows,
                         const std::function<void(const LiftingStep&)>& apply);
/// The same knowing only the fine level's vertex count (all the rows read of it), for a
/// hierarchy that does not hold the fine level's topology.
void loop_refined_blocks(const TriangleTopology& coarse, std::uint32_t fine_vertices, std::uint32_t block_rows,
                         const std::function<void(const LiftingStep&)>& apply);

/// Mean-preserving update for interpolating schemes (seed 003 eq. 5.9), as its synthesis
/// (inverse) step: even = even~ - lambda_l * sum(adjacent details), lambda_l = 1 / (2 (1 + c_l)),
/// c_l the column sum of `predict` at l (see lifting.cpp for the derivation from eq. 5.8).
LiftingStep mean_preserving_update(const TriangleTopology& topology, const LiftingStep& predict);

}  // namespace meshlift::stencils
