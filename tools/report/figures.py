"""The paper's archive-wide figures (Fig. 4-7) and the human-vs-robot power table, from the stage outputs.

Each function reads only the files it is given (the make rule lists the same files as prerequisites, so a
figure is redrawn exactly when one of them changes) and returns a dict the page shows beside the figure
(numbers, or why a figure is empty).
"""
import csv
import json

import numpy as np

import plotting
from files import open_hdf5

COLORS = {"original": "#c9a227", "reconstruction": "#3b6fb6", "raw": "#2a9d8f", "projected": "#7b3fa0"}


def _text(value):
    return value.decode() if isinstance(value, bytes) else str(value)


def read_trial_pcs(synergies_path):
    """The trial's labels and, per segment, the variance explained by PC1-3 (NaN past the file's components)."""
    with open_hdf5(synergies_path) as file:
        labels = {key: _text(file.attrs.get(key, "")) for key in ("trial", "style", "motion_class", "subject")}
        rows = []
        segments = file["segments"] if "segments" in file else {}
        for name in sorted(segments.keys()):  # segments/000, 001, ...
            ratios = np.asarray(segments[name]["explained_variance_ratio"][()], dtype=float)
            padded = np.full(3, np.nan)
            padded[:min(3, ratios.size)] = ratios[:3]
            rows.append(padded)
    return labels, np.array(rows).reshape(-1, 3)


def _grouped_pcs(synergies_paths, group_of):
    groups = {}
    for path in synergies_paths:
        labels, pcs = read_trial_pcs(path)
        group = group_of(labels)
        if group is not None and pcs.size:
            groups.setdefault(group, []).append(pcs)
    return {group: np.vstack(parts) for group, parts in sorted(groups.items())}


def _pc_bars(groups, title, output_stem):
    figure, axes = plotting.new_figure(max(4.0, 1.2 * len(groups) + 2), 3.4)
    width = 0.26
    summary = {}
    for g, (group, pcs) in enumerate(groups.items()):
        mean, sd = np.nanmean(pcs, axis=0) * 100, np.nanstd(pcs, axis=0) * 100
        summary[group] = {"segments": int(pcs.shape[0]), "mean_percent": [round(float(v), 1) for v in mean],
                          "sd_percent": [round(float(v), 1) for v in sd]}
        for k in range(3):
            axes.bar(g + (k - 1) * width, mean[k], width, yerr=sd[k], capsize=3,
                     color=("#1f4e79", "#4f8fc0", "#a9cbe8")[k], label=f"PC{k + 1}" if g == 0 else None)
    axes.set_xticks(range(len(groups)))
    axes.set_xticklabels([f"{group}\n(n={pcs.shape[0]})" for group, pcs in groups.items()])
    axes.set_ylabel("variance explained (%)")
    axes.set_ylim(0, 105)
    axes.set_title(title)
    if groups:
        axes.legend(frameon=False, ncol=3)
    else:
        axes.text(0.5, 0.5, "no trials in this archive", ha="center", va="center", transform=axes.transAxes)
    plotting.save(figure, output_stem)
    return summary


def fig4(synergies_paths, output_stem):
    groups = _grouped_pcs(synergies_paths, lambda labels: labels["motion_class"] or "unlabelled")
    return {"groups": _pc_bars(groups, "Variance explained by PC1-3 per motion class", output_stem)}


def fig5(synergies_paths, output_stem):
    groups = _grouped_pcs(synergies_paths,
                          lambda labels: (labels["style"] or "unlabelled") if labels["motion_class"] == "dance" else None)
    return {"groups": _pc_bars(groups, "Variance explained by PC1-3 per dance genre", output_stem)}


def _metrics(path):
    with open(path) as file:
        return json.load(file)


def _class_of(metrics_path, synergies_path):
    labels, _ = read_trial_pcs(synergies_path)
    return labels["motion_class"] or "unlabelled"


def fig6(metrics_paths, synergies_paths, output_stem):
    """Per motion class, mean over segments of ΔP̄ and ΔK̄E: original, rank-k reconstruction, and the
    perturbed Monte-Carlo samples (mean ± the mean of their per-segment sd)."""
    table = {}
    for metrics_path, synergies_path in zip(metrics_paths, synergies_paths):
        group = _class_of(metrics_path, synergies_path)
        for segment in _metrics(metrics_path).get("segments", []):
            mc = segment.get("monte_carlo")
            if not mc:
                continue
            entry = table.setdefault(group, {"segments": 0, "values": {}})
            entry["segments"] += 1
            for key in ("mean_delta_p", "mean_delta_ke"):
                for variant, value in (("original", mc["original"][key]), ("rank_k", mc["rank_k"][key]),
                                       ("perturbed", mc["perturbed"][key]["mean"]),
                                       ("perturbed_sd", mc["perturbed"][key]["std"])):
                    entry["values"].setdefault(key, {}).setdefault(variant, []).append(value)
    figure, axes_pair = plotting.new_figure(9.0, 3.4, columns=2)
    groups = sorted(table)
    summary = {}
    for axes, key, label in ((axes_pair[0], "mean_delta_p", "mean ΔP (kg·m/s per step)"),
                             (axes_pair[1], "mean_delta_ke", "mean ΔKE (J per step)")):
        width = 0.26
        for g, group in enumerate(groups):
            values = table[group]["values"][key]
            means = {variant: float(np.mean(values[variant])) for variant in values}
            summary.setdefault(group, {"segments": table[group]["segments"]})[key] = {
                variant: float(f"{value:.6g}") for variant, value in means.items()}
            for v, (variant, color, name) in enumerate((("original", COLORS["original"], "original"),
                                                        ("rank_k", COLORS["reconstruction"], "rank-k reconstruction"),
                                                        ("perturbed", "#8fb3de", "100 perturbed reconstructions"))):
                axes.bar(g + (v - 1) * width, means[variant], width, color=color, label=name if g == 0 else None,
                         yerr=means["perturbed_sd"] if variant == "perturbed" else None, capsize=3)
        axes.set_xticks(range(len(groups)))
        axes.set_xticklabels([f"{group}\n(n={table[group]['segments']})" for group in groups])
        axes.set_ylabel(label)
    if groups:
        axes_pair[0].legend(frameon=False, fontsize=8)
    else:
        for axes in axes_pair:
            axes.text(0.5, 0.5, "no Monte-Carlo segments", ha="center", va="center", transform=axes.transAxes)
    figure.suptitle("Energetic reconstruction: original vs synergy reconstructions (per motion class)")
    plotting.save(figure, output_stem)
    return {"groups": summary}


