// Opens the viewer page in headless Chromium and reports what it computed: serves SITE (a folder
// `plimsoll export --web` wrote) on a localhost port, starts Chromium with the DevTools protocol,
// loads index.html?deterministic=1&seconds=S, waits for window.plimsollResult, saves a
// screenshot to SCREENSHOT and prints the result as one line of JSON. Node's standard library
// only (its own small WebSocket client). Exits 1 on any failure, naming it.
// With --interactive it loads the interactive page instead, lets it run, drops a second body
// (the page's button), clicks the first to push it, and reports the bodies' states, the frame
// and physics times and how fast the pushed body moved just after the click.
//   node browser-run.mjs SITE SECONDS SCREENSHOT [CHROMIUM] [--interactive]
import { spawn } from 'node:child_process';
import { createHash, randomBytes } from 'node:crypto';
import { mkdtempSync, readFileSync, rmSync, statSync, writeFileSync } from 'node:fs';
import { createServer } from 'node:http';
import { connect } from 'node:net';
import { tmpdir } from 'node:os';
import { extname, join, normalize, resolve, sep } from 'node:path';

const interactive = process.argv.includes('--interactive');
const [site, seconds = '10', screenshot, chromium = '/usr/bin/chromium'] = process.argv.slice(2).filter((a) => a !== '--interactive');
if (!site || !screenshot) {
  console.error('usage: node browser-run.mjs SITE SECONDS SCREENSHOT [CHROMIUM]');
  process.exit(2);
}
const root = resolve(site);
const TYPES = {
  '.html': 'text/html', '.js': 'text/javascript', '.mjs': 'text/javascript', '.json': 'application/json',
  '.wasm': 'application/wasm', '.gltf': 'model/gltf+json', '.bin': 'application/octet-stream',
  '.png': 'image/png', '.exr': 'application/octet-stream',
};
const timeoutMs = 180000;
const fail = (message) => { console.error(`browser-run: ${message}`); process.exit(1); };
setTimeout(() => fail(`no result after ${timeoutMs / 1000} s`), timeoutMs).unref();

// The static server: files under root only.
const server = createServer((request, response) => {
  const path = normalize(join(root, decodeURIComponent(new URL(request.url, 'http://x').pathname)));
  let file = path;
  try {
    if (!(path + sep).startsWith(root + sep) && path !== root) throw new Error('outside');
    if (statSync(file).isDirectory()) file = join(file, 'index.html');
    const body = readFileSync(file);
    response.writeHead(200, { 'content-type': TYPES[extname(file)] ?? 'application/octet-stream' });
    response.end(body);
  } catch {
    response.writeHead(404);
    response.end();
  }
});
await new Promise((ok) => server.listen(0, '127.0.0.1', ok));
const page = `http://127.0.0.1:${server.address().port}/index.html${interactive ? '' : `?deterministic=1&seconds=${seconds}`}`;

// Chromium: headless, WebGL through its software rasteriser, DevTools on a port it picks.
const profile = mkdtempSync(join(tmpdir(), 'plimsoll-chromium-'));
const browser = spawn(chromium, [
  '--headless', '--no-sandbox', '--disable-gpu-sandbox', '--use-angle=swiftshader', '--enable-unsafe-swiftshader',
  '--no-first-run', '--no-default-browser-check', `--user-data-dir=${profile}`, '--remote-debugging-port=0',
  '--window-size=1280,800', 'about:blank',
], { stdio: ['ignore', 'ignore', 'pipe'] });
const cleanup = () => {
  browser.kill('SIGKILL');
  server.close();
  try { rmSync(profile, { recursive: true, force: true }); } catch { /* it may still hold files */ }
};
process.on('exit', cleanup);
let stderr = '';
const endpoint = await new Promise((ok) => {
  browser.stderr.on('data', (chunk) => {
    stderr += chunk;
    const m = /DevTools listening on (ws:\/\/\S+)/.exec(stderr);
    if (m) ok(m[1]);
  });
  browser.on('exit', (code) => fail(`chromium exited (${code}) before DevTools started:\n${stderr.slice(-2000)}`));
});

// A WebSocket client, enough for the DevTools protocol: text frames, masked from the client.
function websocket(url) {
  const u = new URL(url);
  const socket = connect(Number(u.port), u.hostname);
  const key = randomBytes(16).toString('base64');
  const listeners = [];
  let buffer = Buffer.alloc(0), open = false, fragments = [];
  const ready = new Promise((ok, no) => {
    socket.on('connect', () => socket.write(`GET ${u.pathname} HTTP/1.1\r\nHost: ${u.host}\r\nUpgrade: websocket\r\n` +
      `Connection: Upgrade\r\nSec-WebSocket-Key: ${key}\r\nSec-WebSocket-Version: 13\r\n\r\n`));
    socket.on('error', no);
    socket.on('data', (chunk) => {
      buffer = Buffer.concat([buffer, chunk]);
      if (!open) {
        const end = buffer.indexOf('\r\n\r\n');
        if (end < 0) return;
        const head = buffer.subarray(0, end).toString();
        const accept = createHash('sha1').update(key + '258EAFA5-E914-47DA-95CA-C5AB0DC85B11').digest('base64');
        if (!/^HTTP\/1\.1 101/.test(head) || !head.includes(accept)) return no(new Error(`handshake refused: ${head}`));
        open = true;
        buffer = buffer.subarray(end + 4);
        ok();
      }
      for (;;) {
        if (buffer.length < 2) return;
        const opcode = buffer[0] & 0x0f, fin = buffer[0] & 0x80;
        let length = buffer[1] & 0x7f, at = 2;
        if (length === 126) { if (buffer.length < 4) return; length = buffer.readUInt16BE(2); at = 4; }
        else if (length === 127) { if (buffer.length < 10) return; length = Number(buffer.readBigUInt64BE(2)); at = 10; }
        if (buffer.length < at + length) return;
        const payload = buffer.subarray(at, at + length);
        buffer = buffer.subarray(at + length);
        if (opcode === 0x8) return socket.end();
        if (opcode === 0x9 || opcode === 0xa) continue;
        fragments.push(payload);
        if (!fin) continue;
        const text = Buffer.concat(fragments).toString();
        fragments = [];
        for (const listener of listeners) listener(JSON.parse(text));
      }
    });
  });
  const send = (object) => {
    const payload = Buffer.from(JSON.stringify(object));
    const mask = randomBytes(4);
    const n = payload.length;
    const head = n < 126 ? Buffer.from([0x81, 0x80 | n])
      : n < 65536 ? Buffer.from([0x81, 0x80 | 126, n >> 8, n & 0xff])
        : Buffer.concat([Buffer.from([0x81, 0x80 | 127]), (() => { const b = Buffer.alloc(8); b.writeBigUInt64BE(BigInt(n)); return b; })()]);
    const masked = Buffer.from(payload.map((byte, i) => byte ^ mask[i & 3]));
    socket.write(Buffer.concat([head, mask, masked]));
  };
  return { ready, send, on: (listener) => listeners.push(listener) };
}

