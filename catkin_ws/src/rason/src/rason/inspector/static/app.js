// rason mind inspector: the page. Pushed events (server-sent) say what changed; the page then
// fetches the selected agent's mind state. Every text from the graph goes in with textContent.
"use strict";

const ui = {
  agents: new Map(),       // name -> {name, present, topic, namespace, first, last}
  drawPending: false,      // the agent list is redrawn once per frame, however many changes
  selected: null,          // agent name
  live: true,              // follow the newest state; false = stepping through the history
  step: 0,                 // counts history steps and returns to live: the newest one wins
  shown: null,             // the entry on screen {agent, index, first, last, state, ...}
  latest: {},              // agent -> {index, first}
  cache: {},               // agent -> Map(index -> entry): the states this page has seen
  fetching: false,
  refetch: false,
  now: null,               // ROS time, from the last push
  robots: null,
  cameraSeq: {},
};

const $ = (id) => document.getElementById(id);

function el(tag, attrs, ...children) {
  const node = document.createElement(tag);
  for (const [k, v] of Object.entries(attrs || {})) {
    if (k === "class") node.className = v; else node.setAttribute(k, v);
  }
  for (const child of children) {
    if (child === null || child === undefined) continue;
    node.append(child instanceof Node ? child : document.createTextNode(String(child)));
  }
  return node;
}

function fill(node, items, empty) {
  node.replaceChildren(...(items.length ? items : [el("li", {class: "empty"}, empty || "none")]));
}

// ---------------------------------------------------------------- events pushed by the server
function connect() {
  const source = new EventSource("/api/events");
  source.addEventListener("open", () => setConnection(true));
  source.addEventListener("error", () => setConnection(false));
  source.addEventListener("hello", (e) => {
    const data = JSON.parse(e.data);
    ui.now = data.now;
    setAgents(data.agents);
    drawRobots(data.robots);
  });
  // one agent at a time: a new or changed agent, or one that left
  source.addEventListener("agent", (e) => updateAgent(JSON.parse(e.data)));
  source.addEventListener("gone", (e) => {
    ui.agents.delete(JSON.parse(e.data).name);
    drawAgentsSoon();
  });
  source.addEventListener("mind", (e) => {
    const data = JSON.parse(e.data);
    noteLatest(data.agent, data.index, data.first);
    if (data.agent === ui.selected) {
      if (ui.live) loadLive(); else updateHistoryBar();
    }
  });
  source.addEventListener("robots", (e) => {
    const data = JSON.parse(e.data);
    ui.now = data.now;
    drawRobots(data);
    tick();
  });
  source.addEventListener("clock", (e) => { ui.now = JSON.parse(e.data).now; tick(); });
}

function setConnection(ok) {
  const node = $("connection");
  node.textContent = ok ? "live" : "disconnected: retrying…";
  node.className = ok ? "ok" : "bad";
}

function tick() {
  if (ui.now !== null) $("clock").textContent = `ROS time ${ui.now.toFixed(1)} s`;
  if (ui.shown && ui.live) renderActions(ui.shown);
}

// The newest state an agent is known to have. Pushed events and fetched states can arrive out of
// order (an "agents" event summarised before a newer "mind" event): the newest index seen wins,
// or stepping back from the state on screen could be taken for a step past the newest one.
function noteLatest(agent, index, first) {
  const known = ui.latest[agent];
  ui.latest[agent] = known ? {index: Math.max(known.index, index), first: Math.max(known.first, first)}
                           : {index, first};
}

// ---------------------------------------------------------------- agents
function setAgents(agents) {
  ui.agents = new Map();
  for (const a of agents) updateAgent(a);
  drawAgentsSoon();
}

function updateAgent(a) {
  if (a.last !== null && a.last !== undefined) noteLatest(a.name, a.last, a.first);
  if (a.present) ui.agents.set(a.name, a); else ui.agents.delete(a.name);
  drawAgentsSoon();
}

function drawAgentsSoon() {
  if (ui.drawPending) return;
  ui.drawPending = true;
  requestAnimationFrame(() => { ui.drawPending = false; drawAgents(); });
}

