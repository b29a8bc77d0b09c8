// The viewer page: connects to the station's event stream (a snapshot, then a delta per backend
// round), draws the chosen round, and holds the view in the URL (#round=R&node=ID).
import "./style.css";
import { robotCss } from "./colours";
import { parseMesh } from "./mesh";
import type { ViewerMesh } from "./mesh";
import { DEFAULT_HEIGHT, SCENE_LAYERS, SceneView, robotOf } from "./scene";
import type { ColourMode, SceneLayer } from "./scene";
import { applyDelta, emptyView, nodes } from "./view";
import type { Delta, LayerName, NodeRow, RobotInfo, View } from "./view";
import { drawLineChart } from "./charts";

const $ = <T extends HTMLElement>(id: string) => document.getElementById(id) as T;

interface RoundSummary {
  seq: number;
  round: number;
  final: boolean;
  info: Record<string, number>;
  robots: Record<string, RobotInfo>;
}

const scene = new SceneView($("view"));
let live: View = emptyView();
let shown: View | null = null;
let follow = true;
let summaries: RoundSummary[] = [];
let links: Record<string, RobotInfo> = {};
let linksAt = 0;
let ended = false;
let meshSeq = -1;
let meshFetching = false;
let lastMeshFetch = 0;
let selected: string | null = null;
const shownAt: { seq: number; receivedMs: number; drawnMs: number; publishedMs: number }[] = [];

// --- layers panel ---
const LAYER_TITLES: Record<SceneLayer, string> = {
  mesh: "mesh", agents: "agents", objects: "objects", places: "places", rooms: "rooms",
  buildings: "building", edges: "edges", loop_closures: "loop closures", merges: "merges",
};
const countCells = new Map<SceneLayer, HTMLElement>();
for (const layer of SCENE_LAYERS) {
  const row = document.createElement("div");
  row.className = "layer-row";
  const toggle = document.createElement("input");
  toggle.type = "checkbox";
  toggle.checked = true;
  toggle.id = `toggle-${layer}`;
  toggle.addEventListener("change", () => scene.setLayerVisible(layer, toggle.checked));
  const name = document.createElement("label");
  name.htmlFor = toggle.id;
  name.textContent = LAYER_TITLES[layer];
  row.append(toggle, name);
  if (layer in DEFAULT_HEIGHT) {
    const slider = document.createElement("input");
    slider.type = "range";
    slider.min = "0";
    slider.max = "30";
    slider.step = "0.5";
    slider.id = `height-${layer}`;
    slider.value = String(DEFAULT_HEIGHT[layer as LayerName | "mesh"]);
    slider.title = "height (m)";
    slider.addEventListener("input", () => scene.setLayerHeight(layer as LayerName | "mesh", Number(slider.value)));
    row.append(slider);
  } else {
    row.append(document.createElement("span"));
  }
  const count = document.createElement("span");
  count.className = "count";
  count.id = `count-${layer}`;
  row.append(count);
  countCells.set(layer, count);
  $("layer-rows").append(row);
}

$<HTMLSelectElement>("colour").addEventListener("change", (e) =>
  scene.setColourMode((e.target as HTMLSelectElement).value as ColourMode),
);

// --- rounds: the time slider, follow live, the URL ---
const slider = $<HTMLInputElement>("round");
const followBox = $<HTMLInputElement>("follow");
followBox.addEventListener("change", () => {
  follow = followBox.checked;
  if (follow) show(live);
});
slider.addEventListener("input", () => {
  follow = Number(slider.value) >= live.seq && !ended ? follow : false;
  followBox.checked = follow;
  void showSeq(Number(slider.value));
});

async function showSeq(seq: number): Promise<void> {
  if (seq === live.seq) return show(live);
  const response = await fetch(`api/view?seq=${seq}`);
  if (!response.ok) return;
  const view = applyDelta(emptyView(), (await response.json()) as Delta);
  if (Number(slider.value) === seq || !follow) show(view);
}

function show(view: View): void {
  shown = view;
  scene.setView(view);
  slider.value = String(view.seq);
  const summary = `round ${view.round} (view ${view.seq} of ${live.seq})${view.final ? ", final" : ""}`;
  $("round-text").textContent = summary;
  updateCounts(view);
  updateRobots();
  writeHash();
  if (selected) inspect(selected, focusPending === selected && !!scene.node(selected));
  if (focusPending && scene.node(focusPending)) focusPending = null;
}

