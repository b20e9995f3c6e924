// Lifting wavelet transforms on a semi-regular hierarchy (CODEC-NOTES §2-4, seed 003 §5.4).
// Each level's transform is a short list of lifting steps; each step is a precomputed table
// (compressed rows of indices and weights) built once from the connectivity. analyze() and
// synthesize() are tight loops over these tables and exact inverses of each other.
#pragma once

#include <cstdint>
#include <functional>
#include <span>
#include <string>
#include <vector>

#include "meshlift/semi_regular.h"

namespace meshlift {

/// Frozen values: stored in files later.
enum class Scheme : std::uint8_t {
  linear = 0,     ///< odd = (a+b)/2
  butterfly = 1,  ///< modified butterfly (Zorin, Schroeder, Sweldens 1996), 4-point on boundaries
  loop = 2,       ///< Loop subdivision as predict + update (CODEC-NOTES §3)
};

const char* to_string(Scheme scheme);

/// Loop's beta_n = (1/n) (5/8 - (3/8 + cos(2 pi / n) / 4)^2) (Loop 1987; CODEC-NOTES §2), n >= 1.
double loop_beta(unsigned valence);
/// Parses "linear", "butterfly", "loop"; throws std::invalid_argument otherwise.
Scheme parse_scheme(const std::string& name);

struct WaveletOptions {
  Scheme scheme = Scheme::loop;
  /// linear/butterfly only: add the mean-preserving update (seed 003 eq. 5.9). Loop always has
  /// its own update step (the Loop vertex rule), so this flag is ignored for it.
  bool mean_preserving_update = false;
};

/// One lifting step: for every target vertex t (rows), in synthesis
///   x[t] = scale * x[t] + sum_k weight_k * x[source_k]
/// and in analysis the inverse x[t] = (x[t] - sum_k weight_k * x[source_k]) / scale.
/// Targets and sources are disjoint vertex sets (odd and even), so each step is exactly invertible.
/// Rows share their weights: a scheme has only a handful of distinct rows (regular, boundary,
/// one per extraordinary valence and ring position), so each row stores only its source indices
/// and a pattern holds the scale and the weights. On a semi-regular mesh nearly every row is the
/// regular one, so the rows are stored as runs of consecutive rows of one pattern: the hot loops
/// read one pattern per run, not one per row, and run the regular rows with their arity known at
/// compile time.
struct LiftingStep {
  struct Pattern {
    std::uint32_t arity = 0;         ///< number of sources
    std::uint32_t first_weight = 0;  ///< into pattern_weights
    double scale = 1.0;
  };
  /// `rows` consecutive rows of one pattern.
  struct Run {
    std::uint32_t pattern = 0;
    std::uint32_t rows = 0;
  };
  /// `indices` is followed by this many more entries (zeros), so that the loops over it may read
  /// the sources of rows ahead (to prefetch them) without a bounds check.
  static constexpr std::uint32_t kPadding = 48;

  std::uint32_t first_target = 0;  ///< rows are vertices first_target .. first_target + rows() - 1
  std::uint32_t row_count = 0;
  std::vector<Run> runs;
  std::vector<std::uint32_t> indices;  ///< sources, row after row, then kPadding zeros
  std::vector<Pattern> patterns;
  std::vector<double> pattern_weights;

  std::size_t rows() const { return row_count; }
  std::size_t memory_bytes() const;
};

class WaveletTransform {
 public:
  WaveletTransform(const SemiRegularHierarchy& hierarchy, WaveletOptions options);
  /// Only the tables of levels first_level .. end_level - 1 (of the steps first_level ->
  /// end_level): for a caller that runs one level at a time and wants the tables of one level in
  /// memory at once (a decoder: those of the last level are about three quarters of all).
  /// analyze() and synthesize() throw std::logic_error when asked for a level without tables.
  /// \pre 0 <= first_level <= end_level <= hierarchy.levels().
  WaveletTransform(const SemiRegularHierarchy& hierarchy, WaveletOptions options, int first_level, int end_level);

  /// Fine values -> base values (vertices [0, vertex_count(0))) and, at every odd vertex, its
  /// detail coefficient; in place. values holds vertex_count(levels) * channels doubles
  /// (vertex-major: channels values per vertex).
  void analyze(std::span<double> values, int channels = 3) const;
  /// Base values + details -> values of the mesh at `to_level` (in the first
  /// vertex_count(to_level) vertices); in place. to_level = -1 means the finest level.
  /// from_level > 0 starts from values that already are those of the mesh at from_level (the
  /// first vertex_count(from_level) vertices) and runs only the levels from there. `concurrent`:
  /// each large step's rows in two halves on two threads (the same bits: no row reads another's).
  void synthesize(std::span<double> values, int channels = 3, int to_level = -1, int from_level = 0,
                  bool concurrent = false) const;

