// syn-studio's API over loopback HTTP: the motion a script composes to is syn-compose's (same q to 1e-12),
// the metrics are syn-evaluate's at the studio's grid, and broken, unknown, huge and oversized requests get
// 400/413 with a message while the server goes on serving.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <thread>

#include "common/file_bytes.h"
#include "common/motion_file.h"
#include "stages/library/style_library.h"
#include "stages/segment/segmentation.h"
#include "stages/synergies/synergies.h"
#include "tests/support/demo_motion.h"
#include "tests/support/run_command.h"
#include "tests/support/shared_data.h"
#include "tools/studio/studio.h"
#include "tools/studio/studio_server.h"

// Last: httplib.h includes <resolv.h>, whose `_res` macro breaks Eigen headers included after it.
#include <httplib.h>

namespace syn {
namespace {

namespace fs = std::filesystem;

// A library of the demo's modern-dance trial on G1 and a studio serving it on a free loopback port.
class StudioApiTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    const Model model = Model::Load(testing::SourcePath(testing::kG1Urdf));
    const MotionData& motion = testing::DemoMotionOnG1("05_02");
    LabelledTrial trial;
    trial.labels.trial = "05_02";
    trial.labels.style = "modern";
    trial.synergies = ComputeTrialSynergies(motion, SegmentMotion(motion, model, {}).boundaries,
                                            SynergyOptions{3, VelocitySet::kAll, trial.labels});
    dir_ = new std::string(fs::temp_directory_path() / ("syn_studio_" + std::to_string(::getpid())));
    fs::create_directories(*dir_);
    IntermediateWriter writer(*dir_ + "/library.h5",
                              {kLibrarySchema, kLibrarySchemaVersion, "test", {}, nlohmann::json::array()});
    WriteLibrary(writer, BuildLibrary({trial}, {"05_02"}, 3));
    writer.commit();

    StudioOptions options;
    options.port = 0;
    options.max_body_bytes = 4096;
    options.max_motion_seconds = 30;
    options.max_pieces = 20;
    studio_ = new Studio(*dir_ + "/library.h5", testing::SourcePath(testing::kG1Urdf),
                         testing::SourcePath(testing::kG1Map), options);
    server_ = new StudioServer(*studio_,
                               StudioPage{"<html>page</html>", "// js", "/* css */", "// player", "// three"}, "");
    port_ = server_->bind();
    thread_ = new std::thread([] { server_->run(); });
  }
  static void TearDownTestSuite() {
    server_->stop();
    thread_->join();
    delete thread_;
    delete server_;
    delete studio_;
    fs::remove_all(*dir_);
    delete dir_;
  }

  static httplib::Result Post(const std::string& body) {
    httplib::Client client("127.0.0.1", port_);
    client.set_read_timeout(60, 0);
    return client.Post("/api/compose", body, "application/toml");
  }
  static std::string ModelPath() { return testing::SourcePath(testing::kG1Urdf); }
  // Two of the trial's segments: keyframed gains, a tempo change, repetitions, two interpolations.
  static std::string TwoStepScript() {
    return "model = \"" + ModelPath() + "\"\n"
           "start = { synergy = \"modern/05_02/0\" }\n"
           "[[step]]\n"
           "synergy = \"modern/05_02/0\"\n"
           "repetitions = 2\n"
           "gain = [0.8, 1.1, 0.9]\n"
           "blend = 0.2\n"
           "[[step]]\n"
           "synergy = \"modern/05_02/1\"\n"
           "duration = 1.1\n"
           "interpolation = \"cubic\"\n"
           "[[step.keyframe]]\n"
           "at = 0.0\n"
           "gain = [0.6, 1.0, 1.0]\n"
           "[[step.keyframe]]\n"
           "at = 0.7\n"
           "gain = [1.3, 1.0, 1.0]\n";
  }
  static void ExpectStillServing() {
    httplib::Client client("127.0.0.1", port_);
    const httplib::Result library = client.Get("/api/library");
    ASSERT_TRUE(library) << "the server stopped answering";
    EXPECT_EQ(library->status, 200);
    const httplib::Result composed = Post(TwoStepScript());
    ASSERT_TRUE(composed);
    EXPECT_EQ(composed->status, 200) << composed->body;
  }

