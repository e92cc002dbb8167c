"""The replay page's HTML, style and script (recording/replay_page.py fills in the data).
Everything is inline and nothing is fetched, so the page opens from a file with no
network. Laid out for a laptop screen (1366 x 768): the tree and the map side by side
under the slider, the objects below; no font under 12 px."""

TEMPLATE = r"""<!DOCTYPE html>
<html lang="en">
<head>
<meta charset="utf-8">
<meta name="viewport" content="width=device-width, initial-scale=1">
<title>csl replay: <!--TITLE--></title>
<style>
  * { box-sizing: border-box; }
  body { margin: 0; font: 13px/1.35 system-ui, -apple-system, "Segoe UI", sans-serif; color: #222; background: #f4f4f2; }
  header { display: flex; align-items: center; gap: 10px; padding: 6px 12px; background: #2f3b45; color: #fff;
           position: sticky; top: 0; z-index: 2; }
  header h1 { font-size: 15px; margin: 0 8px 0 0; font-weight: 600; white-space: nowrap; }
  header button { font-size: 14px; min-width: 34px; padding: 2px 8px; }
  #tick { flex: 1; min-width: 200px; }
  #ticklabel { font-variant-numeric: tabular-nums; min-width: 110px; font-size: 14px; }
  main { display: grid; grid-template-columns: minmax(380px, 40%) minmax(0, 1fr); gap: 8px; padding: 8px;
         height: calc(100vh - 44px); min-height: 480px; }
  section.panel { background: #fff; border: 1px solid #ccc; border-radius: 4px; display: flex; flex-direction: column;
                  min-height: 0; }
  section.panel h2 { font-size: 14px; margin: 0; padding: 5px 8px; border-bottom: 1px solid #ddd; background: #fafafa; }
  .note { font-size: 12px; color: #555; padding: 3px 8px; }
  #tree { position: relative; overflow: auto; flex: 1; padding: 4px 6px; font-size: 13px; }
  .node { white-space: nowrap; padding: 1px 4px; border-left: 4px solid transparent; border-radius: 2px; }
  .node .badge { display: inline-block; width: 76px; font-size: 12px; font-weight: 600; }
  .node .kind { color: #777; font-size: 12px; }
  .node .fb { color: #555; font-size: 12px; margin-left: 6px; }
  .st-SUCCESS { background: #dff3d8; border-left-color: #3a9a2a; } .st-SUCCESS .badge { color: #2c7a1f; }
  .st-FAILURE { background: #fbdcdc; border-left-color: #c62828; } .st-FAILURE .badge { color: #b01d1d; }
  .st-RUNNING { background: #fff1c9; border-left-color: #d69a00; } .st-RUNNING .badge { color: #9a6b00; }
  .st-INVALID { color: #888; } .st-INVALID .badge { color: #999; }
  .st-UNKNOWN { color: #666; } .st-UNKNOWN .badge { color: #999; }
  .st-ACTIVE { background: #dbe9f6; border-left-color: #2a6fb0; } .st-ACTIVE .badge { color: #1e5a94; }
  .changed { outline: 2px solid #7a5cc7; }
  #right { display: grid; grid-template-rows: minmax(0, 1fr) auto; gap: 8px; min-height: 0; min-width: 0; }
  #mapbox { flex: 1; min-height: 0; position: relative; }
  #map { width: 100%; height: 100%; display: block; }
  #legend { font-size: 12px; padding: 3px 8px; color: #333; }
  #legend span { margin-right: 10px; white-space: nowrap; }
  #legend i { display: inline-block; width: 11px; height: 11px; border-radius: 6px; vertical-align: -1px; margin-right: 3px; }
  #events { height: 96px; overflow: auto; font-size: 12px; padding: 2px 8px; }
  #events div { white-space: nowrap; overflow: hidden; text-overflow: ellipsis; }
  #objects { padding: 0 8px 16px; display: grid; grid-template-columns: repeat(auto-fill, minmax(420px, 1fr)); gap: 8px; }
  .object { background: #fff; border: 1px solid #ccc; border-radius: 4px; padding: 6px 8px; font-size: 13px; }
  .object h3 { font-size: 14px; margin: 0 0 4px; }
  .object.current { border-color: #d69a00; box-shadow: 0 0 0 2px #f3d27a; }
  .object ol { margin: 0; padding-left: 22px; }
  .object li { font-size: 12px; }
  .object li.future { color: #aaa; }
  .object li.now { font-weight: 600; }
  .object img { max-width: 100%; margin-top: 6px; border: 1px solid #eee; }
  .o-grasped { color: #2c7a1f; } .o-left { color: #1e5a94; } .o-failed { color: #b01d1d; } .o-under-way { color: #9a6b00; }
  h2.objects { font-size: 15px; margin: 8px 8px 6px; }
</style>
</head>
<body>
<header>
  <h1>csl replay: <!--TITLE--></h1>
  <button id="first" title="the first tick">|&#x25C0;</button>
  <button id="back" title="one tick back">&#x25C0;</button>
  <button id="play" title="play / pause">play</button>
  <button id="forward" title="one tick on">&#x25B6;|</button>
  <input id="tick" type="range" min="0" max="0" value="0" aria-label="tick">
  <span id="ticklabel"></span>
</header>
<main>
  <section class="panel" id="treepanel">
    <h2>Behaviour tree</h2>
    <div class="note" id="treenote"></div>
    <div id="tree"></div>
  </section>
  <div id="right">
    <section class="panel">
      <h2>The floor: robot, paths, objects (inches)</h2>
      <div id="mapbox"><svg id="map"></svg></div>
      <div id="legend">
        <span><i style="background:#e07b00"></i>robot (this tick's paths bold)</span>
        <span><i style="background:#9a6b00;border:2px solid #f3d27a"></i>object under way</span>
        <span><i style="background:#3a9a2a"></i>grasped</span><span><i style="background:#2a6fb0"></i>left</span>
        <span><i style="background:#c62828"></i>failed</span><span><i style="background:#999"></i>waiting</span>
      </div>
    </section>
    <section class="panel">
      <h2 id="eventstitle">Events at this tick</h2>
      <div id="events"></div>
    </section>
  </div>
</main>
<h2 class="objects">Objects: the tests chosen, what was measured, the grasps and the outcome</h2>
<div id="objects"></div>
<script type="application/json" id="data">/*DATA*/</script>
<script>
"use strict";
const D = JSON.parse(document.getElementById("data").textContent);
const $ = (id) => document.getElementById(id);
const slider = $("tick");
const SVGNS = $("map").namespaceURI;  // an <svg> in HTML is in the SVG namespace
slider.max = D.ticks;

function el(tag, attrs, text) {
  const e = tag.startsWith("svg:") ? document.createElementNS(SVGNS, tag.slice(4)) : document.createElement(tag);
  for (const [k, v] of Object.entries(attrs || {})) e.setAttribute(k, v);
  if (text !== undefined) e.textContent = text;
  return e;
}

// ---- the behaviour tree: one row per node, indented by depth
const depth = [];
const rows = [];
for (const n of D.nodes) {
  depth[n.id] = n.parent === null ? 0 : depth[n.parent] + 1;
  const row = el("div", {"class": "node", "id": "node-" + n.id, "data-name": n.name});
  row.style.paddingLeft = (4 + 16 * depth[n.id]) + "px";
  row.append(el("span", {"class": "badge"}), el("span", {"class": "name"}, n.name + " "),
             el("span", {"class": "kind"}, n.family === n.kind ? n.kind : n.kind + " (" + n.family + ")"),
             el("span", {"class": "fb"}));
  $("tree").append(row);
  rows.push(row);
}
$("treenote").textContent = D.tree_source === "recording"
  ? "Statuses as recorded (/behaviour_tree/nodes), at the end of the tick; outlined: changed since the tick before."
  : "No recorded statuses (an episode log): the executive's tree, statuses UNKNOWN; ACTIVE marks a node an episode "
    + "event names at this tick.";

// ---- the map: SVG in inches, y up (drawn as -y)
const svg = $("map");
const pts = [];
for (const m of D.moves) { for (const p of m.path) pts.push(p); pts.push(m.pose); }
for (const o of D.objects) if (o.centroid) pts.push(o.centroid);
for (const p of D.poses) if (p) pts.push(p);
let [x0, x1, y0, y1] = [0, 100, 0, 100];
if (D.floor) {
  x0 = D.floor.x; y0 = D.floor.y; x1 = x0 + D.floor.columns * D.floor.cell; y1 = y0 + D.floor.rows * D.floor.cell;
} else if (pts.length) {
  x0 = Math.min(...pts.map(p => p[0])); x1 = Math.max(...pts.map(p => p[0]));
  y0 = Math.min(...pts.map(p => p[1])); y1 = Math.max(...pts.map(p => p[1]));
}
const margin = 2 * D.base_radius;
x0 -= margin; y0 -= margin; x1 += margin; y1 += margin;
svg.setAttribute("viewBox", [x0, -y1, x1 - x0, y1 - y0].join(" "));
const floorLayer = el("svg:g"), pathLayer = el("svg:g"), objectLayer = el("svg:g"), robotLayer = el("svg:g");
svg.append(floorLayer, pathLayer, objectLayer, robotLayer);
if (D.floor) {
  const f = D.floor, canvas = document.createElement("canvas");
  canvas.width = f.columns; canvas.height = f.rows;
  const ctx = canvas.getContext("2d"), img = ctx.createImageData(f.columns, f.rows);
  const raw = atob(f.pixels);
  for (let r = 0; r < f.rows; r++) for (let c = 0; c < f.columns; c++) {
    const v = raw.charCodeAt(r * f.columns + c), i = 4 * ((f.rows - 1 - r) * f.columns + c);
    img.data[i] = img.data[i + 1] = img.data[i + 2] = v; img.data[i + 3] = 255;
  }
  ctx.putImageData(img, 0, 0);
  floorLayer.append(el("svg:image", {"href": canvas.toDataURL("image/png"), "x": f.x, "y": -(f.y + f.rows * f.cell),
                                     "width": f.columns * f.cell, "height": f.rows * f.cell,
                                     "preserveAspectRatio": "none", "opacity": "0.75"}));
} else {
  floorLayer.append(el("svg:rect", {"x": x0, "y": -y1, "width": x1 - x0, "height": y1 - y0, "fill": "#ecebe6"}));
}
const grid = el("svg:g", {"stroke": "#bbb", "stroke-width": "0.2"});
for (let x = Math.ceil(x0 / 24) * 24; x <= x1; x += 24) grid.append(el("svg:line", {"x1": x, "x2": x, "y1": -y1, "y2": -y0}));
for (let y = Math.ceil(y0 / 24) * 24; y <= y1; y += 24) grid.append(el("svg:line", {"x1": x0, "x2": x1, "y1": -y, "y2": -y}));
floorLayer.append(grid);

const R = D.base_radius;
const robot = el("svg:g", {"id": "robot"});
robot.append(el("svg:circle", {"r": R, "cx": 0, "cy": 0, "fill": "#e07b00", "fill-opacity": "0.35", "stroke": "#e07b00", "stroke-width": "0.8"}),
             el("svg:line", {"x1": 0, "y1": 0, "x2": R, "y2": 0, "stroke": "#7a3d00", "stroke-width": "1.2"}));
robotLayer.append(robot);

function fontSize() {  // user units (inches) for 12.5 px on screen
  const box = svg.getBoundingClientRect();
  const scale = Math.min(box.width / (x1 - x0), box.height / (y1 - y0)) || 1;
  return 12.5 / scale;
}

function objectState(o, t) {
  if (o.end_tick !== null && t >= o.end_tick && o.outcome) return o.outcome;
  if (t >= o.start_tick && t > 0) return "under-way";
  return "waiting";
}
const OBJECT_COLOURS = {"grasped": "#3a9a2a", "left": "#2a6fb0", "failed": "#c62828", "under-way": "#d69a00", "waiting": "#999"};

function drawMap(t) {
  pathLayer.replaceChildren(); objectLayer.replaceChildren();
  const fs = fontSize();
  let from = D.poses[0];
  for (const m of D.moves) {
    if (m.tick > t) break;
    const line = (from ? [from.slice(0, 2)] : []).concat(m.path, [m.pose.slice(0, 2)]);
    const now = m.tick === t;
    pathLayer.append(el("svg:polyline", {"points": line.map(p => p[0] + "," + (-p[1])).join(" "), "fill": "none",
      "stroke": m.collided ? "#c62828" : "#e07b00", "stroke-width": now ? 1.6 : 0.6, "stroke-opacity": now ? 1 : 0.55,
      "class": now ? "path now" : "path"}));
    from = m.pose;
  }
  const located = D.events.find(e => e.event === "located");
  if (located && located.tick <= t && t > 0) for (const r of Array.isArray(located.regions) ? located.regions : []) {
    if (!r || !Array.isArray(r.centroid)) continue;
    objectLayer.append(el("svg:circle", {"cx": r.centroid[0], "cy": -r.centroid[1], "r": 1.2, "fill": "#666"}));
  }
  for (const o of D.objects) {
    if (!o.centroid || t < (located ? Math.max(1, located.tick) : o.start_tick)) continue;  // not seen yet
    const state = objectState(o, t), [cx, cy] = o.centroid;
    // a disc of the region's area where the floor's scale is known (pixels are cells of the map), else a dot
    const size = D.floor ? Math.max(1.5, Math.sqrt((o.pixels || 4) / Math.PI) * D.floor.cell) : 3;
    objectLayer.append(el("svg:circle", {"cx": cx, "cy": -cy, "r": size, "fill": OBJECT_COLOURS[state],
      "fill-opacity": state === "waiting" ? 0.35 : 0.7, "stroke": state === "under-way" ? "#f3d27a" : "#333",
      "stroke-width": state === "under-way" ? 1.5 : 0.3, "class": "object-marker " + state, "id": "object-" + o.index}));
    const label = el("svg:text", {"x": cx + size + 1, "y": -cy + fs * 0.35, "font-size": fs, "fill": "#111",
      "paint-order": "stroke", "stroke": "#fff", "stroke-width": fs * 0.25}, o.index + (o.grasp && state !== "under-way" && state !== "waiting" ? " " + o.grasp : ""));
    objectLayer.append(label);
  }
  const pose = D.poses[t];
  robot.style.display = pose ? "" : "none";
  if (pose) robot.setAttribute("transform", "translate(" + pose[0] + "," + (-pose[1]) + ") rotate(" + (-pose[2]) + ")");
  robot.setAttribute("data-pose", pose ? pose.join(",") : "");
}

// ---- the objects
const cards = [];
for (const o of D.objects) {
  const card = el("div", {"class": "object", "id": "card-" + o.index});
  const title = el("h3");
  const list = el("ol");
  for (const s of o.steps) list.append(el("li", {"data-tick": s.tick}, "tick " + s.tick + ": " + s.text));
  card.append(title, list);
  if (D.images[o.index]) card.append(el("img", {"src": D.images[o.index], "alt": "object " + o.index + "'s decision tree"}));
  $("objects").append(card);
  cards.push([o, card, title, list]);
}

function drawObjects(t) {
  for (const [o, card, title, list] of cards) {
    const state = objectState(o, t);
    const word = state === "under-way" ? "under way" : state === "waiting" ? "not yet" : state + (o.grasp ? " (" + o.grasp + ")" : "");
    title.replaceChildren("object " + o.index + ": ", el("span", {"class": "o-" + state}, word));
    card.classList.toggle("current", state === "under-way");
    for (const li of list.children) {
      const at = Number(li.dataset.tick);
      li.className = at > t ? "future" : at === t ? "now" : "";
    }
  }
}

function drawTree(t) {
  const st = D.statuses[t], before = D.statuses[Math.max(0, t - 1)], fb = D.feedback[t];
  for (let i = 0; i < rows.length; i++) {
    const row = rows[i];
    row.className = "node st-" + st[i] + (t > 0 && st[i] !== before[i] ? " changed" : "");
    row.dataset.status = st[i];
    row.children[0].textContent = st[i];
    row.children[3].textContent = fb[i] ? "— " + fb[i] : "";
  }
  // keep the deepest node that changed (where the tree is working: running or active first) in view
  const tree = $("tree"), changed = rows.filter(r => r.classList.contains("changed"));
  const tip = changed.filter(r => /st-(RUNNING|ACTIVE)/.test(r.className)).pop() || changed.pop();
  if (tip && (tip.offsetTop < tree.scrollTop || tip.offsetTop + tip.offsetHeight > tree.scrollTop + tree.clientHeight)) {
    tree.scrollTop = tip.offsetTop - tree.clientHeight / 2;
  }
}

function drawEvents(t) {
  const here = D.events.filter(e => (e.tick || 0) === t && t > 0);
  $("eventstitle").textContent = "Events at tick " + t + " (" + here.length + ")";
  $("events").replaceChildren(...here.map(e => {
    const rest = Object.entries(e).filter(([k]) => !["tick", "event", "path", "regions", "candidates"].includes(k))
      .map(([k, v]) => k + "=" + JSON.stringify(v)).join(" ");
    return el("div", {"title": rest}, e.event + "  " + rest);
  }));
}

function show(t) {
  t = Math.max(0, Math.min(D.ticks, Number(t)));
  slider.value = t;
  const end = D.events.find(e => e.event === "episode_end");
  $("ticklabel").textContent = "tick " + t + " / " + D.ticks + (t === D.ticks && end ? " (" + end.status + ")" : "");
  drawTree(t); drawMap(t); drawObjects(t); drawEvents(t);
  document.body.dataset.tick = t;
}

let timer = null;
function stop() { if (timer) { clearInterval(timer); timer = null; $("play").textContent = "play"; } }
slider.addEventListener("input", () => { stop(); show(slider.value); });
$("first").onclick = () => { stop(); show(0); };
$("back").onclick = () => { stop(); show(Number(slider.value) - 1); };
$("forward").onclick = () => { stop(); show(Number(slider.value) + 1); };
$("play").onclick = () => {
  if (timer) { stop(); return; }
  if (Number(slider.value) >= D.ticks) show(0);
  $("play").textContent = "pause";
  timer = setInterval(() => { if (Number(slider.value) >= D.ticks) stop(); else show(Number(slider.value) + 1); }, 700);
};
document.addEventListener("keydown", (e) => {
  if (e.target === slider) return;
  if (e.key === "ArrowRight") { stop(); show(Number(slider.value) + 1); }
  if (e.key === "ArrowLeft") { stop(); show(Number(slider.value) - 1); }
});
window.addEventListener("resize", () => show(slider.value));
show(0);
</script>
</body>
</html>
"""