function drawAgents() {
  const agents = [...ui.agents.values()].sort((a, b) => (a.name < b.name ? -1 : a.name > b.name ? 1 : 0));
  const list = $("agent-list");
  list.replaceChildren(...agents.map((a) => {
    const item = el("li", {"data-agent": a.name, class: a.name === ui.selected ? "selected" : ""},
                    a.name, el("span", {class: "ns"}, a.topic ? a.namespace || "" : "no mind_state topic"));
    item.addEventListener("click", () => select(a.name));
    return item;
  }));
  $("no-agents").hidden = agents.length > 0;
  if (ui.selected === null && agents.length) select(agents[0].name);
}

function select(name) {
  ui.selected = name;
  ui.live = true;
  ui.shown = null;
  for (const li of $("agent-list").children) li.classList.toggle("selected", li.dataset.agent === name);
  $("mind-title").textContent = name;
  updateHistoryBar();   // "no state" until this agent's arrives: the bar never names another's
  loadLive();
}

// ---------------------------------------------------------------- mind states and history
async function fetchEntry(agent, index) {
  const cached = ui.cache[agent] && index !== null ? ui.cache[agent].get(index) : undefined;
  if (cached) return cached;
  const url = `/api/agents/${encodeURIComponent(agent)}/mind` + (index === null ? "" : `?index=${index}`);
  const response = await fetch(url, {cache: "no-store"});
  if (!response.ok) return null;
  const entry = await response.json();
  (ui.cache[agent] = ui.cache[agent] || new Map()).set(entry.index, entry);
  if (ui.cache[agent].size > 2000) ui.cache[agent].delete(ui.cache[agent].keys().next().value);
  noteLatest(agent, entry.last, entry.first);
  return entry;
}

async function loadLive() {
  // one request at a time; states that arrive meanwhile are fetched once it is done
  if (ui.fetching) { ui.refetch = true; return; }
  ui.fetching = true;
  try {
    do {
      ui.refetch = false;
      const agent = ui.selected;
      let entry = null;
      try { entry = await fetchEntry(agent, null); } catch (err) { entry = null; }
      if (entry && agent === ui.selected && ui.live) show(entry);
    } while (ui.refetch);
  } finally {
    ui.fetching = false;
  }
}

async function goTo(index) {
  // history mode starts when the state asked for is on screen, so the bar never names a state
  // that is not shown; a later step (or live) wins over this one if it comes first
  const agent = ui.selected;
  const latest = ui.latest[agent];
  if (!agent || !latest) return;
  if (index >= latest.index) { goLive(); return; }
  index = Math.max(index, latest.first);
  const step = ++ui.step;
  let entry = null;
  try { entry = await fetchEntry(agent, index); } catch (err) { entry = null; }
  if (step !== ui.step || agent !== ui.selected) return;
  if (entry) { ui.live = false; show(entry); } else updateHistoryBar();
}

function goLive() {
  ui.step++;
  ui.live = true;
  const agent = ui.selected;
  const latest = ui.latest[agent];
  const cached = latest && ui.cache[agent] && ui.cache[agent].get(latest.index);
  if (cached) show(cached);
  loadLive();
}

function updateHistoryBar() {
  const latest = ui.latest[ui.selected];
  const shown = ui.shown;
  const slider = $("history-slider");
  const label = $("history-label");
  $("mind").classList.toggle("history", !ui.live);
  $("history-live").classList.toggle("on", ui.live);
  if (!latest || !shown) {
    label.textContent = "no state"; label.dataset.index = ""; label.dataset.mode = "";
    $("history-back").disabled = $("history-forward").disabled = true;
    return;
  }
  slider.min = latest.first; slider.max = latest.index; slider.value = shown.index;
  $("history-back").disabled = shown.index <= latest.first;
  $("history-forward").disabled = ui.live;
  label.dataset.index = shown.index;
  label.dataset.mode = ui.live ? "live" : "history";
  const stamp = shown.state.stamp !== undefined ? ` · t=${Number(shown.state.stamp).toFixed(2)} s` : "";
  label.textContent = `${ui.live ? "live" : "history"} · state ${shown.index} of ` +
                      `${latest.first}…${latest.index}${stamp}`;
}

