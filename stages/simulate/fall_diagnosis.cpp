#include "stages/simulate/fall_diagnosis.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <string>
#include <vector>

#include "common/percentile.h"

namespace syn {
namespace {

constexpr double kClamped = 0.005;  // m
// m: a capture point this close to the plan's counts as on it.
constexpr double kOnThePlan = 0.05;
// m: a landing shift past any leg's reach (a dance's foot held up for a second predicts metres).
constexpr double kBeyondAnyStep = 1.0;
// s: the lead-up before the run whose turning the summary also reports (about two steps of a walk).
constexpr double kLeadUp = 1.0;

// deg: how far the reference's heading ranged over samples [first, last], unwrapped (a turn through
// ±180 deg counts as the turn it is: frames are far closer than half a turn apart).
double ReferenceTurn(const std::vector<BalanceSample>& samples, size_t first, size_t last) {
  double heading = 0, lowest = 0, highest = 0;
  for (size_t i = first + 1; i <= last; ++i) {
    heading += std::remainder(samples[i].reference_heading - samples[i - 1].reference_heading, 360.0);
    lowest = std::min(lowest, heading);
    highest = std::max(highest, heading);
  }
  return highest - lowest;
}

}  // namespace

bool ZmpClamped(const BalanceSample& sample) { return sample.zmp_shortfall > kClamped; }

bool PlanOffTheSoles(const BalanceSample& sample) { return sample.plan_shortfall > kClamped; }

std::string DescribeFall(const std::vector<BalanceSample>& samples, double step_cap) {
  size_t last = samples.size();  // the last frame with a sole on the floor
  for (size_t i = samples.size(); i-- > 0;) {
    if (samples[i].balancing) {
      last = i;
      break;
    }
  }
  if (last == samples.size()) return samples.empty() ? "" : "; no sole was ever on the floor";
  std::ostringstream out;
  out.precision(2);
  out << std::fixed;
  // The run that ends in the fall: from the last frame the capture point was on the plan to the first
  // after it past a step's reach (what follows is the collapse, not its cause).
  size_t onset = last;
  while (onset > 0 && !(samples[onset - 1].balancing && samples[onset - 1].capture_error <= kOnThePlan)) --onset;
  size_t lost = onset;
  while (lost < last && samples[lost].capture_error <= step_cap) ++lost;
  if (onset == 0 && !(samples[0].capture_error <= kOnThePlan)) {
    out << "; the capture point was off the balance plan from the start (" << samples[0].capture_error << " m at t = "
        << samples[0].time << " s)";
  } else {
    out << "; the capture point left the balance plan at t = " << samples[onset].time << " s (last within "
        << kOnThePlan << " m of it)";
  }
  const bool past_reach = samples[lost].capture_error > step_cap;
  if (past_reach) out << " and was past a step's reach (" << step_cap << " m) at t = " << samples[lost].time << " s";
  int frames = 0, clamped = 0, planted_still = 0, plan_off = 0, on_an_edge = 0;
  double shortfall = 0, landing = 0, yaw = 0, heading = 0;
  std::vector<double> tilt;
  for (size_t i = onset; i <= lost; ++i) {
    const BalanceSample& sample = samples[i];
    ++frames;
    if (ZmpClamped(sample)) ++clamped;
    if (PlanOffTheSoles(sample)) ++plan_off;
    if (sample.balancing && sample.support_points <= 2) ++on_an_edge;
    if (sample.standing_both && !sample.stepping) ++planted_still;
    shortfall = std::max(shortfall, sample.zmp_shortfall);
    landing = std::max(landing, sample.landing_needed);
    yaw = std::max(yaw, std::abs(sample.unexplained_yaw));
    tilt.push_back(sample.unexplained_tilt);
    heading = std::max(heading, std::abs(sample.heading_error));
  }
  if (past_reach) {
    out << "; in between";
  } else {
    out << "; from then to t = " << samples[lost].time << " s";
  }
  out << ", the zero-moment point it needed lay outside the standing soles in " << 100 * clamped / frames
      << " % of the frames (by up to " << shortfall << " m), the balance plan's own in " << 100 * plan_off / frames << " %";
  if (plan_off > 0) out << " (the standing soles were not where the plan had the feet)";
  if (on_an_edge > 0) {
    out << ", the standing soles touched the floor at one or two points (a corner or an edge) in " << 100 * on_an_edge / frames
        << " %";
  }
  if (landing > kBeyondAnyStep) {
    out << ", the steps under way needed landing shifts of more than " << kBeyondAnyStep << " m (the cap is " << step_cap
        << " m)";
  } else if (landing > 0) {
    out << ", the steps under way needed landing shifts of up to " << landing << " m ("
        << (landing > step_cap ? "past" : "within") << " the " << step_cap << " m cap)";
  }
  if (planted_still > 0) out << ", both feet stayed planted in the source for " << 100 * planted_still / frames << " % of it";
  out.precision(0);
  out << ", up to " << *std::max_element(tilt.begin(), tilt.end()) << " N·m of the tilting moment planned no sole gave (median "
      << NearestRankPercentile(tilt, 0.5) << ") and up to " << yaw
      << " N·m of the yaw moment, and the pelvis turned up to " << heading << " deg off the reference's heading";
  size_t lead_up = onset;
  while (lead_up > 0 && samples[lead_up - 1].time >= samples[onset].time - kLeadUp) --lead_up;
  out << "; the reference itself turned " << ReferenceTurn(samples, onset, lost) << " deg over that run";
  if (lead_up < onset) {
    out << " and " << ReferenceTurn(samples, lead_up, onset) << " deg in the ";
    out.precision(2);
    out << samples[onset].time - samples[lead_up].time << " s before it";
  }
  std::vector<double> misses;
  for (size_t i = lead_up; i <= lost; ++i) {
    if (samples[i].landing_miss >= 0) misses.push_back(samples[i].landing_miss);
  }
  if (!misses.empty()) {
    out.precision(2);
    out << "; " << (misses.size() == 1 ? "the foot" : "the " + std::to_string(misses.size()) + " feet") << " that landed between t = "
        << samples[lead_up].time << " and " << samples[lost].time << " s stood ";
    if (misses.size() == 1) {
      out << misses[0] << " m from where the stepping aimed it";
    } else {
      out << "up to " << *std::max_element(misses.begin(), misses.end()) << " m from where the stepping aimed them (median "
          << NearestRankPercentile(misses, 0.5) << " m)";
    }
  }
  if (last + 1 < samples.size()) {
    out.precision(2);
    out << "; no sole on the floor after t = " << samples[last].time << " s";
  }
  return out.str();
}

}  // namespace syn
