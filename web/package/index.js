// The Plimsoll runtime in WebAssembly: load a bundle exported by `plimsoll export`, evaluate
// buoyancy, pressure and drag, float bodies of it and replay its own world as the native
// runtime does, bit for bit (web/README.md). One ES module for node and browsers: it
// instantiates plimsoll.wasm (a standalone module, no emscripten glue) itself.

const WAVE_FIELDS = ['amplitude', 'wavelength', 'directionX', 'directionZ', 'steepness', 'phase'];
const FORCE_FIELDS = 24;
const STATE_FIELDS = 13;
const WATER_OWN = 0;
const WATER_FLAT = 1;
const WATER_CALLBACK = 2;
const WATER_KINDS = ['flat', 'gerstner', 'grid'];

/** A failure of a runtime call: the runtime's message, naming the file or argument. */
export class PlimsollError extends Error {
  constructor(message) {
    super(message);
    this.name = 'PlimsollError';
  }
}

const isNode = typeof process !== 'undefined' && process.versions != null && process.versions.node != null;

async function wasmBytes(source) {
  if (source instanceof ArrayBuffer || ArrayBuffer.isView(source)) return source;
  const url = source ?? new URL('./plimsoll.wasm', import.meta.url);
  const href = url instanceof URL ? url.href : String(url);
  if (isNode && (href.startsWith('file:') || !/^[a-z]+:/i.test(href))) {
    const { readFile } = await import('node:fs/promises');
    return readFile(href.startsWith('file:') ? new URL(href) : href);
  }
  const response = await fetch(href);
  if (!response.ok) throw new PlimsollError(`${href}: HTTP ${response.status} ${response.statusText}`);
  return response.arrayBuffer();
}

/**
 * Loads the WebAssembly module. `wasm`: its URL or path, or its bytes (default: plimsoll.wasm
 * beside this file). Resolves to a Runtime.
 */
export async function loadRuntime(wasm) {
  const bytes = await wasmBytes(wasm);
  const runtime = new Runtime();
  const imports = runtime._imports();
  const module = await WebAssembly.compile(bytes);
  // Whatever else the module imports (the C library's exit and environment) gets an answer that
  // says no: the runtime reads no environment and never exits.
  for (const { module: from, name, kind } of WebAssembly.Module.imports(module)) {
    if (kind !== 'function') continue;
    imports[from] ??= {};
    imports[from][name] ??= name === 'environ_sizes_get'
      ? (count, size) => { runtime._u32()[count >> 2] = 0; runtime._u32()[size >> 2] = 0; return 0; }
      : name === 'environ_get' ? () => 0
      : (...args) => { throw new PlimsollError(`plimsoll.wasm called ${from}.${name}(${args.join(', ')})`); };
  }
  const instance = await WebAssembly.instantiate(module, imports);
  runtime._attach(instance.exports);
  return runtime;
}

function flatWater(level) {
  if (!Number.isFinite(level)) throw new PlimsollError(`water level ${level} is not finite`);
  return { mode: WATER_FLAT, level, id: 0, velocities: 0, min: -Infinity, max: Infinity };
}

export class Runtime {
  constructor() {
    this._callbacks = new Map();
    this._nextCallback = 1;
    this._callbackError = null;
  }

  _imports() {
    const env = {
      emscripten_notify_memory_growth: () => {},
      pw_js_heights: (id, n, x, z, time, out) => this._heights(id, n, x, z, time, out),
      pw_js_velocities: (id, n, x, y, z, time, out) => this._velocities(id, n, x, y, z, time, out),
    };
    return { env, wasi_snapshot_preview1: {} };
  }

  _attach(exports) {
    this._x = exports;
    exports._initialize?.();
    this._scratch = exports.pw_alloc(8 * 256);
    /** The runtime library's version, "major.minor.patch". */
    this.version = this._string(exports.pw_version());
  }

