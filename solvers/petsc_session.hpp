#pragma once
// PETSc lifetime for the steady-state and stability solvers. MPI may already be initialised by the
// caller (the MPI scan calls MPI_Init itself); PETSc then runs on MPI_COMM_SELF of each rank (every solve
// is serial) and does not finalise MPI.
namespace aggkit {

void ensure_petsc_initialized();  // PetscInitializeNoArguments once, if not yet initialised
void finalize_petsc();            // PetscFinalize if we initialised it; safe to call twice

}  // namespace aggkit
