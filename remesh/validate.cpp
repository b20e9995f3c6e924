#include "meshlift/validate.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numeric>
#include <sstream>

#include "meshlift/self_intersection.h"
#include "meshlift/weld.h"

namespace meshlift {
namespace {

/// Union-find with path halving and union by size.
class DisjointSets {
 public:
  explicit DisjointSets(std::size_t n) : parent_(n), size_(n, 1) { std::iota(parent_.begin(), parent_.end(), 0u); }
  std::uint32_t find(std::uint32_t x) {
    while (parent_[x] != x) {
      parent_[x] = parent_[parent_[x]];
      x = parent_[x];
    }
    return x;
  }
  void unite(std::uint32_t a, std::uint32_t b) {
    a = find(a);
    b = find(b);
    if (a == b) return;
    if (size_[a] < size_[b]) std::swap(a, b);
    parent_[b] = a;
    size_[a] += size_[b];
  }

 private:
  std::vector<std::uint32_t> parent_;
  std::vector<std::uint32_t> size_;
};

/// One side of an edge as traversed by a face: from corner `from` to corner `to` (indices into
/// face_indices). `key` packs the undirected edge (min << 32 | max); `forward` is from < to.
struct HalfEdge {
  std::uint64_t key;
  std::uint32_t face;
  std::uint32_t from;
  std::uint32_t to;
  bool forward;
};

std::string structure_error_of(const PolygonMesh& mesh) {
  if (mesh.positions.size() % 3 != 0) return "positions length " + std::to_string(mesh.positions.size()) + " is not a multiple of 3";
  if (mesh.face_offsets.empty()) return "face_offsets is empty (needs a leading 0)";
  if (mesh.face_offsets.front() != 0) return "face_offsets does not start at 0";
  for (std::size_t f = 0; f + 1 < mesh.face_offsets.size(); ++f)
    if (mesh.face_offsets[f + 1] < mesh.face_offsets[f]) return "face_offsets decreases at face " + std::to_string(f);
  if (mesh.face_offsets.back() != mesh.face_indices.size())
    return "face_offsets ends at " + std::to_string(mesh.face_offsets.back()) + " but face_indices has " +
           std::to_string(mesh.face_indices.size()) + " entries";
  if (mesh.face_indices.size() >= kNone) return "too many face corners for 32-bit indices";
  return "";
}

std::string plural(std::uint64_t n, const std::string& singular, const std::string& plural_form) {
  return std::to_string(n) + " " + (n == 1 ? singular : plural_form);
}

std::string json_escape(const std::string& s) {
  std::string out;
  for (const char ch : s) {
    const auto c = static_cast<unsigned char>(ch);
    if (c == '"' || c == '\\') {
      out += '\\';
      out += ch;
    } else if (c < 0x20) {
      char buf[8];
      std::snprintf(buf, sizeof buf, "\\u%04x", c);
      out += buf;
    } else {
      out += ch;
    }
  }
  return out;
}

std::string format_double(double x) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.17g", x);
  return buf;
}

/// The area of the polygon with `n` corners `corners` (indices into p), ½ |Σ (p_i − p_0) ×
/// (p_{i+1} − p_0)| (its vector area).
double polygon_area(const std::vector<double>& p, const std::uint32_t* corners, std::size_t n) {
  const double* o = &p[3 * std::size_t{corners[0]}];
  double v[3] = {0, 0, 0};
  for (std::size_t c = 1; c + 1 < n; ++c) {
    const double* a = &p[3 * std::size_t{corners[c]}];
    const double* b = &p[3 * std::size_t{corners[c + 1]}];
    const double u[3] = {a[0] - o[0], a[1] - o[1], a[2] - o[2]};
    const double w[3] = {b[0] - o[0], b[1] - o[1], b[2] - o[2]};
    v[0] += u[1] * w[2] - u[2] * w[1];
    v[1] += u[2] * w[0] - u[0] * w[2];
    v[2] += u[0] * w[1] - u[1] * w[0];
  }
  return 0.5 * std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
}

}  // namespace

bool has_nonzero_area_face(const TriangleMesh& mesh) {
  const double d = bounding_box_diagonal(mesh.positions);
  for (std::size_t f = 0; f < mesh.face_count(); ++f)
    if (polygon_area(mesh.positions, &mesh.triangles[3 * f], 3) > kZeroAreaFactor * d * d) return true;
  return false;
}

