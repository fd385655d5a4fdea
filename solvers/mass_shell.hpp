#pragma once
// The Jacobian ∂f/∂n on the mass shell as a dense matrix (solvers/stability.hpp): the unknowns are the
// classes below the mass row m (solvers/mass_constrained_system.hpp); class m carries what keeps the mass,
// v_m = -Σ_{k<m} x_k v_k / x_m, and the pinned classes above it stay 0.
#include <Eigen/Core>
#include <cstddef>
#include <span>

#include "solvers/discretisation.hpp"

namespace aggkit {

// A = J_{<m,<m} + J_{<m,m} t^T, t_k = -x_k / x_m, at the state n.
Eigen::MatrixXd mass_shell_jacobian(const Discretisation& grid, std::span<const double> n, std::size_t m);

}  // namespace aggkit
