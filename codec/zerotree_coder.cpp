#include "zerotree_coder.h"

#include "concurrent.h"
#include "large_array.h"

#include <algorithm>
#include <atomic>
#include <bit>
#include <exception>
#include <memory>
#include <stdexcept>
#include <type_traits>

namespace meshlift::zerotree {

Forest::Forest(const SemiRegularHierarchy& h) {
  vertices = h.vertex_count(h.levels());
  roots = h.vertex_count(0);
  levels = h.levels();
  level_starts.push_back(0);
  for (int j = 0; j <= levels; ++j) level_starts.push_back(h.vertex_count(j));
  root_child_offsets.assign(std::size_t{roots} + 1, 0);
  const TriangleTopology& base = h.topology(0);
  if (levels > 0) {
    for (std::uint32_t e = 0; e < base.edge_count(); ++e) ++root_child_offsets[base.edge_vertices[2 * e] + 1];
    for (std::uint32_t v = 0; v < roots; ++v) root_child_offsets[v + 1] += root_child_offsets[v];
    root_children.resize(root_child_offsets[roots]);
    std::vector<std::uint32_t> fill(root_child_offsets.begin(), root_child_offsets.end() - 1);
    for (std::uint32_t e = 0; e < base.edge_count(); ++e) root_children[fill[base.edge_vertices[2 * e]]++] = h.odd_vertex(0, e);
  }
  // Odd vertices of levels 1 .. levels - 1: 3 or 4 children each, all of the next level, read off
  // the topologies as SemiRegularHierarchy::children() gives them (CODEC-NOTES §1): the odd vertex
  // on edge p of level j - 1 has the odd vertices on the halves 2p, 2p + 1 of p, then those on the
  // inner edges 2E + 3f + i parallel to p (face edge i of f) in the faces f of p, ascending. (The
  // hierarchy need not store its tree: the decoder builds it without.)
  const std::uint32_t parents_end = levels >= 2 ? h.vertex_count(levels - 1) : roots;
  assign_large(odd_children, 4 * std::size_t{parents_end - roots}, kNoChild);
  for (int j = 1; j < levels; ++j) {
    const TriangleTopology& coarse = h.topology(j - 1);
    const auto coarse_edges = static_cast<std::uint32_t>(coarse.edge_count());
    std::uint32_t* slots = odd_children.data() + 4 * std::size_t{h.vertex_count(j - 1) - roots};
    for (std::uint32_t p = 0; p < coarse_edges; ++p) {
      slots[4 * p] = h.odd_vertex(j, 2 * p);
      slots[4 * p + 1] = h.odd_vertex(j, 2 * p + 1);
    }
    for (std::uint32_t f = 0; f < coarse.face_count(); ++f)
      for (std::uint32_t i = 0; i < 3; ++i) {
        std::uint32_t* slot = slots + 4 * std::size_t{coarse.face_edges[3 * f + i]};
        if (slot[3] != kNoChild) throw std::logic_error("zerotree::Forest: an edge in more than two faces");
        slot[slot[2] == kNoChild ? 2 : 3] = h.odd_vertex(j, 2 * coarse_edges + 3 * f + i);
      }
    for (std::uint32_t p = 0; p < coarse_edges; ++p)
      if (slots[4 * p + 2] == kNoChild) throw std::logic_error("zerotree::Forest: an odd vertex without 3 or 4 children");
  }
}

namespace {

/// An array of fixed capacity, left uninitialized: its pages become resident only as entries are
/// written, so a capacity at the worst-case bound costs only the address space.
template <class T>
std::unique_ptr<T[]> reserve(std::size_t capacity) {
  return std::make_unique_for_overwrite<T[]>(capacity);
}

}  // namespace

SignificantList::SignificantList(std::size_t capacity)
    : vertex(reserve<std::uint32_t>(capacity)), tag(reserve<std::uint8_t>(capacity)), magnitude(reserve<std::uint32_t>(capacity)) {}

// make_unique_for_overwrite writes nothing only for a trivially constructible record.
static_assert(std::is_trivially_default_constructible_v<Quantized::Coefficient> && sizeof(Quantized::Coefficient) == 8);

void Quantized::allocate(std::size_t count) {
  coefficients = std::make_unique_for_overwrite<Coefficient[]>(count);
  size = count;
}

int top_plane(const Quantized& q) {
  std::uint32_t m = 0;
  for (std::size_t i = 0; i < q.size; ++i) m = std::max(m, q.coefficients[i].magnitude);
  int n = -1;
  while (n < 31 && (std::uint64_t{1} << (n + 1)) <= m) ++n;
  return n;
}

namespace {

constexpr int kLevelContexts = kMaxLevels + 1;

// FORMAT.md §5 (version 2). The level is that of the vertex tested (for the sets: whose set it is).
// One array, so that a model has an index (the two-thread encoder queues decisions by it).
class Models {
 public:
  BitModel& lip(int level, int c) { return model(level, c, kLip); }
  // By how many siblings were significant before (capped at 3), and the child's position among
  // its parent's children (capped at 3: halves first, then the inner edges).
  BitModel& child(int level, int c, int found, int position) { return model(level, c, kChild + 4 * found + position); }
  // By whether the set's vertex is significant itself in this component.
  BitModel& set_descendants(int level, int c, int own) { return model(level, c, kSetDescendants + own); }
  BitModel& set_grandchildren(int level, int c, int own) { return model(level, c, kSetGrandchildren + own); }
  BitModel& refine(int level, int c) { return model(level, c, kRefine); }
  // By the parent's coefficient in this component: not significant (or a root), positive, negative.
  BitModel& sign(int level, int c, int parent) { return model(level, c, kSign + parent); }

