// The versioned HDF5 container every stage reads and writes (DESIGN.md,
// "Intermediate files").
//
// Every file carries root attributes `schema`, `schema_version`, `producer`,
// `parameters` (canonical JSON of every parameter that affects the bytes) and
// `inputs` (JSON list of {path, sha256}). No timestamps: HDF5 object time
// tracking is off, so the same inputs and parameters give byte-identical
// files. Writers write to `NAME.tmp-<pid>` and rename on Commit(), so a killed
// run never leaves a file that make would take as up to date.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace syn {

struct Provenance {
  std::string schema;           // e.g. "synsculpt.markers"
  int64_t schema_version = 0;   // bumped on any incompatible change
  std::string producer;         // e.g. "syn-ingest 0.1.0"
  nlohmann::json parameters = nlohmann::json::object();
  nlohmann::json inputs = nlohmann::json::array();  // [{"path": ..., "sha256": ...}]
};

// {"path": path, "sha256": digest of the file} for Provenance::inputs.
[[nodiscard]] nlohmann::json DescribeInput(const std::string& path);

// Canonical JSON text: keys sorted, no whitespace, shortest round-trip numbers.
[[nodiscard]] std::string CanonicalJson(const nlohmann::json& value);

class IntermediateWriter {
 public:
  // Opens `path.tmp-<pid>` for writing and stores the provenance attributes.
  IntermediateWriter(std::string path, const Provenance& provenance);
  // Without Commit(), the temporary file is removed: nothing half-written stays.
  ~IntermediateWriter();
  IntermediateWriter(const IntermediateWriter&) = delete;
  IntermediateWriter& operator=(const IntermediateWriter&) = delete;

  // Dataset names may contain '/', e.g. "segments/003/components"; groups are
  // created as needed. dims are row-major; data holds their product.
  void writeDoubles(const std::string& name, const std::vector<int64_t>& dims, const double* data);
  void writeDoubles(const std::string& name, const std::vector<double>& values);  // 1-D
  void writeInts(const std::string& name, const std::vector<int64_t>& dims, const int64_t* data);
  void writeInts(const std::string& name, const std::vector<int64_t>& values);  // 1-D
  void writeStrings(const std::string& name, const std::vector<std::string>& values);

  // Attributes on the root ("") or on an existing group or dataset.
  void writeAttribute(const std::string& object, const std::string& name, const std::string& value);
  void writeAttribute(const std::string& object, const std::string& name, double value);
  void writeAttribute(const std::string& object, const std::string& name, int64_t value);

  // Closes the file and renames it onto the final path.
  void commit();

  const std::string& path() const { return path_; }

 private:
  struct Handles;
  std::string path_;
  std::string temporary_path_;
  std::unique_ptr<Handles> handles_;
  bool committed_ = false;
};

struct DoubleArray {
  std::vector<int64_t> dims;
  std::vector<double> values;
};

class IntermediateReader {
 public:
  // Opens and checks `schema` and `schema_version`; a mismatch is a DataError
  // that names both the expected and the found schema/version.
  IntermediateReader(std::string path, const std::string& expected_schema, int64_t expected_version);
  ~IntermediateReader();
  IntermediateReader(const IntermediateReader&) = delete;
  IntermediateReader& operator=(const IntermediateReader&) = delete;

  const Provenance& provenance() const { return provenance_; }
  const std::string& path() const { return path_; }

  [[nodiscard]] bool has(const std::string& name) const;
  [[nodiscard]] DoubleArray readDoubles(const std::string& name) const;
  [[nodiscard]] std::vector<int64_t> readInts(const std::string& name) const;
  [[nodiscard]] std::vector<std::string> readStrings(const std::string& name) const;
  [[nodiscard]] std::string readStringAttribute(const std::string& object, const std::string& name) const;
  [[nodiscard]] double readDoubleAttribute(const std::string& object, const std::string& name) const;
  [[nodiscard]] int64_t readIntAttribute(const std::string& object, const std::string& name) const;
  [[nodiscard]] bool hasAttribute(const std::string& object, const std::string& name) const;
  // Names of the direct children of a group ("" = root), sorted.
  [[nodiscard]] std::vector<std::string> listGroup(const std::string& group) const;

 private:
  struct Handles;
  std::string path_;
  std::unique_ptr<Handles> handles_;
  Provenance provenance_;
};

// Attributes and dataset shapes of any HDF5 file, as JSON (what syn-inspect
// prints). Does not check the schema.
[[nodiscard]] nlohmann::json DescribeIntermediateFile(const std::string& path);

}  // namespace syn
