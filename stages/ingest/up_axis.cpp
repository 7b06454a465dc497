#include "stages/ingest/up_axis.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <vector>

namespace syn {
namespace {

// The value at fraction `q` of the sorted values (nearest rank); `values` is reordered.
double Quantile(std::vector<double>& values, double q) {
  const size_t k = std::min(values.size() - 1, static_cast<size_t>(q * static_cast<double>(values.size() - 1) + 0.5));
  std::nth_element(values.begin(), values.begin() + static_cast<std::ptrdiff_t>(k), values.end());
  return values[k];
}

struct Cue {
  int best = -1;     // axis index the cue points at, -1 if not decisive
  int ranked[3] = {0, 1, 2};
  std::array<double, 3> value{};
};

std::string Metres(double value) {
  char text[32];
  std::snprintf(text, sizeof text, "%.2f m", value);
  return text;
}

}  // namespace

UpAxisDecision DecideUpAxis(const MarkerData& data, char convention, double unit_to_m) {
  UpAxisDecision decision;
  const char fallback = (convention == 'x' || convention == 'y' || convention == 'z') ? convention : 'z';
  decision.axis = fallback;
  const std::string convention_text =
      fallback == convention ? std::string("the format's convention (") + convention + " up)" : "Z (the file does not say)";

  // Per frame: lowest and highest coordinate along each axis, over markers and body/joint positions.
  const size_t markers = data.labels.size(), bodies = data.bodies.size();
  std::array<std::vector<double>, 3> extent, lowest;
  for (int a = 0; a < 3; ++a) extent[a].reserve(data.time_s.size()), lowest[a].reserve(data.time_s.size());
  for (size_t t = 0; t < data.time_s.size(); ++t) {
    std::array<double, 3> lo{INFINITY, INFINITY, INFINITY}, hi{-INFINITY, -INFINITY, -INFINITY};
    int64_t count = 0;
    const auto add = [&](const double* p) {
      if (!std::isfinite(p[0]) || !std::isfinite(p[1]) || !std::isfinite(p[2])) return;
      ++count;
      for (int a = 0; a < 3; ++a) lo[a] = std::min(lo[a], p[a]), hi[a] = std::max(hi[a], p[a]);
    };
    if (data.points.size() >= (t + 1) * markers * 3) {
      for (size_t m = 0; m < markers; ++m) add(&data.points[(t * markers + m) * 3]);
    }
    if (data.body_pose.size() >= (t + 1) * bodies * 7) {
      for (size_t b = 0; b < bodies; ++b) add(&data.body_pose[(t * bodies + b) * 7]);
    }
    if (count < kUpAxisMinPoints) continue;
    for (int a = 0; a < 3; ++a) {
      extent[a].push_back((hi[a] - lo[a]) * unit_to_m);
      lowest[a].push_back(lo[a] * unit_to_m);
    }
  }
  if (static_cast<int64_t>(extent[0].size()) < kUpAxisMinFrames) {
    decision.reason = convention_text + ": too few points to tell from the data";
    return decision;
  }

  Cue tall, floor;
  for (int a = 0; a < 3; ++a) {
    tall.value[a] = Quantile(extent[a], 0.5);
    floor.value[a] = Quantile(lowest[a], 0.9) - Quantile(lowest[a], 0.1);
  }
  std::sort(tall.ranked, tall.ranked + 3, [&](int i, int j) { return tall.value[i] > tall.value[j]; });
  std::sort(floor.ranked, floor.ranked + 3, [&](int i, int j) { return floor.value[i] < floor.value[j]; });
  if (tall.value[tall.ranked[0]] >= kExtentRatio * tall.value[tall.ranked[1]] &&
      tall.value[tall.ranked[0]] >= kMinBodyExtentM) {
    tall.best = tall.ranked[0];
  }
  const double floor_second = floor.value[floor.ranked[1]];
  if (floor.value[floor.ranked[0]] <= kFloorFlatM && floor_second >= kFloorTravelM &&
      floor_second >= kFloorRatio * floor.value[floor.ranked[0]]) {
    floor.best = floor.ranked[0];
  }
  const auto name = [](int axis) { return static_cast<char>('x' + axis); };
  const std::string tall_text = std::string("extent ") + name(tall.ranked[0]) + " " + Metres(tall.value[tall.ranked[0]]) +
                                " vs " + name(tall.ranked[1]) + " " + Metres(tall.value[tall.ranked[1]]);
  const std::string floor_text = std::string("lowest point spreads ") + Metres(floor.value[floor.ranked[0]]) + " along " +
                                 name(floor.ranked[0]) + " vs " + Metres(floor_second) + " along " + name(floor.ranked[1]);
  if (tall.best >= 0 && floor.best >= 0 && tall.best != floor.best) {
    decision.reason = convention_text + ": the data's cues disagree (" + tall_text + "; " + floor_text + ")";
    return decision;
  }
  if (tall.best < 0 && floor.best < 0) {
    decision.reason = convention_text + ": the data cannot tell (" + tall_text + "; " + floor_text + ")";
    return decision;
  }
  decision.from_data = true;
  if (tall.best >= 0 && floor.best >= 0) {
    decision.axis = name(tall.best);
    decision.reason = "data: " + tall_text + "; " + floor_text;
  } else if (tall.best >= 0) {
    decision.axis = name(tall.best);
    decision.reason = "data: " + tall_text + " (the floor cue cannot tell)";
  } else {
    decision.axis = name(floor.best);
    decision.reason = "data: " + floor_text + " (the extent cue cannot tell)";
  }
  return decision;
}

}  // namespace syn
