// `syn-simulate --control-trace FILE.csv`: the ground-mode balance loop, one row per control step.
//
// The motion file holds what happened at the input's frames; why a walk fell lives between them, at the
// control rate: what the centre of mass's level asked of the soles, what the contact-consistent step
// planned them to push, and what the floor gave. Sessions 44-47 wrote temporary patches to dump exactly
// these (the 18 Hz bounce of the soles; a stance whose planned sole forces gave 15 N more sideways force
// than the level asked, enough to lose the capture point in 0.7 s). This is that dump, kept: a CSV a user
// can read with numpy or pandas, written whether the robot stays up or falls.
//
// Columns (ground frame; m, N, N·m, s):
//   time, frame                     the step's time and the input frame it starts from
//   balancing                       1 where a sole was on the floor and the level was set, else 0
//   com_x, com_y                    the centre of mass
//   capture_error_x, _y             the capture point's error from the balance plan's
//   plan_zmp_x, _y                  the plan's zero-moment point (its landing shifts included)
//   wanted_zmp_x, _y                the zero-moment point the capture-point feedback wanted
//   commanded_zmp_x, _y             that point clamped into the standing soles
//   level_force_x, _y, _z           the ground force the level asked for (m (c̈* + g), in the friction cone)
//   planned_force_x, _y, _z         the sole forces the contact-consistent step planned, summed over the feet
//   applied_force_x, _y, _z         the sole forces the floor applied over the step, summed over the feet
//   unexplained_moment_x, _y, _z    the planned base wrench no admissible sole force gave (about the centre
//   unexplained_force_x, _y, _z       of mass)
//   landing_needed                  the largest landing shift a swinging foot needed (uncapped; 0: none)
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "stages/simulate/balance_controller.h"

namespace syn {

struct ControlTraceRow {
  double time = 0;
  int64_t frame = 0;
  bool balancing = false;
  BalanceCommand level;  // the centre of mass, the capture error, the zero-moment points and the level's force
  Eigen::Vector3d planned_force = Eigen::Vector3d::Zero();
  Eigen::Vector3d applied_force = Eigen::Vector3d::Zero();
  Eigen::Matrix<double, 6, 1> unexplained = Eigen::Matrix<double, 6, 1>::Zero();  // (moment, force)
  double landing_needed = 0;
};

class ControlTrace {
 public:
  // Room for `rows` rows, so that recording allocates nothing.
  void reserve(size_t rows) { rows_.reserve(rows); }
  void add(const ControlTraceRow& row) { rows_.push_back(row); }
  const std::vector<ControlTraceRow>& rows() const { return rows_; }

  // The header line and one line per row, numbers with 9 significant digits.
  [[nodiscard]] std::string ToCsv() const;

 private:
  std::vector<ControlTraceRow> rows_;
};

}  // namespace syn
