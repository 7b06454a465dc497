"""The report page: index.html with every figure, its caption and the command that redraws it, the 3-D
player (player.js, three.js wrapped as a classic script so the page works from file://, where Chromium
blocks ES-module imports), and robot.js, the robot description the player draws."""
import html
import json
import os
import shutil

from files import write_atomically
from trial_report import read_motion, read_feet
from urdf_fk import Robot

CAPTIONS = {
    "fig3": "<b>Fig. 3, momentum-based segmentation.</b> ΔP(t) = ‖p(t<sub>i</sub>) − p(t<sub>i−1</sub>)‖ of the "
            "generalized momentum p = A(q)u at the analysis rate (syn-segment); dashed: the threshold used; blue: "
            "the segment boundaries.",
    "fig4": "<b>Fig. 4, synergy representation per motion class.</b> Variance of the generalized velocities "
            "explained by PC1–3 of each momentum segment (syn-synergies), mean ± sd across segments; n = segments.",
    "fig5": "<b>Fig. 5, stylistic variability across dance genres.</b> As Fig. 4, for the dance trials grouped by "
            "genre (the manifest's style).",
    "fig6": "<b>Fig. 6, energetic reconstruction.</b> Mean per-step ΔP and ΔKE at 1 kHz (syn-evaluate) per motion "
            "class, averaged over segments: the segment's own velocities integrated (original), its rank-k synergy "
            "reconstruction, and 100 reconstructions with coefficients perturbed by U(−α, α) (mean ± sd).",
    "fig7": "<b>Fig. 7, foot sliding and power.</b> Foot-sliding ratio and mean mechanical power Σ|τ·q̇| per kg "
            "(syn-evaluate): the retargeted motion (original) and the rank-k synergy reconstruction of its "
            "segments, per motion class; then each text-to-motion input of <code>make project</code> raw and "
            "projected through the torso null space into the style's synergies.",
    "power": "<b>Human vs robot power.</b> Mean mechanical power (W/kg) of each trial retargeted onto the paper's "
             "human model and its HRP-4C (<code>make power-ratio</code>), per motion class.",
    "landmark_error": "<b>Landmark errors.</b> Distance between each tracked robot link and its human landmark "
                      "target (motion.h5 landmark_error) over time.",
    "contact": "<b>Contact phases.</b> The motion file's contact dataset per foot, when the retargeter wrote one.",
}


def _figure(src, caption, command, alt):
    svg = src[:-4] + ".svg"
    return (f'<figure><img src="{src}" alt="{html.escape(alt)}">'
            f'<figcaption>{caption} <a href="{svg}">SVG</a><br><span class="cmd">redraw: '
            f'<code>{html.escape(command)}</code></span></figcaption></figure>')


def _load(path):
    with open(path) as file:
        return json.load(file)


def _number(value, digits=3):
    return "–" if value is None else f"{value:.{digits}g}"


def write_player_assets(out_dir, three_path, here, model_path, robot_map_path, coordinate_names):
    """What the 3-D player needs beside a page: three.js as a classic script (its CommonJS build inside a
    function scope), player.js, report.css, and robot.js (the robot description, with the robot map's feet)."""
    with open(three_path) as file:
        three = file.read()
    _write(os.path.join(out_dir, "three.js"),
           "/* three.js r" + three.split("REVISION = '")[1].split("'")[0] + ", MIT licence, from npm (tools/report/"
           "package-lock.json), wrapped as a classic script by tools/report/page.py. */\n"
           "var THREE = (function () { var exports = {}; var module = { exports: exports };\n" + three +
           "\nreturn exports; })();\n")
    for name in ("player.js", "report.css"):
        shutil.copyfile(os.path.join(here, name), os.path.join(out_dir, name + ".tmp"))
        os.replace(os.path.join(out_dir, name + ".tmp"), os.path.join(out_dir, name))
    robot = Robot(model_path)
    description = robot.description(coordinate_names)
    description["feet"] = [{"side": side, "link": robot.index[link], "sole_points": soles.tolist()}
                           for side, link, soles in read_feet(robot_map_path)]
    _write(os.path.join(out_dir, "robot.js"), "SynReport.setRobot(" + json.dumps(description, separators=(",", ":")) + ");\n")


def page_scripts(trial_list):
    """The page's closing scripts: three.js, the player, the page's controller over `trial_list` ([{id,
    label}]), then robot.js, whose SynReport.setRobot call starts the player."""
    return ('<script src="three.js"></script>\n<script src="player.js"></script>\n'
            f"<script>\nvar SYN_TRIALS = {json.dumps(trial_list)};\n{PAGE_SCRIPT}</script>\n"
            '<script src="robot.js"></script>\n')


