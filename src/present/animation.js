// The crawler animation of a crawlopt report: plain JavaScript, no network, no library.
// It reads the recorded motion from the JSON block #crawler-data (times t, block positions X,
// actuator lengths L, link compressions x, slip states per sample; between samples the exact
// simulator's motion is linear, so linear interpolation is exact) and draws blocks, springs,
// actuators and the friction on every slipping block into the SVG #crawler-svg.
// The state shown is exposed in the DOM for tests and readers: #anim-state carries data-t
// (time), data-y (barycentre advance since t = 0), data-period, data-periods and
// data-displacement (per period, as reported); the SVG carries
// data-px-per-unit (pixels per length unit) and every block rect data-x (its position X_b).
(function () {
  "use strict";
  const data = JSON.parse(document.getElementById("crawler-data").textContent);
  const NS = "http://www.w3.org/2000/svg";
  const svg = document.getElementById("crawler-svg");
  const stateEl = document.getElementById("anim-state");
  const slider = document.getElementById("anim-time");
  const playBtn = document.getElementById("anim-play");
  const speedEl = document.getElementById("anim-speed");
  const speedOut = document.getElementById("anim-speed-value");
  const N = data.X[0].length;
  const n = N - 1;
  const T = data.period;
  const tEnd = data.t[data.t.length - 1];
  const W = 1000, H = 250, groundY = 170, blockH = 46;

  // Display geometry (the model's shape is measured from an arbitrary rest length): spacing l0
  // between blocks, block width bw, actuator drawn with length a0 + (L - Lmin) and the spring
  // taking the rest of the gap, at least 15 % of l0.
  let Lmin = Infinity, Lmax = -Infinity, xkmax = -Infinity, xkmin = Infinity;
  for (let i = 0; i < data.t.length; i++) {
    for (let l = 0; l < n; l++) {
      Lmin = Math.min(Lmin, data.L[i][l]);
      Lmax = Math.max(Lmax, data.L[i][l]);
      const xk = data.x[i][l] / data.k[l];
      xkmax = Math.max(xkmax, xk);
      xkmin = Math.min(xkmin, xk);
    }
  }
  const motion = Math.max(Lmax - Lmin + xkmax - xkmin, Math.abs(data.displacement) * 0.5, 1e-9);
  const l0 = Math.max(data.spacing, (xkmax - Lmin) / 0.45, motion * 1.2);
  const bw = 0.25 * l0;
  const a0 = 0.08 * l0;
  const drawX = (b, X) => X + b * l0; // centre of block b in world units

  let lo = Infinity, hi = -Infinity;
  for (let i = 0; i < data.t.length; i++) {
    for (let b = 0; b < N; b++) {
      lo = Math.min(lo, drawX(b, data.X[i][b]) - bw / 2);
      hi = Math.max(hi, drawX(b, data.X[i][b]) + bw / 2);
    }
  }
  const margin = 0.06 * (hi - lo);
  lo -= margin;
  hi += margin;
  const scale = (W - 40) / (hi - lo); // px per length unit
  const px = (u) => 20 + (u - lo) * scale;
  svg.setAttribute("viewBox", `0 0 ${W} ${H}`);
  svg.dataset.pxPerUnit = String(scale);

  function el(name, attrs, parent) {
    const e = document.createElementNS(NS, name);
    for (const k in attrs) e.setAttribute(k, attrs[k]);
    (parent || svg).appendChild(e);
    return e;
  }
  const FWD = "#0072b2", BWD = "#d55e00", STICK = "#9a9a9a";

  // Ground with a ruler: fixed in the picture, so the advance is visible.
  el("rect", { x: 0, y: groundY, width: W, height: H - groundY, fill: "#f3efe6" });
  el("line", { x1: 0, y1: groundY, x2: W, y2: groundY, stroke: "#6b5b45", "stroke-width": 2 });
  const step = niceStep((hi - lo) / 10);
  for (let v = Math.ceil(lo / step) * step; v <= hi; v += step) {
    el("line", { x1: px(v), y1: groundY, x2: px(v), y2: groundY + 8, stroke: "#6b5b45" });
    const tx = el("text", { x: px(v), y: groundY + 22, "text-anchor": "middle", class: "tick" });
    tx.textContent = fmt(v);
  }
  const unitLabel = el("text", { x: W - 8, y: H - 8, "text-anchor": "end", class: "tick" });
  unitLabel.textContent = "ground position [length]";
  const fwd = el("text", { x: 12, y: 22, class: "note" });
  fwd.textContent = "forward →";

  // Start and current barycentre.
  const y0line = el("line", { y1: 30, y2: groundY, stroke: "#444", "stroke-dasharray": "4 4" });
  const y0label = el("text", { y: 44, class: "note", "text-anchor": "end" });
  y0label.textContent = "y(0)";
  const ymark = el("path", { fill: "#222" });
  const ylabel = el("text", { y: 44, class: "note" });

  const springs = [], acts = [], blocks = [], arrows = [], fricLabels = [];
  for (let l = 0; l < n; l++) {
    springs.push(el("polyline", { fill: "none", stroke: "#333", "stroke-width": 2 }));
    acts.push({
      body: el("rect", { height: 14, fill: "#c9c9c9", stroke: "#555", "stroke-width": 1.5, rx: 2 }),
      rod: el("line", { stroke: "#555", "stroke-width": 3 }),
      label: el("text", { class: "small", "text-anchor": "middle" }),
    });
  }
  for (let b = 0; b < N; b++) {
    const r = el("rect", { height: blockH, width: bw * scale, rx: 4, class: "block", stroke: "#222", "stroke-width": 1.5 });
    r.dataset.index = String(b + 1);
    blocks.push(r);
    const t = el("text", { class: "blocklabel", "text-anchor": "middle" });
    t.textContent = String(b + 1);
    blocks[b].labelEl = t;
    arrows.push(el("path", { "stroke-width": 3, fill: "none" }));
    fricLabels.push(el("text", { class: "small", "text-anchor": "middle" }));
  }

  function niceStep(v) {
    const p = Math.pow(10, Math.floor(Math.log10(v)));
    for (const m of [1, 2, 2.5, 5, 10]) if (m * p >= v) return m * p;
    return 10 * p;
  }
  function fmt(v) {
    const r = Math.round(v * 1e6) / 1e6;
    return String(Number(r.toPrecision(6)));
  }

  // Sample index i with t[i] <= t < t[i+1] (binary search).
  function locate(t) {
    let a = 0, b = data.t.length - 1;
    if (t >= data.t[b]) return b - 1;
    while (b - a > 1) {
      const m = (a + b) >> 1;
      if (data.t[m] <= t) a = m; else b = m;
    }
    return a;
  }
  const lerp = (u, v, s) => u + s * (v - u);

  function render(t) {
    t = Math.min(Math.max(t, 0), tEnd);
    const i = locate(t);
    const dt = data.t[i + 1] - data.t[i];
    const s = dt > 0 ? Math.min(Math.max((t - data.t[i]) / dt, 0), 1) : 1;
    const X = [], L = [], x = [];
    for (let b = 0; b < N; b++) X.push(lerp(data.X[i][b], data.X[i + 1][b], s));
    for (let l = 0; l < n; l++) {
      L.push(lerp(data.L[i][l], data.L[i + 1][l], s));
      x.push(lerp(data.x[i][l], data.x[i + 1][l], s));
    }
    // Slip over the current interval (slip[i+1] is the state over (t[i], t[i+1])).
    const slip = data.slip[Math.min(i + 1, data.slip.length - 1)];
    let y = 0;
    for (let b = 0; b < N; b++) y += X[b];
    y /= N;
    const top = groundY - blockH;
    for (let b = 0; b < N; b++) {
      const cx = px(drawX(b, X[b]));
      const r = blocks[b];
      r.setAttribute("x", cx - (bw * scale) / 2);
      r.setAttribute("y", top);
      r.dataset.x = String(X[b]);
      r.setAttribute("fill", slip[b] > 0 ? FWD : slip[b] < 0 ? BWD : "#e8e8e8");
      r.labelEl.setAttribute("x", cx);
      r.labelEl.setAttribute("y", top + blockH / 2 + 6);
      r.labelEl.setAttribute("fill", slip[b] !== 0 ? "#fff" : "#222");
      // Friction on a slipping block acts against its motion, with threshold mu+ or mu-.
      const a = arrows[b], fl = fricLabels[b];
      if (slip[b] !== 0) {
        const dir = -slip[b];
        const yA = groundY - 8, len = Math.min(0.4 * bw * scale, 40);
        const x1 = cx - (dir * len) / 2, x2 = cx + (dir * len) / 2;
        a.setAttribute("d", `M${x1},${yA} L${x2},${yA} M${x2 - dir * 7},${yA - 5} L${x2},${yA} L${x2 - dir * 7},${yA + 5}`);
        a.setAttribute("stroke", "#fff");
        // Few blocks: the whole sentence; many: the threshold only, so that labels do not collide.
        const mu = slip[b] > 0 ? `μ⁺ = ${fmt(data.mu_forward[b])}` : `μ⁻ = ${fmt(data.mu_backward[b])}`;
        fl.textContent = N <= 4 ? `friction ${mu}` : N <= 8 ? mu : "";
        fl.setAttribute("x", cx);
        fl.setAttribute("y", top - 8);
        fl.setAttribute("fill", slip[b] > 0 ? FWD : BWD);
      } else {
        a.setAttribute("d", "");
        fl.textContent = "";
      }
    }
    const yMid = groundY - blockH / 2;
    for (let l = 0; l < n; l++) {
      const xr = px(drawX(l, X[l])) + (bw * scale) / 2;
      const xl = px(drawX(l + 1, X[l + 1])) - (bw * scale) / 2;
      const actLen = (a0 + (L[l] - Lmin)) * scale;
      const xa = xr + actLen;
      const A = acts[l];
      const bodyLen = Math.min(0.6 * a0 * scale + 12, actLen);
      A.body.setAttribute("x", xr);
      A.body.setAttribute("y", yMid - 7);
      A.body.setAttribute("width", Math.max(bodyLen, 1));
      A.rod.setAttribute("x1", xr + bodyLen);
      A.rod.setAttribute("x2", xa);
      A.rod.setAttribute("y1", yMid);
      A.rod.setAttribute("y2", yMid);
      A.label.setAttribute("x", (xr + xa) / 2);
      A.label.setAttribute("y", yMid - 12);
      A.label.textContent = xl - xr > 50 ? `L${sub(l + 1)}` : "";
      // Spring: a zig-zag from the actuator's end to the next block.
      const zigs = 10, amp = 8, pts = [`${xa},${yMid}`];
      const sl = xl - xa;
      for (let k = 0; k < zigs; k++) {
        pts.push(`${xa + (sl * (k + 0.5)) / zigs},${yMid + (k % 2 === 0 ? -amp : amp)}`);
      }
      pts.push(`${xl},${yMid}`);
      springs[l].setAttribute("points", pts.join(" "));
    }
    const py0 = px(drawX((N - 1) / 2, data.y0));
    const py = px(drawX((N - 1) / 2, y));
    y0line.setAttribute("x1", py0);
    y0line.setAttribute("x2", py0);
    y0label.setAttribute("x", py0 - 4);
    ymark.setAttribute("d", `M${py - 7},30 L${py + 7},30 L${py},42 Z`);
    ylabel.setAttribute("x", py + 10);
    const adv = y - data.y0;
    ylabel.textContent = `y(t) − y(0) = ${fmt(adv)}`;
    stateEl.dataset.t = String(t);
    stateEl.dataset.y = String(adv);
    stateEl.textContent = `t = ${t.toFixed(3)} (period ${Math.min(Math.floor(t / T) + 1, data.periods)} of ${data.periods}),  barycentre advance y(t) − y(0) = ${fmt(adv)}`;
    if (document.activeElement !== slider) slider.value = String(t);
  }
  function sub(k) {
    return String(k).replace(/[0-9]/g, (c) => String.fromCharCode(0x2080 + Number(c)));
  }

  // Playback: at speed 1 one period lasts 4 seconds.
  let t = 0, playing = true, last = null;
  slider.max = String(tEnd);
  slider.step = String(tEnd / 2000);
  function speed() { return Number(speedEl.value); }
  function showSpeed() { speedOut.textContent = `${speed().toFixed(2)}×`; }
  showSpeed();
  speedEl.addEventListener("input", showSpeed);
  playBtn.addEventListener("click", () => {
    playing = !playing;
    playBtn.textContent = playing ? "Pause" : "Play";
    last = null;
  });
  slider.addEventListener("input", () => {
    t = Number(slider.value);
    render(t);
  });
  function frame(now) {
    if (playing) {
      if (last !== null) {
        t += ((now - last) / 1000) * speed() * (T / 4);
        if (t > tEnd) t = 0;
      }
      last = now;
      render(t);
    } else {
      last = null;
    }
    requestAnimationFrame(frame);
  }
  // For tests and readers: show the state at time s and stop.
  window.crawlerShow = function (s) {
    playing = false;
    playBtn.textContent = "Play";
    t = s;
    render(t);
    return { t: Number(stateEl.dataset.t), y: Number(stateEl.dataset.y) };
  };
  playBtn.textContent = "Pause";
  stateEl.dataset.period = String(T);
  stateEl.dataset.periods = String(data.periods);
  stateEl.dataset.displacement = String(data.displacement);
  render(0);
  stateEl.dataset.ready = "1";
  requestAnimationFrame(frame);
})();
