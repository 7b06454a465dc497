// `*.motion.h5` (schema synsculpt.motion): a robot trajectory. Written by
// syn-retarget, syn-compose and syn-project; read by segment, synergies,
// evaluate, export.
//
// Datasets: time[T] (s), q[T,nq], u[T,nu], udot[T,nu], tau[T,nu] (N·m or N;
// a free base's six entries are the residual wrench), coordinate_names[nq],
// velocity_names[nu]; when the motion was retargeted: landmark_names[L],
// landmark_targets[T,L,7] (position m, quaternion w,x,y,z; NaN = no target)
// and landmark_error[T,L,2] (position m, angle rad); optional (readers accept files without them):
// contact_feet[F] (foot sides) and contact[T,F] (1 = the source's foot is planted, syn-retarget's
// contact detection); with a free base, contact_force[T,F,3] (N, ground frame: each foot's share of
// the base's residual wrench that admissible contact forces explain) and unexplained_wrench[T,6] (the
// rest: moment about the whole-body centre of mass N·m, then force N). Root attributes:
// model_name, model_sha256, total_mass (kg).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "common/intermediate_file.h"

namespace syn {

inline constexpr const char* kMotionSchema = "synsculpt.motion";
inline constexpr int64_t kMotionSchemaVersion = 1;

struct MotionData {
  std::vector<double> time_s;                 // [T]
  std::vector<std::string> coordinate_names;  // [nq]
  std::vector<std::string> velocity_names;    // [nu]
  std::vector<double> q;                      // [T, nq]
  std::vector<double> u;                      // [T, nu]
  std::vector<double> udot;                   // [T, nu]
  std::vector<double> tau;                    // [T, nu]

  std::vector<std::string> landmark_names;    // [L], may be empty
  std::vector<double> landmark_targets;       // [T, L, 7]
  std::vector<double> landmark_error;         // [T, L, 2]

  std::vector<std::string> contact_feet;      // [F], may be empty
  std::vector<int64_t> contact;               // [T, F]: 1 = planted
  std::vector<double> contact_force;          // [T, F, 3], may be empty
  std::vector<double> unexplained_wrench;     // [T, 6], may be empty

  std::string model_name;
  std::string model_sha256;
  double total_mass = 0.0;

  int64_t frames() const { return static_cast<int64_t>(time_s.size()); }
  int64_t nq() const { return static_cast<int64_t>(coordinate_names.size()); }
  int64_t nu() const { return static_cast<int64_t>(velocity_names.size()); }
};

void WriteMotionData(IntermediateWriter& writer, const MotionData& motion);

// Drops every frame from `frames` on, from each per-frame array the motion has (its names and model kept).
void KeepFirstFrames(MotionData& motion, int64_t frames);

// Reads a motion file, checking schema, version and array shapes.
[[nodiscard]] MotionData ReadMotionFile(const std::string& path);

class Model;
// Throws DataError naming the URDF when the motion was made with another model (SHA-256) or its
// coordinates differ from the model's.
void CheckMotionMatchesModel(const MotionData& motion, const Model& model);

}  // namespace syn
