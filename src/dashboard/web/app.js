// The dashboard page: log in, then one EventSource (server-sent events) that brings a
// snapshot of the cell and every change after it. No polling, no framework.
"use strict";

const components = new Map();  // uri -> component
const skills = new Map();      // key -> skill
let version = 0;
let events = null;
let scene = null;           // the world model's scene, when the dashboard has a world
let runs = null;            // the MES's last runs, when the dashboard reads its journal
let processes = null;       // the processes in the KB, when the dashboard reads it
const drafts = new Map();   // skill key -> the parameter typed for it (kept across renders)
const results = new Map();  // skill key -> {status, detail} of the last Start or Halt here

// Skills that need a parameter to start, and which: the MES's ExecuteProcess.
const parameterOf = { ExecuteProcessSkillType: "ProcessIri" };

const $ = (id) => document.getElementById(id);

function text(value) {
  return document.createTextNode(value === undefined || value === null ? "" : String(value));
}

function cell(...children) {
  const td = document.createElement("td");
  for (const c of children) td.append(typeof c === "string" ? text(c) : c);
  return td;
}

function badge(label, kind) {
  const span = document.createElement("span");
  span.className = "badge " + kind;
  span.textContent = label;
  return span;
}

function time(iso) {
  if (!iso) return "";
  const d = new Date(iso);
  return isNaN(d) ? iso : d.toLocaleTimeString([], { hour12: false }) + "." +
    String(d.getMilliseconds()).padStart(3, "0");
}

function renderComponents() {
  const body = $("components").tBodies[0];
  body.replaceChildren();
  const sorted = [...components.values()].sort((a, b) => a.uri.localeCompare(b.uri));
  for (const c of sorted) {
    const tr = document.createElement("tr");
    tr.dataset.uri = c.uri;
    tr.dataset.up = c.up ? "true" : "false";
    tr.className = c.up ? "up" : "down";
    const status = c.up ? badge("up", "up")
      : c.state === "connecting" ? badge("connecting", "")
        : badge("down" + (c.downReason ? ": " + c.downReason : ""), "down");
    const detection = (c.detectionMs >= 0 ? c.detectionMs.toFixed(0) + " ms" : "") +
      (c.paperMs > 0 ? ` (paper: ${c.paperMs} ms)` : "");
    tr.append(cell(c.uri), cell(status), cell(c.endpoint), cell(String(c.skills)),
              cell(time(c.detectedAt)), cell(detection));
    body.append(tr);
  }
  const up = sorted.filter((c) => c.up).length;
  $("component-count").textContent = `${up} up, ${sorted.length - up} down`;
}

function renderSkills() {
  const body = $("skills").tBodies[0];
  body.replaceChildren();
  const sorted = [...skills.values()].filter((s) => s.available)
    .sort((a, b) => (a.component + a.name).localeCompare(b.component + b.name));
  for (const s of sorted) {
    const tr = document.createElement("tr");
    tr.dataset.key = s.key;
    tr.dataset.state = s.state || "";
    tr.dataset.lastAt = s.transitions.length ? s.transitions[s.transitions.length - 1].at : "";
    const last = s.transitions.slice(-3).map((t) => `${t.from || "?"}→${t.to} ${time(t.at)}`).join(", ");
    const span = document.createElement("span");
    span.className = "transitions";
    span.textContent = last;
    const actions = document.createElement("span");
    const parameter = parameterOf[s.type];
    if (parameter) {
      const input = document.createElement("input");
      input.className = "parameter";
      input.placeholder = parameter;
      input.dataset.name = parameter;
      input.value = drafts.get(s.key) || "";
      input.addEventListener("input", () => drafts.set(s.key, input.value));
      actions.append(input);
    }
    for (const action of ["start", "halt"]) {
      const b = document.createElement("button");
      b.type = "button";
      b.className = "action " + action;
      b.dataset.action = action;
      b.textContent = action === "start" ? "Start" : "Halt";
      b.addEventListener("click", () => act(s, action, tr));
      actions.append(b);
    }
    const result = resultSpan(results.get(s.key));
    tr.append(cell(s.component), cell(s.name), cell(s.type),
              cell(badge(s.state || "unknown", s.state || "")), cell(span), cell(actions, result));
    body.append(tr);
  }
  $("skill-count").textContent = `${sorted.length} available`;
}

