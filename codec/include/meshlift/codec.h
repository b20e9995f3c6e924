// The meshlift codec: semi-regular mesh <-> embedded .mlz stream (bitstream/FORMAT.md).
// Every prefix of a stream decodes to a valid mesh, coarser or less precise.
#pragma once

#include <cstddef>
#include <cstdint>
#include <limits>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "meshlift/lifting.h"
#include "meshlift/status.h"

namespace meshlift {

struct EncodeOptions {
  Scheme scheme = Scheme::loop;
  /// Linear and butterfly only (Loop has its own update): the lifting's mean-preserving update
  /// step (docs/WAVELETS.md), which makes each coarser level a smoothed rather than a sampled
  /// version of the finer one, so that a prefix missing the finer details is closer to the surface.
  /// On by default: on the nine rate-distortion meshes, butterfly prefixes take 0.3-13 % fewer bits
  /// at equal PSNR (BD-rate against Draco 0.1-8.3 points better), for a butterfly decode about a
  /// third slower (docs/RESULTS.md, "The update step on by default").
  bool mean_preserving_update = true;
  /// Quantization step of the finest bit plane, as a power of two of the bounding-box diagonal:
  /// step = diagonal * 2^-precision_bits (in the normalized coefficient domain, see FORMAT.md).
  int precision_bits = 16;
  /// Geometry details in a local frame (normal, two tangents) of the coarser level instead of
  /// x, y, z (codec/local_frames.h); the tangential components get a step 2^tangent_shift times
  /// coarser. Remeshes place their details mostly along the normal, so this saves bits.
  bool local_frames = true;
  int tangent_shift = 2;
  /// Extra channels (SemiRegularMesh::channels) are quantized with a step of their value range
  /// (largest minus smallest value over all their components) times 2^-channel_precision_bits;
  /// a channel that is constant (or whose range is within 2^-30 of its largest magnitude: a
  /// constant carried through interpolation) gets 2^-channel_precision_bits.
  int channel_precision_bits = 12;
  /// Code the base coefficients' top planes first, predicted from their neighbours in the base
  /// (FORMAT.md §5.1): fewer bits at every rate above the base part's. Off: every plane of the
  /// base in the embedded bit planes, so the very first bytes already refine the whole base (for
  /// rate-distortion experiments: docs/RESULTS.md measures the difference).
  bool predict_base = true;
  /// Cut the embedded stream to at most this many bytes (whole file, headers included). Below
  /// the header and base mesh (the smallest stream that decodes), encode() throws MeshError.
  std::size_t max_bytes = std::numeric_limits<std::size_t>::max();
  /// Threads the encoder may use: 1 for the caller's alone, N >= 2 for independent stages side by
  /// side on 2 (docs/RESULTS.md), 0 for that on a machine with more than one core and a mesh of
  /// kConcurrentEncodeVertices or more (below, starting threads costs more than they save). The
  /// bytes never depend on it.
  unsigned threads = 0;
  static constexpr std::uint32_t kConcurrentEncodeVertices = 1u << 15;
};

/// The same mesh with its vertices and faces in the order a stream stores them: the base in the
/// traversal order of the connectivity coder (FORMAT.md §4), which makes a new base vertex cost
/// only its symbol, and every finer level renumbered to follow. Idempotent.
SemiRegularMesh canonical_order(const SemiRegularMesh& mesh);

/// Encodes the positions of a semi-regular mesh. decode() returns the vertices in
/// canonical_order(mesh), which is `mesh`'s own order when it is already canonical.
/// \throw MeshError if the mesh is unusable (positions of the wrong size, non-finite
/// coordinates, base vertices no face uses) or the precision cannot be met.
std::vector<std::uint8_t> encode(const SemiRegularMesh& mesh, const EncodeOptions& options);

/// What a decode may allocate, as multiples of the counts its header declares (whatever the
/// file's size): at most kDecodeBytesPerBaseFace per declared base face while the base
/// connectivity is decoded, then at most kDecodeBytesPerVertex per output element, max(V, F/2)
/// for the V vertices and F faces the header's base refines to (hierarchy, stencil tables,
/// coefficients, output mesh), on top of the input bytes themselves. The decoder checks both
/// products against DecodeLimits::max_memory_bytes before the allocations they bound;
/// tests/codec/test_hostile.cpp measures real decodes against them.
inline constexpr std::uint64_t kDecodeBytesPerBaseFace = 512;
inline constexpr std::uint64_t kDecodeBytesPerVertex = 256;
/// ... plus this much per output vertex for each component of an extra channel.
inline constexpr std::uint64_t kDecodeBytesPerChannelComponent = 32;

/// Caller-settable caps, checked against the header before anything is allocated.
/// The default memory budget of 4 GiB is the default cap of 2^24 output vertices times
/// kDecodeBytesPerVertex; raise both for larger meshes from trusted sources.
struct DecodeLimits {
  std::uint64_t max_vertices = std::uint64_t{1} << 24;   ///< output vertices (16.8 M)
  std::uint64_t max_base_vertices = std::uint64_t{1} << 22;
  std::uint64_t max_base_faces = std::uint64_t{1} << 23;
  /// Bytes a decode may allocate by the bounds above (kDecodeBytesPerBaseFace, kDecodeBytesPerVertex).
  std::uint64_t max_memory_bytes = std::uint64_t{4} << 30;
};

struct DecodeOptions {
  std::size_t max_bytes = std::numeric_limits<std::size_t>::max();  ///< read at most this prefix
  int max_level = -1;                                                 ///< stop synthesis at this level
  DecodeLimits limits;
  /// Threads the decoder may use: 1 for the caller's alone, N >= 2 for two (the output's faces
  /// made while the coefficients are decoded, each level's synthesis split between them), 0 for
  /// that on a machine with more than one core and an output of kConcurrentDecodeVertices or
  /// more. The decoded mesh and the status never depend on it (but for running out of memory:
  /// two threads hold the output's faces longer, docs/RESULTS.md "Decoding on two threads"). The
  /// streaming Decoder has a thread of its own for the coefficients besides these.
  unsigned threads = 0;
  static constexpr std::uint32_t kConcurrentDecodeVertices = 1u << 15;
};

struct DecodeResult {
  Status status = Status::ok;  ///< ok, or why nothing (or less) could be decoded
  std::string message;         ///< the specific element or offset, for the user
  TriangleMesh mesh;           ///< the best mesh the bytes allow (empty if status is an error)
  std::vector<VertexChannel> channels;  ///< the stream's extra channels, for mesh's vertices
  int level = 0;               ///< refinement level of `mesh`
  int levels = 0;              ///< levels in the stream
  int bit_plane = -1;          ///< lowest bit plane fully or partly decoded (-1: none)
  /// Base vertices whose top planes (the base part, FORMAT.md §5.1) have arrived, in label order:
  /// all of them once the bit planes begin. While fewer, the others are extrapolated from them
  /// (their predictions with zero residuals: a viewer may prefer to wait for all of them).
  std::uint32_t base_vertices_decoded = 0;
  std::size_t bytes_used = 0;  ///< bytes of the input the mesh reflects
  bool complete = false;       ///< the whole stream was decoded
};

/// Decodes a whole or truncated stream. Never throws on bad bytes: a numbered status instead.
DecodeResult decode(std::span<const std::uint8_t> bytes, const DecodeOptions& options = {});

/// decode(bytes, options) into `result`, whose arrays (the mesh's positions and faces, the
/// channels' values) lend their storage where it is large enough: for a caller that decodes again
/// and again (a viewer asking a Decoder for the mesh as bytes arrive) and keeps one result, so
/// that no decode after the first faults in fresh pages for its output (an output of millions of
/// vertices is over 100 MB). The same status and contents as decode(); the arrays may keep spare
/// capacity. On an error status the mesh and channels are empty; the mesh's storage is kept when
/// the failure came before the values were decoded (header, limits, base mesh), not when it came
/// during the decode (out of memory, a corrupt coefficient stream).
void decode_into(std::span<const std::uint8_t> bytes, const DecodeOptions& options, DecodeResult& result);

/// Streaming decode: push bytes as they arrive, ask for the best mesh at any moment. mesh()
/// returns what decode() of the bytes pushed so far returns (the same status and contents), but
/// without decoding those bytes again: once the header and base mesh are in, a thread of the
/// Decoder's own decodes the coefficient stream as it arrives and waits for more, and mesh()
/// dequantizes what it holds and synthesizes the mesh (a cost of the output's size, not of the
/// bytes received). Before that, after a malformed container, or where no thread can be started,
/// mesh() decodes the bytes again. One caller at a time: push() and mesh() are not to be called
/// concurrently on one Decoder. Movable, not copyable; a moved-from Decoder may only be destroyed
/// or assigned to. Destroying one whose thread waits for bytes ends the thread.
class Decoder {
 public:
  explicit Decoder(DecodeOptions options = {});
  ~Decoder();
  Decoder(Decoder&&) noexcept;
  Decoder& operator=(Decoder&&) noexcept;

