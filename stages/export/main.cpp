// syn-export IN.motion.h5 -o OUT.{csv,mot} [--format csv|mot|robot-csv] [--model ROBOT.urdf] [--rate HZ].
#include <filesystem>
#include <iostream>

#include "common/cli.h"
#include "common/file_bytes.h"
#include "stages/export/motion_export.h"

int main(int argc, char** argv) {
  CLI::App app{"Write a motion as text: csv (time and every coordinate, named header), mot (OpenSim motion: "
               "version=1, inDegrees=yes, endheader; revolute joints in degrees, a free base as X-Y-Z angles and "
               "position, synsculpt's Z-up axes) or robot-csv (no header; root position, root quaternion w,x,y,z, "
               "joints in URDF order: the G1 tooling layout). The format defaults from the output's extension.",
               "syn-export"};
  syn::CommonFlags common;
  syn::AddCommonFlags(app, common);
  std::string input, format, model_path, floating_base = "auto";
  double rate = 0;
  app.add_option("INPUT", input, "Motion file")->required();
  app.add_option("--format", format, "csv | mot | robot-csv (default: from the output's extension)");
  app.add_option("--model", model_path, "The robot URDF (needed for mot and robot-csv: joint types and URDF order)");
  app.add_option("--floating-base", floating_base, "auto | free | fixed, as for syn-retarget")->capture_default_str();
  app.add_option("--rate", rate, "Resample uniformly to this rate, Hz (cubic; default: the motion's own frames)");
  return syn::RunTool(app, argc, argv, [&] {
    if (format.empty()) {
      const std::string extension = std::filesystem::path(common.output).extension().string();
      format = extension == ".mot" ? "mot" : "csv";
    }
    if (format != "csv" && format != "mot" && format != "robot-csv") {
      throw syn::UsageError("--format must be csv, mot or robot-csv, not '" + format + "'");
    }
    if (format != "csv" && model_path.empty()) throw syn::UsageError("--format " + format + " needs --model");
    if (rate < 0) throw syn::UsageError("--rate must be positive");
    syn::MotionData motion = syn::ReadMotionFile(input);
    if (rate > 0) motion = syn::ResampleUniformly(motion, rate);
    std::string text;
    if (format == "csv") {
      text = syn::MotionToCsv(motion);
    } else {
      const syn::Model model = syn::LoadModel(model_path, floating_base);
      text = format == "mot" ? syn::MotionToMot(motion, model, std::filesystem::path(input).stem().string())
                             : syn::MotionToRobotCsv(motion, model);
    }
    syn::WriteFileAtomically(common.output, text);
    std::cerr << "syn-export: " << input << " -> " << common.output << " (" << format << ", " << motion.frames()
              << " frames)\n";
  });
}
