// syn-export formats read by robot-learning stacks. Every one needs the robot's URDF (--model), the
// motion at a uniform rate (resample with --rate when it is not), and writes numbers in SI units in
// synsculpt's world frame (Z up, metres, radians).
//
//   unitree-csv  Unitree's LAFAN1 retargeting CSV (the G1/H1 motion files): no header, one row per frame:
//                root position x, y, z (m); root quaternion x, y, z, w (scalar LAST); then each joint's
//                position (rad, or m for prismatic) in the URDF's joint order. The rate is not stored.
//   gmr-npz      General Motion Retargeting's robot motion, as a pickle-free NPZ (np.load without
//                allow_pickle): fps () float64; root_pos (T,3) m; root_rot (T,4) quaternion x,y,z,w;
//                dof_pos (T,J) joint positions in URDF joint order; link_body_list (B,) unicode, every
//                URDF link in file order; local_body_pos (T,B,3) each link origin in the root link's frame
//                (m) = R_root^T (p_link - p_root); plus joint_names (J,) unicode.
//   mjlab-npz    the motion NPZ of BeyondMimic / mjlab motion tracking: fps (1,) float64; joint_pos (T,J)
//                and joint_vel (T,J) in URDF joint order; body_pos_w (T,B,3) m, body_quat_w (T,B,4)
//                quaternion w,x,y,z (scalar FIRST, IsaacLab/mjlab order), body_lin_vel_w (T,B,3) m/s,
//                body_ang_vel_w (T,B,3) rad/s, all in the world frame for every URDF link in file order;
//                plus joint_names (J,) and body_names (B,) unicode. Velocities are finite differences of
//                the sampled poses: central (x[t+1] - x[t-1]) / (t[t+1] - t[t-1]) inside, one-sided at the
//                ends; angular velocity from the relative rotation R[t+1] R[t-1]^T as a rotation vector.
// All NPZ arrays are float64 (cast as needed; the stacks cast to float32 on load).
#pragma once

#include <string>

#include "common/model.h"
#include "common/motion_file.h"

namespace syn {

[[nodiscard]] std::string MotionToUnitreeCsv(const MotionData& motion, const Model& model);
[[nodiscard]] std::string MotionToGmrNpz(const MotionData& motion, const Model& model);
[[nodiscard]] std::string MotionToMjlabNpz(const MotionData& motion, const Model& model);

}  // namespace syn