// Start, Halt or Reset, made by the dashboard as the logged-in user: the component's own
// role check decides (an Observer is refused). `parameters`: written before a Start.
async function call(key, action, parameters) {
  const form = new URLSearchParams({ key, action });
  for (const [name, value] of Object.entries(parameters || {})) form.set("param." + name, value);
  try {
    const r = await fetch("/api/skill", { method: "POST", body: form, credentials: "same-origin" });
    return await r.json();
  } catch (e) {
    return { status: "BadCommunicationError", detail: String(e) };
  }
}

async function act(skill, action, row) {
  const input = row.querySelector("input.parameter");
  const parameters = input && action === "start" ? { [input.dataset.name]: input.value } : {};
  results.set(skill.key, await call(skill.key, action, parameters));
  renderSkills();
}

function resultSpan(r) {
  const span = document.createElement("span");
  span.className = "result";
  if (!r) return span;
  span.dataset.status = r.status;
  span.textContent = r.status === "Good" ? r.detail + ": done" : "refused: " + r.status + " — " + r.detail;
  span.classList.add(r.status === "Good" ? "good" : "bad");
  return span;
}

// The MES's ExecuteProcess skill, which runs a process: the one the page starts and halts.
function mesSkill() {
  return [...skills.values()].find((s) => s.available && s.type === "ExecuteProcessSkillType");
}

let processResult = null;  // {iri, answer} of the last Run or Halt here

async function runProcess(iri, action) {
  const mes = mesSkill();
  if (!mes) return;
  const answer = await call(mes.key, action, action === "start" ? { ProcessIri: iri } : {});
  processResult = { iri, answer };
  renderProcesses();
}

// The run of `iri` in the journal that is the newest, for the progress column.
function lastRunOf(iri) {
  if (!runs) return null;
  return [...runs].reverse().find((r) => r.process === iri) || null;
}

function renderProcesses() {
  $("processes-section").hidden = !processes;
  if (!processes) return;
  const mes = mesSkill();
  $("mes-state").textContent = mes ? `· the MES is ${mes.state || "unknown"}` : "· no MES in the cell";
  $("mes-state").dataset.state = mes ? mes.state : "";
  const body = $("processes").tBodies[0];
  body.replaceChildren();
  for (const p of processes) {
    const tr = document.createElement("tr");
    tr.dataset.process = p.iri;
    const name = document.createElement("span");
    name.textContent = localName(p.iri);
    name.title = p.iri;
    const steps = p.problem ? badge(p.problem, "down") : text(p.steps.map((t, i) => `${i + 1} ${t}`).join(" → "));
    const run = lastRunOf(p.iri);
    const progress = document.createElement("span");
    progress.className = "progress";
    if (run) {
      const done = new Set(run.steps.filter((s) => s.state === "finished").map((s) => s.index)).size;
      progress.dataset.run = run.id;
      progress.dataset.state = run.state;
      progress.textContent = `run ${run.id}: ${run.state}, ${done}/${p.steps.length} steps` +
        (run.reason ? ` (${run.reason})` : "");
    }
    const actions = document.createElement("span");
    const buttons = [["start", "Run"], ["halt", "Halt"]];
    if (mes && mes.state === "Halted") buttons.push(["reset", "Reset MES"]);
    for (const [action, label] of buttons) {
      const b = document.createElement("button");
      b.type = "button";
      b.className = "action " + action;
      b.dataset.action = action;
      b.textContent = label;
      // Run only when the MES is Ready for it (its state known, no run going on).
      const ready = mes && mes.state === "Ready";
      b.disabled = !mes || (action === "start" && (!!p.problem || !ready));
      b.title = !mes ? "no MES in the cell"
        : action === "start" && !ready ? `the MES is ${mes.state || "not known yet"}` : "";
      b.addEventListener("click", () => runProcess(p.iri, action));
      actions.append(b);
    }
    const r = processResult && processResult.iri === p.iri ? processResult.answer : null;
    tr.append(cell(name), cell(steps), cell(progress), cell(actions, resultSpan(r)));
    body.append(tr);
  }
}

