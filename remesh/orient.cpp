// Consistent face orientation by a breadth-first walk over shared edges. See orient.h.
#include "meshlift/orient.h"

#include <algorithm>
#include <array>
#include <cstdint>
#include <tuple>
#include <vector>

namespace meshlift {

Orientation orient_consistently(const TriangleMesh& mesh) {
  const std::size_t faces = mesh.face_count();
  const std::vector<std::uint32_t>& t = mesh.triangles;
  // Every face's edges as (low, high, face, forward: the face runs low -> high), sorted, so that
  // the faces of an edge are neighbours in the list.
  struct Side {
    std::uint32_t low, high, face;
    bool forward;
  };
  std::vector<Side> sides;
  sides.reserve(3 * faces);
  for (std::uint32_t f = 0; f < faces; ++f)
    for (int i = 0; i < 3; ++i) {
      const std::uint32_t a = t[3 * f + i], b = t[3 * f + (i + 1) % 3];
      sides.push_back({std::min(a, b), std::max(a, b), f, a < b});
    }
  std::sort(sides.begin(), sides.end(), [](const Side& x, const Side& y) {
    return std::tie(x.low, x.high, x.face) < std::tie(y.low, y.high, y.face);
  });
  // Per face, its neighbours across edges of exactly two faces, with whether both faces run that
  // edge the same way (then one of them must turn over); and whether it has a boundary edge.
  struct Link {
    std::uint32_t other;
    bool same_way;
  };
  std::vector<std::vector<Link>> links(faces);
  std::vector<char> open_face(faces, 0), tangled_face(faces, 0);
  for (std::size_t i = 0; i < sides.size();) {
    std::size_t j = i + 1;
    while (j < sides.size() && sides[j].low == sides[i].low && sides[j].high == sides[i].high) ++j;
    if (j - i == 1) {
      open_face[sides[i].face] = 1;
    } else if (j - i == 2) {
      const bool same = sides[i].forward == sides[i + 1].forward;
      links[sides[i].face].push_back({sides[i + 1].face, same});
      links[sides[i + 1].face].push_back({sides[i].face, same});
    } else {
      for (std::size_t k = i; k < j; ++k) tangled_face[sides[k].face] = 1;  // an edge of 3+ faces
    }
    i = j;
  }

  Orientation result;
  result.mesh = mesh;
  std::vector<signed char> flip(faces, -1);  // -1: not reached yet
  std::vector<std::uint32_t> component;
  for (std::uint32_t seed = 0; seed < faces; ++seed) {
    if (flip[seed] >= 0) continue;
    // Walk the component from its first face, kept as it is.
    component.assign(1, seed);
    flip[seed] = 0;
    bool consistent = true, closed = true, tangled = false;
    for (std::size_t k = 0; k < component.size(); ++k) {
      const std::uint32_t f = component[k];
      closed &= !open_face[f];
      tangled |= tangled_face[f] != 0;
      for (const Link& link : links[f]) {
        const signed char wanted = static_cast<signed char>(flip[f] ^ (link.same_way ? 1 : 0));
        if (flip[link.other] < 0) {
          flip[link.other] = wanted;
          component.push_back(link.other);
        } else if (flip[link.other] != wanted) {
          consistent = false;
        }
      }
    }
    if (!consistent || tangled) {
      ++result.unorientable_components;
      for (const std::uint32_t f : component) flip[f] = 0;
      continue;
    }
    std::size_t flips = 0;
    for (const std::uint32_t f : component) flips += static_cast<std::size_t>(flip[f]);
    if (flips == 0) continue;  // consistent already: as it is
    ++result.fixed_components;
    bool turn_over = false;
    if (closed) {
      // Six times the signed volume, Σ a · (b × c) over the faces (divergence theorem: each face
      // with the apex at the origin is a signed tetrahedron), taken about the component's first
      // corner (fewer digits lost); positive when the faces face outwards.
      const double* o = &mesh.positions[3 * std::size_t{t[3 * seed]}];
      double volume = 0;
      for (const std::uint32_t f : component) {
        std::array<std::array<double, 3>, 3> c;
        for (int i = 0; i < 3; ++i)
          for (int k = 0; k < 3; ++k) c[i][k] = mesh.positions[3 * std::size_t{t[3 * f + i]} + k] - o[k];
        if (flip[f]) std::swap(c[1], c[2]);
        volume += c[0][0] * (c[1][1] * c[2][2] - c[1][2] * c[2][1]) - c[0][1] * (c[1][0] * c[2][2] - c[1][2] * c[2][0]) +
                  c[0][2] * (c[1][0] * c[2][1] - c[1][1] * c[2][0]);
      }
      turn_over = volume < 0;
    } else {
      turn_over = 2 * flips > component.size();
    }
    for (const std::uint32_t f : component) {
      if (turn_over) flip[f] ^= 1;
      if (!flip[f]) continue;
      ++result.flipped_faces;
      std::swap(result.mesh.triangles[3 * std::size_t{f} + 1], result.mesh.triangles[3 * std::size_t{f} + 2]);
    }
  }
  return result;
}

}  // namespace meshlift
