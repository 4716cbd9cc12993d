"""dist/default_drive.html: a self-contained page (no network) that animates
the belt over the main job's run: bodies, pulleys turning, the tension of
every belt element colour-coded, a time slider, and the span tension and slip
traces of the FMU run with a cursor.

Where the data come from: the FMU has no output for the position of every
belt body, so the belt shape comes from `examples/belt_shape.rs`, which runs
the same physics core with the FMU's default parameters and the main job's
integrator settings and writes one frame per 10 ms. The traces below the
drawing are the FMU's own outputs (FMPy run, every communication point).
`write` checks that both runs agree: their span tensions at the frame times
(returned, printed by the main job).
"""
import json
import pathlib

import numpy as np


def write(frames_path, res, out_path, meta):
    data = json.loads(pathlib.Path(frames_path).read_text())
    frames = data["frames"]
    t = res["time"]
    # The two runs at the frame times: same model, same tolerance, different
    # step sequences, so they agree to the integration error, not bit for bit.
    dev = 0.0
    for f in frames:
        i = int(np.argmin(np.abs(t - f["t"])))
        if abs(t[i] - f["t"]) < 1e-9:
            for k in (1, 2):
                dev = max(dev, abs(f["span"][k - 1] - res[f"span[{k}].tension"][i]))
    dt = t[1] - t[0]
    k = max(1, int(round(0.02 / dt)))
    slip = np.convolve(res["pulley[2].slip"], np.ones(k) / k, mode="same") * 100
    slip[:k] = np.nan
    slip[-k:] = np.nan
    traces = {
        "t": [round(float(x), 4) for x in t],
        "span1": [round(float(x), 2) for x in res["span[1].tension"]],
        "span2": [round(float(x), 2) for x in res["span[2].tension"]],
        "slip": [None if not np.isfinite(x) else round(float(x), 4) for x in slip],
    }
    page = TEMPLATE.replace("@TITLE@", meta["title"]).replace("@SETTINGS@", meta["settings"])
    page = page.replace("@DATA@", json.dumps({"shape": data, "traces": traces},
                                             separators=(",", ":")))
    pathlib.Path(out_path).write_text(page)
    return dev


