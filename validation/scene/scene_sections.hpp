#pragma once
// The readers of the sections of a scene (internal to the scene parser; see scene.hpp for the schema).
#include "validation/scene/scene.hpp"
#include "validation/scene/scene_table.hpp"

namespace aggkit {

TimeGrid read_time(const SceneTable& time);                      // [time]
void read_model(const SceneTable& model, Scene& scene);          // [model]; needs scene.time
// [particles]; a start file's relative path is taken from `folder` (the scene file's; empty: the current one).
ParticleSystem read_particles(const SceneTable& particles, const std::filesystem::path& folder);
void read_engines(const SceneTable& root, Scene& scene);         // [[engine]]; needs model/particles and time
Observation read_observation(const SceneTable& observe, const Scene& scene);  // [observe]
ComparisonPlan read_comparison(const SceneTable& compare, const Scene& scene);  // [compare]

// The scene key of a parameter the solvers name in their own terms: "kernel.a" -> "model.kernel.a".
std::string model_key(const std::string& parameter);

// The output time equal to `t` up to round-off (1e-9 of the end time), or std::nullopt.
std::optional<double> matching_output_time(const TimeGrid& grid, double t);

}  // namespace aggkit
