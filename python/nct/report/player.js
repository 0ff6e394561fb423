// The corneal profile through the puff: a slider over the device's frames,
// the deformed section drawn over the undeformed one, the apex curve with a
// cursor. Data: the page's report-data JSON, key "player".
(function () {
  "use strict";
  const data = JSON.parse(document.getElementById("report-data").textContent).player;
  if (!data) return;
  const NS = "http://www.w3.org/2000/svg";
  const el = (id) => document.getElementById(id);
  const view = el("profile-view"), chart = el("apex-chart"), slider = el("frame");
  const W = +view.getAttribute("width"), H = +view.getAttribute("height"), pad = 24;
  const [x0, x1, y0, y1] = data.extent;
  const scale = Math.min((W - 2 * pad) / (x1 - x0), (H - 2 * pad) / (y1 - y0));
  const sx = (x) => W / 2 + scale * (x - (x0 + x1) / 2);
  const sy = (y) => H / 2 - scale * (y - (y0 + y1) / 2);
  const line = (xy) => {
    let d = "";
    for (let i = 0; i < xy[0].length; ++i)
      d += (i ? "L" : "M") + sx(xy[0][i]).toFixed(1) + "," + sy(xy[1][i]).toFixed(1);
    return d;
  };
  const add = (parent, tag, attrs) => {
    const node = document.createElementNS(NS, tag);
    for (const k in attrs) node.setAttribute(k, attrs[k]);
    parent.appendChild(node);
    return node;
  };
  // A millimetre scale bar and the undeformed section.
  add(view, "line", {x1: pad, y1: H - 8, x2: pad + scale, y2: H - 8, stroke: "#9aa4b2",
                     "stroke-width": 2});
  add(view, "text", {x: pad + scale + 6, y: H - 4, fill: "#9aa4b2", "font-size": 11}).textContent = "1 mm";
  const surfaces = Object.keys(data.frames[0]);
  for (const s of surfaces)
    add(view, "path", {d: line(data.frames[0][s]), fill: "none", stroke: "#7d8590",
                       "stroke-dasharray": "4 3", "stroke-width": 1, class: "undeformed"});
  const tissue = add(view, "path", {id: "profile-cornea", fill: "#3fb9f5", "fill-opacity": 0.25,
                                    stroke: "none"});
  const paths = {};
  for (const s of surfaces)
    paths[s] = add(view, "path", {id: "profile-" + s, fill: "none", stroke: "#e6f4ff",
                                  "stroke-width": 1.6});
  const label = add(view, "text", {x: W - pad, y: 18, fill: "#ffd166", "font-size": 13,
                                   "text-anchor": "end"});

  // The apex curve with the events and a cursor.
  const CW = +chart.getAttribute("width"), CH = +chart.getAttribute("height"), m = 36;
  const t = data.t_ms, a = data.apex_mm;
  const tmax = t[t.length - 1], amin = Math.min(...a), amax = Math.max(...a, 0);
  const cx = (v) => m + (CW - m - 10) * v / tmax;
  const cy = (v) => 12 + (CH - 40) * (amax - v) / (amax - amin || 1);
  add(chart, "line", {x1: m, y1: cy(0), x2: CW - 10, y2: cy(0), stroke: "#c0c6ce"});
  // Time ticks at 1, 2 or 5 times a power of ten, at most seven of them.
  const raw = tmax / 7, power = Math.pow(10, Math.floor(Math.log10(raw)));
  const step = [1, 2, 5, 10].map((f) => f * power).find((s) => s >= raw);
  for (let v = 0; v <= tmax + 1e-9; v += step)
    add(chart, "text", {x: cx(v), y: CH - 12, "font-size": 10, "text-anchor": "middle",
                        fill: "#4b5563"}).textContent = v.toFixed(step < 1 ? 1 : 0);
  add(chart, "text", {x: CW / 2, y: CH - 1, "font-size": 10, "text-anchor": "middle",
                      fill: "#4b5563"}).textContent = "ms from the onset of the puff";
  add(chart, "text", {x: 2, y: cy(amin), "font-size": 10, fill: "#4b5563"}).textContent =
      amin.toFixed(2);
  add(chart, "text", {x: 2, y: cy(0) + 4, "font-size": 10, fill: "#4b5563"}).textContent = "0 mm";
  let d = "";
  for (let i = 0; i < t.length; ++i) d += (i ? "L" : "M") + cx(t[i]).toFixed(1) + "," + cy(a[i]).toFixed(1);
  add(chart, "path", {d: d, fill: "none", stroke: "#1f77b4", "stroke-width": 1.6});
  for (const name in data.events) {
    const k = data.events[name];
    add(chart, "line", {x1: cx(t[k]), y1: 10, x2: cx(t[k]), y2: CH - 26, stroke: "#9aa4b2",
                        "stroke-dasharray": "3 3"});
    add(chart, "text", {x: cx(t[k]) + 3, y: 20, "font-size": 11, fill: "#374151"}).textContent = name;
  }
  const cursor = add(chart, "line", {id: "cursor", y1: 8, y2: CH - 26, stroke: "#d62728",
                                     "stroke-width": 1.5});
  const dot = add(chart, "circle", {r: 3.5, fill: "#d62728"});

  function show(k) {
    const f = data.frames[k];
    for (const s of surfaces) paths[s].setAttribute("d", line(f[s]));
    if (f.anterior && f.posterior) {
      const back = [f.posterior[0].slice().reverse(), f.posterior[1].slice().reverse()];
      tissue.setAttribute("d", line(f.anterior) + line(back).replace("M", "L") + "Z");
    }
    const at = Object.keys(data.events).filter((n) => data.events[n] === k);
    label.textContent = at.join(" ");
    cursor.setAttribute("x1", cx(t[k]));
    cursor.setAttribute("x2", cx(t[k]));
    dot.setAttribute("cx", cx(t[k]));
    dot.setAttribute("cy", cy(a[k]));
    el("readout").textContent = "frame " + (k + 1) + " of " + t.length + "   t = " +
        t[k].toFixed(2) + " ms   apex " + (a[k] >= 0 ? "+" : "") + a[k].toFixed(3) + " mm" +
        (at.length ? "   (" + at.join(", ") + ")" : "");
    slider.value = k;
  }
  slider.addEventListener("input", () => show(+slider.value));
  for (const b of document.querySelectorAll("button[data-frame]"))
    b.addEventListener("click", () => { stop(); show(+b.dataset.frame); });
  let timer = null;
  const play = el("play");
  function stop() { if (timer) clearInterval(timer); timer = null; play.textContent = "Play"; }
  play.addEventListener("click", () => {
    if (timer) return stop();
    play.textContent = "Pause";
    timer = setInterval(() => {
      const k = +slider.value + 1;
      if (k >= t.length) return stop();
      show(k);
    }, 60);
  });
  show(data.events.HC !== undefined ? data.events.HC : 0);
})();
