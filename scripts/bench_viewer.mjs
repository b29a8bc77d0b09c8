// The viewer on a large team's graph in headless chromium (software rendering): time to the
// first frame with the graph and its mesh, frames per second while the camera orbits (frames the
// page drew, checked against the compositor's DrawFrame events), the bytes of the initial
// snapshot, the mesh and the deltas, and the lag between a view's publication and the page
// drawing it (the run's history replayed as if live, one view every 2 s).
//
//   node bench_viewer.mjs --bin BUILD/hydra-multi --web WEB_DIR --run RUN_DIR [--width W --height H]
import { spawn } from "node:child_process";
import fs from "node:fs";
import os from "node:os";
import path from "node:path";
import { launchChromium, parseArgs } from "../tests/web/chromium.mjs";

const args = parseArgs(process.argv.slice(2));
const width = Number(args.width ?? 1280), height = Number(args.height ?? 720);
const children = [];
const userDir = fs.mkdtempSync(path.join(os.tmpdir(), "hm-bench-viewer-"));
let browser = null;
const cleanUp = async () => {
  for (const c of children) if (c.exitCode === null) c.kill("SIGTERM");
  if (browser) await browser.close().catch(() => {});
  fs.rmSync(userDir, { recursive: true, force: true });
};
const watchdog = setTimeout(async () => {
  console.error("bench-viewer: took longer than 10 minutes; stopped");
  await cleanUp();
  process.exit(1);
}, 600_000);

function serve(extra) {
  return new Promise((resolve, reject) => {
    const child = spawn(args.bin, ["view", args.run, "--http", "127.0.0.1:0", "--quiet", ...extra], { stdio: ["ignore", "pipe", "pipe"] });
    children.push(child);
    let seen = "";
    const onData = (d) => {
      seen += d;
      const m = seen.match(/http:\/\/127\.0\.0\.1:\d+\//);
      if (m) resolve(m[0]);
    };
    child.stdout.on("data", onData);
    child.stderr.on("data", onData);
    child.on("exit", (code) => reject(new Error(`view ended (${code}):\n${seen}`)));
  });
}
const median = (xs) => { const s = [...xs].sort((a, b) => a - b); return s.length ? s[Math.floor(s.length / 2)] : NaN; };
const mb = (bytes) => `${(bytes / 1e6).toFixed(2)} MB`;

try {
  const history = fs.readFileSync(path.join(args.run, "viewer", "history.jsonl"), "utf8").split("\n").filter(Boolean).slice(1);
  const deltas = history.slice(1).map((l) => Buffer.byteLength(l));
  // How long the station took to build and publish each view after its backend round ended.
  const builds = history.map((l) => JSON.parse(l).info).filter((i) => i.round_end_unix_ms).map((i) => i.published_unix_ms - i.round_end_unix_ms);
  browser = await launchChromium(args.web, userDir);

  // 1. The finished run.
  const url = await serve([]);
  const snapshotBytes = (await (await fetch(`${url}api/view`)).arrayBuffer()).byteLength;
  const meshBytes = (await (await fetch(`${url}api/mesh`)).arrayBuffer()).byteLength;
  const page = await browser.newPage({ viewport: { width, height } });
  await page.goto(url);
  await page.waitForFunction(() => window.hmViewer && window.hmViewer.firstFullFrameMs() > 0, null, { timeout: 120_000, polling: 50 });
  const firstMs = await page.evaluate(() => window.hmViewer.firstFullFrameMs());
  const stats = await page.evaluate(() => window.hmViewer.stats());
  const faces = Object.values(stats.meshFaces).reduce((a, b) => a + b, 0);
  const nodes = Object.values(stats.nodes).reduce((s, r) => s + Object.values(r).reduce((a, b) => a + b, 0), 0);
  console.log(`graph: ${nodes} nodes, ${faces} mesh faces, ${Object.keys(stats.meshFaces).length} robots, ${history.length} views; viewport ${width}x${height}`);
  console.log(`first frame with the graph and its mesh: ${(firstMs / 1000).toFixed(2)} s after navigation`);
  const orbits = [];
  for (let i = 0; i < 3; ++i) {
    await browser.context.tracing?.stop?.().catch(() => {});
    const cdp = await page.context().newCDPSession(page);
    const events = [];
    cdp.on("Tracing.dataCollected", (e) => events.push(...e.value));
    await cdp.send("Tracing.start", { categories: "disabled-by-default-devtools.timeline.frame", transferMode: "ReportEvents" });
    const r = await page.evaluate(() => window.hmViewer.orbit(5, false));
    const done = new Promise((resolve) => cdp.once("Tracing.tracingComplete", resolve));
    await cdp.send("Tracing.end");
    await done;
    await cdp.detach();
    const drawn = events.filter((e) => e.name === "DrawFrame").length;
    orbits.push({ fps: r.fps, compositor: drawn / r.seconds });
    await page.waitForTimeout(500);
  }
  console.log(`orbiting, 3 x 5 s: ${orbits.map((o) => o.fps.toFixed(1)).join(", ")} frames/s drawn by the page` +
    ` (compositor DrawFrame: ${orbits.map((o) => o.compositor.toFixed(1)).join(", ")} /s)`);
  if (builds.length)
    console.log(`the station built each view in: median ${median(builds).toFixed(0)} ms, max ${Math.max(...builds).toFixed(0)} ms after its backend round (${builds.length} rounds of the run)`);
  console.log(`initial snapshot ${mb(snapshotBytes)} of JSON, mesh ${mb(meshBytes)}; deltas: median ${mb(median(deltas))}, largest ${mb(Math.max(...deltas))} (${deltas.length})`);
  await page.close();

  // 2. The lag: the history replayed as if live.
  const live = await serve(["--replay", "2"]);
  const livePage = await browser.newPage({ viewport: { width, height } });
  await livePage.goto(live);
  await livePage.waitForFunction(() => window.hmViewer && window.hmViewer.stats().ended, null, { timeout: 60_000 + 3000 * history.length });
  await livePage.waitForTimeout(500);
  const shown = await livePage.evaluate(() => window.hmViewer.shownAt());
  // The first view arrives as the snapshot the page connects to (published before it existed).
  const lags = shown.views.slice(1).filter((v) => v.publishedMs > 0 && v.drawnMs > 0).map((v) => shown.timeOrigin + v.drawnMs - v.publishedMs);
  console.log(`lag from a delta's publication to the page drawing it (${lags.length} deltas replayed live): median ${median(lags).toFixed(0)} ms, max ${Math.max(...lags).toFixed(0)} ms` +
    ` (${lags.map((l) => l.toFixed(0)).join(", ")})`);
} catch (error) {
  console.error(`bench-viewer: ${error.stack ?? error}`);
  process.exitCode = 1;
} finally {
  clearTimeout(watchdog);
  await cleanUp();
}
