// The nearest-rank summaries every reported median and p95 comes from (common/percentile.h), against
// values whose ranks are known by hand.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "common/percentile.h"

namespace syn {
namespace {

TEST(Percentile, MedianP95AndLargestByNearestRankOfTheFiniteEntries) {
  // 21 values 0..20, shuffled, with a NaN and an infinity that do not count: rank round(0.5 × 20) = 10,
  // round(0.95 × 20) = 19.
  std::vector<double> values;
  for (int i = 0; i <= 20; ++i) values.push_back(static_cast<double>((i * 8) % 21));
  values.push_back(std::nan(""));
  values.push_back(INFINITY);
  const Spread spread = MedianP95Largest(values);
  EXPECT_EQ(spread.median, 10.0);
  EXPECT_EQ(spread.p95, 19.0);
  EXPECT_EQ(spread.largest, 20.0);
  EXPECT_EQ(spread.median, NearestRankPercentile(values, 0.5));
  // One value is all three; none finite gives NaN.
  const Spread one = MedianP95Largest({2.5});
  EXPECT_EQ(one.median, 2.5);
  EXPECT_EQ(one.p95, 2.5);
  EXPECT_EQ(one.largest, 2.5);
  EXPECT_TRUE(std::isnan(MedianP95Largest({std::nan("")}).largest));
  EXPECT_TRUE(std::isnan(MedianP95Largest({}).median));
}

}  // namespace
}  // namespace syn