  static constexpr int kPerComponent = 25;
  static constexpr std::size_t kCount = std::size_t{kLevelContexts} * kMaxComponents * kPerComponent;
  std::size_t index(const BitModel& m) const { return static_cast<std::size_t>(&m - all_); }
  BitModel& operator[](std::size_t i) { return all_[i]; }

  // The LIP's significance and the signs drift fastest along the lists (across the surface):
  // their models settle at shift 4 (count_max 7), the others at shift 5 (FORMAT.md §5).
  static constexpr std::uint8_t kFastCountMax = 7;
  static_assert(kFastCountMax <= range_coder::kCountMax, "BitModel::count_max indexes kShiftForCount");
  Models() {
    for (int level = 0; level < kLevelContexts; ++level)
      for (int c = 0; c < kMaxComponents; ++c) {
        lip(level, c).count_max = kFastCountMax;
        for (int parent = 0; parent < 3; ++parent) sign(level, c, parent).count_max = kFastCountMax;
      }
  }

 private:
  // Each (level, component)'s models: the LIP's, 16 children's, 2 + 2 sets', the refinement's, 3 signs'.
  static constexpr int kLip = 0, kChild = 1, kSetDescendants = 17, kSetGrandchildren = 19, kRefine = 21, kSign = 22;
  BitModel& model(int level, int c, int k) {
    return all_[static_cast<std::size_t>((level * kMaxComponents + c) * kPerComponent + k)];
  }
  BitModel all_[kCount];
};

// What the contexts read of a coefficient coded so far (2 bits per vertex and component).
constexpr std::uint8_t kSignificant = 1;
constexpr std::uint8_t kSignificantNegative = 2;
// A type-B LIS entry made by a type-A entry none of whose children was significant: L(v) holds
// the significant descendant, so its decision at the same plane is not coded (FORMAT.md §5).
constexpr std::uint8_t kImpliedTag = 0x40;
// LIP and child tags: the level in bits 0-3, the parent's state in bits 4-5 (the sign context).
constexpr std::uint8_t kTagLevelMask = 0x0f;
constexpr int kParentStateShift = 4;


// SPIHT's three lists for one component, as parallel arrays. Every entry carries its vertex's
// level (the context), and the encoder's entries also the value their next decision tests, so
// that the passes, which run once per plane, only walk their lists in order; the per-vertex
// arrays are read once per entry, when it is made.
struct ComponentLists {
  // LIP, coefficients tested one by one. A coefficient enters it at most once: capacity V.
  std::unique_ptr<std::uint32_t[]> lip_vertex;
  // level | parent's state when the entry was made << kParentStateShift | (encoder only) negative << 7
  std::unique_ptr<std::uint8_t[]> lip_tag;
  std::unique_ptr<std::uint32_t[]> lip_magnitude;  // encoder only
  std::size_t lip_size = 0;
  // LIS: vertex, level << 1 | (1 for type B: grandchildren) | kImpliedTag. Only a vertex with
  // children has an entry, first of type A, then perhaps one of type B, one at a time; within a pass the removed
  // entries are compacted away behind the reading position, so the array never holds more than
  // the live entries plus those appended in the pass: capacity 2 * (vertices with children).
  std::unique_ptr<std::uint32_t[]> lis_vertex;
  std::unique_ptr<std::uint8_t[]> lis_tag;
  std::unique_ptr<std::uint8_t[]> lis_width;  // encoder only: bit width of the largest magnitude in the set
  std::size_t lis_size = 0;
  // LSP (the encoder's magnitudes are whole), of capacity V: the decoder's is the Decoded's own,
  // filled in place.
  SignificantList& lsp;

