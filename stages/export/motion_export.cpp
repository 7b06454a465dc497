#include "stages/export/motion_export.h"

#include <cmath>
#include <cstdio>
#include <sstream>

#include <Eigen/Geometry>

#include "common/cubic_spline.h"
#include "common/error.h"
#include "common/file_bytes.h"
#include "common/motion_integration.h"

#include "stages/export/number_text.h"

namespace syn {
namespace {


bool FreeBase(const MotionData& motion) { return motion.nq() == motion.nu() + 1; }

void CheckModel(const MotionData& motion, const Model& model) {
  if (motion.coordinate_names != model.coordinateNames()) {
    throw DataError(Location::InFile(model.sourcePath()), "the motion's coordinates are not those of " + model.name());
  }
}

}  // namespace

MotionData ResampleUniformly(const MotionData& motion, double rate) {
  if (motion.frames() < 2) throw DataError(Location::InFile("motion"), "needs at least 2 frames to resample");
  const int64_t nq = motion.nq();
  std::vector<double> q = motion.q;
  if (FreeBase(motion)) MakeBaseQuaternionsContinuous(q, nq);
  const CubicSpline spline(motion.time_s, std::move(q), nq);
  MotionData result;
  result.coordinate_names = motion.coordinate_names;
  result.velocity_names = motion.velocity_names;
  result.model_name = motion.model_name;
  result.model_sha256 = motion.model_sha256;
  result.total_mass = motion.total_mass;
  const double start = motion.time_s.front(), span = motion.time_s.back() - start;
  const int64_t frames = static_cast<int64_t>(std::floor(span * rate + 1e-9)) + 1;
  result.q.resize(static_cast<size_t>(frames * nq));
  for (int64_t k = 0; k < frames; ++k) {
    const double t = start + static_cast<double>(k) / rate;
    result.time_s.push_back(t);
    double* pose = &result.q[static_cast<size_t>(k * nq)];
    spline.evaluate(t, pose, nullptr);
    if (FreeBase(motion)) {
      const double norm = std::sqrt(pose[0] * pose[0] + pose[1] * pose[1] + pose[2] * pose[2] + pose[3] * pose[3]);
      for (int i = 0; i < 4; ++i) pose[i] /= norm;
    }
  }
  return result;
}

std::string MotionToCsv(const MotionData& motion) {
  std::ostringstream text;
  text << "time";
  for (const std::string& name : motion.coordinate_names) text << ',' << name;
  text << '\n';
  for (int64_t t = 0; t < motion.frames(); ++t) {
    text << ShortestNumberText(motion.time_s[static_cast<size_t>(t)]);
    for (int64_t i = 0; i < motion.nq(); ++i) text << ',' << ShortestNumberText(motion.q[static_cast<size_t>(t * motion.nq() + i)]);
    text << '\n';
  }
  return text.str();
}

std::string MotionToMot(const MotionData& motion, const Model& model, const std::string& name) {
  CheckModel(motion, model);
  const bool free_base = FreeBase(motion);
  std::vector<std::string> columns;
  if (free_base) columns = {"base_rx", "base_ry", "base_rz", "base_tx", "base_ty", "base_tz"};
  std::vector<std::pair<int, double>> joint_columns;  // q index, unit factor
  for (const ModelJoint& joint : model.joints()) {
    if (joint.q_index < 0 || joint.type == "free") continue;
    columns.push_back(joint.name);
    joint_columns.emplace_back(joint.q_index, joint.type == "prismatic" ? 1.0 : 180.0 / M_PI);
  }
  std::ostringstream text;
  text << name << "\nversion=1\nnRows=" << motion.frames() << "\nnColumns=" << columns.size() + 1
       << "\ninDegrees=yes\nendheader\ntime";
  for (const std::string& column : columns) text << '\t' << column;
  text << '\n';
  for (int64_t t = 0; t < motion.frames(); ++t) {
    const double* q = &motion.q[static_cast<size_t>(t * motion.nq())];
    text << ShortestNumberText(motion.time_s[static_cast<size_t>(t)]);
    if (free_base) {
      const Eigen::Matrix3d rotation = Eigen::Quaterniond(q[0], q[1], q[2], q[3]).normalized().toRotationMatrix();
      const Eigen::Vector3d angles = rotation.eulerAngles(0, 1, 2) * (180.0 / M_PI);  // body-fixed X-Y-Z
      for (int i = 0; i < 3; ++i) text << '\t' << ShortestNumberText(angles[i]);
      for (int i = 4; i < 7; ++i) text << '\t' << ShortestNumberText(q[i]);
    }
    for (const auto& [index, factor] : joint_columns) text << '\t' << ShortestNumberText(q[index] * factor);
    text << '\n';
  }
  return text.str();
}

std::string MotionToRobotCsv(const MotionData& motion, const Model& model) {
  CheckModel(motion, model);
  if (!FreeBase(motion)) {
    throw DataError(Location::InFile(model.sourcePath()), "the robot CSV layout needs a free-floating base");
  }
  std::ostringstream text;
  for (int64_t t = 0; t < motion.frames(); ++t) {
    const double* q = &motion.q[static_cast<size_t>(t * motion.nq())];
    text << ShortestNumberText(q[4]) << ',' << ShortestNumberText(q[5]) << ',' << ShortestNumberText(q[6]);
    for (int i = 0; i < 4; ++i) text << ',' << ShortestNumberText(q[i]);
    for (const ModelJoint& joint : model.joints()) {
      if (joint.q_index >= 0 && joint.type != "free") text << ',' << ShortestNumberText(q[joint.q_index]);
    }
    text << '\n';
  }
  return text.str();
}

MotionData ReadRobotCsv(const std::string& path, const Model& model, double rate) {
  if (!model.hasFreeBase()) throw DataError(Location::InFile(model.sourcePath()), "a robot CSV needs a free-floating base");
  std::vector<int> joint_q;
  for (const ModelJoint& joint : model.joints()) {
    if (joint.q_index >= 0 && joint.type != "free") joint_q.push_back(joint.q_index);
  }
  const size_t width = 7 + joint_q.size();
  MotionData motion;
  motion.coordinate_names = model.coordinateNames();
  motion.velocity_names = model.velocityNames();
  motion.model_name = model.name();
  motion.model_sha256 = model.sourceSha256();
  motion.total_mass = model.totalMass();
  std::istringstream lines(ReadFileText(path));
  int line_number = 0;
  for (std::string line; std::getline(lines, line);) {
    ++line_number;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (line.empty()) continue;
    std::vector<double> values;
    std::istringstream cells(line);
    for (std::string cell; std::getline(cells, cell, ',');) {
      char* end = nullptr;
      const double value = std::strtod(cell.c_str(), &end);
      if (cell.empty() || end != cell.c_str() + cell.size()) {
        throw DataError(Location::AtLine(path, line_number), "column " + std::to_string(values.size() + 1) + ": '" +
                                                                 cell + "' is not a number");
      }
      values.push_back(value);
    }
    if (values.size() != width) {
      throw DataError(Location::AtLine(path, line_number),
                      std::to_string(values.size()) + " columns; expected " + std::to_string(width) +
                          " (root position 3, root quaternion w,x,y,z 4, " + std::to_string(joint_q.size()) +
                          " joints of " + model.name() + ")");
    }
    std::vector<double> q(static_cast<size_t>(model.nq()), 0.0);
    for (int i = 0; i < 4; ++i) q[static_cast<size_t>(i)] = values[static_cast<size_t>(3 + i)];
    for (int i = 0; i < 3; ++i) q[static_cast<size_t>(4 + i)] = values[static_cast<size_t>(i)];
    for (size_t j = 0; j < joint_q.size(); ++j) q[static_cast<size_t>(joint_q[j])] = values[7 + j];
    motion.time_s.push_back(static_cast<double>(motion.time_s.size()) / rate);
    motion.q.insert(motion.q.end(), q.begin(), q.end());
  }
  return motion;
}

}  // namespace syn
