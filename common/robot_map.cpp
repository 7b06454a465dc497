#include "common/robot_map.h"

#include <algorithm>
#include <set>

#include "common/error.h"
#include "common/file_bytes.h"
#include "common/marker_set.h"
#include "common/toml_fields.h"

namespace syn {
namespace {

class RobotMapParser {
 public:
  explicit RobotMapParser(std::string file) : fields_(std::move(file)) {}

  // A priority level indexes priority_weights, so it is range-checked before it is narrowed to int.
  int priority(const toml::node& value) const {
    const int64_t level = fields_.integer(value, "priority");
    if (level < 1 || level > 3) fields_.fail(value, "priority must be 1, 2 or 3");
    return static_cast<int>(level);
  }

  RobotTask task(const toml::table& table, int line) const {
    RobotTask task;
    task.line = line;
    for (const auto& [key, value] : table) {
      const std::string name(key.str());
      if (name == "landmark") {
        task.landmark = fields_.text(value, name);
        if (std::none_of(kLandmarkNames.begin(), kLandmarkNames.end(),
                         [&](const char* known) { return task.landmark == known; })) {
          fields_.fail(value, "unknown landmark '" + task.landmark + "'");
        }
      } else if (name == "link") {
        task.link = fields_.text(value, name);
      } else if (name == "type") {
        const std::string type = fields_.text(value, name);
        if (type == "pose") task.type = TaskType::kPose;
        else if (type == "orientation") task.type = TaskType::kOrientation;
        else if (type == "position") task.type = TaskType::kPosition;
        else fields_.fail(value, "task type must be pose, orientation or position, not '" + type + "'");
      } else if (name == "priority") {
        task.priority = priority(value);
      } else if (name == "weight") {
        task.weight = fields_.number(value, name);
        if (!(task.weight >= 0)) fields_.fail(value, "weight must be >= 0");
      } else {
        fields_.fail(value, "unknown task key '" + name + "' (expected landmark, link, type, priority, weight)");
      }
    }
    if (task.landmark.empty() || task.link.empty()) fields_.fail(line, "a task needs a 'landmark' and a 'link'");
    return task;
  }

  RobotFoot foot(const std::string& side, const toml::node& node) const {
    const auto* table = node.as_table();
    if (!table) fields_.fail(node, "feet." + side + " must be a table");
    RobotFoot foot;
    foot.side = side;
    foot.line = LineOf(node);
    for (const auto& [key, value] : *table) {
      const std::string name(key.str());
      if (name == "link") {
        foot.link = fields_.text(value, name);
      } else if (name == "sole_points") {
        const auto* points = value.as_array();
        if (!points || points->empty()) fields_.fail(value, "sole_points must be a list of [x, y, z]");
        for (const toml::node& point : *points) {
          const auto* xyz = point.as_array();
          if (!xyz || xyz->size() != 3) fields_.fail(point, "a sole point is [x, y, z] in the link frame (m)");
          foot.sole_points.push_back({fields_.number((*xyz)[0], "x"), fields_.number((*xyz)[1], "y"), fields_.number((*xyz)[2], "z")});
        }
      } else {
        fields_.fail(value, "unknown foot key '" + name + "' (expected link, sole_points)");
      }
    }
    if (foot.link.empty() || foot.sole_points.empty()) fields_.fail(foot.line, "feet." + side + " needs link and sole_points");
    return foot;
  }