  ComponentLists(const Forest& f, bool encoder, SignificantList& significant) : lsp(significant) {
    const std::uint32_t V = f.vertex_count();
    std::size_t parents = f.odd_children.size() / 4;
    for (std::uint32_t v = 0; v < f.roots; ++v) parents += !f.children(v).empty();
    lip_vertex = reserve<std::uint32_t>(V);
    lip_tag = reserve<std::uint8_t>(V);
    lis_vertex = reserve<std::uint32_t>(2 * parents);
    lis_tag = reserve<std::uint8_t>(2 * parents);
    if (encoder) {
      lip_magnitude = reserve<std::uint32_t>(V);
      lis_width = reserve<std::uint8_t>(2 * parents);
    }
  }
};

constexpr std::uint8_t kNegativeTag = SignificantList::kNegativeTag;
constexpr std::uint8_t kLevelMask = SignificantList::kLevelMask;
constexpr std::size_t kPrefetchDistance = 16;

// One SPIHT run, shared by encoder and decoder. Io supplies the decisions: the encoder computes
// and codes them, the decoder decodes them and returns -1 once the stream is exhausted, where
// the run stops (all decisions before were exactly the encoder's). Only the encoder evaluates
// the values handed to io.bit (`Io::kEncoder && ...`).
//   Sorting pass at plane n: each LIP coefficient: significant? (then sign, move to LSP).
//   Each LIS entry of type A: any descendant significant? If so, each child: significant?
//   (sign, LSP) or to the LIP; the entry becomes type B if grandchildren exist. Type B: any
//   grandchild significant? If so, every child with children joins the LIS as type A.
//   Refinement pass: bit n of every coefficient that was significant before this plane.
//   Two decisions SPIHT implies are not coded (FORMAT.md §5, version 2): the last child of a
//   significant D(v) that is only children, when no sibling was significant; and L(v) at the
//   plane where D(v) was significant and no child was.
// Returns false where the decoder's input ran out; `lists` then hold what was decoded.
// Runs the passes of components [first_component, end_component) only (all of them by default),
// calling io.begin_component(n, c) before each component's passes at plane n: the encoder runs
// some components on one thread and the rest on another (encode()).
template <class Io>
bool run(const Forest& f, int components, int top, int base_plane, const std::int64_t* base_high, Io& caller_io,
         std::vector<ComponentLists>& lists, Models& models, int first_component = 0, int end_component = -1) {
  if (end_component < 0) end_component = components;
  constexpr bool kEncoder = Io::kEncoder;
  // The passes work on a local Io, handed back on every exit: a local whose address does not
  // escape can live in registers (the decoder's range and code), where one behind a reference
  // would be stored and reloaded around every byte store (which may alias anything).
  struct HandBack {
    Io& to;
    Io& from;
    ~HandBack() { to = std::move(from); }
  };
  Io io(std::move(caller_io));
  const HandBack hand_back{caller_io, io};
  // The children of a vertex that has some (only those have LIS entries): a root's from its
  // offsets, an odd vertex's from its 4 slots.
  const std::uint32_t roots = f.roots;
  const std::uint32_t* const root_child_offsets = f.root_child_offsets.data();
  const std::uint32_t* const root_children = f.root_children.data();
  const std::uint32_t* const odd_children = f.odd_children.data();
  auto children = [&](std::uint32_t v, const std::uint32_t*& first) -> std::uint32_t {
    if (v < roots) {
      first = root_children + root_child_offsets[v];
      return root_child_offsets[v + 1] - root_child_offsets[v];
    }
    first = odd_children + 4 * std::size_t{v - roots};
    return first[3] == Forest::kNoChild ? 3 : 4;
  };
  // Every child of a vertex of level j is of level j + 1 and has children unless that is the
  // finest level (Forest): no need to look at the children themselves.
  const int finest = f.levels;
  // The state of each coefficient, 2 bits: 0, or kSignificant / kSignificantNegative once it is
  // significant. Only read for vertices with children (LIS entries), so kept for the levels
  // below the finest only (a quarter of the vertices); per component, 4 vertices a byte: the
  // array of a 2.6 M-vertex mesh (160 KiB a component) stays in a core's L2 cache, where its
  // scattered writes are cheap.
  const std::uint32_t stateful = f.level_starts[static_cast<std::size_t>(finest)];
  const std::size_t state_bytes = (std::size_t{stateful} + 3) / 4;
  const std::unique_ptr<std::uint8_t[]> state_storage =
      std::make_unique<std::uint8_t[]>(state_bytes * static_cast<std::size_t>(components));
  // Base part (FORMAT.md §5.2): the base coefficients with bits at planes >= base_plane start in
  // the LSP, in vertex order, significant (their state set), known down to base_plane; the
  // others in the LIP, in front of every child that joins it. Both are left out of the passes
  // above base_plane (the first base_lip LIP and lsp.preset LSP entries are skipped there).
  const bool base_part = base_plane <= top;
  std::vector<std::size_t> base_lip(static_cast<std::size_t>(components));
  auto high_part = [&](std::uint32_t v, int c) -> std::int64_t {
    if (!base_part) return 0;
    if constexpr (kEncoder) return io.magnitude(v, c) >> base_plane;
    return base_high[std::size_t{v} * static_cast<std::size_t>(components) + static_cast<std::size_t>(c)];
  };
  for (int c = first_component; c < end_component; ++c) {
    ComponentLists& l = lists[static_cast<std::size_t>(c)];
    std::uint8_t* const component_state = state_storage.get() + state_bytes * static_cast<std::size_t>(c);
    SignificantList& lsp = l.lsp;
    for (std::uint32_t v = 0; v < f.roots; ++v) {
      const std::int64_t high = high_part(v, c);
      if (high == 0) continue;
      const bool negative = kEncoder ? io.negative(v, c) : high < 0;
      if (v < stateful)
        component_state[v >> 2] |= static_cast<std::uint8_t>((negative ? kSignificantNegative : kSignificant) << (2 * (v & 3)));
      lsp.vertex[lsp.size] = v;
      lsp.tag[lsp.size] = negative ? kNegativeTag : 0;  // level 0
      lsp.magnitude[lsp.size] =
          kEncoder ? io.magnitude(v, c) : static_cast<std::uint32_t>((high < 0 ? -high : high) << base_plane);
      ++lsp.size;
    }
    lsp.preset = lsp.size;
    for (std::uint32_t v = 0; v < f.roots; ++v) {
      if (high_part(v, c) != 0) continue;
      l.lip_vertex[l.lip_size] = v;
      l.lip_tag[l.lip_size] = kEncoder && io.negative(v, c) ? kNegativeTag : 0;
      if constexpr (kEncoder) l.lip_magnitude[l.lip_size] = io.magnitude(v, c);
      ++l.lip_size;
    }
    base_lip[static_cast<std::size_t>(c)] = l.lip_size;
    for (std::uint32_t v = 0; v < f.roots; ++v) {
      if (!f.children(v).empty()) {
        l.lis_vertex[l.lis_size] = v;
        l.lis_tag[l.lis_size] = 0;
        if constexpr (kEncoder) l.lis_width[l.lis_size] = io.descendants_width(v, c);
        ++l.lis_size;
      }
    }
  }
  for (int n = top; n >= 0; --n) {
    io.begin_plane(n);
    for (int c = first_component; c < end_component; ++c) {
      ComponentLists& l = lists[static_cast<std::size_t>(c)];
      l.lsp.refine_count = l.lsp.size;
      l.lsp.refined = 0;
    }
    for (int c = first_component; c < end_component; ++c) {
      io.begin_component(n, c);
      ComponentLists& l = lists[static_cast<std::size_t>(c)];
      // The lists in locals for the passes (stores of bytes may alias anything in memory).
      std::uint32_t* const lip_vertex = l.lip_vertex.get();
      std::uint8_t* const lip_tag = l.lip_tag.get();
      std::uint32_t* const lip_magnitude = l.lip_magnitude.get();
      std::uint32_t* const lis_vertex = l.lis_vertex.get();
      std::uint8_t* const lis_tag = l.lis_tag.get();
      std::uint8_t* const lis_width = l.lis_width.get();
      std::uint32_t* const lsp_vertex = l.lsp.vertex.get();
      std::uint8_t* const lsp_tag = l.lsp.tag.get();
      std::uint32_t* const lsp_magnitude = l.lsp.magnitude.get();
      std::size_t lip_size = l.lip_size, lis_size = l.lis_size, lsp_size = l.lsp.size;
      const std::uint32_t bit_n = std::uint32_t{1} << n;
      // Where the decoder's input runs out (a decision of -1) the run returns false as it is:
      // its LSP's size and refinement position are stored at every decision (below), so `lists`
      // hold what was decoded, as they do while a decoder waits for bytes (decode_into).
      std::uint8_t* const component_state = state_storage.get() + state_bytes * static_cast<std::size_t>(c);
      auto state_of = [component_state](std::uint32_t v) -> std::uint8_t {
        return (component_state[v >> 2] >> (2 * (v & 3))) & 3;
      };
      // A coefficient found significant: its sign, then it joins the LSP. `tag` is its level and
      // its parent's state, and for the encoder also its sign (kNegativeTag).
      auto newly_significant = [&](std::uint32_t v, std::uint8_t tag, std::uint32_t magnitude) {
        const int level = tag & kTagLevelMask;
        const int negative =
            io.bit(models.sign(level, c, (tag >> kParentStateShift) & 3), kEncoder && (tag & kNegativeTag) != 0);
        if (negative < 0) return false;
        if (v < stateful)
          component_state[v >> 2] |= static_cast<std::uint8_t>((negative ? kSignificantNegative : kSignificant) << (2 * (v & 3)));
        lsp_vertex[lsp_size] = v;
        lsp_tag[lsp_size] = static_cast<std::uint8_t>(level | (negative ? kNegativeTag : 0));
        lsp_magnitude[lsp_size] = kEncoder ? magnitude : bit_n;
        ++lsp_size;
        if constexpr (!kEncoder) l.lsp.size = lsp_size;
        return true;
      };

      // Sorting pass, LIP (compacted in place). Above the base plane the base entries in front
      // wait (their bits there are the base part's).
      const bool above_base = n >= base_plane;
      std::size_t keep = above_base ? base_lip[static_cast<std::size_t>(c)] : 0;
      for (std::size_t i = keep; i < lip_size; ++i) {
        const std::uint32_t v = lip_vertex[i];
        const std::uint8_t tag = lip_tag[i];
        const std::uint32_t magnitude = kEncoder ? lip_magnitude[i] : 0;
        const int s = io.bit(models.lip(tag & kTagLevelMask, c), kEncoder && (magnitude >> n) != 0);
        if (s < 0) return false;
        if (s) {
          if (!newly_significant(v, tag, magnitude)) return false;
        } else {
          lip_vertex[keep] = v;
          lip_tag[keep] = tag;
          if constexpr (kEncoder) lip_magnitude[keep] = magnitude;
          ++keep;
        }
      }
      lip_size = keep;

      // Sorting pass, LIS: grows while it is walked, compacted in place behind the walk.
      keep = 0;
      for (std::size_t i = 0; i < lis_size; ++i) {
        // A set found significant reads its vertex's children, a cache miss in a large forest:
        // ask for them kPrefetchDistance entries ahead (a no-op for the few roots). The encoder
        // knows which sets will be significant, and also reads their vertex's and children's
        // coefficient records: it asks for those, the children's half as far ahead (their
        // slots are in cache by then). Every entry reads its vertex's state (the context).
        if (i + kPrefetchDistance < lis_size)
          __builtin_prefetch(component_state + (lis_vertex[i + kPrefetchDistance] >> 2));
        if (i + kPrefetchDistance < lis_size && (!kEncoder || lis_width[i + kPrefetchDistance] > n)) {
          const std::uint32_t ahead = lis_vertex[i + kPrefetchDistance];
          if (ahead >= roots) __builtin_prefetch(odd_children + 4 * std::size_t{ahead - roots});
          if constexpr (kEncoder) io.prefetch(ahead, c);
        }
        if constexpr (kEncoder) {
          if (i + kPrefetchDistance / 2 < lis_size && lis_width[i + kPrefetchDistance / 2] > n) {
            const std::uint32_t ahead = lis_vertex[i + kPrefetchDistance / 2];
            if (ahead >= roots) {
              const std::uint32_t* slots = odd_children + 4 * std::size_t{ahead - roots};
              for (int k = 0; k < 4; ++k)
                if (slots[k] != Forest::kNoChild) io.prefetch(slots[k], c);
            }
          }
        }
        const std::uint32_t v = lis_vertex[i];
        const std::uint8_t tag = lis_tag[i] & ~kImpliedTag;
        const int level = tag >> 1;
        const bool type_b = tag & 1;
        const std::uint8_t own_state = state_of(v);
        const int s = (lis_tag[i] & kImpliedTag) != 0
                          ? 1
                          : io.bit(type_b ? models.set_grandchildren(level, c, own_state != 0) : models.set_descendants(level, c, own_state != 0),
                                   kEncoder && lis_width[i] > n);
        if (s < 0) return false;
        if (!s) {
          lis_vertex[keep] = v;
          lis_tag[keep] = tag;
          if constexpr (kEncoder) lis_width[keep] = lis_width[i];
          ++keep;
          continue;
        }
        const std::uint32_t* first = nullptr;
        const std::uint32_t count = children(v, first);
        if (!type_b) {
          // D(v) is significant: when it is just the children (L(v) is empty), the last one is
          // significant if none before it was, and is not coded.
          const bool children_only = level + 2 > finest;
          int found = 0;
          for (std::uint32_t k = 0; k < count; ++k) {
            const std::uint32_t child = first[k];
            const std::uint32_t magnitude = kEncoder ? io.magnitude(child, c) : 0;
            const auto child_tag = static_cast<std::uint8_t>((level + 1) | own_state << kParentStateShift |
                                                             (kEncoder && io.negative(child, c) ? kNegativeTag : 0));
            const int cs = children_only && found == 0 && k + 1 == count
                               ? 1
                               : io.bit(models.child(level + 1, c, std::min(found, 3), static_cast<int>(std::min<std::uint32_t>(k, 3))),
                                        kEncoder && (magnitude >> n) != 0);
            if (cs < 0) return false;
            if (cs) {
              if (!newly_significant(child, child_tag, magnitude)) return false;
              ++found;
            } else {
              lip_vertex[lip_size] = child;
              lip_tag[lip_size] = child_tag;
              if constexpr (kEncoder) lip_magnitude[lip_size] = magnitude;
              ++lip_size;
            }
          }
          if (level + 2 <= finest) {  // L(v) is not empty
            lis_vertex[lis_size] = v;
            lis_tag[lis_size] = static_cast<std::uint8_t>(tag | 1 | (found == 0 ? kImpliedTag : 0));
            if constexpr (kEncoder) lis_width[lis_size] = io.grandchildren_width(v, c);
            ++lis_size;
          }
        } else {
          // v has grandchildren, so its children (odd, below the finest level) have children.
          for (std::uint32_t k = 0; k < count; ++k) {
            const std::uint32_t child = first[k];
            lis_vertex[lis_size] = child;
            lis_tag[lis_size] = static_cast<std::uint8_t>((level + 1) << 1);
            if constexpr (kEncoder) lis_width[lis_size] = io.descendants_width(child, c);
            ++lis_size;
          }
        }
      }
      lis_size = keep;
      l.lip_size = lip_size;
      l.lis_size = lis_size;

      // Refinement pass: bit n of each magnitude (the decoder ORs it in; for the encoder, whose
      // magnitude already has it, that changes nothing).
      const std::size_t refine_count = l.lsp.refine_count;
      for (std::size_t i = above_base ? l.lsp.preset : 0; i < refine_count; ++i) {
        const std::uint32_t magnitude = lsp_magnitude[i];
        if constexpr (!kEncoder) l.lsp.refined = i;
        const int b = io.bit(models.refine(lsp_tag[i] & kLevelMask, c), kEncoder && (magnitude & bit_n) != 0);
        if (b < 0) return false;
        lsp_magnitude[i] = magnitude | (static_cast<std::uint32_t>(b) << n);
      }
      l.lsp.refined = refine_count;
      l.lsp.size = lsp_size;
    }
  }
  return true;
}

/// Bit width of x (0 for 0): x >> n != 0 exactly when bit_width(x) > n.
std::uint8_t width(std::uint32_t x) { return static_cast<std::uint8_t>(std::bit_width(x)); }

/// The decisions of some components' passes on their way to the thread that codes them: a
/// model's index in Models and the bit, in slots of kSlotSize that the writer fills and hands
/// over one at a time (a single writer and a single reader; at most kSlots in flight), and a
/// marker where the writer begins a plane after the first, so that the reader can code one
/// plane's decisions and then its own components' of that plane.
class DecisionQueue {
 public:
  static constexpr std::size_t kSlots = 8, kSlotSize = std::size_t{1} << 15;  // 64 KiB a slot
  static_assert(Models::kCount < (1u << 15) - 1, "a model's index and a bit fit 16 bits, beside the marker");
  static constexpr std::uint16_t kPlaneMarker = 0xffff;

