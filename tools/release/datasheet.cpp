#include "tools/release/datasheet.h"

#include <cstdio>
#include <filesystem>
#include <map>
#include <set>
#include <sstream>

#include <nlohmann/json.hpp>

#include "common/error.h"
#include "common/file_bytes.h"
#include "common/intermediate_file.h"
#include "common/library_file.h"
#include "common/model.h"
#include "common/motion_file.h"
#include "common/robot_map.h"
#include "common/sha256.h"
#include "common/synergies_file.h"
#include "common/version.h"
#include "tools/release/trial_quality.h"

namespace syn {
namespace {
namespace fs = std::filesystem;

std::string OrUnknown(const std::string& text) { return text.empty() ? "unknown" : text; }

// A table cell: '|' would end it, a newline would end the row.
std::string Cell(std::string text) {
  std::string cell;
  for (char c : text) cell += c == '|' ? std::string("\\|") : c == '\n' ? std::string(" ") : std::string(1, c);
  return cell;
}

std::string JoinedNames(const std::vector<std::string>& names) {
  std::string text;
  for (const std::string& name : names) text += (text.empty() ? "" : ", ") + name;
  return text;
}

// The first line of a text file that is not part of a leading header (mot: the line after "endheader").
std::string HeaderRow(const std::string& path, bool after_endheader) {
  std::istringstream lines(ReadFileText(path));
  bool in_body = !after_endheader;
  for (std::string line; std::getline(lines, line);) {
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (in_body) return line;
    if (line == "endheader") in_body = true;
  }
  return "";
}

// Groups trials by the canonical JSON of one stage's parameters: "`{...}`: trial, trial".
std::string ParameterGroups(const std::map<std::string, std::vector<std::string>>& trials_by_parameters, size_t trial_count) {
  std::string text;
  for (const auto& [parameters, trials] : trials_by_parameters) {
    text += "    - `" + parameters + "`" + (trials.size() == trial_count ? " (every trial)" : ": " + JoinedNames(trials)) + "\n";
  }
  return text;
}

struct TrialRow {
  const ReleaseTrial* trial;
  TrialQuality quality;
};

}  // namespace

Datasheet MakeDatasheet(const ReleaseManifest& manifest, const std::vector<ReleaseFile>& files,
                        const std::function<std::string(const std::string&)>& disk_path) {
  const std::string urdf = "robot/" + fs::path(manifest.model).filename().string();
  const std::string robot_map_file = "robot/" + fs::path(manifest.robot_map).filename().string();
  std::map<std::string, int> priority_of_landmark;
  std::string map_floating_base = "auto";
  if (!manifest.robot_map.empty()) {
    const RobotMap robot_map = LoadRobotMap(disk_path(robot_map_file));
    for (const RobotTask& task : robot_map.tasks) priority_of_landmark[task.landmark] = task.priority;
    map_floating_base = robot_map.floating_base;
  }

  // Per trial: quality, and the parameters each stage recorded in its output.
  std::vector<TrialRow> rows;
  std::map<std::string, std::map<std::string, std::vector<std::string>>> parameters;  // stage -> json -> trials
  std::string floating_base = map_floating_base;  // syn-retarget's default, --floating-base map
  for (const ReleaseTrial& trial : manifest.trials) {
    const std::string dir = "trials/" + trial.id + "/";
    rows.push_back({&trial, ReadTrialQuality(disk_path(dir + "motion.h5"), disk_path(dir + "metrics.json"), priority_of_landmark)});
    const IntermediateReader motion(disk_path(dir + "motion.h5"), kMotionSchema, kMotionSchemaVersion);
    const nlohmann::json& retarget = motion.provenance().parameters;
    if (retarget.contains("floating_base") && retarget["floating_base"].is_string() && retarget["floating_base"] != "map") {
      floating_base = retarget["floating_base"].get<std::string>();
    }
    parameters[motion.provenance().producer.substr(0, motion.provenance().producer.find(' '))][CanonicalJson(retarget)].push_back(trial.id);
    nlohmann::json synergies = IntermediateReader(disk_path(dir + "synergies.h5"), kSynergiesSchema, kSynergiesSchemaVersion).provenance().parameters;
    for (const char* label : {"subject", "trial", "style", "motion_class"}) synergies.erase(label);
    parameters["syn-synergies"][CanonicalJson(synergies)].push_back(trial.id);
    const nlohmann::json metrics = nlohmann::json::parse(ReadFileText(disk_path(dir + "metrics.json")));
    parameters["syn-evaluate"][CanonicalJson(metrics.value("parameters", nlohmann::json::object()))].push_back(trial.id);
    for (const std::string& format : manifest.exports) {
      const std::string stamp = "params/" + trial.id + ".export." + format + ".json";
      parameters["syn-export"][CanonicalJson(nlohmann::json::parse(ReadFileText(disk_path(stamp))))].push_back(trial.id);
    }
  }
  parameters["syn-library"][CanonicalJson(IntermediateReader(disk_path("library.h5"), kLibrarySchema, kLibrarySchemaVersion).provenance().parameters)]
      .push_back("library.h5");

  // quality.csv
  std::string csv =
      "trial,subject,motion_class,style,frames,duration_s,rate_hz,p1_position_error_median_mm,p1_position_error_p95_mm,"
      "p1_angle_error_median_deg,p1_angle_error_p95_deg,p2_position_error_median_mm,p2_position_error_p95_mm,"
      "p2_angle_error_median_deg,p2_angle_error_p95_deg,stance_drift_median_mm,stance_drift_p95_mm,"
      "deepest_penetration_mm,penetration_frames_ratio,foot_sliding_ratio,contact_feet\n";
  std::set<std::string> subjects;
  int64_t total_frames = 0;
  double total_seconds = 0;
  for (const TrialRow& row : rows) {
    const TrialQuality& q = row.quality;
    std::string feet;
    for (const std::string& foot : q.contact_feet) feet += (feet.empty() ? "" : ";") + foot;
    csv += row.trial->id + "," + row.trial->subject + "," + row.trial->motion_class + "," + row.trial->style + "," +
           std::to_string(q.frames) + "," + FigureText(q.duration_s, 4) + "," + FigureText(q.rate_hz, 3) + "," +
           FigureText(q.p1_position_median_mm, 1) + "," + FigureText(q.p1_position_p95_mm, 1) + "," +
           FigureText(q.p1_angle_median_deg, 2) + "," + FigureText(q.p1_angle_p95_deg, 2) + "," +
           FigureText(q.p2_position_median_mm, 1) + "," + FigureText(q.p2_position_p95_mm, 1) + "," +
           FigureText(q.p2_angle_median_deg, 2) + "," + FigureText(q.p2_angle_p95_deg, 2) + "," +
           FigureText(q.stance_drift_median_mm, 1) + "," + FigureText(q.stance_drift_p95_mm, 1) + "," +
           FigureText(q.deepest_penetration_mm, 1) + "," + FigureText(q.penetration_frames_ratio, 4) + "," +
           FigureText(q.foot_sliding_ratio, 4) + "," + (feet.empty() ? "n/a" : feet) + "\n";
    subjects.insert(row.trial->subject);
    total_frames += q.frames;
    total_seconds += q.duration_s;
  }

  // The robot, as the exports lay it out.
  const Model model = LoadModel(disk_path(urdf), floating_base);
  std::vector<std::string> joints;
  for (const ModelJoint& joint : model.joints()) {
    if (joint.q_index >= 0 && joint.type != "free") joints.push_back(joint.name);
  }

  std::ostringstream md;
  md << "# " << manifest.name << " " << manifest.version << ": robot motions retargeted from motion capture\n\n";
  md << "*Generated by syn-release (synsculpt " << kVersion << ") from the files of this release; `syn-release verify` "
     << "makes it again and compares.*\n\n";
  if (!manifest.description.empty()) md << manifest.description << ".\n\n";
  md << "Human motion-capture trials retargeted onto the robot **" << model.name() << "** by the synsculpt pipeline "
     << "(ingest, retarget, segment, postural synergies, evaluate), with the robot motion of every trial, its exports for "
     << "robot-learning tools, per-trial quality figures, the postural-synergy libraries per style and the pipeline's "
     << "parameters.\n\n";
  char totals[256];
  std::snprintf(totals, sizeof totals, "%s%zu trials, %zu subjects, %lld frames, %.3f s (%.4f h) of robot motion.\n\n",
                kTotalsPrefix, rows.size(), subjects.size(), static_cast<long long>(total_frames), total_seconds,
                total_seconds / 3600.0);
  md << totals;
  md << "**Release licence:** " << OrUnknown(manifest.release_licence) << ". The captures keep their own licences "
     << "(\"Sources and licences\" below); the robot model keeps its own.\n\n";

  md << "## Contents\n\n| path | what |\n|---|---|\n"
     << "| `README.md` | this datasheet |\n"
     << "| `quality.csv` | one row per trial: frames, duration, tracking errors, stance drift, penetration, foot sliding |\n"
     << "| `SHA256SUMS` | SHA-256 of every other file (`sha256sum -c SHA256SUMS`) |\n"
     << "| `manifest.toml` | the manifest the release was made from (trials, labels, parameters, licences) |\n"
     << "| `provenance.json` | synsculpt version, dataset root, versions of the numeric libraries |\n"
     << "| `robot/` | the robot URDF, its robot map (which link tracks which landmark, at which priority)"
     << (manifest.model_licence_file.empty() ? "" : ", the URDF's licence") << " |\n"
     << "| `trials/ID/motion.h5` | the robot motion (HDF5, schema synsculpt.motion): time, q, u, udot, tau, landmark targets "
        "and errors; contact flags when the pipeline detected them |\n"
     << "| `trials/ID/synergies.h5`, `metrics.json` | per-segment postural synergies; syn-evaluate's energy, power and "
        "foot-sliding figures |\n";
  for (const std::string& format : manifest.exports) {
    md << "| `trials/ID/" << FindReleaseExportFormat(format)->file_name << "` | the motion as syn-export `" << format
       << "` (columns below) |\n";
  }
  md << "| `trials/ID/contact.csv` | per frame, 1 where a foot is planted (only for trials whose motion.h5 has contact flags) |\n"
     << "| `library.h5`, `library/STYLE.h5` | postural-synergy libraries, every style and per style |\n"
     << "| `summary/trials.csv`, `summary/segments.csv` | per-trial and per-segment summaries (syn-summary) |\n"
     << "| `params/` | the manifest's parameters per job (stage defaults apply to everything not listed) |\n\n";

  md << "## Robot\n\n"
     << "- URDF: `" << urdf << "`, robot `" << model.name() << "`, " << joints.size() << " actuated joints, "
     << (model.hasFreeBase() ? "free-floating base" : "fixed base") << ", " << model.linkNames().size() << " links, "
     << FigureText(model.totalMass(), 3) << " kg\n"
     << "- URDF SHA-256: `" << Sha256OfFile(disk_path(urdf)) << "` (every motion.h5 records the same in `model_sha256`)\n"
     << "- Source: " << OrUnknown(manifest.model_source) << "\n"
     << "- Licence: " << OrUnknown(manifest.model_licence)
     << (manifest.model_licence_file.empty() ? "" : " (`robot/" + fs::path(manifest.model_licence_file).filename().string() + "`)")
     << "\n- Robot map: `" << robot_map_file << "`\n\n";

  md << "## Pipeline\n\n";
  nlohmann::json provenance = nlohmann::json::object();
  for (const ReleaseFile& file : files) {
    if (file.path == "provenance.json") provenance = nlohmann::json::parse(file.contents());
  }
  md << "- Tool: " << provenance.value("tool", std::string("unknown")) << "\n";
  if (provenance.contains("dependencies") && provenance["dependencies"].is_object()) {
    md << "- Numeric libraries (Debian packages):";
    for (const auto& [package, version] : provenance["dependencies"].items()) md << " " << package << " " << version.get<std::string>() << ";";
    md << "\n";
  }
  md << "- Parameters each stage recorded in its outputs (canonical JSON; `syn-STAGE --help` documents each):\n";
  for (const auto& [stage, groups] : parameters) md << "  - " << stage << ":\n" << ParameterGroups(groups, stage == "syn-library" ? 0 : rows.size());
  md << "\n";

  // Capture licences, numbered for the trial table (L1, L2, ...), each with its sources and their trials.
  std::map<std::string, std::map<std::string, std::vector<std::string>>> by_licence;  // licence -> source -> trials
  for (const ReleaseTrial& trial : manifest.trials) by_licence[trial.licence][trial.source].push_back(trial.id);
  std::map<std::string, std::string> licence_key;
  int licence_number = 0;
  for (const auto& [licence, sources] : by_licence) licence_key[licence] = std::string("L").append(std::to_string(++licence_number));

  md << "## Trials\n\n"
     << "Quality columns (all in `quality.csv`): P1/P2 = landmark tracking error of the robot map's priority-1 tasks "
        "(pelvis, feet, hands pose; head orientation) and priority-2 tasks (upper torso, elbows orientation), median / "
        "95th percentile over frames and landmarks; stance drift = how far a planted foot slides, median / p95; "
        "penetration = deepest sole point below the floor and the fraction of frames with one more than 1 cm below; "
        "sliding = syn-evaluate's foot-sliding ratio. \"n/a\": the motion file carries no such figure.\n\n"
     << "| trial | subject | class | style | frames | duration s | P1 position mm | P1 angle deg | P2 angle deg | "
        "stance drift mm | deepest penetration mm | penetration frames | sliding | licence |\n"
     << "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n";
  for (const TrialRow& row : rows) {
    const TrialQuality& q = row.quality;
    md << "| " << row.trial->id << " | " << row.trial->subject << " | " << row.trial->motion_class << " | " << row.trial->style
       << " | " << q.frames << " | " << FigureText(q.duration_s, 2) << " | " << FigureText(q.p1_position_median_mm, 1) << " / "
       << FigureText(q.p1_position_p95_mm, 1) << " | " << FigureText(q.p1_angle_median_deg, 2) << " / "
       << FigureText(q.p1_angle_p95_deg, 2) << " | " << FigureText(q.p2_angle_median_deg, 2) << " / "
       << FigureText(q.p2_angle_p95_deg, 2) << " | " << FigureText(q.stance_drift_median_mm, 1) << " / "
       << FigureText(q.stance_drift_p95_mm, 1) << " | " << FigureText(q.deepest_penetration_mm, 1) << " | "
       << FigureText(q.penetration_frames_ratio, 4) << " | " << FigureText(q.foot_sliding_ratio, 3) << " | "
       << licence_key[row.trial->licence] << " |\n";
  }
  md << "\n";

  md << "## Exports\n\nEvery export holds the motion at its own frame times (uniform rate, see `quality.csv` rate_hz), in "
        "synsculpt's world frame: Z up, metres, radians, joints in the URDF's joint order. The " << joints.size()
     << " joints, in that order: " << JoinedNames(joints) << ".\n\n";
  const std::string first = manifest.trials.empty() ? "" : "trials/" + manifest.trials.front().id + "/";
  for (const std::string& format : manifest.exports) {
    const std::string file = FindReleaseExportFormat(format)->file_name;
    md << "- `" << file << "` (syn-export `" << format << "`): ";
    if (format == "robot-csv") {
      md << "no header; per frame: root_x, root_y, root_z, root_qw, root_qx, root_qy, root_qz, then the joints (rad).\n";
    } else if (format == "unitree-csv") {
      md << "Unitree's LAFAN1-retargeting CSV: no header; per frame: root_x, root_y, root_z, root_qx, root_qy, root_qz, "
            "root_qw (scalar last), then the joints (rad). The rate is not stored.\n";
    } else if (format == "mjlab-npz") {
      md << "BeyondMimic / mjlab motion NPZ (float64): fps (1,); joint_pos, joint_vel (T," << joints.size()
         << "); body_pos_w (T," << model.linkNames().size() << ",3); body_quat_w (T," << model.linkNames().size()
         << ",4) w,x,y,z; body_lin_vel_w, body_ang_vel_w (T," << model.linkNames().size()
         << ",3) world frame (finite differences); joint_names, body_names (every URDF link in file order).\n";
    } else if (format == "gmr-npz") {
      md << "GMR robot motion NPZ without pickle: fps (); root_pos (T,3); root_rot (T,4) x,y,z,w; dof_pos (T,"
         << joints.size() << "); link_body_list (" << model.linkNames().size() << ",); local_body_pos (T,"
         << model.linkNames().size() << ",3) in the root link's frame; joint_names.\n";
    } else if (format == "mot") {
      md << "OpenSim motion, inDegrees=yes, tab-separated; header row: `" << Cell(HeaderRow(disk_path(first + file), true)) << "`.\n";
    } else {
      md << "header row: `" << Cell(HeaderRow(disk_path(first + file), false)) << "`.\n";
    }
  }
  md << "\n";

  md << "## Sources and licences\n\nThe captures are not in this release. Their licences and sources, as `manifest.toml` "
        "gives them (\"unknown\": the manifest names none):\n\n";
  for (const auto& [licence, sources] : by_licence) {
    md << "- **" << licence_key[licence] << "** " << OrUnknown(licence) << "\n";
    for (const auto& [source, trials] : sources) {
      md << "  - " << OrUnknown(source) << ": " << JoinedNames(trials) << "\n";
    }
  }
  md << "\n## How to cite\n\n"
     << (manifest.citation.empty()
             ? "Cite this release as \"" + manifest.name + " " + manifest.version + ", made with synsculpt " + kVersion +
                   "\", cite the SynSculptor paper for the method, and acknowledge every capture source as its licence asks (above)."
             : manifest.citation)
     << "\n\n## How to check it\n\n"
     << "`sha256sum -c SHA256SUMS` in this folder, or `syn-release verify " << manifest.name << "-" << manifest.version
     << ".tar` (checksums, schema and version of every file, every trial of the manifest present); `syn-release verify "
        "--rebuild` in a synsculpt source tree re-runs the pipeline from the captures and compares every byte.\n";
  return {md.str(), csv};
}

}  // namespace syn