const SVG = "http://www.w3.org/2000/svg";

function svg(name, attributes, label) {
  const e = document.createElementNS(SVG, name);
  for (const [k, v] of Object.entries(attributes)) e.setAttribute(k, v);
  if (label !== undefined) e.textContent = label;
  return e;
}

// The scene from above: x to the right, y up, fitted to the picture with a margin.
function renderScene() {
  $("scene-section").hidden = !scene;
  if (!scene) return;
  const picture = $("scene");
  picture.replaceChildren();
  const W = 640, H = 420, margin = 0.15;
  const rails = scene.rails || [];
  const fuseSlots = scene.fuseSlots || [];
  const robots = scene.robots || [];
  const points = [[0, 0], ...robots.flatMap((r) => [r.base, r.flange]),
                  ...scene.objects.map((o) => o.position),
                  ...scene.docks.map((d) => d.position),
                  ...rails.flatMap((r) => [r.start, r.end]),
                  ...fuseSlots.map((f) => f.position)];
  const xs = points.map((p) => p[0]), ys = points.map((p) => p[1]);
  const minX = Math.min(...xs) - margin, maxX = Math.max(...xs) + margin;
  const minY = Math.min(...ys) - margin, maxY = Math.max(...ys) + margin;
  const scale = Math.min(W / (maxX - minX), H / (maxY - minY));
  const px = (x) => (x - minX) * scale;
  const py = (y) => H - (y - minY) * scale;
  picture.append(svg("rect", { x: 0, y: 0, width: W, height: H, class: "floor" }));
  for (const r of robots) {
    const base = svg("g", { class: "base", "data-robot": r.id });
    base.append(svg("circle", { cx: px(r.base[0]), cy: py(r.base[1]), r: 14 }),
                svg("text", { x: px(r.base[0]) + 18, y: py(r.base[1]) + 4 }, r.id));
    picture.append(base);
  }
  for (const d of scene.docks) {
    const g = svg("g", { class: "dock" + (d.tool ? " full" : ""), "data-dock": d.id, "data-tool": d.tool });
    g.append(svg("rect", { x: px(d.position[0]) - 16, y: py(d.position[1]) - 16, width: 32, height: 32 }),
             svg("text", { x: px(d.position[0]) + 20, y: py(d.position[1]) + 4 },
                 d.id + (d.tool ? ": " + d.tool : ": empty")));
    picture.append(g);
  }
  // A rail, and the blocks on it named along it in their order (they are too narrow to
  // label one by one).
  for (const r of rails) {
    const on = scene.objects.filter((o) => o.rail === r.id)
                            .sort((a, b) => a.railPosition - b.railPosition);
    const g = svg("g", { class: "rail", "data-rail": r.id,
                         "data-blocks": on.map((o) => o.id + "@" + (o.railPosition * 1000).toFixed(1)).join(" ") });
    g.append(svg("line", { x1: px(r.start[0]), y1: py(r.start[1]), x2: px(r.end[0]), y2: py(r.end[1]) }),
             svg("text", { x: px(r.start[0]), y: py(r.start[1]) - 14 },
                 r.id + (on.length ? ": " + on.map((o) => o.id + " at " + (o.railPosition * 1000).toFixed(1) + " mm").join(", ")
                                   : ": empty")));
    picture.append(g);
  }
  // A fuse box's slots, side by side: an outline each, filled when a fuse is seated, and one
  // label for the row (they are too close to label one by one).
  if (fuseSlots.length) {
    const box = svg("g", { class: "fuse-box",
                           "data-seated": fuseSlots.map((f) => f.id + ":" + f.fuse).join(" ") });
    for (const f of fuseSlots) {
      // An ATO slot's opening, 19 x 5 mm, at the picture's scale (a few pixels).
      const w = Math.max(6, 0.019 * scale), h = Math.max(2, 0.005 * scale);
      box.append(svg("rect", { class: "slot" + (f.fuse ? " full" : ""), "data-slot": f.id, "data-fuse": f.fuse,
                               x: px(f.position[0]) - w / 2, y: py(f.position[1]) - h / 2, width: w, height: h }));
    }
    const top = fuseSlots.reduce((a, f) => (f.position[1] > a.position[1] ? f : a));
    box.append(svg("text", { x: px(top.position[0]) + 16, y: py(top.position[1]) - 8 },
                   "fuse box: " + fuseSlots.map((f) => f.id + (f.fuse ? " " + f.fuse : " empty")).join(", ")));
    picture.append(box);
  }
  for (const o of scene.objects) {
    // A fuse seated in its slot is drawn as the slot, filled.
    if (fuseSlots.some((f) => f.fuse === o.id)) continue;
    const w = Math.max(3, o.size[0] * scale), h = Math.max(4, o.size[1] * scale);
    const held = robots.some((r) => r.graspedObject === o.id);
    const g = svg("g", { class: "object" + (held ? " held" : ""), "data-object": o.id,
                         "data-x": o.position[0].toFixed(3), "data-y": o.position[1].toFixed(3) });
    g.append(svg("rect", { x: px(o.position[0]) - w / 2, y: py(o.position[1]) - h / 2, width: w, height: h }));
    if (!o.rail) g.append(svg("text", { x: px(o.position[0]) + w / 2 + 4, y: py(o.position[1]) + 4 }, o.id));
    picture.append(g);
  }
  for (const r of robots) {
    const f = r.flange;
    const flange = svg("g", { class: "flange", "data-robot": r.id, "data-tool": r.mountedTool });
    flange.append(svg("circle", { cx: px(f[0]), cy: py(f[1]), r: 9 }),
                  svg("line", { x1: px(f[0]) - 13, y1: py(f[1]), x2: px(f[0]) + 13, y2: py(f[1]) }),
                  svg("line", { x1: px(f[0]), y1: py(f[1]) - 13, x2: px(f[0]), y2: py(f[1]) + 13 }),
                  svg("text", { x: px(f[0]) + 14, y: py(f[1]) - 12 },
                      r.id + "'s flange" + (r.mountedTool ? " with " + r.mountedTool : "") +
                      (r.graspedObject ? ", holding " + r.graspedObject : "")));
    picture.append(flange);
  }
}

