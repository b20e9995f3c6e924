// OpenMesh's triangle mesh as remesh/'s decimators use it (decimate.cpp, and the progressive
// mesh of spherical_parametrization.cpp): double coordinates, and the halfedge collapse test
// compiled here (not installed).
#pragma once

#include <OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh>

#include <algorithm>
#include <vector>

namespace meshlift {

struct DoubleTraits : OpenMesh::DefaultTraits {
  using Point = OpenMesh::Vec3d;
  using Normal = OpenMesh::Vec3d;
};

/// The collapse test is written here because Debian's libOpenMeshCore is built with assertions
/// on: its TriConnectivity::is_collapse_ok() checks the type name of the status property (a
/// string built, compared and freed) at every access, a third of a decimation's time (armadillo:
/// perf, 22 % in the test, 12 % memcmp, 8 % malloc and free). This one is compiled in our
/// translation units, where the status accessors are inline, and it hides the library's, so
/// DecimaterT<HalfedgeMesh>::is_collapse_legal() calls it. It makes the library's decisions
/// (tests/remesh/test_decimate.cpp compares the two on every halfedge as meshes collapse).
struct HalfedgeMesh : OpenMesh::TriMesh_ArrayKernelT<DoubleTraits> {
  /// The halfedge collapse v0 -> v1 keeps a manifold mesh of the same topology: neither edge is
  /// deleted; the triangle on either side is not a corner flap with two boundary edges; the
  /// two triangles' third vertices vl and vr differ (or, both absent, the edge is no edge of a
  /// face); v0 and v1 have no common neighbour but vl and vr (the link condition, seed 002
  /// §8.3.5); and an edge between two boundary vertices is itself a boundary edge.
  bool is_collapse_ok(HalfedgeHandle v0v1) {
    if (status(edge_handle(v0v1)).deleted()) return false;
    const HalfedgeHandle v1v0 = opposite_halfedge_handle(v0v1);
    const VertexHandle v0 = to_vertex_handle(v1v0), v1 = to_vertex_handle(v0v1);
    if (status(v0).deleted() || status(v1).deleted()) return false;
    // The third vertex of the triangle on a side, or none; false when that triangle's two other
    // edges are both boundary edges.
    auto third = [&](HalfedgeHandle h, VertexHandle& apex) {
      if (is_boundary(h)) return true;
      const HalfedgeHandle h1 = next_halfedge_handle(h), h2 = next_halfedge_handle(h1);
      apex = to_vertex_handle(h1);
      return !(is_boundary(opposite_halfedge_handle(h1)) && is_boundary(opposite_halfedge_handle(h2)));
    };
    VertexHandle vl, vr;
    if (!third(v0v1, vl) || !third(v1v0, vr) || vl == vr) return false;
    // Common neighbours: one rings are small (valence ~6), so a scan of v1's beats tagging.
    ring_.clear();
    for_each_outgoing(v1, [&](HalfedgeHandle h) {
      ring_.push_back(to_vertex_handle(h));
      return true;
    });
    return for_each_outgoing(v0, [&](HalfedgeHandle h) {
             const VertexHandle w = to_vertex_handle(h);
             return w == vl || w == vr || std::find(ring_.begin(), ring_.end(), w) == ring_.end();
           }) &&
           !(is_boundary(v0) && is_boundary(v1) && !is_boundary(v0v1) && !is_boundary(v1v0));
  }

  /// The halfedge from `from` to `to`, or an invalid handle: the library's, compiled here for the
  /// same reason. DecimaterT::is_collapse_legal() asks it for every collapse it weighs (its
  /// tetrahedron test): 8 % of a decimation (perf, the 104k armadillo of docs/RESULTS.md).
  HalfedgeHandle find_halfedge(VertexHandle from, VertexHandle to) const {
    HalfedgeHandle found;
    for_each_outgoing(from, [&](HalfedgeHandle h) {
      if (to_vertex_handle(h) == to) found = h;
      return !found.is_valid();
    });
    return found;
  }

  /// Calls visit(h) for each halfedge h out of v until it returns false; returns whether it never
  /// did. By halfedges (the opposite's next is the next outgoing halfedge), not OpenMesh's
  /// circulators, which check their state at every step.
  template <class Visit>
  bool for_each_outgoing(VertexHandle v, Visit&& visit) const {
    const HalfedgeHandle start = halfedge_handle(v);
    if (!start.is_valid()) return true;  // an isolated vertex
    HalfedgeHandle h = start;
    do {
      if (!visit(h)) return false;
      h = next_halfedge_handle(opposite_halfedge_handle(h));
    } while (h != start);
    return true;
  }

 private:
  std::vector<VertexHandle> ring_;  // v1's one ring, kept for its storage
};

}  // namespace meshlift
