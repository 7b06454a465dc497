// Style-conditioned synergy libraries (paper, "Stylistic Variability across
// Dance Synergies"): per style, one shared basis from all of its segments'
// velocity samples (each segment centred on its own mean), the variance that
// basis retains on each trial, and per motion class the spread of the
// per-segment PC1–PC3 variance ratios (the paper's Fig. 4 and Fig. 5 data).
#pragma once

#include <map>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "common/intermediate_file.h"
#include "stages/synergies/synergies.h"

namespace syn {

struct StyleBasis {
  Eigen::MatrixXd components;             // [k, nv], orthonormal rows: Sᵀ
  Eigen::VectorXd singular_values;        // [k]
  Eigen::VectorXd explained_variance_ratio;  // [k]
  std::vector<std::string> trials;
  std::vector<double> retained_variance;  // per trial: ‖Xc S Sᵀ‖² / ‖Xc‖² over its segments
  int64_t segments = 0;
};

struct ClassSpread {
  Eigen::VectorXd mean_ratio, std_ratio;  // [3]: PC1..PC3 explained-variance ratio over segments
  int64_t segments = 0;
};

struct LabelledTrial {
  SynergyOptions labels;
  TrialSynergies synergies;
};

struct SynergyLibrary {
  std::vector<std::string> velocity_names;
  std::map<std::string, StyleBasis> styles;
  std::map<std::string, ClassSpread> classes;
  // Every segment's synergies by trial name, so that syn-compose can script them (stored without the
  // velocity samples).
  std::map<std::string, LabelledTrial> trials;
};

// Throws DataError (naming `sources[i]`) when trials disagree on velocity names.
[[nodiscard]] SynergyLibrary BuildLibrary(const std::vector<LabelledTrial>& trials, const std::vector<std::string>& sources,
                                          int components);

void WriteLibrary(IntermediateWriter& writer, const SynergyLibrary& library);

inline constexpr const char* kLibrarySchema = "synsculpt.library";
inline constexpr int64_t kLibrarySchemaVersion = 1;

// One segment's synergies from a library file, by "STYLE/TRIAL/SEGMENT" (e.g. "salsa/60_10/2").
struct LibrarySynergy {
  std::string style, trial;
  int64_t index = 0;
  SynergyOptions labels;
  std::vector<std::string> velocity_names;
  TrialSynergies::Segment segment;
};

class LibraryReader {
 public:
  explicit LibraryReader(const std::string& path);
  const std::string& path() const { return reader_.path(); }
  const std::vector<std::string>& velocityNames() const { return velocity_names_; }
  // Every "STYLE/TRIAL/SEGMENT" the library holds, sorted.
  const std::vector<std::string>& synergyNames() const { return names_; }
  bool has(const std::string& name) const;
  // Throws DataError listing what the library holds when `name` is absent or malformed.
  [[nodiscard]] LibrarySynergy read(const std::string& name) const;
  // The shared basis of a style, [k, nv] orthonormal rows (Sᵀ).
  [[nodiscard]] Eigen::MatrixXd styleBasis(const std::string& style) const;
  [[nodiscard]] std::vector<std::string> styleNames() const;

 private:
  IntermediateReader reader_;
  std::vector<std::string> velocity_names_, names_;
};

}  // namespace syn
