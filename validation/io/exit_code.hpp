#pragma once
// Exit status of `aggkit` (documented in `aggkit --help`).
namespace aggkit {

enum ExitCode : int {
  exit_pass = 0,            // every engine completed and every comparison is within its tolerance
  exit_failed = 1,          // a comparison exceeded its tolerance, or an engine failed during its run
  exit_bad_input = 2,       // bad scene, bad command line, unreadable scene, unwritable output folder
  exit_internal_error = 3,  // an unexpected error (a bug or a system failure): please report it
  exit_interrupted = 4,     // SIGTERM or SIGINT: the last checkpoint was written (aggkit run --resume DIR continues)
};

}  // namespace aggkit
