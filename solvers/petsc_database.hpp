#pragma once
// The PETSc options database of one solve and the checking of PETSc calls (defined in petsc_options.cpp;
// solvers/petsc_options.hpp says where options come from). Shared by the SNES steady-state solver, the
// shift-invert eigen solver and the check of a scene's petsc_options.
#include <petscsnes.h>

#include <string>
#include <vector>

namespace aggkit {

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

}  // namespace aggkit
