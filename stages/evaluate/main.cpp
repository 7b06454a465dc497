// syn-evaluate IN.motion.h5 --model ROBOT.urdf [--synergies S.h5] [--robot-map MAP.toml] -o OUT.metrics.json:
// the paper's metrics, per trial, per segment and for Monte-Carlo synergy reconstructions.
#include <iostream>

#include "common/cli.h"
#include "common/file_bytes.h"
#include "common/intermediate_file.h"
#include "stages/evaluate/evaluate.h"

int main(int argc, char** argv) {
  CLI::App app{"Evaluate a motion as the paper does, on a uniform grid (cubic resampling, default 1 kHz): mean dP = "
               "mean |p_k - p_(k-1)| with p = A(q)u, mean dKE with KE = u'Au/2, mechanical power sum_actuated "
               "|tau_i u_i| / total mass (tau by inverse dynamics; free-base residual excluded), the foot-sliding "
               "ratio and, with --synergies, Monte-Carlo reconstructions a_i = sigma_i (1 + delta_i), delta ~ "
               "U(-alpha, alpha), integrated from each segment's q0.",
               "syn-evaluate"};
  syn::CommonFlags common;
  syn::AddCommonFlags(app, common);
  syn::EvaluateOptions options;
  std::string input, model_path, robot_map_path, synergies_path, csv_path, floating_base = "auto";
  app.add_option("INPUT", input, "Motion file (syn-retarget, syn-compose or syn-project)")->required();
  app.add_option("--model", model_path, "The robot URDF the motion was made with")->required();
  app.add_option("--floating-base", floating_base, "auto | free | fixed, as for syn-retarget")->capture_default_str();
  app.add_option("--robot-map", robot_map_path, "Robot map whose [[foot]] sole points define foot sliding "
                                                "(without it, no foot-sliding ratio)");
  app.add_option("--synergies", synergies_path, "Synergies of this motion: per-segment metrics and Monte-Carlo");
  app.add_option("--csv", csv_path, "Also write one row per segment to this CSV file");
  app.add_option("--eval-rate", options.eval_rate, "Evaluation grid, Hz (paper: the 1 kHz control rate)")
      ->capture_default_str();
  app.add_option("--samples", options.monte_carlo.samples, "Monte-Carlo reconstructions per segment (paper: 100)")
      ->capture_default_str();
  app.add_option("--alpha", options.monte_carlo.alpha, "Coefficient perturbation: delta ~ U(-alpha, alpha) (paper: 0.2)")
      ->capture_default_str();
  app.add_option("--threads", options.threads,
                 "Threads for the Monte-Carlo reconstructions; 0 = SYN_THREADS if set, else the cores make -jN "
                 "leaves (cores / N), else every core. Any count gives byte-identical output")
      ->capture_default_str();
  app.add_option("--seed", options.monte_carlo.seed, "Random seed; same seed, same numbers")->capture_default_str();
  app.add_option("--contact-height", options.sliding.contact_height,
                 "A foot is in contact below this height, m (text-to-motion foot skating, GMD 2023: 0.05)")
      ->capture_default_str();
  app.add_option("--slide-speed", options.sliding.slide_speed,
                 "A foot in contact slides above this horizontal speed, m/s (GMD 2023: 2.5 cm per frame at 20 fps "
                 "= 0.5)")
      ->capture_default_str();
  app.add_option("--slide-window", options.sliding.window,
                 "The speed is the sole centroid's displacement over this centred window, s (one 20 fps frame)")
      ->capture_default_str();
  app.add_option("--penetration", options.sliding.penetration, "A foot deeper than this below z = 0 counts too, m")
      ->capture_default_str();
  const auto parameters = [&] {
    syn::RequireValid(options);
    return syn::WithFloatingBase(options.ToJson(), floating_base);
  };
  return syn::RunTool(app, argc, argv, parameters, [&] {
    syn::RequireValid(options);
    const syn::Model model = syn::LoadModel(model_path, floating_base);
    syn::PrintWarnings("syn-evaluate", model.warnings());
    syn::PrintNotes("syn-evaluate", model.notes(), common.verbose);
    std::vector<syn::FootPoints> feet;
    if (!robot_map_path.empty()) feet = syn::FeetOnModel(syn::LoadRobotMap(robot_map_path), model);
    const syn::MotionData motion = syn::ReadMotionFile(input);
    syn::TrialSynergies synergies;
    if (!synergies_path.empty()) synergies = syn::ReadTrialSynergies(synergies_path, nullptr);

    nlohmann::json metrics = syn::EvaluateMotion(motion, model, feet, synergies_path.empty() ? nullptr : &synergies,
                                                 options, synergies_path);
    metrics["producer"] = std::string("syn-evaluate ") + syn::kVersion;
    metrics["parameters"]["floating_base"] = floating_base;
    nlohmann::json inputs = nlohmann::json::array({syn::DescribeInput(input), syn::DescribeInput(model_path)});
    for (const std::string& path : {robot_map_path, synergies_path}) {
      if (!path.empty()) inputs.push_back(syn::DescribeInput(path));
    }
    metrics["inputs"] = inputs;
    if (!csv_path.empty()) syn::WriteFileAtomically(csv_path, syn::SegmentMetricsCsv(metrics));
    syn::WriteFileAtomically(common.output, metrics.dump(1) + "\n");

    const nlohmann::json& trial = metrics["trial"];
    std::cerr << "syn-evaluate: " << input << " -> " << common.output << ": mean dP " << trial["mean_delta_p"]
              << ", mean dKE " << trial["mean_delta_ke"] << ", power " << trial["mean_power_w_per_kg"]
              << " W/kg, foot sliding " << trial["foot_sliding_ratio"];
    if (trial.contains("base_residual")) {
      std::cerr << ", base residual unexplained by contact forces " << trial["base_residual"]["mean_unexplained_force_n"]
                << " N / " << trial["base_residual"]["mean_unexplained_moment_nm"] << " N·m";
    }
    if (metrics.contains("monte_carlo") && metrics["monte_carlo"].contains("mean_rank_k_relative_change_delta_p")) {
      std::cerr << "; rank-k change dP " << metrics["monte_carlo"]["mean_rank_k_relative_change_delta_p"] << ", dKE "
                << metrics["monte_carlo"]["mean_rank_k_relative_change_delta_ke"];
    }
    std::cerr << "\n";
  });
}