  DecisionQueue() : decisions_(std::make_unique_for_overwrite<std::uint16_t[]>(kSlots * kSlotSize)) {}

  // Writer side. push() returns false once the reader has asked the writer to stop (seen when
  // a slot is handed over).
  bool push(std::uint16_t decision) {
    slot_[size_++] = decision;
    if (size_ == kSlotSize) hand_over(false);
    return !stop_;
  }
  /// The last slot, however full: the reader stops after it.
  void finish() { hand_over(true); }

  /// Reader side: asks the writer to stop (it still hands over every slot up to the last).
  void ask_to_stop() { stop_asked_.store(true, std::memory_order_relaxed); }

  /// Reader side: calls code(decision) for every decision in order up to the next plane marker
  /// (returns true) or the end of the last slot (returns false, and at once on later calls).
  template <class Code>
  bool read_plane(Code&& code) {
    for (;;) {
      if (reader_.count == kNoSlot) {
        if (reader_.ended) return false;
        std::uint64_t ready;
        while ((ready = written_.load(std::memory_order_acquire)) <= reader_.slot)
          written_.wait(ready, std::memory_order_acquire);
        const std::uint32_t entry = sizes_[reader_.slot % kSlots];
        reader_.count = entry & ~kLast;
        reader_.last = (entry & kLast) != 0;
        reader_.at = 0;
        reader_.data = decisions_.get() + (reader_.slot % kSlots) * kSlotSize;
      }
      while (reader_.at < reader_.count) {
        const std::uint16_t d = reader_.data[reader_.at++];
        if (d == kPlaneMarker) return true;
        code(d);
      }
      // The slot is done: hand it back.
      read_.store(++reader_.slot, std::memory_order_release);
      read_.notify_one();
      reader_.count = kNoSlot;
      if (reader_.last) {
        reader_.ended = true;
        return false;
      }
    }
  }
  /// Reader side: reads to the end, dropping the decisions (once the reader's own passes have
  /// stopped: the writer may be waiting for a free slot).
  void drain() {
    while (read_plane([](std::uint16_t) {})) {
    }
  }

