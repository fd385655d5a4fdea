// The `aggkit` command line: parses arguments and calls the libraries.
//   [mpirun -np K] aggkit run SCENE --out DIR [--checkpoint-every 10m] [--quiet] [--no-plot] [-- PETSC_OPTIONS]
//   aggkit run --resume DIR [--quiet]
// (under mpirun the realizations of particle and DSMC engines are spread over the ranks, without checkpoints)
//   [mpirun -np K] aggkit scan SCENE --out DIR [--quiet] [--no-plot]
//   aggkit validate [--tier fast|full] [--out DIR] [--jobs K] [--quiet] [--no-plot] [--rerun] [SCENE ...]
//   [mpirun -np K] aggkit sweep SCENE --out DIR [--quiet] [--no-plot]
//   aggkit kernels
//   aggkit --version
// Exit status: 0 pass; 1 a comparison failed (or an engine failed); 2 bad input (bad scene or command
// line, unreadable scene, unwritable output folder, a checkpoint that cannot be continued); 3 an unexpected
// internal error; 4 stopped by SIGTERM or SIGINT after writing the last checkpoint.
#include <algorithm>
#include <cmath>
#include <exception>
#include <iostream>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "analysis/input_error.hpp"
#include "solvers/petsc_options.hpp"
#include "validation/engines/engine.hpp"
#include "validation/engines/rank_share.hpp"
#include "validation/io/exit_code.hpp"
#include "validation/harness/harness.hpp"
#include "validation/harness/output_folder.hpp"
#include "validation/harness/run_checkpoint.hpp"
#include "validation/scene/kernel_catalogue.hpp"
#include "validation/scan/scan.hpp"
#include "validation/runs/mpi_ranks.hpp"
#include "validation/scene/scene.hpp"
#include "validation/validate/validate.hpp"
#include "validation/sweep/sweep.hpp"
#include "validation/io/text.hpp"
#include "validation/io/version.hpp"

