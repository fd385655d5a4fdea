// Scan scenes: the [scan] grid (lists and ranges, log spacing) and every bad input named by key and value.
#include <catch2/catch.hpp>

#include <cmath>

#include "analysis/input_error.hpp"
#include "tests/validation/scene_fixture.hpp"
#include "validation/scan/scan_plan.hpp"

using namespace aggkit;
using Catch::Matchers::Contains;

namespace {

struct ScanText {
  std::string model = "kernel = { name = \"brownian\", a = 0.9 }\nsize = 64\n";
  std::string time = "end = 100.0\nevery = 1.0\n";
  std::string engines;
  std::string scan = "a = [0.9, 0.95]\nlambda = { from = 0.001, to = 0.1, count = 3, spacing = \"log\" }\n";
  std::string text() const {
    return "name = \"scan\"\n[model]\n" + model + "[time]\n" + time + engines + "[scan]\n" + scan;
  }
};

void check_bad(const std::function<void(ScanText&)>& change, const std::string& key, const std::string& value) {
  ScanText s;
  change(s);
  INFO(s.text());
  try {
    parse_scan_plan(s.text());
    FAIL("accepted");
  } catch (const InputError& e) {
    CHECK_THAT(std::string(e.what()), Contains(key) && Contains(value));
  }
}

}  // namespace

TEST_CASE("scan plan: lists, linear and log ranges") {
  const ScanPlan plan = parse_scan_plan(ScanText().text());
  REQUIRE(plan.a == std::vector<double>{0.9, 0.95});
  REQUIRE(plan.lambda.size() == 3);
  CHECK(plan.lambda[0] == 0.001);
  CHECK(plan.lambda[1] == Approx(0.01).epsilon(1e-14));
  CHECK(plan.lambda[2] == 0.1);
  CHECK(plan.lambda_log);
  CHECK(plan.point_count() == 6);
  CHECK(plan.point(4).a == 0.95);  // a-major
  CHECK(plan.point(4).lambda == plan.lambda[1]);
  CHECK(plan.series == "M0");
  CHECK(plan.criteria.tail_fraction == 0.5);
  CHECK(plan.scene.engines.size() == 1);  // a default cvode engine
  CHECK(plan.scene.engines[0].name == "cvode");

  ScanText linear;
  linear.scan = "a = { from = 0.55, to = 1.0, count = 10 }\nlambda = [0.01]\nseries = \"M2\"\ntail = 0.25\n"
                "truncation_check = { points = [[0.95, 0.01]], lambda_crit = true }\n";
  linear.time = "end = 100.0\nevery = 0.5\n";
  const ScanPlan p = parse_scan_plan(linear.text());
  REQUIRE(p.a.size() == 10);
  CHECK(p.a[1] == 0.6);  // rounded to 12 digits, not 0.6000000000000001
  CHECK(p.a.back() == 1.0);
  CHECK_FALSE(p.lambda_log);
  CHECK(p.series_order == 2);
  CHECK(p.criteria.tail_fraction == 0.25);
  CHECK(p.check_points == std::vector<std::pair<double, double>>{{0.95, 0.01}});
  CHECK(p.check_lambda_crit);

  // A list with one ratio throughout is log-spaced (its λ_crit midpoint is geometric).
  ScanText geometric;
  geometric.scan = "a = [0.9]\nlambda = [0.001, 0.01, 0.1]\n";
  CHECK(parse_scan_plan(geometric.text()).lambda_log);
}

TEST_CASE("scan plan: the point model carries a, lambda and N, the fingerprint ignores the grid") {
  const ScanPlan plan = parse_scan_plan(ScanText().text());
  const AggregationModel m = point_model(plan, 0.95, 0.02, 128);
  CHECK(m.kernel.describe() == Kernel::brownian(0.95).describe());
  CHECK(m.lambda(0.0) == 0.02);
  CHECK(m.size == 128);
  ScanText other_grid;
  other_grid.scan = "a = [0.7]\nlambda = [0.5]\n";
  CHECK(parse_scan_plan(other_grid.text()).fingerprint == plan.fingerprint);
  ScanText other_model;
  other_model.model = "kernel = { name = \"brownian\", a = 0.9 }\nsize = 65\n";
  CHECK(parse_scan_plan(other_model.text()).fingerprint != plan.fingerprint);
}

