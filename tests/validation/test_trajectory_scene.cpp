// observe.snapshots = { every = Δt }: which output times get a trajectory frame, and the bounds on the file
// count and the disk a trajectory may take, checked before anything runs.
#include <catch2/catch.hpp>

#include "analysis/input_error.hpp"
#include "validation/scene/scene.hpp"

using namespace aggkit;
using Catch::Matchers::Contains;

namespace {

std::string scene_with(const std::string& snapshots, const std::string& count = "100", const std::string& time = "every = 0.25") {
  return "name = \"trajectory\"\n[particles]\ndimension = 2\ncount = " + count +
         "\nradius = 0.5\nvolume_fraction = 0.2\nboundary = \"reflecting\"\n"
         "initial = { lattice = \"square\", speed = 1.0, directions = \"uniform\" }\n"
         "[time]\nend = 10.0\n" + time + "\n[[engine]]\nname = \"ed\"\n[observe]\nseries = [\"clusters\"]\nsnapshots = " +
         snapshots + "\n";
}

std::string refusal(const std::string& text) {
  try {
    parse_scene(text);
  } catch (const InputError& e) {
    return e.what();
  }
  return "accepted";
}

}  // namespace

TEST_CASE("trajectory scene: frames at the output times at least `every` apart") {
  const Scene every = parse_scene(scene_with("{ every = 1.0 }"));
  CHECK(every.observe.snapshots);  // the final snapshot as with `true`
  CHECK(every.observe.frame_every == 1.0);
  REQUIRE(every.observe.frame_outputs.size() == 10);  // t = 1, 2, ..., 10 of the outputs 0.25, 0.5, ...
  for (std::size_t i = 0; i < 10; ++i) CHECK(every.time.outputs[every.observe.frame_outputs[i]] == Approx(double(i + 1)));
  // Finer than the outputs: every output; uneven outputs: the next one at least `every` later.
  CHECK(parse_scene(scene_with("{ every = 0.1 }")).observe.frame_outputs.size() == 40);
  const Scene uneven = parse_scene(scene_with("{ every = 2.0 }", "100", "outputs = [1.0, 2.0, 3.5, 4.0, 9.0]"));
  std::vector<double> times;
  for (std::size_t k : uneven.observe.frame_outputs) times.push_back(uneven.time.outputs[k]);
  CHECK(times == std::vector<double>{2.0, 4.0, 9.0});
  // `true` keeps its meaning: the final configuration only.
  const Scene final_only = parse_scene(scene_with("true"));
  CHECK(final_only.observe.snapshots);
  CHECK(final_only.observe.frame_every == 0);
  CHECK(final_only.observe.frame_outputs.empty());
}

TEST_CASE("trajectory scene: the file count and the disk estimate are bounded before the run") {
  // 40 outputs + t = 0 = 41 frames against max_frames = 20.
  CHECK_THAT(refusal(scene_with("{ every = 0.25, max_frames = 20 }")),
             Contains("observe.snapshots.every") && Contains("max_frames = 20") && Contains("41"));
  CHECK(refusal(scene_with("{ every = 0.25, max_frames = 41 }")) == "accepted");
  // 10^6 particles x 11 frames x about 135 B = 1.5 GB: within the default 2048 MB, beyond 1000 MB.
  CHECK(refusal(scene_with("{ every = 1.0 }", "1000000")) == "accepted");
  CHECK_THAT(refusal(scene_with("{ every = 1.0, max_megabytes = 1000 }", "1000000")),
             Contains("max_megabytes = 1000") && Contains("1481 MB"));
  CHECK_THAT(refusal(scene_with("{ every = 1.0, colour = 1 }")), Contains("observe.snapshots.colour"));
  CHECK_THAT(refusal(scene_with("{ every = -1.0 }")), Contains("observe.snapshots.every"));
  CHECK_THAT(refusal(scene_with("{ max_frames = 5 }")), Contains("observe.snapshots.every"));
}
