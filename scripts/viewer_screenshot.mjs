// A screenshot of the viewer on a finished run (the README's): `view RUN` in headless chromium,
// a node inspected and found by search, then the picture.
//
//   node viewer_screenshot.mjs --bin BUILD/hydra-multi --web WEB_DIR --run RUN_DIR --out PNG [--node ID]
import { spawn } from "node:child_process";
import fs from "node:fs";
import os from "node:os";
import path from "node:path";
import { launchChromium, parseArgs } from "../tests/web/chromium.mjs";

const args = parseArgs(process.argv.slice(2));
const userDir = fs.mkdtempSync(path.join(os.tmpdir(), "hm-screenshot-"));
const view = spawn(args.bin, ["view", args.run, "--http", "127.0.0.1:0", "--quiet"], { stdio: ["ignore", "pipe", "inherit"] });
let browser = null;
try {
  const url = await new Promise((resolve, reject) => {
    let seen = "";
    view.stdout.on("data", (d) => {
      seen += d;
      const m = seen.match(/http:\/\/127\.0\.0\.1:\d+\//);
      if (m) resolve(m[0]);
    });
    view.on("exit", (code) => reject(new Error(`view ended (${code})`)));
  });
  browser = await launchChromium(args.web, userDir);
  const page = await browser.newPage({ viewport: { width: 1600, height: 960 } });
  const ready = () => page.waitForFunction(() => window.hmViewer && window.hmViewer.firstFullFrameMs() > 0 && window.hmViewer.stats().ended, null, { timeout: 60_000 });
  await page.goto(url);
  await ready();
  // By default an object several robots mapped: the target of the first object merge.
  const node = args.node ?? (await page.evaluate(() => window.hmViewer.mergedObject()));
  await page.goto(`${url}#node=${encodeURIComponent(node)}`);
  await page.reload();
  await ready();
  await page.waitForTimeout(800);
  await page.screenshot({ path: args.out });
  console.log(`viewer screenshot: ${args.out}`);
} finally {
  if (browser) await browser.close();
  view.kill("SIGTERM");
  fs.rmSync(userDir, { recursive: true, force: true });
}
