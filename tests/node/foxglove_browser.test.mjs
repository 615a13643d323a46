// The built-in web page in a real browser: headless Chromium (driven over the DevTools
// protocol) loads http://127.0.0.1:PORT/ from `vlpground replay --rate 1 --foxglove` and the
// test checks that the frame counter advances and that the screenshot shows ground and
// obstacle colours. Environment (set by ctest): VLPGROUND_CLI, VLPGROUND_SOURCE_DIR,
// CHROMIUM, FOXGLOVE_TEST_DIR (the screenshot is kept there as live_page.png).
import { test } from "node:test";
import assert from "node:assert/strict";
import { spawn } from "node:child_process";
import { mkdirSync, mkdtempSync, rmSync, writeFileSync } from "node:fs";
import { tmpdir } from "node:os";
import path from "node:path";
import { inflateSync } from "node:zlib";
import WebSocket from "ws";
import { startCli, stopCli } from "./foxglove_support.mjs";

const source = process.env.VLPGROUND_SOURCE_DIR;
const outDir = process.env.FOXGLOVE_TEST_DIR;
const pcap = path.join(source, "pcaps", "urban_demo.pcap");

// Headless Chromium with a DevTools endpoint on a free port; resolves { proc, endpoint }.
async function startChromium(profile) {
  const proc = spawn(process.env.CHROMIUM, [
    "--headless=new", "--no-sandbox", "--disable-gpu", "--no-first-run", "--disable-extensions",
    "--remote-debugging-port=0", `--user-data-dir=${profile}`, "--window-size=960,720",
    "--force-device-scale-factor=1", "about:blank"], { stdio: ["ignore", "ignore", "pipe"] });
  let stderr = "";
  const endpoint = await new Promise((resolve, reject) => {
    const timer = setTimeout(() => reject(new Error(`no DevTools endpoint:\n${stderr}`)), 30000);
    proc.stderr.on("data", (d) => {
      stderr += d;
      const m = /DevTools listening on (ws:\/\/\S+)/.exec(stderr);
      if (m) { clearTimeout(timer); resolve(m[1]); }
    });
    proc.on("exit", (code) => { clearTimeout(timer); reject(new Error(`chromium exited ${code}:\n${stderr}`)); });
  });
  return { proc, endpoint };
}

// A minimal DevTools protocol client: send(method, params, sessionId) -> result.
async function devtools(endpoint) {
  const ws = new WebSocket(endpoint, { perMessageDeflate: false });
  await new Promise((resolve, reject) => { ws.once("open", resolve); ws.once("error", reject); });
  let next = 1;
  const pending = new Map();
  ws.on("message", (data) => {
    const m = JSON.parse(data.toString());
    const p = pending.get(m.id);
    if (!p) return;
    pending.delete(m.id);
    if (m.error) p.reject(new Error(JSON.stringify(m.error))); else p.resolve(m.result);
  });
  const send = (method, params = {}, sessionId = undefined) => new Promise((resolve, reject) => {
    const id = next++;
    pending.set(id, { resolve, reject });
    ws.send(JSON.stringify({ id, method, params, ...(sessionId ? { sessionId } : {}) }));
  });
  return { send, close: () => ws.close() };
}

// RGB(A) pixels of an 8-bit PNG (what Page.captureScreenshot returns).
function decodePng(png) {
  let pos = 8, width = 0, height = 0, channels = 0;
  const idat = [];
  while (pos < png.length) {
    const length = png.readUInt32BE(pos), type = png.toString("ascii", pos + 4, pos + 8);
    const data = png.subarray(pos + 8, pos + 8 + length);
    if (type === "IHDR") {
      width = data.readUInt32BE(0); height = data.readUInt32BE(4);
      assert.equal(data[8], 8, "8-bit PNG");
      channels = { 2: 3, 6: 4 }[data[9]];
      assert.ok(channels, `colour type ${data[9]}`);
    } else if (type === "IDAT") idat.push(data);
    pos += 12 + length;
  }
  const raw = inflateSync(Buffer.concat(idat)), stride = width * channels;
  const out = Buffer.alloc(height * stride);
  for (let y = 0; y < height; ++y) {
    const filter = raw[y * (stride + 1)], line = raw.subarray(y * (stride + 1) + 1, (y + 1) * (stride + 1));
    for (let x = 0; x < stride; ++x) {
      const a = x >= channels ? out[y * stride + x - channels] : 0;
      const b = y > 0 ? out[(y - 1) * stride + x] : 0;
      const c = x >= channels && y > 0 ? out[(y - 1) * stride + x - channels] : 0;
      const pa = Math.abs(b - c), pb = Math.abs(a - c), pc = Math.abs(a + b - 2 * c);
      const predictor = [0, a, b, (a + b) >> 1, pa <= pb && pa <= pc ? a : pb <= pc ? b : c][filter];
      out[y * stride + x] = (line[x] + predictor) & 0xff;
    }
  }
  return { width, height, channels, pixels: out };
}

