#include "stages/compose/compose_script.h"

#include <algorithm>
#include <stdexcept>

#include "common/toml_fields.h"

namespace syn {

Interpolation InterpolationFromName(const std::string& name) {
  if (name == "step") return Interpolation::kStep;
  if (name == "linear") return Interpolation::kLinear;
  if (name == "cubic") return Interpolation::kCubic;
  if (name == "minimum-jerk") return Interpolation::kMinimumJerk;
  throw std::invalid_argument("interpolation must be step, linear, cubic or minimum-jerk, not '" + name + "'");
}

const char* InterpolationName(Interpolation interpolation) {
  switch (interpolation) {
    case Interpolation::kStep: return "step";
    case Interpolation::kLinear: return "linear";
    case Interpolation::kCubic: return "cubic";
    case Interpolation::kMinimumJerk: return "minimum-jerk";
  }
  return "?";
}

double BlendWeight(Interpolation interpolation, double x) {
  x = std::clamp(x, 0.0, 1.0);
  switch (interpolation) {
    case Interpolation::kStep: return x < 1.0 ? 0.0 : 1.0;
    case Interpolation::kLinear: return x;
    case Interpolation::kCubic: return x * x * (3.0 - 2.0 * x);
    case Interpolation::kMinimumJerk: return x * x * x * (10.0 + x * (-15.0 + 6.0 * x));
  }
  return x;
}

namespace {

class ScriptParser {
 public:
  explicit ScriptParser(const std::string& path) : fields_(path) {}

  ComposeScript parse() { return parseTable(fields_.parseFile()); }
  ComposeScript parse(const std::string& toml_text) { return parseTable(fields_.parseText(toml_text)); }

 private:
  ComposeScript parseTable(const toml::table& root) {
    ComposeScript script;
    script.file = fields_.file();
    for (const auto& [key, value] : root) {
      const std::string name(key.str());
      if (name == "model") {
        script.model = fields_.text(value, name);
      } else if (name == "floating_base") {
        script.floating_base = fields_.text(value, name);
      } else if (name == "limit_scaling") {
        const std::string mode = fields_.text(value, name);
        if (mode != "joint" && mode != "step") fields_.fail(value, "limit_scaling must be joint or step");
        script.scale_whole_step = mode == "step";
      } else if (name == "start") {
        parseStart(fields_.table(value, name), script);
      } else if (name == "step") {
        const auto* steps = value.as_array();
        if (!steps) fields_.fail(value, "'step' must be an array of tables ([[step]])");
        for (const toml::node& step : *steps) script.steps.push_back(parseStep(fields_.table(step, "step")));
      } else {
        fields_.fail(value, "unknown key '" + name + "' (expected model, floating_base, limit_scaling, start, [[step]])");
      }
    }
    if (script.model.empty()) fields_.fail(1, "the script names no robot: model = \"path/to/robot.urdf\"");
    if (script.steps.empty()) fields_.fail(1, "the script has no [[step]]");
    return script;
  }

  void parseStart(const toml::table& table, ComposeScript& script) const {
    script.start_line = LineOf(table);
    bool has_time = false;
    for (const auto& [key, value] : table) {
      const std::string name(key.str());
      if (name == "synergy") script.start_synergy = fields_.text(value, name);
      else if (name == "motion") script.start_motion = fields_.text(value, name);
      else if (name == "time") { script.start_time = fields_.number(value, name); has_time = true; }
      else fields_.fail(value, "unknown start key '" + name + "' (expected synergy, or motion and time)");
    }
    if (script.start_synergy.empty() == script.start_motion.empty()) {
      fields_.fail(script.start_line, "start needs exactly one of synergy = \"STYLE/TRIAL/SEGMENT\" or motion = \"file\"");
    }
    if (has_time && script.start_motion.empty()) fields_.fail(script.start_line, "start time applies to a motion only");
  }

  // coefficients = [...] or gain = [...] of a step or keyframe.
  bool parseCoefficients(const std::string& name, const toml::node& value, CoefficientKeyframe& into) const {
    if (name == "coefficients") into.coefficients = fields_.numbers(value, name);
    else if (name == "gain") into.gains = fields_.numbers(value, name);
    else return false;
    if (!into.coefficients.empty() && !into.gains.empty()) fields_.fail(value, "give coefficients or gain, not both");
    return true;
  }