function show(entry) {
  ui.shown = entry;
  const state = entry.state;
  const mind = state.mind;
  $("mind-title").textContent = `${entry.agent}` + (state.node ? `  (node ${state.node})` : "");
  renderBeliefs(mind.beliefs || []);
  fill($("rules"), (mind.rules || []).map((r) => el("li", {class: "term"}, r)));
  renderIntentions(mind.intentions || []);
  fill($("events"), (mind.events || []).map((e) => el("li", {class: "term"}, e.trigger,
       e.intention !== null ? el("span", {class: "chip"}, `intention ${e.intention}`) : null)));
  fill($("desires"), (mind.desires || []).map((d) => el("li", {class: "term"}, d)));
  renderActions(entry);
  renderMessages($("messages-in"), state.messages_in || [], "from");
  renderMessages($("messages-out"), state.messages_out || [], "to");
  updateHistoryBar();
}

function renderBeliefs(beliefs) {
  const groups = new Map();
  for (const b of beliefs) {
    if (!groups.has(b.group)) groups.set(b.group, []);
    groups.get(b.group).push(b);
  }
  const node = $("beliefs");
  if (!groups.size) { node.replaceChildren(el("p", {class: "empty"}, "no beliefs")); return; }
  node.replaceChildren(...[...groups.keys()].sort().map((group) => {
    const items = groups.get(group).map((b) => el("li", {class: "belief term", "data-belief": b.text},
      b.text,
      ...b.annots.map((a) => el("span", {class: "chip"}, a)),
      ...b.sources.map((s) => el("span", {class: "chip source" + (s === "percept" ? " percept" : "")},
                                  `source(${s})`))));
    const details = el("details", {class: "group", open: ""},
                       el("summary", {}, `${group} (${items.length})`), el("ul", {}, ...items));
    return details;
  }));
}

function renderIntentions(intentions) {
  const node = $("intentions");
  if (!intentions.length) { node.replaceChildren(el("p", {class: "empty"}, "no intentions")); return; }
  node.replaceChildren(...intentions.map((i) => el("div", {class: "intention", "data-intention": i.id},
    el("div", {class: "head"}, `intention ${i.id}`,
       el("span", {class: "state"}, i.suspended ? `waiting: ${i.suspended}` : "running")),
    ...i.means.map((m, k) => el("div", {class: "means" + (k === 0 ? " top" : "")},
      el("div", {}, el("span", {class: "trigger term"}, m.trigger), el("span", {class: "where"}, m.where)),
      el("div", {class: "term"}, m.plan),
      el("ol", {class: "term"}, ...m.body.map((s) => el("li", {class: s.step}, s.text))),
      m.doing && !m.body.some((s) => s.step === "current" && s.text === m.doing)
        ? el("div", {class: "term"}, "inside the block: ", m.doing) : null,
      Object.keys(m.unifier).length
        ? el("div", {class: "unifier term"},
             "{ " + Object.entries(m.unifier).map(([k, v]) => `${k}=${v}`).join(", ") + " }")
        : null)))));
}

function renderActions(entry) {
  const state = entry.state;
  const now = ui.live && ui.now !== null ? ui.now : state.stamp;
  fill($("actions"), (state.actions || []).map((a) => {
    const age = now !== undefined && now !== null ? `${Math.max(0, now - a.sent_at).toFixed(1)} s` : "";
    return el("li", {class: "term"}, `${a.id}: ${a.text}`, el("span", {class: "chip"}, age),
              a.accepted_at === null ? el("span", {class: "chip"}, "not yet accepted") : null);
  }));
}

function renderMessages(table, messages, direction) {
  const rows = messages.slice().reverse().map((m) => el("tr", {},
    el("td", {}, Number(m.time).toFixed(2)),
    el("td", {}, direction === "from" ? m.sender : (m.receiver || "all")),
    el("td", {}, m.performative),
    el("td", {class: "term"}, m.content)));
  table.replaceChildren(...(rows.length ? rows : [el("tr", {}, el("td", {class: "empty"}, "none"))]));
}

// ---------------------------------------------------------------- robots
const COLORS = ["#2563eb", "#dc2626", "#059669", "#7c3aed", "#d97706", "#0891b2"];
const ROBOT_RADIUS = 0.177;   // Kobuki base (m)
const SEEN = /^robot\(([^,()]+),(-?[\d.]+),(-?[\d.]+),(-?[\d.]+)\)$/;

