// rig: the live chart and the results of a run page. Plain script, no build step.
//
// The readings of the run's record arrive as server-sent events from /runs/{id}/live:
// "rows" events carry the new rows (id = rows seen, so the browser's EventSource resumes
// after a dropped connection), "end" says the run is over. The results are fetched every
// 5 s while the run is open, and as soon as a row typed on the page is stored (the server
// renders them, /runs/{id}/results?lang=). Long records are thinned for drawing only (min-max per pixel
// column); every row is kept.
(function () {
  "use strict";

  const config = JSON.parse(document.getElementById("run-config").textContent);
  const canvas = document.getElementById("live-chart");
  const select = document.getElementById("live-channel");
  const status = document.getElementById("live-status");
  const counter = document.getElementById("live-rows");
  const counted = document.getElementById("live-rows-words");
  const plural = new Intl.PluralRules(config.lang);
  const stateCell = document.getElementById("run-state");
  const note = document.getElementById("results-note");
  const columns = {};
  const units = {};
  const labels = {};
  for (const c of config.channels) {
    columns[c.name] = [];
    units[c.name] = c.unit;
    labels[c.name] = c.label;
  }
  let rows = 0;
  let open = config.state === "open";
  let drawPending = false;
  let resultsTimer = null;

  function setStatus(key) {
    status.textContent = config.text[key];
    status.dataset.state = key;
  }

  // --- numbers as the reports print them: four significant figures, powers of ten, the
  // page language's decimal sign ---------------------------------------------------------
  const SUPERSCRIPT = { "0": "⁰", "1": "¹", "2": "²", "3": "³", "4": "⁴", "5": "⁵",
    "6": "⁶", "7": "⁷", "8": "⁸", "9": "⁹", "-": "⁻", "+": "" };

  function fmt(v) {
    if (typeof v !== "number" || !isFinite(v)) return "—";
    if (v === 0) return "0";
    const a = Math.abs(v);
    if (a >= 1e4 || a < 1e-4) {
      const [m, e] = v.toExponential(3).split("e");
      const mantissa = (m.includes(".") ? m.replace(/\.?0+$/, "") : m).replace(".", config.decimal);
      return mantissa + "·10" + e.replace(/^\+/, "").split("").map((c) => SUPERSCRIPT[c]).join("");
    }
    const s = v.toPrecision(4);
    return (s.includes(".") ? s.replace(/\.?0+$/, "") : s).replace(".", config.decimal);
  }

  // --- the live readings ---------------------------------------------------------------
  function addRows(data) {
    const skip = Math.max(0, rows - data.start);  // rows already held (a repeated event)
    for (const name in data.columns) {
      const target = columns[name];
      if (!target) continue;
      const values = data.columns[name];
      for (let i = skip; i < values.length; i++) target.push(values[i]);
    }
    rows = Math.max(rows, data.stop);
    counter.textContent = String(rows);
    counted.textContent = config.rows_received[plural.select(rows)];
    scheduleDraw();
  }

  function connect() {
    const source = new EventSource(config.live_url + "&from=0");
    source.addEventListener("open", () => setStatus("streaming"));
    source.addEventListener("rows", (event) => addRows(JSON.parse(event.data)));
    source.addEventListener("end", (event) => {
      const data = JSON.parse(event.data);
      source.close();
      open = false;
      setStatus("ended");
      stateCell.textContent = config.text["state_" + data.state] || data.state;
      refreshResults();
    });
    source.addEventListener("error", () => {
      if (source.readyState !== EventSource.CLOSED) setStatus("reconnecting");
    });
  }

  // --- the chart -------------------------------------------------------------------------
  function scheduleDraw() {
    if (drawPending) return;
    drawPending = true;
    window.requestAnimationFrame(draw);
  }

  function niceTicks(lo, hi, count) {
    if (!(hi > lo)) return [lo];
    const raw = (hi - lo) / count;
    const power = Math.pow(10, Math.floor(Math.log10(raw)));
    const step = [1, 2, 5, 10].map((k) => k * power).find((s) => s >= raw) || raw;
    const ticks = [];
    for (let v = Math.ceil(lo / step) * step; v <= hi + step * 1e-9; v += step) ticks.push(v);
    return ticks;
  }

  function bounds(values) {
    let lo = Infinity;
    let hi = -Infinity;
    for (const v of values) {
      if (v === null || !isFinite(v)) continue;
      if (v < lo) lo = v;
      if (v > hi) hi = v;
    }
    if (lo === Infinity) return [0, 1];
    if (lo === hi) return [lo - 1, hi + 1];
    const pad = (hi - lo) * 0.04;
    return [lo - pad, hi + pad];
  }

  function draw() {
    drawPending = false;
    const ratio = window.devicePixelRatio || 1;
    const width = canvas.clientWidth;
    const height = canvas.clientHeight;
    canvas.width = Math.round(width * ratio);
    canvas.height = Math.round(height * ratio);
    const ctx = canvas.getContext("2d");
    ctx.setTransform(ratio, 0, 0, ratio, 0, 0);
    ctx.clearRect(0, 0, width, height);
    const left = 72;
    const right = 14;
    const top = 12;
    const bottom = 44;
    const plotW = Math.max(10, width - left - right);
    const plotH = Math.max(10, height - top - bottom);
    const xs = columns[config.x];
    const ys = columns[select.value];
    const [x0, x1] = bounds(xs);
    const [y0, y1] = bounds(ys);
    const px = (x) => left + ((x - x0) / (x1 - x0)) * plotW;
    const py = (y) => top + plotH - ((y - y0) / (y1 - y0)) * plotH;

    ctx.font = "12px system-ui, sans-serif";
    ctx.strokeStyle = "#ddd";
    ctx.fillStyle = "#333";
    ctx.lineWidth = 1;
    ctx.textAlign = "center";
    ctx.textBaseline = "top";
    for (const v of niceTicks(x0, x1, 8)) {
      const x = px(v);
      ctx.beginPath(); ctx.moveTo(x, top); ctx.lineTo(x, top + plotH); ctx.stroke();
      ctx.fillText(fmt(v), x, top + plotH + 4);
    }
    ctx.textAlign = "right";
    ctx.textBaseline = "middle";
    for (const v of niceTicks(y0, y1, 6)) {
      const y = py(v);
      ctx.beginPath(); ctx.moveTo(left, y); ctx.lineTo(left + plotW, y); ctx.stroke();
      ctx.fillText(fmt(v), left - 6, y);
    }
    ctx.strokeStyle = "#888";
    ctx.strokeRect(left, top, plotW, plotH);
    ctx.textAlign = "center";
    ctx.textBaseline = "bottom";
    ctx.fillText(labels[config.x] + ", " + units[config.x], left + plotW / 2, height - 2);
    ctx.save();
    ctx.translate(14, top + plotH / 2);
    ctx.rotate(-Math.PI / 2);
    ctx.textBaseline = "top";
    ctx.fillText(labels[select.value] + ", " + units[select.value], 0, -10);
    ctx.restore();

    // Points in row order; few are drawn as markers, many as a line thinned to min-max per
    // pixel column.
    let drawn = 0;
    ctx.save();
    ctx.beginPath();
    ctx.rect(left, top, plotW, plotH);
    ctx.clip();
    ctx.strokeStyle = "#1f77b4";
    ctx.fillStyle = "#1f77b4";
    const n = Math.min(xs.length, ys.length);
    if (n <= 300) {
      for (let i = 0; i < n; i++) {
        if (xs[i] === null || ys[i] === null) continue;
        ctx.beginPath();
        ctx.arc(px(xs[i]), py(ys[i]), 3, 0, 2 * Math.PI);
        ctx.fill();
        drawn++;
      }
    } else {
      ctx.beginPath();
      let column = null;
      let lo = 0;
      let hi = 0;
      let started = false;
      const flush = () => {
        if (column === null) return;
        if (!started) { ctx.moveTo(column, py(lo)); started = true; }
        ctx.lineTo(column, py(lo));
        ctx.lineTo(column, py(hi));
      };
      for (let i = 0; i < n; i++) {
        if (xs[i] === null || ys[i] === null) continue;
        drawn++;
        const c = Math.round(px(xs[i]));
        if (c !== column) { flush(); column = c; lo = ys[i]; hi = ys[i]; }
        else { lo = Math.min(lo, ys[i]); hi = Math.max(hi, ys[i]); }
      }
      flush();
      ctx.stroke();
    }
    ctx.restore();
    canvas.dataset.points = String(drawn);
  }

  // --- the results: the server renders them in the page's language ------------------------
  async function refreshResults() {
    try {
      const answer = await fetch(config.results_url, { headers: { Accept: "text/html" } });
      if (answer.ok) document.getElementById("results").innerHTML = await answer.text();
    } catch (error) {
      // the next refresh tries again
    }
    if (!open && note !== null) note.remove();
    if (!open && resultsTimer !== null) {
      window.clearInterval(resultsTimer);
      resultsTimer = null;
    }
  }

  select.addEventListener("change", scheduleDraw);
  document.addEventListener("rig:row-stored", refreshResults); // a row typed on this page (entry.js)
  window.addEventListener("resize", scheduleDraw);
  connect();
  refreshResults();
  if (open) resultsTimer = window.setInterval(refreshResults, 5000);
  scheduleDraw();
})();
