// What the package's tests share: the repository's tools (the plimsoll CLI to export bundles, the
// native runtime built by scripts/build-web.sh from the same sources), the module, and bundles
// exported once per test run into a temporary folder.
import { execFileSync } from 'node:child_process';
import { existsSync, mkdtempSync, readdirSync, rmSync, statSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { dirname, join, resolve } from 'node:path';
import { fileURLToPath } from 'node:url';

import { loadRuntime } from '../index.js';

export const repo = resolve(dirname(fileURLToPath(import.meta.url)), '../../..');
export const cli = process.env.PLIMSOLL_CLI ?? join(repo, 'build/editor/plimsoll');
export const native = process.env.PLIMSOLL_WEB_NATIVE ?? join(repo, 'build-web/native');
export const floatBody = join(native, 'runtime/plimsoll_float_body');
export const reference = join(native, 'plimsoll_web_reference');
export const wasm = join(repo, 'web/package/plimsoll.wasm');

/** Why the tests that need the native side cannot run, or null. */
export function missing() {
  if (!existsSync(wasm)) return `${wasm} not built (scripts/build-web.sh)`;
  if (!existsSync(cli)) return `${cli} not built (scripts/build.sh; or set PLIMSOLL_CLI)`;
  if (!existsSync(floatBody) || !existsSync(reference))
    return `${native} has no float_body or plimsoll_web_reference (scripts/build-web.sh; or set PLIMSOLL_WEB_NATIVE)`;
  return null;
}

let work = null;
const exported = new Map();
process.on('exit', () => { if (work) rmSync(work, { recursive: true, force: true }); });

/** The folder of the one body `plimsoll export PROJECT` writes (exported once per run). */
export function exportProject(project) {
  if (exported.has(project)) return exported.get(project);
  work ??= mkdtempSync(join(tmpdir(), 'plimsoll-web-test-'));
  const out = join(work, project.replace(/\W/g, '_'));
  execFileSync(cli, ['export', join(repo, 'projects', project), '--out', out, '--quiet'], { stdio: 'pipe' });
  const bodies = [];
  const walk = (dir) => {
    for (const name of readdirSync(dir)) {
      const path = join(dir, name);
      if (statSync(path).isDirectory()) walk(path);
      else if (name === 'manifest.json') bodies.push(dir);
    }
  };
  walk(out);
  if (bodies.length !== 1) throw new Error(`${project}: expected one body, found ${bodies.length}`);
  exported.set(project, bodies[0]);
  return bodies[0];
}

let runtime = null;
export async function theRuntime() {
  runtime ??= await loadRuntime(wasm);
  return runtime;
}

/** xorshift64*: the same poses on every run. */
export function random(seed) {
  let s = BigInt(seed) || 1n;
  return () => {
    s ^= s >> 12n; s ^= (s << 25n) & 0xffffffffffffffffn; s ^= s >> 27n;
    return Number(((s * 0x2545f4914f6cdd1dn) & 0xffffffffffffffffn) >> 11n) / 2 ** 53;
  };
}
