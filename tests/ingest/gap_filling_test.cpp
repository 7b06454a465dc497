#include "stages/ingest/gap_filling.h"

#include <gtest/gtest.h>

#include <cmath>

namespace syn {
namespace {

// One marker whose x follows f(t), y = 2 f(t), z = -f(t), at 100 Hz.
MarkerData OneMarker(int frames, double (*f)(double)) {
  MarkerData data;
  data.rate_hz = 100;
  data.labels = {"M"};
  for (int t = 0; t < frames; ++t) {
    const double time = t / 100.0;
    data.time_s.push_back(time);
    data.points.insert(data.points.end(), {f(time), 2 * f(time), -f(time)});
  }
  return data;
}

void Erase(MarkerData& data, int first, int last) {
  for (int t = first; t <= last; ++t) {
    for (int axis = 0; axis < 3; ++axis) data.points[t * 3 + axis] = std::nan("");
  }
}

TEST(GapFilling, LinearMotionIsRecoveredExactly) {
  MarkerData data = OneMarker(50, [](double t) { return 0.3 + 1.7 * t; });
  const std::vector<double> truth = data.points;
  Erase(data, 20, 24);
  const auto reports = FillMarkerGaps(data, 5);
  ASSERT_EQ(reports.size(), 1u);
  EXPECT_EQ(reports[0].gaps, 1);
  EXPECT_EQ(reports[0].gaps_filled, 1);
  EXPECT_EQ(reports[0].missing_before, 5);
  EXPECT_EQ(reports[0].missing_after, 0);
  for (size_t i = 0; i < truth.size(); ++i) EXPECT_NEAR(data.points[i], truth[i], 1e-12) << i;
}

TEST(GapFilling, SmoothMotionIsRecoveredClosely) {
  MarkerData data = OneMarker(200, [](double t) { return std::sin(2.0 * M_PI * 1.0 * t); });
  const std::vector<double> truth = data.points;
  Erase(data, 100, 107);
  FillMarkerGaps(data, 10);
  for (int t = 100; t <= 107; ++t) EXPECT_NEAR(data.points[t * 3], truth[t * 3], 1e-4) << t;
}

TEST(GapFilling, LongGapsAndEdgesStayMissing) {
  MarkerData data = OneMarker(60, [](double t) { return t; });
  Erase(data, 0, 2);    // start of trial: never extrapolated
  Erase(data, 10, 12);  // short: filled
  Erase(data, 30, 39);  // 10 frames > 5: left
  Erase(data, 58, 59);  // end of trial
  const auto reports = FillMarkerGaps(data, 5);
  EXPECT_EQ(reports[0].gaps, 4);
  EXPECT_EQ(reports[0].gaps_filled, 1);
  EXPECT_EQ(reports[0].missing_before, 3 + 3 + 10 + 2);
  EXPECT_EQ(reports[0].missing_after, 3 + 10 + 2);
  EXPECT_TRUE(std::isnan(data.points[0]));
  EXPECT_FALSE(std::isnan(data.points[11 * 3]));
  EXPECT_TRUE(std::isnan(data.points[35 * 3]));
  EXPECT_TRUE(std::isnan(data.points[59 * 3 + 2]));
}

TEST(GapFilling, ZeroMeansReportOnly) {
  MarkerData data = OneMarker(20, [](double t) { return t; });
  Erase(data, 5, 5);
  const auto reports = FillMarkerGaps(data, 0);
  EXPECT_EQ(reports[0].gaps, 1);
  EXPECT_EQ(reports[0].gaps_filled, 0);
  EXPECT_TRUE(std::isnan(data.points[5 * 3]));
}

}  // namespace
}  // namespace syn
