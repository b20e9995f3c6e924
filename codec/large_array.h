// Filling the codec's large arrays (a level's connectivity, the stencil tables, the output faces:
// tens of MB for a few million vertices) costs more in page faults than in the writes themselves:
// one fault per 4 KiB page, about 2 us each on a virtual machine. An array about to be written
// whole is made resident by one system call instead (populate). Internal to codec/.
//
// No transparent huge pages: asking for them (MADV_HUGEPAGE) took 512 times fewer faults, and a
// decode run again in the same process was 5-8 % faster, but a process that decodes once got its
// huge pages from memory the hypervisor had taken back (this machine is a KVM guest that reports
// its free 8 MiB blocks to the host: page_reporting_order=11), and each one's first write waited
// for the host: `meshlift decode` of a 3.3 M-vertex file took 208-225 ms in half the runs and
// 479-555 ms in the others, 235-240 ms in every run without them (docs/RESULTS.md).
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#if defined(__linux__)
#include <sys/mman.h>
#endif

namespace meshlift {

/// Arrays smaller than this are left to fault their pages in one by one (they may come from the
/// heap, resident already: a system call would cost more than it saves).
inline constexpr std::size_t kPopulateArrayBytes = std::size_t{256} << 10;

/// Makes the pages inside [data, data + bytes) resident and writable in one system call
/// (MADV_POPULATE_WRITE, Linux 5.14), for storage about to be written whole: the kernel still
/// clears each page, but without a fault per page. Only a hint: where the kernel does not offer
/// it (kernels before 5.14, other systems) nothing changes.
inline void populate([[maybe_unused]] void* data, [[maybe_unused]] std::size_t bytes) {
#if defined(__linux__) && defined(MADV_POPULATE_WRITE)
  constexpr std::uintptr_t kPage = 4096;
  if (bytes < kPopulateArrayBytes) return;
  const auto address = reinterpret_cast<std::uintptr_t>(data);
  const std::uintptr_t begin = (address + kPage - 1) & ~(kPage - 1), end = (address + bytes) & ~(kPage - 1);
  if (end > begin) madvise(reinterpret_cast<void*>(begin), end - begin, MADV_POPULATE_WRITE);
#endif
}

/// v.assign(n, value), with the storage allocated exactly and made resident before it is first written.
template <class T>
void assign_large(std::vector<T>& v, std::size_t n, const T& value = T{}) {
  if (n > v.capacity()) {
    std::vector<T>().swap(v);
    v.reserve(n);
    populate(v.data(), n * sizeof(T));
  }
  v.assign(n, value);
}

/// v emptied, with room for n elements, made resident before it is first written: for an array filled
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
  populate(v.data(), n * sizeof(T));
}

}  // namespace meshlift
