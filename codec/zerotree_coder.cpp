#include "zerotree_coder.h"

#include <algorithm>
#include <stdexcept>

namespace meshlift::zerotree {

Forest::Forest(const SemiRegularHierarchy& h) {
  const std::uint32_t V = h.vertex_count(h.levels());
  roots = h.vertex_count(0);
  level.resize(V);
  for (int j = 0; j <= h.levels(); ++j)
    std::fill(level.begin() + (j == 0 ? 0 : h.vertex_count(j - 1)), level.begin() + h.vertex_count(j),
              static_cast<std::uint8_t>(j));
  child_offsets.assign(V + 1, 0);
  const TriangleTopology& base = h.topology(0);
  if (h.levels() > 0)
    for (std::uint32_t e = 0; e < base.edge_count(); ++e) ++child_offsets[base.edge_vertices[2 * e] + 1];
  for (std::uint32_t v = roots; v < V; ++v) child_offsets[v + 1] = static_cast<std::uint32_t>(h.children(v).size());
  for (std::uint32_t v = 0; v < V; ++v) child_offsets[v + 1] += child_offsets[v];
  children.resize(child_offsets[V]);
  std::vector<std::uint32_t> fill(child_offsets.begin(), child_offsets.end() - 1);
  if (h.levels() > 0)
    for (std::uint32_t e = 0; e < base.edge_count(); ++e) children[fill[base.edge_vertices[2 * e]]++] = h.odd_vertex(0, e);
  for (std::uint32_t v = roots; v < V; ++v)
    for (std::uint32_t c : h.children(v)) children[fill[v]++] = c;
}

int top_plane(const Quantized& q) {
  std::uint32_t m = 0;
  for (std::uint32_t x : q.magnitude) m = std::max(m, x);
  int n = -1;
  while (n < 31 && (std::uint64_t{1} << (n + 1)) <= m) ++n;
  return n;
}

namespace {

constexpr int kLevelContexts = kMaxLevels + 1;
constexpr std::uint32_t kRemoved = 0xffffffffu;

struct Models {
  BitModel lip[kLevelContexts][kMaxComponents];
  BitModel child[kLevelContexts][kMaxComponents][4];  // by how many siblings were significant before
  BitModel set_descendants[kLevelContexts][kMaxComponents];
  BitModel set_grandchildren[kLevelContexts][kMaxComponents];
  BitModel refine[kLevelContexts][kMaxComponents];
};

struct Lists {
  std::vector<std::uint32_t> insignificant_pixels;  // SPIHT's LIP: coefficients tested one by one
  std::vector<std::uint32_t> insignificant_sets;    // LIS: vertex << 1 | (1 for type B: grandchildren)
  std::vector<std::uint32_t> significant;           // LSP
};

// One SPIHT run, shared by encoder and decoder. Io supplies the decisions: the encoder computes
// and codes them, the decoder decodes them and returns -1 once the stream is exhausted, where
// the run stops (all decisions before were exactly the encoder's).
//   Sorting pass at plane n: each LIP coefficient: significant? (then sign, move to LSP).
//   Each LIS entry of type A: any descendant significant? If so, each child: significant?
//   (sign, LSP) or to the LIP; the entry becomes type B if grandchildren exist. Type B: any
//   grandchild significant? If so, every child with children joins the LIS as type A.
//   Refinement pass: bit n of every coefficient that was significant before this plane.
template <class Io>
bool run(const Forest& f, int components, int top, Io& io) {
  Models models;
  std::vector<Lists> lists(static_cast<std::size_t>(components));
  for (auto& l : lists) {
    l.insignificant_pixels.resize(f.roots);
    for (std::uint32_t v = 0; v < f.roots; ++v) {
      l.insignificant_pixels[v] = v;
      if (f.child_offsets[v + 1] > f.child_offsets[v]) l.insignificant_sets.push_back(v << 1);
    }
  }
  auto has_children = [&](std::uint32_t v) { return f.child_offsets[v + 1] > f.child_offsets[v]; };
  // Every child of a vertex of level j is of level j + 1 and has children unless that is the
  // finest level: no need to look at the children themselves.
  const int finest = f.level.empty() ? 0 : f.level.back();
  auto has_grandchildren = [&](std::uint32_t v) { return has_children(v) && f.level[v] + 2 <= finest; };
  for (int n = top; n >= 0; --n) {
    io.begin_plane(n);
    for (int c = 0; c < components; ++c) {
      Lists& l = lists[static_cast<std::size_t>(c)];
      const std::size_t refine_count = l.significant.size();
      auto newly_significant = [&](std::uint32_t v) {
        if (io.sign(v, c) < 0) return false;
        io.significant(v, c, n);
        l.significant.push_back(v);
        return true;
      };
      // Sorting pass, LIP.
      std::size_t keep = 0;
      for (std::size_t i = 0; i < l.insignificant_pixels.size(); ++i) {
        const std::uint32_t v = l.insignificant_pixels[i];
        const int s = io.bit(models.lip[f.level[v]][c], io.is_significant(v, c, n));
        if (s < 0) return false;
        if (s) {
          if (!newly_significant(v)) return false;
        } else {
          l.insignificant_pixels[keep++] = v;
        }
      }
      l.insignificant_pixels.resize(keep);
      // Sorting pass, LIS (grows while it is walked).
      for (std::size_t i = 0; i < l.insignificant_sets.size(); ++i) {
        const std::uint32_t entry = l.insignificant_sets[i];
        const std::uint32_t v = entry >> 1;
        if ((entry & 1) == 0) {
          const int s = io.bit(models.set_descendants[f.level[v]][c], io.descendant_significant(v, c, n));
          if (s < 0) return false;
          if (!s) continue;
          int found = 0;
          for (std::uint32_t k = f.child_offsets[v]; k < f.child_offsets[v + 1]; ++k) {
            const std::uint32_t child = f.children[k];
            const int cs = io.bit(models.child[f.level[child]][c][std::min(found, 3)], io.is_significant(child, c, n));
            if (cs < 0) return false;
            if (cs) {
              if (!newly_significant(child)) return false;
              ++found;
            } else {
              l.insignificant_pixels.push_back(child);
            }
          }
          l.insignificant_sets[i] = kRemoved;
          if (has_grandchildren(v)) l.insignificant_sets.push_back(v << 1 | 1);
        } else {
          const int s = io.bit(models.set_grandchildren[f.level[v]][c], io.grandchild_significant(v, c, n));
          if (s < 0) return false;
          if (!s) continue;
          l.insignificant_sets[i] = kRemoved;
          for (std::uint32_t k = f.child_offsets[v]; k < f.child_offsets[v + 1]; ++k)
            if (has_children(f.children[k])) l.insignificant_sets.push_back(f.children[k] << 1);
        }
      }
      l.insignificant_sets.erase(std::remove(l.insignificant_sets.begin(), l.insignificant_sets.end(), kRemoved),
                                 l.insignificant_sets.end());
      // Refinement pass.
      for (std::size_t i = 0; i < refine_count; ++i) {
        const std::uint32_t v = l.significant[i];
        const int b = io.bit(models.refine[f.level[v]][c], io.magnitude_bit(v, c, n));
        if (b < 0) return false;
        io.refined(v, c, n, b);
      }
    }
  }
  return true;
}

class EncoderIo {
 public:
  EncoderIo(const Forest& f, const Quantized& q, RangeEncoder& encoder) : q_(q), encoder_(encoder), k_(q.components) {
    // Bottom-up maxima: descendants[v] = max |c| over D(v), grandchildren[v] over L(v) = D(v)
    // minus the children. Children always have larger indices than their parent.
    const std::size_t n = q.magnitude.size();
    descendants_.assign(n, 0);
    grandchildren_.assign(n, 0);
    for (std::uint32_t v = f.vertex_count(); v-- > 0;)
      for (std::uint32_t k = f.child_offsets[v]; k < f.child_offsets[v + 1]; ++k) {
        const std::uint32_t child = f.children[k];
        for (int c = 0; c < k_; ++c) {
          const std::size_t pv = index(v, c), pc = index(child, c);
          descendants_[pv] = std::max({descendants_[pv], q.magnitude[pc], descendants_[pc]});
          grandchildren_[pv] = std::max(grandchildren_[pv], descendants_[pc]);
        }
      }
  }
  void begin_plane(int) {}
  int bit(BitModel& m, bool value) {
    encoder_.encode(m, value ? 1 : 0);
    return value ? 1 : 0;
  }
  int sign(std::uint32_t v, int c) {
    encoder_.encode_direct(q_.negative[index(v, c)], 1);
    return 0;
  }
  void significant(std::uint32_t, int, int) {}
  void refined(std::uint32_t, int, int, int) {}
  bool is_significant(std::uint32_t v, int c, int n) const { return q_.magnitude[index(v, c)] >> n; }
  bool descendant_significant(std::uint32_t v, int c, int n) const { return descendants_[index(v, c)] >> n; }
  bool grandchild_significant(std::uint32_t v, int c, int n) const { return grandchildren_[index(v, c)] >> n; }
  bool magnitude_bit(std::uint32_t v, int c, int n) const { return (q_.magnitude[index(v, c)] >> n) & 1; }