function writeHash(): void {
  const parts: string[] = [];
  if (shown && !follow) parts.push(`round=${shown.round}`);
  if (selected) parts.push(`node=${encodeURIComponent(selected)}`);
  const hash = parts.length ? `#${parts.join("&")}` : "";
  if (location.hash !== hash) history.replaceState(null, "", hash || location.pathname + location.search);
}

function readHash(): { round?: number; node?: string } {
  const params = new URLSearchParams(location.hash.slice(1));
  const round = params.get("round");
  return { round: round === null ? undefined : Number(round), node: params.get("node") ?? undefined };
}

// --- counts ---
function updateCounts(view: View): void {
  const stats = scene.stats();
  for (const layer of SCENE_LAYERS) {
    const cell = countCells.get(layer)!;
    if (layer === "mesh") cell.textContent = String(Object.values(stats.meshFaces).reduce((a, b) => a + b, 0));
    else if (layer === "edges") cell.textContent = String(view.tables.edges.size);
    else if (layer === "loop_closures") cell.textContent = String(view.tables.loop_closures.size);
    else if (layer === "merges") cell.textContent = String(view.tables.merges.size);
    else cell.textContent = String(Object.values(stats.nodes[layer] ?? {}).reduce((a, b) => a + b, 0));
  }
  const lc = stats.loopClosures;
  $("closure-counts").innerHTML =
    `<div id="lc-intra">intra-robot: <b>${lc.intraKept}</b> kept, <b>${lc.intraRejected}</b> rejected</div>` +
    `<div id="lc-inter">inter-robot: <b>${lc.interKept}</b> kept, <b>${lc.interRejected}</b> rejected</div>` +
    `<div class="count">kept solid, rejected faded; inter-robot in white</div>`;
  const i = view.info;
  $("merge-counts").innerHTML =
    `<div id="merges-count"><b>${view.tables.merges.size}</b> made (${i.merges_accepted ?? 0} of ${i.merges_proposed ?? 0} proposed` +
    `${i.label_merges ? `, ${i.label_merges} by label votes` : ""}${i.merges_undone ? `, ${i.merges_undone} undone` : ""})</div>` +
    `<div class="count">rooms: ${i.rooms ?? 0}; backend round ${(i.time_s ?? 0).toFixed(2)} s</div>`;
}

// --- the robots' status strip ---
function updateRobots(): void {
  const view = shown ?? live;
  const strip = $("robots");
  strip.replaceChildren();
  const now = performance.now();
  for (const robot of Object.keys({ ...live.robots, ...view.robots }).sort()) {
    const r: RobotInfo = { ...view.robots[robot], ...(follow ? links[robot] : {}) };
    const silent = r.silent_s !== undefined ? r.silent_s + (follow && links[robot] ? (now - linksAt) / 1000 : 0) : undefined;
    let state: string;
    let css = "";
    if (r.done) state = "done";
    else if (r.connected === undefined) state = ended ? "done" : "in-process replay";
    else if (r.connected && (silent ?? 0) < 30) ((state = "connected"), (css = "state-connected"));
    else ((state = `silent for ${Math.round(silent ?? 0)} s`), (css = "state-silent"));
    const div = document.createElement("div");
    div.className = "robot";
    div.id = `robot-${robot}`;
    div.style.borderColor = robotCss(robot);
    div.innerHTML =
      `<b>${robot}</b> <span class="${css}">${state}</span> · seq ${r.next_sequence !== undefined ? r.next_sequence - 1 : "-"}` +
      ` · ${r.applied ?? 0} applied` +
      (r.bytes !== undefined ? ` · ${(r.bytes / 1e6).toFixed(2)} MB` : "") +
      ` · ${r.aligned ? "aligned" : "not aligned"}`;
    strip.append(div);
  }
}
setInterval(updateRobots, 1000);

