// Headless check of polylocd's live page (service/live/page.html) against a running server
// (polylocd or mock_live_server.mjs): the page connects, loads nothing from other hosts, and
// draws the robot marker (the only magenta, rgb(255,0,255)) where the pose says, by the
// transform documented at the top of page.html, re-implemented here independently.
//
//   node check_live_page.mjs <url> [--shots 2] [--interval-ms 1500] [--out DIR] [--expect-move M]
//
// Uses Debian's Chromium (/usr/bin/chromium) through playwright-core; never downloads a browser.
import { mkdirSync, writeFileSync } from "node:fs";
import path from "node:path";
import { chromium } from "playwright-core";
import { PNG } from "pngjs";

const BAR = 24, M = 20;               // page.html's status bar height and margin
const VIEW = { width: 900, height: 600 };
const CONNECT_TIMEOUT_MS = 60000;  // a browser starting on a loaded 2-core machine is slow
const MAX_ERROR_PX = 3, MIN_MARKER_PX = 20;

function usage(msg) {
  console.error(`FAIL: ${msg}\nusage: node check_live_page.mjs <url> [--shots N] [--interval-ms MS] [--out DIR] [--expect-move M]`);
  process.exit(1);
}

function parseArgs(argv) {
  const opt = { url: null, shots: 2, intervalMs: 1500, out: null, expectMove: 0.2, readyFile: null };
  for (let i = 0; i < argv.length; i++) {
    const a = argv[i], val = () => (i + 1 < argv.length ? argv[++i] : usage(`${a} needs a value`));
    if (a === "--shots") opt.shots = Number(val());
    else if (a === "--interval-ms") opt.intervalMs = Number(val());
    else if (a === "--out") opt.out = val();
    else if (a === "--expect-move") opt.expectMove = Number(val());
    else if (a === "--ready-file") opt.readyFile = val();
    else if (a.startsWith("--")) usage(`unknown option ${a}`);
    else if (!opt.url) opt.url = a;
    else usage(`unexpected argument ${a}`);
  }
  if (!opt.url) usage("no url");
  if (!(Number.isInteger(opt.shots) && opt.shots >= 1)) usage("--shots must be an integer >= 1");
  if (!(opt.intervalMs >= 0)) usage("--interval-ms must be >= 0");
  if (!(opt.expectMove >= 0)) usage("--expect-move must be >= 0");
  return opt;
}

class Fail extends Error {}
const fail = (msg) => { throw new Fail(msg); };

// page.html's transform, written out again: map metres -> canvas CSS pixels.
function expectedPixel(pose, bounds, W, H) {
  const [xmin, ymin, xmax, ymax] = bounds;
  const s = Math.min((W - 2 * M) / (xmax - xmin), (H - BAR - 2 * M) / (ymax - ymin));
  return { x: M + (pose.x - xmin) * s, y: H - M - (pose.y - ymin) * s, s };
}

// Centroid (pixel centres) of the clearly magenta pixels; anti-aliased edges fall out.
function magentaCentroid(png) {
  let n = 0, sx = 0, sy = 0;
  for (let y = 0; y < png.height; y++) {
    for (let x = 0; x < png.width; x++) {
      const i = 4 * (y * png.width + x), d = png.data;
      if (d[i] > 200 && d[i + 1] < 60 && d[i + 2] > 200) { n++; sx += x + 0.5; sy += y + 0.5; }
    }
  }
  return n ? { n, x: sx / n, y: sy / n } : { n: 0 };
}

const f2 = (v) => v.toFixed(2), f1 = (v) => v.toFixed(1);

