// The operator console's page: draws the frames and maps the server sends over the
// WebSocket, and sends the operator's commands back (see crates/usar-console/src/protocol.rs).
"use strict";

const params = new URLSearchParams(location.search);
const token = params.get("token") || "";
const state = { frame: null, map: null, selected: null, cells: null, labels: null, cellMap: null };
window.consoleState = state; // for tests and the curious
const $ = (id) => document.getElementById(id);
let socket = null;

function log(text) {
  const li = document.createElement("li");
  li.textContent = new Date().toLocaleTimeString() + " " + text;
  const ol = $("log");
  ol.insertBefore(li, ol.firstChild);
  while (ol.children.length > 50) ol.removeChild(ol.lastChild);
}

function send(message) {
  if (socket && socket.readyState === WebSocket.OPEN) socket.send(JSON.stringify(message));
}

function connect() {
  const url = (location.protocol === "https:" ? "wss://" : "ws://") + location.host + "/ws" +
    (token ? "?token=" + encodeURIComponent(token) : "");
  socket = new WebSocket(url);
  socket.onopen = () => {
    $("connection").textContent = "connected";
    $("connection").className = "good";
    $("control-status").textContent = token ? "control: token given" :
      "no access token: open the address `usar console` printed (…/?token=…)";
  };
  socket.onclose = (event) => {
    $("connection").className = "bad";
    if (event.code === 1008) {
      // Refused for the token (missing, wrong or too many attempts): retrying would not help.
      $("connection").textContent = "closed: " + (event.reason || "access token refused");
      return;
    }
    $("connection").textContent = "disconnected; retrying";
    setTimeout(connect, 1000);
  };
  socket.onmessage = (event) => {
    let m;
    try { m = JSON.parse(event.data); } catch (e) { return; }
    if (m.type === "frame") { state.frame = m; render(); }
    else if (m.type === "map") { setMap(m); render(); }
    else if (m.type === "error") { log("refused: " + m.message); }
    else if (m.type === "ok") { log("ok: " + m.request); }
  };
}

function decode(b64) {
  const s = atob(b64 || "");
  const a = new Uint8Array(s.length);
  for (let i = 0; i < s.length; i++) a[i] = s.charCodeAt(i);
  return a;
}

function setMap(m) {
  state.map = m;
  state.cells = decode(m.cells);
  state.labels = decode(m.labels);
  state.cellMap = decode(m.cell_map);
  drawLayers();
  drawChart();
}

// World (x east, y north) to canvas pixels: the team map's extent fills the canvas.
function transform() {
  const m = state.map, c = $("map");
  if (!m || !m.width) return null;
  const w = m.width * m.resolution_m, h = m.height * m.resolution_m;
  const scale = Math.min(c.width / w, c.height / h);
  return {
    scale,
    toPx: (x, y) => [(x - m.origin[0]) * scale, c.height - (y - m.origin[1]) * scale],
    toWorld: (px, py) => [px / scale + m.origin[0], (c.height - py) / scale + m.origin[1]],
  };
}

const LABEL_TINT = [null, "rgba(80,140,255,0.25)", "rgba(80,255,140,0.2)", "rgba(255,200,80,0.2)", "rgba(255,90,200,0.22)"];
const CELL_COLOURS = [null, "rgba(120,200,255,0.25)", "rgba(120,200,255,0.45)", "rgba(200,150,80,0.35)",
  "rgba(200,150,80,0.6)", "rgba(255,60,60,0.45)", "rgba(255,255,0,0.6)", "rgba(255,120,0,0.4)"];
const BTM_COLOURS = { terminal: "#fff", divergence: "#4cf", free_space: "#8f8", obstacle: "#f84", victim: "#ff0", hazard: "#f0f" };

function render() {
  const f = state.frame;
  if (!f) return;
  $("clock").textContent = formatTime(f.time_s) + (f.paused ? " (paused)" : "");
  $("speed").textContent = f.speed + "×";
  // The selector follows the mission's speed (another viewer may have changed it).
  const select = $("speed-select");
  if (document.activeElement !== select && [...select.options].some((o) => Number(o.value) === f.speed)) {
    select.value = [...select.options].find((o) => Number(o.value) === f.speed).value;
  }
  $("measured").textContent = f.measured_speed.toFixed(2) + "×";
  $("explored").textContent = f.explored_m2.toFixed(1) + " m² known, coverage " + (100 * f.coverage).toFixed(1) + " %" +
    (f.team_finish ? " — mission ended: " + f.team_finish : "");
  $("btm-status").textContent = "BTM: " + f.btm_nodes + " nodes, " + f.btm_links + " links; hypothesis " + f.hypothesis +
    "; weights w_l " + f.weights[0] + ", w_p " + f.weights[1] + ", w_q " + f.weights[2] + "; MAXQ primitives " + f.maxq_primitives;
  renderRobots(f);
  renderVictims(f);
  renderHandoffs(f);
  drawMap();
}

