// Flag values: what is accepted and the exact error for what is not.
#include "cli/flags.h"  // private to burrlab::runner

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <string>

namespace burrlab::runner {
namespace {

std::string ErrorOf(const Result<double>& result) {
  return result.ok() ? "(ok)" : result.error().message;
}

TEST(ParseNumber, AcceptsDecimalAndScientificNotation) {
  EXPECT_DOUBLE_EQ(*ParseNumber("--x", "3"), 3.0);
  EXPECT_DOUBLE_EQ(*ParseNumber("--x", "-0.25"), -0.25);
  EXPECT_DOUBLE_EQ(*ParseNumber("--x", "+1.5e2"), 150.0);
  EXPECT_DOUBLE_EQ(*ParseNumber("--x", ".5"), 0.5);
}

TEST(ParseNumber, RejectsNonFiniteOverflowAndTrailingText) {
  for (const char* text :
       {"nan", "inf", "-inf", "infinity", "1e999", "-1e999", "3mm", "3 ", " 3",
        "", "+", "+-1", "0x10", "1,5", "--1"}) {
    EXPECT_EQ(ErrorOf(ParseNumber("--x", text)),
              "--x must be a finite number, got '" + std::string(text) + "'");
  }
}

TEST(ParseNumber, RejectsUnderflowAsTooCloseToZero) {
  EXPECT_EQ(ErrorOf(ParseNumber("--x", "1e-999")),
            "--x is too close to zero to represent, got '1e-999'");
}

TEST(ParsePositive, NamesTheUnitInTheError) {
  EXPECT_EQ(ErrorOf(ParsePositive("--force-n", "0", "N")),
            "--force-n must be a positive number of N, got '0'");
  EXPECT_EQ(ErrorOf(ParsePositive("--ratio", "-2", "")),
            "--ratio must be a positive number, got '-2'");
  EXPECT_EQ(ErrorOf(ParsePositive("--force-n", "-nan", "N")),
            "--force-n must be a finite number, got '-nan'");
}

TEST(ParseNonNegative, AcceptsZeroAndRejectsNegatives) {
  EXPECT_DOUBLE_EQ(*ParseNonNegative("--alpha", "0", "1/s"), 0.0);
  EXPECT_FALSE(std::signbit(*ParseNonNegative("--alpha", "-0", "1/s")));
  EXPECT_EQ(ErrorOf(ParseNonNegative("--alpha", "-0.1", "1/s")),
            "--alpha must be zero or a positive number of 1/s, got '-0.1'");
}

TEST(ParseInteger, AcceptsWholeNumbersInRange) {
  EXPECT_EQ(*ParseInteger("--points", "2", 2, 10), 2);
  EXPECT_EQ(*ParseInteger("--points", "10", 2, 10), 10);
  for (const char* text :
       {"1", "11", "2.5", "1e1", "", "99999999999999999999"}) {
    const Result<std::int64_t> result = ParseInteger("--points", text, 2, 10);
    ASSERT_FALSE(result.ok()) << text;
    EXPECT_EQ(result.error().message,
              "--points must be a whole number from 2 to 10, got '" +
                  std::string(text) + "'");
  }
}

TEST(ParseUnsigned, TakesTheWholeSixtyFourBitRange) {
  EXPECT_EQ(*ParseUnsigned("--seed", "18446744073709551615"),
            18446744073709551615u);
  const Result<std::uint64_t> negative = ParseUnsigned("--seed", "-1");
  ASSERT_FALSE(negative.ok());
  EXPECT_EQ(negative.error().message,
            "--seed must be a whole number from 0 to 18446744073709551615, "
            "got '-1'");
  EXPECT_FALSE(ParseUnsigned("--seed", "18446744073709551616").ok());
}

TEST(ParseSeed, TakesTheSeedAsTheExportsWriteItOrBare) {
  EXPECT_EQ(*ParseSeed("--seed", "seed-18446744073709551615"),
            18446744073709551615u);
  EXPECT_EQ(*ParseSeed("--seed", "9223372036854775809"), 9223372036854775809u);
  const Result<std::uint64_t> bad = ParseSeed("--seed", "seed-1.5");
  ASSERT_FALSE(bad.ok());
  EXPECT_EQ(bad.error().message,
            "--seed must be a whole number from 0 to 18446744073709551615, "
            "bare or as the exports write it (seed-N), got 'seed-1.5'");
}

TEST(ParseDirection, ReadsThreeCommaSeparatedNumbers) {
  const Result<glm::dvec3> direction = ParseDirection("--normal", "0,-1,2.5");
  ASSERT_TRUE(direction.ok());
  EXPECT_EQ(*direction, glm::dvec3(0.0, -1.0, 2.5));
}

TEST(ParseDirection, RejectsWrongCountNonFiniteAndZero) {
  const auto error = [](const char* text) {
    const Result<glm::dvec3> result = ParseDirection("--normal", text);
    return result.ok() ? std::string("(ok)") : result.error().message;
  };
  EXPECT_EQ(error("1,2"),
            "--normal must be three comma-separated numbers X,Y,Z, got '1,2'");
  EXPECT_EQ(error("1,2,3,4"),
            "--normal must be three comma-separated numbers X,Y,Z, got "
            "'1,2,3,4'");
  EXPECT_EQ(error("1,,3"),
            "--normal must be three finite numbers X,Y,Z, got '1,,3'");
  EXPECT_EQ(error("1,nan,0"),
            "--normal must be three finite numbers X,Y,Z, got '1,nan,0'");
  EXPECT_EQ(error("0,0,0"),
            "--normal must not be the zero vector, got '0,0,0'");
  EXPECT_EQ(error("0,-0,0"),
            "--normal must not be the zero vector, got '0,-0,0'");
}

}  // namespace
}  // namespace burrlab::runner
