// The viewer page in a real browser (Debian's chromium, headless, driven by playwright-core):
// a live `run --http` of the tiny team updates the page while it runs; then `view` of that run's
// folder: the nodes drawn per layer and robot equal the graph's, toggling a layer hides it,
// clicking a node shows its id, the time slider changes what is drawn, search and a link with
// #round=...&node=... show the same thing; a screenshot is written. Starts and stops its own
// servers on loopback ports they pick; bounded by a watchdog.
//
//   node viewer_browser.mjs --bin BUILD/hydra-multi --web WEB_DIR --out DIR [--screenshot PNG]
import { spawn, spawnSync } from "node:child_process";
import fs from "node:fs";
import path from "node:path";
import { launchChromium, parseArgs } from "./chromium.mjs";

const args = parseArgs(process.argv.slice(2));
for (const needed of ["bin", "web", "out"]) {
  if (!args[needed]) {
    console.error(`usage: node viewer_browser.mjs --bin HYDRA_MULTI --web WEB_DIR --out DIR [--screenshot PNG]`);
    process.exit(2);
  }
}

const children = [];
let browser = null;
let userDir = null;
async function cleanUp() {
  for (const c of children) if (c.exitCode === null) c.kill("SIGTERM");
  if (browser) await browser.close().catch(() => {});
  if (userDir) fs.rmSync(userDir, { recursive: true, force: true });
}
const watchdog = setTimeout(async () => {
  console.error("FAIL: the browser test took longer than 150 s");
  await cleanUp();
  process.exit(1);
}, 150_000);

let failures = 0;
function check(condition, what, detail = "") {
  console.log(`${condition ? "ok  " : "FAIL"} ${what}${detail ? `: ${detail}` : ""}`);
  if (!condition) ++failures;
}

