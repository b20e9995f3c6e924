#include "stream_header.h"

#include <bit>
#include <cmath>
#include <cstdio>
#include <limits>
#include <string>

#include "base_values.h"
#include "meshlift/byte_io.h"
#include "zerotree_coder.h"

namespace meshlift {
namespace {
constexpr std::uint8_t kFlagUpdate = 1;
constexpr std::uint8_t kFlagLocalFrames = 2;
constexpr std::uint8_t kFlagChannels = 4;
constexpr std::uint8_t kFlagColour = 8;
constexpr std::uint8_t kKnownFlags = kFlagUpdate | kFlagLocalFrames | kFlagChannels | kFlagColour;
constexpr int kMaxTangentShift = 16;
constexpr int kMaxChannels = 4;
}  // namespace

double header_float(double x, const char* what, bool positive) {
  const double rounded = static_cast<double>(static_cast<float>(x));
  if (!std::isfinite(rounded) || (positive && !(rounded >= std::numeric_limits<float>::min()))) {
    char value[32];
    std::snprintf(value, sizeof value, "%g", x);
    throw MeshError(std::string("encode: the ") + what + " (" + value +
                    ") is outside the range of the header's floats (FORMAT.md §3): coordinates up to 3.4e38 in magnitude");
  }
  return rounded;
}

int StreamHeader::components() const {
  int k = zerotree::kGeometryComponents;
  for (const ChannelQuantization& c : channels) k += c.components;
  return k;
}

double StreamHeader::component_step(int c, int level) const {
  if (c < zerotree::kGeometryComponents) return c > 0 && level > 0 && local_frames ? std::ldexp(step, tangent_shift) : step;
  c -= zerotree::kGeometryComponents;
  for (const ChannelQuantization& channel : channels) {
    if (c < channel.components) return channel.step;
    c -= channel.components;
  }
  return step;  // not reached for c < components()
}

// Layout (FORMAT.md §3): u8 scheme, u8 flags, u8 levels, u8 top_plane + 1, u8 base_plane, varint base vertices,
// varint base faces, f64 step, 3 x f32 center, (levels + 1) x f32 level weights; if flag bit 1,
// u8 tangent_shift; if flag bit 2, u8 channel count, then per channel u8 components, f64 step,
// components x f32 center. The f32 values are doubles that the encoder has rounded to float
// (header_float), so writing them as floats loses nothing; the steps stay doubles (a mesh near
// the smallest floats has steps below them).
std::vector<std::uint8_t> StreamHeader::write() const {
  ByteWriter w;
  w.u8(static_cast<std::uint8_t>(scheme));
  w.u8(static_cast<std::uint8_t>((mean_preserving_update ? kFlagUpdate : 0) | (local_frames ? kFlagLocalFrames : 0) |
                                 (channels.empty() ? 0 : kFlagChannels) | (colour ? kFlagColour : 0)));
  w.u8(static_cast<std::uint8_t>(levels));
  w.u8(static_cast<std::uint8_t>(top_plane + 1));
  w.u8(static_cast<std::uint8_t>(base_plane));
  w.varint(base_vertices);
  w.varint(base_faces);
  auto f32 = [&w](double x) { w.u32(std::bit_cast<std::uint32_t>(static_cast<float>(x))); };
  w.u64(std::bit_cast<std::uint64_t>(step));
  for (double c : center) f32(c);
  for (double weight : level_weights) f32(weight);
  if (local_frames) w.u8(static_cast<std::uint8_t>(tangent_shift));
  if (!channels.empty()) {
    w.u8(static_cast<std::uint8_t>(channels.size()));
    for (const ChannelQuantization& c : channels) {
      w.u8(static_cast<std::uint8_t>(c.components));
      w.u64(std::bit_cast<std::uint64_t>(c.step));
      for (double x : c.center) f32(x);
    }
  }
  return w.take();
}

Status StreamHeader::read(std::span<const std::uint8_t> payload, const DecodeLimits& limits, std::string& message) {
  ByteReader r(payload);
  std::uint8_t scheme_byte = 0, flags = 0, levels_byte = 0, plane_byte = 0, base_plane_byte = 0;
  std::uint64_t vertices = 0, faces = 0;
  r.u8(scheme_byte);
  r.u8(flags);
  r.u8(levels_byte);
  r.u8(plane_byte);
  r.u8(base_plane_byte);
  r.varint(vertices);
  r.varint(faces);
  if (!r.ok()) {
    message = "header chunk too short";
    return Status::corrupt;
  }
  if (scheme_byte > static_cast<std::uint8_t>(Scheme::loop)) {
    message = "unknown wavelet scheme " + std::to_string(scheme_byte);
    return Status::corrupt;
  }
  if (flags & ~kKnownFlags) {
    message = "reserved header flag bits set";
    return Status::reserved_bits_set;
  }
  if (levels_byte > kMaxLevels) {
    message = "header claims " + std::to_string(levels_byte) + " levels (at most " + std::to_string(kMaxLevels) + ")";
    return Status::limit_exceeded;
  }
  if (plane_byte > 32) {
    message = "header claims bit plane " + std::to_string(plane_byte - 1);
    return Status::corrupt;
  }
  if (base_plane_byte > plane_byte || plane_byte - base_plane_byte > base_values::kMaxPlanes) {
    message = "header claims base plane " + std::to_string(base_plane_byte) + " with top plane " +
              std::to_string(static_cast<int>(plane_byte) - 1) + " (the base part covers at most " +
              std::to_string(base_values::kMaxPlanes) + " planes, none above the top)";
    return Status::corrupt;
  }
  if (vertices < 3 || faces < 1) {
    message = "header claims an empty base mesh";
    return Status::corrupt;
  }
  if (vertices > limits.max_base_vertices || faces > limits.max_base_faces) {
    message = "header claims " + std::to_string(vertices) + " base vertices and " + std::to_string(faces) +
              " base faces (limits " + std::to_string(limits.max_base_vertices) + ", " +
              std::to_string(limits.max_base_faces) + ")";
    return Status::limit_exceeded;
  }
  scheme = static_cast<Scheme>(scheme_byte);
  mean_preserving_update = flags & kFlagUpdate;
  local_frames = flags & kFlagLocalFrames;
  levels = levels_byte;
  top_plane = static_cast<int>(plane_byte) - 1;
  base_plane = base_plane_byte;
  base_vertices = static_cast<std::uint32_t>(vertices);
  base_faces = static_cast<std::uint32_t>(faces);
  auto read_double = [&](double& out) {
    std::uint64_t bits = 0;
    r.u64(bits);
    out = std::bit_cast<double>(bits);
  };
  auto read_float = [&](double& out) {
    std::uint32_t bits = 0;
    r.u32(bits);
    out = static_cast<double>(std::bit_cast<float>(bits));
  };
  read_double(step);
  for (double& c : center) read_float(c);
  level_weights.resize(static_cast<std::size_t>(levels) + 1);
  for (double& weight : level_weights) read_float(weight);
  tangent_shift = 0;
  if (local_frames) {
    std::uint8_t shift = 0;
    r.u8(shift);
    if (r.ok() && shift > kMaxTangentShift) {
      message = "header claims a tangent shift of " + std::to_string(shift) + " (at most " +
                std::to_string(kMaxTangentShift) + ")";
      return Status::corrupt;
    }
    tangent_shift = shift;
  }
  channels.clear();
  if (flags & kFlagChannels) {
    std::uint8_t count = 0;
    r.u8(count);
    if (r.ok() && (count < 1 || count > kMaxChannels)) {
      message = "header claims " + std::to_string(count) + " channels (1 to " + std::to_string(kMaxChannels) + ")";
      return Status::corrupt;
    }
    int total = 0;
    for (int i = 0; i < count && r.ok(); ++i) {
      std::uint8_t components = 0;
      r.u8(components);
      total += components;
      if (r.ok() && (components < 1 || total > zerotree::kMaxChannelComponents)) {
        message = "header channel " + std::to_string(i) + " has " + std::to_string(components) +
                  " components (all channels together: 1 to " + std::to_string(zerotree::kMaxChannelComponents) + ")";
        return Status::corrupt;
      }
      ChannelQuantization c;
      c.components = components;
      read_double(c.step);
      c.center.resize(components);
      for (double& x : c.center) read_float(x);
      channels.push_back(std::move(c));
    }
  }
  if (!r.ok()) {
    message = "header chunk too short for its quantization parameters";
    return Status::corrupt;
  }
  colour = flags & kFlagColour;
  if (colour && (channels.empty() || channels[0].components != 3)) {
    message = "header marks the first channel as the colour, but it is not a channel of 3 components";
    return Status::corrupt;
  }
  bool finite = std::isfinite(step) && step > 0;
  for (double c : center) finite = finite && std::isfinite(c);
  for (double weight : level_weights) finite = finite && std::isfinite(weight) && weight > 0;
  for (const ChannelQuantization& c : channels) {
    finite = finite && std::isfinite(c.step) && c.step > 0;
    for (double x : c.center) finite = finite && std::isfinite(x);
  }
  if (!finite) {
    message = "header holds a non-finite or non-positive quantization parameter";
    return Status::corrupt;
  }
  // Each reconstructed coefficient is at most 2^(top_plane + 1) steps_c / w_j, and synthesis sums
  // bounded combinations of them (stencil weights of absolute sum below 2, at most 12 levels):
  // parameters that could take a decode near the double range (hostile or damaged headers) are
  // refused here, so no decode can produce an infinite coordinate.
  constexpr double kMaxMagnitude = 1e250;
  bool bounded = true;
  for (double c : center) bounded = bounded && std::abs(c) <= kMaxMagnitude;
  for (const ChannelQuantization& channel : channels)
    for (double c : channel.center) bounded = bounded && std::abs(c) <= kMaxMagnitude;
  for (int j = 0; j <= levels && bounded; ++j)
    for (int c = 0; c < components(); ++c)
      bounded = bounded && std::ldexp(component_step(c, j), top_plane + 1) / level_weights[static_cast<std::size_t>(j)] <= kMaxMagnitude;
  if (!bounded) {
    message = "header quantization parameters exceed the range a decode can represent";
    return Status::corrupt;
  }
  if (r.remaining() != 0) {
    message = "header chunk has " + std::to_string(r.remaining()) + " unexpected trailing bytes";
    return Status::corrupt;
  }
  return Status::ok;
}

}  // namespace meshlift