  static std::string* dir_;
  static Studio* studio_;
  static StudioServer* server_;
  static std::thread* thread_;
  static int port_;
};
std::string* StudioApiTest::dir_ = nullptr;
Studio* StudioApiTest::studio_ = nullptr;
StudioServer* StudioApiTest::server_ = nullptr;
std::thread* StudioApiTest::thread_ = nullptr;
int StudioApiTest::port_ = 0;

TEST_F(StudioApiTest, ComposeRoundTripIsSynComposesMotionAndSynEvaluatesMetrics) {
  const httplib::Result reply = Post(TwoStepScript());
  ASSERT_TRUE(reply);
  ASSERT_EQ(reply->status, 200) << reply->body;
  const nlohmann::json studio = nlohmann::json::parse(reply->body);

  // The same script through the batch tools.
  const std::string script = *dir_ + "/two_steps.toml", motion_path = *dir_ + "/two_steps.motion.h5",
                    metrics_path = *dir_ + "/two_steps.metrics.json";
  std::ofstream(script) << TwoStepScript();
  const testing::CommandResult composed = testing::RunCommand(testing::BinPath("syn-compose") + " " + script +
                                                              " --library " + *dir_ + "/library.h5 -o " + motion_path);
  ASSERT_EQ(composed.exit_code, 0) << composed.output;
  const MotionData batch = ReadMotionFile(motion_path);

  const std::vector<double> time = studio["time"];
  ASSERT_EQ(time.size(), batch.time_s.size());
  ASSERT_EQ(studio["q"].size(), static_cast<size_t>(batch.frames()));
  double largest_q = 0, largest_t = 0;
  for (int64_t k = 0; k < batch.frames(); ++k) {
    largest_t = std::max(largest_t, std::abs(time[static_cast<size_t>(k)] - batch.time_s[static_cast<size_t>(k)]));
    const std::vector<double> row = studio["q"][static_cast<size_t>(k)];
    ASSERT_EQ(static_cast<int64_t>(row.size()), batch.nq());
    for (int64_t i = 0; i < batch.nq(); ++i) {
      largest_q = std::max(largest_q, std::abs(row[static_cast<size_t>(i)] - batch.q[static_cast<size_t>(k * batch.nq() + i)]));
    }
  }
  EXPECT_LE(largest_t, 1e-12);
  EXPECT_LE(largest_q, 1e-12);
  EXPECT_EQ(studio["coordinate_names"].get<std::vector<std::string>>(), batch.coordinate_names);
  ASSERT_EQ(studio["steps"].size(), 2u);
  EXPECT_EQ(studio["steps"][1]["line"], 8);

  // syn-evaluate at the studio's grid and feet gives the same trial metrics.
  const testing::CommandResult evaluated = testing::RunCommand(
      testing::BinPath("syn-evaluate") + " " + motion_path + " --model " + ModelPath() + " --robot-map " +
      testing::SourcePath(testing::kG1Map) + " --eval-rate " + std::to_string(studio_->options().eval_rate) +
      " -o " + metrics_path);
  ASSERT_EQ(evaluated.exit_code, 0) << evaluated.output;
  const nlohmann::json trial = nlohmann::json::parse(ReadFileText(metrics_path))["trial"];
  const nlohmann::json& metrics = studio["metrics"];
  EXPECT_NEAR(metrics["delta_p"].get<double>(), trial["mean_delta_p"].get<double>(), 1e-9);
  EXPECT_NEAR(metrics["delta_ke"].get<double>(), trial["mean_delta_ke"].get<double>(), 1e-9);
  EXPECT_NEAR(metrics["power_w_per_kg"].get<double>(), trial["mean_power_w_per_kg"].get<double>(), 1e-9);
  EXPECT_NEAR(metrics["foot_sliding_ratio"].get<double>(), trial["foot_sliding_ratio"].get<double>(), 1e-12);
  ASSERT_EQ(metrics["steps"].size(), 2u);
  ASSERT_EQ(metrics["series"]["momentum"].size(), time.size());
  // The kinetic energy series (½ uᵀ A u per frame) averages near the evaluation grid's mean KE (same motion,
  // other instants): a check that the plots show this motion.
  double kinetic = 0;
  for (double value : metrics["series"]["kinetic_energy"]) kinetic += value;
  kinetic /= static_cast<double>(time.size());
  EXPECT_NEAR(kinetic, trial["mean_kinetic_energy"].get<double>(), 0.1 * trial["mean_kinetic_energy"].get<double>());
}

