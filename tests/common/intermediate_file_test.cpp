#include "common/intermediate_file.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>

#include "common/error.h"
#include "tests/support/scratch_file.h"

namespace syn {
namespace {

std::string TempPath(const std::string& name) {
  return (testing::ProcessScratchDir("syn_test_") / name).string();
}

std::string Bytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

Provenance TestProvenance(int64_t version) {
  Provenance provenance;
  provenance.schema = "synsculpt.test";
  provenance.schema_version = version;
  provenance.producer = "intermediate_file_test";
  provenance.parameters = {{"threshold", 0.75}, {"alpha", "x"}};
  provenance.inputs = nlohmann::json::array({{{"path", "a.c3d"}, {"sha256", "00"}}});
  return provenance;
}

void WriteSample(const std::string& path, int64_t version) {
  IntermediateWriter writer(path, TestProvenance(version));
  const std::vector<double> points = {1.0, 2.0, std::nan(""), 4.0, 5.0, 6.0};
  writer.writeDoubles("points", {2, 1, 3}, points.data());
  writer.writeStrings("labels", {"LFHD"});
  writer.writeInts("segments/000/boundaries", std::vector<int64_t>{0, 10, 20});
  writer.writeAttribute("segments/000", "duration", 1.5);
  writer.commit();
}

TEST(IntermediateFile, SameContentGivesByteIdenticalFiles) {
  const std::string first = TempPath("first.h5");
  const std::string second = TempPath("second.h5");
  WriteSample(first, 1);
  sleep(1);  // a timestamp, if one were stored, would now differ
  WriteSample(second, 1);
  const std::string a = Bytes(first), b = Bytes(second);
  ASSERT_FALSE(a.empty());
  EXPECT_EQ(a.size(), b.size());
  EXPECT_TRUE(a == b) << "two writes of the same content differ";
}

TEST(IntermediateFile, RoundTripsDatasetsAndProvenance) {
  const std::string path = TempPath("roundtrip.h5");
  WriteSample(path, 1);
  IntermediateReader reader(path, "synsculpt.test", 1);
  EXPECT_EQ(reader.provenance().producer, "intermediate_file_test");
  EXPECT_DOUBLE_EQ(reader.provenance().parameters.at("threshold").get<double>(), 0.75);
  EXPECT_EQ(reader.provenance().inputs.at(0).at("path"), "a.c3d");
  const DoubleArray points = reader.readDoubles("points");
  EXPECT_EQ(points.dims, (std::vector<int64_t>{2, 1, 3}));
  EXPECT_EQ(points.values[3], 4.0);
  EXPECT_TRUE(std::isnan(points.values[2]));
  EXPECT_EQ(reader.readStrings("labels"), std::vector<std::string>{"LFHD"});
  EXPECT_EQ(reader.readInts("segments/000/boundaries"), (std::vector<int64_t>{0, 10, 20}));
  EXPECT_DOUBLE_EQ(reader.readDoubleAttribute("segments/000", "duration"), 1.5);
  EXPECT_TRUE(reader.has("segments/000/boundaries"));
  EXPECT_FALSE(reader.has("segments/001/boundaries"));
  EXPECT_EQ(reader.listGroup("segments"), std::vector<std::string>{"000"});
}

TEST(IntermediateFile, ReaderRefusesAnotherSchemaVersionByName) {
  const std::string path = TempPath("version2.h5");
  WriteSample(path, 2);
  try {
    IntermediateReader reader(path, "synsculpt.test", 1);
    FAIL() << "a version-2 file was accepted by a version-1 reader";
  } catch (const DataError& error) {
    const std::string message = error.what();
    EXPECT_NE(message.find(path), std::string::npos) << message;
    EXPECT_NE(message.find("synsculpt.test version 2"), std::string::npos) << message;
    EXPECT_NE(message.find("version 1"), std::string::npos) << message;
  }
  EXPECT_THROW(IntermediateReader(path, "synsculpt.motion", 2), DataError);
}

TEST(IntermediateFile, UncommittedWriterLeavesNothing) {
  const std::string path = TempPath("abandoned.h5");
  std::filesystem::remove(path);
  {
    IntermediateWriter writer(path, TestProvenance(1));
    writer.writeDoubles("time", std::vector<double>{0.0, 0.1});
  }  // destroyed without commit(), as when a stage throws half-way
  EXPECT_FALSE(std::filesystem::exists(path));
  for (const auto& entry : std::filesystem::directory_iterator(std::filesystem::path(path).parent_path())) {
    EXPECT_EQ(entry.path().string().find("abandoned.h5.tmp-"), std::string::npos) << entry.path();
  }
}

TEST(IntermediateFile, NonHdf5InputIsRefusedWithItsName) {
  const std::string path = TempPath("not_hdf5.h5");
  std::ofstream(path) << "hello";
  try {
    IntermediateReader reader(path, "synsculpt.markers", 1);
    FAIL();
  } catch (const DataError& error) {
    EXPECT_NE(std::string(error.what()).find("not an HDF5 file"), std::string::npos);
  }
}

TEST(IntermediateFile, DescriptionListsShapesAndAttributes) {
  const std::string path = TempPath("describe.h5");
  WriteSample(path, 1);
  const nlohmann::json description = DescribeIntermediateFile(path);
  EXPECT_EQ(description["attributes"]["schema"], "synsculpt.test");
  EXPECT_EQ(description["attributes"]["schema_version"], 1);
  EXPECT_EQ(description["attributes"]["parameters"]["threshold"], 0.75);
  EXPECT_EQ(description["datasets"]["points"]["shape"], nlohmann::json({2, 1, 3}));
  EXPECT_EQ(description["datasets"]["labels"]["type"], "string");
}

TEST(CanonicalJson, SortsKeysAndRoundTripsNumbers) {
  const nlohmann::json value = {{"b", 0.1}, {"a", 1e-300}, {"c", {{"z", 1}, {"y", 2}}}};
  const std::string text = CanonicalJson(value);
  EXPECT_EQ(text, R"({"a":1e-300,"b":0.1,"c":{"y":2,"z":1}})");
  EXPECT_EQ(nlohmann::json::parse(text)["b"].get<double>(), 0.1);
}

}  // namespace
}  // namespace syn
