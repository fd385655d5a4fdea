#pragma once
// Low-rank symmetric approximation of a kernel matrix K_ij (i, j = 1..N) without forming it:
// adaptive cross approximation with partial pivoting [Bebendorf2000],
// then recompression to K ≈ Σ_r c_r w_r(i) w_r(j) with orthonormal w_r (QR + symmetric eigensolve).
#include <cstddef>
#include <functional>

#include "solvers/kernels.hpp"

namespace aggkit {

// `kernel(i, j)` must be symmetric and positive. The approximation aims at a maximum relative entry
// error ≤ tolerance; the achieved error is measured on every entry for N ≤ 2048, otherwise on the
// rows and columns of the 64 smallest sizes, the diagonal, the last row and 64 pseudo-random rows.
SeparableForm cross_approximation(const std::function<double(std::size_t, std::size_t)>& kernel,
                                  std::size_t N, double tolerance);

// Max relative entry error of `form` against `kernel`, on the entry set described above.
double separable_form_error(const SeparableForm& form,
                            const std::function<double(std::size_t, std::size_t)>& kernel,
                            std::size_t N, std::size_t* checked_entries = nullptr);

// K̃_ij from a separable form (1-based sizes).
double separable_entry(const SeparableForm& form, std::size_t i, std::size_t j);

}  // namespace aggkit
