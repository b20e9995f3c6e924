// Filling the codec's large arrays (a level's connectivity, the stencil tables, the output faces:
// tens of MB for a few million vertices) costs more in page faults than in the writes themselves:
// one fault per 4 KiB page, about 2 us each on a virtual machine. Asking the kernel for
// transparent huge pages (2 MiB) on such an array before its first write takes 512 times fewer
// faults (64 MB: 37 ms -> 8 ms of system time measured here). The pages a huge page does not
// cover (an array's unaligned ends, arrays below 2 MiB) are made resident by one system call
// instead of a fault each (populate). Only hints: where the kernel does not offer them
// (transparent_hugepage "never", kernels before 5.14, other systems) nothing changes. Internal to
// codec/.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#if defined(__linux__)
#include <sys/mman.h>
#endif

namespace meshlift {

/// Arrays smaller than this keep ordinary pages. Only the whole 2 MiB pages inside an array are
/// advised, so an array written whole wastes nothing on them; one filled from its start (the
/// coefficient coder's lists) holds at most one partly used huge page, at its end.
inline constexpr std::size_t kHugePageArrayBytes = std::size_t{2} << 20;

/// Arrays smaller than this are left to fault their pages in one by one (they may come from the
/// heap, resident already: a system call would cost more than it saves).
inline constexpr std::size_t kPopulateArrayBytes = std::size_t{256} << 10;

/// Hints that the whole 2 MiB pages inside [data, data + bytes) be backed by huge pages.
inline void advise_huge_pages([[maybe_unused]] void* data, [[maybe_unused]] std::size_t bytes) {
#if defined(__linux__) && defined(MADV_HUGEPAGE)
  constexpr std::uintptr_t kHuge = std::uintptr_t{2} << 20;
  if (bytes < kHugePageArrayBytes) return;
  const auto address = reinterpret_cast<std::uintptr_t>(data);
  const std::uintptr_t begin = (address + kHuge - 1) & ~(kHuge - 1), end = (address + bytes) & ~(kHuge - 1);
  if (end > begin) madvise(reinterpret_cast<void*>(begin), end - begin, MADV_HUGEPAGE);
#endif
}

/// Makes the pages inside [data, data + bytes) resident and writable in one system call
/// (MADV_POPULATE_WRITE, Linux 5.14), for storage about to be written whole: the kernel still
/// clears each page, but without a fault per page. Only a hint, like advise_huge_pages.
inline void populate([[maybe_unused]] void* data, [[maybe_unused]] std::size_t bytes) {
#if defined(__linux__) && defined(MADV_POPULATE_WRITE)
  constexpr std::uintptr_t kPage = 4096;
  if (bytes < kPopulateArrayBytes) return;
  const auto address = reinterpret_cast<std::uintptr_t>(data);
  const std::uintptr_t begin = (address + kPage - 1) & ~(kPage - 1), end = (address + bytes) & ~(kPage - 1);
  if (end > begin) madvise(reinterpret_cast<void*>(begin), end - begin, MADV_POPULATE_WRITE);
#endif
}

/// v.assign(n, value), with the storage allocated exactly and advised before it is first written.
template <class T>
void assign_large(std::vector<T>& v, std::size_t n, const T& value = T{}) {
  if (n > v.capacity()) {
    std::vector<T>().swap(v);
    v.reserve(n);
    advise_huge_pages(v.data(), n * sizeof(T));
    populate(v.data(), n * sizeof(T));
  }
  v.assign(n, value);
}

/// v emptied, with room for n elements, advised before it is first written: for an array filled
/// by appending, which then writes each element once (assign_large writes it twice: the zeros,
/// then the value). Storage that already holds n elements is kept: an array a caller hands over
/// again and again (decode_into) has its pages resident.
template <class T>
void reserve_large(std::vector<T>& v, std::size_t n) {
  if (v.capacity() >= n) {
    v.clear();
    return;
  }
  std::vector<T>().swap(v);
  v.reserve(n);
  advise_huge_pages(v.data(), n * sizeof(T));
  populate(v.data(), n * sizeof(T));
}

}  // namespace meshlift