MeshReport validate_mesh(const PolygonMesh& mesh) {
  MeshReport r;
  r.vertices = mesh.positions.size() / 3;
  r.vertex_colours = !mesh.colors.empty();
  r.structure_error = structure_error_of(mesh);
  if (!r.structure_error.empty()) return r;

  const std::size_t vertex_count = mesh.vertex_count();
  const std::size_t face_count = mesh.face_count();
  const std::vector<double>& p = mesh.positions;
  r.faces = face_count;

  // ---- vertices: finiteness, bounding box, exact duplicates ----
  std::vector<char> finite(vertex_count, 1);
  double lo[3] = {0, 0, 0}, hi[3] = {0, 0, 0};
  bool any_finite = false;
  for (std::size_t v = 0; v < vertex_count; ++v) {
    if (!(std::isfinite(p[3 * v]) && std::isfinite(p[3 * v + 1]) && std::isfinite(p[3 * v + 2]))) {
      finite[v] = 0;
      if (r.non_finite_vertices++ == 0) r.first_non_finite_vertex = static_cast<std::uint32_t>(v);
      continue;
    }
    for (int k = 0; k < 3; ++k) {
      lo[k] = any_finite ? std::min(lo[k], p[3 * v + k]) : p[3 * v + k];
      hi[k] = any_finite ? std::max(hi[k], p[3 * v + k]) : p[3 * v + k];
    }
    any_finite = true;
  }
  r.bbox_diagonal = std::sqrt((hi[0] - lo[0]) * (hi[0] - lo[0]) + (hi[1] - lo[1]) * (hi[1] - lo[1]) +
                              (hi[2] - lo[2]) * (hi[2] - lo[2]));
  r.duplicate_vertices = coincident_vertex_count(p);  // weld.h

  // ---- faces: corner counts, index range, repeated indices -> usable ----
  const std::vector<std::uint32_t>& corner_vertex = mesh.face_indices;
  std::vector<char> usable(face_count, 0);
  std::vector<char> named(vertex_count, 0);  // named by any in-range corner
  std::vector<std::uint32_t> scratch;
  for (std::size_t f = 0; f < face_count; ++f) {
    const std::uint32_t begin = mesh.face_offsets[f], end = mesh.face_offsets[f + 1];
    const std::size_t size = end - begin;
    if (size != 3) {
      if (r.non_triangle_faces++ == 0) {
        r.first_non_triangle_face = static_cast<std::uint32_t>(f);
        r.first_non_triangle_face_corners = size;
      }
    }
    std::uint64_t bad = 0;
    for (std::uint32_t c = begin; c < end; ++c) {
      if (corner_vertex[c] >= vertex_count) ++bad;
      else named[corner_vertex[c]] = 1;
    }
    if (bad) {
      r.invalid_indices += bad;
      if (r.invalid_index_faces++ == 0) r.first_invalid_index_face = static_cast<std::uint32_t>(f);
      continue;
    }
    scratch.assign(corner_vertex.begin() + begin, corner_vertex.begin() + end);
    std::sort(scratch.begin(), scratch.end());
    if (size < 3 || std::adjacent_find(scratch.begin(), scratch.end()) != scratch.end()) {
      if (r.degenerate_faces++ == 0) r.first_degenerate_face = static_cast<std::uint32_t>(f);
      continue;
    }
    usable[f] = 1;
  }
  for (std::size_t v = 0; v < vertex_count; ++v)
    if (!named[v]) ++r.isolated_vertices;

  // ---- zero-area faces: area = ½ |Σ (p_i − p_0) × (p_{i+1} − p_0)| (vector area of a polygon) ----
  const double zero_area = kZeroAreaFactor * r.bbox_diagonal * r.bbox_diagonal;
  for (std::size_t f = 0; f < face_count; ++f) {
    if (!usable[f]) continue;
    const std::uint32_t begin = mesh.face_offsets[f], end = mesh.face_offsets[f + 1];
    bool all_finite = true;
    for (std::uint32_t c = begin; c < end; ++c) all_finite = all_finite && finite[corner_vertex[c]];
    if (!all_finite) continue;
    if (polygon_area(p, &corner_vertex[begin], end - begin) <= zero_area) ++r.zero_area_faces;
  }

  // ---- edges: sort the half-edges of usable faces by undirected key ----
  // In the order of (key, face): a counting sort by the key's high half, the edge's smaller
  // vertex (faces in increasing order within each), then each vertex's few half-edges by the low
  // half, stably. The same order as one comparison sort, in linear time.
  std::vector<HalfEdge> half_edges;
  {
    std::vector<std::uint32_t> first_of_vertex(vertex_count + 1, 0);
    auto for_each_half_edge = [&](auto&& visit) {
      for (std::size_t f = 0; f < face_count; ++f) {
        if (!usable[f]) continue;
        const std::uint32_t begin = mesh.face_offsets[f], end = mesh.face_offsets[f + 1];
        for (std::uint32_t c = begin; c < end; ++c) {
          const std::uint32_t d = c + 1 < end ? c + 1 : begin;
          visit(static_cast<std::uint32_t>(f), c, d, corner_vertex[c], corner_vertex[d]);
        }
      }
    };
    for_each_half_edge([&](std::uint32_t, std::uint32_t, std::uint32_t, std::uint32_t a, std::uint32_t b) {
      ++first_of_vertex[std::min(a, b) + 1];
    });
    for (std::size_t v = 0; v < vertex_count; ++v) first_of_vertex[v + 1] += first_of_vertex[v];
    half_edges.resize(first_of_vertex[vertex_count]);
    std::vector<std::uint32_t> next(first_of_vertex.begin(), first_of_vertex.end() - 1);
    for_each_half_edge([&](std::uint32_t f, std::uint32_t c, std::uint32_t d, std::uint32_t a, std::uint32_t b) {
      const std::uint64_t key = (std::uint64_t(std::min(a, b)) << 32) | std::max(a, b);
      half_edges[next[std::min(a, b)]++] = {key, f, c, d, a < b};
    });
    // Each vertex's half-edges: the few of an ordinary vertex (about its valence) by an insertion
    // sort (stable, so faces stay in order; no buffer), the many of a hub (a fan of thousands of
    // faces, as a hostile file may hold) by a comparison sort on (key, face), never quadratic.
    constexpr std::uint32_t kInsertionSortMost = 32;
    for (std::size_t v = 0; v < vertex_count; ++v) {
      const std::uint32_t first = first_of_vertex[v], last = first_of_vertex[v + 1];
      if (last - first > kInsertionSortMost) {
        std::sort(half_edges.begin() + first, half_edges.begin() + last, [](const HalfEdge& x, const HalfEdge& y) {
          return x.key != y.key ? x.key < y.key : x.face < y.face;
        });
        continue;
      }
      for (std::uint32_t i = first + 1; i < last; ++i) {
        const HalfEdge h = half_edges[i];
        std::uint32_t k = i;
        for (; k > first && half_edges[k - 1].key > h.key; --k) half_edges[k] = half_edges[k - 1];
        half_edges[k] = h;
      }
    }
  }
  // Calls visit(i, j) for each edge in key order: the half-edges [i, j) sharing its key.
  auto for_each_edge = [&](auto&& visit) {
    for (std::size_t i = 0; i < half_edges.size();) {
      std::size_t j = i + 1;
      while (j < half_edges.size() && half_edges[j].key == half_edges[i].key) ++j;
      visit(i, j);
      i = j;
    }
  };

  // Fans around vertices: corners joined across manifold edges (section 8.3.1: a manifold vertex
  // has one cycle, a boundary vertex one chain of triangles; more than one fan is a pinch).
  DisjointSets fans(corner_vertex.size());
  DisjointSets boundary_sets(vertex_count);
  std::vector<char> on_boundary(vertex_count, 0);
  std::vector<char> face_on_non_manifold_edge(face_count, 0);
  // Face adjacency across manifold edges, counted here per face and listed below.
  std::vector<std::uint32_t> first_adjacent(face_count + 1, 0);
  std::vector<std::uint64_t> edge_keys;  // one per distinct edge, for per-component counts
  for_each_edge([&](std::size_t i, std::size_t j) {
    const std::size_t multiplicity = j - i;
    ++r.edges;
    edge_keys.push_back(half_edges[i].key);
    const auto a = static_cast<std::uint32_t>(half_edges[i].key >> 32);
    const auto b = static_cast<std::uint32_t>(half_edges[i].key & 0xffffffffu);
    if (multiplicity == 1) {
      ++r.boundary_edges;
      boundary_sets.unite(a, b);
      on_boundary[a] = on_boundary[b] = 1;
    } else if (multiplicity == 2) {
      const HalfEdge& x = half_edges[i];
      const HalfEdge& y = half_edges[i + 1];
      // Section 8.3.1.1: consistently oriented neighbours list the shared edge as (i,j) and (j,i).
      const bool flip = x.forward == y.forward;
      if (flip && r.inconsistent_edges++ == 0) {
        r.first_inconsistent_edge[0] = a;
        r.first_inconsistent_edge[1] = b;
      }
      ++first_adjacent[x.face + 1];
      ++first_adjacent[y.face + 1];
      const auto corner_at = [&](const HalfEdge& h, std::uint32_t v) { return corner_vertex[h.from] == v ? h.from : h.to; };
      fans.unite(corner_at(x, a), corner_at(y, a));
      fans.unite(corner_at(x, b), corner_at(y, b));
    } else {
      if (r.non_manifold_edges++ == 0) {
        r.first_non_manifold_edge[0] = a;
        r.first_non_manifold_edge[1] = b;
      }
      for (std::size_t k = i; k < j; ++k) face_on_non_manifold_edge[half_edges[k].face] = 1;
    }
  });
  r.consistently_oriented = r.inconsistent_edges == 0;

  std::vector<char> non_manifold_vertex(vertex_count, 0);
  {
    // A vertex whose usable corners lie in more than one fan: each vertex's first fan root
    // against the others', the vertices in increasing order.
    std::vector<std::uint32_t> fan_of_vertex(vertex_count, kNone);
    for (std::size_t f = 0; f < face_count; ++f) {
      if (!usable[f]) continue;
      for (std::uint32_t c = mesh.face_offsets[f]; c < mesh.face_offsets[f + 1]; ++c) {
        const std::uint32_t v = corner_vertex[c], root = fans.find(c);
        if (fan_of_vertex[v] == kNone)
          fan_of_vertex[v] = root;
        else if (fan_of_vertex[v] != root)
          non_manifold_vertex[v] = 1;
      }
    }
    for (std::size_t v = 0; v < vertex_count; ++v)
      if (non_manifold_vertex[v] && r.non_manifold_vertices++ == 0) r.first_non_manifold_vertex = static_cast<std::uint32_t>(v);
  }

  // ---- components: vertices joined by usable faces ----
  DisjointSets vertex_sets(vertex_count);
  std::vector<char> referenced(vertex_count, 0);
  for (std::size_t f = 0; f < face_count; ++f) {
    if (!usable[f]) continue;
    const std::uint32_t begin = mesh.face_offsets[f], end = mesh.face_offsets[f + 1];
    for (std::uint32_t c = begin; c < end; ++c) {
      referenced[corner_vertex[c]] = 1;
      vertex_sets.unite(corner_vertex[begin], corner_vertex[c]);
    }
  }
  std::vector<std::uint32_t> component_of_root(vertex_count, kNone);
  std::vector<ComponentReport> components;
  std::vector<std::uint32_t> vertex_component(vertex_count, kNone);
  for (std::size_t v = 0; v < vertex_count; ++v) {
    if (!referenced[v]) continue;
    ++r.referenced_vertices;
    const std::uint32_t root = vertex_sets.find(static_cast<std::uint32_t>(v));
    if (component_of_root[root] == kNone) {
      component_of_root[root] = static_cast<std::uint32_t>(components.size());
      components.emplace_back();
      components.back().manifold = true;
      components.back().orientable = true;
    }
    vertex_component[v] = component_of_root[root];
    ComponentReport& c = components[vertex_component[v]];
    ++c.vertices;
    if (non_manifold_vertex[v]) c.manifold = false;
    if (on_boundary[v] && boundary_sets.find(static_cast<std::uint32_t>(v)) == v) {
      ++c.boundary_loops;
      ++r.boundary_loops;
    }
  }
  std::vector<std::uint32_t> face_component(face_count, kNone);
  for (std::size_t f = 0; f < face_count; ++f) {
    if (!usable[f]) continue;
    face_component[f] = vertex_component[corner_vertex[mesh.face_offsets[f]]];
    ComponentReport& c = components[face_component[f]];
    if (c.faces++ == 0) c.first_face = static_cast<std::uint32_t>(f);
    if (face_on_non_manifold_edge[f]) c.manifold = false;
  }
  for (const std::uint64_t key : edge_keys) ++components[vertex_component[key >> 32]].edges;

  // ---- orientation: breadth-first propagation of face signs (exercise 8.6) ----
  // Across a manifold edge, sign(g) = sign(f) when the faces run the edge in opposite directions
  // and −sign(f) when they run it the same way; a contradiction means non-orientable.
  // Each face's neighbours across its manifold edges, and whether both faces run the edge the
  // same way (`flip`).
  for (std::size_t f = 0; f < face_count; ++f) first_adjacent[f + 1] += first_adjacent[f];
  std::vector<std::uint32_t> adjacent(first_adjacent[face_count]);
  std::vector<char> flip(adjacent.size());
  {
    std::vector<std::uint32_t> next(first_adjacent.begin(), first_adjacent.end() - 1);
    for_each_edge([&](std::size_t i, std::size_t j) {
      if (j - i != 2) return;
      const HalfEdge& x = half_edges[i];
      const HalfEdge& y = half_edges[i + 1];
      const char same_way = x.forward == y.forward;
      flip[next[x.face]] = same_way;
      adjacent[next[x.face]++] = y.face;
      flip[next[y.face]] = same_way;
      adjacent[next[y.face]++] = x.face;
    });
  }
  std::vector<signed char> sign(face_count, 0);
  std::vector<std::uint32_t> queue;
  for (std::size_t seed = 0; seed < face_count; ++seed) {
    if (!usable[seed] || sign[seed] != 0) continue;
    sign[seed] = 1;
    queue.assign(1, static_cast<std::uint32_t>(seed));
    for (std::size_t head = 0; head < queue.size(); ++head) {
      const std::uint32_t f = queue[head];
      for (std::uint32_t k = first_adjacent[f]; k < first_adjacent[f + 1]; ++k) {
        const std::uint32_t other = adjacent[k];
        const signed char wanted = static_cast<signed char>(flip[k] ? -sign[f] : sign[f]);
        if (sign[other] == 0) {
          sign[other] = wanted;
          queue.push_back(other);
        } else if (sign[other] != wanted) {
          r.orientable = false;
          components[face_component[f]].orientable = false;
        }
      }
    }
  }

  // ---- Euler characteristic and genus: χ = V − E + F = 2 − 2g − b (closed: b = 0) ----
  const std::uint64_t usable_faces = static_cast<std::uint64_t>(std::count(usable.begin(), usable.end(), 1));
  r.euler_characteristic =
      static_cast<std::int64_t>(r.referenced_vertices) - static_cast<std::int64_t>(r.edges) + static_cast<std::int64_t>(usable_faces);
  for (ComponentReport& c : components) {
    c.euler = static_cast<std::int64_t>(c.vertices) - static_cast<std::int64_t>(c.edges) + static_cast<std::int64_t>(c.faces);
    c.closed = c.boundary_loops == 0;
    const std::int64_t twice_genus = 2 - c.euler - static_cast<std::int64_t>(c.boundary_loops);
    c.genus = (c.manifold && c.orientable && twice_genus >= 0 && twice_genus % 2 == 0) ? twice_genus / 2 : -1;
  }
  std::sort(components.begin(), components.end(), [](const ComponentReport& x, const ComponentReport& y) {
    return x.faces != y.faces ? x.faces > y.faces : x.first_face < y.first_face;
  });
  r.connected_components = components.size();
  r.components = std::move(components);
  return r;
}