TEMPLATE = r"""<!DOCTYPE html>
<html lang="en">
<head>
<meta charset="utf-8">
<title>@TITLE@</title>
<style>
  body { font-family: system-ui, sans-serif; margin: 16px 24px; color: #222; max-width: 1080px; }
  h1 { font-size: 20px; margin: 0 0 4px; }
  .sub { color: #555; font-size: 13px; margin-bottom: 10px; }
  canvas { display: block; border: 1px solid #ddd; background: #fff; }
  #controls { display: flex; align-items: center; gap: 12px; margin: 8px 0; font-size: 14px; }
  #slider { flex: 1; }
  #readout { font-family: ui-monospace, monospace; font-size: 13px; white-space: pre; margin: 4px 0 10px; }
  .plots { display: flex; gap: 12px; }
  .note { font-size: 12px; color: #555; margin-top: 10px; }
</style>
</head>
<body>
<h1>@TITLE@</h1>
<div class="sub">@SETTINGS@. Pulley 1 (left) drives, pulley 2 (right) is driven; both turn clockwise.
Belt elements coloured by their tension; the red dot is the probe body.</div>
<canvas id="drive" width="1040" height="300"></canvas>
<div id="controls">
  <button id="play">Pause</button>
  <label>speed <select id="speed"><option value="0.05">0.05x</option><option value="0.1" selected>0.1x</option>
    <option value="0.25">0.25x</option><option value="1">1x</option></select></label>
  <input id="slider" type="range" min="0" value="0" step="1">
</div>
<div id="readout"></div>
<div class="plots">
  <canvas id="tension" width="514" height="220"></canvas>
  <canvas id="slip" width="514" height="220"></canvas>
</div>
<div class="note">The belt shape (one frame per 10 ms) is computed by the model's physics core with the FMU's default
parameters and the same integrator settings (examples/belt_shape.rs), because the FMU outputs pulley and span
quantities, not every body's position; the traces are the FMU's outputs at every communication point. Sign
convention: x to the right, y up, angles positive counter-clockwise.</div>
<script>
"use strict";
const DATA = @DATA@;
const S = DATA.shape, TR = DATA.traces, F = S.frames;
const cv = document.getElementById("drive"), cx = cv.getContext("2d");
const slider = document.getElementById("slider"), playBtn = document.getElementById("play");
slider.max = F.length - 1;
// world -> canvas: fit the pulleys with a margin, same scale on both axes
let x0 = Infinity, x1 = -Infinity, y0 = Infinity, y1 = -Infinity;
for (const p of S.pulleys) {
  x0 = Math.min(x0, p.x - p.r); x1 = Math.max(x1, p.x + p.r);
  y0 = Math.min(y0, p.y - p.r); y1 = Math.max(y1, p.y + p.r);
}
const LEGEND = 60, margin = 0.02;
const scale = Math.min((cv.width - 40) / (x1 - x0 + 2 * margin), (cv.height - LEGEND - 20) / (y1 - y0 + 2 * margin));
const ox = (cv.width - scale * (x1 - x0)) / 2 - scale * x0;
const oy = (cv.height - LEGEND) / 2 + scale * (y0 + y1) / 2;
const X = x => ox + scale * x, Y = y => oy - scale * y;
let tmin = Infinity, tmax = -Infinity;
for (const f of F) for (const v of f.T) { tmin = Math.min(tmin, v); tmax = Math.max(tmax, v); }
tmin = Math.max(0, tmin);
function colour(v) {  // blue (low) - green - red (high)
  const u = Math.min(1, Math.max(0, (v - tmin) / (tmax - tmin || 1)));
  const h = 240 * (1 - u);
  return `hsl(${h},85%,45%)`;
}
function drawDrive(i) {
  const f = F[i];
  cx.clearRect(0, 0, cv.width, cv.height);
  S.pulleys.forEach((p, j) => {
    cx.beginPath(); cx.arc(X(p.x), Y(p.y), scale * p.r, 0, 2 * Math.PI);
    cx.fillStyle = "#eee"; cx.fill(); cx.strokeStyle = "#888"; cx.lineWidth = 1; cx.stroke();
    for (let s = 0; s < 3; s++) {  // spokes turn with the pulley angle (counter-clockwise positive)
      const a = f.angle[j] + s * 2 * Math.PI / 3;
      cx.beginPath(); cx.moveTo(X(p.x), Y(p.y));
      cx.lineTo(X(p.x + 0.9 * p.r * Math.cos(a)), Y(p.y + 0.9 * p.r * Math.sin(a)));
      cx.strokeStyle = "#555"; cx.lineWidth = 2; cx.stroke();
    }
    cx.fillStyle = "#000"; cx.font = "13px sans-serif"; cx.textAlign = "center";
    cx.fillText(`pulley ${j + 1}`, X(p.x), Y(p.y - p.r) + 40);
  });
  const n = S.bodies;
  cx.lineWidth = 4; cx.lineCap = "round";
  for (let k = 0; k < n; k++) {  // SDE k joins body k-1 and body k
    const a = (k + n - 1) % n;
    cx.beginPath(); cx.moveTo(X(f.x[a]), Y(f.y[a])); cx.lineTo(X(f.x[k]), Y(f.y[k]));
    cx.strokeStyle = colour(f.T[k]); cx.stroke();
  }
  cx.fillStyle = "#222";
  for (let k = 0; k < n; k++) { cx.beginPath(); cx.arc(X(f.x[k]), Y(f.y[k]), 1.5, 0, 2 * Math.PI); cx.fill(); }
  const b = S.probe - 1;
  cx.beginPath(); cx.arc(X(f.x[b]), Y(f.y[b]), 6, 0, 2 * Math.PI); cx.fillStyle = "#d00"; cx.fill();
  cx.fillStyle = "#d00"; cx.textAlign = "left"; cx.fillText(`body ${S.probe}`, X(f.x[b]) + 8, Y(f.y[b]) - 8);
  // tension scale
  const lx = 40, ly = cv.height - 38, lw = 300;
  for (let s = 0; s < lw; s++) { cx.fillStyle = colour(tmin + (tmax - tmin) * s / lw); cx.fillRect(lx + s, ly, 1, 12); }
  cx.fillStyle = "#222"; cx.textAlign = "left"; cx.font = "12px sans-serif";
  cx.fillText(`${tmin.toFixed(0)} N`, lx, ly + 26);
  cx.textAlign = "right"; cx.fillText(`${tmax.toFixed(0)} N`, lx + lw, ly + 26);
  cx.textAlign = "center"; cx.fillText("element tension", lx + lw / 2, ly - 4);
  cx.textAlign = "right"; cx.fillText(`t = ${f.t.toFixed(3)} s`, cv.width - 20, cv.height - 20);
}
function plot(id, series, label, t) {
  const c = document.getElementById(id), g = c.getContext("2d");
  const L = 48, R = 10, T = 20, B = 30, w = c.width - L - R, h = c.height - T - B;
  let lo = Infinity, hi = -Infinity;
  for (const s of series) for (const v of s.y) if (v !== null) { lo = Math.min(lo, v); hi = Math.max(hi, v); }
  if (id === "slip" && Math.max(lo, -1) < Math.min(hi, 3)) { lo = Math.max(lo, -1); hi = Math.min(hi, 3); }
  const t0 = TR.t[0], t1 = TR.t[TR.t.length - 1];
  const px = v => L + w * (v - t0) / (t1 - t0), py = v => T + h * (1 - (v - lo) / (hi - lo || 1));
  g.clearRect(0, 0, c.width, c.height);
  g.strokeStyle = "#999"; g.lineWidth = 1; g.strokeRect(L, T, w, h);
  g.fillStyle = "#222"; g.font = "12px sans-serif"; g.textAlign = "left"; g.fillText(label, L, 14);
  g.textAlign = "right";
  for (let s = 0; s <= 4; s++) { const v = lo + (hi - lo) * s / 4; g.fillText(v.toFixed(id === "slip" ? 1 : 0), L - 4, py(v) + 4); }
  g.textAlign = "center";
  for (let s = 0; s <= 4; s++) { const v = t0 + (t1 - t0) * s / 4; g.fillText(v.toFixed(2) + " s", px(v), T + h + 16); }
  for (const s of series) {
    g.beginPath(); let pen = false;
    for (let i = 0; i < TR.t.length; i++) {
      const v = s.y[i];
      if (v === null || v < lo || v > hi) { pen = false; continue; }
      if (pen) g.lineTo(px(TR.t[i]), py(v)); else { g.moveTo(px(TR.t[i]), py(v)); pen = true; }
    }
    g.strokeStyle = s.c; g.lineWidth = 1.2; g.stroke();
    if (s.name) { g.fillStyle = s.c; g.textAlign = "right"; g.fillText(s.name, L + w - 4, T + 14 + 14 * series.indexOf(s)); }
  }
  g.strokeStyle = "#d00"; g.beginPath(); g.moveTo(px(t), T); g.lineTo(px(t), T + h); g.stroke();
}
const rpm = 60 / (2 * Math.PI);
function show(i) {
  const f = F[i];
  drawDrive(i);
  plot("tension", [{y: TR.span1, c: "#c33", name: "span 1 (bottom, tight)"}, {y: TR.span2, c: "#36c", name: "span 2 (top, slack)"}],
       "span tension [N]", f.t);
  plot("slip", [{y: TR.slip, c: "#393", name: "pulley 2, 20 ms mean"}], "slip 1 - ω2 r2 / ω1 r1 [%]", f.t);
  document.getElementById("readout").textContent =
    `t = ${f.t.toFixed(3)} s   pulley 1: ${f.omega[0].toFixed(2)} rad/s (${(f.omega[0] * rpm).toFixed(1)} rpm)` +
    `   pulley 2: ${f.omega[1].toFixed(2)} rad/s (${(f.omega[1] * rpm).toFixed(1)} rpm)` +
    `   span 1: ${f.span[0].toFixed(0)} N   span 2: ${f.span[1].toFixed(0)} N`;
}
let frame = 0, playing = true, last = null;
slider.addEventListener("input", () => { frame = +slider.value; show(frame); });
playBtn.addEventListener("click", () => { playing = !playing; playBtn.textContent = playing ? "Pause" : "Play"; last = null; });
function tick(ts) {
  if (playing) {
    if (last !== null) {
      const sp = +document.getElementById("speed").value;
      const adv = (ts - last) / 1000 * sp / S.frameStep;
      if (adv >= 1) { frame = (frame + Math.floor(adv)) % F.length; slider.value = frame; show(frame); last = ts; }
    } else last = ts;
  }
  requestAnimationFrame(tick);
}
const params = new URLSearchParams(location.search);
if (params.has("t")) {  // ?t=1.2: show that time, paused (used for the screenshot)
  const want = +params.get("t");
  frame = F.reduce((b, f, i) => Math.abs(f.t - want) < Math.abs(F[b].t - want) ? i : b, 0);
  playing = false; playBtn.textContent = "Play"; slider.value = frame;
}
show(frame);
document.body.dataset.status = "drawn";
requestAnimationFrame(tick);
</script>
</body>
</html>
"""
