// The module's replay of a bundle's own world against the native float_body --csv (built from
// the same sources by scripts/build-web.sh): the same CSV text and the same state hash, for the
// buoy (waves) and the damaged boat (flooding).
import assert from 'node:assert/strict';
import { execFileSync } from 'node:child_process';
import { mkdtempSync, readFileSync, rmSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { join } from 'node:path';
import { test } from 'node:test';

import { exportProject, floatBody, missing, theRuntime } from './helpers.js';

const skip = missing() ?? false;
const SECONDS = 10;

for (const project of ['buoy.plim.json', 'damaged_boat.plim.json']) {
  test(`replay equals native float_body --csv: ${project}`, { skip }, async () => {
    const folder = exportProject(project);
    const dir = mkdtempSync(join(tmpdir(), 'plimsoll-web-csv-'));
    try {
      const stdout = execFileSync(floatBody, [folder, String(SECONDS), '--csv', join(dir, 'native.csv')]).toString();
      const nativeHash = /state hash ([0-9a-f]{16})/.exec(stdout)?.[1];
      assert.ok(nativeHash, `float_body printed no hash: ${stdout}`);
      const rt = await theRuntime();
      const bundle = await rt.fetchBundle(folder);
      const simulation = bundle.createSimulation();
      const before = simulation.nodeWater().reduce((s, v) => s + v, 0);
      const { csv, stateHash, frames } = simulation.replay(SECONDS);
      assert.equal(frames, Math.ceil(SECONDS / bundle.world.timeStep - 1e-9));
      const nativeCsv = readFileSync(join(dir, 'native.csv'), 'utf8');
      const a = csv.split('\n'), b = nativeCsv.split('\n');
      const first = a.findIndex((row, i) => row !== b[i]);
      assert.equal(first, -1, `row ${first} differs:\n  web    ${a[first]}\n  native ${b[first]}`);
      assert.equal(stateHash, nativeHash);
      if (project.startsWith('damaged')) {
        // The boat floods: water came in during the run.
        const after = simulation.nodeWater().reduce((s, v) => s + v, 0);
        assert.ok(after > before, `water inside: ${before} m^3 at the start, ${after} after ${SECONDS} s`);
      }
      simulation.dispose();
      bundle.dispose();
    } finally {
      rmSync(dir, { recursive: true, force: true });
    }
  });
}