function drawRobots(view) {
  if (!view) return;
  ui.robots = view;
  const names = Object.keys(view.robots);
  const color = (name) => COLORS[names.indexOf(name) % COLORS.length];
  const seen = [];
  for (const name of names) {
    const r = view.robots[name];
    const observer = (r.truth || r.odom || {}).pose;
    for (const [source, list] of Object.entries(r.perceptions)) {
      for (const text of list) {
        const m = SEEN.exec(text.replace(/\s/g, ""));
        const item = {observer: name, source, text};
        if (m && observer) {
          const angle = Number(m[2]) * Math.PI / 180, depth = Number(m[3]);
          const fx = depth, fy = -depth * Math.tan(angle);       // forward, left (right = +angle)
          const c = Math.cos(observer.yaw), s = Math.sin(observer.yaw);
          item.at = [observer.x + c * fx - s * fy, observer.y + s * fx + c * fy];
          item.from = [observer.x, observer.y];
          item.yaw = observer.yaw - (Number(m[4]) - Number(m[2])) * Math.PI / 180;
          item.label = `${m[1]}: ${Math.abs(Number(m[2])).toFixed(1)}° ${Number(m[2]) >= 0 ? "right" : "left"}, ` +
                       `depth ${depth.toFixed(2)} m, yaw ${Number(m[4]).toFixed(1)}°`;
        }
        seen.push(item);
      }
    }
  }
  const robotColor = (name) => (names.includes(name) ? color(name) : "#6b7280");
  drawMap(view, names, color, seen, robotColor);
  drawMissions(view.missions || {}, robotColor);
  fill($("seen"), seen.map((s) => el("li", {class: "term"}, `${s.observer} sees `, s.label || s.text,
                                     el("span", {class: "chip"}, s.source))),
       "no perception from a synthesizer");
  drawCameras(view);
  fill($("diagnostics"), (view.diagnostics || []).map((d) => el("li", {class: `level-${d.level}`},
    `${d.name}: ${d.message}`, ...Object.entries(d.values).filter(([k]) => k === "fault")
      .map(([k, v]) => el("span", {class: "chip"}, `${k}=${v}`)))),
    "no /diagnostics yet");
}

// A robot's odometry starts at its own origin: put it on the map where the simulator's ground
// truth was when the inspector saw both first, so the two paths start together and drift apart.
function anchored(robot) {
  const odom = robot.odom, truth = robot.truth;
  if (!odom || !truth) return odom;
  const turn = truth.first.yaw - odom.first.yaw;
  const c = Math.cos(turn), s = Math.sin(turn);
  const move = ([x, y]) => {
    const dx = x - odom.first.x, dy = y - odom.first.y;
    return [truth.first.x + c * dx - s * dy, truth.first.y + s * dx + c * dy];
  };
  const [px, py] = move([odom.pose.x, odom.pose.y]);
  return {pose: {x: px, y: py, yaw: odom.pose.yaw + turn}, trail: odom.trail.map(move)};
}

// What an agent's beliefs say of its mission (the server reads waypoint/3, reached/2,
// delegated/1, recovery/1...: rason.inspector.mission): one line per waypoint and the recovery.
function drawMissions(missions, robotColor) {
  const box = $("missions");
  const agents = Object.keys(missions);
  if (!agents.length) {
    box.replaceChildren(el("p", {class: "empty"}, "no agent believes it has a mission"));
    return;
  }
  box.replaceChildren(...agents.map((agent) => {
    const m = missions[agent];
    const state = m.done ? "completed" : m.gave_up !== null ? `given up: ${m.gave_up}` : "under way";
    const recovery = m.recovery === null ? "no recovery in force"
      : `recovery in force: ${m.recovery}` + (m.diagnosis !== null ? ` (diagnosis ${m.diagnosis})` : "");
    const delegation = m.delegated_to === null ? null
      : el("span", {class: "chip"}, `delegated to ${m.delegated_to}` + (m.accepted ? ", accepted" : ", offered"));
    const items = m.waypoints.map((p) => {
      const where = `waypoint ${p.index} (${p.x}, ${p.y}): `;
      const who = p.reached_by !== null ? `reached by ${p.reached_by}`
        : p.assigned_to !== null ? `${p.assigned_to}'s` + (p.current ? ", driving to it" : "")
        : "nobody's";
      const kind = p.reached_by !== null ? "reached" : p.assigned_to === null ? "nobody" : p.current ? "current" : "";
      const item = el("li", {class: `term ${kind}`, "data-waypoint": p.index,
                             "data-reached-by": p.reached_by || "", "data-assigned-to": p.assigned_to || ""},
                      where, who);
      item.style.borderLeft = `4px solid ${robotColor(p.reached_by || p.assigned_to || "")}`;
      item.style.paddingLeft = "4px";
      return item;
    });
    return el("div", {class: "mission", "data-agent": agent, "data-recovery": m.recovery || ""},
              el("div", {}, el("b", {}, `${agent}'s mission`), ` · ${state}`, delegation),
              el("div", {class: "recovery"}, recovery),
              el("ul", {class: "plain"}, ...items));
  }));
}