def write_page(archive, three_path, here, command_line):
    r = archive.report
    make_command = f"make report MANIFEST={archive.manifest_path}"
    trials = [_load(os.path.join(r, "trials", t["id"], "trial.json")) for t in archive.trials]
    names = read_motion(os.path.join(archive.dir, "trials", archive.trials[0]["id"], "motion.h5"))["coordinate_names"]
    write_player_assets(r, three_path, here, archive.model, archive.robot_map, names)

    body = [f"<header><h1>synsculpt report: {html.escape(archive.name)}</h1>",
            f"<p>{html.escape(archive.description)} — {len(trials)} trials, robot "
            f"<code>{html.escape(archive.model)}</code>. Regenerate (redraws only what changed): "
            f"<code>{html.escape(make_command)}</code></p>",
            '<nav><a href="#player">3-D playback</a> · <a href="#figures">figures</a> · <a href="#trials">trials</a>'
            "</nav></header>"]
    body.append(PLAYER_SECTION)
    body.append('<section id="figures"><h2>Archive figures</h2>')
    for name in ("fig4", "fig5", "fig6", "fig7", "power"):
        path = os.path.join(r, name + ".json")
        if not os.path.exists(path):
            if name == "power":
                body.append('<p class="missing">Human vs robot power table: not available — run '
                            f"<code>make power-ratio MANIFEST={html.escape(archive.manifest_path)}</code>, then "
                            f"<code>{html.escape(make_command)}</code>.</p>")
            continue
        summary = _load(path)
        body.append(_figure(f"{name}.png", CAPTIONS[name], summary["command"], name))
        if name == "fig7" and not summary.get("text_to_motion"):
            body.append('<p class="missing">Text-to-motion rows: not available — run <code>make project</code>, '
                        f"then <code>{html.escape(make_command)}</code>.</p>")
        if name == "power":
            body.append(html_table(summary["header"], summary["rows"]))
    body.append("</section>")

    body.append('<section id="trials"><h2>Trials</h2>')
    body.append(html_table(["trial", "class", "style", "duration (s)", "segments", "foot sliding", "power (W/kg)",
                        "median landmark error (mm)"],
                       [[f'<a href="#trial-{t["id"]}">{html.escape(t["id"])}</a>', t["motion_class"], t["style"],
                         _number(t["duration_s"], 4), t["fig3"]["segments"], _number(t["foot_sliding_ratio"]),
                         _number(t["mean_power_w_per_kg"]),
                         ", ".join(f"{k} {v}" for k, v in sorted(t["median_landmark_error_mm"].items()))]
                        for t in trials], escape=False))
    for t in trials:
        tid = t["id"]
        trial_command = command_line(archive, "trial", tid)
        body.append(f'<article id="trial-{html.escape(tid)}"><h3>{html.escape(tid)} '
                    f'<small>{html.escape(t["motion_class"])} {html.escape(t["style"])}</small> '
                    f'<button class="play" data-trial="{html.escape(tid)}" data-time="0">play in 3-D</button></h3>')
        body.append(_figure(f"trials/{tid}/fig3.png", CAPTIONS["fig3"], trial_command, f"{tid} momentum"))
        body.append(_figure(f"trials/{tid}/landmark_error.png", CAPTIONS["landmark_error"], trial_command,
                            f"{tid} landmark errors"))
        if t["contact_dataset"]:
            body.append(_figure(f"trials/{tid}/contact.png", CAPTIONS["contact"], trial_command, f"{tid} contact"))
        else:
            body.append('<p class="missing">Contact phases: not available (motion.h5 has no <code>contact</code> '
                        "dataset). The player shows contacts estimated from the sole points instead.</p>")
        alignment = t.get("human_alignment", {})
        body.append(f'<p class="note">{t["frames"]} frames at {t["rate_hz"]} Hz (the player samples '
                    f'one in {t["player_stride"]}); foot sliding (syn-evaluate, 1 kHz): {_number(t["foot_sliding_ratio"])}; '
                    f'frames the player marks sliding: {t["sliding_frames_estimated"]}; the human is drawn at scale '
                    f'{alignment.get("scale")} and heading {alignment.get("heading_deg")}° (fitted to the landmark '
                    "targets, as syn-retarget placed them).</p>")
        rows = [[w["frame"], f'<button class="play" data-trial="{html.escape(tid)}" data-time="{w["time"]}">'
                 f'{w["time"]} s</button>', html.escape(w["landmark"]), w["error_mm"], _number(w["angle_deg"])]
                for w in t["worst_frames"]]
        body.append("<h4>Worst frames (largest landmark position error; one per 0.25 s)</h4>")
        body.append(html_table(["frame", "time", "worst landmark", "error (mm)", "angle (deg)"], rows, escape=False)
                    if rows else '<p class="missing">not available: no landmark errors in motion.h5</p>')
        body.append("</article>")
    body.append("</section>")

    trial_list = [{"id": t["id"], "label": f'{t["id"]} ({t["motion_class"]})'} for t in trials]
    page = (f'<!doctype html>\n<html lang="en"><head><meta charset="utf-8"><title>synsculpt report: '
            f'{html.escape(archive.name)}</title><link rel="stylesheet" href="report.css"></head><body>\n'
            + "\n".join(body) + "\n" + page_scripts(trial_list) + "</body></html>\n")
    _write(os.path.join(r, "index.html"), page)