// --- inspector and search ---
function inspect(id: string, focus: boolean): void {
  const view = shown ?? live;
  const row = scene.node(id);
  selected = id;
  scene.select(row ? id : null);
  if (focus && row) scene.focus(id);
  writeHash();
  const panel = $("inspector");
  panel.hidden = false;
  $("inspect-id").textContent = id;
  const fields = $("inspect-fields");
  fields.replaceChildren();
  const add = (name: string, value: string | Node) => {
    const dt = document.createElement("dt");
    dt.textContent = name;
    const dd = document.createElement("dd");
    dd.append(value);
    fields.append(dt, dd);
  };
  const link = (target: string) => {
    const a = document.createElement("a");
    a.textContent = target;
    a.addEventListener("click", () => inspect(target, true));
    return a;
  };
  if (!row) {
    const into = [...view.tables.merges.values()].find((m) => m[1] === id);
    add("round", String(view.round));
    if (into) add("merged into", link(String(into[0])));
    else add("", "not in this round's graph");
    return;
  }
  const [, layer, robot, x, y, z, parent, attributes] = row;
  add("layer", layer);
  add("robot", robot || "(the station's)");
  add("position", `${(x / 100).toFixed(2)}, ${(y / 100).toFixed(2)}, ${(z / 100).toFixed(2)} m`);
  add("parent", parent ? link(parent) : "none");
  const children = nodes(view).filter((n) => n[6] === id);
  const list = document.createElement("span");
  children.slice(0, 40).forEach((c, i) => list.append(i ? ", " : "", link(c[0])));
  if (children.length > 40) list.append(` and ${children.length - 40} more`);
  add(`children (${children.length})`, children.length ? list : "none");
  const names: Record<string, string> = {
    box: "box (cm)", distance: "free space (cm)", t: "time (s)", k: "keyframe", q: "orientation (w, x, y, z)",
    vertices: "mesh vertices",
  };
  for (const [key, value] of Object.entries(attributes)) add(names[key] ?? key, Array.isArray(value) ? value.join(", ") : String(value));
  const merged = [...view.tables.merges.values()].filter((m) => m[0] === id || m[1] === id);
  if (merged.length) add("merged", merged.map((m) => `${m[1]} into ${m[0]}`).join("; "));
}
$("inspect-close").addEventListener("click", () => {
  selected = null;
  scene.select(null);
  $("inspector").hidden = true;
  writeHash();
});
scene.renderer.domElement.addEventListener("click", (e) => {
  const id = scene.pick(e.clientX, e.clientY);
  if (id) inspect(id, false);
});

const search = $<HTMLInputElement>("search");
search.addEventListener("input", () => {
  const text = search.value.trim().toLowerCase();
  const results = $("search-results");
  results.replaceChildren();
  if (!text) return;
  const matches = nodes(shown ?? live)
    .filter((n: NodeRow) => n[0].toLowerCase() === text || n[0].toLowerCase().startsWith(text) || (n[7].name ?? "").toLowerCase().includes(text))
    .slice(0, 50);
  for (const n of matches) {
    const li = document.createElement("li");
    li.textContent = `${n[0]} ${n[7].name ?? ""} (${n[1]}${n[2] ? `, ${n[2]}` : ""})`;
    li.addEventListener("click", () => {
      results.replaceChildren();
      inspect(n[0], true);
    });
    results.append(li);
  }
});

// --- charts ---
function updateCharts(): void {
  const time = summaries.map((s) => [s.seq, s.info.time_s ?? 0] as [number, number]);
  drawLineChart($("chart-time") as unknown as SVGSVGElement, { backend: time }, { backend: "#e0e0e0" });
  const series: Record<string, [number, number][]> = {};
  const colours: Record<string, string> = {};
  const haveBytes = summaries.some((s) => Object.values(s.robots).some((r) => r.bytes !== undefined));
  for (const s of summaries) {
    for (const [robot, r] of Object.entries(s.robots)) {
      (series[robot] ??= []).push([s.seq, haveBytes ? (r.bytes ?? 0) / 1e6 : (r.applied ?? 0)]);
      colours[robot] = robotCss(robot);
    }
  }
  drawLineChart($("chart-bytes") as unknown as SVGSVGElement, series, colours);
  $("chart-bytes").previousElementSibling!.textContent = haveBytes ? "MB received per robot" : "Updates applied per robot";
}

// --- the mesh ---
async function fetchMesh(): Promise<void> {
  if (meshFetching) return;
  meshFetching = true;
  lastMeshFetch = performance.now();
  try {
    const response = await fetch(`api/mesh${meshSeq >= 0 ? `?after=${meshSeq}` : ""}`);
    if (response.status !== 200) return;
    const mesh: ViewerMesh = parseMesh(await response.arrayBuffer());
    meshSeq = mesh.seq;
    scene.setMesh(mesh);
    if (shown) updateCounts(shown);
  } finally {
    meshFetching = false;
  }
}

// --- the stream ---
function setConnection(state: string, text: string): void {
  const el = $("connection");
  el.dataset.state = state;
  el.textContent = text;
}

