// The G1's pelvis and feet as pose tasks of the per-frame IK, and their targets at a given configuration:
// what the FrameIk tests solve back.
#pragma once

#include <algorithm>
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "common/model.h"
#include "stages/retarget/frame_ik.h"
#include "tests/support/demo_motion.h"
#include "tests/support/shared_data.h"

namespace syn::testing {

class G1LegTasks {
 public:
  G1LegTasks() : model_(Model::Load(SourcePath(kG1Urdf))), workspace_(model_) {
    for (const char* link : {"pelvis", "left_ankle_roll_link", "right_ankle_roll_link"}) {
      tasks_.push_back(IkTask{model_.findLinkIndex(link), TaskType::kPose, 1.0});
    }
  }

  // The index in q of the coordinate `name`.
  int Coordinate(const std::string& name) const {
    const auto& names = model_.coordinateNames();
    return static_cast<int>(std::find(names.begin(), names.end(), name) - names.begin());
  }

  // The tasks' link poses at `goal`.
  std::vector<IkTarget> TargetsAt(const Eigen::VectorXd& goal) {
    workspace_.setQ(goal);
    std::vector<IkTarget> targets;
    for (const IkTask& task : tasks_) {
      const Eigen::Isometry3d pose = workspace_.findLinkPose(task.link);
      targets.push_back(IkTarget{true, true, pose.translation(), Eigen::Quaterniond(pose.linear())});
    }
    return targets;
  }

 protected:
  Model model_;
  Workspace workspace_;
  std::vector<IkTask> tasks_;
};

}  // namespace syn::testing
