// Refines a tetrahedron with Loop wavelets through the installed library and checks the round trip.
#include <meshlift/lifting.h>
#include <meshlift/validate.h>

#include <cmath>
#include <cstdio>

int main() {
  meshlift::TriangleMesh tetrahedron;
  tetrahedron.positions = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1};
  tetrahedron.triangles = {0, 2, 1, 0, 1, 3, 0, 3, 2, 1, 2, 3};
  if (!meshlift::first_problem_for_triangle_codec(meshlift::validate_mesh(tetrahedron)).empty()) return 1;
  const meshlift::SemiRegularMesh mesh = meshlift::refine_linear(tetrahedron, 3);
  const meshlift::WaveletTransform wavelet(mesh.hierarchy, {meshlift::Scheme::loop, false});
  std::vector<double> values = mesh.positions;
  wavelet.analyze(values);
  wavelet.synthesize(values);
  double error = 0;
  for (std::size_t i = 0; i < values.size(); ++i) error = std::fmax(error, std::fabs(values[i] - mesh.positions[i]));
  std::printf("consumer: %u vertices, round-trip error %.1e\n", mesh.hierarchy.vertex_count(3), error);
  return error < 1e-12 ? 0 : 1;
}