// Starts a process and resolves with the first http:// URL it prints on stdout or stderr.
function startServer(argv, name) {
  return new Promise((resolve, reject) => {
    const child = spawn(args.bin, argv, { stdio: ["ignore", "pipe", "pipe"] });
    children.push(child);
    let seen = "";
    const onData = (chunk) => {
      seen += chunk.toString();
      const match = seen.match(/http:\/\/127\.0\.0\.1:\d+\//);
      if (match) resolve({ child, url: match[0] });
    };
    child.stdout.on("data", onData);
    child.stderr.on("data", onData);
    child.on("exit", (code) => reject(new Error(`${name} ended (${code}) before printing its URL:\n${seen}`)));
  });
}

// Nodes per layer and robot of a graph file, as the page counts them.
function graphCounts(file) {
  const graph = JSON.parse(fs.readFileSync(file, "utf8"));
  const counts = {};
  for (const n of graph.nodes) {
    const at = n.id.indexOf("@");
    const robot = at >= 0 ? n.id.slice(at + 1) : /^[a-oq-z]\d+$/.test(n.id) ? n.id[0] : "";
    counts[n.layer] ??= {};
    counts[n.layer][robot] = (counts[n.layer][robot] ?? 0) + 1;
  }
  return counts;
}
const sorted = (o) => JSON.stringify(Object.keys(o).sort().map((k) => [k, typeof o[k] === "object" ? JSON.parse(sorted(o[k])) : o[k]]));
const total = (counts) => Object.values(counts).reduce((s, r) => s + Object.values(r).reduce((a, b) => a + b, 0), 0);

async function openViewer(url) {
  const page = await browser.newPage({ viewport: { width: 1280, height: 800 } });
  page.on("pageerror", (e) => check(false, "no error on the page", e.message));
  await page.goto(url);
  return page;
}
const stats = (page) => page.evaluate(() => window.hmViewer.stats());

try {
  fs.rmSync(args.out, { recursive: true, force: true });
  fs.mkdirSync(args.out, { recursive: true });
  const dataset = path.join(args.out, "tiny");
  const sim = spawnSync(args.bin, ["simulate", "--preset", "tiny", "--seed", "1", "--out", dataset, "--quiet"]);
  if (sim.status !== 0) throw new Error(`simulate failed: ${sim.stderr}`);
  userDir = fs.mkdtempSync(path.join(args.out, "chromium-"));
  browser = await launchChromium(args.web, userDir);

  // 1. Live: the page follows a run while it runs.
  const runOut = path.join(args.out, "tiny-run");
  const live = await startServer(["run", "--dataset", dataset, "--out", runOut, "--speed", "10", "--http", "127.0.0.1:0"], "run --http");
  const runEnded = new Promise((resolve) => live.child.on("exit", resolve));
  const livePage = await openViewer(live.url);
  await livePage.waitForFunction(() => window.hmViewer && window.hmViewer.stats().seq > 0, null, { timeout: 30_000 });
  const first = await stats(livePage);
  const streaming = await livePage.textContent("#robot-a");
  check(/connected/.test(streaming) && /MB/.test(streaming), "the status strip shows a robot streaming and its bytes", streaming);
  await livePage.waitForFunction(() => window.hmViewer.stats().ended, null, { timeout: 60_000 });
  const last = await stats(livePage);
  check(last.seq > first.seq, "a live run updates the page while it runs", `view ${first.seq} then ${last.seq}`);
  check(total(last.nodes) > total(first.nodes), "the live page draws the map as it grows", `${total(first.nodes)} then ${total(last.nodes)} nodes`);
  const code = await runEnded;
  check(code === 0, "run --http ends by itself", `exit code ${code}`);
  check(sorted(last.nodes) === sorted(graphCounts(path.join(runOut, "graph.json"))), "the live page's last view is the run's final graph");
  await livePage.close();

  // 2. The finished run, served by `view`.
  const view = await startServer(["view", runOut, "--http", "127.0.0.1:0"], "view");
  const page = await openViewer(view.url);
  await page.waitForFunction(() => window.hmViewer && window.hmViewer.stats().ended && window.hmViewer.stats().meshSeq > 0, null, { timeout: 30_000 });
  await page.waitForTimeout(300);
  const shown = await stats(page);
  const expected = graphCounts(path.join(runOut, "graph.json"));
  check(sorted(shown.nodes) === sorted(expected), "nodes drawn per layer and robot equal the graph's", sorted(shown.nodes));
  check(Object.values(shown.meshFaces).reduce((a, b) => a + b, 0) > 0, "the mesh is drawn", JSON.stringify(shown.meshFaces));
  const lc = shown.loopClosures;
  check(lc.interKept + lc.interRejected > 0, "inter-robot loop closures are drawn", JSON.stringify(lc));
  check((await page.textContent("#lc-inter")).includes(`${lc.interKept} kept`), "the loop-closure counts are shown");
  check((await page.locator(".robot").count()) === Object.keys(expected.agents).length, "one status per robot");
  const status = await page.textContent("#robot-b");
  check(/done/.test(status) && /applied/.test(status) && /MB/.test(status) && /aligned/.test(status), "a robot's status: done, sequence, applied, bytes, aligned", status);

  // Toggling a layer hides it.
  await page.click("#toggle-objects");
  check((await stats(page)).visible.objects === false, "toggling objects hides them");
  await page.click("#toggle-objects");
  check((await stats(page)).visible.objects === true, "toggling again shows them");

  // Clicking a node shows its id (the building: the top layer, nothing above it).
  const building = Object.keys(expected.buildings ?? {}).length ? "B(0)" : null;
  check(building !== null, "the graph has a building");
  const at = await page.evaluate((id) => window.hmViewer.screenPositionOf(id), building);
  await page.mouse.click(at.x, at.y);
  await page.waitForFunction(() => !document.getElementById("inspector").hidden, null, { timeout: 5000 });
  check((await page.textContent("#inspect-id")) === building, "clicking a node shows its id", await page.textContent("#inspect-id"));
  check((await page.textContent("#inspect-fields")).includes("buildings"), "the inspector names the node's layer");
  check(page.url().includes(`node=${encodeURIComponent(building)}`), "the URL holds the node", page.url());

  // Search by id.
  const object = JSON.parse(fs.readFileSync(path.join(runOut, "graph.json"), "utf8")).nodes.find((n) => n.layer === "objects").id;
  await page.fill("#search", object);
  await page.click("#search-results li >> nth=0");
  check((await page.textContent("#inspect-id")) === object, "search by id selects the node", object);

  // The time slider changes what is drawn, and the URL holds the round.
  await page.evaluate(() => {
    const slider = document.getElementById("round");
    slider.value = "2";
    slider.dispatchEvent(new Event("input"));
  });
  await page.waitForFunction(() => window.hmViewer.stats().shownSeq === 2, null, { timeout: 5000 });
  const early = await stats(page);
  check(total(early.nodes) < total(shown.nodes), "an earlier round draws less", `${total(early.nodes)} vs ${total(shown.nodes)} nodes`);
  check(/round=\d+/.test(page.url()), "the URL holds the round", page.url());

  // A link shows the same thing.
  const link = page.url();
  const again = await openViewer(link);
  await again.waitForFunction(() => window.hmViewer && window.hmViewer.stats().shownSeq > 0 && window.hmViewer.stats().ended, null, { timeout: 20_000 });
  const linked = await stats(again);
  check(linked.round === early.round && sorted(linked.nodes) === sorted(early.nodes), "a link opens the same round", `round ${linked.round}`);
  check((await again.textContent("#inspect-id")) === object, "a link opens the same node");
  await again.close();

  // Back to the end for the screenshot.
  await page.check("#follow");
  await page.selectOption("#colour", "robot");
  await page.waitForTimeout(300);
  if (args.screenshot) {
    await page.screenshot({ path: args.screenshot });
    check(fs.statSync(args.screenshot).size > 10_000, "a screenshot is written", args.screenshot);
  }
} catch (error) {
  check(false, "the test ran to its end", error.stack ?? String(error));
} finally {
  clearTimeout(watchdog);
  await cleanUp();
}
console.log(failures === 0 ? "viewer in a browser: all checks passed" : `viewer in a browser: ${failures} check(s) failed`);
process.exit(failures === 0 ? 0 : 1);