TEST_F(StudioApiTest, LibraryListsStylesSegmentsAndSigma) {
  httplib::Client client("127.0.0.1", port_);
  const httplib::Result reply = client.Get("/api/library");
  ASSERT_TRUE(reply);
  ASSERT_EQ(reply->status, 200);
  const nlohmann::json library = nlohmann::json::parse(reply->body);
  ASSERT_EQ(library["styles"].size(), 1u);
  EXPECT_EQ(library["styles"][0]["name"], "modern");
  EXPECT_EQ(library["model"], ModelPath());
  const LibraryReader reader(*dir_ + "/library.h5");
  const nlohmann::json& segments = library["styles"][0]["segments"];
  ASSERT_EQ(segments.size(), reader.synergyNames().size());
  for (const nlohmann::json& segment : segments) {
    const LibrarySynergy synergy = reader.read(segment["name"]);
    const std::vector<double> sigma = segment["sigma"];
    ASSERT_EQ(static_cast<Eigen::Index>(sigma.size()), synergy.segment.synergies.singular_values.size());
    for (size_t i = 0; i < sigma.size(); ++i) EXPECT_EQ(sigma[i], synergy.segment.synergies.singular_values[static_cast<Eigen::Index>(i)]);
    EXPECT_EQ(segment["duration_s"].get<double>(), synergy.segment.duration);
  }
}

// Each bad request: its status and message, then the server answers a good one.
TEST_F(StudioApiTest, BadScriptsGet400WithTheirLineAndTheServerGoesOn) {
  struct Case {
    std::string what, body, expected;
  };
  const std::string head = "model = \"" + ModelPath() + "\"\n";
  const std::vector<Case> cases = {
      {"malformed TOML", head + "[[step]]\nsynergy = \"modern/05_02/0\nrepetitions = 2\n", "script.toml:3"},
      {"unknown segment", head + "[[step]]\nsynergy = \"salsa/60_10/9\"\n", "script.toml:2"},
      {"huge repetitions", head + "[[step]]\nsynergy = \"modern/05_02/0\"\nrepetitions = 1000000000\n",
       "script.toml:4: repetitions must be at most"},
      {"more repetitions than the studio composes",
       head + "[[step]]\nsynergy = \"modern/05_02/0\"\nduration = 0.1\nrepetitions = 21\n", "--max-pieces"},
      {"repetitions past 32 bits", head + "[[step]]\nsynergy = \"modern/05_02/0\"\nrepetitions = 4294967297\n",
       "script.toml:4: repetitions must be at most"},
      {"too long", head + "[[step]]\nsynergy = \"modern/05_02/0\"\nduration = 1000.0\n", "--max-motion-seconds"},
      {"another robot", "model = \"/etc/hostname\"\n[[step]]\nsynergy = \"modern/05_02/0\"\n", "not the studio's robot"},
      {"wrong coefficient count", head + "[[step]]\nsynergy = \"modern/05_02/0\"\ngain = [1.0]\n", "script.toml:"},
  };
  for (const Case& bad : cases) {
    SCOPED_TRACE(bad.what);
    const httplib::Result reply = Post(bad.body);
    ASSERT_TRUE(reply);
    EXPECT_EQ(reply->status, 400);
    const std::string message = nlohmann::json::parse(reply->body).value("error", "");
    EXPECT_NE(message.find(bad.expected), std::string::npos) << message;
    ExpectStillServing();
  }
}

TEST_F(StudioApiTest, OversizedBodyGets413AndTheServerGoesOn) {
  const std::string body = TwoStepScript() + "# " + std::string(studio_->options().max_body_bytes, 'x') + "\n";
  const httplib::Result reply = Post(body);
  ASSERT_TRUE(reply);
  EXPECT_EQ(reply->status, 413);
  EXPECT_NE(reply->body.find("--max-body-bytes"), std::string::npos) << reply->body;
  ExpectStillServing();
}

TEST_F(StudioApiTest, ServesThePageAndSaysWhatIsMissing) {
  httplib::Client client("127.0.0.1", port_);
  const httplib::Result page = client.Get("/");
  ASSERT_TRUE(page);
  EXPECT_EQ(page->body, "<html>page</html>");
  const httplib::Result missing = client.Get("/nothing-here");
  ASSERT_TRUE(missing);
  EXPECT_EQ(missing->status, 404);
  EXPECT_NE(missing->body.find("/nothing-here"), std::string::npos);
}

}  // namespace
}  // namespace syn