  _f64(ptr, n) { return new Float64Array(this._x.memory.buffer, ptr, n); }
  _u32() { return new Uint32Array(this._x.memory.buffer); }
  _string(ptr) {
    const bytes = new Uint8Array(this._x.memory.buffer, ptr);
    return new TextDecoder().decode(bytes.subarray(0, bytes.indexOf(0)));
  }
  _cstring(text) {
    const bytes = new TextEncoder().encode(text);
    const ptr = this._x.pw_alloc(bytes.length + 1);
    const view = new Uint8Array(this._x.memory.buffer, ptr, bytes.length + 1);
    view.set(bytes);
    view[bytes.length] = 0;
    return ptr;
  }
  /** Throws the call's failure: a water callback's own error first, else the runtime's message. */
  _check(ok, call) {
    if (!ok || this._callbackError) throw this._error(call);
  }
  _error(call) {
    const message = this._string(this._x.pw_last_error());
    const thrown = this._callbackError;
    this._callbackError = null;
    if (thrown) return thrown;
    return new PlimsollError(`${call}: ${message || 'failed'}`);
  }
  _hash(fn, handle) {
    fn(handle, this._scratch);
    const u = this._u32();
    const hi = u[this._scratch >> 2], lo = u[(this._scratch >> 2) + 1];
    return hi.toString(16).padStart(8, '0') + lo.toString(16).padStart(8, '0');
  }

  // The water callbacks the module calls: JavaScript's answer for many points at once.
  _heights(id, n, x, z, time, out) {
    const water = this._callbacks.get(id);
    try {
      const result = water.heights(this._f64(x, n), this._f64(z, n), time, this._f64(out, n));
      if (result != null) this._f64(out, n).set(result);
      const heights = this._f64(out, n);
      const bad = heights.findIndex((h) => !Number.isFinite(h));
      if (bad >= 0) {
        const xs = this._f64(x, n), zs = this._f64(z, n);
        throw new PlimsollError(`water: the heights callback returned ${heights[bad]} at (${xs[bad]}, ${zs[bad]})`);
      }
    } catch (e) {
      this._callbackError ??= e;
      this._f64(out, n).fill(NaN);
    }
  }
  _velocities(id, n, x, y, z, time, out) {
    const water = this._callbacks.get(id);
    try {
      const result = water.velocities(this._f64(x, n), this._f64(y, n), this._f64(z, n), time, this._f64(out, 3 * n));
      if (result != null) this._f64(out, 3 * n).set(result);
      if (this._f64(out, 3 * n).some((v) => !Number.isFinite(v)))
        throw new PlimsollError('water: the velocities callback returned NaN or Inf');
    } catch (e) {
      this._callbackError ??= e;
      this._f64(out, 3 * n).fill(NaN);
    }
  }

  /** The water argument of a call, registered for the call's duration when it is a callback. */
  _water(water) {
    if (water == null || water === 'bundle') return { mode: WATER_OWN, level: 0, id: 0, velocities: 0, min: 0, max: 0 };
    if (typeof water === 'number') return flatWater(water);
    if (typeof water.heights === 'function') {
      const id = this._nextCallback++;
      this._callbacks.set(id, water);
      return {
        mode: WATER_CALLBACK, level: water.level ?? 0, id, velocities: typeof water.velocities === 'function' ? 1 : 0,
        min: water.minHeight ?? -Infinity, max: water.maxHeight ?? Infinity,
      };
    }
    if (typeof water.level === 'number') return flatWater(water.level);
    throw new PlimsollError('water: expected "bundle", a level, {level} or {heights(x, z, time, out)}');
  }
  _release(w) { if (w.mode === WATER_CALLBACK) this._callbacks.delete(w.id); }

  /**
   * Loads a bundle from its files in memory: a Map or an object of path inside the bundle ->
   * bytes (Uint8Array or ArrayBuffer). `options.name` prefixes error messages (default
   * "memory"); `options.verify` (default true) checks every file's size and SHA-256 against
   * the manifest.
   */
  loadBundle(files, options = {}) {
    const entries = files instanceof Map ? [...files.entries()] : Object.entries(files);
    const x = this._x;
    const count = entries.length;
    const table = x.pw_alloc(12 * Math.max(count, 1));
    const owned = [table];
    try {
      for (let i = 0; i < count; ++i) {
        const [path, data] = entries[i];
        const bytes = data instanceof Uint8Array ? data : new Uint8Array(data.buffer ?? data, data.byteOffset ?? 0, data.byteLength);
        const pathPtr = this._cstring(path);
        const dataPtr = x.pw_alloc(bytes.length);
        owned.push(pathPtr, dataPtr);
        new Uint8Array(x.memory.buffer, dataPtr, bytes.length).set(bytes);
        const u = this._u32();
        u[(table >> 2) + i] = pathPtr;
        u[(table >> 2) + count + i] = dataPtr;
        u[(table >> 2) + 2 * count + i] = bytes.length;
      }
      const name = this._cstring(options.name ?? 'memory');
      owned.push(name);
      const handle = x.pw_bundle_load(count, table, table + 4 * count, table + 8 * count, name,
                                      options.verify === false ? 0 : 1);
      if (!handle) throw this._error('loadBundle');
      return new Bundle(this, handle);
    } finally {
      for (const p of owned) x.pw_free(p);
    }
  }