def fig7(metrics_paths, synergies_paths, project_pairs, output_stem):
    """Foot-sliding ratio and mean power per motion class: original motion and rank-k reconstruction (their
    segments' means); then each text-to-motion input raw and projected (`project_pairs`: name, raw metrics,
    projected metrics)."""
    rows = {}
    for metrics_path, synergies_path in zip(metrics_paths, synergies_paths):
        group = _class_of(metrics_path, synergies_path)
        metrics = _metrics(metrics_path)
        entry = rows.setdefault(group, {"original": {"foot_sliding_ratio": [], "mean_power_w_per_kg": []},
                                        "reconstruction": {"foot_sliding_ratio": [], "mean_power_w_per_kg": []}})
        for key in ("foot_sliding_ratio", "mean_power_w_per_kg"):
            entry["original"][key].append(metrics["trial"][key])
            for segment in metrics.get("segments", []):
                rank_k = segment.get("monte_carlo", {}).get("rank_k", {})
                if key in rank_k:
                    entry["reconstruction"][key].append(rank_k[key])
    bars = []  # (group label, variant, sliding, power)
    for group in sorted(rows):
        for variant in ("original", "reconstruction"):
            values = rows[group][variant]
            if values["foot_sliding_ratio"]:
                bars.append((group, variant, float(np.mean(values["foot_sliding_ratio"])),
                             float(np.mean(values["mean_power_w_per_kg"]))))
    for name, raw_path, projected_path in project_pairs:
        for variant, path in (("raw", raw_path), ("projected", projected_path)):
            trial = _metrics(path)["trial"]
            bars.append((f"t2m {name}", variant, trial["foot_sliding_ratio"], trial["mean_power_w_per_kg"]))
    groups = list(dict.fromkeys(bar[0] for bar in bars))
    figure, axes_pair = plotting.new_figure(max(9.0, 0.9 * len(groups) + 3), 3.8, columns=2)
    width = 0.38
    for axes, column, label in ((axes_pair[0], 2, "foot-sliding ratio"), (axes_pair[1], 3, "mean power (W/kg)")):
        seen = set()
        for bar in bars:
            g = groups.index(bar[0])
            offset = -width / 2 if bar[1] in ("original", "raw") else width / 2
            axes.bar(g + offset, bar[column], width, color=COLORS[bar[1]],
                     label=bar[1] if bar[1] not in seen else None)
            seen.add(bar[1])
        axes.set_xticks(range(len(groups)))
        axes.set_xticklabels(groups, rotation=30, ha="right", fontsize=8)
        axes.set_ylabel(label)
    axes_pair[0].set_ylim(0, 1.3)  # a ratio: the legend goes in the headroom
    axes_pair[0].legend(frameon=False, fontsize=8, ncol=4, loc="upper left")
    if not project_pairs:
        axes_pair[1].text(0.98, 0.98, "text-to-motion: run `make project`", ha="right", va="top", fontsize=8,
                          transform=axes_pair[1].transAxes, color="#666")
    figure.suptitle("Foot sliding and power: original, synergy reconstruction, text-to-motion raw and projected")
    plotting.save(figure, output_stem)
    return {"bars": [{"group": b[0], "variant": b[1], "foot_sliding_ratio": round(b[2], 4),
                      "mean_power_w_per_kg": round(b[3], 3)} for b in bars],
            "text_to_motion": bool(project_pairs)}


def power_table(csv_path, output_stem):
    """The human-vs-robot power table (make power-ratio): per trial, then the per-class means as a bar chart."""
    with open(csv_path, newline="") as file:
        reader = csv.reader(file)
        header = next(reader)
        rows = [row for row in reader if row]
    column = {name: i for i, name in enumerate(header)}  # syn-summary --table power-ratio
    classes = {}
    for row in rows:
        classes.setdefault(row[column["motion_class"]], []).append(
            [float(row[column[key]] or "nan") for key in ("human_w_per_kg", "robot_w_per_kg", "robot_over_human")])
    figure, axes = plotting.new_figure(max(4.0, 1.1 * len(classes) + 2), 3.4)
    names = sorted(classes)
    means = np.array([np.mean(classes[name], axis=0) for name in names]).reshape(-1, 3)
    axes.bar(np.arange(len(names)) - 0.2, means[:, 0], 0.4, color="#c06030", label="human model")
    axes.bar(np.arange(len(names)) + 0.2, means[:, 1], 0.4, color="#3b6fb6", label="HRP-4C (robot)")
    axes.set_xticks(range(len(names)))
    axes.set_xticklabels(names)
    axes.set_ylabel("mean power (W/kg)")
    axes.legend(frameon=False)
    axes.set_title("Human vs robot mean mechanical power per motion class")
    plotting.save(figure, output_stem)
    return {"header": header, "rows": rows,
            "classes": {name: {"trials": len(classes[name]), "mean": [round(float(v), 3) for v in means[i]]}
                        for i, name in enumerate(names)}}