MeshReport validate_mesh(const TriangleMesh& mesh) {
  if (mesh.triangles.size() % 3 != 0) {
    MeshReport r;
    r.vertices = mesh.positions.size() / 3;
    r.structure_error = "triangles length " + std::to_string(mesh.triangles.size()) + " is not a multiple of 3";
    return r;
  }
  return validate_mesh(to_polygon_mesh(mesh));
}

namespace {

/// The first problem of a mesh for the triangle codec and what to do about it (either empty): the
/// one chain of checks both first_problem_for_triangle_codec() and how_to_repair() read.
struct Problem {
  std::string what, repair;
};

Problem first_problem(const MeshReport& r) {
  if (!r.structure_error.empty()) return {"malformed mesh arrays: " + r.structure_error, ""};
  if (r.faces == 0)
    return r.vertices == 0 ? Problem{"mesh is empty", ""}
                           : Problem{"mesh has no faces",
                                     "a point cloud, or a file whose faces were not written: meshlift codes surfaces; "
                                     "reconstruct one from the points first (a surface reconstruction, e.g. screened "
                                     "Poisson)"};
  if (r.invalid_index_faces > 0)
    return {plural(r.invalid_indices, "face corner references a vertex", "face corners reference vertices") +
                " that do not exist (first in face " + std::to_string(r.first_invalid_index_face) + ")",
            "the file is damaged or its faces count their vertices otherwise: write it again"};
  if (r.non_triangle_faces > 0) {
    std::string message = "face " + std::to_string(r.first_non_triangle_face) + " has " +
                          plural(r.first_non_triangle_face_corners, "corner", "corners") + ": triangles required";
    if (r.non_triangle_faces > 1) message += " (" + std::to_string(r.non_triangle_faces) + " non-triangle faces)";
    return {message, "split the faces into triangles first (the CLI and to_triangle_mesh() do)"};
  }
  if (r.degenerate_faces > 0)
    return {plural(r.degenerate_faces, "degenerate face", "degenerate faces") + " (repeated vertex; first: face " +
                std::to_string(r.first_degenerate_face) + ")",
            "remove the faces that name a vertex twice (they have no area)"};
  const auto edge = [](const std::uint32_t (&e)[2]) {
    return "edge " + std::to_string(e[0]) + "-" + std::to_string(e[1]);
  };
  if (r.non_finite_vertices > 0)
    return {plural(r.non_finite_vertices, "vertex has", "vertices have") + " non-finite coordinates (first: vertex " +
                std::to_string(r.first_non_finite_vertex) + ")",
            "remove those vertices and their faces, or give them coordinates"};
  if (r.non_manifold_edges > 0)
    return {plural(r.non_manifold_edges, "non-manifold edge", "non-manifold edges") + " (first: " +
                edge(r.first_non_manifold_edge) + ", on more than two faces)",
            "keep at most two faces on each edge: remove the extra faces, or give them vertices of their own (a "
            "piece apart)"};
  if (r.non_manifold_vertices > 0)
    return {plural(r.non_manifold_vertices, "non-manifold vertex", "non-manifold vertices") + " (first: vertex " +
                std::to_string(r.first_non_manifold_vertex) + ", where separate fans of faces meet)",
            "give each fan of faces its own copy of the vertex (pieces that only touch there become separate), or "
            "remove the pieces that meet there"};
  if (!r.orientable)
    return {"mesh is not orientable",
            "a one-sided surface (a Moebius strip) has no consistent orientation: cut it open where it twists"};
  if (!r.consistently_oriented)
    return {plural(r.inconsistent_edges, "edge is", "edges are") +
                " traversed in the same direction by both faces: orientation is inconsistent (first: " +
                edge(r.first_inconsistent_edge) + ")",
            "turn the faces written the other way over, so that every edge is run both ways"};
  return {};
}

}  // namespace

