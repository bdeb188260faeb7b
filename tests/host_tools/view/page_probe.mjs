// Opens a sinew-view page in headless Chromium through the DevTools protocol
// (over --remote-debugging-pipe: no WebSocket client, which Debian 12's
// Node 18 lacks),
// waits until it has drawn frames, saves a screenshot and prints what the
// page shows as JSON: frames drawn, the frame's time, the input table, the
// chart's summary, the error banner, and the screenshot's pixels inside the
// 3D view that differ from its background (the mesh and overlays).
//   node page_probe.mjs MIN_FRAMES TIMEOUT_S URL OUT.png [URL OUT.png ...]
// One JSON line per page, in order, from one browser (pages opened in turn).
// MIN_FRAMES 0 waits for the error banner instead of drawn frames.
//   node page_probe.mjs --diff A.png B.png   pixels of the 3D view that differ
// Node's own modules only (zlib for the PNG): no packages.
import {spawn} from 'node:child_process';
import fs from 'node:fs';
import os from 'node:os';
import path from 'node:path';
import zlib from 'node:zlib';

const [minFramesArg, timeoutArg, ...pages] = process.argv.slice(2);
const minFrames = Number(minFramesArg);
const deadline = Date.now() + 1000 * Number(timeoutArg || 30);
const chromium = process.env.CHROMIUM || 'chromium';
// The 3D view's canvas (880 x 720 at the page's top left, host_tools/view/web:
// #scene) and its clear colour. The band the error banner covers at the top
// and the legend's at the bottom are left out: only the scene is counted.
const VIEW = {x: 0, y: 48, w: 880, h: 632}, BACKGROUND = [0x1e, 0x22, 0x28];

if (minFramesArg === '--diff') diffAndExit(timeoutArg, pages[0]);
const sleep = (ms) => new Promise((r) => setTimeout(r, ms));
const profile = fs.mkdtempSync(path.join(os.tmpdir(), 'sinew-view-probe-'));
const browser = spawn(chromium, [
  '--headless=new', '--no-sandbox', '--no-first-run', '--no-default-browser-check', '--disable-dev-shm-usage',
  '--use-angle=swiftshader', '--enable-unsafe-swiftshader', '--window-size=1320,740', '--hide-scrollbars',
  '--remote-debugging-pipe', `--user-data-dir=${profile}`, 'about:blank'],
  // fd 3: commands in, fd 4: replies out; its own process group, so that
  // its helper processes (GPU, renderer, crash handler) end with it.
  {stdio: ['ignore', 'ignore', 'pipe', 'pipe', 'pipe'], detached: true});
let browserLog = '';
browser.stderr.on('data', (d) => { browserLog += d; });

function fail(why) {
  console.log(JSON.stringify({ok: false, error: why, browser: browserLog.slice(-2000)}));
  finish(1);
}
function finish(code) {
  // The profile is removed once the browser has exited (it writes to it). A
  // helper process may still write a file while the directory goes: retry,
  // and never let the clean-up turn a finished probe into a failure.
  const done = () => {
    for (let attempt = 1; ; ++attempt) {
      try {
        fs.rmSync(profile, {recursive: true, force: true});
        break;
      } catch (e) {
        if (attempt === 20) {
          process.stderr.write(`page_probe: could not remove ${profile}: ${e.code}\n`);
          break;
        }
        Atomics.wait(new Int32Array(new SharedArrayBuffer(4)), 0, 0, 50);  // 50 ms
      }
    }
    process.exit(code);
  };
  if (browser.exitCode !== null || browser.signalCode !== null) done();
  browser.once('exit', done);
  try {
    process.kill(-browser.pid, 'SIGKILL');  // the whole group
  } catch {
    browser.kill('SIGKILL');
  }
}