 private:
  static constexpr std::uint32_t kLast = std::uint32_t{1} << 31;
  static constexpr std::uint32_t kNoSlot = ~std::uint32_t{0};

  void hand_over(bool last) {
    sizes_[slots_written_ % kSlots] = static_cast<std::uint32_t>(size_) | (last ? kLast : 0);
    written_.store(++slots_written_, std::memory_order_release);
    written_.notify_one();
    if (last) return;
    stop_ = stop_asked_.load(std::memory_order_relaxed);
    // The next slot once the reader is done with it.
    std::uint64_t done;
    while (slots_written_ - (done = read_.load(std::memory_order_acquire)) >= kSlots) read_.wait(done, std::memory_order_acquire);
    slot_ = decisions_.get() + (slots_written_ % kSlots) * kSlotSize;
    size_ = 0;
  }

  std::unique_ptr<std::uint16_t[]> decisions_;
  std::uint32_t sizes_[kSlots] = {};
  // The counters and each side's own fields on cache lines of their own (the writer's change
  // with every push: a line the reader writes too would move between the cores each time).
  alignas(64) std::atomic<std::uint64_t> written_{0};  // slots handed over
  alignas(64) std::atomic<std::uint64_t> read_{0};     // slots coded
  std::atomic<bool> stop_asked_{false};
  // The writer's own.
  alignas(64) std::uint16_t* slot_ = decisions_.get();
  std::size_t size_ = 0;
  std::uint64_t slots_written_ = 0;
  bool stop_ = false;  // stop_asked_ as of the last slot handed over
  // The reader's own: the slot being read (count kNoSlot: none yet) and where in it.
  alignas(64) struct {
    std::uint64_t slot = 0;
    const std::uint16_t* data = nullptr;
    std::uint32_t count = kNoSlot, at = 0;
    bool last = false, ended = false;
  } reader_;
};

class EncoderIo {
 public:
  static constexpr bool kEncoder = true;

