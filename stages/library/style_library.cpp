#include "stages/library/style_library.h"

#include <algorithm>
#include <cmath>

#include "common/error.h"
#include "common/principal_axes.h"

namespace syn {
SynergyLibrary BuildLibrary(const std::vector<LabelledTrial>& trials, const std::vector<std::string>& sources,
                            int components) {
  SynergyLibrary library;
  if (trials.empty()) return library;
  library.velocity_names = trials[0].synergies.velocity_names;
  std::map<std::string, std::vector<size_t>> by_style;
  std::map<std::string, std::vector<Eigen::Vector3d>> class_ratios;
  for (size_t i = 0; i < trials.size(); ++i) {
    if (trials[i].synergies.velocity_names != library.velocity_names) {
      throw DataError(Location::InFile(sources[i]), "its velocities differ from " + sources[0] +
                                                        "'s: every trial of a library must use the same robot and --velocities");
    }
    by_style[trials[i].labels.style].push_back(i);
    std::string name = trials[i].labels.trial.empty() ? sources[i] : trials[i].labels.trial;
    std::replace(name.begin(), name.end(), '/', '_');
    if (library.trials.count(name)) {
      throw DataError(Location::InFile(sources[i]), "trial '" + name + "' appears twice in one library");
    }
    LabelledTrial& stored = library.trials[name];
    stored.labels = trials[i].labels;
    stored.synergies.velocity_names = trials[i].synergies.velocity_names;
    stored.synergies.segments = trials[i].synergies.segments;
    for (const auto& segment : trials[i].synergies.segments) {
      Eigen::Vector3d ratios = Eigen::Vector3d::Zero();
      const Eigen::VectorXd& r = segment.synergies.explained_variance_ratio;
      for (int k = 0; k < 3 && k < r.size(); ++k) ratios[k] = r[k];
      class_ratios[trials[i].labels.motion_class].push_back(ratios);
    }
  }
  const Eigen::Index width = static_cast<Eigen::Index>(library.velocity_names.size());
  for (const auto& [style, members] : by_style) {
    Eigen::Index rows = 0;
    for (size_t i : members) {
      for (const auto& segment : trials[i].synergies.segments) rows += segment.velocities.rows();
    }
    Eigen::MatrixXd stacked(rows, width);
    Eigen::Index row = 0;
    for (size_t i : members) {
      for (const auto& segment : trials[i].synergies.segments) {
        stacked.middleRows(row, segment.velocities.rows()) =
            segment.velocities.rowwise() - segment.velocities.colwise().mean();
        row += segment.velocities.rows();
      }
    }
    StyleBasis basis;
    const PrincipalAxes principal = ComputePrincipalAxes(stacked, components, /*with_scores=*/false);
    basis.components = principal.axes.transpose();
    basis.singular_values = principal.singular_values.head(principal.axes.cols());
    basis.explained_variance_ratio = principal.explained_variance_ratio;
    for (size_t i : members) {
      double kept = 0, all = 0;
      for (const auto& segment : trials[i].synergies.segments) {
        const Eigen::MatrixXd centred = segment.velocities.rowwise() - segment.velocities.colwise().mean();
        kept += (centred * principal.axes).squaredNorm();
        all += centred.squaredNorm();
        ++basis.segments;
      }
      basis.trials.push_back(trials[i].labels.trial.empty() ? sources[i] : trials[i].labels.trial);
      basis.retained_variance.push_back(all > 0 ? kept / all : 1.0);
    }
    library.styles[style] = basis;
  }
  for (const auto& [motion_class, ratios] : class_ratios) {
    ClassSpread spread;
    spread.segments = static_cast<int64_t>(ratios.size());
    Eigen::Vector3d mean = Eigen::Vector3d::Zero(), squares = Eigen::Vector3d::Zero();
    for (const Eigen::Vector3d& r : ratios) mean += r;
    mean /= static_cast<double>(ratios.size());
    for (const Eigen::Vector3d& r : ratios) squares += (r - mean).cwiseAbs2();
    spread.mean_ratio = mean;
    spread.std_ratio = ratios.size() > 1 ? Eigen::Vector3d((squares / static_cast<double>(ratios.size() - 1)).cwiseSqrt())
                                         : Eigen::Vector3d::Zero();
    library.classes[motion_class] = spread;
  }
  return library;
}

}  // namespace syn