def html_table(header, rows, escape=True):
    cell = (lambda v: html.escape(str(v))) if escape else str
    return ("<table><thead><tr>" + "".join(f"<th>{html.escape(str(h))}</th>" for h in header) + "</tr></thead><tbody>"
            + "".join("<tr>" + "".join(f"<td>{cell(v)}</td>" for v in row) + "</tr>" for row in rows)
            + "</tbody></table>")


def _write(path, text):
    write_atomically(path, text)


PLAYER_SECTION = """<section id="player"><h2>3-D playback</h2>
<div class="player-controls">
 <label>trial <select id="trial"></select></label>
 <button id="play">play</button>
 <label>speed <select id="speed"><option>0.25</option><option>0.5</option><option selected>1</option><option>2</option></select></label>
 <input id="slider" type="range" min="0" max="0" value="0" step="1">
 <span id="clock">0.00 s</span>
 <label><input id="beside" type="checkbox" checked> human beside the robot</label>
</div>
<div id="viewport"></div>
<p class="legend">Robot: a capsule from each link's joint to its children's (the G1 URDF has no meshes);
feet: boxes through the robot map's sole points, <span style="color:#2a9d8f">green in contact</span>,
<span style="color:#d62828">red while sliding</span> (sole within the contact height and moving faster
than the sliding speed, as syn-evaluate defines it, or penetrating). <span style="color:#e07a1f">Orange</span>:
the captured human (markers.h5: its skeleton's joints, or its markers) turned, scaled and moved as the retargeter did, feet on the ground, 1 m
beside the robot or overlaid;
<span style="color:#c2185b">magenta points</span>: the retargeter's landmark targets for the tracked links
(motion.h5 landmark_targets). Drag to orbit, wheel to zoom.
<span id="contact-source"></span></p>
</section>"""

PAGE_SCRIPT = r"""
var SynReport = (function () {
  var player = null, trials = {}, pending = {}, state = {trial: null};
  var slider = document.getElementById('slider'), clock = document.getElementById('clock');
  function decode(b64, Type) {
    var bytes = Uint8Array.from(atob(b64), function (c) { return c.charCodeAt(0); });
    return new Type(bytes.buffer);
  }
  function show(id, time) {
    if (!trials[id]) {  // motion files are classic scripts too: fetch() is blocked from file://
      pending[id] = time;
      var script = document.createElement('script');
      script.src = 'trials/' + encodeURIComponent(id) + '/motion.js';
      script.onerror = function () { console.error('cannot load ' + script.src); };
      document.body.appendChild(script);
      return;
    }
    state.trial = id;
    document.getElementById('trial').value = id;
    player.setMotion(trials[id]);
    slider.max = trials[id].frames - 1;
    document.getElementById('contact-source').textContent = trials[id].contact_source === 'motion.h5'
      ? 'Contacts: motion.h5 contact dataset.' : 'Contacts: estimated from the sole points (motion.h5 has no contact dataset).';
    player.setTime(time || 0);
  }
  function onFrame(frame, time) {
    slider.value = frame;
    clock.textContent = time.toFixed(2) + ' s';
  }
  return {
    setRobot: function (description) {
      player = SynPlayer.create(document.getElementById('viewport'), description, {onFrame: onFrame});
      window.synPlayer = player;
      var select = document.getElementById('trial');
      SYN_TRIALS.forEach(function (t) {
        var option = document.createElement('option');
        option.value = t.id; option.textContent = t.label; select.appendChild(option);
      });
      select.onchange = function () { show(select.value, 0); };
      slider.oninput = function () { player.pause(); player.setFrame(Number(slider.value)); };
      document.getElementById('play').onclick = function () {
        if (player.playing()) player.pause(); else player.play();
        this.textContent = player.playing() ? 'pause' : 'play';
      };
      document.getElementById('speed').onchange = function () { player.setSpeed(Number(this.value)); };
      document.getElementById('beside').onchange = function () { player.setHumanOffset(this.checked ? 1.0 : 0.0); };
      Array.prototype.forEach.call(document.querySelectorAll('button.play'), function (button) {
        button.onclick = function () {
          show(button.dataset.trial, Number(button.dataset.time));
          document.getElementById('player').scrollIntoView();
        };
      });
      if (SYN_TRIALS.length) show(SYN_TRIALS[0].id, 0);
    },
    addTrial: function (data) {
      data.time = decode(data.time, Float32Array);
      data.q = decode(data.q, Float32Array);
      if (data.landmarks) data.landmarks.positions = decode(data.landmarks.positions, Float32Array);
      if (data.human) data.human.positions = decode(data.human.positions, Float32Array);
      data.contact = decode(data.contact, Uint8Array);
      data.sliding = decode(data.sliding, Uint8Array);
      trials[data.id] = data;
      if (data.id in pending) { var time = pending[data.id]; delete pending[data.id]; show(data.id, time); }
    },
    ready: function () { return state.trial !== null && player !== null; },
    current: function () { return state.trial; }
  };
})();
"""