  int levels() const { return static_cast<int>(steps_.size()); }
  const WaveletOptions& options() const { return options_; }
  /// Steps of level j -> j+1, in synthesis order (empty for a level without tables).
  const std::vector<LiftingStep>& steps(int level) const { return steps_[level]; }
  std::size_t memory_bytes() const;

 private:
  void require_tables(int first_level, int end_level) const;

  WaveletOptions options_;
  int first_level_ = 0, end_level_ = 0;  ///< the levels with tables
  std::vector<std::uint32_t> vertex_counts_;
  std::vector<std::vector<LiftingStep>> steps_;
};

/// Synthesis of level `level` -> `level` + 1 alone: the bits of
/// WaveletTransform(hierarchy, options, level, level + 1).synthesize(values, channels, level + 1, level),
/// for a caller that runs one level at a time and needs no tables afterwards (a decoder). For
/// Loop above the base the predict step is applied as its rows are read off the coarse faces and
/// the update step's rows are built and applied a block at a time in one small buffer; linear
/// and butterfly apply their predict rows as they read them off the level below too (at the base
/// they build and apply them a block at a time). With the mean-preserving update, its step comes
/// first, without a table either: the predict rows' column sums over a first pass of those rows,
/// then each even vertex's row as a scatter over the level's edges in increasing order (above
/// the base read off the level below), the same operations in the same order as its table row.
/// So those tables (18 to 36 bytes per vertex of level + 1) are never in memory, and each block
/// is applied while it is in cache; Loop's level 0 builds the level's tables. Only level 0 reads
/// topology(level): above it the hierarchy need hold levels up to level - 1 only.
/// \pre 0 <= level < hierarchy.levels(); values hold vertex_count(level + 1) * channels doubles.
void synthesize_level(const SemiRegularHierarchy& hierarchy, WaveletOptions options, int level, std::span<double> values,
                      int channels = 3);
/// The same, calling before_odd(first, count) for the odd vertices [first, first + count) of level
/// `level` + 1, every one exactly once and before any step reads it, while the level's even
/// vertices still hold the level-`level` mesh: in each predict block's or chunk's turn where the
/// level is made a block or chunk at a time, else (Loop's level 0, and the mean-preserving update, which reads all
/// the details first) once for all of them first. For a caller that prepares the details there
/// while they are in cache (the decoder turns them out of their local frames).
/// With `concurrent`, the block paths (Loop above the base, linear and butterfly) run on two
/// threads, each half of a step's rows on one: the same bits (a step's rows are independent), and
/// before_odd is then called from both threads at once, with disjoint ranges. With the
/// mean-preserving update, its one call runs on a thread of its own beside the column sums' pass
/// (which reads only the topology and writes only its own sums), and both end before the update
/// reads a detail.
/// `update_weights`, if not empty, are update_weights(hierarchy, options.scheme, level), made
/// once by a caller that synthesizes the level again and again (a streaming decoder) or earlier
/// on a spare thread; else the update's synthesis computes them. Ignored without the update.
void synthesize_level(const SemiRegularHierarchy& hierarchy, WaveletOptions options, int level, std::span<double> values,
                      int channels, const std::function<void(std::uint32_t first, std::uint32_t count)>& before_odd,
                      bool concurrent = false, std::span<const double> update_weights = {});

/// Analysis of level `level` + 1 -> `level` alone, the inverse of synthesize_level(): the bits of
/// the tables' analysis of that level (WaveletTransform::analyze runs the levels from the finest
/// down), without the tables above the base, as synthesize_level() reads its rows (Loop: the
/// update's rows a block at a time, then the predict rows straight off the coarse faces; linear
/// and butterfly: the predict rows as they are read off the level below, then the
/// mean-preserving update as a scatter over the level's edges into a buffer of the level's
/// values). The base builds its tables (small). For an encoder that needs no tables afterwards.
/// `concurrent`: each large step's rows in two halves on two threads (the same bits).
/// `update_weights`: as for synthesize_level (computed here if empty; ignored without the update).
/// \pre 0 <= level < hierarchy.levels(); values hold vertex_count(level + 1) * channels doubles.
void analyze_level(const SemiRegularHierarchy& hierarchy, WaveletOptions options, int level, std::span<double> values,
                   int channels = 3, bool concurrent = false, std::span<const double> update_weights = {});

/// The mean-preserving update's weight in the row of each vertex of level `level` (below
/// vertex_count(level)), for linear or butterfly: -lambda_v, lambda_v = 1 / (2 (1 + c_v)) with c_v
/// the sum of v's weights in the level's predict rows (docs/WAVELETS.md; seed 003 eq. 5.9): the
/// weights of stencils::mean_preserving_update's rows, bit for bit, without its table. Reads the
/// topology of level - 1 only (of level 0 at the base). \throw std::invalid_argument for Loop or
/// a level not below the finest.
std::vector<double> update_weights(const SemiRegularHierarchy& hierarchy, Scheme scheme, int level);

}  // namespace meshlift