std::string first_problem_for_triangle_codec(const MeshReport& r) { return first_problem(r).what; }

std::string how_to_repair(const MeshReport& r) { return first_problem(r).repair; }

void add_self_intersections(const PolygonMesh& mesh, MeshReport& report) {
  if (!first_problem_for_triangle_codec(report).empty()) return;
  // Beyond float range the BVH cannot hold the mesh (self_intersection.h): not checked.
  for (const double x : mesh.positions)
    if (!(std::abs(x) <= 1e30)) return;
  std::size_t total = 0;
  const auto first = self_intersections(to_triangle_mesh(mesh), 1, &total);
  report.self_intersecting_pairs = total;
  if (!first.empty()) report.first_self_intersection[0] = first[0][0], report.first_self_intersection[1] = first[0][1];
}

std::string to_text(const MeshReport& r) {
  std::ostringstream out;
  const auto line = [&](const std::string& name, const std::string& value) {
    out << name << ':' << std::string(name.size() < 24 ? 24 - name.size() : 1, ' ') << value << '\n';
  };
  const auto face_or_none = [](std::uint32_t f) { return f == kNone ? std::string("-") : "face " + std::to_string(f); };
  const auto yes_no = [](bool b) { return std::string(b ? "yes" : "no"); };
  if (!r.structure_error.empty()) line("structure error", r.structure_error);
  line("vertices", std::to_string(r.vertices));
  if (r.vertex_colours) line("vertex colours", "red, green, blue (remesh and encode carry them)");
  line("faces", std::to_string(r.faces));
  line("edges", std::to_string(r.edges));
  line("euler characteristic", std::to_string(r.euler_characteristic));
  line("components", std::to_string(r.connected_components));
  line("manifold", yes_no(r.is_manifold()));
  line("closed", yes_no(r.is_closed()));
  line("orientable", yes_no(r.orientable));
  line("consistently oriented", yes_no(r.consistently_oriented));
  line("boundary edges", std::to_string(r.boundary_edges));
  line("boundary loops", std::to_string(r.boundary_loops));
  line("non-manifold edges", std::to_string(r.non_manifold_edges));
  line("non-manifold vertices", std::to_string(r.non_manifold_vertices));
  line("inconsistent edges", std::to_string(r.inconsistent_edges));
  line("non-triangle faces", std::to_string(r.non_triangle_faces) +
                                 (r.non_triangle_faces ? " (first: " + face_or_none(r.first_non_triangle_face) + ")" : ""));
  line("degenerate faces", std::to_string(r.degenerate_faces) +
                               (r.degenerate_faces ? " (first: " + face_or_none(r.first_degenerate_face) + ")" : ""));
  line("invalid index faces", std::to_string(r.invalid_index_faces) +
                                  (r.invalid_index_faces ? " (first: " + face_or_none(r.first_invalid_index_face) + ")" : ""));
  line("zero-area faces", std::to_string(r.zero_area_faces));
  line("referenced vertices", std::to_string(r.referenced_vertices));
  line("isolated vertices", std::to_string(r.isolated_vertices));
  line("duplicate vertices", std::to_string(r.duplicate_vertices));
  line("non-finite vertices", std::to_string(r.non_finite_vertices));
  line("bbox diagonal", format_double(r.bbox_diagonal));
  if (r.self_intersecting_pairs)
    line("self-intersections", std::to_string(*r.self_intersecting_pairs) + " pairs of faces cross" +
                                   (*r.self_intersecting_pairs ? " (first: faces " + std::to_string(r.first_self_intersection[0]) +
                                                                     " and " + std::to_string(r.first_self_intersection[1]) + ")"
                                                               : ""));
  const std::string problem = first_problem_for_triangle_codec(r);
  line("triangle codec", problem.empty() ? std::string("ok") : problem);
  const std::size_t listed = std::min<std::size_t>(r.components.size(), 10);
  for (std::size_t i = 0; i < listed; ++i) {
    const ComponentReport& c = r.components[i];
    out << "component " << i << ": V " << c.vertices << "  E " << c.edges << "  F " << c.faces << "  euler " << c.euler
        << "  boundary loops " << c.boundary_loops << "  " << (c.closed ? "closed" : "open") << "  "
        << (c.manifold ? "manifold" : "non-manifold") << "  " << (c.orientable ? "orientable" : "non-orientable")
        << "  genus " << (c.genus >= 0 ? std::to_string(c.genus) : std::string("-")) << '\n';
  }
  if (r.components.size() > listed) out << "... " << r.components.size() - listed << " more components\n";
  return out.str();
}

