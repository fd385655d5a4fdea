#pragma once
// Low-rank symmetric approximation of a kernel matrix K_ij (i, j = 1..N) without forming it, in O(N R)
// kernel evaluations and O(N R²) arithmetic:
//  1. a skeleton of sizes — every size up to 64, then a geometric grid of ratio 1.03 up to N — on which
//     the m × m kernel matrix (m ≈ 64 + 34 ln(N / 64)) is factorised by symmetric elimination with
//     Bunch–Parlett complete pivoting (1×1 or 2×2 pivots [BunchParlett1971]; the kernels of interest are
//     indefinite, like (i/j)^a + (j/i)^a) until its residual is below the tolerance;
//  2. the residual columns of the chosen pivots extended to all N sizes by the same elimination applied to
//     the kernel columns at the pivots (each size's row: R kernel values, a triangular substitution), in
//     long double: the elimination cancels terms up to max K / min K times larger than the smallest
//     entries, which in double arithmetic alone costs two digits at N = 2^17;
//  3. each pivot block diagonalised, so K̃ = Σ_r c_r w_r(i) w_r(j) with a diagonal coupling.
// The error is then measured against direct evaluation (separable_form_error). Should it exceed the
// tolerance (a kernel not smooth in log-size between skeleton points), the skeleton is refined (every size
// up to 256, ratio 1.005) and the factorisation repeated; the measured error is reported either way.
#include <cstddef>
#include <functional>

#include "solvers/separable_form.hpp"

namespace aggkit {

// `kernel(i, j)` must be symmetric and positive. The approximation aims at a maximum relative entry
// error ≤ tolerance; the achieved error is measured as separable_form_error describes.
SeparableForm cross_approximation(const std::function<double(std::size_t, std::size_t)>& kernel,
                                  std::size_t N, double tolerance);

// Max relative entry error of `form` against `kernel`: on every entry for N ≤ 256; otherwise on the
// full rows (by symmetry also the columns) of sizes 1..16 and N, 24 log-spaced and 24 pseudo-random
// sizes, and every 7th diagonal entry.
double separable_form_error(const SeparableForm& form,
                            const std::function<double(std::size_t, std::size_t)>& kernel,
                            std::size_t N, std::size_t* checked_entries = nullptr);

// K̃_ij from a separable form (1-based sizes).
double separable_entry(const SeparableForm& form, std::size_t i, std::size_t j);

}  // namespace aggkit
