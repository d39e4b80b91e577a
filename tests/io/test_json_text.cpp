// The shared JSON writer (io/json_text.hpp): layout the tools' tests grep for, numbers that
// read back exactly, and NaN/Inf refused with the member named instead of printed.
#include "io/json_text.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

namespace vigs::io {
namespace {

TEST(JsonText, OneLineLayoutKeepsOrderSpacingAndEscapes) {
  Json j;
  j["name"] = "a \"b\"\n";
  j["count"] = 60;
  j["fps"] = 1.0;  // whole double: printed as 1
  j["ratio"] = 0.1;
  j["list"] = {1, 2};
  j["nested"] = {{"ok", true}, {"none", nullptr}};
  EXPECT_EQ(json_line(j),
            R"({"name": "a \"b\"\n", "count": 60, "fps": 1, "ratio": 0.1, "list": [1, 2], )"
            R"("nested": {"ok": true, "none": null}})");
}

TEST(JsonText, LinesLayoutPutsMembersAndObjectRowsOnTheirOwnLines) {
  Json j;
  j["a"] = 1;
  j["rows"] = Json::array({{{"k", 1}}, {{"k", 2}}});
  j["empty"] = Json::array();
  j["nums"] = {1.5, 2};
  EXPECT_EQ(json_lines(j),
            "{\n  \"a\": 1,\n  \"rows\": [\n    {\"k\": 1},\n    {\"k\": 2}\n  ],\n"
            "  \"empty\": [\n  ],\n  \"nums\": [1.5, 2]\n}");
}

TEST(JsonText, NumbersRoundTripExactly) {
  const double v = 1.3034497145650266;
  Json j;
  j["rmse"] = v;
  j["big"] = std::uint64_t{123456789012345};
  const Json back = Json::parse(json_line(j));
  EXPECT_EQ(back["rmse"].get<double>(), v);
  EXPECT_EQ(back["big"].get<std::uint64_t>(), 123456789012345u);
}

TEST(JsonText, NonFiniteIsRefusedNamingTheMember) {
  for (const double bad : {std::nan(""), std::numeric_limits<double>::infinity(),
                           -std::numeric_limits<double>::infinity()}) {
    Json j;
    j["ate"] = {{"pairs", 3}, {"rmse", bad}};
    try {
      (void)json_line(j);
      FAIL() << "non-finite number printed";
    } catch (const JsonNonFiniteError& e) {
      EXPECT_NE(std::string(e.what()).find("\"/ate/rmse\""), std::string::npos) << e.what();
    }
    EXPECT_THROW((void)json_lines(j), JsonNonFiniteError);
    j["ate"]["rmse"] = rounded(bad, 9);  // rounding passes NaN/Inf through, still refused
    EXPECT_THROW((void)json_line(j), JsonNonFiniteError);
    Json arr = {1.0, bad};
    EXPECT_THROW((void)json_line(arr), JsonNonFiniteError);
  }
}

TEST(JsonText, FiniteOrNullStatesUndefinedValuesExplicitly) {
  Json j;
  j["psnr_db"] = finite_or_null(std::numeric_limits<double>::infinity());
  j["fps"] = finite_or_null(std::optional<double>{});
  j["ssim"] = finite_or_null(0.5);
  EXPECT_EQ(json_line(j), R"({"psnr_db": null, "fps": null, "ssim": 0.5})");
}

TEST(JsonText, RoundedAndFixedKeepTheReportsPrecision) {
  EXPECT_EQ(json_line(Json::array({rounded(0.123456789012, 9), fixed(12.34567, 3), fixed(2.0, 1)})),
            "[0.123456789, 12.346, 2]");
}

TEST(JsonText, InvalidUtf8InStringsIsReplacedNotThrown) {
  Json j;
  j["path"] = std::string(
      "a\xff"
      "b");
  EXPECT_EQ(json_line(j),
            "{\"path\": \"a\xEF\xBF\xBD"
            "b\"}");
}

}  // namespace
}  // namespace vigs::io
