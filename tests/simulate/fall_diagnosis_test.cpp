// A fall's summary (fall_diagnosis.h) on histories whose story is known: the run it reports starts at the
// last frame the capture point was on the plan and ends where it was past a step's reach, and the shares
// and extremes it quotes are those of that run, not of the collapse after it.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "stages/simulate/fall_diagnosis.h"

namespace syn {
namespace {

constexpr double kCap = 0.3;

// 100 frames at 100 Hz: on the plan until 0.5 s, then off it by 6.5 cm growing 1 m/s (past the 0.3 m cap
// at 0.74 s) with the zero-moment point clamped; standing on both feet unless `stepping`, whose step needs
// a landing shift of `landing` m; yaw moments of 30 N·m on the plan and 200 N·m in the collapse past 0.9 s,
// tilting moments of 100 N·m per second of time (the run's 24 frames 51-74 N·m), 900 N·m in the collapse;
// the standing soles flat on the floor (eight points, four while one foot swings), the plan's zero-moment point on them.
std::vector<BalanceSample> History(bool stepping, double landing) {
  std::vector<BalanceSample> samples;
  for (int i = 0; i < 100; ++i) {
    BalanceSample sample;
    sample.time = 0.01 * i;
    sample.balancing = true;
    sample.capture_error = sample.time <= 0.5 ? 0.01 : 0.065 + (sample.time - 0.5);
    sample.zmp_shortfall = sample.time <= 0.5 ? 0.0 : 0.02 + 0.1 * (sample.time - 0.5);
    sample.standing_both = !stepping;
    sample.stepping = stepping && sample.time > 0.5;
    sample.landing_needed = sample.stepping ? landing : 0.0;
    sample.unexplained_yaw = sample.time > 0.9 ? -200.0 : 30.0;
    sample.unexplained_tilt = sample.time > 0.9 ? 900.0 : 100.0 * sample.time;
    sample.heading_error = sample.time > 0.9 ? 90.0 : -12.0;
    sample.support_points = stepping && sample.time > 0.5 ? 4 : 8;  // flat soles
    samples.push_back(sample);
  }
  return samples;
}

bool Has(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

TEST(FallDiagnosis, StandingWithNoStepToTake) {
  const std::string text = DescribeFall(History(false, 0), kCap);
  EXPECT_TRUE(Has(text, "left the balance plan at t = 0.51 s (last within 0.05 m of it)")) << text;
  EXPECT_TRUE(Has(text, "past a step's reach (0.30 m) at t = 0.74 s")) << text;
  EXPECT_TRUE(Has(text, "outside the standing soles in 100 % of the frames")) << text;
  EXPECT_TRUE(Has(text, "both feet stayed planted in the source for 100 %")) << text;
  EXPECT_FALSE(Has(text, "landing")) << text;
  // The run's yaw and heading, not the collapse's.
  EXPECT_TRUE(Has(text, "up to 30 N·m of the yaw moment")) << text;
  // Nearest rank round(0.5 × 23) = 12 of the run's sorted 51-74 N·m: 63.
  EXPECT_TRUE(Has(text, "up to 74 N·m of the tilting moment planned no sole gave (median 63)")) << text;
  EXPECT_TRUE(Has(text, "up to 12 deg off the reference's heading")) << text;
  // The plan's own zero-moment point stayed on the feet, and they stood flat.
  EXPECT_TRUE(Has(text, "the balance plan's own in 0 %")) << text;
  EXPECT_FALSE(Has(text, "corner")) << text;
}

// The feet not where the plan had them (its own zero-moment point off the standing soles from frame 63)
// and, from frame 69, standing on an edge: shares of the 24 frames of the run (51-74), not of the collapse.
TEST(FallDiagnosis, ThePlanOffTheFeetAndTheSolesOnAnEdge) {
  std::vector<BalanceSample> samples = History(false, 0);
  for (size_t i = 63; i < samples.size(); ++i) samples[i].plan_shortfall = 0.03;
  for (size_t i = 69; i < samples.size(); ++i) samples[i].support_points = 2;
  const std::string text = DescribeFall(samples, kCap);
  EXPECT_TRUE(Has(text, "the balance plan's own in 50 % (the standing soles were not where the plan had the feet)")) << text;
  EXPECT_TRUE(Has(text, "at one or two points (a corner or an edge) in 25 %")) << text;
}

// The reference turning: 60 deg/s from 0.2 s on, its heading given in (-180, 180] and crossing 180 deg at
// 0.37 s (so the summary must unwrap it), against the run 0.51-0.74 s (14 deg) and the second before it
// (here all of 0-0.51 s: 19 deg).
TEST(FallDiagnosis, HowFarTheReferenceTurned) {
  std::vector<BalanceSample> samples = History(false, 0);
  for (BalanceSample& sample : samples) {
    sample.reference_heading = std::remainder(170.0 + 60.0 * std::max(0.0, sample.time - 0.2), 360.0);
  }
  const std::string text = DescribeFall(samples, kCap);
  EXPECT_TRUE(Has(text, "the reference itself turned 14 deg over that run and 19 deg in the 0.51 s before it")) << text;
  // A reference walking straight: 0 deg, however far its heading is from zero.
  for (BalanceSample& sample : samples) sample.reference_heading = -170.0;
  EXPECT_TRUE(Has(DescribeFall(samples, kCap), "turned 0 deg over that run and 0 deg in the 0.51 s before it"));
}

TEST(FallDiagnosis, AStepPastItsCap) {
  const std::string past = DescribeFall(History(true, 0.45), kCap);
  EXPECT_TRUE(Has(past, "landing shifts of up to 0.45 m (past the 0.30 m cap)")) << past;
  EXPECT_FALSE(Has(past, "planted")) << past;
  const std::string within = DescribeFall(History(true, 0.2), kCap);
  EXPECT_TRUE(Has(within, "(within the 0.30 m cap)")) << within;
  // A swing held up for seconds predicts an error of metres: no number pretends to be a step.
  const std::string beyond = DescribeFall(History(true, 104.0), kCap);
  EXPECT_TRUE(Has(beyond, "landing shifts of more than 1.00 m")) << beyond;
}

// Where the feet landed against where the stepping aimed them: the landings from a second before the run
// to its end (0.30, 0.55 and 0.60 s here), not the collapse's (0.80 s).
TEST(FallDiagnosis, HowFarTheLandingsStoodFromTheirAims) {
  std::vector<BalanceSample> samples = History(true, 0.2);
  samples[30].landing_miss = 0.05;
  samples[55].landing_miss = 0.08;
  samples[60].landing_miss = 0.12;
  samples[80].landing_miss = 0.9;
  std::string text = DescribeFall(samples, kCap);
  EXPECT_TRUE(Has(text, "; the 3 feet that landed between t = 0.00 and 0.74 s stood up to 0.12 m from where the stepping aimed "
                        "them (median 0.08 m)")) << text;
  samples[30].landing_miss = samples[55].landing_miss = -1;
  text = DescribeFall(samples, kCap);
  EXPECT_TRUE(Has(text, "; the foot that landed between t = 0.00 and 0.74 s stood 0.12 m from where the stepping aimed it")) << text;
  // No landing in that time: nothing said.
  samples[60].landing_miss = -1;
  EXPECT_FALSE(Has(DescribeFall(samples, kCap), "landed")) << DescribeFall(samples, kCap);
}

TEST(FallDiagnosis, OffThePlanFromTheStartAndThenInTheAir) {
  std::vector<BalanceSample> samples = History(false, 0);
  for (BalanceSample& sample : samples) sample.capture_error += 0.2;
  for (size_t i = 95; i < samples.size(); ++i) samples[i].balancing = false;
  const std::string text = DescribeFall(samples, kCap);
  EXPECT_TRUE(Has(text, "off the balance plan from the start (0.21 m at t = 0.00 s)")) << text;
  EXPECT_TRUE(Has(text, "no sole on the floor after t = 0.94 s")) << text;
}

// A fall whose capture point never got past a step's reach before the soles left the floor (CMU 94_15):
// the run reported ends at the last frame with a sole down.
TEST(FallDiagnosis, InTheAirBeforePastReach) {
  std::vector<BalanceSample> samples = History(false, 0);
  for (size_t i = 60; i < samples.size(); ++i) samples[i].balancing = false;
  const std::string text = DescribeFall(samples, kCap);
  EXPECT_FALSE(Has(text, "past a step's reach")) << text;
  EXPECT_TRUE(Has(text, "left the balance plan at t = 0.51 s (last within 0.05 m of it); from then to t = 0.59 s,"))
      << text;
  EXPECT_TRUE(Has(text, "no sole on the floor after t = 0.59 s")) << text;
}

TEST(FallDiagnosis, NothingToSay) {
  EXPECT_EQ(DescribeFall({}, kCap), "");
  std::vector<BalanceSample> airborne(3);
  EXPECT_EQ(DescribeFall(airborne, kCap), "; no sole was ever on the floor");
}

TEST(FallDiagnosis, ClampedMeansMoreThanRounding) {
  BalanceSample sample;
  sample.zmp_shortfall = 0.004;
  EXPECT_FALSE(ZmpClamped(sample));
  sample.zmp_shortfall = 0.006;
  EXPECT_TRUE(ZmpClamped(sample));
  sample.plan_shortfall = 0.004;
  EXPECT_FALSE(PlanOffTheSoles(sample));
  sample.plan_shortfall = 0.006;
  EXPECT_TRUE(PlanOffTheSoles(sample));
}

}  // namespace
}  // namespace syn
