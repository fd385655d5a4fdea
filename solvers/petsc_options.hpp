#pragma once
// The PETSc options of aggkit's SNES solves [Balay2022]: what PETSc users pass as "-snes_monitor
// -snes_rtol 1e-12 -ksp_type bcgs". Options come from the engine (scene key petsc_options) and from the
// command line (`aggkit run SCENE --out DIR -- OPTIONS`), both carried by the solve's own
// SteadyStateOptions (petsc_options, command_line_petsc_options); they are applied after aggkit's own
// settings, so they override them, the command line last (it overrides the scene). Nothing is global:
// each solve reads its options from a database of its own (solvers/petsc_database.hpp).
#include <string>

namespace aggkit {

// Checks `options` as the SNES solver will read them (SNESSetFromOptions on a Newton line-search SNES
// with GMRES): InputError with key `key`, the value and PETSc's message for bad syntax, an unknown
// type (-ksp_type foo) or a bad value (-snes_rtol abc). Initialises PETSc if needed.
void check_petsc_options(const std::string& options, const std::string& key);

}  // namespace aggkit
