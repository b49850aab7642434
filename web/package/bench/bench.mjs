// node bench/bench.mjs BUNDLE_FOLDER [STEPS]: the WebAssembly side of web/README.md's figures,
// the same work web/native/bench.cpp (plimsoll_web_bench) times natively: loading the bundle from
// memory (files read first; the first evaluation, which builds the tiles, included), one
// evaluation on the bundle's own water, one Body.step (1/240 s) and one Simulation frame.
// Medians of 5 rounds; one line of JSON.
import { readdirSync, readFileSync, statSync } from 'node:fs';
import { join, relative } from 'node:path';
import { performance } from 'node:perf_hooks';

import { loadRuntime } from '../index.js';

const [folder, stepsText = '2000'] = process.argv.slice(2);
const steps = Number(stepsText);
const files = new Map();
const walk = (dir) => {
  for (const name of readdirSync(dir)) {
    const path = join(dir, name);
    if (statSync(path).isDirectory()) walk(path);
    else files.set(relative(folder, path), new Uint8Array(readFileSync(path)));
  }
};
walk(folder);
const median = (v) => [...v].sort((a, b) => a - b)[v.length >> 1];

const t = performance.now();
const runtime = await loadRuntime();
const instantiateMs = performance.now() - t;
const load = [], evaluate = [], step = [], frame = [];
let bundle;
for (let round = 0; round < 5; ++round) {
  bundle?.dispose();
  const t0 = performance.now();
  bundle = runtime.loadBundle(files, { name: 'bench' });
  bundle.evaluate({ position: [0, 0, 0] });
  load.push(performance.now() - t0);
}
const dt = 1 / 240;
let sink = 0;
for (let round = 0; round < 5; ++round) {
  const start = bundle.world.start;
  let t0 = performance.now();
  for (let i = 0; i < steps; ++i) {
    const pose = { position: [start.position[0], start.position[1] + 0.001 * (i % 50), start.position[2]], orientation: start.orientation };
    sink += bundle.evaluate(pose, {}, { time: i * dt }).submergedVolume;
  }
  evaluate.push((1000 * (performance.now() - t0)) / steps);
  const body = bundle.createBody();
  t0 = performance.now();
  for (let i = 0; i < steps; ++i) body.step(dt, { time: i * dt });
  step.push((1000 * (performance.now() - t0)) / steps);
  sink += body.state.position[1];
  body.dispose();
  const simulation = bundle.createSimulation();
  const frames = Math.max(1, steps >> 2);
  t0 = performance.now();
  for (let i = 0; i < frames; ++i) simulation.advanceFrame();
  frame.push((1000 * (performance.now() - t0)) / frames);
  sink += simulation.state().centerOfMass[1];
  simulation.dispose();
}
console.log(JSON.stringify({
  body: bundle.name, instantiate_ms: +instantiateMs.toFixed(2), load_ms: +median(load).toFixed(2),
  evaluate_us: +median(evaluate).toFixed(1), step_us: +median(step).toFixed(1), frame_us: +median(frame).toFixed(1),
  check: +sink.toPrecision(3),
}));
