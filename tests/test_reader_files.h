// Shared by the mesh-file reader tests (tests/remesh/test_*_reader.cpp): scratch files, the
// message read_mesh throws for some bytes, and a comparison with OpenMesh's own reader.
#pragma once

#include <OpenMesh/Core/IO/MeshIO.hh>
#include <OpenMesh/Core/Mesh/PolyMesh_ArrayKernelT.hh>
#include <catch2/catch.hpp>

#include <unistd.h>

#include <algorithm>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "meshlift/mesh_io.h"

namespace meshlift::test {

/// A directory of scratch files for one test case, removed afterwards.
struct Scratch {
  std::filesystem::path directory;
  explicit Scratch(const std::string& name)
      : directory(std::filesystem::temp_directory_path() / ("meshlift_reader_" + name + "_" + std::to_string(::getpid()))) {
    std::filesystem::create_directories(directory);
  }
  ~Scratch() {
    std::error_code ignored;
    std::filesystem::remove_all(directory, ignored);
  }
  Scratch(const Scratch&) = delete;
  Scratch& operator=(const Scratch&) = delete;
  std::string write(const std::string& name, const std::string& bytes) const {
    const std::string path = (directory / name).string();
    std::ofstream(path, std::ios::binary) << bytes;
    return path;
  }
};

/// The message read_mesh throws for `bytes` saved as bad.`extension`, without the "path: "
/// prefix (which it must start with); "no error" if the file reads.
inline std::string read_error(const Scratch& scratch, const std::string& extension, const std::string& bytes) {
  const std::string path = scratch.write("bad." + extension, bytes);
  try {
    read_mesh(path);
  } catch (const MeshIOError& e) {
    const std::string message = e.what();
    REQUIRE(message.rfind(path + ": ", 0) == 0);
    return message.substr(path.size() + 2);
  }
  return "no error";
}

/// Checks that `ours` (read_mesh of `path`) is what OpenMesh's reader makes of the file: the
/// same vertices (its points are floats: ours rounded to float must equal them) and the same
/// faces in order, each face's corners in turn (OpenMesh's walk may start at any corner).
inline void require_as_openmesh_reads(const PolygonMesh& ours, const std::string& path) {
  OpenMesh::PolyMesh_ArrayKernelT<> theirs;
  REQUIRE(OpenMesh::IO::read_mesh(theirs, path));
  REQUIRE(ours.vertex_count() == theirs.n_vertices());
  REQUIRE(ours.face_count() == theirs.n_faces());
  for (const auto v : theirs.vertices())
    for (int k = 0; k < 3; ++k)
      REQUIRE(static_cast<float>(ours.positions[3 * static_cast<std::size_t>(v.idx()) + k]) == theirs.point(v)[k]);
  auto from_smallest = [](std::vector<std::uint32_t> corners) {
    std::rotate(corners.begin(), std::min_element(corners.begin(), corners.end()), corners.end());
    return corners;
  };
  for (const auto f : theirs.faces()) {
    std::vector<std::uint32_t> corners;
    for (const auto v : theirs.fv_range(f)) corners.push_back(static_cast<std::uint32_t>(v.idx()));
    const std::size_t i = static_cast<std::size_t>(f.idx());
    REQUIRE(from_smallest({ours.face_indices.begin() + ours.face_offsets[i],
                           ours.face_indices.begin() + ours.face_offsets[i + 1]}) == from_smallest(corners));
  }
}

}  // namespace meshlift::test