// DevTools messages over Chromium's pipe: JSON, each ended by a NUL byte.
// `sessionId` addresses a page attached with Target.attachToTarget (flatten).
function devtoolsPipe() {
  const commands = browser.stdio[3], replies = browser.stdio[4];
  let next = 1, pending = Buffer.alloc(0);
  const waiting = new Map();
  replies.on('data', (chunk) => {
    pending = Buffer.concat([pending, chunk]);
    for (let end = pending.indexOf(0); end >= 0; end = pending.indexOf(0)) {
      const msg = JSON.parse(pending.subarray(0, end).toString('utf8'));
      pending = pending.subarray(end + 1);
      if (msg.id && waiting.has(msg.id)) {
        waiting.get(msg.id)(msg);
        waiting.delete(msg.id);
      }
    }
  });
  const call = (method, params = {}, sessionId = undefined) => new Promise((resolve, reject) => {
    if (Date.now() > deadline) return reject(new Error(method + ': past the deadline'));
    const id = next++;
    waiting.set(id, (msg) => msg.error ? reject(new Error(method + ': ' + msg.error.message)) : resolve(msg.result));
    commands.write(JSON.stringify(sessionId ? {id, method, params, sessionId} : {id, method, params}) + '\0');
  });
  return {call};
}

// PNG (8-bit RGB or RGBA, non-interlaced, as Chromium writes it) to pixels.
function decodePng(bytes) {
  let at = 8, width = 0, height = 0, channels = 0;
  const idat = [];
  while (at < bytes.length) {
    const length = bytes.readUInt32BE(at), type = bytes.toString('latin1', at + 4, at + 8);
    const data = bytes.subarray(at + 8, at + 8 + length);
    if (type === 'IHDR') {
      width = data.readUInt32BE(0); height = data.readUInt32BE(4);
      if (data[8] !== 8 || data[12] !== 0) throw new Error('unexpected PNG bit depth or interlace');
      channels = {2: 3, 6: 4}[data[9]];
      if (!channels) throw new Error('unexpected PNG colour type ' + data[9]);
    } else if (type === 'IDAT') idat.push(data);
    at += 12 + length;
  }
  const raw = zlib.inflateSync(Buffer.concat(idat));
  const stride = width * channels, pixels = Buffer.alloc(height * stride);
  for (let y = 0; y < height; ++y) {
    const filter = raw[y * (stride + 1)], line = raw.subarray(y * (stride + 1) + 1, (y + 1) * (stride + 1));
    for (let x = 0; x < stride; ++x) {
      const a = x >= channels ? pixels[y * stride + x - channels] : 0;
      const b = y > 0 ? pixels[(y - 1) * stride + x] : 0;
      const c = x >= channels && y > 0 ? pixels[(y - 1) * stride + x - channels] : 0;
      let p = line[x];
      if (filter === 1) p += a;
      else if (filter === 2) p += b;
      else if (filter === 3) p += (a + b) >> 1;
      else if (filter === 4) {
        const e = a + b - c, pa = Math.abs(e - a), pb = Math.abs(e - b), pc = Math.abs(e - c);
        p += pa <= pb && pa <= pc ? a : pb <= pc ? b : c;
      }
      pixels[y * stride + x] = p & 0xff;
    }
  }
  return {width, height, channels, pixels};
}

function diffAndExit(a, b) {
  const [p, q] = [a, b].map((f) => decodePng(fs.readFileSync(f)));
  let differ = 0;
  for (let y = VIEW.y; y < Math.min(VIEW.y + VIEW.h, p.height, q.height); ++y)
    for (let x = VIEW.x; x < Math.min(VIEW.x + VIEW.w, p.width, q.width); ++x) {
      const i = (y * p.width + x) * p.channels, j = (y * q.width + x) * q.channels;
      if ([0, 1, 2].some((c) => Math.abs(p.pixels[i + c] - q.pixels[j + c]) > 24)) ++differ;
    }
  console.log(JSON.stringify({differingPixels: differ}));
  process.exit(0);
}