async function run(opt, state) {
  const pageUrl = new URL(opt.url);
  const browser = (state.browser = await chromium.launch({
    executablePath: "/usr/bin/chromium",
    args: ["--headless", "--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run",
           "--disable-background-networking", "--disable-component-update", "--disable-sync"],
    timeout: 30000,
  }));
  const context = await browser.newContext({ viewport: VIEW, deviceScaleFactor: 1 });
  const page = await context.newPage();

  // Everything the page asks for, plain requests and WebSockets alike.
  const requested = [], pageErrors = [];
  page.on("request", (r) => requested.push(r.url()));
  page.on("websocket", (w) => requested.push(w.url()));
  page.on("pageerror", (e) => pageErrors.push(String(e)));
  const checkRequests = () => {
    for (const u of requested) {
      const p = new URL(u);
      if (["data:", "blob:", "about:"].includes(p.protocol)) continue;  // not a network request
      if (p.host !== pageUrl.host) fail(`page requested an outside resource: ${u}`);
    }
    if (pageErrors.length) fail(`page error: ${pageErrors[0]}`);
  };

  const resp = await page.goto(opt.url, { waitUntil: "load", timeout: 45000 })
    .catch((e) => fail(`cannot load ${opt.url}: ${e.message.split("\n")[0]}`));
  if (!resp || !resp.ok()) fail(`GET ${opt.url}: ${resp ? resp.status() : "no response"}`);
  // Connected and the map drawn: say so (the test starts the data only then: a browser starting
  // on a loaded machine must not miss it), then wait for the robot.
  if (opt.readyFile) {
    try {
      await page.waitForFunction(() => window.polyloc && window.polyloc.connected && window.polyloc.bounds, null,
                                 { timeout: CONNECT_TIMEOUT_MS, polling: 100 });
    } catch (e) {
      fail(`page not connected within ${CONNECT_TIMEOUT_MS / 1000} s`);
    }
    writeFileSync(opt.readyFile, "connected\n");
  }
  try {
    await page.waitForFunction(
      () => window.polyloc && window.polyloc.connected && window.polyloc.frames >= 3 && window.polyloc.pose,
      null, { timeout: CONNECT_TIMEOUT_MS, polling: 100 });
  } catch (e) {
    const st = await page.evaluate(() => JSON.stringify(window.polyloc ?? null)).catch(() => "?");
    fail(`page not connected with a pose and >= 3 topview frames within ${CONNECT_TIMEOUT_MS / 1000} s ` +
         `(window.polyloc = ${st}${pageErrors.length ? `; page error: ${pageErrors[0]}` : ""})`);
  }
  checkRequests();
  if (opt.out) mkdirSync(opt.out, { recursive: true });

  const shots = [];
  for (let k = 1; k <= opt.shots; k++) {
    if (k > 1) await page.waitForTimeout(opt.intervalMs);
    let st, buf;
    await page.evaluate(() => { window.polyloc.freeze = true; });
    try {
      // Two animation frames: any drawing requested before the freeze has happened.
      await page.evaluate(() => new Promise((r) => requestAnimationFrame(() => requestAnimationFrame(r))));
      st = await page.evaluate(() => ({ pose: window.polyloc.pose, bounds: window.polyloc.bounds,
                                        W: window.innerWidth, H: window.innerHeight }));
      buf = await page.screenshot({ type: "png" });
      // The drawing must not have changed while the screenshot was taken.
      // And freeze must hold: give a frame or two time to arrive (10 Hz), then the drawn pose
      // must be the same although more frames were counted.
      const frames0 = await page.evaluate(() => window.polyloc.frames);
      await page.waitForFunction((n) => window.polyloc.frames > n + 1, frames0, { timeout: 500, polling: 20 }).catch(() => {});
      const after = await page.evaluate(() => ({ pose: window.polyloc.pose, bounds: window.polyloc.bounds }));
      if (JSON.stringify(after) !== JSON.stringify({ pose: st.pose, bounds: st.bounds }))
        fail(`shot ${k}: pose or bounds changed while frozen`);
    } finally {
      await page.evaluate(() => { window.polyloc.freeze = false; }).catch(() => {});
    }
    if (opt.out) writeFileSync(path.join(opt.out, `live_shot_${k}.png`), buf);

    const { pose, bounds, W, H } = st;
    if (!pose || !Number.isFinite(pose.x) || !Number.isFinite(pose.y)) fail(`shot ${k}: no pose drawn (${JSON.stringify(pose)})`);
    if (!Array.isArray(bounds) || bounds.length !== 4 || !(bounds[2] > bounds[0] && bounds[3] > bounds[1]))
      fail(`shot ${k}: bad bounds ${JSON.stringify(bounds)}`);
    const png = PNG.sync.read(buf);
    if (png.width !== W || png.height !== H) fail(`shot ${k}: screenshot ${png.width}x${png.height}, window ${W}x${H}`);
    const exp = expectedPixel(pose, bounds, W, H);
    const mk = magentaCentroid(png);
    // A disc of radius max(5, 0.3 s) px: at least 40 % of its area (at least 20 px) must be magenta
    // (a marker in another colour still has magenta-ish anti-aliased edge pixels).
    const minPx = Math.max(MIN_MARKER_PX, 0.4 * Math.PI * Math.max(5, 0.3 * exp.s) ** 2);
    if (mk.n < minPx)
      fail(`shot ${k}: only ${mk.n} magenta pixels (< ${Math.round(minPx)}; robot marker missing or not rgb(255,0,255)?), ` +
           `expected near (${f1(exp.x)}, ${f1(exp.y)})`);
    const err = Math.hypot(mk.x - exp.x, mk.y - exp.y);
    console.log(`shot ${k}: pose (${f2(pose.x)}, ${f2(pose.y)}) expected px (${f1(exp.x)}, ${f1(exp.y)}) ` +
                `marker (${f1(mk.x)}, ${f1(mk.y)}) error ${f1(err)} px`);
    if (err > MAX_ERROR_PX) fail(`shot ${k}: marker ${f1(err)} px from where the pose puts it (> ${MAX_ERROR_PX})`);
    shots.push({ pose, exp, mk });
  }

  if (shots.length >= 2 && opt.expectMove > 0) {
    const a = shots[0], b = shots[shots.length - 1];
    const moved = Math.hypot(b.pose.x - a.pose.x, b.pose.y - a.pose.y);
    const expPx = Math.hypot(b.exp.x - a.exp.x, b.exp.y - a.exp.y);
    const mkPx = Math.hypot(b.mk.x - a.mk.x, b.mk.y - a.mk.y);
    console.log(`moved ${f2(moved)} m, expected ${f1(expPx)} px, marker ${f1(mkPx)} px`);
    if (moved < opt.expectMove) fail(`robot moved ${f2(moved)} m between shot 1 and ${shots.length} (< ${opt.expectMove} m)`);
    if (mkPx < 0.5 * opt.expectMove * b.exp.s || Math.abs(mkPx - expPx) > 2 * MAX_ERROR_PX)
      fail(`marker moved ${f1(mkPx)} px, the pose says ${f1(expPx)} px`);
  }
  checkRequests();  // again: nothing fetched from elsewhere later either
}

const opt = parseArgs(process.argv.slice(2));
const state = { browser: null };
// Bound the whole run: launch, connect, shots, close.
const budgetMs = 30000 + CONNECT_TIMEOUT_MS * (opt.readyFile ? 2 : 1) + 45000 + opt.shots * (opt.intervalMs + 5000);
const watchdog = setTimeout(() => {
  console.error(`FAIL: check_live_page took more than ${Math.round(budgetMs / 1000)} s`);
  process.exit(1);  // the browser process is killed with us (playwright's exit handler)
}, budgetMs);

let code = 0;
try {
  await run(opt, state);
  console.log("check_live_page: ok");
} catch (e) {
  console.error(`FAIL: ${e instanceof Fail ? e.message : e?.stack ?? e}`);
  code = 1;
} finally {
  if (state.browser) await Promise.race([state.browser.close().catch(() => {}), new Promise((r) => setTimeout(r, 10000))]);
  clearTimeout(watchdog);
}
process.exit(code);
