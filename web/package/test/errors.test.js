// Bad input: a damaged or incomplete bundle is refused with a message naming the file and the
// problem, and bad arguments with the call and the argument.
import assert from 'node:assert/strict';
import { readdirSync, readFileSync, statSync } from 'node:fs';
import { join, relative } from 'node:path';
import { test } from 'node:test';

import { PlimsollError } from '../index.js';
import { exportProject, missing, theRuntime } from './helpers.js';

const skip = missing() ?? false;

function files(folder) {
  const out = new Map();
  const walk = (dir) => {
    for (const name of readdirSync(dir)) {
      const path = join(dir, name);
      if (statSync(path).isDirectory()) walk(path);
      else out.set(relative(folder, path), new Uint8Array(readFileSync(path)));
    }
  };
  walk(folder);
  return out;
}

test('a truncated file is named, with its size against the manifest\'s', { skip }, async () => {
  const rt = await theRuntime();
  const bundle = files(exportProject('buoy.plim.json'));
  const samples = bundle.get('samples.exr');
  bundle.set('samples.exr', samples.subarray(0, samples.length - 5));
  assert.throws(() => rt.loadBundle(bundle, { name: 'pak' }),
    (e) => e instanceof PlimsollError && /pak\/samples\.exr/.test(e.message) && /truncated|bytes/.test(e.message));
});

test('a missing file is named', { skip }, async () => {
  const rt = await theRuntime();
  const bundle = files(exportProject('buoy.plim.json'));
  bundle.delete('samples.exr');
  assert.throws(() => rt.loadBundle(bundle, { name: 'pak' }), /samples\.exr/);
});

test('unverified, the decoder still refuses an image that is not OpenEXR', { skip }, async () => {
  const rt = await theRuntime();
  const bundle = files(exportProject('buoy.plim.json'));
  const samples = new Uint8Array(bundle.get('samples.exr'));
  samples[0] ^= 0xff;  // no longer OpenEXR's magic number
  bundle.set('samples.exr', samples);
  assert.throws(() => rt.loadBundle(bundle, { name: 'pak', verify: false }), /samples\.exr/);
});

test('a pose with NaN is refused, naming it', { skip }, async () => {
  const rt = await theRuntime();
  const bundle = rt.loadBundle(files(exportProject('buoy.plim.json')));
  assert.throws(() => bundle.evaluate({ position: [NaN, 0, 0] }), /evaluate: .*NaN/);
  assert.throws(() => bundle.evaluate({ position: [0, 0, 0] }, {}, { water: 'sea' }), /water/);
  bundle.dispose();
});