try {
  const root = devtoolsPipe();
  let page;
  while (!page && Date.now() < deadline) {  // the first tab appears once the browser is up
    page = (await root.call('Target.getTargets')).targetInfos.find((t) => t.type === 'page');
    if (!page) await sleep(100);
  }
  if (!page) throw new Error('chromium opened no page');
  const {sessionId} = await root.call('Target.attachToTarget', {targetId: page.targetId, flatten: true});
  const cdp = {call: (method, params = {}) => root.call(method, params, sessionId)};
  await cdp.call('Page.enable');
  // The page's size, whatever the window's decorations take.
  await cdp.call('Emulation.setDeviceMetricsOverride', {width: 1320, height: 740, deviceScaleFactor: 1, mobile: false});
  for (let k = 0; k + 1 < pages.length; k += 2) await probePage(cdp, pages[k], pages[k + 1]);
  finish(0);
} catch (e) {
  fail(String(e && e.stack || e));
}

async function probePage(cdp, url, pngPath) {
  await cdp.call('Page.navigate', {url});
  const read = async (expr) => (await cdp.call('Runtime.evaluate', {expression: expr, returnByValue: true})).result.value;
  let shown = null;
  while (Date.now() < deadline) {
    shown = await read(`(() => ({
      framesDrawn: Number(document.body ? document.body.dataset.framesDrawn || 0 : 0),
      timeS: document.body && document.body.dataset.timeS !== undefined ? Number(document.body.dataset.timeS) : null,
      error: document.getElementById('error') && !document.getElementById('error').hidden
          ? document.getElementById('error').textContent : '',
      status: document.getElementById('status') ? document.getElementById('status').textContent : '',
      rigInputs: window.sinewView && window.sinewView.rig ? window.sinewView.rig.inputs.map((i) => i.name) : [],
      inputRows: [...document.querySelectorAll('#inputs tbody tr')].map((r) => [...r.cells].map((c) => c.textContent)),
      chart: document.getElementById('chart-summary') ? document.getElementById('chart-summary').textContent : '',
      // The drawn frame's skeleton and SPH particles' centroid, metres.
      joints: window.sinewView && window.sinewView.lastMessage ? Array.from(window.sinewView.lastMessage.data.joints) : [],
      sphCentroid: (() => {
        const p = window.sinewView && window.sinewView.lastMessage ? window.sinewView.lastMessage.data.sph_position : null;
        if (!p || p.length === 0) return null;
        const c = [0, 0, 0];
        for (let k = 0; k < p.length; ++k) c[k % 3] += p[k] / (p.length / 3);
        return c;
      })()
    }))()`);
    // MIN_FRAMES 0: wait for the error banner instead (a rig/stream mismatch).
    const ready = (s) => s && (minFrames > 0 ? s.framesDrawn >= minFrames : s.error !== '');
    if (ready(shown)) break;
    await sleep(200);
  }
  if (!(shown && (minFrames > 0 ? shown.framesDrawn >= minFrames : shown.error !== '')))
    throw new Error('the page drew ' + (shown ? shown.framesDrawn : 0) + ' frames before the timeout: ' +
                    JSON.stringify(shown));
  await sleep(300);  // the last frame's panels
  const shot = await cdp.call('Page.captureScreenshot', {format: 'png'});
  const png = Buffer.from(shot.data, 'base64');
  fs.writeFileSync(pngPath, png);
  const image = decodePng(png);
  let drawn = 0;
  for (let y = VIEW.y; y < Math.min(VIEW.y + VIEW.h, image.height); ++y)
    for (let x = VIEW.x; x < Math.min(VIEW.x + VIEW.w, image.width); ++x) {
      const at = (y * image.width + x) * image.channels;
      const d = Math.max(...[0, 1, 2].map((c) => Math.abs(image.pixels[at + c] - BACKGROUND[c])));
      if (d > 24) ++drawn;
    }
  console.log(JSON.stringify({ok: true, url, ...shown, width: image.width, height: image.height,
                              viewPixels: VIEW.w * VIEW.h, drawnPixels: drawn}));
}
