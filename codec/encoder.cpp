// Semi-regular mesh -> .mlz stream: analyze, normalize and quantize, then the HEAD, BASE and
// COEF chunks (bitstream/FORMAT.md §3-5). Mirrors decoder.cpp.
#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <memory>
#include <optional>
#include <thread>

#include "base_mesh_coder.h"
#include "base_values.h"
#include "canonical_order.h"
#include "concurrent.h"
#include "large_array.h"
#include "local_frames.h"
#include "meshlift/codec.h"
#include "meshlift/container.h"
#include "quantize.h"
#include "stencils.h"
#include "stream_header.h"
#include "zerotree_coder.h"

namespace meshlift {
namespace {

/// COEF chunks hold this many bytes of the range-coded stream each, so that corruption is
/// located to within one chunk while the per-chunk overhead stays below 0.02 %.
constexpr std::size_t kCoefficientChunkBytes = 64 * 1024;

/// L2 norm of the synthesis basis function of one vertex of each level (CODEC-NOTES §4): a unit
/// coefficient at a vertex in the middle of the level's range, synthesized to the finest level.
/// Scaling level j's coefficients by it makes one quantization step cost the same squared error
/// at every level.
///
/// Each impulse above the base is synthesized over its support only, a small part of the finest
/// level (the base vertex's, whose support is not small, by the whole synthesis: see below):
/// a row of a lifting step whose target and sources are all zero gives +0 (its scale is positive),
/// which is what an untouched zero holds, and zeros add nothing to the sum of squares; so
/// computing exactly the rows that can be nonzero, each by the operations synthesize() applies
/// (lifting.cpp: scale * target first, then the sources in table order), gives the norm's bits.
/// A row can be nonzero only if its target or one of its sources is. Every predict row's sources
/// lie within one edge of an endpoint of its edge (linear: the endpoints; Loop: the wing
/// vertices; butterfly: wings, tips across the wing edges, an extraordinary endpoint's ring,
/// boundary neighbours), so the rows to compute are those of the edges at the live vertices and
/// at their neighbours; an update row's sources are the odd vertices on its vertex's edges, so
/// those are the endpoints of live odd vertices' edges and the live even vertices themselves.
/// `buffer` holds at least vertex_count(L) zeros and is left holding zeros; `update` each level's
/// mean-preserving update weights (update_weights(); empty for Loop or without the update). The
/// rows and the incident edges come from stencils::LevelRows, one at a time, each row as its
/// table holds it: no table is built above the base, no level but the base lists its edges.
std::vector<double> level_weights(const SemiRegularHierarchy& h, WaveletOptions wavelet, std::span<double> buffer,
                                  const std::vector<std::vector<double>>& update) {
  const int L = h.levels();
  std::vector<double> weights(static_cast<std::size_t>(L) + 1);
  std::vector<std::unique_ptr<stencils::LevelRows>> level_rows;
  std::size_t most_rows = 0;
  for (int i = 0; i < L; ++i) {
    const auto level = static_cast<std::size_t>(i);
    level_rows.push_back(
        std::make_unique<stencils::LevelRows>(h, wavelet, i, i > 0 ? level_rows.back().get() : nullptr, update[level]));
    for (const stencils::LevelRows::Step& step : level_rows.back()->steps())
      most_rows = std::max<std::size_t>(most_rows, step.rows);
  }
  double* x = buffer.data();
  const std::uint32_t V_L = h.vertex_count(L);
  std::vector<std::uint8_t> is_live, is_near, is_candidate;
  assign_large(is_live, V_L);
  assign_large(is_near, V_L);
  assign_large(is_candidate, most_rows);
  std::vector<std::uint32_t> live, near, candidates, incident;
  auto make_live = [&](std::uint32_t v) {
    if (!is_live[v]) is_live[v] = 1, live.push_back(v);
  };
  // Calls f(v) for the marked entries v of `marks` listed in `list`, in increasing order, clearing
  // their marks: by a sweep over the marks when the list is long, else by sorting it. The sweep
  // skips 8 clear marks per test, ~n / 8 steps against sorting's ~k log2 k for k entries: it wins
  // down to lists of about n / 256 entries.
  auto in_order = [](std::vector<std::uint8_t>& marks, std::vector<std::uint32_t>& list, std::size_t n, auto&& f) {
    if (list.size() * 256 > n) {
      // Most marks are clear: 8 of them tested at once, the set ones then in order.
      std::uint32_t v = 0;
      for (; v + 8 <= n; v += 8) {
        std::uint64_t word;
        std::memcpy(&word, &marks[v], sizeof word);
        if (word == 0) continue;
        for (std::uint32_t u = v; u < v + 8; ++u)
          if (marks[u]) marks[u] = 0, f(u);
      }
      for (; v < n; ++v)
        if (marks[v]) marks[v] = 0, f(v);
    } else {
      std::sort(list.begin(), list.end());
      for (const std::uint32_t v : list) marks[v] = 0, f(v);
    }
    list.clear();
  };
  for (int j = 0; j <= L; ++j) {
    if (j == 0) {
      // A base vertex's support covers much of the finest level: there the whole synthesis, one
      // channel, costs less than tracking the support (15-18 against 40-60 ms on the bench mesh,
      // in a resident buffer). It gives the same bits: the rows outside the support compute +0 as
      // said above, and their squares add nothing to the sum, taken in the same vertex order.
      x[h.vertex_count(0) / 2] = 1.0;
      for (int i = 0; i < L; ++i)
        synthesize_level(h, wavelet, i, buffer.first(V_L), 1, {}, false, update[static_cast<std::size_t>(i)]);
      double sum = 0.0;
      for (std::uint32_t v = 0; v < V_L; ++v) {
        sum += x[v] * x[v];
        x[v] = 0.0;
      }
      weights[0] = std::sqrt(sum);
      continue;
    }
    const std::uint32_t begin = h.vertex_count(j - 1);
    x[begin + (h.vertex_count(j) - begin) / 2] = 1.0;
    make_live(begin + (h.vertex_count(j) - begin) / 2);
    for (int i = std::max(0, j - 1); i < L; ++i) {
      const std::uint32_t V = h.vertex_count(i), fine_V = h.vertex_count(i + 1);
      stencils::LevelRows& rows = *level_rows[static_cast<std::size_t>(i)];
      for (std::size_t s = 0; s < rows.steps().size(); ++s) {
        const stencils::LevelRows::Step step = rows.steps()[s];
        auto candidate = [&](std::uint32_t target) {
          const std::uint32_t row = target - step.first_target;
          if (!is_candidate[row]) is_candidate[row] = 1, candidates.push_back(row);
        };
        if (step.first_target == V) {  // predict: targets are the odd vertices V + e
          // The live even vertices and their neighbours, then the edges at them.
          auto make_near = [&](std::uint32_t v) {
            if (!is_near[v]) is_near[v] = 1, near.push_back(v);
          };
          for (const std::uint32_t u : live) {
            if (u >= V) {
              if (u < fine_V) candidate(u);
              continue;
            }
            make_near(u);
            rows.incident_edges(u, incident);
            for (const std::uint32_t e : incident) {
              std::uint32_t a, b;
              rows.edge_ends(e, a, b);
              make_near(a == u ? b : a);
            }
          }
          for (const std::uint32_t w : near) {
            is_near[w] = 0;
            rows.incident_edges(w, incident);
            for (const std::uint32_t e : incident) candidate(V + e);
          }
          near.clear();
        } else {  // update: targets are the even vertices
          for (const std::uint32_t u : live) {
            if (u < V) {
              candidate(u);
            } else if (u < fine_V) {
              std::uint32_t a, b;
              rows.edge_ends(u - V, a, b);
              candidate(a);
              candidate(b);
            }
          }
        }
        // The candidate rows in row order, each as synthesize_run computes it for one channel.
        in_order(is_candidate, candidates, step.rows, [&](std::uint32_t row) {
          const std::uint32_t target = step.first_target + row;
          const stencils::LevelRows::Row r = rows.row(s, target);
          double acc = r.scale * x[target];
          for (std::size_t k = 0; k < r.sources.size(); ++k) acc += r.weights[k] * x[r.sources[k]];
          x[target] = acc;
          make_live(target);
        });
      }
    }
    // The sum of squares in vertex order, over the vertices that may be nonzero.
    double sum = 0.0;
    in_order(is_live, live, V_L, [&](std::uint32_t v) {
      sum += x[v] * x[v];
      x[v] = 0.0;
    });
    weights[static_cast<std::size_t>(j)] = std::sqrt(sum);
  }
  return weights;
}

}  // namespace

std::vector<std::uint8_t> encode(const SemiRegularMesh& input, const EncodeOptions& options) {
  const SemiRegularHierarchy& given = input.hierarchy;
  const std::uint32_t V = given.vertex_count(given.levels());
  if (V >= (std::uint32_t{1} << 31)) throw MeshError("encode: too many vertices");
  if (options.precision_bits < 1 || options.precision_bits > 40)
    throw MeshError("encode: precision_bits must be between 1 and 40");
  if (options.local_frames && (options.tangent_shift < 0 || options.tangent_shift > 16))
    throw MeshError("encode: tangent_shift must be between 0 and 16");
  if (!input.channels.empty()) {
    if (input.channels.size() > 4) throw MeshError("encode: at most 4 extra channels");
    if (options.channel_precision_bits < 1 || options.channel_precision_bits > 40)
      throw MeshError("encode: channel_precision_bits must be between 1 and 40");
    int total = 0;
    for (const VertexChannel& c : input.channels) {
      if (c.colour && (&c != &input.channels.front() || c.components != 3))
        throw MeshError("encode: the colour must be the first extra channel, of 3 components");
      total += c.components;
      if (c.components < 1 || total > zerotree::kMaxChannelComponents)
        throw MeshError("encode: extra channels may have " + std::to_string(zerotree::kMaxChannelComponents) +
                        " components together, at least 1 each");
    }
  }
  std::vector<char> used(given.vertex_count(0), 0);
  for (std::uint32_t v : given.triangles(0)) used[v] = 1;
  if (std::find(used.begin(), used.end(), 0) != used.end()) throw MeshError("encode: the base mesh has vertices no face uses");

  // With more than one thread, the independent stages run side by side (concurrent.h): the
  // canonical hierarchy's topology while its renumbering is computed, the level weights while the
  // values are gathered and analyzed.
  const bool concurrent = options.threads == 0
                              ? std::thread::hardware_concurrency() > 1 && V >= EncodeOptions::kConcurrentEncodeVertices
                              : options.threads > 1;
  // The canonical order as a renumbering, read through: no reordered copy of the positions, and
  // a hierarchy without the finest faces, the coefficient tree and the topology of the level below
  // the finest (nothing here reads them: what needs that level reads it off the level below, as
  // the decoder does). A mesh in that order already (a decoded one, canonical_order()'s output)
  // is read as it is.
  const std::optional<CanonicalHierarchy> canonical =
      canonical_hierarchy_if_reordered(input, false, false, concurrent, false);  // also checks the array sizes
  const bool in_order = !canonical;
  const SemiRegularHierarchy& h = in_order ? given : canonical->hierarchy;
  const std::uint32_t* const old_vertex = in_order ? nullptr : canonical->old_vertex.data();
  const int L = h.levels();

  StreamHeader header;
  header.scheme = options.scheme;
  header.mean_preserving_update = options.mean_preserving_update && options.scheme != Scheme::loop;
  header.levels = L;
  header.base_vertices = h.vertex_count(0);
  header.base_faces = static_cast<std::uint32_t>(h.topology(0).face_count());
  header.local_frames = options.local_frames;
  header.tangent_shift = options.local_frames ? options.tangent_shift : 0;
  header.colour = !input.channels.empty() && input.channels.front().colour;

  // The values to analyze, K per vertex (geometry, then the channels), in canonical order: first
  // as given, then centred below. Made resident in one system call (large_array.h), as the arrays below.
  const int K = 3 + [&] {
    int n = 0;
    for (const VertexChannel& c : input.channels) n += c.components;
    return n;
  }();
  const std::size_t k_stride = static_cast<std::size_t>(K);
  std::vector<double> values;
  const WaveletOptions wavelet{header.scheme, header.mean_preserving_update};
  // The mean-preserving update's weights of each level (its predict rows' column sums), made once
  // for the level weights, the analysis and the closed loop's syntheses: the finest level's (about
  // three quarters of the work) beside the others'.
  std::vector<std::vector<double>> update(static_cast<std::size_t>(L));
  if (wavelet.mean_preserving_update && L > 0)
    run_both(
        concurrent, [&] { update.back() = update_weights(h, wavelet.scheme, L - 1); },
        [&] {
          for (int j = 0; j + 1 < L; ++j) update[static_cast<std::size_t>(j)] = update_weights(h, wavelet.scheme, j);
        });
  // No transform tables (18 to 36 bytes per vertex, and their build on the critical path): the
  // values are analyzed a level at a time as the decoder synthesizes them (analyze_level), and
  // the level weights read the few rows and incident edges they follow one at a time
  // (stencils::LevelRows). On one side those weights, into a buffer of zeros made resident before
  // the base vertex's whole synthesis writes it (large_array.h: one system call for the pages
  // instead of a fault each). On the other the values gathered, analyzed, and the quantized
  // records' pages made resident (every record is written below).
  zerotree::Quantized q;
  q.components = K;
  std::optional<zerotree::Forest> forest;
  run_both(concurrent, [&] {
    std::vector<double> impulses;
    assign_large(impulses, V, 0.0);
    header.level_weights = level_weights(h, wavelet, impulses, update);
    for (double& weight : header.level_weights) weight = header_float(weight, "level weight", true);
  }, [&] {
    // Each value's extremes over all vertices (the bounding box and the channels' ranges), and
    // whether one is NaN or infinite, in one pass over the input in its own order (min and max are
    // exact; the one case where their order shows, a signed zero, is settled below); the values
    // are then gathered in canonical order already centred, each written once.
    double lowest[zerotree::kMaxComponents], highest[zerotree::kMaxComponents];  // K <= kMaxComponents: checked above
    // Whether a coordinate ([0]) or a channel value ([1]) is NaN or infinite.
    bool nonfinite[2] = {false, false};
    // The extremes as a pass in canonical order finds them: where every value of a component is
    // a zero, min and max keep the first they see, so the sign of the centre (0.5 (lo + hi)) is
    // that of canonical vertex 0's zero. Elsewhere the order changes nothing they give.
    const std::size_t first_vertex = in_order ? 0 : old_vertex[0];
    auto take_extremes = [&](const std::vector<double>& array, std::size_t n, std::size_t first) {
      // In locals: in the arrays, every value's update would be stored and loaded back.
      double low[zerotree::kMaxComponents], high[zerotree::kMaxComponents];
      std::fill_n(low, n, std::numeric_limits<double>::infinity());
      std::fill_n(high, n, -std::numeric_limits<double>::infinity());
      bool bad = false;
      for (std::size_t v = 0; v < V; ++v)
        for (std::size_t i = 0; i < n; ++i) {
          const double x = array[n * v + i];
          low[i] = std::min(low[i], x);
          high[i] = std::max(high[i], x);
          bad |= !(std::abs(x) <= std::numeric_limits<double>::max());
        }
      for (std::size_t i = 0; i < n; ++i)
        if (low[i] == 0 && high[i] == 0) low[i] = high[i] = array[n * first_vertex + i];
      std::copy_n(low, n, lowest + first);
      std::copy_n(high, n, highest + first);
      nonfinite[first >= 3] |= bad;
    };
    take_extremes(input.positions, 3, 0);
    std::size_t offset = 3;
    for (const VertexChannel& c : input.channels) {
      take_extremes(c.values, static_cast<std::size_t>(c.components), offset);
      offset += static_cast<std::size_t>(c.components);
    }
    if (nonfinite[0]) throw MeshError("encode: a vertex coordinate is NaN or infinite");
    if (nonfinite[1]) throw MeshError("encode: a channel value is NaN or infinite");
    // Bounding box and centre in canonical order (as over canonical_order(input).positions; the
    // diagonal as bounding_box_diagonal computes it from the same extremes).
    double lo[3], hi[3];
    for (std::size_t k = 0; k < 3; ++k) {
      lo[k] = lowest[k];
      hi[k] = highest[k];
      header.center[k] = header_float(0.5 * (lo[k] + hi[k]), "bounding-box centre", false);
    }
    double diagonal = std::sqrt((hi[0] - lo[0]) * (hi[0] - lo[0]) + (hi[1] - lo[1]) * (hi[1] - lo[1]) +
                                (hi[2] - lo[2]) * (hi[2] - lo[2]));
    if (!(diagonal > 0)) diagonal = 1.0;
    header.step = std::ldexp(diagonal, -options.precision_bits);
    // Each channel: centred on the middle of each component's range, one step for all its
    // components from the widest range.
    offset = 3;
    for (const VertexChannel& c : input.channels) {
      ChannelQuantization hc;
      hc.components = c.components;
      double range = 0, magnitude = 0;
      for (int k = 0; k < c.components; ++k) {
        const std::size_t i = offset + static_cast<std::size_t>(k);
        const double low = lowest[i], high = highest[i];
        hc.center.push_back(header_float(0.5 * (low + high), "channel centre", false));
        range = std::max(range, high - low);
        magnitude = std::max({magnitude, std::abs(low), std::abs(high)});
      }
      // A range at the values' own rounding level is none: a constant carried through
      // interpolation (a file's one grey, 0.7529411764705882 ± an ulp, read off the input at each
      // vertex) would get a step of ~1e-19, and the values' offset from the header's float centre
      // (up to 2^-24 of the magnitude) would be past 2^31 steps. Above 2^-30 of the magnitude that
      // offset is below 2^(6 + channel_precision_bits) steps times the level weight: far within.
      if (range <= 0x1p-30 * magnitude) range = 0;
      hc.step = std::ldexp(range > 0 ? range : 1.0, -options.channel_precision_bits);
      header.channels.push_back(std::move(hc));
      offset += static_cast<std::size_t>(c.components);
    }

    // The values in canonical order, centred (on the header's centres: the decoder adds the same).
    double centre[zerotree::kMaxComponents];
    std::copy(header.center.begin(), header.center.end(), centre);
    offset = 3;
    for (const ChannelQuantization& c : header.channels) {
      std::copy(c.center.begin(), c.center.end(), centre + offset);
      offset += c.center.size();
    }
    reserve_large(values, std::size_t{V} * k_stride);  // appended: each value written once
    // One value at a time (push_back inlines; a 3-value insert per vertex is a memmove call).
    for (std::uint32_t v = 0; v < V; ++v) {
      const std::size_t old = in_order ? v : old_vertex[v];
      for (std::size_t i = 0; i < 3; ++i) values.push_back(input.positions[3 * old + i] - centre[i]);
      std::size_t k = 3;
      for (const VertexChannel& c : input.channels) {
        const std::size_t n = static_cast<std::size_t>(c.components);
        for (std::size_t i = 0; i < n; ++i) values.push_back(c.values[n * old + i] - centre[k++]);
      }
    }
    forest.emplace(h);  // the coefficient tree for the bit planes
    // Analysis of the centred values, from the finest level down: base values at [0, V0),
    // details at the odd vertices. On this thread alone (the other is busy).
    for (int j = L - 1; j >= 0; --j) analyze_level(h, wavelet, j, values, K, false, update[static_cast<std::size_t>(j)]);
    q.allocate(values.size());
    populate(q.coefficients.get(), q.size * sizeof(zerotree::Quantized::Coefficient));
  });

  // Quantization: magnitude = floor(|c w_j| / step_c) (a dead-zone quantizer; the decoder
  // reconstructs at the middle of the interval its bits leave open).
  std::vector<double> base_step(k_stride), detail_step(k_stride);
  for (int c = 0; c < K; ++c) {
    base_step[static_cast<std::size_t>(c)] = header.component_step(c, 0);
    detail_step[static_cast<std::size_t>(c)] = header.component_step(c, 1);
  }
  // Quantizes the coefficients of vertices [first, first + count) of level j (quantize.h); if
  // `reconstruction` is given, writes there what the decoder will reconstruct from them at full
  // rate (it may be `values` itself: each is written after its coefficient is read). Returns
  // whether a step was too fine for a coefficient (thrown after the loops below).
  auto quantize_vertices = [&](int j, std::size_t first, std::size_t count, double* reconstruction) {
    const std::size_t i = k_stride * first;
    return quantize(&values[i], k_stride * count, K, (j == 0 ? base_step : detail_step).data(),
                    header.level_weights[static_cast<std::size_t>(j)], q.coefficients.get() + i,
                    reconstruction != nullptr ? reconstruction + i : nullptr);
  };
  auto quantize_level = [&](int j, double* reconstruction) {
    const std::size_t first = j == 0 ? 0 : h.vertex_count(j - 1);
    return quantize_vertices(j, first, h.vertex_count(j) - first, reconstruction);
  };
  bool too_fine = false;
  if (!header.local_frames) {
    for (int j = 0; j <= L; ++j) too_fine |= quantize_level(j, nullptr);
  } else {
    // The closed loop's reconstruction in the coefficients' own array: once a vertex's
    // coefficients are quantized nothing reads them again, so each is overwritten by what the
    // decoder will reconstruct from them; vertices [0, V_j) then hold the decoder's level-j mesh,
    // those above still the coefficients to quantize (no second array of V K values).
    const std::span<double> decoded(values);
    // Closed loop: the frames of level j + 1 come from the level-j mesh as the decoder will have
    // it at full rate (quantized coarser levels, synthesized), not from the exact one, so both
    // sides rotate by the same frames bit for bit. Every value of `decoded` a synthesis reads has
    // been written by then (the base, then each level's odd vertices before its synthesis).
    too_fine |= quantize_level(0, decoded.data());
    for (int j = 0; j < L; ++j) {
      // The level's frames computed once for both rotations, a block at a time: the block's odd
      // vertices' details into their frames, quantized, their reconstructions back (the same
      // operations as three passes over the level: no vertex reads another's values here, so
      // the two halves of the level's edges may run side by side).
      // The finest level's reconstruction is read by nothing (no frames are made from it): its
      // details are only turned and quantized.
      const bool finest = j + 1 == L;
      const frames::LevelFrames level_frames(h, j, decoded, K);
      auto close_loop = [&](std::uint32_t begin, std::uint32_t end) {
        bool too_fine_here = false;
        level_frames.for_each_block(begin, end, [&](const frames::FrameBlock& block) {
          const std::size_t first = h.odd_vertex(j, block.first_edge);
          for (std::uint32_t i = 0; i < block.count; ++i)
            block.rotate(i, &values[k_stride * (first + i)], frames::Direction::to_local);
          too_fine_here |= quantize_vertices(j + 1, first, block.count, finest ? nullptr : decoded.data());
          if (finest) return;
          for (std::uint32_t i = 0; i < block.count; ++i)
            block.rotate(i, &decoded[k_stride * (first + i)], frames::Direction::to_global);
        });
        return too_fine_here;
      };
      const std::uint32_t edges = level_frames.edge_count(), half = edges / 2;
      bool first_half = false, second_half = false;
      run_both(
          concurrent, [&] { second_half = close_loop(half, edges); }, [&] { first_half = close_loop(0, half); });
      too_fine |= first_half || second_half;
      if (!finest) synthesize_level(h, wavelet, j, decoded, K, {}, concurrent, update[static_cast<std::size_t>(j)]);
    }
  }
  if (too_fine)
    throw MeshError("encode: precision_bits " + std::to_string(options.precision_bits) + " is too fine for " +
                    std::to_string(L) + " levels; use fewer bits");
  header.top_plane = zerotree::top_plane(q);
  header.base_plane = options.predict_base
                          ? base_values::choose_base_plane(h.topology(0), q, header.top_plane)
                          : header.top_plane + 1;

  // The base part, then the bit planes (FORMAT.md §5). With a budget the planes stop once the
  // coefficient bytes emitted pass the end of the chunk the file's cut falls in (the file's
  // first max_bytes bytes hold fewer coefficient bytes than that): those chunks are then the
  // whole stream's, byte for byte and at the same sizes, and so is the file truncate_file()
  // makes of them below, without the planes past the cut.
  std::size_t stop_after = std::numeric_limits<std::size_t>::max();
  if (options.max_bytes < stop_after - 2 * kCoefficientChunkBytes)
    stop_after = (options.max_bytes / kCoefficientChunkBytes + 1) * kCoefficientChunkBytes;
  RangeEncoder coefficient_encoder;
  base_values::encode(h.topology(0), q, header.base_plane, header.top_plane, coefficient_encoder);
  zerotree::encode(*forest, q, header.top_plane, header.base_plane, coefficient_encoder, concurrent, stop_after);
  const std::vector<std::uint8_t> coefficients = coefficient_encoder.finish();

  ContainerWriter writer;
  writer.add_chunk(kTagHeader, header.write());
  writer.add_chunk(kTagBaseMesh, base_mesh::encode_faces(h.triangles(0), h.vertex_count(0)));
  // Nothing decodes without the whole header and base connectivity: a budget below them would
  // give a file that only a cut inside its base chunk can produce, which reads as corrupt.
  const std::size_t minimum = writer.size();
  if (options.max_bytes < minimum)
    throw MeshError("encode: a budget of " + std::to_string(options.max_bytes) +
                    " bytes is below this mesh's smallest decodable stream, " + std::to_string(minimum) +
                    " bytes (header and base mesh); raise the budget or use a smaller base");
  for (std::size_t offset = 0; offset < coefficients.size(); offset += kCoefficientChunkBytes)
    writer.add_chunk(kTagCoefficients,
                     std::span(coefficients).subspan(offset, std::min(kCoefficientChunkBytes, coefficients.size() - offset)));
  std::vector<std::uint8_t> file = writer.finish();
  if (file.size() > options.max_bytes) {
    // truncate_file may add up to a 4-byte checksum after the cut: cut that much earlier.
    std::vector<std::uint8_t> cut;
    const std::size_t target = options.max_bytes > container::kChecksumBytes ? options.max_bytes - container::kChecksumBytes : 0;
    if (truncate_file(file, target, cut) != Status::ok)
      throw MeshError("encode: max_bytes " + std::to_string(options.max_bytes) + " is smaller than the stream's header");
    file = std::move(cut);
  }
  return file;
}

}  // namespace meshlift