function drawMap(view, names, color, seen, robotColor) {
  const canvas = $("map");
  const ctx = canvas.getContext("2d");
  const waypoints = Object.values(view.missions || {}).flatMap((m) => m.waypoints);
  const points = waypoints.map((p) => [p.x, p.y]);
  for (const name of names) {
    for (const track of [view.robots[name].truth, anchored(view.robots[name])]) {
      if (!track) continue;
      points.push([track.pose.x, track.pose.y], ...track.trail);
    }
  }
  for (const s of seen) if (s.at) points.push(s.at);
  ctx.clearRect(0, 0, canvas.width, canvas.height);
  if (!points.length) {
    ctx.fillStyle = "#9ca3af"; ctx.font = "14px sans-serif";
    ctx.fillText("no odometry yet", 20, 30);
    return;
  }
  let [minX, minY, maxX, maxY] = [Infinity, Infinity, -Infinity, -Infinity];
  for (const [x, y] of points) {
    minX = Math.min(minX, x); maxX = Math.max(maxX, x); minY = Math.min(minY, y); maxY = Math.max(maxY, y);
  }
  const span = Math.max(maxX - minX, maxY - minY, 2.5) + 1.0;
  const cx = (minX + maxX) / 2, cy = (minY + maxY) / 2;
  const scale = Math.min(canvas.width, canvas.height) / span;
  // world x to the right, world y up
  const px = (x, y) => [canvas.width / 2 + (x - cx) * scale, canvas.height / 2 - (y - cy) * scale];

  ctx.strokeStyle = "#ebe7df"; ctx.lineWidth = 1;
  const step = 0.5;
  for (let gx = Math.floor((cx - span) / step) * step; gx <= cx + span; gx += step) {
    const [a] = px(gx, 0); ctx.beginPath(); ctx.moveTo(a, 0); ctx.lineTo(a, canvas.height); ctx.stroke();
  }
  for (let gy = Math.floor((cy - span) / step) * step; gy <= cy + span; gy += step) {
    const [, b] = px(0, gy); ctx.beginPath(); ctx.moveTo(0, b); ctx.lineTo(canvas.width, b); ctx.stroke();
  }
  ctx.fillStyle = "#6b7280"; ctx.font = "11px sans-serif";
  ctx.fillText(`grid ${step} m · x →, y ↑`, 6, canvas.height - 6);

  for (const p of waypoints) {
    const [a, b] = px(p.x, p.y);
    const who = p.reached_by || p.assigned_to;
    ctx.strokeStyle = who ? robotColor(who) : "#b91c1c";
    ctx.lineWidth = p.current ? 3 : 1.5;
    ctx.setLineDash([3, 3]);
    ctx.beginPath(); ctx.arc(a, b, 0.3 * scale, 0, 2 * Math.PI); ctx.stroke();
    ctx.setLineDash([]);
    ctx.beginPath(); ctx.arc(a, b, 9, 0, 2 * Math.PI);
    if (p.reached_by) { ctx.fillStyle = robotColor(p.reached_by); ctx.fill(); }
    ctx.stroke();
    ctx.fillStyle = p.reached_by ? "#fff" : ctx.strokeStyle;
    ctx.font = "bold 11px sans-serif"; ctx.textAlign = "center"; ctx.textBaseline = "middle";
    ctx.fillText(String(p.index), a, b);
    ctx.textAlign = "start"; ctx.textBaseline = "alphabetic";
  }

  for (const name of names) {
    const r = view.robots[name];
    for (const [track, dashed] of [[r.truth, false], [anchored(r), true]]) {
      if (!track) continue;
      ctx.strokeStyle = color(name); ctx.lineWidth = dashed ? 1.5 : 2.5;
      ctx.setLineDash(dashed ? [6, 4] : []);
      ctx.beginPath();
      track.trail.forEach(([x, y], k) => { const [a, b] = px(x, y); k ? ctx.lineTo(a, b) : ctx.moveTo(a, b); });
      ctx.stroke();
      const p = track.pose;
      const [a, b] = px(p.x, p.y);
      ctx.beginPath(); ctx.arc(a, b, ROBOT_RADIUS * scale, 0, 2 * Math.PI);
      ctx.globalAlpha = dashed ? 0.15 : 0.3; ctx.fillStyle = color(name); ctx.fill(); ctx.globalAlpha = 1;
      ctx.stroke();
      const [hx, hy] = px(p.x + Math.cos(p.yaw) * ROBOT_RADIUS * 1.6, p.y + Math.sin(p.yaw) * ROBOT_RADIUS * 1.6);
      ctx.beginPath(); ctx.moveTo(a, b); ctx.lineTo(hx, hy); ctx.stroke();
      ctx.setLineDash([]);
      if (!dashed || !r.truth) {
        ctx.fillStyle = color(name); ctx.font = "bold 12px sans-serif";
        ctx.fillText(name, a + ROBOT_RADIUS * scale + 4, b - ROBOT_RADIUS * scale);
      }
    }
  }
  for (const s of seen) {
    if (!s.at) continue;
    const [a, b] = px(...s.from), [c, d] = px(...s.at);
    ctx.strokeStyle = "#d97706"; ctx.lineWidth = 1.5; ctx.setLineDash([2, 3]);
    ctx.beginPath(); ctx.moveTo(a, b); ctx.lineTo(c, d); ctx.stroke(); ctx.setLineDash([]);
    ctx.beginPath(); ctx.arc(c, d, 6, 0, 2 * Math.PI); ctx.stroke();
    const [e, f] = px(s.at[0] + Math.cos(s.yaw) * 0.3, s.at[1] + Math.sin(s.yaw) * 0.3);
    ctx.beginPath(); ctx.moveTo(c, d); ctx.lineTo(e, f); ctx.stroke();
  }
}

