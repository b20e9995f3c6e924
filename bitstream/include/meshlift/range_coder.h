// Adaptive binary range coder (LZMA-style carry-propagating encoder, 32-bit range) whose decoder
// knows exactly which of its symbols the available bytes determine: a stream cut at any byte
// decodes to a prefix of the encoded symbols. Knows bits only; the exact arithmetic is specified
// as decoder pseudo-code in bitstream/FORMAT.md §7, and the two classes below mirror it.
//
// Choices (frozen by format version 2, unchanged in 3; version 1 had kCountMax = 63 and no
// per-model count_max):
//  - probabilities are 15-bit (kProbOne = 2^15) and held in [kProbMin, kProbMax] =
//    [128, 32640], so one byte of normalization always restores range >= 2^24 and the
//    cheapest bit costs log2(256/255) = 0.0056 bits;
//  - adaptation is count-based: a model's first updates move fast (shift 1, 2, 2, 3, ...,
//    about 1/(n+1), like a frequency count) and settle at shift 5 after 15 updates (a window
//    of ~32 bits). At a stationary p = 0.05 this costs ~4 % above the entropy (shift 7 after
//    63 updates, version 1's: ~1.4 %; tests/bitstream/test_range_coder.cpp prints the figure),
//    but the coefficient coder's statistics drift along its lists (across the surface): the
//    faster window codes remeshed meshes in 2-3 % fewer bits at equal error (docs/RESULTS.md);
//  - both sides normalize *before* each decision, so the decoder reads exactly the bytes the
//    encoder wrote and can tell whether a decision used a byte that is not there.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "meshlift/status.h"

namespace meshlift {

namespace range_coder {
inline constexpr int kProbBits = 15;
inline constexpr std::uint32_t kProbOne = std::uint32_t{1} << kProbBits;
inline constexpr std::uint32_t kProbMin = 128;
inline constexpr std::uint32_t kProbMax = kProbOne - kProbMin;
inline constexpr std::uint16_t kHalf = kProbOne / 2;
inline constexpr std::uint32_t kTop = std::uint32_t{1} << 24;  ///< normalize when range < kTop
inline constexpr std::uint8_t kCountMax = 15;                    ///< update count saturates here
inline constexpr int kMaxDirectBits = 32;
/// Adaptation shift for a model updated `count` times: 1 + floor(log2(count + 1)), in [1, 5].
inline constexpr std::array<std::uint8_t, kCountMax + 1> kShiftForCount = [] {
  std::array<std::uint8_t, kCountMax + 1> shifts{};
  for (int count = 0; count <= kCountMax; ++count) {
    int shift = 1;
    while ((count + 1) >> shift) ++shift;
    shifts[static_cast<std::size_t>(count)] = static_cast<std::uint8_t>(shift);
  }
  return shifts;
}();
}  // namespace range_coder

/// Adaptive probability that the next bit is 0, in units of 2^-15. Encoder and decoder must
/// start from equal models (default-constructed) and feed them the same bits in the same order.
struct BitModel {
  std::uint16_t p = range_coder::kHalf;  ///< P(bit == 0) * 2^15, always in [kProbMin, kProbMax]
  std::uint8_t count = 0;                ///< updates so far, saturating at count_max
  /// Where count saturates, so the shift the model settles at: kCountMax (shift 5), or less
  /// for a model whose statistics drift faster (FORMAT.md §7.3 says which). Must be <= kCountMax
  /// (it indexes kShiftForCount; set it only from constants checked so).
  std::uint8_t count_max = range_coder::kCountMax;

