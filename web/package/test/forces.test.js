// The module's forces against the native runtime's (plimsoll_web_reference, built from the same
// sources by scripts/build-web.sh) on a few hundred poses per bundle: the bundle's own water
// (Gerstner waves where the project has them) and flat water, every number equal to the bit.
import assert from 'node:assert/strict';
import { execFileSync } from 'node:child_process';
import { test } from 'node:test';

import { exportProject, missing, random, reference, theRuntime } from './helpers.js';

const skip = missing() ?? false;
const POSES = 300;

function poses(bundle, seed) {
  const next = random(seed);
  const span = Math.max(...bundle.bounds.max.map((v, i) => v - bundle.bounds.min[i]));
  const out = [];
  for (let i = 0; i < POSES; ++i) {
    const q = [next() - 0.5, next() - 0.5, next() - 0.5, next() - 0.5];
    const n = Math.hypot(...q);
    out.push({
      water: i % 3 === 2 ? String(0.05 * span) : 'own',
      time: 10 * next(),
      position: [span * (next() - 0.5), span * (1.2 * next() - 0.6), span * (next() - 0.5)],
      orientation: q.map((c) => c / n),
      linear: [next() - 0.5, next() - 0.5, next() - 0.5],
      angular: [next() - 0.5, next() - 0.5, next() - 0.5],
    });
  }
  return out;
}

const FIELDS = ['submergedVolume', 'centerOfBuoyancy', 'force', 'torque', 'pressureForce', 'pressureTorque',
  'dragForce', 'dragTorque', 'wettedArea', 'submergedSamples'];
const flatten = (f) => FIELDS.flatMap((k) => f[k]);

for (const project of ['buoy.plim.json', 'damaged_boat.plim.json']) {
  test(`forces equal the native runtime's: ${project}`, { skip }, async () => {
    const rt = await theRuntime();
    const folder = exportProject(project);
    const bundle = await rt.fetchBundle(folder);
    const list = poses(bundle, project.length);
    const lines = list.map((p) => [p.water, p.time, ...p.position, ...p.orientation, ...p.linear, ...p.angular]
      .map((v) => (typeof v === 'number' ? v.toPrecision(17) : v)).join(' ')).join('\n');
    const expected = execFileSync(reference, [folder], { input: `${lines}\n` }).toString().trim().split('\n');
    assert.equal(expected.length, list.length);
    let wet = 0;
    list.forEach((p, i) => {
      // Parsing the printed numbers gives back the very doubles: a pose's text is its value.
      const pose = { position: p.position.map((v) => Number(v.toPrecision(17))), orientation: p.orientation.map((v) => Number(v.toPrecision(17))) };
      const velocity = { linear: p.linear.map((v) => Number(v.toPrecision(17))), angular: p.angular.map((v) => Number(v.toPrecision(17))) };
      const water = p.water === 'own' ? 'bundle' : Number(p.water);
      const got = flatten(bundle.evaluate(pose, velocity, { water, time: Number(p.time.toPrecision(17)) }));
      const want = expected[i].split(' ').map(Number);
      assert.deepEqual(got, want, `pose ${i} (${p.water} water)`);
      if (got[0] > 0) ++wet;
    });
    // The poses reach the water: at least a third of them are partly submerged.
    assert.ok(wet > POSES / 3, `${wet} of ${POSES} poses touch the water`);
    bundle.dispose();
  });
}

test('a JavaScript height callback is asked in batches and gives the bundle water\'s forces', { skip }, async () => {
  const rt = await theRuntime();
  const bundle = await rt.fetchBundle(exportProject('buoy.plim.json'));
  let calls = 0, largest = 0;
  const water = {
    level: bundle.world.water.level,
    heights(x, z, time, out) {
      ++calls;
      largest = Math.max(largest, x.length);
      bundle.waterHeights(x, z, time, out);
    },
    velocities(x, y, z, time, out) { out.fill(0); },
  };
  const flatOwn = { level: bundle.world.water.level, heights: (x, z, t, out) => out.fill(bundle.world.water.level) };
  const next = random(7);
  for (let i = 0; i < 50; ++i) {
    const pose = { position: [next() - 0.5, next() - 0.8, next() - 0.5], orientation: [1, 0, 0, 0] };
    const time = 5 * next();
    const viaCallback = bundle.evaluate(pose, {}, { water, time });
    const own = bundle.evaluate(pose, {}, { water: 'bundle', time });
    // Hydrostatics depend on the heights only; the drag differs (the callback's water is still).
    for (const k of ['submergedVolume', 'centerOfBuoyancy', 'pressureForce', 'pressureTorque', 'wettedArea'])
      assert.deepEqual(viaCallback[k], own[k], `${k} at pose ${i}`);
    assert.ok(Number.isFinite(bundle.evaluate(pose, {}, { water: flatOwn, time }).submergedVolume));
  }
  assert.ok(largest > 1, `the callback was asked ${largest} points at most per call`);
  assert.ok(calls > 0);
  bundle.dispose();
});

test('a callback that throws fails the call with its own error', { skip }, async () => {
  const rt = await theRuntime();
  const bundle = await rt.fetchBundle(exportProject('buoy.plim.json'));
  const water = { heights() { throw new Error('no sea today'); } };
  assert.throws(() => bundle.evaluate({ position: [0, 0, 0] }, {}, { water }), /no sea today/);
  // ... and the next call is unaffected.
  assert.ok(bundle.evaluate({ position: [0, 0, 0] }).submergedVolume > 0);
  bundle.dispose();
});

test('a callback that returns NaN is refused, naming the point', { skip }, async () => {
  const rt = await theRuntime();
  const bundle = await rt.fetchBundle(exportProject('buoy.plim.json'));
  const water = { heights: (x, z, t, out) => { out.fill(0); out[out.length - 1] = NaN; } };
  assert.throws(() => bundle.evaluate({ position: [0, 0, 0] }, {}, { water }), /heights callback returned NaN at \(/);
  bundle.dispose();
});

for (const project of ['buoy.plim.json', 'damaged_boat.plim.json']) {
  test(`a body stepped 480 times equals the native stepBody's: ${project}`, { skip }, async () => {
    const rt = await theRuntime();
    const folder = exportProject(project);
    const [line] = execFileSync(reference, [folder, '--steps', '480']).toString().trim().split('\n');
    const words = line.split(' ');
    const nativeHash = words.pop();
    const want = words.map(Number);
    const bundle = await rt.fetchBundle(folder);
    const body = bundle.createBody();
    const dt = 1 / 240;
    const waterBefore = body.nodeWater().reduce((s, v) => s + v, 0);
    for (let i = 0; i < 480; ++i) body.step(dt, { time: i * dt });
    const st = body.state;
    const load = body.waterLoad(dt, { time: 480 * dt });
    const got = [...st.position, ...st.orientation, ...st.velocity, ...st.angularVelocity, ...flatten(load.forces),
      load.waterMass, ...load.force, ...load.torque];
    assert.deepEqual(got, want);
    assert.equal(body.stateHash(), nativeHash);
    if (bundle.nodeCapacities.length) assert.ok(body.nodeWater().reduce((s, v) => s + v, 0) !== waterBefore, 'the water inside moved');
    body.dispose();
    bundle.dispose();
  });
}
