// Embedded bit-plane coding of the wavelet coefficients by set partitioning in hierarchical
// trees (SPIHT, Said & Pearlman 1996) over the semi-regular coefficient tree, as Progressive
// Geometry Compression (Khodakovsky, Schroeder, Sweldens 2000) does, with every decision coded by
// the adaptive binary range coder under a context (level, component, and what is known of the
// vertex, its siblings and its parent: FORMAT.md §5.2, versions 2 to 4), after the base part
// (base_values.h) has coded the base vertices' top planes.
// A vertex carries K components: its three geometry coefficients (x, y, z, or normal and two
// tangents in local frames) and then those of any extra channels (FORMAT.md §5).
// Encoder and decoder run the same traversal (zerotree_coder.cpp), so they cannot drift apart.
#pragma once

#include <algorithm>
#include <cstdint>
#include <limits>
#include <memory>
#include <span>
#include <vector>

#include "meshlift/range_coder.h"
#include "meshlift/semi_regular.h"

namespace meshlift::zerotree {

/// Components coded per vertex: 3 for the geometry, up to kMaxChannelComponents more.
inline constexpr int kGeometryComponents = 3;
inline constexpr int kMaxChannelComponents = 4;
inline constexpr int kMaxComponents = kGeometryComponents + kMaxChannelComponents;

/// The coding forest over all vertices: roots are the base vertices; a base vertex's children
/// are the level-1 odd vertices on the base edges it starts (edge_vertices[2e] == v); every other
/// vertex's children are its coefficient-tree children (CODEC-NOTES §1), in increasing order.
/// Every child of a vertex of level j is of level j + 1, and every odd vertex below the finest
/// level has children (3 or 4): the coder relies on both, and the constructor checks them.
struct Forest {
  static constexpr std::uint32_t kNoChild = 0xffffffffu;

  std::uint32_t roots = 0;
  std::uint32_t vertices = 0;
  int levels = 0;
  std::vector<std::uint32_t> level_starts;  ///< first vertex of each level, and `vertices`
  std::vector<std::uint32_t> root_child_offsets;  ///< roots + 1
  std::vector<std::uint32_t> root_children;
  /// 4 slots per odd vertex of levels 1 .. levels - 1 (vertex v at 4 (v - roots)): its children,
  /// the last kNoChild for the 3 of a boundary edge's vertex. Fixed slots: one memory access
  /// finds a vertex's children.
  std::vector<std::uint32_t> odd_children;

  /// \throw std::logic_error if `hierarchy` breaks the properties above.
  explicit Forest(const SemiRegularHierarchy& hierarchy);
  std::uint32_t vertex_count() const { return vertices; }
  /// Children of v, in coding order.
  std::span<const std::uint32_t> children(std::uint32_t v) const {
    if (v < roots) return {root_children.data() + root_child_offsets[v], root_children.data() + root_child_offsets[v + 1]};
    if (v >= level_starts[static_cast<std::size_t>(levels)]) return {};  // the finest level
    const std::uint32_t* slots = odd_children.data() + 4 * std::size_t{v - roots};
    return {slots, slots[3] == kNoChild ? 3u : 4u};
  }
};

/// Integer magnitudes floor(|c| / step) and signs of the normalized coefficients, `components`
/// per vertex (vertex-major), each in the record the encoder's passes read: its magnitude and
/// sign and the bit widths of the largest magnitudes below it, all in 8 bytes (one memory access
/// per coefficient in the passes). The widths are to be 0 (as the quantizer writes them):
/// encode() fills in those of the vertices with children.
struct Quantized {
  /// Trivial (no member initializers), so that allocate() leaves the records unwritten;
  /// Coefficient{} is all zeros.
  struct Coefficient {
    std::uint32_t magnitude;
    bool negative;
    std::uint8_t descendants_width;    ///< over D(v), the vertex's descendants
    std::uint8_t grandchildren_width;  ///< over L(v) = D(v) minus the children
  };
  int components = kGeometryComponents;
  std::size_t size = 0;  ///< vertices * components
  /// Left uninitialized by allocate(): the quantizer writes every record.
  std::unique_ptr<Coefficient[]> coefficients;

  /// Room for `count` records, not written.
  void allocate(std::size_t count);
};

/// Highest plane n with some magnitude >= 2^n (-1 if all are zero).
int top_plane(const Quantized& q);

/// Codes q's magnitudes and signs; fills in the widths of its vertices with children first.
/// The base vertices' bits at planes >= base_plane are not coded here (base_values.h codes them
/// before): a base coefficient with bits there starts in the LSP, the others in the LIP, and
/// both are first tested or refined at plane base_plane - 1 (FORMAT.md §5.2). base_plane >
/// top_plane: the base is coded here like every vertex (nothing before).
/// `concurrent` (and more than one component): the passes, which decide every bit from the
/// magnitudes alone, of all components but the last run on a second thread, writing their
/// decisions to a queue (model indices and bits); the caller's thread codes, at each plane,
/// those decisions, then its own component's as its passes make them. Each component's lists,
/// state and models are its own, so the same bytes as on one thread.
/// `stop_after`: the passes stop once the encoder has emitted more than this many bytes
/// (RangeEncoder::bytes_final(), checked before each decision coded, on either thread count);
/// the stream is then a prefix of the whole one but for its last few bytes, and every byte up
/// to stop_after the same. Returns whether every plane was coded.
bool encode(const Forest& forest, Quantized& q, int top_plane, int base_plane, RangeEncoder& encoder,
            bool concurrent = false, std::size_t stop_after = std::numeric_limits<std::size_t>::max());

/// SPIHT's list of significant coefficients (LSP) of one component, in the order they became
/// significant, as parallel arrays of capacity `capacity` (pages become resident as they fill):
/// vertex; level | kNegativeTag; magnitude (the decoder's: the bits known so far).
struct SignificantList {
  static constexpr std::uint8_t kNegativeTag = 0x80;
  static constexpr std::uint8_t kLevelMask = 0x7f;