  /**
   * Fetches a bundle folder from `url` (its manifest.json, then every file it lists) and loads
   * it. In node a file: URL or a path reads the files from disk.
   */
  async fetchBundle(url, options = {}) {
    const base = new URL(String(url).endsWith('/') ? String(url) : `${url}/`, isNode && !/^[a-z]+:/i.test(String(url))
      ? `file://${process.cwd()}/` : globalThis.location?.href);
    const read = async (path) => {
      const target = new URL(path, base);
      if (isNode && target.protocol === 'file:') {
        const { readFile } = await import('node:fs/promises');
        return new Uint8Array(await readFile(target));
      }
      const response = await fetch(target);
      if (!response.ok) throw new PlimsollError(`${target.href}: HTTP ${response.status} ${response.statusText}`);
      return new Uint8Array(await response.arrayBuffer());
    };
    const manifestBytes = await read('manifest.json');
    let manifest;
    try {
      manifest = JSON.parse(new TextDecoder().decode(manifestBytes));
    } catch (e) {
      throw new PlimsollError(`${new URL('manifest.json', base).href}: not JSON (${e.message})`);
    }
    const files = new Map([['manifest.json', manifestBytes]]);
    const listed = Array.isArray(manifest.files) ? manifest.files : [];
    await Promise.all(listed.map(async (entry) => {
      const path = typeof entry === 'string' ? entry : entry?.path;
      if (typeof path === 'string' && !files.has(path)) files.set(path, await read(path));
    }));
    return this.loadBundle(files, { name: options.name ?? base.href.replace(/\/$/, ''), verify: options.verify });
  }
}

function pose(p) {
  return [...(p.position ?? [0, 0, 0]), ...(p.orientation ?? [1, 0, 0, 0])];
}

function readForces(v) {
  const at = (i) => [v[i], v[i + 1], v[i + 2]];
  return {
    submergedVolume: v[0], centerOfBuoyancy: at(1), force: at(4), torque: at(7),
    pressureForce: at(10), pressureTorque: at(13), dragForce: at(16), dragTorque: at(19),
    wettedArea: v[22], submergedSamples: v[23],
  };
}

export class Bundle {
  constructor(runtime, handle) {
    this._rt = runtime;
    this._h = handle;
    const x = runtime._x;
    /** The body's name (the manifest's "body"). */
    this.name = runtime._string(x.pw_bundle_body(handle));
    const info = Array.from((x.pw_bundle_info(handle, runtime._scratch), runtime._f64(runtime._scratch, 42)));
    const at = (i) => [info[i], info[i + 1], info[i + 2]];
    /** mass_properties.texture: kg, m^3, object-space centre of mass, inertia (row major). */
    this.mass = { mass: info[0], volume: info[1], centerOfMass: at(2), inertia: info.slice(5, 14) };
    this.sampleCount = info[14];
    this.textureSize = info[41];
    /** The project's medium and the manifest's drag coefficients. */
    this.fluid = { density: info[16], gravity: info[17], dragCoefficient: info[18], frictionCoefficient: info[19] };
    this.damping = { linear: info[20], vertical: info[21], angular: info[22] };
    /** Object-space box around the sample list. */
    this.bounds = { min: at(35), max: at(38) };
    const waves = [];
    for (let i = 0; i < info[27]; ++i) {
      x.pw_bundle_wave(handle, i, runtime._scratch);
      const w = runtime._f64(runtime._scratch, 6);
      waves.push(Object.fromEntries(WAVE_FIELDS.map((k, j) => [k, w[j]])));
    }
    /** The world the body was exported from (schema 1.4): its water, step and start. */
    this.world = {
      timeStep: info[23], subSteps: info[24],
      water: { kind: WATER_KINDS[info[25]] ?? 'flat', level: info[26], waves },
      start: { position: at(28), orientation: [info[31], info[32], info[33], info[34]] },
    };
    const nodes = info[15];
    /** The water graph's node capacities (m^3); empty without a graph. */
    this.nodeCapacities = Array.from({ length: nodes }, (_, i) => x.pw_bundle_node_capacity(handle, i));
  }

  _live() {
    if (!this._h) throw new PlimsollError('the bundle was disposed');
    return this._h;
  }