namespace {

const char* exit_status_help =
    "Exit status:\n"
    "  0  every engine completed and every comparison is within its tolerance\n"
    "  1  a comparison exceeded its tolerance, or an engine failed during its run\n"
    "  2  bad input: scene (key, value and what is allowed are named), command line, missing or\n"
    "     unreadable scene file, output folder that cannot be created or written\n"
    "  3  an unexpected internal error (please report it)\n"
    "  4  aggkit run stopped by SIGTERM or SIGINT after writing its last checkpoint (continue it with\n"
    "     aggkit run --resume DIR)\n";

std::string engine_help() {
  return aggkit::engines_help() + "\n" + aggkit::observables_help() + "\n" + exit_status_help;
}

struct RunArguments {
  std::string scene;
  std::string out;
  bool quiet = false;
  bool no_plot = false;
  bool force = false;
  std::string checkpoint_every;  // a duration: "600", "10m", "1.5h"
  std::string resume;            // the output folder of a run to continue
  std::string petsc_options;  // after `--`: PETSc options for the snes engines
};

// The PETSc options after `--` go to every snes engine of the scene (after the scene's petsc_options).
void use_petsc_options(aggkit::Scene& scene, const std::string& options) {
  if (options.empty()) return;
  const bool has_snes = std::any_of(scene.engines.begin(), scene.engines.end(),
                                    [](const aggkit::EngineSpec& e) { return e.name == "snes"; });
  if (!has_snes) {
    std::cerr << "aggkit: warning: the PETSc options after -- (" << options
              << ") are read by engine snes only, and this scene has none\n";
    return;
  }
  aggkit::check_petsc_options(options, "-- (PETSc options on the command line)");
  scene.command_line_petsc_options = options;
}

// A wall-time duration: seconds, or a number with the unit s, m, h or d ("10m", "1.5h").
double parse_duration(const std::string& text, const std::string& key) {
  const std::string allowed = "a duration > 0: seconds, or a number with s, m, h or d (600, 10m, 1.5h)";
  std::size_t used = 0;
  double value = 0;
  try {
    value = std::stod(text, &used);
  } catch (const std::exception&) {
    throw aggkit::InputError(key, "\"" + text + "\"", allowed);
  }
  const std::string unit = text.substr(used);
  const double scale = unit.empty() || unit == "s" ? 1 : unit == "m" ? 60 : unit == "h" ? 3600 : unit == "d" ? 86400 : 0;
  if (scale == 0 || !(value > 0) || !std::isfinite(value * scale)) throw aggkit::InputError(key, "\"" + text + "\"", allowed);
  return value * scale;
}

// Under mpirun (or srun) the particle and DSMC engines spread their realizations over the ranks: every rank
// reads the scene (a bad one ends every rank with exit status 2), rank 0 runs the scene and writes every
// output, the other ranks run their share of the realizations and end with rank 0's exit status.
int run(RunArguments arguments, std::optional<aggkit::MpiSession>& mpi, int* argc, char*** argv) {
  if (!aggkit::mpirun_variable().empty()) mpi.emplace(argc, argv);
  const aggkit::MpiRanks world;
  const aggkit::RankGroup* ranks = aggkit::shared_ranks(&world);
  const bool rank_zero = world.rank() == 0;
  aggkit::RunOptions options;
  std::optional<aggkit::Scene> scene;
  aggkit::gather_shares(ranks, [&] {  // every rank reads the run and its scene; one that cannot fails every rank
    if (!arguments.resume.empty()) {
      if (!arguments.scene.empty() || !arguments.out.empty() || !arguments.checkpoint_every.empty())
        throw aggkit::InputError("--resume", arguments.resume,
                                 "the folder of the run to continue, alone: its scene, --out and --checkpoint-every are "
                                 "those of the run (DIR/checkpoint/run.json)");
      const aggkit::CheckpointedRun run = aggkit::read_checkpointed_run(arguments.resume);
      const std::uint64_t now = aggkit::scene_fingerprint(run.scene, "--resume");
      if (now != run.fingerprint)
        throw aggkit::InputError("--resume", arguments.resume,
                                 "a run whose scene is unchanged: " + run.scene.string() +
                                     " changed since the checkpoint (its text's fingerprint differs); restore it, or "
                                     "start a new run");
      arguments.scene = run.scene.string();
      arguments.out = arguments.resume;
      arguments.no_plot = !run.plot;
      options.checkpoint_every = run.interval;
      options.resume = true;
    } else {
      if (arguments.scene.empty()) throw aggkit::InputError("scene", "(none)", "a scene file (or --resume DIR)");
      if (arguments.out.empty()) throw aggkit::InputError("--out", "(none)", "an output folder (or --resume DIR)");
      if (!arguments.checkpoint_every.empty())
        options.checkpoint_every = parse_duration(arguments.checkpoint_every, "--checkpoint-every");
      // Before the scene is read: a run refused for bad input must not leave an earlier run's summary behind.
      if (rank_zero) aggkit::OutputFolder(arguments.out).forget_summary();
    }
    scene.emplace(aggkit::load_scene(arguments.scene));
    options.scene_fingerprint = aggkit::scene_fingerprint(arguments.scene, "scene");
    return std::string();
  });
  if (!rank_zero) return aggkit::serve_realizations(*scene, *ranks);
  // Rank 0 ends the other ranks' service with its exit status, however the run ends.
  struct ServiceEnd {
    const aggkit::RankGroup* ranks;
    int code = aggkit::exit_internal_error;
    ~ServiceEnd() {
      if (ranks) aggkit::end_realization_service(*ranks, code);
    }
  } service{ranks};
  try {
    use_petsc_options(*scene, arguments.petsc_options);
    options.out = arguments.out;
    options.plot = !arguments.no_plot;
    options.force = arguments.force;
    options.scene_file = std::filesystem::absolute(arguments.scene);
    options.catch_signals = true;
    options.ranks = ranks;
    if (arguments.quiet) options.progress = nullptr;
    service.code = aggkit::run_scene(*scene, options).exit_code;
    return service.code;
  } catch (const aggkit::RunInterrupted& stop) {
    std::cerr << "aggkit: stopped by signal " << stop.signal << " after the last checkpoint; continue with: aggkit run --resume "
              << arguments.out << "\n";
    return service.code = aggkit::exit_interrupted;
  } catch (const aggkit::InputError&) {
    service.code = aggkit::exit_bad_input;
    throw;
  }
}

// MPI is initialised for the scan and the sweep (a singleton job without mpirun), and for a run under mpirun.
int scan(const RunArguments& arguments, int* argc, char*** argv) {
  aggkit::MpiSession mpi(argc, argv);
  const aggkit::ScanPlan plan = aggkit::load_scan_plan(arguments.scene);
  aggkit::ScanOptions options;
  options.out = arguments.out;
  options.plot = !arguments.no_plot;
  options.progress = arguments.quiet ? nullptr : &std::cerr;
  return aggkit::run_scan(plan, options).exit_code;
}

struct ValidateArguments {
  std::string tier = "fast";
  std::string out = "validation";
  long jobs = 1;
  bool quiet = false;
  bool no_plot = false;
  bool rerun = false;
  std::vector<std::string> scenes;
};

// Each scene runs in a child process of this very program (/proc/self/exe).
int validate(const ValidateArguments& arguments) {
  aggkit::ValidateOptions options;
  options.tier = aggkit::parse_tier(arguments.tier);
  if (arguments.jobs < 1 || arguments.jobs > 1024)
    throw aggkit::InputError("--jobs", std::to_string(arguments.jobs), "a number of child processes from 1 to 1024");
  options.jobs = std::size_t(arguments.jobs);
  options.out = arguments.out;
  options.scenes = arguments.scenes;
  options.plot = !arguments.no_plot;
  options.rerun = arguments.rerun;
  options.program = std::filesystem::read_symlink("/proc/self/exe");
  options.mpiexec = aggkit::default_mpiexec();
  options.progress = arguments.quiet ? nullptr : &std::cerr;
  options.table = &std::cout;
  return aggkit::run_validation(options).exit_code;
}

// The sweep, like the scan, runs under MPI (a singleton job without mpirun).
int sweep(const RunArguments& arguments, int* argc, char*** argv) {
  aggkit::MpiSession mpi(argc, argv);
  const aggkit::SweepPlan plan = aggkit::load_sweep_plan(arguments.scene);
  aggkit::SweepOptions options;
  options.out = arguments.out;
  options.plot = !arguments.no_plot;
  options.progress = arguments.quiet ? nullptr : &std::cerr;
  return aggkit::run_sweep(plan, options).exit_code;
}

// The subcommands: each declares its arguments and help on `app` and returns its parser.
CLI::App* add_run_command(CLI::App& app, RunArguments& arguments) {
  CLI::App* run_command = app.add_subcommand(
      "run", "run a scene and write its outputs, comparisons and report; MPI: mpirun -np K spreads the realizations");
  run_command->add_option("scene", arguments.scene, "scene file (TOML; see validation/scenes/)");
  run_command->add_option("--out,-o", arguments.out, "output folder (created if needed)");
  run_command->add_option("--checkpoint-every", arguments.checkpoint_every,
                          "write each engine's state to DIR/checkpoint/ this often (600, 10m, 1.5h; at output times); "
                          "SIGTERM/SIGINT write a last one and exit 4");
  run_command->add_option("--resume", arguments.resume, "continue the run in this folder from its last checkpoint");
  run_command->add_flag("--quiet,-q", arguments.quiet, "no progress lines on stderr");
  run_command->add_flag("--no-plot", arguments.no_plot, "do not draw report.png");
  run_command->add_flag("--force", arguments.force,
                        "write into a non-empty folder that no aggkit run wrote (files of other names are left alone)");
  run_command->footer("Under mpirun -np K the realizations of the particle engines and the runs of DSMC are spread over\n"
                      "the ranks (threads within each rank); rank 0 writes the outputs of a one-process run with the\n"
                      "same seeds. Checkpoints (--checkpoint-every, --resume) need one process.\n\n"
                      "PETSc options (-snes_monitor, -snes_rtol 1e-12, -ksp_type bcgs, ...) for the snes engines go "
                      "after --:\n  aggkit run SCENE --out DIR -- -snes_monitor\n\n" + engine_help());
  return run_command;
}

CLI::App* add_scan_command(CLI::App& app, RunArguments& scan_arguments) {
  CLI::App* scan_command = app.add_subcommand(
      "scan", "classify the oscillation regime over an (a, lambda) grid and locate lambda_crit(a); MPI: mpirun -np K");
  scan_command->add_option("scene", scan_arguments.scene, "scan scene (TOML with a [scan] section; see validation/scan/scan_plan.hpp)")
      ->required();
  scan_command->add_option("--out,-o", scan_arguments.out, "output folder (created if needed; a rerun resumes)")
      ->required();
  scan_command->add_flag("--quiet,-q", scan_arguments.quiet, "no progress lines on stderr");
  scan_command->add_flag("--no-plot", scan_arguments.no_plot, "do not draw phase_diagram.png");
  scan_command->footer(
      "Writes DIR/scan.csv (a,lambda,regime,period,amplitude,...), DIR/lambda_crit.csv (a,lambda_crit,...),\n"
      "DIR/phase_diagram.png, DIR/timing.csv, DIR/truncation_check.csv (if asked) and DIR/points/ (finished\n"
      "points: an interrupted scan resumes). Exit status 0: every point classified; 1: some runs failed;\n"
      "2: bad input.");
  return scan_command;
}

CLI::App* add_validate_command(CLI::App& app, ValidateArguments& validate_arguments) {
  CLI::App* validate_command = app.add_subcommand(
      "validate", "run every shipped scene (or those given) in parallel: pass/fail table, DIR/validation.json, DIR/report.html");
  validate_command->add_option("scene", validate_arguments.scenes,
                               "scene files, folders of scenes, or names of shipped scenes (default: every shipped scene "
                               "of the tier)");
  validate_command->add_option("--tier", validate_arguments.tier,
                               "fast: the scenes of tier fast (default); full: every scene");
  validate_command->add_option("--out,-o", validate_arguments.out,
                               "output folder (default ./validation; a rerun resumes)");
  validate_command->add_option("--jobs,-j", validate_arguments.jobs,
                               "cores (job slots) for the scenes, each in a child process: a run scene holds one, a "
                               "scan scene the free ones (default 1)");
  validate_command->add_flag("--quiet,-q", validate_arguments.quiet, "no progress lines on stderr");
  validate_command->add_flag("--no-plot", validate_arguments.no_plot, "no plots (report.html without images)");
  validate_command->add_flag("--rerun", validate_arguments.rerun, "rerun the scenes an earlier validation into DIR finished");
  validate_command->footer(
      "Each scene runs as `aggkit run SCENE --out DIR/<scene>` (`aggkit scan` for a scene with a [scan]\n"
      "section: it passes when every point is classified), its output in DIR/logs/<scene>.log. Finished scenes\n"
      "are recorded in DIR/finished/: an interrupted validation rerun into the same DIR runs only the rest\n"
      "(a changed scene file is rerun). Prints a pass/fail table (scene, engines, worst comparison, its error,\n"
      "tolerance and share of the tolerance used, wall time); writes DIR/validation.json and DIR/report.html.\n"
      "Not under mpirun: --jobs K gives the scenes K cores on this machine, one each, except a scan scene:\n"
      "the scans start first, each on the cores free then, as `mpiexec -np S aggkit scan` (the same outputs;\n"
      "$AGGKIT_MPIEXEC names the launcher, empty: none). The progress lines say how many cores each scene\n"
      "holds. On a cluster, spread one scene's realizations over MPI ranks by running it alone:\n"
      "mpirun -np K aggkit run SCENE --out DIR/<scene> (examples/slurm-run.sh).\n"
      "Exit status 0: every scene passes; 1: a scene failed; 2: bad input (option, scene, output folder).");
  return validate_command;
}

CLI::App* add_sweep_command(CLI::App& app, RunArguments& sweep_arguments) {
  CLI::App* sweep_command = app.add_subcommand(
      "sweep", "run a scene over the product of the values of scene keys in its [sweep]; MPI: mpirun -np K");
  sweep_command->add_option("scene", sweep_arguments.scene, "scene with a [sweep] section (see validation/sweep/sweep_plan.hpp)")
      ->required();
  sweep_command->add_option("--out,-o", sweep_arguments.out, "output folder (created if needed; a rerun resumes)")
      ->required();
  sweep_command->add_flag("--quiet,-q", sweep_arguments.quiet, "no progress lines on stderr");
  sweep_command->add_flag("--no-plot", sweep_arguments.no_plot, "do not draw the maps");
  sweep_command->footer(
      "[sweep] \"engine.damping\" = { from = 10, to = 1e5, count = 7, spacing = \"log\" } (or a list of values), any\n"
      "scene key, quoted; engine.X: the only engine, engine[i].X: by index, engine[label].X: by label;\n"
      "realizations = R (every seed + r for realization r); maps = [columns] (default observe.final).\n"
      "Writes DIR/sweep.csv (a row per point and realization: the swept values and the final values),\n"
      "DIR/sweep_mean.csv (per point: <column>, <column>_stderr, <column>_n), DIR/timing.csv,\n"
      "DIR/map_<column>.png, DIR/runs/ (each run's outputs) and DIR/points/ (finished runs: an interrupted sweep\n"
      "resumes). Exit status 0: every run finished; 1: some runs failed; 2: bad input (a key the scene refuses).");
  return sweep_command;
}

// Everything after `--` is for PETSc (aggkit run ... -- -snes_monitor), not for the command line parser:
// returns how many arguments the parser gets and appends the rest to `petsc_options`.
int split_petsc_options(int argc, char** argv, std::string& petsc_options) {
  int own_arguments = argc;
  for (int i = 1; i < argc; ++i)
    if (std::string(argv[i]) == "--") {
      own_arguments = i;
      break;
    }
  for (int i = own_arguments + 1; i < argc; ++i)
    petsc_options += (petsc_options.empty() ? "" : " ") + std::string(argv[i]);
  return own_arguments;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"aggkit: Smoluchowski aggregation-shattering kinetics and its validation harness"};
  app.set_version_flag("--version", std::string("aggkit ") + aggkit::version());
  app.footer(exit_status_help);
  app.require_subcommand(1);

