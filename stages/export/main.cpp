// syn-export IN.motion.h5 -o OUT [--format csv|mot|robot-csv|unitree-csv|gmr-npz|mjlab-npz] [--model ROBOT.urdf]
// [--rate HZ]. Layouts: stages/export/motion_export.h and stages/export/robot_learning_export.h.
#include <algorithm>
#include <filesystem>
#include <iostream>

#include "common/cli.h"
#include "common/file_bytes.h"
#include "stages/export/motion_export.h"
#include "stages/export/robot_learning_export.h"

int main(int argc, char** argv) {
  CLI::App app{
      "Write a motion for other tools. Quaternion order: synsculpt's motion files, csv and robot-csv store "
      "w,x,y,z (scalar first); unitree-csv and gmr-npz write x,y,z,w (scalar last); mjlab-npz writes w,x,y,z. "
      "All positions in metres in synsculpt's Z-up world, joint positions in rad (m for prismatic), joints in "
      "the URDF's joint order.\n"
      "  csv          header 'time,<coordinate names>'; one row per frame: time (s), then every coordinate "
      "as stored (a free base as base_qw,base_qx,base_qy,base_qz,base_x,base_y,base_z, then the joints)\n"
      "  mot          OpenSim motion (version=1, inDegrees=yes, endheader; tab-separated): time, a free base as "
      "body-fixed X-Y-Z angles (deg) and position (m), revolute joints in degrees\n"
      "  robot-csv    no header; per frame: root x,y,z, root quaternion w,x,y,z, joints (the G1 tooling layout "
      "of ../shared/datasets/robot_motion)\n"
      "  unitree-csv  Unitree's LAFAN1 retargeting CSV: no header; per frame: root x,y,z, root quaternion "
      "x,y,z,w, joints\n"
      "  gmr-npz      GMR robot motion without pickle: fps () Hz; root_pos (T,3); root_rot (T,4) x,y,z,w; dof_pos "
      "(T,J); link_body_list (B,) every URDF link; local_body_pos (T,B,3) link origins in the root link's frame; "
      "joint_names (J,)\n"
      "  mjlab-npz    BeyondMimic / mjlab motion: fps (1,) Hz; joint_pos, joint_vel (T,J); body_pos_w (T,B,3); "
      "body_quat_w (T,B,4) w,x,y,z; body_lin_vel_w, body_ang_vel_w (T,B,3) world frame (central finite "
      "differences); joint_names (J,), body_names (B,) every URDF link\n"
      "The NPZ formats need evenly spaced frames (use --rate). The format defaults from the output's extension "
      "(.mot: mot, .npz: mjlab-npz, else csv).",
      "syn-export"};
  syn::CommonFlags common;
  syn::AddCommonFlags(app, common);
  std::string input, format, model_path, floating_base = "auto";
  double rate = 0;
  app.add_option("INPUT", input, "Motion file")->required();
  app.add_option("--format", format, "csv | mot | robot-csv | unitree-csv | gmr-npz | mjlab-npz (default: from the "
                                     "output's extension)");
  app.add_option("--model", model_path,
                 "The robot URDF (needed for all but csv: joint types, URDF order, forward kinematics)");
  app.add_option("--floating-base", floating_base, "auto | free | fixed, as for syn-retarget")->capture_default_str();
  app.add_option("--rate", rate, "Resample uniformly to this rate, Hz (cubic; default: the motion's own frames)");
  return syn::RunTool(app, argc, argv, [&] {
    if (format.empty()) {
      const std::string extension = std::filesystem::path(common.output).extension().string();
      format = extension == ".mot" ? "mot" : extension == ".npz" ? "mjlab-npz" : "csv";
    }
    const std::vector<std::string> formats = {"csv", "mot", "robot-csv", "unitree-csv", "gmr-npz", "mjlab-npz"};
    if (std::find(formats.begin(), formats.end(), format) == formats.end()) {
      throw syn::UsageError("--format must be csv, mot, robot-csv, unitree-csv, gmr-npz or mjlab-npz, not '" + format + "'");
    }
    if (format != "csv" && model_path.empty()) throw syn::UsageError("--format " + format + " needs --model");
    if (rate < 0) throw syn::UsageError("--rate must be positive");
    syn::MotionData motion = syn::ReadMotionFile(input);
    if (rate > 0) motion = syn::ResampleUniformly(motion, rate);
    std::string bytes;
    if (format == "csv") {
      bytes = syn::MotionToCsv(motion);
    } else {
      const syn::Model model = syn::LoadModel(model_path, floating_base);
      syn::PrintWarnings("syn-export", model.warnings());
      syn::PrintNotes("syn-export", model.notes(), common.verbose);
      if (format == "mot") bytes = syn::MotionToMot(motion, model, std::filesystem::path(input).stem().string());
      else if (format == "robot-csv") bytes = syn::MotionToRobotCsv(motion, model);
      else if (format == "unitree-csv") bytes = syn::MotionToUnitreeCsv(motion, model);
      else if (format == "gmr-npz") bytes = syn::MotionToGmrNpz(motion, model);
      else bytes = syn::MotionToMjlabNpz(motion, model);
    }
    syn::WriteFileAtomically(common.output, bytes);
    std::cerr << "syn-export: " << input << " -> " << common.output << " (" << format << ", " << motion.frames()
              << " frames)\n";
  });
}
