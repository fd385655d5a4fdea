// The one-row record files that resumable runs read back (validation/runs/run_store.hpp): exactly a header,
// one row and nothing after it; anything else is not a record and its run is done again.
#include <catch2/catch.hpp>
#include <cmath>
#include <string>

#include "analysis/text.hpp"
#include "validation/runs/json_record.hpp"
#include "validation/runs/run_store.hpp"

using aggkit::one_row_record;
using aggkit::record_number;

TEST_CASE("run records: one row under the exact header is a record, with its fields") {
  const auto f = one_row_record("a,b,c\n1,x,\n", "a,b,c");
  REQUIRE(f);
  CHECK(f->size() == 3);  // the trailing comma is an empty last field
  CHECK((*f)[0] == "1");
  CHECK((*f)[1] == "x");
  CHECK((*f)[2].empty());
  CHECK(one_row_record("a,b\n1,2", "a,b"));  // the last newline may be missing
}

TEST_CASE("run records: a damaged, truncated or foreign file is not a record") {
  CHECK(!one_row_record("", "a,b"));
  CHECK(!one_row_record("a,b\n", "a,b"));           // truncated after the header
  CHECK(!one_row_record("a,b,c\n1,2,3\n", "a,b"));  // another header: another kind of record
  CHECK(!one_row_record("a,b\n1,2\n3,4\n", "a,b"));  // two rows
  CHECK(!one_row_record("a,b\n1,2\n\n", "a,b"));     // anything after the row
  CHECK(!one_row_record("b,a\n1,2\n", "a,b"));
}

TEST_CASE("run records: a number field is the whole field read as a number") {
  CHECK(record_number("0.25") == 0.25);
  CHECK(record_number("-1e-300") == -1e-300);
  CHECK(std::isnan(*record_number("nan")));
  CHECK(!record_number("0.25x"));
  CHECK(!record_number("yes"));
  CHECK(!record_number("1e999"));  // out of range
  CHECK(!record_number("-1e999"));
  // A subnormal number is read as written (a cached state's far tail holds densities ~1e-318).
  CHECK(record_number("-6.888886e-318") == -6.888886e-318);
  CHECK(record_number("4.9406564584124654e-324") == 4.9406564584124654e-324);
  CHECK(record_number(aggkit::shortest_text(3e-320)) == 3e-320);
  CHECK(!record_number(""));
  REQUIRE(record_number("", /*empty_is_nan=*/true));
  CHECK(std::isnan(*record_number("", true)));
}

TEST_CASE("run records: a JSON record is one whole object, anything else is no record") {
  const auto record = aggkit::json_record("{\"point\": 3, \"seconds\": 1.5}\n");
  REQUIRE(record);
  CHECK((*record)["point"].get<int>() == 3);
  CHECK_FALSE(aggkit::json_record(""));
  CHECK_FALSE(aggkit::json_record("{\"point\": 3, \"seconds\": 1."));  // truncated by a kill
  CHECK_FALSE(aggkit::json_record("[1, 2]"));                         // not an object
  CHECK_FALSE(aggkit::json_record("{\"point\": 3} {\"point\": 4}"));   // two records written over each other
}