  ComposeStep parseStep(const toml::table& table) const {
    ComposeStep step;
    step.line = LineOf(table);
    CoefficientKeyframe constant;
    constant.line = step.line;
    for (const auto& [key, value] : table) {
      const std::string name(key.str());
      if (name == "synergy") {
        step.synergy = fields_.text(value, name);
      } else if (parseCoefficients(name, value, constant)) {
        constant.line = LineOf(value);
      } else if (name == "duration") {
        step.duration = fields_.number(value, name);
        if (!(*step.duration > 0)) fields_.fail(value, "duration must be positive");
      } else if (name == "repetitions") {
        // Checked before narrowing: 4294967297 would otherwise wrap to 1.
        const int64_t repetitions = fields_.integer(value, name);
        if (repetitions < 1) fields_.fail(value, "repetitions must be at least 1");
        if (repetitions > 1000000) fields_.fail(value, "repetitions must be at most 1000000");
        step.repetitions = static_cast<int>(repetitions);
      } else if (name == "interpolation") {
        try {
          step.interpolation = InterpolationFromName(fields_.text(value, name));
        } catch (const std::invalid_argument& error) {
          fields_.fail(value, error.what());
        }
      } else if (name == "blend") {
        step.blend = fields_.number(value, name);
        if (!(step.blend >= 0)) fields_.fail(value, "blend must be >= 0 s");
      } else if (name == "keyframe") {
        const auto* keyframes = value.as_array();
        if (!keyframes) fields_.fail(value, "'keyframe' must be an array of tables ([[step.keyframe]])");
        for (const toml::node& node : *keyframes) step.keyframes.push_back(parseKeyframe(fields_.table(node, "keyframe")));
      } else {
        fields_.fail(value, "unknown step key '" + name + "' (expected synergy, coefficients or gain, duration, "
                            "repetitions, interpolation, blend, [[step.keyframe]])");
      }
    }
    if (step.synergy.empty()) fields_.fail(step.line, "step has no synergy = \"STYLE/TRIAL/SEGMENT\"");
    const bool constant_given = !constant.coefficients.empty() || !constant.gains.empty();
    if (constant_given && !step.keyframes.empty()) {
      fields_.fail(constant.line, "a step has constant coefficients or keyframes, not both");
    }
    if (constant_given) step.keyframes.push_back(constant);
    std::stable_sort(step.keyframes.begin(), step.keyframes.end(),
                     [](const CoefficientKeyframe& a, const CoefficientKeyframe& b) { return a.at < b.at; });
    return step;
  }

  CoefficientKeyframe parseKeyframe(const toml::table& table) const {
    CoefficientKeyframe keyframe;
    keyframe.line = LineOf(table);
    bool has_at = false;
    for (const auto& [key, value] : table) {
      const std::string name(key.str());
      if (name == "at") {
        keyframe.at = fields_.number(value, name);
        has_at = true;
        if (!(keyframe.at >= 0 && keyframe.at <= 1)) fields_.fail(value, "keyframe 'at' is normalized step time in [0, 1]");
      } else if (!parseCoefficients(name, value, keyframe)) {
        fields_.fail(value, "unknown keyframe key '" + name + "' (expected at, coefficients or gain)");
      }
    }
    if (!has_at) fields_.fail(keyframe.line, "keyframe needs at = normalized time in [0, 1]");
    if (keyframe.coefficients.empty() && keyframe.gains.empty()) {
      fields_.fail(keyframe.line, "keyframe needs coefficients = [...] or gain = [...]");
    }
    return keyframe;
  }

  TomlFields fields_;
};

}  // namespace

ComposeScript LoadComposeScript(const std::string& path) { return ScriptParser(path).parse(); }

ComposeScript ParseComposeScript(const std::string& toml_text, const std::string& file_name) {
  return ScriptParser(file_name).parse(toml_text);
}

}  // namespace syn
