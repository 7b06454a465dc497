// The human-vs-robot power table: one row per trial from the labels in its
// synergies file and the trial-level power of two syn-evaluate JSON files.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <string>

#include "common/error.h"
#include "common/file_bytes.h"
#include "common/intermediate_file.h"
#include "stages/summary/summary_tables.h"
#include "stages/synergies/synergies.h"

namespace syn {
namespace {

namespace fs = std::filesystem;

class PowerRatioTable : public ::testing::Test {
 protected:
  void SetUp() override {
    directory_ = fs::temp_directory_path() / ("syn_power_ratio_" + std::to_string(::getpid()));
    fs::create_directories(directory_);
    // (Labels assigned from strings, not literals: GCC 12 warns falsely on a short literal here.)
    const std::string trial = "02_01", subject = "02", motion_class = "walk";
    SynergyLabels options;
    options.trial = trial;
    options.subject = subject;
    options.motion_class = motion_class;
    IntermediateWriter writer(path("synergies.h5"),
                              {kSynergiesSchema, kSynergiesSchemaVersion, "test", options.ToJson(), nlohmann::json::array()});
    WriteTrialSynergies(writer, TrialSynergies{}, options);
    writer.commit();
  }
  void TearDown() override { fs::remove_all(directory_); }

  std::string path(const std::string& name) const { return (fs::path(directory_) / name).string(); }
  std::string metrics(const std::string& name, const std::string& trial_object) const {
    WriteFileAtomically(path(name), "{\"trial\": " + trial_object + "}");
    return path(name);
  }

  std::string directory_;
};

TEST_F(PowerRatioTable, RowHoldsBothPowersAndTheirRatio) {
  const std::string robot = metrics("robot.json", "{\"mean_power_w_per_kg\": 7.5}");
  const std::string human = metrics("human.json", "{\"mean_power_w_per_kg\": 2.5}");
  WritePowerRatioTable({path("synergies.h5")}, {robot}, {human}, path("ratio.csv"));
  EXPECT_EQ(ReadFileText(path("ratio.csv")),
            "trial,subject,motion_class,human_w_per_kg,robot_w_per_kg,robot_over_human\n"
            "02_01,02,walk,2.5,7.5,3\n");
}

TEST_F(PowerRatioTable, MetricsWithoutPowerNameTheFileAndWriteNothing) {
  const std::string robot = metrics("robot.json", "{\"mean_power_w_per_kg\": 7.5}");
  const std::string human = metrics("human.json", "{\"mean_delta_p\": 0.1}");
  try {
    WritePowerRatioTable({path("synergies.h5")}, {robot}, {human}, path("ratio.csv"));
    FAIL() << "expected an error";
  } catch (const DataError& error) {
    EXPECT_NE(std::string(error.what()).find("human.json"), std::string::npos) << error.what();
    EXPECT_NE(std::string(error.what()).find("mean_power_w_per_kg"), std::string::npos) << error.what();
  }
  EXPECT_FALSE(fs::exists(path("ratio.csv")));
}

TEST_F(PowerRatioTable, ListsOfDifferentLengthsAreAUsageError) {
  const std::string robot = metrics("robot.json", "{\"mean_power_w_per_kg\": 7.5}");
  EXPECT_THROW(WritePowerRatioTable({path("synergies.h5")}, {robot}, {}, path("ratio.csv")), UsageError);
}

}  // namespace
}  // namespace syn