  RobotMap parse(const std::string& toml_text) {
    const toml::table root = fields_.parseText(toml_text);
    RobotMap map;
    map.file = fields_.file();
    for (const auto& [key, value] : root) {
      const std::string name(key.str());
      if (name == "robot") {
        map.robot = fields_.text(value, name);
      } else if (name == "floating_base") {
        map.floating_base = fields_.text(value, name);
        if (map.floating_base != "auto" && map.floating_base != "free" && map.floating_base != "fixed") {
          fields_.fail(value, "floating_base must be auto, free or fixed");
        }
      } else if (name == "proportions") {
        map.proportions = fields_.text(value, name);
        if (map.proportions != "height" && map.proportions != "chains") fields_.fail(value, "proportions must be height or chains");
      } else if (name == "max_roll") {
        map.max_roll = fields_.number(value, name);
        if (!(map.max_roll >= 0 && map.max_roll <= M_PI / 2)) fields_.fail(value, "max_roll must be in [0, pi/2] rad");
      } else if (name == "base_smoothing") {
        map.base_smoothing = fields_.number(value, name);
        if (!(map.base_smoothing >= 0 && map.base_smoothing <= 1)) fields_.fail(value, "base_smoothing must be in [0, 1] s");
      } else if (name == "velocity_limit_scale") {
        map.velocity_limit_scale = fields_.number(value, name);
        if (!(map.velocity_limit_scale >= 0)) fields_.fail(value, "velocity_limit_scale must be >= 0 (0: unbounded)");
      } else if (name == "priority_weights") {
        const auto* list = value.as_array();
        if (!list || list->size() != 3) fields_.fail(value, "priority_weights must list 3 numbers (levels 1..3)");
        for (size_t i = 0; i < 3; ++i) map.priority_weights[i] = fields_.number((*list)[i], "priority_weights");
      } else if (name == "task") {
        const auto* list = value.as_array();
        if (!list) fields_.fail(value, "tasks are written as [[task]] tables");
        std::set<std::string> landmarks;
        for (const toml::node& element : *list) {
          const auto* table = element.as_table();
          if (!table) fields_.fail(element, "expected a [[task]] table");
          RobotTask parsed = task(*table, LineOf(element));
          if (!landmarks.insert(parsed.landmark).second) {
            fields_.fail(parsed.line, "landmark '" + parsed.landmark + "' has two tasks");
          }
          map.tasks.push_back(std::move(parsed));
        }
      } else if (name == "posture") {
        const auto* table = value.as_table();
        if (!table) fields_.fail(value, "[posture] must be a table");
        for (const auto& [posture_key, posture_value] : *table) {
          if (posture_key == "weight") map.posture_weight = fields_.number(posture_value, "weight");
          else if (posture_key == "priority") map.posture_priority = priority(posture_value);
          else fields_.fail(posture_value, "unknown posture key (expected weight, priority)");
        }
      } else if (name == "reference_stance" || name == "calibration_stance") {
        const auto* table = value.as_table();
        if (!table) fields_.fail(value, "[" + name + "] must map joint names to positions");
        auto& stance = name == "reference_stance" ? map.reference_stance : map.calibration_stance.emplace();
        for (const auto& [joint, position] : *table) stance[std::string(joint.str())] = fields_.number(position, "q");
      } else if (name == "joint_ranges") {
        const auto* table = value.as_table();
        if (!table) fields_.fail(value, "[joint_ranges] must map joint names to [lower, upper]");
        map.joint_ranges_line = LineOf(value);
        for (const auto& [joint, range] : *table) {
          const auto* bounds = range.as_array();
          if (!bounds || bounds->size() != 2) fields_.fail(range, "a joint range is [lower, upper] (rad or m)");
          const double lower = fields_.number((*bounds)[0], "lower"), upper = fields_.number((*bounds)[1], "upper");
          if (!(lower < upper)) fields_.fail(range, "a joint range needs lower < upper");
          map.joint_ranges[std::string(joint.str())] = {lower, upper};
        }
      } else if (name == "feet") {
        const auto* table = value.as_table();
        if (!table) fields_.fail(value, "[feet] must hold [feet.left] and [feet.right]");
        for (const auto& [side, foot_node] : *table) {
          if (side != "left" && side != "right") fields_.fail(foot_node, "feet are 'left' and 'right'");
          map.feet.push_back(foot(std::string(side.str()), foot_node));
        }
      } else {
        fields_.fail(value, "unknown key '" + name +
                                "' (expected robot, floating_base, proportions, max_roll, base_smoothing, velocity_limit_scale, priority_weights, [[task]], [posture], "
                                "[reference_stance], [calibration_stance], [joint_ranges], [feet])");
      }
    }
    if (map.tasks.empty()) fields_.fail(1, "the robot map has no [[task]]");
    return map;
  }

 private:
  TomlFields fields_;
};

}  // namespace

std::string TaskTypeName(TaskType type) {
  switch (type) {
    case TaskType::kPose: return "pose";
    case TaskType::kOrientation: return "orientation";
    case TaskType::kPosition: return "position";
  }
  return "?";
}

RobotMap ParseRobotMap(const std::string& toml_text, const std::string& file_name) {
  return RobotMapParser(file_name).parse(toml_text);
}

RobotMap LoadRobotMap(const std::string& path) { return ParseRobotMap(ReadFileText(path), path); }

void CheckRobotMapNames(const RobotMap& map, const std::function<bool(const std::string&)>& has_link,
                        const std::function<bool(const std::string&)>& has_joint, const std::string& model_name) {
  for (const RobotTask& task : map.tasks) {
    if (!has_link(task.link)) {
      throw DataError(Location::AtLine(map.file, task.line),
                      "link '" + task.link + "' (task for " + task.landmark + ") is not in " + model_name);
    }
  }
  for (const RobotFoot& foot : map.feet) {
    if (!has_link(foot.link)) {
      throw DataError(Location::AtLine(map.file, foot.line), "foot link '" + foot.link + "' is not in " + model_name);
    }
  }
  for (const auto& [joint, range] : map.joint_ranges) {
    if (!has_joint(joint)) {
      throw DataError(Location::AtLine(map.file, map.joint_ranges_line),
                      "[joint_ranges] names joint '" + joint + "', which " + model_name + " does not have");
    }
  }
  const std::map<std::string, double> no_stance;
  for (const auto& [table, stance] : {std::pair{"reference_stance", &map.reference_stance},
                                      std::pair{"calibration_stance", map.calibration_stance ? &*map.calibration_stance : &no_stance}}) {
    for (const auto& [joint, position] : *stance) {
      if (!has_joint(joint)) {
        throw DataError(Location::InFile(map.file), std::string(table) + " names joint '" + joint + "', which " +
                                                        model_name + " does not have");
      }
    }
  }
}

}  // namespace syn
