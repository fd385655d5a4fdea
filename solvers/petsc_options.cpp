#include "solvers/petsc_options.hpp"

#include <petscsnes.h>

#include <stdexcept>

#include "analysis/input_error.hpp"
#include "solvers/petsc_session.hpp"
#include "solvers/petsc_database.hpp"

namespace aggkit {

void check_petsc(PetscErrorCode code, const char* what) {
  if (code != 0)
    throw std::runtime_error(std::string("PETSc: ") + what + " failed with code " + std::to_string(code) + ": " +
                             petsc_error_text(code));
}

std::string petsc_error_text(PetscErrorCode code) {
  const char* text = nullptr;
  char* specific = nullptr;
  PetscErrorMessage(code, &text, &specific);
  std::string message = specific && *specific ? specific : "";
  if (text && *text) message += std::string(message.empty() ? "" : " (") + text + (message.empty() ? "" : ")");
  while (!message.empty() && (message.back() == '\n' || message.back() == ' ')) message.pop_back();
  return message.empty() ? "PETSc error code " + std::to_string(code) : message;
}

PetscOptionDatabase::PetscOptionDatabase(const std::string& options, const std::string& key) {
  const std::size_t first = options.find_first_not_of(" \t\n");
  if (first != std::string::npos && options[first] != '-')
    throw InputError(key, "\"" + options + "\"",
                     "PETSc options \"-name value -flag ...\" (the text must start with an option name such as -snes_rtol)");
  ensure_petsc_initialized();
  if (PetscOptionsCreate(&options_) != 0) throw std::runtime_error("PetscOptionsCreate failed");
  const PetscErrorCode code = PetscOptionsInsertString(options_, options.c_str());
  if (code != 0) {
    const std::string why = petsc_error_text(code);
    PetscOptionsDestroy(&options_);
    throw InputError(key, "\"" + options + "\"", "PETSc options (\"-name value -flag ...\"): " + why);
  }
}

PetscOptionDatabase::~PetscOptionDatabase() {
  if (options_) PetscOptionsDestroy(&options_);
}

std::vector<std::string> PetscOptionDatabase::unused() const {
  PetscInt count = 0;
  char** names = nullptr;
  char** values = nullptr;
  std::vector<std::string> left;
  if (PetscOptionsLeftGet(options_, &count, &names, &values) != 0) return left;
  for (PetscInt i = 0; i < count; ++i) {
    std::string entry = "-";
    entry += names[i];
    if (values[i]) entry.append(" ").append(values[i]);
    left.push_back(entry);
  }
  PetscOptionsLeftRestore(options_, &count, &names, &values);
  return left;
}

PetscErrorCode use_options_database(SNES snes, PetscOptions options) {
  SNESLineSearch line_search = nullptr;
  KSP ksp = nullptr;
  PC pc = nullptr;
  PetscErrorCode code = PetscObjectSetOptions(reinterpret_cast<PetscObject>(snes), options);
  if (code == 0) code = SNESGetLineSearch(snes, &line_search);
  if (code == 0) code = PetscObjectSetOptions(reinterpret_cast<PetscObject>(line_search), options);
  if (code == 0) code = SNESGetKSP(snes, &ksp);
  if (code == 0) code = PetscObjectSetOptions(reinterpret_cast<PetscObject>(ksp), options);
  if (code == 0) code = KSPGetPC(ksp, &pc);
  if (code == 0) code = PetscObjectSetOptions(reinterpret_cast<PetscObject>(pc), options);
  return code;
}

void check_petsc_options(const std::string& options, const std::string& key) {
  PetscOptionDatabase database(options, key);
  SNES snes = nullptr;
  PetscErrorCode code = SNESCreate(PETSC_COMM_SELF, &snes);
  if (code == 0) code = SNESSetType(snes, SNESNEWTONLS);
  KSP ksp = nullptr;
  PC pc = nullptr;
  SNESLineSearch line_search = nullptr;
  if (code == 0) code = SNESGetLineSearch(snes, &line_search);
  if (code == 0) code = SNESLineSearchSetType(line_search, SNESLINESEARCHBT);
  if (code == 0) code = SNESGetKSP(snes, &ksp);
  if (code == 0) code = KSPSetType(ksp, KSPGMRES);
  if (code == 0) code = KSPGetPC(ksp, &pc);
  if (code == 0) code = PCSetType(pc, PCSHELL);
  if (code == 0) code = use_options_database(snes, database.get());
  const std::string setup_failure = code != 0 ? petsc_error_text(code) : "";
  if (code == 0) code = SNESSetFromOptions(snes);
  const std::string why = code != 0 ? petsc_error_text(code) : "";
  if (snes) SNESDestroy(&snes);
  if (!setup_failure.empty()) throw std::runtime_error("PETSc: setting up the options check failed: " + setup_failure);
  if (code != 0) throw InputError(key, "\"" + options + "\"", "options SNES, KSP and PC accept: " + why);
}

}  // namespace aggkit