const wanted = readHash();
let focusPending: string | null = wanted.node ?? null;  // a linked node: looked at once drawn
async function start(): Promise<void> {
  const rounds = await (await fetch("api/rounds")).json();
  summaries = rounds.rounds;
  ended = rounds.ended;
  updateCharts();
  await fetchMesh();
  if (wanted.round !== undefined) {
    const match = [...summaries].reverse().find((s) => s.round === wanted.round);
    if (match) {
      follow = false;
      followBox.checked = false;
      await showSeq(match.seq);
    }
  }
  if (wanted.node) inspect(wanted.node, true);
  const events = new EventSource("api/events");
  const onView = (e: MessageEvent) => {
    const receivedMs = performance.now();
    const delta = JSON.parse(e.data) as Delta;
    live = applyDelta(live, delta);
    if (!summaries.length || summaries[summaries.length - 1].seq < delta.seq)
      summaries.push({ seq: delta.seq, round: delta.round, final: delta.final, info: delta.info, robots: delta.robots });
    slider.max = String(live.seq);
    if (follow || !shown) show(live);
    else $("round-text").textContent = `round ${shown.round} (view ${shown.seq} of ${live.seq})`;
    const entry = { seq: delta.seq, receivedMs, drawnMs: 0, publishedMs: delta.info.published_unix_ms ?? 0 };
    shownAt.push(entry);
    scene.invalidate();
    scene.afterFrame.push((drawnMs) => (entry.drawnMs = drawnMs));
    updateCharts();
    if (!ended && performance.now() - lastMeshFetch > 2000) void fetchMesh();
  };
  events.addEventListener("snapshot", (e) => {
    // A snapshot after a reconnect may come from a restarted station: its rounds start again.
    void fetch("api/rounds")
      .then((r) => r.json())
      .then((rounds) => {
        summaries = rounds.rounds;
        updateCharts();
      });
    onView(e as MessageEvent);
  });
  events.addEventListener("delta", onView);
  events.addEventListener("status", (e) => {
    links = JSON.parse((e as MessageEvent).data).robots;
    linksAt = performance.now();
  });
  events.addEventListener("end", () => {
    ended = true;
    events.close();
    setConnection("ended", "run ended");
    void fetchMesh();
    updateRobots();
  });
  events.addEventListener("open", () => setConnection(ended ? "ended" : "live", ended ? "run ended" : "live"));
  events.addEventListener("error", () => {
    if (!ended) setConnection("offline", "station offline: reconnecting");
  });
}

// What the tests and the benchmark read (docs/VIEWER.md "Testing hooks").
(window as unknown as Record<string, unknown>).hmViewer = {
  stats: () => ({ ...scene.stats(), liveSeq: live.seq, ended, follow, shownSeq: shown?.seq ?? 0, meshSeq }),
  screenPositionOf: (id: string) => scene.screenPositionOf(id),
  /** Per view received: when it arrived and was drawn (performance.now()) and published (Unix ms). */
  shownAt: () => ({ timeOrigin: performance.timeOrigin, views: shownAt }),
  firstFullFrameMs: () => scene.firstFullFrameMs,
  inspected: () => selected,
  mergedObject: () => [...(shown ?? live).tables.merges.values()].find((m) => m[2] === "objects" && scene.node(String(m[0])))?.[0] ?? null,
  renderInfo: () => {
    scene.setMoving(true);
    scene.renderer.render(scene.scene, scene.camera);
    const moving = { ...scene.renderer.info.render };
    scene.setMoving(false);
    scene.renderer.render(scene.scene, scene.camera);
    return { moving, still: { ...scene.renderer.info.render } };
  },
  robotOf,
  orbit: (seconds: number, sync = true) =>
    new Promise((resolve) => {
      const startFrames = scene.frames;
      const before = { ...scene.timings };
      const t0 = performance.now();
      const target = scene.controls.target.clone();
      const offset = scene.camera.position.clone().sub(target);
      scene.setMoving(true);
      scene.syncFrames = sync;
      scene.onFrame = () => {
        const t = (performance.now() - t0) / 1000;
        const angle = t * 0.8;
        const c = Math.cos(angle), s = Math.sin(angle);
        scene.camera.position.set(target.x + c * offset.x - s * offset.y, target.y + s * offset.x + c * offset.y, target.z + offset.z);
        scene.camera.lookAt(target);
        scene.invalidate();
        if (t >= seconds) {
          scene.onFrame = null;
          scene.syncFrames = false;
          scene.setMoving(false);
          const frames = scene.frames - startFrames;
          const per = (k: "render" | "labels" | "finish") => (scene.timings[k] - before[k]) / Math.max(1, frames);
          resolve({ frames, seconds: t, fps: frames / t, renderMs: per("render"), labelsMs: per("labels"), finishMs: per("finish") });
        }
      };
    }),
};
void start();
