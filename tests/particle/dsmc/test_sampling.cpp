// The pieces of the majorant sampler: size bins tile the sizes, the Fenwick tree selects by rank, and the
// corner bound of a bin pair is a true upper bound of every built-in kernel (quasi-convexity, see
// particle/dsmc/acceptance_rejection.hpp).
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <map>

#include "particle/dsmc/binned_population.hpp"
#include "particle/dsmc/fenwick.hpp"
#include "particle/dsmc/kernel_table.hpp"
#include "particle/dsmc/size_bins.hpp"
#include "solvers/kernels.hpp"

using namespace aggkit;

TEST_CASE("dsmc: size bins tile the sizes with hi/lo < 1.5") {
  for (std::size_t b = 0; b + 1 < 60; ++b) {
    CHECK(dsmc::bin_high(b) + 1 == dsmc::bin_low(b + 1));
    CHECK(double(dsmc::bin_high(b)) < 1.5 * double(dsmc::bin_low(b)));
  }
  for (std::uint64_t s : {1ULL, 2ULL, 3ULL, 7ULL, 8ULL, 11ULL, 12ULL, 1000ULL, 123456789ULL, (1ULL << 40) + 5}) {
    const std::size_t b = dsmc::bin_of(s);
    CHECK(dsmc::bin_low(b) <= s);
    CHECK(s <= dsmc::bin_high(b));
  }
}

TEST_CASE("dsmc: Fenwick selection returns the size holding a given rank") {
  dsmc::Fenwick tree(10);
  const std::vector<std::uint64_t> counts{0, 3, 0, 0, 1, 0, 0, 0, 0, 0, 2};  // sizes 1..10
  for (std::uint64_t s = 1; s <= 10; ++s) tree.add(s, std::int64_t(counts[s]));
  const std::vector<std::uint64_t> expected{1, 1, 1, 4, 10, 10};
  for (std::uint64_t r = 0; r < expected.size(); ++r) CHECK(tree.select(r) == expected[r]);
  CHECK(tree.prefix(4) == 4);
  tree.scale(2);
  CHECK(tree.select(7) == 4);
}

TEST_CASE("dsmc: the corner bound of every bin pair bounds the kernel inside it") {
  for (const Kernel& kernel : {Kernel::ballistic(), Kernel::brownian(0.95), Kernel::brownian(0.3), Kernel::sum(),
                               Kernel::linear(0.5, 0.2), Kernel::generalized_product(0.4)}) {
    INFO(kernel.describe());
    double worst = 0.0;
    for (std::size_t b = 0; b < 24; ++b)
      for (std::size_t c = 0; c < 24; ++c) {
        const std::uint64_t bl = dsmc::bin_low(b), bh = dsmc::bin_high(b), cl = dsmc::bin_low(c), ch = dsmc::bin_high(c);
        const double bound = std::max({kernel(bl, cl), kernel(bl, ch), kernel(bh, cl), kernel(bh, ch)});
        // Every size pair in small bins, a grid of 17 × 17 in large ones.
        const std::uint64_t step_b = std::max<std::uint64_t>(1, (bh - bl) / 16), step_c = std::max<std::uint64_t>(1, (ch - cl) / 16);
        for (std::uint64_t i = bl; i <= bh; i += step_b)
          for (std::uint64_t j = cl; j <= ch; j += step_c) worst = std::max(worst, kernel(i, j) / bound);
      }
    CHECK(worst <= 1.0 + 1e-14);
  }
}

TEST_CASE("dsmc: a binned population picks, removes and doubles particles of both kinds") {
  dsmc::BinnedPopulation population(4);
  population.add(1, 1000);  // shattering-sized monomer counts are one bucket
  population.add(6, 1);     // bucketed? no: 6 > B = 4, stored individually
  population.add(7, 2);
  population.add(3, 5);
  CHECK(population.particles() == 1008);
  const std::size_t bin = dsmc::bin_of(6);  // sizes 6 and 7 share a bin
  CHECK(population.count(bin) == 3);
  std::vector<std::uint64_t> sizes;
  for (std::uint64_t r = 0; r < 3; ++r) sizes.push_back(population.pick(bin, r).size);
  std::sort(sizes.begin(), sizes.end());
  CHECK(sizes == std::vector<std::uint64_t>{6, 7, 7});
  population.remove(population.pick(bin, 2));
  population.remove(population.pick(dsmc::bin_of(1), 0));
  CHECK(population.particles() == 1006);
  population.duplicate();
  std::uint64_t mass = 0;
  population.for_each_group([&](std::uint64_t s, std::uint64_t n) { mass += s * n; });
  CHECK(mass == 2 * (999 + 15 + 13));  // 999 monomers, 5 trimers and two of {6, 7, 7}: 6 + 7
}

