#include "base_mesh_coder.h"

#include <algorithm>
#include <tuple>
#include <unordered_map>

#include "meshlift/mesh.h"

namespace meshlift::base_mesh {

// value + 1 = 1 b_{n-1} ... b_0: n zeros-then-one in unary (models by position), then n bits.
void UintCoder::encode(RangeEncoder& encoder, std::uint32_t value) {
  const std::uint64_t v = std::uint64_t{value} + 1;
  int n = 0;
  while ((v >> (n + 1)) != 0) ++n;
  for (int i = 0; i < n; ++i) encoder.encode(length_[i], 0);
  encoder.encode(length_[n], 1);
  for (int i = n - 1; i >= 0; --i) {
    const int bit = static_cast<int>((v >> i) & 1);
    const int rank = n - 1 - i;
    if (rank < 3)
      encoder.encode(mantissa_[n][rank], bit);
    else
      encoder.encode_direct(static_cast<std::uint32_t>(bit), 1);
  }
}

bool UintCoder::decode(RangeDecoder& decoder, std::uint32_t& value) {
  int n = 0;
  while (true) {
    if (n > 32) return false;
    const int stop = decoder.decode(length_[n]);
    if (decoder.exhausted()) return false;
    if (stop) break;
    ++n;
  }
  std::uint64_t v = 1;
  for (int i = n - 1; i >= 0; --i) {
    const int rank = n - 1 - i;
    const int bit = rank < 3 ? decoder.decode(mantissa_[n][rank]) : static_cast<int>(decoder.decode_direct(1));
    if (decoder.exhausted()) return false;
    v = v << 1 | static_cast<std::uint64_t>(bit);
  }
  if (v - 1 > 0xffffffffu) return false;
  value = static_cast<std::uint32_t>(v - 1);
  return true;
}

namespace {

std::uint64_t key(std::uint32_t u, std::uint32_t w) { return (std::uint64_t{u} << 32) | w; }

/// A set of directed edges (keys), insert-only: open addressing with linear probing in one flat
/// array, at most half full. The traversal asks it about every edge of every face, and
/// std::unordered_set spent most of a base decode in allocating its nodes and chasing them.
class EdgeSet {
 public:
  bool contains(std::uint64_t k) const {
    if (size_ == 0) return false;
    for (std::size_t i = slot(k);; i = (i + 1) & mask_) {
      if (slots_[i] == k) return true;
      if (slots_[i] == kEmpty) return false;
    }
  }
  void insert(std::uint64_t k) {
    if (2 * (size_ + 1) > slots_.size()) grow();
    for (std::size_t i = slot(k);; i = (i + 1) & mask_) {
      if (slots_[i] == k) return;
      if (slots_[i] == kEmpty) {
        slots_[i] = k;
        ++size_;
        return;
      }
    }
  }