  /// The adaptation rule (FORMAT.md §7.3), shared by encoder and decoder so they cannot drift:
  /// bit 0: p += (kProbMax - p) >> shift;  bit 1: p -= (p - kProbMin) >> shift.
  /// Without a branch on `bit` (0 or 1): the coefficient coder's refinement bits are close to
  /// equiprobable, and a mispredicted branch per bit would cost more than the arithmetic.
  void update(int bit) {
    const int shift = range_coder::kShiftForCount[count];
    count = static_cast<std::uint8_t>(count + (count < count_max));
    const std::uint32_t one = 0u - static_cast<std::uint32_t>(bit);  // all ones if bit == 1
    const std::uint32_t up = (range_coder::kProbMax - p) >> shift, down = (p - range_coder::kProbMin) >> shift;
    p = static_cast<std::uint16_t>(p + (up & ~one) - (down & one));
  }
};

/// Writes bits into a range-coded byte stream. Not for untrusted input (there is none); may
/// throw std::bad_alloc like any std::vector.
class RangeEncoder {
 public:
  /// Codes `bit` (0 or nonzero = 1) with the probability in `model`, then adapts `model`.
  void encode(BitModel& model, int bit) {
    normalize();
    const std::uint32_t bound = (range_ >> range_coder::kProbBits) * model.p;
    const int b = bit != 0;
    const std::uint32_t one = 0u - static_cast<std::uint32_t>(b);  // all ones if b == 1
    low_ += bound & one;
    range_ = bound ^ ((bound ^ (range_ - bound)) & one);  // bound if b == 0, else range_ - bound
    model.update(b);
  }

  /// Codes the low `bits` bits of `value`, most significant first, each with probability 1/2.
  /// \pre 0 <= bits <= 32 (other counts are clamped to that range).
  void encode_direct(std::uint32_t value, int bits) {
    bits = bits < 0 ? 0 : (bits > range_coder::kMaxDirectBits ? range_coder::kMaxDirectBits : bits);
    for (int i = bits - 1; i >= 0; --i) {
      normalize();
      range_ >>= 1;
      low_ += range_ & (0u - ((value >> i) & 1u));  // branch-free: signs are close to equiprobable
    }
  }

  /// Flushes and returns the stream. The encoder is reset to its initial state afterwards.
  std::vector<std::uint8_t> finish();

  /// Size that finish() would return if called now: the exact cost of everything coded so far.
  std::size_t bytes_so_far() const { return out_.size() + static_cast<std::size_t>(cache_size_) + 4; }

  /// Bytes emitted so far: the first bytes_final() bytes of finish()'s stream, whatever is coded
  /// after (a carry reaches only the bytes still held back, the cache and its run of 0xFF).
  std::size_t bytes_final() const { return out_.size(); }

 private:
  void normalize() {
    if (range_ < range_coder::kTop) {
      range_ <<= 8;
      shift_low();
    }
  }
  void shift_low();

  std::uint64_t low_ = 0;  ///< 32 bits of interval start plus a carry in bit 32
  std::uint32_t range_ = 0xFFFFFFFFu;
  std::uint8_t cache_ = 0;           ///< last byte not yet written (a carry may still change it)
  std::uint64_t cache_size_ = 1;     ///< cache_ plus the 0xFF bytes pending behind it
  std::vector<std::uint8_t> out_;
};

/// Bytes that go on arriving while a RangeDecoder reads them (a streaming decode on a thread of
/// its own, codec/decoder.cpp): the decoder asks for more when it reaches the end of what it holds,
/// so that it stops exactly where a decoder of the bytes so far would stop, and goes on from there.
class ByteSource {
 public:
  /// Waits until more than `have` bytes have arrived, or until no more will come. Returns every
  /// byte so far (the first `have` as before; the span may have moved), or a span of `have` bytes
  /// or fewer when no more will come.
  virtual std::span<const std::uint8_t> more(std::size_t have) = 0;