  /**
   * Buoyancy, pressure and drag for the body at `pose` ({position, orientation [w, x, y, z]})
   * moving with `velocity` ({linear, angular}). options.water: "bundle" (default: the bundle's
   * own flat or Gerstner water), a level, or {heights(x, z, time, out), velocities?, minHeight?,
   * maxHeight?}: one call with arrays of points per batch. options.time (s), options.fluid.
   */
  evaluate(bodyPose, velocity = {}, options = {}) {
    const rt = this._rt, x = rt._x, s = rt._scratch;
    const fluid = { ...this.fluid, ...options.fluid };
    const input = [...pose(bodyPose), ...(velocity.linear ?? [0, 0, 0]), ...(velocity.angular ?? [0, 0, 0]),
      options.time ?? 0, fluid.density, fluid.gravity, fluid.dragCoefficient, fluid.frictionCoefficient];
    rt._f64(s, 18).set(input);
    const w = rt._water(options.water);
    try {
      rt._check(x.pw_bundle_evaluate(this._live(), s, w.mode, w.level, w.id, w.velocities, w.min, w.max, s + 8 * 32),
                'evaluate');
    } finally {
      rt._release(w);
    }
    return readForces(rt._f64(s + 8 * 32, FORCE_FIELDS));
  }

  /** Heights of the bundle's own water at the points (x[i], z[i]) at `time`. */
  waterHeights(xs, zs, time = 0, out = new Float64Array(xs.length)) {
    const rt = this._rt, x = rt._x, n = xs.length;
    const ptr = x.pw_alloc(8 * 3 * Math.max(n, 1));
    try {
      rt._f64(ptr, n).set(xs);
      rt._f64(ptr + 8 * n, n).set(zs);
      x.pw_bundle_water_heights(this._live(), n, ptr, ptr + 8 * n, time, ptr + 16 * n);
      out.set(rt._f64(ptr + 16 * n, n));
    } finally {
      x.pw_free(ptr);
    }
    return out;
  }

  /** A floating body of this bundle (its own water inside, its own state). */
  createBody(state = {}) { return new Body(this, state); }

  /** The bundle's own world, replayed as `plimsoll simulate` and float_body --csv step it. */
  createSimulation() { return new Simulation(this); }

  dispose() {
    if (this._h) this._rt._x.pw_bundle_destroy(this._h);
    this._h = 0;
  }
}

export class Body {
  constructor(bundle, state) {
    this.bundle = bundle;
    this._rt = bundle._rt;
    this._h = this._rt._x.pw_body_create(bundle._live());
    /** Pose of the object origin and velocity of the centre of mass, world axes. */
    this.state = {
      position: state.position ?? [...bundle.world.start.position],
      orientation: state.orientation ?? [...bundle.world.start.orientation],
      velocity: state.velocity ?? [0, 0, 0],
      angularVelocity: state.angularVelocity ?? [0, 0, 0],
    };
  }

  _call(dt, options, out, call) {
    const rt = this._rt, x = rt._x, s = rt._scratch;
    const st = this.state;
    const fluid = { ...this.bundle.fluid, ...options.fluid };
    rt._f64(s, STATE_FIELDS).set([...st.position, ...st.orientation, ...st.velocity, ...st.angularVelocity]);
    rt._f64(s + 8 * 16, 4).set([fluid.density, fluid.gravity, fluid.dragCoefficient, fluid.frictionCoefficient]);
    const w = rt._water(options.water);
    try {
      rt._check(x.pw_body_step(this._live(), s, s + 8 * 16, options.time ?? 0, dt, w.mode, w.level, w.id, w.velocities,
                               w.min, w.max, out), call);
    } finally {
      rt._release(w);
    }
  }

  /**
   * One semi-implicit Euler step of dt seconds (gravity, buoyancy, drag, damping, the water
   * inside; the water graph steps first). options: water (as Bundle.evaluate), time (s), fluid.
   */
  step(dt, options = {}) {
    this._call(dt, options, 0, 'step');
    const v = Array.from(this._rt._f64(this._rt._scratch, STATE_FIELDS));
    const st = this.state;
    st.position = v.slice(0, 3);
    st.orientation = v.slice(3, 7);
    st.velocity = v.slice(7, 10);
    st.angularVelocity = v.slice(10, 13);
    return this;
  }

