#include "solvers/low_rank.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <stdexcept>

namespace aggkit {

double separable_entry(const SeparableForm& form, std::size_t i, std::size_t j) {
  double sum = 0.0;
  for (std::size_t p = 0; p < form.rank(); ++p)
    for (std::size_t q = 0; q < form.rank(); ++q)
      if (form.coupling[p][q] != 0.0)
        sum += form.coupling[p][q] * form.features[p][i - 1] * form.features[q][j - 1];
  return sum;
}

namespace {

// Rows on which the error is measured (1-based sizes); all rows for small N.
std::vector<std::size_t> check_rows(std::size_t N) {
  std::vector<std::size_t> rows;
  if (N <= 2048) {
    for (std::size_t i = 1; i <= N; ++i) rows.push_back(i);
    return rows;
  }
  for (std::size_t i = 1; i <= 64; ++i) rows.push_back(i);
  std::uint64_t state = 0x9E3779B97F4A7C15ull;  // splitmix64: fixed, reproducible sample
  for (int r = 0; r < 64; ++r) {
    state += 0x9E3779B97F4A7C15ull;
    std::uint64_t z = state;
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    z ^= z >> 31;
    rows.push_back(65 + z % (N - 64));
  }
  rows.push_back(N);
  std::sort(rows.begin(), rows.end());
  rows.erase(std::unique(rows.begin(), rows.end()), rows.end());
  return rows;
}

}  // namespace

double separable_form_error(const SeparableForm& form,
                            const std::function<double(std::size_t, std::size_t)>& kernel,
                            std::size_t N, std::size_t* checked_entries) {
  const std::size_t R = form.rank();
  // Fold the coupling into the left factor once: K̃_ij = Σ_q (Σ_p C_pq φ_p(i)) φ_q(j).
  std::vector<double> left(R);
  double worst = 0.0;
  std::size_t count = 0;
  auto check = [&](std::size_t i, std::size_t j) {
    double approx = 0.0;
    for (std::size_t q = 0; q < R; ++q) approx += left[q] * form.features[q][j - 1];
    const double exact = kernel(i, j);
    worst = std::max(worst, std::abs(approx - exact) / std::abs(exact));
    ++count;
  };
  const auto rows = check_rows(N);
  for (std::size_t i : rows) {
    for (std::size_t q = 0; q < R; ++q) {
      left[q] = 0.0;
      for (std::size_t p = 0; p < R; ++p) left[q] += form.coupling[p][q] * form.features[p][i - 1];
    }
    for (std::size_t j = 1; j <= N; ++j) check(i, j);
  }
  if (N > 2048)  // the diagonal too (by symmetry the checked rows also cover those columns)
    for (std::size_t i = 1; i <= N; i += 7) {
      for (std::size_t q = 0; q < R; ++q) {
        left[q] = 0.0;
        for (std::size_t p = 0; p < R; ++p) left[q] += form.coupling[p][q] * form.features[p][i - 1];
      }
      check(i, i);
    }
  if (checked_entries) *checked_entries = count;
  return worst;
}

SeparableForm cross_approximation(const std::function<double(std::size_t, std::size_t)>& kernel,
                                  std::size_t N, double tolerance) {
  if (!(tolerance > 0.0)) throw std::invalid_argument("cross_approximation: tolerance must be > 0");
  // Smallest kernel value over the checked rows: the entry scale the relative tolerance refers to.
  double smallest = std::numeric_limits<double>::infinity();
  for (std::size_t i : check_rows(std::min<std::size_t>(N, 64)))
    for (std::size_t j = 1; j <= N; ++j) smallest = std::min(smallest, kernel(i, j));
  for (std::size_t i = 1; i <= N; i += std::max<std::size_t>(1, N / 256)) smallest = std::min(smallest, kernel(i, i));

  // ACA with partial pivoting: K ≈ Σ_r u_r v_r^T, residual rows/columns formed on the fly.
  std::vector<Eigen::VectorXd> U, V;
  std::vector<char> row_used(N + 1, 0);
  std::size_t pivot_row = 1;
  const std::size_t max_rank = std::min<std::size_t>(N, 400);
  int small_updates = 0, stalled = 0;
  double best_update = std::numeric_limits<double>::infinity();
  while (U.size() < max_rank) {
    row_used[pivot_row] = 1;
    Eigen::VectorXd row(N);
    for (std::size_t j = 1; j <= N; ++j) row[j - 1] = kernel(pivot_row, j);
    for (std::size_t r = 0; r < U.size(); ++r) row -= U[r][pivot_row - 1] * V[r];
    Eigen::Index jmax;
    const double pivot_abs = row.cwiseAbs().maxCoeff(&jmax);
    if (pivot_abs == 0.0) {
      auto next = std::find(row_used.begin() + 1, row_used.end(), 0);
      if (next == row_used.end()) break;
      pivot_row = std::size_t(next - row_used.begin());
      continue;
    }
    const std::size_t pivot_col = std::size_t(jmax) + 1;
    Eigen::VectorXd col(N);
    for (std::size_t i = 1; i <= N; ++i) col[i - 1] = kernel(i, pivot_col);
    for (std::size_t r = 0; r < U.size(); ++r) col -= V[r][pivot_col - 1] * U[r];
    Eigen::VectorXd v = row / row[jmax];
    U.push_back(col);
    V.push_back(v);
    // Stop when the rank-one update is below the tolerance on the smallest entry, twice in a row
    // (a single small update can be a lucky pivot).
    const double update = col.cwiseAbs().maxCoeff() * v.cwiseAbs().maxCoeff();
    small_updates = update <= 0.05 * tolerance * smallest ? small_updates + 1 : 0;
    if (small_updates >= 2) break;
    // A tolerance below the round-off floor (~1e-16 max K / min K) cannot be met: stop when the
    // updates have not decreased for 8 steps; the measured error below then reports what was reached.
    stalled = update < 0.5 * best_update ? 0 : stalled + 1;
    best_update = std::min(best_update, update);
    if (stalled >= 8) break;
    Eigen::Index imax = 0;
    double best = -1.0;
    for (std::size_t i = 1; i <= N; ++i)
      if (!row_used[i] && std::abs(col[i - 1]) > best) best = std::abs(col[i - 1]), imax = Eigen::Index(i - 1);
    if (best < 0.0) break;
    pivot_row = std::size_t(imax) + 1;
  }

  // Recompress the symmetrised approximation ½(U V^T + V U^T) = W M W^T, W = [U V]:
  // W = Q R, core S = R M R^T = Z Λ Z^T, features Q z_r with coupling diag(Λ).
  const Eigen::Index R = Eigen::Index(U.size());
  Eigen::MatrixXd W(N, 2 * R);
  for (Eigen::Index r = 0; r < R; ++r) W.col(r) = U[r], W.col(R + r) = V[r];
  Eigen::HouseholderQR<Eigen::MatrixXd> qr(W);
  const Eigen::Index m = std::min<Eigen::Index>(Eigen::Index(N), 2 * R);
  Eigen::MatrixXd Q = qr.householderQ() * Eigen::MatrixXd::Identity(Eigen::Index(N), m);
  Eigen::MatrixXd Rf = qr.matrixQR().topRows(m).triangularView<Eigen::Upper>();
  Eigen::MatrixXd M = Eigen::MatrixXd::Zero(2 * R, 2 * R);
  M.topRightCorner(R, R) = 0.5 * Eigen::MatrixXd::Identity(R, R);
  M.bottomLeftCorner(R, R) = 0.5 * Eigen::MatrixXd::Identity(R, R);
  Eigen::MatrixXd S = Rf * M * Rf.transpose();
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(0.5 * (S + S.transpose()));
  // Keep the eigenpairs whose dropped contribution |λ_r| max|w_r|^2, summed, stays well below the tolerance.
  std::vector<std::pair<double, Eigen::Index>> order;
  for (Eigen::Index r = 0; r < eig.eigenvalues().size(); ++r) {
    const Eigen::VectorXd w = Q * eig.eigenvectors().col(r);
    const double wmax = w.cwiseAbs().maxCoeff();
    order.emplace_back(std::abs(eig.eigenvalues()[r]) * wmax * wmax, r);
  }
  std::sort(order.begin(), order.end());
  double dropped = 0.0;
  std::size_t first_kept = 0;
  while (first_kept < order.size() && dropped + order[first_kept].first <= 0.02 * tolerance * smallest)
    dropped += order[first_kept++].first;

  SeparableForm form;
  form.exact = false;
  form.tolerance = tolerance;
  const std::size_t rank = order.size() - first_kept;
  form.coupling.assign(rank, std::vector<double>(rank, 0.0));
  for (std::size_t r = 0; r < rank; ++r) {
    const Eigen::Index e = order[order.size() - 1 - r].second;  // largest first
    const Eigen::VectorXd w = Q * eig.eigenvectors().col(e);
    form.features.emplace_back(w.data(), w.data() + N);
    form.coupling[r][r] = eig.eigenvalues()[e];
  }
  form.max_relative_error = separable_form_error(form, kernel, N, &form.checked_entries);
  return form;
}

}  // namespace aggkit