 private:
  /// No edge has this key: vertex indices are below kNone.
  static constexpr std::uint64_t kEmpty = ~std::uint64_t{0};
  std::size_t slot(std::uint64_t k) const {
    return static_cast<std::size_t>((k * 0x9E3779B97F4A7C15ull) >> 32) & mask_;  // Fibonacci hashing
  }
  void grow() {
    std::vector<std::uint64_t> old = std::move(slots_);
    slots_.assign(std::max<std::size_t>(64, 2 * old.size()), kEmpty);
    mask_ = slots_.size() - 1;
    size_ = 0;
    for (const std::uint64_t k : old)
      if (k != kEmpty) insert(k);
  }
  std::vector<std::uint64_t> slots_;
  std::size_t mask_ = 0, size_ = 0;
};

/// What the previous gate turned out to be: the context of the next gate's symbols.
enum Previous : int { kWasNew = 0, kWasRight = 1, kWasLeft = 2, kWasOther = 3 };

/// Initial probabilities of the decision models (FORMAT.md §4, its table of q): P(bit = 0) = q / 256, as
/// measured over the base meshes that `meshlift remesh` made of 20 meshes of Debian's
/// libcgal-demo outside the development corpus (bunny00, bull, dino, …; the bits each
/// decision took, (zeros + 1/2) / (decisions + 1) rounded to 1/256). 128: never taken there.
/// Indexed [previous symbol][k] as the models are.
constexpr std::uint8_t kBoundaryQ[4] = {252, 253, 255, 244};
constexpr std::uint8_t kRightQ[4][6] = {{128, 255, 128, 128, 128, 128},
                                        {128, 251, 250, 215, 152, 103},
                                        {128, 128, 253, 231, 155, 92},
                                        {128, 250, 254, 93, 76, 83}};
constexpr std::uint8_t kLeftQ[4][6] = {{128, 128, 250, 211, 178, 103},
                                       {128, 251, 230, 224, 176, 100},
                                       {128, 128, 241, 234, 179, 106},
                                       {128, 255, 250, 176, 163, 120}};
constexpr std::uint8_t kNewVertexQ[4][6] = {{128, 128, 6, 1, 23, 29},
                                            {128, 5, 77, 96, 28, 31},
                                            {128, 128, 3, 21, 19, 27},
                                            {128, 25, 28, 21, 37, 18}};
constexpr std::uint8_t kStartNewQ = 1, kSplitLeftQ = 181, kSplitRightQ = 236;
/// The update count a primed model starts at: it adapts at rate 1/8 at first instead of 1/2, so
/// the prior is worth a few decisions, not one (FORMAT.md §7.3).
constexpr std::uint8_t kPrimedCount = 4;

constexpr BitModel primed(std::uint8_t q) {
  BitModel model;
  model.p = static_cast<std::uint16_t>(q * 128);
  model.count = kPrimedCount;
  return model;
}

/// The farthest a split vertex is looked for along the front, in open edges (FORMAT.md §4).
constexpr std::uint32_t kMaxWalk = 64;

/// The models of the traversal symbols (FORMAT.md §4), the gate symbols per previous symbol.
struct Models {
  Models() {
    for (int i = 0; i < 4; ++i) {
      boundary[i] = primed(kBoundaryQ[i]);
      for (int k = 0; k < 6; ++k) {
        right[i][k] = primed(kRightQ[i][k]);
        left[i][k] = primed(kLeftQ[i][k]);
        new_vertex[i][k] = primed(kNewVertexQ[i][k]);
      }
    }
  }
  BitModel boundary[4], right[4][6], left[4][6], new_vertex[4][6];
  BitModel start_new = primed(kStartNewQ), split_left = primed(kSplitLeftQ), split_right = primed(kSplitRightQ);
  UintCoder index, vertex, walk_left, walk_right;
};

/// What encoder and decoder both know, in the new labels: the faces coded so far, their directed
/// edges, the open edges (coded, twin not coded) at each vertex, and the stack of gates.
class Front {
 public:
  explicit Front(std::uint32_t vertex_count)
      : out_open_(vertex_count), in_open_(vertex_count), faces_at_(vertex_count, 0) {}
  /// Faces coded around v so far, capped at 5: a vertex with many is likely to be closed next.
  int faces_at(std::uint32_t v) const { return std::min<int>(faces_at_[v], 5); }

  /// Adds face (a, b, c); false if it repeats a coded directed edge (not a manifold mesh).
  bool add_face(std::uint32_t a, std::uint32_t b, std::uint32_t c) {
    const std::uint32_t corners[3] = {a, b, c};
    for (int i = 0; i < 3; ++i)
      if (coded_.contains(key(corners[i], corners[(i + 1) % 3]))) return false;
    faces.insert(faces.end(), {a, b, c});
    ++faces_at_[a];
    ++faces_at_[b];
    ++faces_at_[c];
    for (int i = 0; i < 3; ++i) {
      const std::uint32_t u = corners[i], w = corners[(i + 1) % 3];
      coded_.insert(key(u, w));
      if (coded_.contains(key(w, u))) {
        erase(out_open_[w], u);
        erase(in_open_[u], w);
      } else {
        out_open_[u].push_back(w);
        in_open_[w].push_back(u);
        gates_.push_back({u, w});
      }
    }
    return true;
  }
  /// The next gate a -> b whose far side is not coded yet; false when there is none.
  bool next_gate(std::uint32_t& a, std::uint32_t& b) {
    while (!gates_.empty()) {
      const auto [u, w] = gates_.back();
      gates_.pop_back();
      if (!coded_.contains(key(w, u))) {
        a = u;
        b = w;
        return true;
      }
    }
    return false;
  }
  /// Vertices x with an open edge x -> a (a face (b, a, x) closes against it: "right").
  const std::vector<std::uint32_t>& right(std::uint32_t a) const { return in_open_[a]; }
  /// Vertices x with an open edge b -> x (a face (b, a, x) closes against it: "left").
  const std::vector<std::uint32_t>& left(std::uint32_t b) const { return out_open_[b]; }
  /// One open edge along the front from v: leftwards (v -> x) or rightwards (x -> v), along the
  /// oldest such edge of v; kNone where the front stops at v.
  std::uint32_t step(std::uint32_t v, bool leftwards) const {
    const std::vector<std::uint32_t>& next = leftwards ? out_open_[v] : in_open_[v];
    return next.empty() ? kNone : next.front();
  }
  /// The vertex `steps` step()s from v; kNone where the front stops first.
  std::uint32_t walk(std::uint32_t v, std::uint32_t steps, bool leftwards) const {
    for (; steps > 0 && v != kNone; --steps) v = step(v, leftwards);
    return v;
  }
  /// The fewest step()s from v that reach `target`, at most kMaxWalk; 0 if none do.
  std::uint32_t steps_to(std::uint32_t v, std::uint32_t target, bool leftwards) const {
    for (std::uint32_t steps = 1; steps <= kMaxWalk && v != kNone; ++steps)
      if ((v = step(v, leftwards)) == target) return steps;
    return 0;
  }