const ws = websocket(endpoint);
await ws.ready;
let nextId = 1;
const pending = new Map();
const messages = [];
ws.on((message) => {
  if (message.id && pending.has(message.id)) {
    const { ok, no } = pending.get(message.id);
    pending.delete(message.id);
    if (message.error) no(new Error(JSON.stringify(message.error)));
    else ok(message.result);
  } else if (message.method === 'Runtime.consoleAPICalled' || message.method === 'Runtime.exceptionThrown') {
    messages.push(JSON.stringify(message.params).slice(0, 400));
  }
});
const call = (method, params = {}, sessionId) => new Promise((ok, no) => {
  const id = nextId++;
  pending.set(id, { ok, no });
  ws.send({ id, method, params, ...(sessionId ? { sessionId } : {}) });
});

const { targetId } = await call('Target.createTarget', { url: 'about:blank' });
const { sessionId } = await call('Target.attachToTarget', { targetId, flatten: true });
await call('Runtime.enable', {}, sessionId);
await call('Page.enable', {}, sessionId);
const started = Date.now();
await call('Page.navigate', { url: page }, sessionId);
const evaluate = async (expression) => {
  const { result: value, exceptionDetails } = await call('Runtime.evaluate', { expression, returnByValue: true }, sessionId);
  if (exceptionDetails) fail(`${expression}: ${JSON.stringify(exceptionDetails).slice(0, 400)}`);
  return value.value;
};
const waitFor = async (expression, what) => {
  for (;;) {
    const error = await evaluate('JSON.stringify(window.plimsollResult?.error ?? null)');
    if (JSON.parse(error ?? 'null')) fail(`the page failed: ${JSON.parse(error)}\n${messages.join('\n')}`);
    if (await evaluate(expression)) return;
    if (Date.now() - started > timeoutMs - 10000) fail(`waited in vain for ${what}; the page's console:\n${messages.join('\n')}`);
    await new Promise((ok) => setTimeout(ok, 100));
  }
};
if (interactive) {
  await waitFor('(window.plimsollViewer?.frames ?? 0) >= 20', '20 frames');
  await evaluate("document.getElementById('drop').click()");
  await waitFor('window.plimsollViewer.bodies.length === 2', 'the dropped body');
  const at = await evaluate('window.plimsollViewer.screen(0)');
  const before = await evaluate('window.plimsollViewer.frames');
  for (const type of ['mousePressed', 'mouseReleased'])
    await call('Input.dispatchMouseEvent', { type, x: at.x, y: at.y, button: 'left', clickCount: 1 }, sessionId);
  await waitFor(`window.plimsollViewer.frames >= ${before} + 2`, 'a frame after the push');
  const pushed = await evaluate('JSON.stringify(window.plimsollViewer.bodies[0])');
  const runFor = Number(seconds);
  await waitFor(`window.plimsollViewer.time >= ${runFor}`, `${runFor} simulated seconds`);
  const state = JSON.parse(await evaluate('JSON.stringify(window.plimsollViewer)'));
  const shot = await call('Page.captureScreenshot', { format: 'png' }, sessionId);
  writeFileSync(screenshot, Buffer.from(shot.data, 'base64'));
  const v = JSON.parse(pushed).velocity;
  console.log(JSON.stringify({
    frames: state.frames, time: state.time, frameMs: state.frameMs, physicsMs: state.physicsMs, bodies: state.bodies,
    pushedSpeed: Math.hypot(v[0], v[2]), screenshot, pageMs: Date.now() - started,
  }));
  process.exit(0);
}
let result = null;
while (!result) {
  await new Promise((ok) => setTimeout(ok, 200));
  const { result: value } = await call('Runtime.evaluate',
    { expression: 'JSON.stringify(window.plimsollResult ?? null)', returnByValue: true }, sessionId);
  result = JSON.parse(value.value ?? 'null');
  if (Date.now() - started > timeoutMs - 10000) fail(`the page gave no result; its console:\n${messages.join('\n')}`);
}
if (result.error) fail(`the page failed: ${result.error}\n${messages.join('\n')}`);
const shot = await call('Page.captureScreenshot', { format: 'png' }, sessionId);
writeFileSync(screenshot, Buffer.from(shot.data, 'base64'));
result.pageMs = Date.now() - started;
result.screenshot = screenshot;
console.log(JSON.stringify(result));
process.exit(0);
