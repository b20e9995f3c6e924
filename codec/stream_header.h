// The HEAD chunk of a .mlz stream (bitstream/FORMAT.md §3): written and read side by side.
#pragma once

#include <array>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "meshlift/codec.h"

namespace meshlift {

/// x as the header stores the centres and level weights (FORMAT.md §3: floats), back in a
/// double. The encoder rounds them so before using them, so encoder and decoder use the same
/// values. \throw MeshError naming `what` if the float is infinite or, where `positive`, below
/// the smallest normal float (a weight must stay a positive number the decoder can scale by).
double header_float(double x, const char* what, bool positive);

struct StreamHeader {
  Scheme scheme = Scheme::loop;
  bool mean_preserving_update = false;
  int levels = 0;
  int top_plane = -1;  ///< highest bit plane coded, -1 if every coefficient is zero
  /// The base part (base_values.h) codes the base coefficients' planes [base_plane, top_plane];
  /// top_plane + 1: no base part.
  int base_plane = 0;
  std::uint32_t base_vertices = 0;
  std::uint32_t base_faces = 0;
  double step = 1.0;  ///< quantization step of plane 0, normalized coefficient domain
  std::array<double, 3> center{};
  std::vector<double> level_weights;  ///< levels + 1 synthesis-basis norms
  /// Geometry details in local frames (local_frames.h), tangential components quantized with
  /// step * 2^tangent_shift (flag bit 1).
  bool local_frames = false;
  int tangent_shift = 0;
  /// Extra per-vertex channels (flag bit 2).
  std::vector<ChannelQuantization> channels;
  /// The first channel is the vertices' colour, red, green, blue (flag bit 3).
  bool colour = false;

  /// Components coded per vertex: 3 + the channels' components.
  int components() const;
  /// Quantization step of component c of a vertex of `level` (geometry x/y/z, and the normal of
  /// a detail: step; the tangents of a detail (level > 0) in local frames: step * 2^tangent_shift;
  /// channel components: their channel's step).
  double component_step(int c, int level) const;

  std::vector<std::uint8_t> write() const;
  /// Parses and validates a HEAD payload against `limits`; on failure returns the status and
  /// sets `message` to the offending field.
  Status read(std::span<const std::uint8_t> payload, const DecodeLimits& limits, std::string& message);
};

}  // namespace meshlift
