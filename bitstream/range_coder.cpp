// Range coder: the out-of-line parts (byte output with carry propagation, decoder start-up).
// The arithmetic follows Igor Pavlov's LZMA range coder (LZMA SDK, LzmaEnc.c RangeEnc_ShiftLow
// and LzmaDec.c), with the changes listed in range_coder.h; FORMAT.md §7 is the specification.
#include "meshlift/range_coder.h"

namespace meshlift {

// Emits the top byte of low_. A byte cannot be written while a later carry could still
// increment it: the last byte below 0xFF is held in cache_, followed by cache_size_ - 1
// pending 0xFF bytes, until low_ shows whether the carry came (bit 32 set: cache_ + 1 and the
// 0xFFs wrap to 0x00) or can no longer come (top byte below 0xFF).
void RangeEncoder::shift_low() {
  if (static_cast<std::uint32_t>(low_) < 0xFF000000u || (low_ >> 32) != 0) {
    const auto carry = static_cast<std::uint8_t>(low_ >> 32);
    std::uint8_t pending = cache_;
    do {
      out_.push_back(static_cast<std::uint8_t>(pending + carry));
      pending = 0xFF;
    } while (--cache_size_ != 0);
    cache_ = static_cast<std::uint8_t>(low_ >> 24);
  }
  ++cache_size_;
  low_ = (low_ & 0x00FFFFFFu) << 8;
}

// Writes the cache and the four bytes of low_: the decoder, whose code register is 32 bits
// wide, reads exactly these and never past them, so the value low_ (in [low, low + range))
// decodes every symbol.
std::vector<std::uint8_t> RangeEncoder::finish() {
  for (int i = 0; i < 5; ++i) shift_low();
  std::vector<std::uint8_t> bytes = std::move(out_);
  *this = RangeEncoder();
  return bytes;
}

RangeDecoder::RangeDecoder(std::span<const std::uint8_t> bytes)
    : begin_(bytes.data()), next_(bytes.data()), end_(bytes.data() + bytes.size()) {
  if (bytes.size() < 5) {
    next_ = end_;
    status_ = Status::truncated;
    return;
  }
  // The first byte is the encoder's initial cache, always 0 (low + range <= 2^32 at the start,
  // so no carry reaches it); the next four fill the code register. code must be < range.
  code_ = 0;
  for (int i = 1; i < 5; ++i) code_ = (code_ << 8) | bytes[static_cast<std::size_t>(i)];
  next_ = begin_ + 5;
  if (bytes[0] != 0 || code_ == 0xFFFFFFFFu) {
    next_ = end_;
    status_ = Status::corrupt;
    return;
  }
  range_ = 0xFFFFFFFFu;
  status_ = Status::ok;
}

RangeDecoder::RangeDecoder(ByteSource& source) {
  std::span<const std::uint8_t> bytes = source.more(0);
  while (bytes.size() < 5) {
    const std::span<const std::uint8_t> longer = source.more(bytes.size());
    if (longer.size() <= bytes.size()) break;
    bytes = longer;
  }
  *this = RangeDecoder(bytes);
  source_ = &source;
}

bool RangeDecoder::wait_for_bytes() {
  const auto used = static_cast<std::size_t>(next_ - begin_), have = static_cast<std::size_t>(end_ - begin_);
  const std::span<const std::uint8_t> bytes = source_->more(have);
  if (bytes.size() <= have) return false;
  begin_ = bytes.data();
  next_ = begin_ + used;
  end_ = begin_ + bytes.size();
  return true;
}

}  // namespace meshlift