  /// Reads q's records, which the passes read in place (fill_widths() completes them first).
  /// Codes every decision with `encoder`, or, given a queue, writes it there as the index of its
  /// model among `models` (the passes' own) and its bit.
  /// Stops (bit() returns -1, as a decoder's does at the end of its bytes) once `encoder` has
  /// emitted more than `stop_after` bytes, or, with a queue, once its reader asks.
  EncoderIo(Quantized& q, RangeEncoder& encoder, std::size_t stop_after, DecisionQueue* queue = nullptr,
            const Models* models = nullptr)
      : coefficients_(q.coefficients.get()),
        encoder_(&encoder),
        stop_after_(stop_after),
        queue_(queue),
        models_(models),
        k_(static_cast<std::size_t>(q.components)) {}
  /// Completes q's records (their widths) for the passes; with `concurrent` the widths of a large
  /// level are filled in two halves side by side.
  void fill_widths(const Forest& f, bool concurrent) {
    if (k_ == kGeometryComponents)
      fill_widths<kGeometryComponents>(f, concurrent);
    else
      fill_widths<0>(f, concurrent);
  }
  void begin_plane(int) {}
  void begin_component(int, int) {}
  int bit(BitModel& m, bool value) {
    if (queue_ != nullptr) {
      if (!queue_->push(static_cast<std::uint16_t>(models_->index(m) << 1 | (value ? 1 : 0)))) return -1;
    } else {
      if (encoder_->bytes_final() > stop_after_) return -1;
      encoder_->encode(m, value ? 1 : 0);
    }
    return value ? 1 : 0;
  }
  void prefetch(std::uint32_t v, int c) const { __builtin_prefetch(&coefficients_[index(v, c)]); }
  std::uint32_t magnitude(std::uint32_t v, int c) const { return coefficients_[index(v, c)].magnitude; }
  bool negative(std::uint32_t v, int c) const { return coefficients_[index(v, c)].negative; }
  std::uint8_t descendants_width(std::uint32_t v, int c) const { return coefficients_[index(v, c)].descendants_width; }
  std::uint8_t grandchildren_width(std::uint32_t v, int c) const { return coefficients_[index(v, c)].grandchildren_width; }

