// Simbody's Assembler with a Markers goal (and an OrientationSensors goal for
// orientation tasks) tracking link targets frame by frame: the engine behind
// OpenSim's InverseKinematicsTool, kept as the reference our per-frame IK
// (stages/retarget/frame_ik) is benchmarked against on the same targets.
#pragma once

#include <memory>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "common/model.h"

namespace syn {

struct AssemblerTask {
  int link = -1;             // Model link index; the marker is the link origin, the sensor its frame
  bool position = true;
  bool orientation = true;
  double weight = 1.0;
};

class AssemblerTracker {
 public:
  // accuracy: the Assembler's relative accuracy (OpenSim's IK default is 1e-5). Joint limits are
  // given to the Assembler as restricted coordinate ranges.
  AssemblerTracker(const Model& model, const std::vector<AssemblerTask>& tasks, double accuracy = 1e-5);
  ~AssemblerTracker();
  AssemblerTracker(const AssemblerTracker&) = delete;
  AssemblerTracker& operator=(const AssemblerTracker&) = delete;

  // One frame: positions and orientations have one entry per task (entries a task does not use are
  // ignored). The first call starts from q; later calls warm-start from the previous solution, as
  // Assembler::track does. q receives the solution.
  void track(const std::vector<Eigen::Vector3d>& positions, const std::vector<Eigen::Quaterniond>& orientations,
             Eigen::VectorXd& q);

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace syn
