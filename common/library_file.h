// `library.h5` and `library/STYLE.h5` (schema synsculpt.library): synergy
// libraries by style. Written by syn-library; read by syn-compose,
// syn-project, the studio and the report.
//
// Root: velocity_names[nv], style_names, class_names, trial_names. Per style,
// group "styles/STYLE": components[k,nv] (the shared basis Sᵀ, orthonormal
// rows), singular_values[k], explained_variance_ratio[k], trials,
// trial_retained_variance (per trial ‖Xc S Sᵀ‖² / ‖Xc‖²), attribute segments.
// Per motion class, "classes/CLASS": pc_ratio_mean[3], pc_ratio_std[3]
// (PC1–PC3 explained-variance ratio over segments: the paper's Fig. 4 and 5).
// Per trial, "trials/TRIAL": its segments as in synergies files
// (common/synergies_file.h, without the velocity samples) and its labels.
#pragma once

#include <map>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "common/intermediate_file.h"
#include "common/synergies_file.h"

namespace syn {

inline constexpr const char* kLibrarySchema = "synsculpt.library";
inline constexpr int64_t kLibrarySchemaVersion = 1;

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
  SynergyLabels labels;
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

void WriteLibrary(IntermediateWriter& writer, const SynergyLibrary& library);

// One segment's synergies from a library file, by "STYLE/TRIAL/SEGMENT" (e.g. "salsa/60_10/2").
struct LibrarySynergy {
  std::string style, trial;
  int64_t index = 0;
  SynergyLabels labels;
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