 private:
  using Coefficient = Quantized::Coefficient;

  /// Bottom-up bit widths of the maxima: over D(v) and over L(v) = D(v) minus the children.
  /// Children always belong to the next level, so a walk over the levels from the finest down
  /// sees every child's widths complete; within a level no vertex reads another's, so a large
  /// level may run in two halves side by side (`concurrent`). The finest level's vertices have
  /// none: their widths stay the 0 the records hold (Quantized). K: the components per vertex
  /// known at compile time (the geometry alone, the common case: its loops unrolled), or 0 for k_.
  template <std::size_t K>
  void fill_widths(const Forest& f, bool concurrent) {
    const std::size_t k = K != 0 ? K : k_;
    // Vertices [first, last), from the last down.
    auto fill = [&](std::uint32_t first, std::uint32_t last) {
      for (std::uint32_t v = last; v-- > first;) {
        // The inner-edge children are far from the halves: ask for them a few vertices ahead.
        if (v >= first + kPrefetchDistance)
          for (const std::uint32_t child : f.children(v - static_cast<std::uint32_t>(kPrefetchDistance))) prefetch(child, 0);
        // The widths gathered in locals (registers) and stored once.
        std::uint8_t descendants[kMaxComponents] = {}, grandchildren[kMaxComponents] = {};
        for (const std::uint32_t child : f.children(v)) {
          const Coefficient* y = &coefficients_[index(child, std::size_t{0})];
          for (std::size_t c = 0; c < k; ++c) {
            descendants[c] = std::max({descendants[c], width(y[c].magnitude), y[c].descendants_width});
            grandchildren[c] = std::max(grandchildren[c], y[c].descendants_width);
          }
        }
        Coefficient* x = &coefficients_[index(v, std::size_t{0})];
        for (std::size_t c = 0; c < k; ++c) {
          x[c].descendants_width = descendants[c];
          x[c].grandchildren_width = grandchildren[c];
        }
      }
    };
    constexpr std::uint32_t kConcurrentVertices = 1u << 14;
    for (int j = f.levels - 1; j >= 0; --j) {
      const std::uint32_t first = f.level_starts[static_cast<std::size_t>(j)];
      const std::uint32_t last = f.level_starts[static_cast<std::size_t>(j) + 1], middle = first + (last - first) / 2;
      run_both(concurrent && last - first >= kConcurrentVertices, [&] { fill(middle, last); }, [&] { fill(first, middle); });
    }
  }

  std::size_t index(std::uint32_t v, int c) const { return std::size_t{v} * k_ + static_cast<std::size_t>(c); }
  std::size_t index(std::uint32_t v, std::size_t c) const { return std::size_t{v} * k_ + c; }
  Coefficient* coefficients_;

 protected:
  RangeEncoder* encoder_;
  std::size_t stop_after_;
  DecisionQueue* queue_;
  const Models* models_;
  std::size_t k_;
};

/// On two threads, the passes of the first components write their decisions to a queue
/// (EncoderIo with a queue), and a plane marker where each plane after the first begins.
class QueueingIo : public EncoderIo {
 public:
  using EncoderIo::EncoderIo;
  void begin_component(int, int c) {
    if (c != 0) return;
    if (begun_) queue_->push(DecisionQueue::kPlaneMarker);
    begun_ = true;
  }

 private:
  bool begun_ = false;  // whether a plane has begun
};

/// ... and the other thread codes, at each plane, those decisions of the plane (read off the
/// queue, coded with its own models, `coded`, which the passes of its components use too), then
/// its own components' as its passes make them: the decisions of one thread in the order of
/// one, so the same bytes.
class CodingIo : public EncoderIo {
 public:
  CodingIo(Quantized& q, RangeEncoder& encoder, std::size_t stop_after, DecisionQueue& from, Models& coded, int first_own)
      : EncoderIo(q, encoder, stop_after), from_(&from), coded_(&coded), first_own_(first_own) {}
  /// Past `stop_after` bytes it codes no more: it asks the other thread to stop, and its own
  /// passes' next decision stops them (bit() returns -1).
  void begin_component(int, int c) {
    if (c != first_own_) return;
    from_->read_plane([this](std::uint16_t d) {
      if (stopped_) return;
      if (encoder_->bytes_final() > stop_after_) {
        from_->ask_to_stop();
        stopped_ = true;
        return;
      }
      encoder_->encode((*coded_)[d >> 1], d & 1);
    });
  }
  /// Whether it stopped coding the other thread's decisions at the budget.
  bool stopped() const { return stopped_; }