  void push(std::span<const std::uint8_t> bytes);
  std::size_t bytes_received() const;
  /// The mesh decoded from everything pushed so far (the same as decode() of that prefix).
  DecodeResult mesh() const;
  /// The same into `result`, reusing its arrays' storage (decode_into): for a caller asking
  /// again and again.
  void mesh(DecodeResult& result) const;

 private:
  struct State;
  std::unique_ptr<State> state_;
};

/// How an extra channel is quantized (FORMAT.md §3): its step and the centre of each component.
struct ChannelQuantization {
  int components = 1;
  double step = 1.0;
  std::vector<double> center;
};

/// Facts from a stream's header, without decoding coefficients.
struct StreamInfo {
  Status status = Status::ok;
  std::string message;
  Scheme scheme = Scheme::loop;
  bool mean_preserving_update = false;
  int levels = 0;
  std::uint64_t base_vertices = 0, base_faces = 0, vertices = 0, faces = 0;
  double step = 0;  ///< quantization step of the finest plane (normalized domain)
  std::vector<double> level_weights;  ///< w_j: level j's coefficients are known within step / w_j
  int top_plane = 0;
  /// The base coefficients' planes base_plane..top_plane are coded first, predicted from their
  /// neighbours (FORMAT.md §5.1); top_plane + 1: not at all.
  int base_plane = 0;
  /// Bytes of the HEAD and BASE chunks (payloads: the header and the base connectivity).
  std::size_t header_and_connectivity_bytes = 0;
  /// Bytes of the coefficient stream the base part takes (the base positions' top planes),
  /// to within the range decoder's 4 bytes of lookahead; 0 without a base part, or if the file
  /// does not hold all of it.
  std::size_t base_part_bytes = 0;
  bool local_frames = false;
  int tangent_shift = 0;
  std::vector<ChannelQuantization> channels;
  bool colour = false;  ///< the first channel is the vertices' colour (FORMAT.md §3, flag bit 3)
  struct Chunk {
    std::string tag;
    std::size_t offset = 0, size = 0;
    bool complete = false;
  };
  std::vector<Chunk> chunks;
};
StreamInfo inspect(std::span<const std::uint8_t> bytes);

}  // namespace meshlift
