// Types of the Plimsoll runtime's WebAssembly package (index.js). Units SI, +y up; quaternions
// are [w, x, y, z], object -> world; velocities are of the centre of mass, world axes; forces in
// world axes, torques about the centre of mass.

export type Vec3 = [number, number, number];
export type Quaternion = [number, number, number, number];

export interface Pose {
  position?: Vec3;
  orientation?: Quaternion;
}
export interface Velocity {
  linear?: Vec3;
  angular?: Vec3;
}
export interface Fluid {
  density: number;
  gravity: number;
  dragCoefficient: number;
  frictionCoefficient: number;
}

/** The caller's water: one call per batch of points, arrays in, heights out. */
export interface WaterCallback {
  /** Fill out[i] with the height at (x[i], z[i]) (or return an array of them). */
  heights(x: Float64Array, z: Float64Array, time: number, out: Float64Array): void | ArrayLike<number>;
  /** Optional: out[3 i..3 i + 2] = the water's velocity at (x[i], y[i], z[i]) (for drag). */
  velocities?(x: Float64Array, y: Float64Array, z: Float64Array, time: number, out: Float64Array): void | ArrayLike<number>;
  /** Mean level (m), and bounds of the heights (a body wholly above maxHeight costs nothing). */
  level?: number;
  minHeight?: number;
  maxHeight?: number;
}
/** "bundle" (default): the bundle's own flat or Gerstner water; a number: flat water there. */
export type Water = 'bundle' | number | { level: number } | WaterCallback;

export interface Forces {
  submergedVolume: number;
  centerOfBuoyancy: Vec3;
  force: Vec3;
  torque: Vec3;
  pressureForce: Vec3;
  pressureTorque: Vec3;
  dragForce: Vec3;
  dragTorque: Vec3;
  wettedArea: number;
  submergedSamples: number;
}

export interface EvaluateOptions {
  water?: Water;
  time?: number;
  fluid?: Partial<Fluid>;
}

export interface Wave {
  amplitude: number;
  wavelength: number;
  directionX: number;
  directionZ: number;
  steepness: number;
  phase: number;
}

export interface BundleWorld {
  timeStep: number;
  subSteps: number;
  water: { kind: 'flat' | 'gerstner' | 'grid'; level: number; waves: Wave[] };
  start: { position: Vec3; orientation: Quaternion };
}

export class PlimsollError extends Error {}

/** Loads plimsoll.wasm (default: beside index.js), from a URL, a path (node) or its bytes. */
export function loadRuntime(wasm?: string | URL | ArrayBuffer | ArrayBufferView): Promise<Runtime>;

export class Runtime {
  readonly version: string;
  /** A bundle from its files: path inside the bundle -> bytes. verify (default true) checks sizes and SHA-256. */
  loadBundle(files: Map<string, Uint8Array | ArrayBuffer> | Record<string, Uint8Array | ArrayBuffer>,
             options?: { name?: string; verify?: boolean }): Bundle;
  /** Fetches a bundle folder (manifest.json and the files it lists); file: URLs and paths in node. */
  fetchBundle(url: string | URL, options?: { name?: string; verify?: boolean }): Promise<Bundle>;
}

export class Bundle {
  readonly name: string;
  readonly mass: { mass: number; volume: number; centerOfMass: Vec3; inertia: number[] };
  readonly sampleCount: number;
  readonly textureSize: number;
  readonly fluid: Fluid;
  readonly damping: { linear: number; vertical: number; angular: number };
  readonly bounds: { min: Vec3; max: Vec3 };
  readonly world: BundleWorld;
  readonly nodeCapacities: number[];
  evaluate(pose: Pose, velocity?: Velocity, options?: EvaluateOptions): Forces;
  /** Heights of the bundle's own water at (x[i], z[i]). */
  waterHeights(x: ArrayLike<number>, z: ArrayLike<number>, time?: number, out?: Float64Array): Float64Array;
  createBody(state?: Partial<BodyState>): Body;
  createSimulation(): Simulation;
  dispose(): void;
}

export interface BodyState {
  position: Vec3;
  orientation: Quaternion;
  velocity: Vec3;
  angularVelocity: Vec3;
}

export interface WaterLoad {
  forces: Forces;
  waterMass: number;
  force: Vec3;
  torque: Vec3;
}

export class Body {
  readonly bundle: Bundle;
  /** Set it freely between steps (a push is a change of velocity). */
  state: BodyState;
  step(dt: number, options?: EvaluateOptions): this;
  /** What a step of dt would apply at the current state (no step). */
  waterLoad(dt: number, options?: EvaluateOptions): WaterLoad;
  nodeWater(): number[];
  /** 16 hex digits. */
  stateHash(): string;
  readonly asleep: boolean;
  wake(): void;
  dispose(): void;
}

export interface SimulationState {
  time: number;
  centerOfMass: Vec3;
  orientation: Quaternion;
  velocity: Vec3;
  angularVelocity: Vec3;
  submergedVolume: number;
  buoyantForce: Vec3;
  mass: number;
  localCenterOfMass: Vec3;
  frameTime: number;
  subSteps: number;
}

export class Simulation {
  readonly bundle: Bundle;
  advanceFrame(water?: Water): this;
  state(): SimulationState;
  /** This frame's row of float_body --csv. */
  csvRow(): string;
  /** float_body BUNDLE SECONDS --csv: the CSV text and the final state hash. */
  replay(seconds: number, water?: Water): { csv: string; frames: number; stateHash: string };
  stateHash(): string;
  nodeWater(): number[];
  readonly asleep: boolean;
  dispose(): void;
}
