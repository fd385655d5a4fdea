#pragma once
// PETSc glue for the matrix-free mass-constrained operator (solvers/mass_constrained_system.hpp):
// a MatShell applying J_F - σB and a PCShell applying the lower-triangular preconditioner P_σ^{-1}.
// Shared by the SNES steady-state solver and the shift-invert eigen solver.
#include <petscsnes.h>

#include "solvers/mass_constrained_system.hpp"
#include "solvers/petsc_database.hpp"  // PETSc calls and their options, used with the shells

namespace aggkit {

struct ShellOperator {
  MassConstrainedSystem* system = nullptr;
  double shift = 0.0;  // σ
};

// A sequential N×N MatShell for (J_F - σB); `op` must outlive it.
Mat make_shell_matrix(ShellOperator& op);
// Makes `pc` a PCShell applying P_σ^{-1} (or PCNONE when `enabled` is false).
void set_shell_preconditioner(PC pc, ShellOperator& op, bool enabled);

}  // namespace aggkit