std::string to_json(const MeshReport& r) {
  std::ostringstream out;
  const auto face_or_null = [](std::uint32_t f) { return f == kNone ? std::string("null") : std::to_string(f); };
  const auto boolean = [](bool b) { return std::string(b ? "true" : "false"); };
  const std::string problem = first_problem_for_triangle_codec(r);
  out << "{\n";
  out << "  \"structure_error\": " << (r.structure_error.empty() ? "null" : '"' + json_escape(r.structure_error) + '"') << ",\n";
  out << "  \"vertices\": " << r.vertices << ",\n";
  out << "  \"vertex_colours\": " << (r.vertex_colours ? "true" : "false") << ",\n";
  out << "  \"faces\": " << r.faces << ",\n";
  out << "  \"edges\": " << r.edges << ",\n";
  out << "  \"euler_characteristic\": " << r.euler_characteristic << ",\n";
  out << "  \"connected_components\": " << r.connected_components << ",\n";
  out << "  \"manifold\": " << boolean(r.is_manifold()) << ",\n";
  out << "  \"closed\": " << boolean(r.is_closed()) << ",\n";
  out << "  \"orientable\": " << boolean(r.orientable) << ",\n";
  out << "  \"consistently_oriented\": " << boolean(r.consistently_oriented) << ",\n";
  out << "  \"boundary_edges\": " << r.boundary_edges << ",\n";
  out << "  \"boundary_loops\": " << r.boundary_loops << ",\n";
  out << "  \"non_manifold_edges\": " << r.non_manifold_edges << ",\n";
  out << "  \"non_manifold_vertices\": " << r.non_manifold_vertices << ",\n";
  out << "  \"inconsistent_edges\": " << r.inconsistent_edges << ",\n";
  out << "  \"non_triangle_faces\": " << r.non_triangle_faces << ",\n";
  out << "  \"first_non_triangle_face\": " << face_or_null(r.first_non_triangle_face) << ",\n";
  out << "  \"first_non_triangle_face_corners\": " << r.first_non_triangle_face_corners << ",\n";
  out << "  \"degenerate_faces\": " << r.degenerate_faces << ",\n";
  out << "  \"first_degenerate_face\": " << face_or_null(r.first_degenerate_face) << ",\n";
  out << "  \"invalid_index_faces\": " << r.invalid_index_faces << ",\n";
  out << "  \"invalid_indices\": " << r.invalid_indices << ",\n";
  out << "  \"first_invalid_index_face\": " << face_or_null(r.first_invalid_index_face) << ",\n";
  out << "  \"zero_area_faces\": " << r.zero_area_faces << ",\n";
  out << "  \"referenced_vertices\": " << r.referenced_vertices << ",\n";
  out << "  \"isolated_vertices\": " << r.isolated_vertices << ",\n";
  out << "  \"duplicate_vertices\": " << r.duplicate_vertices << ",\n";
  out << "  \"non_finite_vertices\": " << r.non_finite_vertices << ",\n";
  out << "  \"bbox_diagonal\": " << (std::isfinite(r.bbox_diagonal) ? format_double(r.bbox_diagonal) : "null") << ",\n";
  out << "  \"self_intersecting_pairs\": " << (r.self_intersecting_pairs ? std::to_string(*r.self_intersecting_pairs) : "null")
      << ",\n";
  out << "  \"first_self_intersection\": ";
  if (r.first_self_intersection[0] == kNone) out << "null,\n";
  else out << '[' << r.first_self_intersection[0] << ", " << r.first_self_intersection[1] << "],\n";
  out << "  \"triangle_codec_problem\": " << (problem.empty() ? "null" : '"' + json_escape(problem) + '"') << ",\n";
  const std::size_t listed = std::min<std::size_t>(r.components.size(), 100);
  out << "  \"components_listed\": " << listed << ",\n";
  out << "  \"components\": [";
  for (std::size_t i = 0; i < listed; ++i) {
    const ComponentReport& c = r.components[i];
    out << (i ? ",\n" : "\n") << "    {\"vertices\": " << c.vertices << ", \"faces\": " << c.faces << ", \"edges\": " << c.edges
        << ", \"euler\": " << c.euler << ", \"boundary_loops\": " << c.boundary_loops << ", \"closed\": " << boolean(c.closed)
        << ", \"manifold\": " << boolean(c.manifold) << ", \"orientable\": " << boolean(c.orientable)
        << ", \"genus\": " << c.genus << ", \"first_face\": " << face_or_null(c.first_face) << "}";
  }
  out << (listed ? "\n  ]\n" : "]\n") << "}\n";
  return out.str();
}

}  // namespace meshlift
