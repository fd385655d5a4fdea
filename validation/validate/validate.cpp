#include "validation/validate/validate.hpp"

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <system_error>
#include <unistd.h>

#include "analysis/input_error.hpp"
#include "validation/runs/mpi_ranks.hpp"
#include "validation/io/atomic_file.hpp"
#include "validation/runs/run_folder.hpp"
#include "validation/validate/finished_record.hpp"
#include "validation/validate/report_html.hpp"
#include "validation/validate/scene_jobs.hpp"
#include "validation/validate/validation_json.hpp"
#include "validation/validate/validation_plan.hpp"
#include "validation/validate/validation_table.hpp"

namespace aggkit {

namespace {

[[noreturn]] void unusable(const std::filesystem::path& out, const std::string& why) {
  throw InputError("--out", out.string(), "a folder that can be created and written (" + why + ")");
}

// DIR is empty, new, or an earlier validation's (it has DIR/finished or DIR/validation.json): a validation
// never spreads its folders into a folder of someone else's.
void prepare_output(const std::filesystem::path& out) {
  std::error_code error;
  if (std::filesystem::exists(out, error)) {
    if (!std::filesystem::is_directory(out, error)) unusable(out, "it is a file");
    const bool ours = std::filesystem::is_directory(finished_folder(out), error) ||
                      std::filesystem::exists(out / "validation.json", error);
    if (!ours && !std::filesystem::is_empty(out, error))
      throw InputError("--out", out.string(),
                       "a new or empty folder, or one an earlier `aggkit validate` wrote (this one holds other files)");
  }
  check_writable_folder(finished_folder(out), out);
  check_writable_folder(out / "logs", out);
}

bool outputs_present(const std::filesystem::path& out, const PlannedScene& scene) {
  std::error_code error;
  return std::filesystem::exists(out / scene.folder / (scene.kind == SceneKind::run ? "summary.json" : "scan.csv"), error);
}

// Refused under mpirun: every rank would run every scene into the same folder.
void refuse_mpirun() {
  if (const std::string variable = mpirun_variable(); !variable.empty())
    throw InputError("mpirun", variable,
                     "no mpirun: aggkit validate runs its scenes as child processes, --jobs K at a time (to spread "
                     "one scene's realizations over ranks, run it alone: mpirun -np K aggkit run SCENE --out DIR)");
}

std::string cores_text(std::size_t cores) { return std::to_string(cores) + (cores == 1 ? " core" : " cores"); }

std::string line_for(const SceneOutcome& s, std::size_t cores) {
  std::string line = s.scene.name + ": " + to_string(s.verdict);
  if (s.worst) {
    const ComparisonLine& c = s.comparisons[*s.worst];
    line += ", worst " + c.engine + " " + c.observable + " " + error_text(c) + " (tolerance " + tolerance_text(c) +
            ", used " + used_text(c) + ")";
  } else if (s.scene.kind == SceneKind::scan) {
    line += ", " + std::to_string(s.scan_points) + " points";
  }
  if (!s.problem.empty() && s.verdict != Verdict::pass) line += ": " + s.problem;
  return line + " (" + seconds_text(s.wall_seconds) + " s on " + cores_text(cores) + ")";
}

void check_options(const ValidateOptions& options) {
  if (options.jobs < 1 || options.jobs > 1024)
    throw InputError("--jobs", std::to_string(options.jobs), "a number of child processes from 1 to 1024");
  if (!options.mpiexec.empty() && ::access(options.mpiexec.c_str(), X_OK) != 0)
    throw InputError("AGGKIT_MPIEXEC", options.mpiexec.string(),
                     "an executable MPI launcher (mpiexec, mpirun) to run scan scenes on several cores, or empty for "
                     "none (every scene on one core)");
}

// Scan scenes first (they are the long ones, and they take the free cores), then the full tier, then the fast.
int start_priority(const PlannedScene& scene) {
  if (scene.kind == SceneKind::scan) return 2;
  return scene.tier == SceneTier::full ? 1 : 0;
}

// Open MPI's settings for a scan's mpiexec (other launchers ignore them): as many ranks as the slots it holds
// even beyond the cores Open MPI counts (--jobs may exceed them), ranks not bound to cores (the other
// scenes, and another scan, share the same cores), and, as root, the consent Open MPI asks of root.
std::vector<std::string> mpiexec_environment() {
  std::vector<std::string> environment{"OMPI_MCA_rmaps_base_oversubscribe=1", "OMPI_MCA_hwloc_base_binding_policy=none"};
  if (::geteuid() == 0) {
    environment.emplace_back("OMPI_ALLOW_RUN_AS_ROOT=1");
    environment.emplace_back("OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1");
  }
  return environment;
}

std::vector<ChildJob> scene_jobs(const ValidationPlan& plan, const std::vector<std::size_t>& todo,
                                 const ValidateOptions& options) {
  std::vector<ChildJob> jobs;
  for (const std::size_t i : todo) {
    const PlannedScene& scene = plan.scenes[i];
    ChildJob job;
    job.argv = {options.program.string(), to_string(scene.kind), scene.file.string(), "--out",
                (options.out / scene.folder).string(), "--quiet"};
    if (!options.plot) job.argv.push_back("--no-plot");
    job.log = options.out / "logs" / (scene.folder + ".log");
    job.priority = start_priority(scene);
    if (scene.kind == SceneKind::scan && !options.mpiexec.empty() && scene.runs > 1) {
      job.max_slots = scene.runs;
      job.spread = [argv = job.argv, mpiexec = options.mpiexec.string()](std::size_t slots) {
        std::vector<std::string> spread{mpiexec, "-np", std::to_string(slots)};
        spread.insert(spread.end(), argv.begin(), argv.end());
        return spread;
      };
      job.environment = mpiexec_environment();
    }
    jobs.push_back(std::move(job));
  }
  return jobs;
}

// Runs the scenes `todo` of the plan into `outcomes`, recording each that ends with a verdict.
void run_scenes(const ValidationPlan& plan, const std::vector<std::size_t>& todo, const ValidateOptions& options,
                std::vector<SceneOutcome>& outcomes) {
  const std::filesystem::path& out = options.out;
  std::ostream* progress = options.progress;
  std::size_t done = 0;
  std::vector<std::size_t> cores(todo.size(), 1);
  JobCallbacks callbacks;
  callbacks.started = [&](std::size_t job, std::size_t slots) {
    cores[job] = slots;
    if (progress)
      *progress << "aggkit validate: started " << plan.scenes[todo[job]].name << " on " << cores_text(slots)
                << (slots > 1 ? " (" + std::to_string(slots) + " MPI ranks)" : "") << "\n" << std::flush;
  };
  callbacks.finished = [&](std::size_t job, const ChildOutcome& child) {
    const std::size_t i = todo[job];
    const PlannedScene& scene = plan.scenes[i];
    const int exit_code = child.started ? child.exit_status : -1;
    if (exit_code == 0 || exit_code == 1) write_finished_record(out, scene, {exit_code, child.wall_seconds});
    outcomes[i] = read_scene_outcome(out, scene, exit_code, child.signal, child.wall_seconds, false);
    ++done;
    if (progress)
      *progress << "aggkit validate: [" << done << "/" << todo.size() << "] " << line_for(outcomes[i], cores[job]) << "\n"
                << std::flush;
  };
  callbacks.running = [&](const std::vector<RunningJob>& running) {
    if (!progress) return;
    std::string line = "aggkit validate: " + std::to_string(done) + "/" + std::to_string(todo.size()) + " done; running";
    for (const RunningJob& r : running)
      line += " " + plan.scenes[todo[r.job]].name + " (" + seconds_text(r.seconds) + " s, " + cores_text(r.slots) + ")";
    *progress << line << "\n" << std::flush;
  };
  run_child_jobs(scene_jobs(plan, todo, options), options.jobs, callbacks);
}

void print_header(const ValidateOptions& options, const ValidationPlan& plan, const std::vector<std::size_t>& todo) {
  std::ostream* progress = options.progress;
  if (!progress) return;
  *progress << "aggkit validate: " << plan.scenes.size() << " scenes (tier " << to_string(options.tier) << "), "
            << plan.scenes.size() - todo.size() << " finished earlier, " << todo.size() << " to run, " << options.jobs
            << " at a time; outputs in " << options.out.string() << "\n";
  bool scan = false;
  for (const std::size_t i : todo) scan = scan || (plan.scenes[i].kind == SceneKind::scan && plan.scenes[i].runs > 1);
  if (scan && options.jobs > 1)
    *progress << (options.mpiexec.empty()
                      ? std::string("aggkit validate: no MPI launcher (set AGGKIT_MPIEXEC): scan scenes start first, on one core each")
                      : "aggkit validate: scan scenes start first, each on the free cores as MPI ranks (" +
                            options.mpiexec.string() + ")")
              << "\n";
  *progress << std::flush;
}

ValidationOutcome finish_validation(const ValidateOptions& options, const ValidationPlan& plan,
                                    std::vector<SceneOutcome> outcomes, double wall_seconds) {
  ValidationOutcome result;
  result.scenes = std::move(outcomes);
  bool bad_input = false, failed = false;
  for (const auto& s : result.scenes) {
    bad_input = bad_input || s.verdict == Verdict::bad_input;
    failed = failed || !without_failure(s.verdict);
  }
  result.exit_code = bad_input ? 2 : failed ? 1 : 0;
  ValidationTotals totals;
  totals.tier = options.tier;
  totals.jobs = options.jobs;
  totals.wall_seconds = wall_seconds;
  totals.exit_code = result.exit_code;
  totals.notes = plan.notes;
  const std::filesystem::path& out = options.out;
  write_file_atomically(out / "validation.json", validation_json(result.scenes, totals));
  write_file_atomically(out / "report.html", report_html(out, result.scenes, totals));
  if (options.table) {
    print_validation_table(*options.table, result.scenes);
    *options.table << "aggkit validate: " << (result.exit_code == 0 ? "PASS" : "FAIL") << " ("
                   << seconds_text(totals.wall_seconds) << " s); " << (out / "validation.json").string() << ", "
                   << (out / "report.html").string() << "\n";
  }
  return result;
}

}  // namespace

ValidationOutcome run_validation(const ValidateOptions& options) {
  const auto started = std::chrono::steady_clock::now();
  check_options(options);
  refuse_mpirun();
  const ValidationPlan plan = plan_validation(options.scenes, options.tier, options.plot);
  if (plan.scenes.empty())
    throw InputError("--tier", to_string(options.tier),
                     "a tier with scenes to run: " + std::to_string(plan.notes.size()) +
                         " scenes are left out (tier full; use --tier full)");
  const std::filesystem::path& out = options.out;
  prepare_output(out);

  std::vector<SceneOutcome> outcomes(plan.scenes.size());
  std::vector<std::size_t> todo;
  for (std::size_t i = 0; i < plan.scenes.size(); ++i) {
    const PlannedScene& scene = plan.scenes[i];
    if (options.rerun) forget_finished_record(out, scene);
    const auto record = read_finished_record(out, scene);
    if (record && outputs_present(out, scene)) {
      outcomes[i] = read_scene_outcome(out, scene, record->exit_code, 0, record->wall_seconds, /*resumed=*/true);
    } else {
      forget_finished_record(out, scene);
      outcomes[i].scene = scene;
      todo.push_back(i);
    }
  }
  print_header(options, plan, todo);
  run_scenes(plan, todo, options, outcomes);
  const double wall_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
  return finish_validation(options, plan, std::move(outcomes), wall_seconds);
}

std::filesystem::path default_mpiexec() {
  if (const char* variable = std::getenv("AGGKIT_MPIEXEC")) return variable;
  std::error_code error;
  const std::filesystem::path built = AGGKIT_MPIEXEC_BUILD;
  if (!built.empty() && std::filesystem::is_regular_file(built, error) && ::access(built.c_str(), X_OK) == 0) return built;
  return {};
}

}  // namespace aggkit