TEST_CASE("scan plan: bad input names the key and the value") {
  check_bad([](ScanText& s) { s.scan = "a = []\nlambda = [0.01]\n"; }, "scan.a", "[]");
  check_bad([](ScanText& s) { s.scan = "a = [0.9]\nlambda = { from = 0.1, to = 0.01, count = 3 }\n"; }, "scan.lambda.to", "0.01");
  check_bad([](ScanText& s) { s.scan = "a = [0.9]\nlambda = { from = 0.01, to = 0.1, count = 0 }\n"; }, "scan.lambda.count", "0");
  check_bad([](ScanText& s) { s.scan = "a = [0.9, 1.2]\nlambda = [0.01]\n"; }, "scan.a[1]", "1.2");
  check_bad([](ScanText& s) { s.scan = "a = { from = -0.5, to = 0.9, count = 3 }\nlambda = [0.01]\n"; }, "scan.a[0]", "-0.5");
  check_bad([](ScanText& s) { s.scan = "a = [0.9]\nlambda = [0.0, 0.01]\n"; }, "scan.lambda[0]", "0");
  check_bad([](ScanText& s) { s.scan = "a = [0.9]\nlambda = [0.01, nan]\n"; }, "scan.lambda[1]", "nan");
  check_bad([](ScanText& s) { s.scan = "a = [0.95, 0.9]\nlambda = [0.01]\n"; }, "scan.a[1]", "0.9");
  check_bad([](ScanText& s) { s.scan = "a = [0.9]\nlambda = { from = 0.0, to = 0.1, count = 3, spacing = \"log\" }\n"; },
            "scan.lambda.from", "0");
  check_bad([](ScanText& s) { s.scan = "a = [0.9]\nlambda = { from = 0.01, to = 0.1, count = 3, spacing = \"cubic\" }\n"; },
            "scan.lambda.spacing", "cubic");
  check_bad([](ScanText& s) { s.scan = "a = [0.9]\n"; }, "scan.lambda", "missing");
  check_bad([](ScanText& s) { s.scan = "a = [0.9]\nlambda = [0.01]\nseries = \"M3\"\n"; }, "scan.series", "M3");
  check_bad([](ScanText& s) { s.scan = "a = [0.9]\nlambda = [0.01]\ntail = 1.5\n"; }, "scan.tail", "1.5");
  check_bad([](ScanText& s) { s.scan = "a = [0.9]\nlambda = [0.01]\nsteps = 3\n"; }, "scan.steps", "3");
  check_bad([](ScanText& s) { s.scan = "a = [0.9]\nlambda = [0.01]\ntruncation_check = { points = [[1.5, 0.01]] }\n"; },
            "scan.truncation_check.points[0][0]", "1.5");
  check_bad([](ScanText& s) { s.model = "kernel = { name = \"constant\" }\nsize = 64\n"; }, "model.kernel.name", "constant");
  check_bad([](ScanText& s) { s.model = "kernel = { name = \"brownian\", a = 0.9 }\nsize = 1\n"; }, "model.size", "1");
  check_bad([](ScanText& s) { s.time = "end = 100.0\nevery = 3.0\n"; }, "time", "100");  // 3, 6, .., 99, 100
  check_bad([](ScanText& s) { s.time = "end = 100.0\nevery = 10.0\n"; }, "time.every", "10 outputs");
  check_bad([](ScanText& s) { s.engines = "[[engine]]\nname = \"exact\"\n"; }, "engine", "exact");
  check_bad([](ScanText& s) { s.engines = "[[engine]]\nname = \"cvode\"\nrtol = -1\n"; }, "engine[0].rtol", "-1");
  check_bad([](ScanText& s) { s.scan = "a = [0.9]\nlambda = [0.01]\n[observe]\nseries = [\"M0\"]\n"; }, "observe", "M0");
}

TEST_CASE("scan plan: a missing or malformed file is bad input") {
  CHECK_THROWS_WITH(load_scan_plan("/nonexistent/scan.toml"), Contains("scene = /nonexistent/scan.toml"));
  CHECK_THROWS_WITH(parse_scan_plan("name = \"x\"\n[scan\n"), Contains("malformed TOML"));
  CHECK_THROWS_WITH(parse_scan_plan("name = \"x\"\n[model]\nkernel = { name = \"brownian\", a = 0.9 }\nsize = 64\n"
                                    "[time]\nend = 100.0\nevery = 1.0\n"),
                    Contains("scan") && Contains("required"));
}