function formatTime(s) {
  const m = Math.floor(s / 60), r = s - 60 * m;
  return m + ":" + (r < 10 ? "0" : "") + r.toFixed(1);
}

// The robot list is updated in place (a click never lands on an element just replaced).
function renderRobots(f) {
  const ul = $("robots");
  const ids = f.robots.map((r) => String(r.id));
  [...ul.children].forEach((li) => { if (!ids.includes(li.dataset.id)) li.remove(); });
  f.robots.forEach((r, k) => {
    let li = $("robot-" + r.id);
    if (!li) { li = document.createElement("li"); li.id = "robot-" + r.id; li.dataset.id = r.id; }
    if (ul.children[k] !== li) ul.insertBefore(li, ul.children[k] || null);
    const cls = r.mode + (state.selected === r.id ? " selected" : "");
    if (li.className !== cls) li.className = cls;
    const text = `${r.name}: ${r.mode}, ${r.task} (${r.x.toFixed(1)}, ${r.y.toFixed(1)})`;
    if (li.textContent !== text) li.textContent = text;
  });
}

function renderVictims(f) {
  const html = f.victims.map((v) =>
    `<li class="victim-${v.status}" data-x="${v.x}" data-y="${v.y}">${v.status} at (${v.x.toFixed(1)}, ${v.y.toFixed(1)})` +
    (v.probability != null ? `, p = ${v.probability.toFixed(2)}` : "") + "</li>").join("");
  if ($("victims").innerHTML !== html) $("victims").innerHTML = html;
}

// One card per hand-off, in the desk's order (the one being answered first). A card is made
// when its hand-off appears and removed once it is answered, never rebuilt while it shows: a
// question arriving behind it does not replace the button a person is about to click. A stuck
// robot's card is updated in place as the robot is driven.
function handoffCard(h) {
  const card = document.createElement("div");
  card.id = "handoff-" + h.id;
  if (h.kind === "victim") {
    card.className = "handoff victim";
    card.innerHTML = `Robot ${h.robot}: possible victim at ` +
      `(${h.x.toFixed(1)}, ${h.y.toFixed(1)}), p = ${h.probability.toFixed(2)}, ${h.size_m2.toFixed(3)} m²<br>` +
      `<img src="${h.thermal}" alt="thermal region" title="thermal region">` +
      `<img src="${h.depth}" alt="depth profile" title="depth profile ahead"><br>` +
      `<button class="confirm" data-id="${h.id}">Confirm victim</button>` +
      `<button class="reject" data-id="${h.id}">Reject</button>`;
  } else {
    card.className = "handoff stuck";
    card.innerHTML = `<span class="why"></span> <button class="take" data-robot="${h.robot}">Take over</button>`;
  }
  return card;
}

function renderHandoffs(f) {
  const div = $("handoffs");
  const shown = new Set(f.handoffs.map((h) => "handoff-" + h.id));
  [...div.children].forEach((c) => { if (!shown.has(c.id)) c.remove(); });
  if (!f.handoffs.length) {
    if (!div.children.length) div.innerHTML = '<p class="empty">none</p>';
    return;
  }
  f.handoffs.forEach((h, k) => {
    const card = $("handoff-" + h.id) || handoffCard(h);
    if (div.children[k] !== card) div.insertBefore(card, div.children[k] || null);
    if (h.kind !== "stuck") return;
    const why = h.reason === "no progress"
      ? "has driven without exploring anything new; drive it (arrow keys) until it explores again"
      : "cannot make its commands take effect; drive it (arrow keys) until one does";
    const text = `Robot ${h.robot} at (${h.x.toFixed(1)}, ${h.y.toFixed(1)}) ${why}.` +
      (h.suggested ? ` Its exploration would head ${h.suggested}.` : "");
    const span = card.querySelector(".why");
    if (span.textContent !== text) span.textContent = text;
    card.dataset.reason = h.reason || "";
    card.dataset.suggested = h.suggested || "";
  });
}

// The map layers (team grid and labels, MAXQ cell map, BTM) change only with a map message:
// they are drawn once into this canvas, and every frame copies it under victims and robots.
const layers = document.createElement("canvas");

