#include "stages/library/style_library.h"

#include <algorithm>
#include <cmath>

#include <Eigen/SVD>

#include "common/error.h"
#include "common/row_major.h"

namespace syn {
namespace {

std::vector<double> ToVector(const Eigen::VectorXd& vector) { return {vector.data(), vector.data() + vector.size()}; }

}  // namespace

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
    const Eigen::BDCSVD<Eigen::MatrixXd> svd(stacked, Eigen::ComputeThinV);
    const int k = std::min<int>(components, static_cast<int>(svd.singularValues().size()));
    Eigen::MatrixXd v = svd.matrixV().leftCols(k);
    for (int c = 0; c < k; ++c) {
      Eigen::Index largest = 0;
      v.col(c).cwiseAbs().maxCoeff(&largest);
      if (v(largest, c) < 0) v.col(c) = -v.col(c);
    }
    basis.components = v.transpose();
    basis.singular_values = svd.singularValues().head(k);
    const double total = svd.singularValues().squaredNorm();
    basis.explained_variance_ratio = total > 0 ? Eigen::VectorXd(basis.singular_values.array().square() / total)
                                               : Eigen::VectorXd::Zero(k);
    for (size_t i : members) {
      double kept = 0, all = 0;
      for (const auto& segment : trials[i].synergies.segments) {
        const Eigen::MatrixXd centred = segment.velocities.rowwise() - segment.velocities.colwise().mean();
        kept += (centred * v).squaredNorm();
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

void WriteLibrary(IntermediateWriter& writer, const SynergyLibrary& library) {
  writer.writeStrings("velocity_names", library.velocity_names);
  std::vector<std::string> styles, classes;
  for (const auto& [style, basis] : library.styles) {
    styles.push_back(style);
    const std::string group = "styles/" + style;
    writer.writeDoubles(group + "/components", {basis.components.rows(), basis.components.cols()},
                        RowMajorValues(basis.components).data());
    writer.writeDoubles(group + "/singular_values", ToVector(basis.singular_values));
    writer.writeDoubles(group + "/explained_variance_ratio", ToVector(basis.explained_variance_ratio));
    writer.writeStrings(group + "/trials", basis.trials);
    writer.writeDoubles(group + "/trial_retained_variance", basis.retained_variance);
    writer.writeAttribute(group, "segments", basis.segments);
  }
  for (const auto& [motion_class, spread] : library.classes) {
    classes.push_back(motion_class.empty() ? std::string("unlabelled") : motion_class);
    const std::string group = "classes/" + (motion_class.empty() ? std::string("unlabelled") : motion_class);
    writer.writeDoubles(group + "/pc_ratio_mean", ToVector(spread.mean_ratio));
    writer.writeDoubles(group + "/pc_ratio_std", ToVector(spread.std_ratio));
    writer.writeAttribute(group, "segments", spread.segments);
  }
  writer.writeStrings("style_names", styles);
  writer.writeStrings("class_names", classes);
  std::vector<std::string> trial_names;
  for (const auto& [name, trial] : library.trials) {
    if (trial.synergies.segments.empty()) continue;  // HDF5 groups exist once something is written in them
    trial_names.push_back(name);
    const std::string group = "trials/" + name;
    for (size_t s = 0; s < trial.synergies.segments.size(); ++s) {
      WriteSynergySegment(writer, group + "/" + SegmentGroupName(s), trial.synergies.segments[s], false);
    }
    for (const char* key : {"subject", "trial", "style", "motion_class"}) {
      writer.writeAttribute(group, key, trial.labels.ToJson()[key].get<std::string>());
    }
    writer.writeAttribute(group, "segment_count", static_cast<int64_t>(trial.synergies.segments.size()));
  }
  writer.writeStrings("trial_names", trial_names);
}

LibraryReader::LibraryReader(const std::string& path) : reader_(path, kLibrarySchema, kLibrarySchemaVersion) {
  velocity_names_ = reader_.readStrings("velocity_names");
  if (!reader_.has("trial_names")) return;
  for (const std::string& trial : reader_.readStrings("trial_names")) {
    const std::string group = "trials/" + trial;
    const std::string style = reader_.readStringAttribute(group, "style");
    const int64_t count = reader_.readIntAttribute(group, "segment_count");
    for (int64_t s = 0; s < count; ++s) names_.push_back(style + "/" + trial + "/" + std::to_string(s));
  }
  std::sort(names_.begin(), names_.end());
}

bool LibraryReader::has(const std::string& name) const {
  return std::binary_search(names_.begin(), names_.end(), name);
}

LibrarySynergy LibraryReader::read(const std::string& name) const {
  if (!has(name)) {
    std::string known;
    for (size_t i = 0; i < names_.size() && i < 40; ++i) known += (i ? ", " : "") + names_[i];
    if (names_.size() > 40) known += ", ...";
    throw DataError(Location::InFile(path()), "no synergy '" + name + "' (expected STYLE/TRIAL/SEGMENT; the library "
                                              "holds: " + (known.empty() ? std::string("none") : known) + ")");
  }
  const size_t first = name.find('/'), last = name.rfind('/');
  LibrarySynergy result;
  result.style = name.substr(0, first);
  result.trial = name.substr(first + 1, last - first - 1);
  result.index = std::stoll(name.substr(last + 1));
  const std::string group = "trials/" + result.trial;
  result.labels.subject = reader_.readStringAttribute(group, "subject");
  result.labels.trial = reader_.readStringAttribute(group, "trial");
  result.labels.style = reader_.readStringAttribute(group, "style");
  result.labels.motion_class = reader_.readStringAttribute(group, "motion_class");
  result.velocity_names = velocity_names_;
  result.segment = ReadSynergySegment(reader_, group + "/" + SegmentGroupName(static_cast<size_t>(result.index)));
  return result;
}

Eigen::MatrixXd LibraryReader::styleBasis(const std::string& style) const {
  const std::string name = "styles/" + style + "/components";
  if (!reader_.has(name)) {
    std::string known;
    for (const std::string& s : styleNames()) known += (known.empty() ? "" : ", ") + s;
    throw DataError(Location::InFile(path()), "no style '" + style + "' (the library holds: " + known + ")");
  }
  return MatrixFromRowMajor(reader_.readDoubles(name));
}

std::vector<std::string> LibraryReader::styleNames() const { return reader_.readStrings("style_names"); }

}  // namespace syn
