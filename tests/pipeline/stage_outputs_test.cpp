// What the syn-* tools write, checked from the files themselves: metrics.json and syn-evaluate --csv against
// sums computed here from the motion file, the summary CSVs against metrics.json, syn-export --rate against an
// independent natural cubic spline and .mot's degrees, and outputs that do not depend on the working folder or
// the output's name. One short bundled capture (datasets/demo/14_14_excerpt.bvh) runs through every stage
// once per test process (tests/pipeline/stage_chain.h).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "common/model.h"
#include "common/motion_file.h"
#include "common/segments_file.h"
#include "tests/pipeline/stage_chain.h"
#include "tests/support/demo_motion.h"
#include "tests/support/run_command.h"
#include "tests/support/shared_data.h"

namespace syn::testing {
namespace {

namespace fs = std::filesystem;

std::string ReadText(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

// Rows of a CSV without quoted fields (ours quote only labels with commas, which these have not).
std::vector<std::vector<std::string>> ReadCsv(const std::string& path, char separator = ',') {
  std::vector<std::vector<std::string>> rows;
  std::istringstream lines(ReadText(path));
  for (std::string line; std::getline(lines, line);) {
    std::vector<std::string> cells;
    std::string cell;
    std::istringstream fields(line);
    while (std::getline(fields, cell, separator)) cells.push_back(cell);
    if (!line.empty() && line.back() == separator) cells.emplace_back();
    rows.push_back(cells);
  }
  return rows;
}

int Column(const std::vector<std::string>& header, const std::string& name) {
  for (size_t i = 0; i < header.size(); ++i) {
    if (header[i] == name) return static_cast<int>(i);
  }
  ADD_FAILURE() << "no column " << name;
  return 0;
}

// Mean |p_k - p_(k-1)|, mean |KE_k - KE_(k-1)| and mean KE over frames [first, last] of the motion file's own
// samples, p = A(q) u (the evaluation grid is put on those samples by --eval-rate).
struct Means {
  double delta_p = 0, delta_ke = 0, kinetic = 0;
};
Means MeansOver(const MotionData& motion, const Model& model, int64_t first, int64_t last) {
  Workspace workspace(model);
  const int64_t nq = model.nq(), nu = model.nu();
  Eigen::VectorXd p(nu), p_before(nu);
  double kinetic_before = 0;
  Means means;
  for (int64_t t = first; t <= last; ++t) {
    workspace.setQ(Eigen::Map<const Eigen::VectorXd>(&motion.q[static_cast<size_t>(t * nq)], nq));
    const Eigen::Map<const Eigen::VectorXd> u(&motion.u[static_cast<size_t>(t * nu)], nu);
    workspace.calcMassTimes(u, p);
    const double kinetic = 0.5 * u.dot(p);
    means.kinetic += kinetic;
    if (t > first) {
      means.delta_p += (p - p_before).norm();
      means.delta_ke += std::abs(kinetic - kinetic_before);
    }
    p_before = p;
    kinetic_before = kinetic;
  }
  means.kinetic /= static_cast<double>(last - first + 1);
  means.delta_p /= static_cast<double>(last - first);
  means.delta_ke /= static_cast<double>(last - first);
  return means;
}

void ExpectRelativelyNear(double actual, double expected, double tolerance, const std::string& what) {
  EXPECT_NEAR(actual, expected, tolerance * std::max(1.0, std::abs(expected))) << what;
}

TEST(StageOutputs, MetricsJsonAndEvaluateCsvMatchSumsMadeFromTheMotionFile) {
  const StageChain& chain = Chain();
  const Model model = Model::Load(SourcePath(kG1Urdf));
  const MotionData motion = ReadMotionFile(chain.motion);
  const nlohmann::json metrics = nlohmann::json::parse(ReadText(chain.metrics));
  EXPECT_EQ(metrics["motion"]["frames"].get<int64_t>(), motion.frames());
  EXPECT_NEAR(metrics["motion"]["duration_s"].get<double>(), motion.time_s.back() - motion.time_s.front(), 1e-12);
  EXPECT_NEAR(metrics["model"]["total_mass_kg"].get<double>(), model.totalMass(), 1e-9);
  EXPECT_EQ(metrics["trial"]["eval_frames"].get<int64_t>(), motion.frames()) << "the grid should be the samples";

  const Means whole = MeansOver(motion, model, 0, motion.frames() - 1);
  ExpectRelativelyNear(metrics["trial"]["mean_delta_p"].get<double>(), whole.delta_p, 1e-7, "trial mean dP");
  ExpectRelativelyNear(metrics["trial"]["mean_delta_ke"].get<double>(), whole.delta_ke, 1e-7, "trial mean dKE");
  ExpectRelativelyNear(metrics["trial"]["mean_kinetic_energy"].get<double>(), whole.kinetic, 1e-7, "trial mean KE");
  const double sliding = metrics["trial"]["foot_sliding_ratio"].get<double>();
  EXPECT_GE(sliding, 0.0);
  EXPECT_LE(sliding, 1.0);

  // Per segment, in metrics.json and in the --csv file, against the segments file's frame ranges.
  const SegmentsData segments = ReadSegmentsFile(chain.segments);
  const auto rows = ReadCsv(chain.evaluate_csv);
  ASSERT_GE(rows.size(), 2u);
  const std::vector<std::string>& header = rows[0];
  ASSERT_EQ(metrics["segments"].size(), rows.size() - 1);
  ASSERT_EQ(segments.boundaries.size(), rows.size()) << "one row per segment, between consecutive boundaries";
  for (size_t s = 0; s + 1 < rows.size(); ++s) {
    SCOPED_TRACE("segment " + std::to_string(s));
    const std::vector<std::string>& row = rows[s + 1];
    const nlohmann::json& stored = metrics["segments"][s]["stored"];
    const int64_t start = std::stoll(row[Column(header, "start_frame")]);
    const int64_t end = std::stoll(row[Column(header, "end_frame")]);
    EXPECT_EQ(start, segments.boundaries[s]);
    EXPECT_EQ(end, segments.boundaries[s + 1]);
    EXPECT_EQ(std::stoll(row[Column(header, "segment")]), static_cast<int64_t>(s));
    const Means means = MeansOver(motion, model, start, end - 1);
    for (const auto& [key, expected] : std::map<std::string, double>{
             {"mean_delta_p", means.delta_p}, {"mean_delta_ke", means.delta_ke}, {"mean_kinetic_energy", means.kinetic}}) {
      ExpectRelativelyNear(stored[key].get<double>(), expected, 1e-7, "metrics.json " + key);
      ExpectRelativelyNear(std::stod(row[Column(header, key)]), expected, 1e-7, "csv " + key);
    }
    EXPECT_DOUBLE_EQ(std::stod(row[Column(header, "start_s")]), motion.time_s[static_cast<size_t>(start)]);
    EXPECT_DOUBLE_EQ(std::stod(row[Column(header, "end_s")]), motion.time_s[static_cast<size_t>(end - 1)]);
    EXPECT_DOUBLE_EQ(std::stod(row[Column(header, "mean_power_w_per_kg")]), stored["mean_power_w_per_kg"].get<double>());
    EXPECT_EQ(std::stoll(row[Column(header, "mc_components")]), 3);
  }
}

TEST(StageOutputs, SummaryCsvsCarryTheMetricsAndTheSegments) {
  const StageChain& chain = Chain();
  const nlohmann::json metrics = nlohmann::json::parse(ReadText(chain.metrics));
  const MotionData motion = ReadMotionFile(chain.motion);
  const auto trials = ReadCsv(chain.summary_trials);
  ASSERT_EQ(trials.size(), 2u) << "a header and one trial";
  const auto& header = trials[0];
  const auto& row = trials[1];
  EXPECT_EQ(row[Column(header, "trial")], "t");
  EXPECT_EQ(row[Column(header, "style")], "jacks");
  const SegmentsData segments = ReadSegmentsFile(chain.segments);
  EXPECT_EQ(std::stoll(row[Column(header, "segments")]), static_cast<int64_t>(segments.boundaries.size()) - 1);
  // The trials table's duration_s is the sum of its segments' durations (each from its first to its last
  // frame), which is shorter than the motion by one frame interval per boundary between segments.
  double segment_durations = 0;
  for (size_t s = 0; s + 1 < segments.boundaries.size(); ++s) {
    segment_durations += motion.time_s[static_cast<size_t>(segments.boundaries[s + 1] - 1)] -
                         motion.time_s[static_cast<size_t>(segments.boundaries[s])];
  }
  ExpectRelativelyNear(std::stod(row[Column(header, "duration_s")]), segment_durations, 1e-5, "duration_s");
  for (const char* key : {"mean_delta_p", "mean_delta_ke", "mean_power_w_per_kg", "foot_sliding_ratio"}) {
    ExpectRelativelyNear(std::stod(row[Column(header, key)]), metrics["trial"][key].get<double>(), 1e-5, key);
  }
  ExpectRelativelyNear(std::stod(row[Column(header, "rank_k_change_delta_p")]),
                       metrics["monte_carlo"]["mean_rank_k_relative_change_delta_p"].get<double>(), 1e-5,
                       "rank_k_change_delta_p");
  ASSERT_TRUE(metrics["trial"].contains("base_residual")) << "the retargeted motion's contact forces";
  ExpectRelativelyNear(std::stod(row[Column(header, "unexplained_residual_force_n")]),
                       metrics["trial"]["base_residual"]["mean_unexplained_force_n"].get<double>(), 1e-5,
                       "unexplained_residual_force_n");
  ExpectRelativelyNear(std::stod(row[Column(header, "unexplained_residual_moment_nm")]),
                       metrics["trial"]["base_residual"]["mean_unexplained_moment_nm"].get<double>(), 1e-5,
                       "unexplained_residual_moment_nm");

  const auto segment_rows = ReadCsv(chain.summary_segments);
  ASSERT_EQ(segment_rows.size(), segments.boundaries.size()) << "a header and one row per segment";
  for (size_t s = 0; s + 1 < segment_rows.size(); ++s) {
    const auto& cells = segment_rows[s + 1];
    EXPECT_EQ(std::stoll(cells[Column(segment_rows[0], "start_frame")]), segments.boundaries[s]);
    EXPECT_EQ(std::stoll(cells[Column(segment_rows[0], "end_frame")]), segments.boundaries[s + 1]);
    ExpectRelativelyNear(std::stod(cells[Column(segment_rows[0], "duration_s")]),
                         motion.time_s[static_cast<size_t>(segments.boundaries[s + 1] - 1)] -
                             motion.time_s[static_cast<size_t>(segments.boundaries[s])],
                         1e-5, "segment duration_s");
    ExpectRelativelyNear(std::stod(cells[Column(segment_rows[0], "mean_delta_p")]),
                         metrics["segments"][s]["stored"]["mean_delta_p"].get<double>(), 1e-5, "segment mean_delta_p");
    const double pc1 = std::stod(cells[Column(segment_rows[0], "pc1_ratio")]);
    const double pc2 = std::stod(cells[Column(segment_rows[0], "pc2_ratio")]);
    EXPECT_GE(pc1, pc2);
    EXPECT_LE(pc1, 1.0);
  }
}

// A natural cubic spline through (t_i, y_i), written here from the textbook tridiagonal system.
class NaturalSpline {
 public:
  NaturalSpline(std::vector<double> t, std::vector<double> y) : t_(std::move(t)), y_(std::move(y)), m_(t_.size(), 0) {
    const size_t n = t_.size();
    std::vector<double> diagonal(n, 1), upper(n, 0), lower(n, 0), right(n, 0);
    for (size_t i = 1; i + 1 < n; ++i) {
      const double h0 = t_[i] - t_[i - 1], h1 = t_[i + 1] - t_[i];
      lower[i] = h0;
      diagonal[i] = 2 * (h0 + h1);
      upper[i] = h1;
      right[i] = 6 * ((y_[i + 1] - y_[i]) / h1 - (y_[i] - y_[i - 1]) / h0);
    }
    for (size_t i = 1; i < n; ++i) {  // Thomas algorithm
      const double factor = lower[i] / diagonal[i - 1];
      diagonal[i] -= factor * upper[i - 1];
      right[i] -= factor * right[i - 1];
    }
    for (size_t i = n; i-- > 0;) m_[i] = (right[i] - (i + 1 < n ? upper[i] * m_[i + 1] : 0)) / diagonal[i];
  }
  double operator()(double t) const {
    size_t i = 0;
    while (i + 2 < t_.size() && t > t_[i + 1]) ++i;
    const double h = t_[i + 1] - t_[i], a = t_[i + 1] - t, b = t - t_[i];
    return m_[i] * a * a * a / (6 * h) + m_[i + 1] * b * b * b / (6 * h) + (y_[i] / h - m_[i] * h / 6) * a +
           (y_[i + 1] / h - m_[i + 1] * h / 6) * b;
  }

 private:
  std::vector<double> t_, y_, m_;
};

TEST(StageOutputs, ExportRateResamplesWithANaturalCubicAndMotIsInDegrees) {
  const StageChain& chain = Chain();
  const MotionData motion = ReadMotionFile(chain.motion);
  const auto rows = ReadCsv(chain.mot_at_double_rate, '\t');
  // Header: name, version, nRows, nColumns, inDegrees, endheader, column names.
  ASSERT_GT(rows.size(), 7u);
  const int64_t expected_rows =
      static_cast<int64_t>(std::floor((motion.time_s.back() - motion.time_s.front()) * 2 * chain.rate_hz + 1e-9)) + 1;
  EXPECT_EQ(rows[2][0], "nRows=" + std::to_string(expected_rows));
  ASSERT_EQ(static_cast<int64_t>(rows.size()) - 7, expected_rows);
  const std::vector<std::string>& header = rows[6];
  int checked = 0;
  for (const char* joint : {"left_knee_joint", "right_shoulder_pitch_joint", "waist_yaw_joint"}) {
    SCOPED_TRACE(joint);
    int q_index = -1;
    for (size_t i = 0; i < motion.coordinate_names.size(); ++i) {
      if (motion.coordinate_names[i] == joint) q_index = static_cast<int>(i);
    }
    ASSERT_GE(q_index, 0);
    std::vector<double> values;
    for (int64_t t = 0; t < motion.frames(); ++t) values.push_back(motion.q[static_cast<size_t>(t * motion.nq() + q_index)]);
    const NaturalSpline spline(motion.time_s, values);
    const int column = Column(header, joint);
    for (int64_t k = 0; k < expected_rows; ++k) {
      const std::vector<std::string>& row = rows[static_cast<size_t>(7 + k)];
      const double time = motion.time_s.front() + static_cast<double>(k) / (2 * chain.rate_hz);
      ASSERT_NEAR(std::stod(row[0]), time, 1e-9) << "row " << k;
      const double degrees = std::stod(row[static_cast<size_t>(column)]);
      ASSERT_NEAR(degrees, spline(time) * 180.0 / M_PI, 1e-7) << "row " << k;
      if (k % 2 == 0) {  // on a sample of the motion: its own value
        ASSERT_NEAR(degrees, values[static_cast<size_t>(k / 2)] * 180.0 / M_PI, 1e-9) << "row " << k;
      }
      ++checked;
    }
  }
  EXPECT_GT(checked, 100);
}

// The same inputs give the same bytes whatever the working folder and whatever the output is called.
TEST(StageOutputs, OutputsDoNotDependOnTheFolderOrTheOutputName) {
  const StageChain& chain = Chain();
  const std::string base = chain.dir + "/elsewhere";
  fs::create_directories(base + "/a");
  fs::create_directories(base + "/b/deeper");
  for (const char* folder : {"/a/", "/b/"}) {
    fs::copy_file(SourcePath("datasets/demo/14_14_excerpt.bvh"), base + folder + "capture.bvh");
    fs::copy_file(chain.motion, base + folder + "motion.h5");
    fs::copy_file(SourcePath(kG1Urdf), base + folder + "g1.urdf");
  }
  const auto run_in = [&](const std::string& folder, const std::string& command) {
    const CommandResult result = RunCommand("cd " + base + folder + " && " + command);
    EXPECT_EQ(result.exit_code, 0) << command << "\n" << result.output;
  };
  run_in("/a", BinPath("syn-ingest") + " capture.bvh -o first.markers.h5");
  run_in("/b", BinPath("syn-ingest") + " capture.bvh -o deeper/other-name.h5");
  EXPECT_EQ(ReadText(base + "/a/first.markers.h5"), ReadText(base + "/b/deeper/other-name.h5")) << "syn-ingest";
  run_in("/a", BinPath("syn-segment") + " motion.h5 --model g1.urdf -o s.h5");
  run_in("/b", BinPath("syn-segment") + " motion.h5 --model g1.urdf -o deeper/segments-elsewhere.h5");
  EXPECT_EQ(ReadText(base + "/a/s.h5"), ReadText(base + "/b/deeper/segments-elsewhere.h5")) << "syn-segment";
  run_in("/a", BinPath("syn-evaluate") + " motion.h5 --model g1.urdf -o m.json --eval-rate 200");
  run_in("/b", BinPath("syn-evaluate") + " motion.h5 --model g1.urdf -o deeper/x.json --eval-rate 200");
  EXPECT_EQ(ReadText(base + "/a/m.json"), ReadText(base + "/b/deeper/x.json")) << "syn-evaluate";
  EXPECT_FALSE(ReadText(base + "/a/m.json").empty());
}

}  // namespace
}  // namespace syn::testing
