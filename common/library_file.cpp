#include "common/library_file.h"

#include <algorithm>

#include "common/error.h"
#include "common/row_major.h"

namespace syn {
namespace {

std::vector<double> ToVector(const Eigen::VectorXd& vector) { return {vector.data(), vector.data() + vector.size()}; }

}  // namespace

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
    WriteSynergyLabels(writer, group, trial.labels);
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
  result.labels = ReadSynergyLabels(reader_, group);
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
