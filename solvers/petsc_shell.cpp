#include "solvers/petsc_shell.hpp"

#include <stdexcept>


namespace aggkit {

namespace {

ShellOperator* context_of(Mat A) {
  void* ctx = nullptr;
  MatShellGetContext(A, &ctx);
  return static_cast<ShellOperator*>(ctx);
}

PetscErrorCode shell_mult(Mat A, Vec x, Vec y) {
  ShellOperator* op = context_of(A);
  const std::size_t N = op->system->size();
  const PetscScalar* xx = nullptr;
  PetscScalar* yy = nullptr;
  VecGetArrayRead(x, &xx);
  VecGetArray(y, &yy);
  PetscErrorCode code = 0;
  try {
    op->system->apply({xx, N}, {yy, N}, op->shift);
  } catch (...) {
    code = PETSC_ERR_LIB;
  }
  VecRestoreArray(y, &yy);
  VecRestoreArrayRead(x, &xx);
  return code;
}

PetscErrorCode shell_precondition(PC pc, Vec r, Vec z) {
  void* ctx = nullptr;
  PCShellGetContext(pc, &ctx);
  auto* op = static_cast<ShellOperator*>(ctx);
  const std::size_t N = op->system->size();
  const PetscScalar* rr = nullptr;
  PetscScalar* zz = nullptr;
  VecGetArrayRead(r, &rr);
  VecGetArray(z, &zz);
  op->system->precondition({rr, N}, {zz, N}, op->shift);
  VecRestoreArray(z, &zz);
  VecRestoreArrayRead(r, &rr);
  return 0;
}

}  // namespace

Mat make_shell_matrix(ShellOperator& op) {
  const PetscInt N = PetscInt(op.system->size());
  Mat A = nullptr;
  check_petsc(MatCreateShell(PETSC_COMM_SELF, N, N, N, N, &op, &A), "MatCreateShell");
  check_petsc(MatShellSetOperation(A, MATOP_MULT, (void (*)(void))shell_mult), "MatShellSetOperation");
  return A;
}

void set_shell_preconditioner(PC pc, ShellOperator& op, bool enabled) {
  if (!enabled) {
    check_petsc(PCSetType(pc, PCNONE), "PCSetType");
    return;
  }
  check_petsc(PCSetType(pc, PCSHELL), "PCSetType");
  check_petsc(PCShellSetContext(pc, &op), "PCShellSetContext");
  check_petsc(PCShellSetApply(pc, shell_precondition), "PCShellSetApply");
  check_petsc(PCShellSetName(pc, "monomer-attachment lower-triangular"), "PCShellSetName");
}

}  // namespace aggkit
