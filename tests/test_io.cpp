// The io room's values as summary.json writes them: numbers that parse back to within their
// 13 significant digits, NaN and inf as null (strict JSON has neither), and strings escaped so
// any bytes (a scene name, a path) give valid JSON text in UTF-8.
#include "gimp/io/json.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <limits>
#include <random>
#include <string>

namespace {

TEST(JsonNumber, ParsesBackToThirteenDigits) {
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> mant(-10, 10);
  std::uniform_int_distribution<int> ex(-300, 300);
  for (int t = 0; t < 2000; ++t) {
    const double v = mant(rng) * std::pow(10.0, ex(rng));
    const std::string s = gimp::jsonNumber(v);
    char *end = nullptr;
    const double back = std::strtod(s.c_str(), &end);
    EXPECT_EQ(*end, '\0') << s;
    EXPECT_LE(std::fabs(back - v), 5e-13 * std::fabs(v)) << s;
  }
  EXPECT_EQ(gimp::jsonNumber(0.0), "0.000000000000e+00");
  EXPECT_EQ(std::strtod(gimp::jsonNumber(-1e-310).c_str(), nullptr), -1e-310); // subnormal
}

TEST(JsonNumber, NotANumberIsNull) {
  EXPECT_EQ(gimp::jsonNumber(std::nan("")), "null");
  EXPECT_EQ(gimp::jsonNumber(std::numeric_limits<double>::infinity()), "null");
  EXPECT_EQ(gimp::jsonNumber(-std::numeric_limits<double>::infinity()), "null");
}

TEST(JsonString, EscapesWhatJsonForbids) {
  EXPECT_EQ(gimp::jsonString("plate"), "\"plate\"");
  EXPECT_EQ(gimp::jsonString("a\"b\\c"), "\"a\\\"b\\\\c\"");
  EXPECT_EQ(gimp::jsonString(std::string("t\tn\n\x01", 5)), "\"t\\u0009n\\u000a\\u0001\"");
  EXPECT_EQ(gimp::jsonString(std::string("nul\0x", 5)), "\"nul\\u0000x\"");
}

TEST(JsonString, KeepsUtf8AndReplacesWhatIsNot) {
  const std::string accents = "d\xc3\xa9j\xc3\xa0 \xe2\x82\xac \xf0\x9f\x98\x80"; // é à € 😀
  EXPECT_EQ(gimp::jsonString(accents), "\"" + accents + "\"");
  EXPECT_EQ(gimp::jsonString("a\xff"
                             "b"),
            "\"a\\ufffdb\"");                                         // a byte that starts nothing
  EXPECT_EQ(gimp::jsonString("a\xc3"), "\"a\\ufffd\"");               // a sequence cut short
  EXPECT_EQ(gimp::jsonString("\xe2\x28\xa1"), "\"\\ufffd(\\ufffd\""); // a bad continuation
}

} // namespace
