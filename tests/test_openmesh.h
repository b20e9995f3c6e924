// OpenMesh as an independent oracle in tests: double-precision mesh types and conversions from
// and to the flat meshes.
#pragma once

#include <OpenMesh/Core/Mesh/PolyMesh_ArrayKernelT.hh>
#include <OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh>
#include <catch2/catch.hpp>
#include <vector>

#include "meshlift/mesh.h"

namespace meshlift::test {

struct DoubleTraits : OpenMesh::DefaultTraits {
  using Point = OpenMesh::Vec3d;
  using Normal = OpenMesh::Vec3d;
};
using OpenMeshTri = OpenMesh::TriMesh_ArrayKernelT<DoubleTraits>;
using OpenMeshPoly = OpenMesh::PolyMesh_ArrayKernelT<DoubleTraits>;

/// The flat mesh as an OpenMesh mesh (OM = OpenMeshTri or OpenMeshPoly); every face must be added.
template <typename OM>
OM to_openmesh(const PolygonMesh& mesh) {
  OM om;
  std::vector<typename OM::VertexHandle> vertices;
  for (std::size_t v = 0; v < mesh.vertex_count(); ++v)
    vertices.push_back(om.add_vertex({mesh.positions[3 * v], mesh.positions[3 * v + 1], mesh.positions[3 * v + 2]}));
  for (std::size_t f = 0; f < mesh.face_count(); ++f) {
    std::vector<typename OM::VertexHandle> corners;
    for (std::uint32_t c = mesh.face_offsets[f]; c < mesh.face_offsets[f + 1]; ++c)
      corners.push_back(vertices[mesh.face_indices[c]]);
    REQUIRE(om.add_face(corners).is_valid());
  }
  return om;
}

template <typename OM>
OM to_openmesh(const TriangleMesh& mesh) {
  return to_openmesh<OM>(to_polygon_mesh(mesh));
}

template <typename OM>
PolygonMesh from_openmesh(const OM& om) {
  PolygonMesh mesh;
  for (auto v : om.vertices()) {
    const auto& p = om.point(v);
    mesh.positions.insert(mesh.positions.end(), {p[0], p[1], p[2]});
  }
  for (auto f : om.faces()) {
    for (auto v : om.fv_range(f)) mesh.face_indices.push_back(static_cast<std::uint32_t>(v.idx()));
    mesh.face_offsets.push_back(static_cast<std::uint32_t>(mesh.face_indices.size()));
  }
  return mesh;
}

/// Positions (xyz) of the vertices of `mesh` after `levels` steps of an OpenMesh uniform
/// subdivider (e.g. OpenMesh::Subdivider::Uniform::LoopT<OpenMeshTri, double>). Those subdividers
/// append new vertices and keep the old indices, so these are the first vertex_count() vertices.
template <typename OM, typename Subdivider>
std::vector<double> openmesh_subdivided_originals(const PolygonMesh& mesh, int levels) {
  OM om = to_openmesh<OM>(mesh);
  Subdivider subdivider;
  REQUIRE(subdivider(om, static_cast<std::size_t>(levels)));
  REQUIRE(om.n_vertices() > mesh.vertex_count());
  std::vector<double> positions;
  positions.reserve(mesh.positions.size());
  for (std::size_t v = 0; v < mesh.vertex_count(); ++v) {
    const auto& p = om.point(typename OM::VertexHandle(static_cast<int>(v)));
    positions.insert(positions.end(), {p[0], p[1], p[2]});
  }
  return positions;
}

}  // namespace meshlift::test