function drawCameras(view) {
  const box = $("cameras");
  for (const [name, r] of Object.entries(view.robots)) {
    if (!r.camera) continue;
    let figure = box.querySelector(`figure[data-robot="${CSS.escape(name)}"]`);
    if (!figure) {
      figure = el("figure", {"data-robot": name}, el("img", {alt: `${name}'s camera`}), el("figcaption", {}));
      figure.style.margin = "6px 0";
      box.append(figure);
    }
    const img = figure.querySelector("img");
    if (ui.cameraSeq[name] !== r.camera.seq && !img.dataset.loading) {
      ui.cameraSeq[name] = r.camera.seq;
      img.dataset.loading = "1";
      img.onload = img.onerror = () => { delete img.dataset.loading; };
      img.src = `/api/camera/${encodeURIComponent(name)}.jpg?seq=${r.camera.seq}`;
      figure.querySelector("figcaption").textContent =
        `${name}'s camera, frame at t=${Number(r.camera.stamp).toFixed(2)} s`;
    }
  }
}

// ---------------------------------------------------------------- controls
$("history-back").addEventListener("click", () => ui.shown && goTo(ui.shown.index - 1));
$("history-forward").addEventListener("click", () => ui.shown && goTo(ui.shown.index + 1));
$("history-live").addEventListener("click", goLive);
$("history-slider").addEventListener("input", (e) => goTo(Number(e.target.value)));
document.addEventListener("keydown", (e) => {
  if (e.target.tagName === "INPUT") return;
  if (e.key === "ArrowLeft" && ui.shown) goTo(ui.shown.index - 1);
  else if (e.key === "ArrowRight" && ui.shown) goTo(ui.shown.index + 1);
  else if (e.key === "End") goLive();
});
connect();
