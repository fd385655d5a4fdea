// The `aggkit` command line: parses arguments and calls the libraries.
//   aggkit run SCENE --out DIR [--quiet] [--no-plot]
//   aggkit kernels
//   aggkit --version
// Exit status: 0 pass; 1 a comparison failed (or an engine failed); 2 bad input (bad scene or command
// line, unreadable scene, unwritable output folder); 3 an unexpected internal error.
#include <exception>
#include <iostream>
#include <string>

#include <CLI/CLI.hpp>

#include "analysis/input_error.hpp"
#include "validation/engine.hpp"
#include "validation/exit_code.hpp"
#include "validation/harness.hpp"
#include "validation/kernel_catalogue.hpp"
#include "validation/scene.hpp"
#include "validation/text.hpp"
#include "validation/version.hpp"

namespace {

const char* exit_status_help =
    "Exit status:\n"
    "  0  every engine completed and every comparison is within its tolerance\n"
    "  1  a comparison exceeded its tolerance, or an engine failed during its run\n"
    "  2  bad input: scene (key, value and what is allowed are named), command line, missing or\n"
    "     unreadable scene file, output folder that cannot be created or written\n"
    "  3  an unexpected internal error (please report it)\n";

std::string engine_help() {
  std::string help = "Engines ([[engine]] name = ...):\n";
  for (const auto& type : aggkit::engine_types()) {
    help += "  " + type.name + ": " + type.description + "\n";
    if (!type.keys.empty()) help += "    options: " + aggkit::join(type.keys) + "\n";
  }
  return help + "\n" + exit_status_help;
}

struct RunArguments {
  std::string scene;
  std::string out;
  bool quiet = false;
  bool no_plot = false;
};

int run(const RunArguments& arguments) {
  const aggkit::Scene scene = aggkit::load_scene(arguments.scene);
  aggkit::RunOptions options;
  options.out = arguments.out;
  options.plot = !arguments.no_plot;
  if (arguments.quiet) options.progress = nullptr;
  return aggkit::run_scene(scene, options).exit_code;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"aggkit: Smoluchowski aggregation-shattering kinetics and its validation harness"};
  app.set_version_flag("--version", std::string("aggkit ") + aggkit::version());
  app.footer(exit_status_help);
  app.require_subcommand(1);

  RunArguments arguments;
  CLI::App* run_command = app.add_subcommand("run", "run a scene and write its outputs, comparisons and report");
  run_command->add_option("scene", arguments.scene, "scene file (TOML; see validation/scenes/)")->required();
  run_command->add_option("--out,-o", arguments.out, "output folder (created if needed)")->required();
  run_command->add_flag("--quiet,-q", arguments.quiet, "no progress lines on stderr");
  run_command->add_flag("--no-plot", arguments.no_plot, "do not draw report.png");
  run_command->footer(engine_help());
  CLI::App* kernels_command = app.add_subcommand("kernels", "list the kernels and their parameters");

  try {
    app.parse(argc, argv);
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

  try {
    if (*kernels_command) {
      aggkit::print_kernel_catalogue(std::cout);
      return aggkit::exit_pass;
    }
    return run(arguments);
  } catch (const aggkit::InputError& e) {
    std::cerr << "aggkit: error: " << e.what() << "\n";
    return aggkit::exit_bad_input;
  } catch (const std::exception& e) {
    std::cerr << "aggkit: internal error: " << e.what() << "\n";
    return aggkit::exit_internal_error;
  } catch (...) {
    std::cerr << "aggkit: internal error: unknown exception\n";
    return aggkit::exit_internal_error;
  }
}
