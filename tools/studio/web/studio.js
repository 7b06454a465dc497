/* syn-studio's page: edits a compose script (manifests/scripts/README.md) as data, sends its TOML to
 * POST /api/compose on every change (one request in flight at a time; the latest edit wins), plays the
 * motion with the report's player (tools/report/player.js) and draws the metrics. Load and save read and
 * write the very TOML syn-compose reads: the server parses loaded files (POST /api/parse), and what is saved
 * is exactly the text last composed.
 *
 * For tests: window.studio = {ready (a Promise), state, lastResult, composeCount, scriptText(), player}.
 */
(function () {
  'use strict';
  var SCRIPT_NAME = 'studio.toml';
  var studio = window.studio = {state: null, lastResult: null, composeCount: 0, player: null};
  var library = null, segments = {}, stepLines = [];
  var inFlight = false, dirty = false, fileName = SCRIPT_NAME;
  var $ = function (id) { return document.getElementById(id); };

  function getJson(url) {
    return fetch(url).then(function (r) { if (!r.ok) throw new Error(url + ': HTTP ' + r.status); return r.json(); });
  }
  function post(url, body) {
    return fetch(url + '?file=' + encodeURIComponent(SCRIPT_NAME), {method: 'POST', body: body,
      headers: {'Content-Type': 'application/toml'}}).then(function (r) {
      return r.json().then(function (json) { return {status: r.status, json: json}; });
    });
  }
  function element(tag, attributes, children) {
    var e = document.createElement(tag);
    Object.keys(attributes || {}).forEach(function (k) {
      if (k === 'text') e.textContent = attributes[k]; else if (k.slice(0, 2) === 'on') e[k] = attributes[k];
      else e.setAttribute(k, attributes[k]);
    });
    (children || []).forEach(function (c) { if (c) e.appendChild(c); });
    return e;
  }

  // ---- the script as TOML (the format stages/compose/compose_script.h reads) -------------------------
  // Floats keep a decimal point (TOML reads `1` as an integer) and every digit JavaScript needs to give
  // the same double back, so the saved file composes to the same motion.
  function float(x) { return Number.isInteger(x) ? x.toFixed(1) : String(x); }
  function floats(values) { return '[' + values.map(float).join(', ') + ']'; }
  function scriptText(state) {
    var lines = ['# a SynSculptor script saved by syn-studio; compose it in batch with', '#   syn-compose FILE.toml --library LIBRARY.h5 -o FILE.motion.h5',
                 'model = ' + JSON.stringify(state.model)];
    if (state.floating_base && state.floating_base !== 'auto') lines.push('floating_base = ' + JSON.stringify(state.floating_base));
    lines.push('limit_scaling = ' + JSON.stringify(state.limit_scaling || 'joint'));
    if (state.start && state.start.synergy) lines.push('start = { synergy = ' + JSON.stringify(state.start.synergy) + ' }');
    if (state.start && state.start.motion) {
      lines.push('start = { motion = ' + JSON.stringify(state.start.motion) + ', time = ' + float(state.start.time) + ' }');
    }
    stepLines = [];
    state.steps.forEach(function (step) {
      lines.push('');
      lines.push('[[step]]');
      stepLines.push(lines.length);  // 1-based line of [[step]]
      lines.push('synergy = ' + JSON.stringify(step.synergy));
      if (step.duration !== null && step.duration !== undefined) lines.push('duration = ' + float(step.duration));
      lines.push('repetitions = ' + step.repetitions);
      lines.push('interpolation = ' + JSON.stringify(step.interpolation));
      lines.push('blend = ' + float(step.blend));
      var keyframes = step.keyframes;
      if (keyframes.length === 1 && keyframes[0].at === 0) {  // constant coefficients
        lines.push(keyframes[0].gain ? 'gain = ' + floats(keyframes[0].gain) : 'coefficients = ' + floats(keyframes[0].coefficients));
      } else {
        keyframes.forEach(function (keyframe) {
          lines.push('[[step.keyframe]]');
          lines.push('at = ' + float(keyframe.at));
          lines.push(keyframe.gain ? 'gain = ' + floats(keyframe.gain) : 'coefficients = ' + floats(keyframe.coefficients));
        });
      }
    });
    return lines.join('\n') + '\n';
  }
  studio.scriptText = function () { return scriptText(studio.state); };

  // The step a message's "studio.toml:LINE" points into, or -1.
  function stepOfLine(message) {
    var match = new RegExp(SCRIPT_NAME.replace('.', '\\.') + ':(\\d+)').exec(message);
    if (!match) return -1;
    var line = Number(match[1]), step = -1;
    stepLines.forEach(function (start, s) { if (line >= start) step = s; });
    return step;
  }

  // ---- composing ---------------------------------------------------------------------------------------
  function compose() {
    if (inFlight) { dirty = true; return; }
    inFlight = true;
    var text = scriptText(studio.state);
    $('status').textContent = 'composing…';
    var started = performance.now();
    post('/api/compose', text).then(function (reply) {
      if (reply.status === 200) {
        studio.lastResult = reply.json;
        studio.lastText = text;
        $('error').textContent = '';
        show(reply.json);
        $('status').textContent = 'composed in ' + Math.round(performance.now() - started) + ' ms';
        renderWarnings(reply.json.warnings, -1, '');
      } else {
        var message = reply.json.error || ('HTTP ' + reply.status);
        $('error').textContent = message;
        $('status').textContent = 'not composed (HTTP ' + reply.status + ')';
        renderWarnings([], stepOfLine(message), message);
      }
    }).catch(function (error) {
      $('error').textContent = String(error);
    }).then(function () {
      studio.composeCount += 1;
      inFlight = false;
      if (dirty) { dirty = false; compose(); }
    });
  }

  function show(result) {
    var frames = result.time.length, nq = result.coordinate_names.length;
    var time = new Float32Array(frames), q = new Float32Array(frames * nq);
    for (var k = 0; k < frames; k++) {
      time[k] = result.time[k];
      for (var i = 0; i < nq; i++) q[k * nq + i] = result.q[k][i];
    }
    var player = studio.player, wasPlaying = player.playing(), at = player.frameCount() ? Number($('clock').dataset.t || 0) : 0;
    player.pause();
    player.setMotion({frames: frames, nq: nq, time: time, q: q});
    player.setTime(Math.min(at, time[frames - 1]));
    $('time').max = String(frames - 1);
    if (wasPlaying) player.play();
    var m = result.metrics;
    $('summary').textContent = 'duration ' + result.time[frames - 1].toFixed(2) + ' s · ' + frames + ' frames · ΔP ' +
      number(m.delta_p) + ' · ΔKE ' + number(m.delta_ke) + ' J · power ' + number(m.power_w_per_kg) +
      ' W/kg · foot sliding ' + number(m.foot_sliding_ratio) + ' (metrics at ' + m.eval_rate + ' Hz)';
    drawMomentum(result);
    drawBars($('plot-delta'), result.metrics.steps, [['delta_p', '#1f77b4', 'ΔP'], ['delta_ke', '#ff7f0e', 'ΔKE']]);
    drawBars($('plot-sliding'), result.metrics.steps, [['foot_sliding_ratio', '#d62828', 'sliding']]);
  }
  function number(x) { return x === null || x === undefined ? '–' : Number(x).toPrecision(3); }

  // ---- plots (canvas 2-D) -------------------------------------------------------------------------------
  function drawMomentum(result) {
    var canvas = $('plot-momentum'), g = canvas.getContext('2d'), w = canvas.width, h = canvas.height;
    var t = result.time, series = result.metrics.series, end = t[t.length - 1] || 1, pad = 28;
    g.clearRect(0, 0, w, h);
    result.steps.forEach(function (step, s) {
      g.fillStyle = s % 2 ? '#eef2f6' : '#f8fafc';
      g.fillRect(pad + step.start_s / end * (w - pad - 4), 0, (step.end_s - step.start_s) / end * (w - pad - 4), h - 14);
    });
    [['momentum', '#2a6f97'], ['kinetic_energy', '#e07a1f']].forEach(function (entry) {
      var values = series[entry[0]], top = Math.max.apply(null, values.concat([1e-9]));
      g.strokeStyle = entry[1];
      g.beginPath();
      values.forEach(function (v, k) {
        var x = pad + t[k] / end * (w - pad - 4), y = (h - 16) - v / top * (h - 26);
        if (k) g.lineTo(x, y); else g.moveTo(x, y);
      });
      g.stroke();
      g.fillStyle = entry[1];
      g.fillText(entry[0].replace('_', ' ') + ' (max ' + number(top) + ')', pad + 4, entry[0] === 'momentum' ? 10 : 22);
    });
    g.fillStyle = '#333';
    g.fillText('0', pad - 8, h - 2);
    g.fillText(end.toFixed(2) + ' s', w - 40, h - 2);
  }
  function drawBars(canvas, steps, keys) {
    var g = canvas.getContext('2d'), w = canvas.width, h = canvas.height, pad = 28;
    g.clearRect(0, 0, w, h);
    var n = steps.length, slot = (w - pad) / Math.max(1, n), bar = slot / (keys.length + 1);
    keys.forEach(function (key, j) {
      var top = 1e-12;
      steps.forEach(function (step) { top = Math.max(top, step[key[0]] || 0); });
      if (key[0] === 'foot_sliding_ratio') top = Math.max(top, 0.1);
      g.fillStyle = key[1];
      steps.forEach(function (step, s) {
        var v = step[key[0]] || 0, height = v / top * (h - 48);  // room above for the legend
        g.fillRect(pad + s * slot + (j + 0.5) * bar, h - 16 - height, bar * 0.9, height);
        g.fillText(number(step[key[0]]), pad + s * slot + (j + 0.5) * bar, h - 20 - height);
      });
      g.fillText(key[2] + ' (max ' + number(top) + ')', pad + 4 + j * 130, 10);
    });
    g.fillStyle = '#333';
    for (var s = 0; s < n; s++) g.fillText('step ' + (s + 1), pad + s * slot + 4, h - 3);
  }

  // ---- the editor ---------------------------------------------------------------------------------------
  function slider(label, value, min, max, step, format, onInput, testId) {
    var input = element('input', {type: 'range', min: min, max: max, step: step});
    input.value = String(value);
    if (testId) input.dataset.test = testId;
    var readout = element('span', {'class': 'value', text: format(value)});
    input.oninput = function () { var v = Number(input.value); readout.textContent = format(v); onInput(v); };
    return element('div', {'class': 'row'}, [element('span', {text: label}), input, readout]);
  }

  function coefficientRows(step, s, keyframe, k) {
    var sigma = segments[step.synergy] ? segments[step.synergy].sigma : [];
    var rows = [];
    sigma.forEach(function (sig, i) {
      var gain = keyframe ? (keyframe.gain ? keyframe.gain[i] : keyframe.coefficients[i] / sig) : 1;
      rows.push(slider('a' + (i + 1) + ' / σ' + (i + 1), gain, -2, 3, 0.01, function (g) {
        return g.toFixed(2) + ' (' + (g * sig).toPrecision(3) + ')';
      }, function (g) {
        if (!step.keyframes.length) step.keyframes.push({at: 0, gain: sigma.map(function () { return 1; })});
        var target = step.keyframes[k];
        if (target.gain) target.gain[i] = g; else target.coefficients[i] = g * sig;
        compose();
      }, 'gain-' + s + '-' + k + '-' + i));
    });
    return rows;
  }

  function renderSteps() {
    var list = $('steps');
    list.innerHTML = '';
    studio.state.steps.forEach(function (step, s) {
      var own = segments[step.synergy] ? segments[step.synergy].duration_s : 1;
      var duration = step.duration === null || step.duration === undefined ? own : step.duration;
      var move = function (delta) {
        return function () {
          var steps = studio.state.steps, to = s + delta;
          if (to < 0 || to >= steps.length) return;
          var moved = steps.splice(s, 1)[0];
          steps.splice(to, 0, moved);
          renderSteps(); compose();
        };
      };
      var head = element('div', {'class': 'step-head'}, [
        element('span', {'class': 'name', text: step.synergy}),
        element('button', {text: '↑', title: 'move up', onclick: move(-1)}),
        element('button', {text: '↓', title: 'move down', onclick: move(1)}),
        element('button', {text: '✕', title: 'delete', onclick: function () {
          if (studio.state.steps.length === 1) return;  // a script needs a step
          studio.state.steps.splice(s, 1); renderSteps(); compose();
        }})]);
      var rows = [head];
      if (step.keyframes.length <= 1) {
        rows = rows.concat(coefficientRows(step, s, step.keyframes[0], 0));
      } else {
        step.keyframes.forEach(function (keyframe, k) {
          rows.push(element('div', {'class': 'keyframe-at', text: 'keyframe at ' + keyframe.at + ' of the step'}));
          rows = rows.concat(coefficientRows(step, s, keyframe, k));
        });
      }
      var durationRow, tempoRow;
      durationRow = slider('duration (s)', duration, Math.max(0.05, own / 4), own * 4, 0.01, function (d) {
        return d.toFixed(2) + ' s';
      }, function (d) { step.duration = d; compose(); }, 'duration-' + s);
      tempoRow = slider('tempo', own / duration, 0.25, 4, 0.01, function (x) {
        return x.toFixed(2) + '×';
      }, function (x) { step.duration = own / x; compose(); }, 'tempo-' + s);
      rows.push(durationRow, tempoRow);
      var repetitions = element('input', {type: 'number', min: 1, max: 50, step: 1});
      repetitions.value = String(step.repetitions);
      repetitions.onchange = function () { step.repetitions = Math.max(1, Math.round(Number(repetitions.value) || 1)); compose(); };
      rows.push(element('div', {'class': 'row'}, [element('span', {text: 'repetitions'}), repetitions, element('span')]));
      var interpolation = element('select');
      ['step', 'linear', 'cubic', 'minimum-jerk'].forEach(function (name) {
        interpolation.appendChild(element('option', {text: name}));
      });
      interpolation.value = step.interpolation;
      interpolation.onchange = function () { step.interpolation = interpolation.value; compose(); };
      rows.push(element('div', {'class': 'row'}, [element('span', {text: 'interpolation'}), interpolation, element('span')]));
      rows.push(slider('blend (s)', step.blend, 0, 1, 0.01, function (b) { return b.toFixed(2) + ' s'; },
                       function (b) { step.blend = b; compose(); }, 'blend-' + s));
      rows.push(element('div', {'class': 'warning', 'data-step': String(s)}));
      list.appendChild(element('li', {'data-step': String(s)}, rows));
    });
  }

  // Joint-limit warnings (and a located error) on the step that causes them.
  function renderWarnings(warnings, errorStep, errorMessage) {
    var items = $('steps').children;
    for (var s = 0; s < items.length; s++) {
      var mine = warnings.filter(function (w) { return w.step === s; }).map(function (w) { return w.message; });
      if (errorStep === s) mine.push(errorMessage);
      items[s].querySelector('.warning').textContent = mine.join('\n');
      items[s].classList.toggle('warned', mine.length > 0);
    }
  }

  function fillSelectors() {
    var style = $('style'), segment = $('segment'), start = $('start');
    style.innerHTML = '';
    library.styles.forEach(function (entry) { style.appendChild(element('option', {text: entry.name})); });
    var fillSegments = function () {
      segment.innerHTML = '';
      library.styles.filter(function (entry) { return entry.name === style.value; })[0].segments.forEach(function (entry) {
        segment.appendChild(element('option', {value: entry.name,
          text: entry.name + ' (' + entry.duration_s.toFixed(2) + ' s)'}));
      });
    };
    style.onchange = fillSegments;
    fillSegments();
    start.innerHTML = '';
    start.appendChild(element('option', {value: '', text: "first step's pose"}));
    Object.keys(segments).sort().forEach(function (name) { start.appendChild(element('option', {value: name, text: name})); });
    start.onchange = function () { studio.state.start = start.value ? {synergy: start.value} : null; compose(); };
    $('limit-scaling').onchange = function () { studio.state.limit_scaling = this.value; compose(); };
    $('add-step').onclick = function () {
      studio.state.steps.push({synergy: segment.value, duration: null, repetitions: 1, interpolation: 'minimum-jerk',
                               blend: 0.2, keyframes: []});
      renderSteps(); compose();
    };
  }

  function setState(state) {
    studio.state = state;
    $('limit-scaling').value = state.limit_scaling || 'joint';
    $('start').value = state.start && state.start.synergy ? state.start.synergy : '';
    renderSteps();
    compose();
  }

  function defaultState() {
    var first = library.styles[0].segments[0].name;
    return {model: library.model, floating_base: 'auto', limit_scaling: 'joint', start: null,
            steps: [{synergy: first, duration: null, repetitions: 1, interpolation: 'minimum-jerk', blend: 0.2, keyframes: []}]};
  }

  function loadText(text) {
    return post('/api/parse', text).then(function (reply) {
      if (reply.status !== 200) { $('error').textContent = reply.json.error; return; }
      setState(reply.json);
    });
  }

  studio.ready = Promise.all([getJson('/api/library'), getJson('/api/robot'), fetch('/api/script').then(function (r) { return r.text(); })])
    .then(function (loaded) {
      library = loaded[0];
      library.styles.forEach(function (style) {
        style.segments.forEach(function (entry) { segments[entry.name] = entry; });
      });
      $('library-name').textContent = library.library + ' · ' + library.robot;
      studio.player = SynPlayer.create($('viewport'), loaded[1], {onFrame: function (frame, t) {
        $('time').value = String(frame);
        $('clock').textContent = t.toFixed(2) + ' s';
        $('clock').dataset.t = String(t);
      }});
      $('time').oninput = function () { studio.player.pause(); $('play').textContent = 'play'; studio.player.setFrame(Number(this.value)); };
      $('play').onclick = function () {
        if (studio.player.playing()) studio.player.pause(); else studio.player.play();
        this.textContent = studio.player.playing() ? 'pause' : 'play';
      };
      $('load').onchange = function () {
        var file = this.files[0];
        if (!file) return;
        fileName = file.name;
        file.text().then(loadText);
      };
      $('save').onclick = function () {
        var link = element('a', {href: URL.createObjectURL(new Blob([scriptText(studio.state)], {type: 'application/toml'})),
                                 download: fileName});
        document.body.appendChild(link);
        link.click();
        link.remove();
      };
      fillSelectors();
      var initial = loaded[2];
      if (initial.trim()) return loadText(initial).then(function () { studio.player.play(); });
      setState(defaultState());
      studio.player.play();
    });
})();