function localName(iri) {
  const cut = Math.max(iri.lastIndexOf("/"), iri.lastIndexOf("#"));
  return cut < 0 ? iri : iri.slice(cut + 1);
}

let orderResults = new Map();  // order id -> the answer to this page's last action on it

async function cancelOrder(id) {
  const form = new URLSearchParams({ order: String(id), action: "cancel" });
  let answer;
  try {
    const r = await fetch("/api/order", { method: "POST", body: form, credentials: "same-origin" });
    answer = await r.json();
  } catch (e) {
    answer = { status: "BadCommunicationError", detail: String(e) };
  }
  orderResults.set(id, answer);
  renderRuns();
}

// Each order's run as a timeline: one lane per component, one bar per step attempt, newest
// first; an order not ended yet has a Cancel button (the MES checks the user's role).
function renderRuns() {
  $("runs-section").hidden = !runs || runs.length === 0;
  const box = $("runs");
  box.replaceChildren();
  if (!runs) return;
  for (const run of [...runs].reverse()) {
    const end = run.endedMs || Math.max(Date.now(), ...run.steps.map((s) => s.endedMs || 0));
    const span = Math.max(1, end - run.startedMs);
    const div = document.createElement("div");
    div.className = "run";
    div.dataset.run = run.id;
    div.dataset.state = run.state;
    const title = document.createElement("h3");
    title.textContent = `order ${run.id}: ${localName(run.process)}, ${run.state}` +
      (run.priority ? `, priority ${run.priority}` : "") +
      (run.endedMs ? ` in ${((run.endedMs - run.startedMs) / 1000).toFixed(1)} s` : "") +
      (run.reason ? ` (${run.reason})` : "");
    div.append(title);
    if (run.state === "queued" || run.state === "running") {
      const b = document.createElement("button");
      b.type = "button";
      b.className = "action cancel";
      b.dataset.action = "cancel";
      b.textContent = "Cancel order";
      b.addEventListener("click", () => cancelOrder(run.id));
      title.append(" ", b);
    }
    if (orderResults.has(run.id)) title.append(" ", resultSpan(orderResults.get(run.id)));
    const lanes = [...new Set(run.steps.map((s) => s.component))];
    const W = 1100, left = 260, laneH = 24;
    const picture = svg("svg", { width: W, height: lanes.length * laneH + 8, class: "timeline" });
    lanes.forEach((c, i) => {
      picture.append(svg("text", { x: 4, y: i * laneH + 17, class: "lane" }, c));
    });
    const x = (ms) => left + ((ms - run.startedMs) / span) * (W - left - 8);
    for (const s of run.steps) {
      const lane = lanes.indexOf(s.component);
      const from = x(s.startedMs), to = x(s.endedMs || end);
      const g = svg("g", { class: "step " + s.state, "data-step": s.index, "data-state": s.state });
      const title = svg("title", {}, `step ${s.index} (attempt ${s.attempt}) ${s.skillType} on ${s.component}: ` +
        `${s.state}` + (s.endedMs ? `, ${s.endedMs - s.startedMs} ms` : "") + (s.reason ? ` - ${s.reason}` : "") +
        (s.note ? ` (${s.note})` : ""));
      g.append(title, svg("rect", { x: from, y: lane * laneH + 4, width: Math.max(2, to - from), height: laneH - 8 }),
               svg("text", { x: from + 3, y: lane * laneH + 17 }, `${s.index} ${s.skillType}`));
      picture.append(g);
    }
    div.append(picture);
    box.append(div);
  }
}