  /**
   * What a step of dt would apply at the current state, without stepping: the evaluation's
   * forces, the mass of the water inside and the load's force and torque (buoyancy, drag,
   * damping, the water's weight; not the body's own weight). options as step().
   */
  waterLoad(dt, options = {}) {
    const out = this._rt._scratch + 8 * 32;
    this._call(dt, options, out, 'waterLoad');
    const v = Array.from(this._rt._f64(out, 31));
    return { forces: readForces(v), waterMass: v[24], force: v.slice(25, 28), torque: v.slice(28, 31) };
  }

  /** Water in each node of the body's water graph, m^3 (empty without a graph). */
  nodeWater() {
    const rt = this._rt;
    const n = rt._x.pw_body_node_water(this._live(), rt._scratch);
    return Array.from(rt._f64(rt._scratch, n));
  }
  /** FNV-1a of the body's snapshot (its water, random sequence, radiation), 16 hex digits. */
  stateHash() { return this._rt._hash(this._rt._x.pw_body_hash, this._live()); }
  get asleep() { return this._rt._x.pw_body_asleep(this._live()) === 1; }
  wake() { this._rt._x.pw_body_wake(this._live()); }
  _live() {
    if (!this._h) throw new PlimsollError('the body was disposed');
    return this._h;
  }
  dispose() {
    if (this._h) this._rt._x.pw_body_destroy(this._h);
    this._h = 0;
  }
}

const CSV_HEADER = 'time,body,x,y,z,qw,qx,qy,qz,vx,vy,vz,wx,wy,wz,submerged_volume,fx,fy,fz,mass,com_x,com_y,com_z\n';

export class Simulation {
  constructor(bundle) {
    this.bundle = bundle;
    this._rt = bundle._rt;
    this._h = this._rt._x.pw_simulation_create(bundle._live());
    if (!this._h) throw this._rt._error('createSimulation');
  }

  /** One frame of the project's time step; water as Bundle.evaluate (default: the bundle's). */
  advanceFrame(water) {
    const rt = this._rt;
    const w = rt._water(water);
    try {
      rt._check(rt._x.pw_simulation_advance(this._live(), w.mode, w.level, w.id, w.velocities, w.min, w.max),
                'advanceFrame');
    } finally {
      rt._release(w);
    }
    return this;
  }

  /** The columns of `plimsoll simulate --out`, and the frame time and last sub-step count. */
  state() {
    const rt = this._rt;
    rt._x.pw_simulation_state(this._live(), rt._scratch);
    const v = Array.from(rt._f64(rt._scratch, 24));
    return {
      time: v[0], centerOfMass: v.slice(1, 4), orientation: v.slice(4, 8), velocity: v.slice(8, 11),
      angularVelocity: v.slice(11, 14), submergedVolume: v[14], buoyantForce: v.slice(15, 18), mass: v[18],
      localCenterOfMass: v.slice(19, 22), frameTime: v[22], subSteps: v[23],
    };
  }

  /** This frame's row of float_body --csv, the same text. */
  csvRow() {
    const rt = this._rt, x = rt._x;
    const buffer = x.pw_alloc(1024);
    try {
      const n = x.pw_simulation_csv_row(this._live(), buffer, 1024);
      return new TextDecoder().decode(new Uint8Array(x.memory.buffer, buffer, n));
    } finally {
      x.pw_free(buffer);
    }
  }

  /**
   * float_body BUNDLE SECONDS --csv: advances ceil(seconds / frame time) frames and returns the
   * CSV text (header and one row per frame) and the final state hash.
   */
  replay(seconds, water) {
    const frames = Math.ceil(seconds / this.state().frameTime - 1e-9);
    let csv = CSV_HEADER;
    for (let i = 0; i < frames; ++i) csv += this.advanceFrame(water).csvRow();
    return { csv, frames, stateHash: this.stateHash() };
  }

  /** FNV-1a of the simulation's snapshot, 16 hex digits: equal hashes, equal states. */
  stateHash() { return this._rt._hash(this._rt._x.pw_simulation_hash, this._live()); }
  nodeWater() {
    const rt = this._rt;
    const n = rt._x.pw_simulation_node_water(this._live(), rt._scratch);
    return Array.from(rt._f64(rt._scratch, n));
  }
  get asleep() { return this._rt._x.pw_simulation_asleep(this._live()) === 1; }
  _live() {
    if (!this._h) throw new PlimsollError('the simulation was disposed');
    return this._h;
  }
  dispose() {
    if (this._h) this._rt._x.pw_simulation_destroy(this._h);
    this._h = 0;
  }
}
