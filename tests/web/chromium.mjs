// Debian's chromium, headless, for the viewer's browser test and benchmark: software WebGL
// (SwiftShader), no network of its own, a fresh profile in `userDir`. playwright-core comes
// from the page's own packages (web/node_modules), never downloads a browser.
import { createRequire } from "node:module";
import path from "node:path";

export const CHROMIUM_ARGS = [
  "--no-sandbox", "--use-angle=swiftshader", "--enable-unsafe-swiftshader", "--disable-quic", "--no-first-run",
  "--disable-background-networking", "--disable-component-update", "--disable-sync", "--disable-extensions",
  "--disable-default-apps", "--no-default-browser-check", "--metrics-recording-only",
];

/** A persistent context in userDir; .newPage({viewport}) and .close(). */
export async function launchChromium(webDir, userDir) {
  const require = createRequire(path.join(path.resolve(webDir), "package.json"));
  const { chromium } = require("playwright-core");
  const context = await chromium.launchPersistentContext(userDir, {
    executablePath: process.env.CHROMIUM ?? "/usr/bin/chromium", headless: true, args: CHROMIUM_ARGS,
  });
  return {
    context,
    newPage: async ({ viewport }) => {
      const page = await context.newPage();
      await page.setViewportSize(viewport);
      return page;
    },
    close: () => context.close(),
  };
}

/** Parses --name value pairs. */
export function parseArgs(argv) {
  const out = {};
  for (let i = 0; i < argv.length; ++i) if (argv[i].startsWith("--")) out[argv[i].slice(2)] = argv[i + 1];
  return out;
}
