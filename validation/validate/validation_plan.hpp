#pragma once
// Which scenes `aggkit validate` runs, and how. With no SCENE arguments: every scene file (*.toml) of the
// shipped folder (shipped_scene_folder()) whose tier is selected — `--tier fast` the fast ones, `--tier full`
// all. A SCENE argument is a scene file (run whatever its tier: it was asked for by name), a folder (its
// *.toml files, filtered by tier like the shipped folder) or the name of a shipped scene file without
// ".toml" ("constant-exact").
// Scene files with a [scan] section are scan scenes (validation/scan/scan_plan.hpp): they run through
// `aggkit scan` and pass when every point is classified; the others through `aggkit run`.
// Every scene is read and checked here, before anything runs: bad input is an InputError naming the key.
#include <cstddef>
#include <filesystem>
#include <string>
#include <vector>

#include "validation/scene/scene.hpp"

namespace aggkit {

enum class SceneKind { run, scan };
const char* to_string(SceneKind kind);

struct PlannedScene {
  std::string name;              // the scene's `name`
  std::string folder;            // DIR/<folder>/: the name, as a file name (unique in the plan)
  std::filesystem::path file;    // the scene file
  SceneKind kind = SceneKind::run;
  SceneTier tier = SceneTier::fast;
  std::vector<std::string> engines;  // engine labels, in run order
  std::string description;       // the scene file's opening comment, without the '#'
  std::string fingerprint;       // what a finished result depends on: the file's text and how it is run
  // Independent runs the scene can spread over MPI ranks: a scan's points (and its truncation check's runs at
  // N and 2N); 1 for a run scene, which validate runs in one process so that its outputs are one process's.
  std::size_t runs = 1;
};

struct ValidationPlan {
  SceneTier tier = SceneTier::fast;
  std::vector<PlannedScene> scenes;  // in the order given, each folder's scenes by file name
  std::vector<std::string> notes;    // scenes left out, and why (e.g. a full scene under --tier fast)
};

// "fast" or "full"; InputError for `--tier` otherwise.
SceneTier parse_tier(const std::string& text);
// $AGGKIT_SCENES if set, else the source tree's validation/scenes if it exists, else share/aggkit/scenes.
std::filesystem::path shipped_scene_folder();
// The opening comment lines of a scene file's text ("# a\n# b\nname = .." gives "a\nb").
std::string opening_comment(const std::string& text);
// `plot` is part of the fingerprint (a result without plots is not reused for one with them).
ValidationPlan plan_validation(const std::vector<std::string>& arguments, SceneTier tier, bool plot);

}  // namespace aggkit