  std::unique_ptr<std::uint32_t[]> vertex;
  std::unique_ptr<std::uint8_t[]> tag;
  std::unique_ptr<std::uint32_t[]> magnitude;
  std::size_t size = 0;
  /// Of the plane being coded: entries [0, refine_count) were significant before it, and
  /// [0, refined) of them have had its refinement bit.
  std::size_t refine_count = 0, refined = 0;
  /// Entries [0, preset) are the base coefficients the base part made significant (base_values.h),
  /// known down to the base plane before the first plane began.
  std::size_t preset = 0;

  explicit SignificantList(std::size_t capacity);
};

/// What the decoder knows: the significant coefficients, per component; every other one is 0.
/// Every plane is decoded whole before the next begins, so a significant coefficient's lowest
/// known plane is last_plane, or last_plane + 1 if the stream ended before its bit of
/// last_plane (the LSP entries [refined, refine_count) of each component).
struct Decoded {
  /// A significant coefficient: its magnitude lies in [known, known + 2^low_plane) steps.
  struct Coefficient {
    std::uint32_t vertex;
    int component;
    int level;  ///< of the vertex
    std::uint32_t known;
    int low_plane;
    bool negative;
    /// Reconstruction in steps: the midpoint of the interval, signed.
    double steps() const { return midpoint(known, low_plane, negative); }
  };

  int components = kGeometryComponents;
  std::vector<SignificantList> significant;  ///< one per component (none if top_plane < 0)
  int last_plane = -1;  ///< the lowest plane the decoder reached (partly or wholly)
  int base_plane = 0;   ///< the preset entries are known down to this plane at least
  bool complete = false;

  /// Calls f(const Coefficient&) for every significant coefficient, component by component.
  template <class F>
  void for_each(F&& f) const {
    for (std::size_t c = 0; c < significant.size(); ++c) {
      const SignificantList& l = significant[c];
      for (std::size_t i = 0; i < l.size; ++i) {
        const std::uint8_t tag = l.tag[i];
        const int low = last_plane + (i >= l.refined && i < l.refine_count ? 1 : 0);
        f(Coefficient{l.vertex[i], static_cast<int>(c), tag & SignificantList::kLevelMask, l.magnitude[i],
                      i < l.preset ? std::min(low, base_plane) : low, (tag & SignificantList::kNegativeTag) != 0});
      }
    }
  }

  /// A magnitude known to lie in [known, known + 2^low_plane) steps, reconstructed at the middle
  /// of that interval, signed (FORMAT.md §5); 0 if insignificant. The encoder's closed loop uses
  /// it with low_plane = 0 for what the decoder reconstructs at full rate.
  static double midpoint(std::uint32_t known, int low_plane, bool negative) {
    if (known == 0) return 0.0;
    const double mid = known + 0.5 * static_cast<double>(std::uint64_t{1} << low_plane);
    return negative ? -mid : mid;
  }
};

/// A coefficient in the transform domain from its reconstruction in steps (Decoded::Coefficient::steps,
/// or the encoder's own full-rate midpoint): steps * step / w_j. One function for both sides, so
/// that the encoder's closed loop (local frames) sees bit for bit what the decoder will.
inline double dequantize(double steps, double step, double weight) { return steps * step / weight; }

/// Decodes until the stream ends (decoder exhausted) or every plane down to 0 is done. `base_high`
/// holds the base part's values (base_values::decode: sign * (magnitude >> base_plane), vertex-major,
/// roots * components), read only if base_plane <= top_plane.
Decoded decode(const Forest& forest, int components, int top_plane, int base_plane,
               std::span<const std::int64_t> base_high, RangeDecoder& decoder);

/// decode() into `out`, for a decoder whose bytes arrive while it runs (RangeDecoder on a
/// ByteSource): out's lists are made before the first decision and filled in place, so that at
/// every decision `out` holds what the decisions before it give (for_each, last_plane), the
/// same as decode() of the bytes that had arrived. Another thread may read it while this one
/// waits in the source for bytes (ordered by the source's lock). Returns out.complete.
bool decode_into(const Forest& forest, int components, int top_plane, int base_plane,
                 std::span<const std::int64_t> base_high, RangeDecoder& decoder, Decoded& out);

}  // namespace meshlift::zerotree