 private:
  DecisionQueue* from_;
  Models* coded_;
  int first_own_;
  bool stopped_ = false;
};

class DecoderIo {
 public:
  static constexpr bool kEncoder = false;

  /// Decodes from a copy of `decoder` (kept in registers in the passes); decoder() gives it back.
  /// Each plane begun is written to `last_plane` at once (Decoded::last_plane, read while the
  /// decoder waits for bytes).
  DecoderIo(const RangeDecoder& decoder, int& last_plane) : decoder_(decoder), last_plane_(&last_plane) {}
  void begin_plane(int n) { *last_plane_ = n; }
  void begin_component(int, int) {}
  int bit(BitModel& m, bool) { return decoder_.try_decode(m); }
  std::uint32_t magnitude(std::uint32_t, int) const { return 0; }
  bool negative(std::uint32_t, int) const { return false; }
  std::uint8_t descendants_width(std::uint32_t, int) const { return 0; }
  std::uint8_t grandchildren_width(std::uint32_t, int) const { return 0; }

  const RangeDecoder& decoder() const { return decoder_; }

 private:
  RangeDecoder decoder_;
  int* last_plane_;
};

}  // namespace

bool encode(const Forest& forest, Quantized& q, int top, int base_plane, RangeEncoder& encoder, bool concurrent,
            std::size_t stop_after) {
  if (q.components < 1 || q.components > kMaxComponents) throw std::invalid_argument("zerotree: bad component count");
  if (q.size != std::size_t{forest.vertex_count()} * static_cast<std::size_t>(q.components))
    throw std::invalid_argument("zerotree: the coefficients are not the forest's vertices times the components");
  if (top < 0) return true;
  std::vector<SignificantList> significant;
  std::vector<ComponentLists> lists;
  significant.reserve(static_cast<std::size_t>(q.components));
  lists.reserve(static_cast<std::size_t>(q.components));
  for (int c = 0; c < q.components; ++c) lists.emplace_back(forest, true, significant.emplace_back(forest.vertex_count()));
  EncoderIo io(q, encoder, stop_after);
  io.fill_widths(forest, concurrent);
  Models models;
  if (concurrent && q.components > 1) {
    // The passes of all components but the last on a thread of their own, writing their
    // decisions to a queue; on this one, at each plane, those decisions coded, then the last
    // component's passes coding theirs (CodingIo). The range coder's work (about half the passes')
    // then sits beside the last component's passes. Each component's lists, state and models are
    // its own, so the two threads share nothing but the queue and the records they read.
    const int split = q.components - 1;
    DecisionQueue queue;
    bool complete_first = false, complete_last = false;
    const bool ran = try_run_both(
        [&] {
          struct Finish {
            DecisionQueue& queue;
            ~Finish() { queue.finish(); }  // also if the passes throw: the reader must not wait forever
          } finish{queue};
          Models indexed;  // the passes' own, for the models' indices
          QueueingIo producer(q, encoder, stop_after, &queue, &indexed);
          complete_first = run(forest, q.components, top, base_plane, nullptr, producer, lists, indexed, 0, split);
        },
        [&] {
          CodingIo coder(q, encoder, stop_after, queue, models, split);
          try {
            // Complete only if no queued decision was left uncoded either.
            complete_last = run(forest, q.components, top, base_plane, nullptr, coder, lists, models, split, q.components) &&
                            !coder.stopped();
          } catch (...) {
            queue.ask_to_stop();
            queue.drain();
            throw;
          }
          // Stopped at the budget: the other thread may be waiting for a free slot.
          if (!complete_last) queue.ask_to_stop();
          queue.drain();
        });
    if (ran) return complete_first && complete_last;  // else no thread could be started: on this one
  }
  return run(forest, q.components, top, base_plane, nullptr, io, lists, models);
}

Decoded decode(const Forest& forest, int components, int top, int base_plane, std::span<const std::int64_t> base_high,
               RangeDecoder& decoder) {
  Decoded out;
  decode_into(forest, components, top, base_plane, base_high, decoder, out);
  return out;
}

bool decode_into(const Forest& forest, int components, int top, int base_plane, std::span<const std::int64_t> base_high,
                 RangeDecoder& decoder, Decoded& out) {
  if (components < 1 || components > kMaxComponents) throw std::invalid_argument("zerotree: bad component count");
  if (base_plane <= top && base_high.size() != std::size_t{forest.roots} * static_cast<std::size_t>(components))
    throw std::invalid_argument("zerotree: the base part's values are not the roots times the components");
  out = Decoded();
  out.components = components;
  out.base_plane = base_plane;
  if (top < 0) {
    out.complete = true;
    return true;
  }
  std::vector<ComponentLists> lists;
  out.significant.reserve(static_cast<std::size_t>(components));  // never moved while the run writes them
  lists.reserve(static_cast<std::size_t>(components));
  for (int c = 0; c < components; ++c) lists.emplace_back(forest, false, out.significant.emplace_back(forest.vertex_count()));
  DecoderIo io(decoder, out.last_plane);
  Models models;
  out.complete = run(forest, components, top, base_plane, base_high.data(), io, lists, models);
  decoder = io.decoder();
  return out.complete;
}

}  // namespace meshlift::zerotree