  RunArguments arguments;
  add_run_command(app, arguments);  // the default: a run
  RunArguments scan_arguments;
  CLI::App* scan_command = add_scan_command(app, scan_arguments);
  ValidateArguments validate_arguments;
  CLI::App* validate_command = add_validate_command(app, validate_arguments);
  RunArguments sweep_arguments;
  CLI::App* sweep_command = add_sweep_command(app, sweep_arguments);
  CLI::App* kernels_command = app.add_subcommand("kernels", "list the kernels and their parameters");

  const int own_arguments = split_petsc_options(argc, argv, arguments.petsc_options);

  try {
    app.parse(own_arguments, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForVersion& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    std::cerr << "aggkit: error: " << e.what() << "\nRun with --help for more information.\n";
    return aggkit::exit_bad_input;
  }

  // aggkit run under mpirun: MPI lives until every rank has met at the end, so that rank 0 has printed its
  // error before a rank ends with a non-zero status (mpirun then ends the whole job).
  std::optional<aggkit::MpiSession> run_mpi;
  int code = aggkit::exit_internal_error;
  try {
    if (*kernels_command) {
      aggkit::print_kernel_catalogue(std::cout);
      return aggkit::exit_pass;
    }
    if (*scan_command) return scan(scan_arguments, &argc, &argv);
    if (*validate_command) return validate(validate_arguments);
    if (*sweep_command) return sweep(sweep_arguments, &argc, &argv);
    code = run(arguments, run_mpi, &argc, &argv);
  } catch (const aggkit::ShareAbandoned& abandoned) {  // another rank failed; rank 0 has said why
    code = abandoned.input ? aggkit::exit_bad_input : aggkit::exit_internal_error;
  } catch (const aggkit::InputError& e) {
    std::cerr << "aggkit: error: " << e.what() << "\n";
    code = aggkit::exit_bad_input;
  } catch (const std::exception& e) {
    std::cerr << "aggkit: internal error: " << e.what() << "\n";
    code = aggkit::exit_internal_error;
  } catch (...) {
    std::cerr << "aggkit: internal error: unknown exception\n";
    code = aggkit::exit_internal_error;
  }
  if (run_mpi) aggkit::mpi_barrier();
  return code;
}