 private:
  std::size_t index(std::uint32_t v, int c) const { return std::size_t{v} * static_cast<std::size_t>(k_) + static_cast<std::size_t>(c); }
  const Quantized& q_;
  RangeEncoder& encoder_;
  int k_;
  std::vector<std::uint32_t> descendants_, grandchildren_;
};

class DecoderIo {
 public:
  DecoderIo(RangeDecoder& decoder, Decoded& out) : decoder_(decoder), out_(out), k_(out.components) {}
  void begin_plane(int n) { out_.last_plane = n; }
  int bit(BitModel& m, bool) {
    const int b = decoder_.decode(m);
    return decoder_.exhausted() ? -1 : b;
  }
  int sign(std::uint32_t v, int c) {
    const std::uint32_t negative = decoder_.decode_direct(1);
    if (decoder_.exhausted()) return -1;
    out_.negative[index(v, c)] = static_cast<std::uint8_t>(negative);
    return 0;
  }
  void significant(std::uint32_t v, int c, int n) {
    out_.known[index(v, c)] = std::uint32_t{1} << n;
    out_.low_plane[index(v, c)] = static_cast<std::int8_t>(n);
  }
  void refined(std::uint32_t v, int c, int n, int b) {
    out_.known[index(v, c)] |= static_cast<std::uint32_t>(b) << n;
    out_.low_plane[index(v, c)] = static_cast<std::int8_t>(n);
  }
  bool is_significant(std::uint32_t, int, int) const { return false; }
  bool descendant_significant(std::uint32_t, int, int) const { return false; }
  bool grandchild_significant(std::uint32_t, int, int) const { return false; }
  bool magnitude_bit(std::uint32_t, int, int) const { return false; }

 private:
  std::size_t index(std::uint32_t v, int c) const { return std::size_t{v} * static_cast<std::size_t>(k_) + static_cast<std::size_t>(c); }
  RangeDecoder& decoder_;
  Decoded& out_;
  int k_;
};

}  // namespace

void encode(const Forest& forest, const Quantized& q, int top, RangeEncoder& encoder) {
  if (q.components < 1 || q.components > kMaxComponents) throw std::invalid_argument("zerotree: bad component count");
  EncoderIo io(forest, q, encoder);
  if (top >= 0) run(forest, q.components, top, io);
}

Decoded decode(const Forest& forest, int components, int top, RangeDecoder& decoder) {
  if (components < 1 || components > kMaxComponents) throw std::invalid_argument("zerotree: bad component count");
  Decoded out;
  out.components = components;
  const std::size_t n = std::size_t{forest.vertex_count()} * static_cast<std::size_t>(components);
  out.known.assign(n, 0);
  out.low_plane.assign(n, 0);
  out.negative.assign(n, 0);
  DecoderIo io(decoder, out);
  out.complete = top < 0 || run(forest, components, top, io);
  return out;
}

}  // namespace meshlift::zerotree
