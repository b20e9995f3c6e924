// Any triangle mesh -> semi-regular mesh. See remesh.h.
#include "meshlift/remesh.h"

namespace meshlift {

RemeshResult remesh(const TriangleMesh& mesh, const RemeshOptions& options) {
  if (options.recognize) {
    if (auto recovered = recover_semi_regular(mesh)) {
      RemeshResult result{std::move(*recovered)};
      result.recognized = true;
      result.base_vertices = result.mesh.hierarchy.vertex_count(0);
      return result;
    }
  }
  throw MeshError("remeshing a mesh without subdivision connectivity: in progress");
}

}  // namespace meshlift