TEST_CASE("dsmc: the kernel table equals the kernel bit for bit, cutoff included, inside and beyond the table") {
  for (const bool cutoff : {false, true}) {
    const Kernel kernel = Kernel::ballistic();
    const dsmc::InteractionKernel direct(kernel, cutoff, Truncation::cutoff, 50);
    const dsmc::KernelTable table(direct);
    const std::uint64_t top = dsmc::KernelTable::sizes + 16;
    std::size_t zeros = 0;
    for (std::uint64_t i = 1; i <= top; ++i)
      for (std::uint64_t j = 1; j <= top; ++j) {
        INFO("cutoff " << cutoff << ", K(" << i << ", " << j << ")");
        REQUIRE(table(i, j) == direct(i, j));  // exact equality: the table holds the kernel's own values
        zeros += table(i, j) == 0.0;
      }
    CHECK((zeros > 0) == cutoff);  // the cutoff (i + j > 50) is in the table
  }
  // The rows of small sizes against large ones, both argument orders, up to and beyond their length; a kernel
  // that is not symmetric tells the orders apart.
  const Kernel skew = Kernel::user("skew", [](double i, double j) { return std::sqrt(i) + 2.0 * std::cbrt(j); });
  for (const Kernel& kernel : {Kernel::ballistic(), skew}) {
    const dsmc::InteractionKernel direct(kernel, false, Truncation::cutoff, 50);
    const dsmc::KernelTable table(direct);
    for (std::uint64_t i = 1; i <= dsmc::KernelTable::row_sizes + 2; ++i)
      for (std::uint64_t j = 1; j <= dsmc::KernelTable::row_length + 40; ++j) {
        INFO(kernel.name() << ": K(" << i << ", " << j << ")");
        REQUIRE(table(i, j) == direct(i, j));
        REQUIRE(table(j, i) == direct(j, i));
      }
  }
}

TEST_CASE("dsmc: a bin picks its bucketed particles in increasing size by rank, through adds, removals and doubling") {
  // Bucket limit 300: bins of 1 to 8 sizes (scanned), of 32 to 64 sizes (own trees) and [256, 383] cut at 300.
  dsmc::BinnedPopulation population(300);
  dsmc::Random random(5);
  std::map<std::uint64_t, std::uint64_t> counts;
  for (int i = 0; i < 3000; ++i) {
    const std::uint64_t size = 1 + random.below(i % 3 == 0 ? 400 : 120), copies = 1 + random.below(3);
    population.add(size, copies);
    counts[size] += copies;
  }
  const auto check_ranks = [&] {
    for (std::size_t b = 0; b < population.bins(); ++b) {
      std::vector<std::uint64_t> expected;  // the bin's bucketed sizes in increasing order, then the others
      for (const auto& [size, n] : counts)
        if (dsmc::bin_of(size) == b && size <= 300) expected.insert(expected.end(), n, size);
      REQUIRE(population.count(b) >= expected.size());
      for (std::uint64_t r = 0; r < expected.size(); ++r) {
        INFO("bin " << b << ", rank " << r);
        REQUIRE(population.pick(b, r).size == expected[r]);
        REQUIRE(population.pick(b, r).large_index == dsmc::BinnedPopulation::npos);
      }
    }
  };
  check_ranks();
  for (int i = 0; i < 2000; ++i) {  // removals at random ranks
    std::size_t b = 0;
    do b = random.below(population.bins()); while (population.count(b) == 0);
    const auto picked = population.pick(b, random.below(population.count(b)));
    population.remove(picked);
    if (--counts[picked.size] == 0) counts.erase(picked.size);
  }
  check_ranks();
  population.duplicate();
  for (auto& entry : counts) entry.second *= 2;
  check_ranks();
}
