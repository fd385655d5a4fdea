#pragma once
// PETSc glue for the matrix-free mass-constrained operator (solvers/mass_constrained_system.hpp):
// a MatShell applying J_F - σB and a PCShell applying the lower-triangular preconditioner P_σ^{-1}.
// Shared by the SNES steady-state solver and the shift-invert eigen solver.
#include <petscsnes.h>

#include <string>
#include <vector>

#include "solvers/mass_constrained_system.hpp"

namespace aggkit {

struct ShellOperator {
  MassConstrainedSystem* system = nullptr;
  double shift = 0.0;  // σ
};

// The PETSc options database of one solve (solvers/petsc_options.hpp says where options come from).
// One options database (RAII): the entries of `options` ("-name value -flag ..."). Throws InputError
// with key `key` if the text is not a list of options (PETSc's message).
class PetscOptionDatabase {
 public:
  PetscOptionDatabase(const std::string& options, const std::string& key);
  ~PetscOptionDatabase();
  PetscOptionDatabase(const PetscOptionDatabase&) = delete;
  PetscOptionDatabase& operator=(const PetscOptionDatabase&) = delete;
  PetscOptions get() const { return options_; }
  // Entries no PETSc object read (misspelled or meant for another solver), as "-name value".
  std::vector<std::string> unused() const;

 private:
  PetscOptions options_ = nullptr;
};

// Makes `snes`, its line search, KSP and PC read `options` (PETSc 3.18 does not pass an object's database
// on to the line search it creates). Returns PETSc's error code.
PetscErrorCode use_options_database(SNES snes, PetscOptions options);

// PETSc's message for the last error (the one that returned `code`), for exceptions.
std::string petsc_error_text(PetscErrorCode code);

// Throws std::runtime_error naming `what` when a PETSc call failed.
void check_petsc(PetscErrorCode code, const char* what);

// A sequential N×N MatShell for (J_F - σB); `op` must outlive it.
Mat make_shell_matrix(ShellOperator& op);
// Makes `pc` a PCShell applying P_σ^{-1} (or PCNONE when `enabled` is false).
void set_shell_preconditioner(PC pc, ShellOperator& op, bool enabled);

}  // namespace aggkit