function apply(event) {
  if (event.type === "snapshot") {
    components.clear();
    skills.clear();
    for (const c of event.components) components.set(c.uri, c);
    for (const s of event.skills) skills.set(s.key, s);
    scene = event.scene || null;
    runs = event.runs || null;
    processes = event.processes || null;
  } else if (event.version <= version) {
    return;  // heard already (a snapshot includes it)
  } else if (event.type === "component") {
    components.set(event.component.uri, event.component);
  } else if (event.type === "skill") {
    skills.set(event.skill.key, event.skill);
  } else if (event.type === "scene") {
    scene = event.scene;
  } else if (event.type === "runs") {
    runs = event.runs;
  } else if (event.type === "processes") {
    processes = event.processes;
  }
  version = event.version;
  renderComponents();
  renderSkills();
  renderScene();
  renderRuns();
  renderProcesses();
}

function listen() {
  if (events) events.close();
  events = new EventSource("/events");
  events.onopen = () => { $("cell-state").textContent = "live"; };
  events.onmessage = (m) => apply(JSON.parse(m.data));
  events.onerror = async () => {
    $("cell-state").textContent = "reconnecting";
    // A session that ended (logout elsewhere, a restarted dashboard) shows the login again.
    const me = await fetch("/api/me", { credentials: "same-origin" });
    if (me.status === 401) { events.close(); showLogin(); }
  };
}

function showCell(me) {
  $("login").hidden = true;
  $("login-error").textContent = "";
  $("login-password").value = "";
  $("cell").hidden = false;
  $("who").hidden = false;
  $("user").textContent = `${me.user} (${me.roles.join(", ")})`;
  listen();
}

function showLogin(message) {
  $("cell").hidden = true;
  $("who").hidden = true;
  $("login").hidden = false;
  $("cell-state").textContent = "";
  $("login-error").textContent = message || "";
}

async function start() {
  $("login").addEventListener("submit", async (e) => {
    e.preventDefault();
    const form = new URLSearchParams({ user: $("login-user").value, password: $("login-password").value });
    const r = await fetch("/login", { method: "POST", body: form, credentials: "same-origin" });
    if (r.ok) {
      showCell(await r.json());
    } else if (r.status === 429) {
      showLogin(`Too many wrong passwords for this user: try again in ${r.headers.get("Retry-After")} s.`);
    } else {
      showLogin("Wrong user or password.");
    }
  });
  $("logout").addEventListener("click", async () => {
    if (events) events.close();
    await fetch("/logout", { method: "POST", credentials: "same-origin" });
    showLogin();
  });
  const me = await fetch("/api/me", { credentials: "same-origin" });
  if (me.ok) showCell(await me.json()); else showLogin();
}

start();