function drawLayers() {
  const c = $("map"), t = transform(), m = state.map;
  layers.width = c.width;
  layers.height = c.height;
  const g = layers.getContext("2d");
  g.fillStyle = "#0c0d10";
  g.fillRect(0, 0, c.width, c.height);
  if (!t) return;
  const px = m.resolution_m * t.scale, showLabels = $("layer-labels").checked;
  for (let r = 0; r < m.height; r++) {
    for (let q = 0; q < m.width; q++) {
      const i = r * m.width + q, v = state.cells[i];
      if (!v) continue;
      const [x, y] = t.toPx(m.origin[0] + q * m.resolution_m, m.origin[1] + (r + 1) * m.resolution_m);
      g.fillStyle = v === 1 ? "#8a8f99" : "#101010";
      g.fillRect(x, y, px + 0.5, px + 0.5);
      if (showLabels && v === 1 && state.labels[i]) {
        g.fillStyle = LABEL_TINT[state.labels[i]];
        g.fillRect(x, y, px + 0.5, px + 0.5);
      }
    }
  }
  if ($("layer-cells").checked && m.cell_cols) {
    const s = m.cell_size_m * t.scale;
    for (let r = 0; r < m.cell_rows; r++) {
      for (let q = 0; q < m.cell_cols; q++) {
        const v = state.cellMap[r * m.cell_cols + q];
        if (!v) continue;
        const [x, y] = t.toPx(m.cell_origin[0] + q * m.cell_size_m, m.cell_origin[1] + (r + 1) * m.cell_size_m);
        g.fillStyle = CELL_COLOURS[v];
        g.fillRect(x + 1, y + 1, s - 2, s - 2);
      }
    }
  }
  if ($("layer-btm").checked) {
    const nodes = new Map(m.btm_nodes.map((n) => [n.id, n]));
    g.lineWidth = 1.5;
    for (const l of m.btm_links) {
      const a = nodes.get(l.start);
      if (!a) continue;
      const b = l.end != null ? nodes.get(l.end) : null;
      const [x0, y0] = t.toPx(a.x, a.y);
      const [x1, y1] = b ? t.toPx(b.x, b.y) : t.toPx(a.x + 0.8 * Math.cos(l.direction_rad), a.y + 0.8 * Math.sin(l.direction_rad));
      g.strokeStyle = l.searched ? "rgba(80,220,255,0.8)" : "rgba(255,255,255,0.5)";
      g.setLineDash(l.searched ? [] : [4, 3]);
      g.beginPath(); g.moveTo(x0, y0); g.lineTo(x1, y1); g.stroke();
    }
    g.setLineDash([]);
    for (const n of m.btm_nodes) {
      const [x, y] = t.toPx(n.x, n.y);
      g.fillStyle = BTM_COLOURS[n.kind] || "#ccc";
      g.beginPath(); g.arc(x, y, 3.5, 0, 2 * Math.PI); g.fill();
    }
  }
}

function drawMap() {
  const c = $("map"), g = c.getContext("2d"), t = transform(), f = state.frame;
  if (layers.width !== c.width || layers.height !== c.height) drawLayers();
  g.drawImage(layers, 0, 0);
  if (!t || !f) return;
  for (const v of f.victims) {
    const [x, y] = t.toPx(v.x, v.y);
    g.fillStyle = v.status === "tagged" ? "#3f3" : v.status === "dismissed" ? "#777" : "#fd3";
    g.beginPath(); g.arc(x, y, 6, 0, 2 * Math.PI); g.fill();
    g.strokeStyle = "#000"; g.stroke();
  }
  for (const r of f.robots) {
    const [x, y] = t.toPx(r.x, r.y);
    if (r.goal) {
      const [gx, gy] = t.toPx(r.goal[0], r.goal[1]);
      g.strokeStyle = "rgba(255,255,255,0.35)"; g.setLineDash([3, 3]);
      g.beginPath(); g.moveTo(x, y); g.lineTo(gx, gy); g.stroke(); g.setLineDash([]);
    }
    g.save();
    g.translate(x, y);
    g.rotate(-r.theta);
    g.fillStyle = { maxq: "#ff9c1a", team: "#3da5ff", btm: "#4cf08a" }[r.kind] || "#3da5ff";
    g.beginPath(); g.moveTo(10, 0); g.lineTo(-7, 6); g.lineTo(-7, -6); g.closePath(); g.fill();
    g.lineWidth = r.mode === "operator" ? 3 : 1;
    g.strokeStyle = r.mode === "operator" ? "#ff3030" : state.selected === r.id ? "#fff" : "#000";
    g.stroke();
    g.restore();
    g.fillStyle = "#fff";
    g.fillText(String(r.id), x + 8, y - 8);
  }
}

