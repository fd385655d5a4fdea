// Memory latency of this machine, the bound on the event-driven engines at large N (bench/results/log/ed-ballistic-aggregation.md,
// elastic gas): nanoseconds per load for one chain of dependent random loads (each address read from
// the previous line, as an event reads slot -> state -> cell table -> neighbours) and for 8 independent
// chains interleaved (what prefetching can reach), over arrays of 1 to 256 MiB of 64-byte lines, with the
// arrays in transparent huge pages (HugePageAllocator) and without.
//   bench_memory_latency [LOADS]   (default 2e7 loads per size)
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <numeric>
#include <random>
#include <vector>

#include "bench/figures.hpp"
#include "particle/common/huge_page_allocator.hpp"

namespace {

struct alignas(64) Line {
  std::size_t next;
};

template <class Lines>
void measure(Lines& lines, std::size_t loads, double& dependent_ns, double& interleaved_ns) {
  const std::size_t n = lines.size();
  std::vector<std::size_t> order(n);
  std::iota(order.begin(), order.end(), std::size_t(0));
  std::shuffle(order.begin(), order.end(), std::mt19937_64(1));
  for (std::size_t k = 0; k < n; ++k) lines[order[k]].next = order[(k + 1) % n];  // one cycle through all
  std::size_t at = order[0];
  auto start = std::chrono::steady_clock::now();
  for (std::size_t k = 0; k < loads; ++k) at = lines[at].next;
  dependent_ns = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count() / double(loads) * 1e9;
  std::size_t chain[8];
  for (int c = 0; c < 8; ++c) chain[c] = order[std::size_t(c) * n / 8];
  start = std::chrono::steady_clock::now();
  for (std::size_t k = 0; k < loads / 8; ++k)
    for (std::size_t& c : chain) c = lines[c].next;
  interleaved_ns = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count() / double(loads) * 1e9;
  if (at + chain[0] == std::size_t(-1)) std::puts("");  // keeps the loads
}

}  // namespace

int main(int argc, char** argv) {
  const std::size_t loads = argc > 1 ? std::size_t(std::atof(argv[1])) : std::size_t(20'000'000);
  const aggkit::bench::Figures figures("memory_latency", argc, argv);
  std::printf("# ns per random 64-byte load: one dependent chain / 8 interleaved chains\n");
  std::printf("%8s %14s %14s %14s %14s\n", "MiB", "dep_4k", "inter_4k", "dep_huge", "inter_huge");
  for (std::size_t mib : {1, 4, 16, 64, 256}) {
    const std::size_t n = (mib << 20) / sizeof(Line);
    double d4 = 0, i4 = 0, dh = 0, ih = 0;
    {
      std::vector<Line> lines(n);  // plain heap: small pages where THP is in madvise mode (as here)
      measure(lines, loads, d4, i4);
    }
    {
      std::vector<Line, aggkit::HugePageAllocator<Line>> lines(n);
      measure(lines, loads, dh, ih);
    }
    std::printf("%8zu %14.1f %14.1f %14.1f %14.1f\n", mib, d4, i4, dh, ih);
    figures.add(std::to_string(mib) + " MiB", "dependent_load_ns", d4, "ns");
    figures.add(std::to_string(mib) + " MiB", "interleaved_load_ns", i4, "ns");
  }
}