 protected:
  ~ByteSource() = default;
};

/// Reads a range-coded stream. Safe on any input: never reads outside `bytes`, never throws,
/// never allocates.
///
/// Contract (the prefix property): call decode()/decode_direct() with the same sequence of
/// models and bit counts as the encoder and check exhausted() after each call. Every symbol
/// decoded while exhausted() was false after the call is identical to the encoder's. The first
/// call whose decision would need a byte past the end of `bytes` sets exhausted(), and that
/// symbol and all later ones are not trustworthy: decode() then returns 0 and
/// decode_direct() returns the bits decoded before the end with the rest zero, without
/// consuming input or updating models. So a stream cut after n bytes yields a prefix of the
/// symbols, and the prefix never shrinks as n grows; the whole stream yields every symbol.
///
/// A stream shorter than the 5 initial bytes is exhausted from the start (status() ==
/// truncated). A first byte other than 0 (the encoder always writes 0) or an impossible
/// initial code makes status() == corrupt, also exhausted from the start. Other corruption
/// cannot be detected here: the symbols are then merely wrong, which is what chunk checksums
/// are for.
class RangeDecoder {
 public:
  RangeDecoder() = default;  ///< an empty stream: exhausted, status() == truncated
  explicit RangeDecoder(std::span<const std::uint8_t> bytes);
  /// Reads from `source`, waiting in it whenever a decision needs a byte that has not arrived
  /// (first for the 5 initial bytes). The symbols are those of the span decoder over the bytes that
  /// arrive; it is exhausted only once `source` says no more will come. `source` must outlive it,
  /// and what its more() throws passes through the decoder's calls.
  explicit RangeDecoder(ByteSource& source);

  int decode(BitModel& model) {
    const int bit = try_decode(model);
    return bit < 0 ? 0 : bit;
  }

  /// decode() and exhausted() in one: the bit, or -1 if this decision is the one that found the
  /// input exhausted (or it already was). Branch-free apart from normalization, so that the
  /// caller's code decides whether a branch on the bit is worth its mispredictions.
  int try_decode(BitModel& model) {
    if (range_ < range_coder::kTop && !refill()) return -1;
    const std::uint32_t bound = (range_ >> range_coder::kProbBits) * model.p;
    const int bit = code_ >= bound;
    const std::uint32_t one = 0u - static_cast<std::uint32_t>(bit);  // all ones if bit == 1
    code_ -= bound & one;
    range_ = bound ^ ((bound ^ (range_ - bound)) & one);  // bound if bit == 0, else range_ - bound
    model.update(bit);
    return bit;
  }

  /// Decodes `bits` equiprobable bits, most significant first. \pre 0 <= bits <= 32 (clamped).
  std::uint32_t decode_direct(int bits) {
    bits = bits < 0 ? 0 : (bits > range_coder::kMaxDirectBits ? range_coder::kMaxDirectBits : bits);
    std::uint32_t value = 0;
    for (int i = bits - 1; i >= 0; --i) {
      if (range_ < range_coder::kTop && !refill()) {
        return static_cast<std::uint32_t>(std::uint64_t{value} << (i + 1));
      }
      range_ >>= 1;
      std::uint32_t bit = 0;
      if (code_ >= range_) {
        code_ -= range_;
        bit = 1;
      }
      value = (value << 1) | bit;
    }
    return value;
  }

  /// True once a decision needed a byte the input does not have (or the input is unusable);
  /// the symbol of that call and all later ones are not trustworthy.
  bool exhausted() const { return status_ != Status::ok; }
  /// ok while not exhausted; truncated when the input ran out; corrupt for a bad first byte.
  Status status() const { return status_; }
  /// Bytes of the input consumed so far (at most its size).
  std::size_t position() const { return static_cast<std::size_t>(next_ - begin_); }

 private:
  /// One normalization step: shifts in the next byte, or marks the stream exhausted.
  bool refill() {
    if (next_ == end_ && !(source_ != nullptr && status_ == Status::ok && wait_for_bytes())) {
      if (status_ == Status::ok) status_ = Status::truncated;
      range_ = 0;  // keeps every later call on this slow path
      return false;
    }
    range_ <<= 8;
    code_ = (code_ << 8) | *next_++;
    return true;
  }

  /// Asks source_ for more bytes; false if none will come.
  bool wait_for_bytes();

  ByteSource* source_ = nullptr;
  const std::uint8_t* begin_ = nullptr;
  const std::uint8_t* next_ = nullptr;
  const std::uint8_t* end_ = nullptr;
  std::uint32_t range_ = 0;
  std::uint32_t code_ = 0;
  Status status_ = Status::truncated;
};

}  // namespace meshlift