function drawChart() {
  const c = $("chart"), g = c.getContext("2d"), s = (state.map && state.map.explored) || [];
  g.fillStyle = "#111"; g.fillRect(0, 0, c.width, c.height);
  if (s.length < 2) return;
  const tMax = s[s.length - 1][0] || 1, aMax = Math.max(...s.map((p) => p[1]), 1);
  g.strokeStyle = "#6cf"; g.lineWidth = 2; g.beginPath();
  s.forEach((p, i) => {
    const x = 30 + (c.width - 40) * p[0] / tMax, y = c.height - 20 - (c.height - 30) * p[1] / aMax;
    if (i) g.lineTo(x, y); else g.moveTo(x, y);
  });
  g.stroke();
  g.fillStyle = "#aaa";
  g.fillText(aMax.toFixed(0) + " m²", 2, 12);
  g.fillText(formatTime(tMax), c.width - 50, c.height - 5);
}

// --- Controls ---
$("pause").onclick = () => send({ type: "pause" });
$("resume").onclick = () => send({ type: "resume" });
$("speed-select").onchange = (e) => send({ type: "speed", factor: Number(e.target.value) });
$("apply-weights").onclick = () => send({ type: "weights", w_l: Number($("w_l").value), w_p: Number($("w_p").value), w_q: Number($("w_q").value) });
$("hypothesis").onchange = (e) => send({ type: "hypothesis", name: e.target.value });
$("robots").onclick = (e) => {
  const li = e.target.closest("li");
  const r = li && state.frame && state.frame.robots.find((x) => x.id === Number(li.dataset.id));
  if (r && r.kind === "btm") { log("the BTM crawler follows paper 004's behaviours on its own"); return; }
  if (li) { state.selected = Number(li.dataset.id); log("selected robot " + state.selected); render(); }
};
$("handoffs").onclick = (e) => {
  const b = e.target.closest("button");
  if (!b) return;
  if (b.classList.contains("confirm") || b.classList.contains("reject")) {
    send({ type: "answer_victim", handoff: Number(b.dataset.id), tag: b.classList.contains("confirm") });
  } else if (b.classList.contains("take")) {
    state.selected = Number(b.dataset.robot);
    $("map").focus();
    log("took over robot " + state.selected);
  }
};
$("map").onclick = (e) => {
  const t = transform();
  if (!t || state.selected == null) return;
  const c = $("map"), rect = c.getBoundingClientRect();
  // Client pixels to canvas pixels (the canvas may be drawn at another size than its own).
  const [x, y] = t.toWorld((e.clientX - rect.left) * c.width / rect.width, (e.clientY - rect.top) * c.height / rect.height);
  send({ type: "send_to", robot: state.selected, x, y });
};
["layer-labels", "layer-cells", "layer-btm"].forEach((id) => { $(id).onchange = () => { drawLayers(); drawMap(); }; });

const KEYS = { ArrowUp: "forward", w: "forward", ArrowDown: "backward", s: "backward", ArrowLeft: "left", a: "left", ArrowRight: "right", d: "right" };
const held = new Set();
document.addEventListener("keydown", (e) => {
  if (e.target.tagName === "INPUT" || e.target.tagName === "SELECT") return;
  if (e.key === "Escape" && state.selected) { send({ type: "release", robot: state.selected }); return; }
  const command = KEYS[e.key];
  if (!command || state.selected == null) return;
  e.preventDefault();
  if (state.selected === 0) {
    // The MAXQ robot moves by cells: one command per key press.
    if (!e.repeat) send({ type: "drive", robot: 0, command });
  } else {
    held.add(command);
  }
});
document.addEventListener("keyup", (e) => { const c = KEYS[e.key]; if (c) held.delete(c); });

// Team robots: velocity from held keys or a gamepad, ten times a second.
let lastPad = {};
setInterval(() => {
  if (state.selected == null) return;
  let linear = 0, angular = 0;
  if (held.has("forward")) linear += 1;
  if (held.has("backward")) linear -= 0.5;
  if (held.has("left")) angular += 1;
  if (held.has("right")) angular -= 1;
  const pads = navigator.getGamepads ? navigator.getGamepads() : [];
  for (const pad of pads) {
    if (!pad) continue;
    const ax = pad.axes[0] || 0, ay = pad.axes[1] || 0;
    if (Math.abs(ay) > 0.15) linear = -ay;
    if (Math.abs(ax) > 0.15) angular = -ax;
    if (state.selected === 0) {
      // D-pad buttons 12-15 (standard mapping) as single cell commands.
      [[12, "forward"], [13, "backward"], [14, "left"], [15, "right"]].forEach(([b, c]) => {
        const pressed = pad.buttons[b] && pad.buttons[b].pressed;
        if (pressed && !lastPad[b]) send({ type: "drive", robot: 0, command: c });
        lastPad[b] = pressed;
      });
    }
  }
  if (state.selected !== 0 && (linear || angular)) send({ type: "teleop", robot: state.selected, linear, angular });
}, 100);

connect();