  std::vector<std::uint32_t> faces;
  std::uint32_t seen = 0;  ///< vertices labelled so far; the next new vertex gets this label

 private:
  static void erase(std::vector<std::uint32_t>& v, std::uint32_t x) { v.erase(std::find(v.begin(), v.end(), x)); }
  std::vector<std::vector<std::uint32_t>> out_open_, in_open_;
  std::vector<std::uint32_t> faces_at_;
  EdgeSet coded_;
  std::vector<std::pair<std::uint32_t, std::uint32_t>> gates_;  // newest last
};

std::uint32_t position_in(const std::vector<std::uint32_t>& list, std::uint32_t x) {
  return static_cast<std::uint32_t>(std::find(list.begin(), list.end(), x) - list.begin());
}

}  // namespace

std::vector<std::uint8_t> encode_faces(std::span<const std::uint32_t> triangles, std::uint32_t vertex_count,
                                       CodingOrder* order) {
  const auto F = static_cast<std::uint32_t>(triangles.size() / 3);
  // Old directed edge (u, w) -> 3 * face + corner of u.
  std::unordered_map<std::uint64_t, std::uint32_t> corner_of_edge;
  corner_of_edge.reserve(triangles.size());
  for (std::uint32_t f = 0; f < F; ++f)
    for (std::uint32_t i = 0; i < 3; ++i)
      corner_of_edge[key(triangles[3 * f + i], triangles[3 * f + (i + 1) % 3])] = 3 * f + i;

  RangeEncoder encoder;
  Models m;
  Front front(vertex_count);
  std::vector<std::uint32_t> label(vertex_count, kNone), old_of(vertex_count, kNone);
  std::vector<char> coded(F, 0);
  CodingOrder local;
  CodingOrder& out = order ? *order : local;
  out = CodingOrder{};
  auto take_face = [&](std::uint32_t f, std::uint32_t rotation, std::uint32_t a, std::uint32_t b, std::uint32_t c) {
    front.add_face(a, b, c);
    out.face.push_back(f);
    out.rotation.push_back(rotation);
    coded[f] = 1;
  };
  auto new_label = [&](std::uint32_t v) {
    label[v] = front.seen++;
    old_of[label[v]] = v;
    return label[v];
  };

  std::uint32_t next_start = 0;
  int previous = kWasOther;
  while (out.face.size() < F) {
    std::uint32_t a, b;
    if (!front.next_gate(a, b)) {
      // A new component starts at the lowest uncoded face: its three corners, each new or named.
      while (coded[next_start]) ++next_start;
      std::uint32_t corners[3];
      for (int i = 0; i < 3; ++i) {
        const std::uint32_t v = triangles[3 * next_start + i];
        encoder.encode(m.start_new, label[v] == kNone);
        if (label[v] == kNone)
          corners[i] = new_label(v);
        else
          m.vertex.encode(encoder, front.seen - 1 - (corners[i] = label[v]));
      }
      take_face(next_start, 0, corners[0], corners[1], corners[2]);
      continue;
    }
    const auto across = corner_of_edge.find(key(old_of[b], old_of[a]));
    encoder.encode(m.boundary[previous], across == corner_of_edge.end());
    if (across == corner_of_edge.end()) {
      previous = kWasOther;
      continue;
    }
    const std::uint32_t f = across->second / 3, r = across->second % 3;
    const std::uint32_t c_old = triangles[3 * f + (r + 2) % 3];
    std::uint32_t c = label[c_old];
    bool named = false;
    const int context = previous;
    for (const auto& [list, model, kind] :
         {std::tuple{&front.right(a), &m.right[context][front.faces_at(a)], kWasRight},
          std::tuple{&front.left(b), &m.left[context][front.faces_at(b)], kWasLeft}}) {
      if (named || list->empty()) continue;
      const bool here = c != kNone && std::find(list->begin(), list->end(), c) != list->end();
      encoder.encode(*model, here);
      if (here && list->size() > 1) m.index.encode(encoder, position_in(*list, c));
      named = here;
      if (here) previous = kind;
    }
    if (!named) {
      encoder.encode(m.new_vertex[context][front.faces_at(b)], c == kNone);
      previous = c == kNone ? kWasNew : kWasOther;
      if (c == kNone) {
        c = new_label(c_old);
      } else {
        // A split: c is on the front but not next to the gate, most often two open edges left
        // of b or right of a; how far, else its label.
        const std::uint32_t left = front.steps_to(b, c, true), right = front.steps_to(a, c, false);
        const bool by_left = left != 0 && (right == 0 || left <= right);
        encoder.encode(m.split_left, !by_left);
        if (by_left) {
          m.walk_left.encode(encoder, left - 2);
          ++out.left_walks;
        } else {
          encoder.encode(m.split_right, right == 0);
          if (right != 0) {
            m.walk_right.encode(encoder, right - 2);
            ++out.right_walks;
          } else {
            m.vertex.encode(encoder, front.seen - 1 - c);
            ++out.split_labels;
          }
        }
      }
    }
    take_face(f, r, b, a, c);
  }
  out.label = label;
  for (std::uint32_t v = 0; v < vertex_count; ++v)
    if (out.label[v] == kNone) out.label[v] = front.seen++;
  return encoder.finish();
}

bool decode_faces(std::span<const std::uint8_t> bytes, std::uint32_t vertex_count, std::uint32_t face_count,
                  std::vector<std::uint32_t>& triangles) {
  RangeDecoder decoder(bytes);
  Models m;
  Front front(vertex_count);
  auto bit = [&](BitModel& model, int& out) {
    out = decoder.decode(model);
    return !decoder.exhausted();
  };
  // A vertex named explicitly must already be labelled; a new one gets the next label.
  auto named_vertex = [&](std::uint32_t& v) {
    std::uint32_t back = 0;
    if (!m.vertex.decode(decoder, back) || back >= front.seen) return false;
    v = front.seen - 1 - back;
    return true;
  };
  auto fresh_vertex = [&](std::uint32_t& v) {
    if (front.seen >= vertex_count) return false;
    v = front.seen++;
    return true;
  };
  // Twins of gates declared boundary: no later face may run along one (the encoder declares a
  // gate boundary only when no face lies across it), so a stream that puts one there is corrupt.
  EdgeSet boundary;
  auto crosses_boundary = [&](std::uint32_t x, std::uint32_t y, std::uint32_t z) {
    return boundary.contains(key(x, y)) || boundary.contains(key(y, z)) || boundary.contains(key(z, x));
  };
  int previous = kWasOther;
  while (front.faces.size() < 3 * std::size_t{face_count}) {
    std::uint32_t a, b;
    int s = 0;
    if (!front.next_gate(a, b)) {
      std::uint32_t corners[3];
      for (auto& corner : corners) {
        if (!bit(m.start_new, s)) return false;
        if (!(s ? fresh_vertex(corner) : named_vertex(corner))) return false;
      }
      if (corners[0] == corners[1] || corners[1] == corners[2] || corners[0] == corners[2]) return false;
      if (crosses_boundary(corners[0], corners[1], corners[2])) return false;
      if (!front.add_face(corners[0], corners[1], corners[2])) return false;
      continue;
    }
    if (!bit(m.boundary[previous], s)) return false;
    if (s) {
      boundary.insert(key(b, a));
      previous = kWasOther;
      continue;
    }
    std::uint32_t c = kNone;
    const int context = previous;
    for (const auto& [list, model, kind] :
         {std::tuple{&front.right(a), &m.right[context][front.faces_at(a)], kWasRight},
          std::tuple{&front.left(b), &m.left[context][front.faces_at(b)], kWasLeft}}) {
      if (c != kNone || list->empty()) continue;
      if (!bit(*model, s)) return false;
      if (!s) continue;
      std::uint32_t index = 0;
      if (list->size() > 1 && (!m.index.decode(decoder, index) || index >= list->size())) return false;
      c = (*list)[index];
      previous = kind;
    }
    if (c == kNone) {
      if (!bit(m.new_vertex[context][front.faces_at(b)], s)) return false;
      previous = s ? kWasNew : kWasOther;
      if (s) {
        if (!fresh_vertex(c)) return false;
      } else {
        // A split: two or more open edges left of b, or right of a, or a label.
        int by_label = 0;
        if (!bit(m.split_left, s)) return false;
        if (s && !bit(m.split_right, by_label)) return false;
        if (by_label) {
          if (!named_vertex(c)) return false;
        } else {
          std::uint32_t steps = 0;
          if (!(s ? m.walk_right : m.walk_left).decode(decoder, steps) || steps > kMaxWalk - 2) return false;
          c = front.walk(s ? a : b, steps + 2, !s);
          if (c == kNone) return false;
        }
      }
    }
    if (c == a || c == b || crosses_boundary(b, a, c) || !front.add_face(b, a, c)) return false;
  }
  triangles = std::move(front.faces);
  return true;
}

}  // namespace meshlift::base_mesh