function countColour(image, [r, g, b], tolerance = 40) {
  let n = 0;
  for (let i = 0; i < image.pixels.length; i += image.channels) {
    const p = image.pixels;
    if (Math.abs(p[i] - r) < tolerance && Math.abs(p[i + 1] - g) < tolerance && Math.abs(p[i + 2] - b) < tolerance) ++n;
  }
  return n;
}

test("the web page in headless Chromium: frame counter advancing, ground and obstacles drawn", async () => {
  mkdirSync(outDir, { recursive: true });
  const profile = mkdtempSync(path.join(tmpdir(), "vlpground-chromium-"));
  let chromium = null, cdp = null, run = null;
  try {
    chromium = await startChromium(profile);  // first: it takes a while to start
    cdp = await devtools(chromium.endpoint);
    run = await startCli(["replay", pcap, "--rate", "1", "--loop", "--frames", "900"]);
    const { targetId } = await cdp.send("Target.createTarget", { url: `http://127.0.0.1:${run.port}/` });
    const { sessionId } = await cdp.send("Target.attachToTarget", { targetId, flatten: true });
    const text = async (id) => (await cdp.send("Runtime.evaluate",
      { expression: `document.getElementById(${JSON.stringify(id)})?.textContent ?? ""`, returnByValue: true },
      sessionId)).result.value;

    let first = NaN, frame = NaN;
    const deadline = Date.now() + 30000;
    while (!Number.isInteger(first) && Date.now() < deadline) {
      first = Number.parseInt(await text("frame"), 10);
      if (!Number.isInteger(first)) await new Promise((r) => setTimeout(r, 100));
    }
    assert.ok(Number.isInteger(first), "the page shows a frame number");
    // Until the counter moved on, a status (once a second) showed the replay's ~10 Hz and a
    // whole rotation is on screen (the capture's partial first and last rotations are
    // smaller). The rate is frames per second since the previous status, so one second of a
    // slow start (a sanitizer build beside a starting browser) may show less: the next
    // status is awaited rather than timed.
    const tenHertz = (r) => r > 5 && r < 15;
    let rate = NaN, points = 0;
    while (!(frame >= first + 3 && tenHertz(rate) && points > 15000) && Date.now() < deadline) {
      frame = Number.parseInt(await text("frame"), 10);
      rate = Number.parseFloat(await text("rate"));
      points = Number(await text("points"));
      await new Promise((r) => setTimeout(r, 50));
    }
    assert.ok(frame >= first + 3, `the frame counter advances: ${first} -> ${frame}`);
    assert.ok(tenHertz(rate), `the frame rate shows ~10 Hz: ${rate}`);
    assert.ok(points > 15000, `a whole rotation drawn: ${points} points`);
    assert.match(await text("state"), /connected/);
    assert.match(await text("gps"), /PPS locked/);

    // A screenshot of a whole rotation (the page may move on to a partial one meanwhile).
    let png = null;
    while (png === null && Date.now() < deadline) {
      const before = Number(await text("points"));
      const shot = await cdp.send("Page.captureScreenshot", { format: "png" }, sessionId);
      if (before > 15000 && Number(await text("points")) > 15000) png = Buffer.from(shot.data, "base64");
    }
    assert.ok(png !== null, "a screenshot of a whole rotation");
    writeFileSync(path.join(outDir, "live_page.png"), png);
    const image = decodePng(png);
    const ground = countColour(image, [0x28, 0xc8, 0x50]), obstacles = countColour(image, [0xe6, 0x32, 0x28]);
    assert.ok(ground > 2000, `ground-coloured pixels: ${ground}`);
    assert.ok(obstacles > 300, `obstacle-coloured pixels: ${obstacles}`);
  } finally {
    cdp?.close();
    if (chromium) { chromium.proc.kill("SIGKILL"); await new Promise((r) => chromium.proc.once("exit", r)).catch(() => {}); }
    // Chromium's helper processes may still write into the profile for a moment after the
    // browser was killed: retry, and never let the clean-up hide the test's own result.
    try { rmSync(profile, { recursive: true, force: true, maxRetries: 10, retryDelay: 200 }); } catch {}
    if (run) await stopCli(run);
  }
});
