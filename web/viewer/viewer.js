// The Plimsoll viewer: an exported bundle's glTF mesh floating on its own water, simulated by the
// runtime's WebAssembly module, with its buoyancy, weight and drag drawn. Drop more bodies of it,
// click one to push it, drag one to pull it, watch a damaged one flood.
//
// URL parameters: bundle=FOLDER (default: the first of bundles.json, which `plimsoll export
// --web` writes); deterministic=1&seconds=S replays the bundle's own world for S simulated
// seconds in fixed frames (float_body --csv's run: the same state hash as the native runtime)
// and reports it in #result and window.plimsollResult.
import * as THREE from 'three';
import { GLTFLoader } from 'three/addons/loaders/GLTFLoader.js';
import { OrbitControls } from 'three/addons/controls/OrbitControls.js';
import { loadRuntime } from 'plimsoll-runtime';

const params = new URLSearchParams(location.search);
const deterministic = params.has('deterministic');
const seconds = Number(params.get('seconds') ?? 10);
const $ = (id) => document.getElementById(id);

function fail(error) {
  console.error(error);
  $('error').textContent = String(error?.message ?? error);
  window.plimsollResult = { error: String(error?.message ?? error) };
  $('result').textContent = JSON.stringify(window.plimsollResult);
  document.title = 'Plimsoll viewer: failed';
}

async function bundleUrl() {
  if (params.get('bundle')) return new URL(params.get('bundle').replace(/\/?$/, '/'), location.href);
  const response = await fetch('bundles.json');
  if (!response.ok) throw new Error('no bundle: give ?bundle=FOLDER, or open the page `plimsoll export --web` wrote');
  const list = await response.json();
  if (!list.bundles?.length) throw new Error('bundles.json lists no bundle');
  return new URL(list.bundles[0].replace(/\/?$/, '/'), location.href);
}

// wxyz (the runtime's) to three.js's quaternion.
const quaternion = (q) => new THREE.Quaternion(q[1], q[2], q[3], q[0]);
const vec = (v) => new THREE.Vector3(v[0], v[1], v[2]);

async function main() {
  const runtime = await loadRuntime(new URL('./vendor/plimsoll-runtime/plimsoll.wasm', import.meta.url));
  const url = await bundleUrl();
  const loadStart = performance.now();
  const bundle = await runtime.fetchBundle(url);
  const loadMs = performance.now() - loadStart;
  const manifest = await (await fetch(new URL('manifest.json', url))).json();
  $('title').textContent = `${bundle.name} (${bundle.sampleCount} samples, ${bundle.world.water.kind} water)`;

  const renderer = new THREE.WebGLRenderer({ antialias: true, preserveDrawingBuffer: true });
  renderer.setPixelRatio(window.devicePixelRatio);
  renderer.setSize(window.innerWidth, window.innerHeight);
  document.body.prepend(renderer.domElement);
  const scene = new THREE.Scene();
  scene.background = new THREE.Color(0x9cc6e0);
  scene.add(new THREE.HemisphereLight(0xdfefff, 0x203040, 1.6));
  const sun = new THREE.DirectionalLight(0xffffff, 1.8);
  sun.position.set(5, 10, 3);
  scene.add(sun);

  const span = Math.max(...bundle.bounds.max.map((v, i) => v - bundle.bounds.min[i]));
  const camera = new THREE.PerspectiveCamera(45, window.innerWidth / window.innerHeight, 0.01 * span, 200 * span);
  const start = bundle.world.start.position;
  camera.position.set(start[0] + 2.2 * span, start[1] + 1.4 * span, start[2] + 2.6 * span);
  const controls = new OrbitControls(camera, renderer.domElement);
  controls.target.set(start[0], bundle.world.water.level, start[2]);
  controls.update();
  window.addEventListener('resize', () => {
    camera.aspect = window.innerWidth / window.innerHeight;
    camera.updateProjectionMatrix();
    renderer.setSize(window.innerWidth, window.innerHeight);
  });

  // The water: a grid whose heights are the physics' own water (Bundle.waterHeights).
  const waterSize = Math.max(30, 12 * span), cells = 96;
  const waterGeometry = new THREE.PlaneGeometry(waterSize, waterSize, cells, cells);
  waterGeometry.rotateX(-Math.PI / 2);
  waterGeometry.translate(start[0], 0, start[2]);
  const positions = waterGeometry.attributes.position;
  const wx = new Float64Array(positions.count), wz = new Float64Array(positions.count), wy = new Float64Array(positions.count);
  for (let i = 0; i < positions.count; ++i) { wx[i] = positions.getX(i); wz[i] = positions.getZ(i); }
  const water = new THREE.Mesh(waterGeometry, new THREE.MeshStandardMaterial({
    color: 0x1f6f9a, roughness: 0.25, metalness: 0.1, transparent: true, opacity: 0.78, side: THREE.DoubleSide,
  }));
  scene.add(water);
  const updateWater = (time) => {
    bundle.waterHeights(wx, wz, time, wy);
    for (let i = 0; i < positions.count; ++i) positions.setY(i, wy[i]);
    positions.needsUpdate = true;
    waterGeometry.computeVertexNormals();
  };

  const gltf = await new GLTFLoader().loadAsync(new URL(manifest.gltf, url).href);
  const g = bundle.fluid.gravity;
  const weight = bundle.mass.mass * g;
  const arrowScale = span / weight;

  function makeVisual() {
    const root = gltf.scene.clone(true);
    root.traverse((o) => {
      if (o.isMesh) {
        o.material = o.material.clone();
        o.userData.baseColor = o.material.color?.clone();
      }
    });
    const group = new THREE.Group();
    group.add(root);
    scene.add(group);
    const arrows = {
      buoyancy: new THREE.ArrowHelper(new THREE.Vector3(0, 1, 0), new THREE.Vector3(), 1, 0x3cd070),
      weight: new THREE.ArrowHelper(new THREE.Vector3(0, -1, 0), new THREE.Vector3(), 1, 0xff5050),
      drag: new THREE.ArrowHelper(new THREE.Vector3(1, 0, 0), new THREE.Vector3(), 1, 0x4a8cff),
    };
    for (const a of Object.values(arrows)) {
      // Drawn over the hull and the water: the forces act inside the body.
      a.traverse((o) => { if (o.material) { o.material.depthTest = false; o.material.transparent = true; } o.renderOrder = 10; });
      scene.add(a);
    }
    return { group, root, arrows };
  }

  function setArrow(arrow, origin, force) {
    const f = vec(force);
    const length = f.length() * arrowScale;
    arrow.visible = length > 1e-3 * span;
    if (!arrow.visible) return;
    arrow.position.copy(origin);
    arrow.setDirection(f.normalize());
    arrow.setLength(length, 0.15 * span, 0.07 * span);
  }

  // The hull tinted blue as it fills; the panel lists the water per node of the selected body.
  function showFlooding(visual, water, listed = true) {
    const capacity = bundle.nodeCapacities.reduce((s, v) => s + v, 0);
    const filled = capacity > 0 ? water.reduce((s, v) => s + v, 0) / capacity : 0;
    visual.root.traverse((o) => {
      if (o.isMesh && o.userData.baseColor) o.material.color.copy(o.userData.baseColor).lerp(new THREE.Color(0x2060ff), 0.8 * filled);
    });
    if (!listed) return;
    $('nodes').innerHTML = bundle.nodeCapacities.map((c, i) =>
      `<div class="row"><span>node ${i}</span><span>${water[i].toFixed(3)} / ${c.toFixed(3)} m³</span></div>` +
      `<div class="bar"><div style="width:${(100 * Math.min(1, water[i] / c)).toFixed(1)}%"></div></div>`).join('');
  }

  // Where the object origin is for a centre of mass and orientation (the simulation reports the
  // centre of mass of the body with its water).
  function placeByCenterOfMass(visual, centerOfMass, orientation, localCenterOfMass) {
    const q = quaternion(orientation);
    const origin = vec(centerOfMass).sub(vec(localCenterOfMass).applyQuaternion(q));
    visual.group.position.copy(origin);
    visual.group.quaternion.copy(q);
  }

  const frameTimes = [], physicsTimes = [];
  const average = (list, value) => {
    list.push(value);
    if (list.length > 60) list.shift();
    return list.reduce((s, v) => s + v, 0) / list.length;
  };

  if (deterministic) {
    // float_body --csv's run: the bundle's own world in its own frames, as fast as it computes.
    const simulation = bundle.createSimulation();
    const visual = makeVisual();
    const frames = Math.ceil(seconds / simulation.state().frameTime - 1e-9);
    const physicsStart = performance.now();
    for (let i = 0; i < frames; ++i) simulation.advanceFrame();
    const physicsMs = performance.now() - physicsStart;
    const s = simulation.state();
    placeByCenterOfMass(visual, s.centerOfMass, s.orientation, s.localCenterOfMass);
    setArrow(visual.arrows.buoyancy, vec(s.centerOfMass), s.buoyantForce);
    setArrow(visual.arrows.weight, vec(s.centerOfMass), [0, -s.mass * g, 0]);
    visual.arrows.drag.visible = false;
    showFlooding(visual, simulation.nodeWater());
    updateWater(s.time);
    const hash = simulation.stateHash();
    $('hash').textContent = hash;
    $('simTime').textContent = `${s.time.toFixed(3)} s (${frames} frames)`;
    $('physicsTime').textContent = `${(physicsMs / frames).toFixed(3)} ms / frame`;
    $('bodyCount').textContent = '1';
    const renderStart = performance.now();
    renderer.render(scene, camera);
    $('frameTime').textContent = `${(performance.now() - renderStart).toFixed(1)} ms`;
    window.plimsollResult = {
      stateHash: hash, frames, time: s.time, physicsMs, loadMs, body: bundle.name, runtime: runtime.version,
    };
    $('result').textContent = JSON.stringify(window.plimsollResult);
    document.title = 'Plimsoll viewer: done';
    return;
  }

  // Interactive: Body instances stepped in fixed sub-steps of the project's frame.
  const dt = bundle.world.timeStep / Math.max(1, bundle.world.subSteps);
  const bodies = [];
  let time = 0, paused = false, selected = 0;  // the body the panel and the hash describe
  const addBody = (state) => {
    const body = bundle.createBody(state);
    bodies.push({ body, visual: makeVisual() });
  };
  const reset = () => {
    for (const b of bodies.splice(0)) {
      b.body.dispose();
      scene.remove(b.visual.group, ...Object.values(b.visual.arrows));
    }
    time = 0;
    selected = 0;
    addBody({});
  };
  reset();
  let seed = 1;
  const random = () => ((seed = (seed * 16807) % 2147483647) / 2147483647);
  $('drop').onclick = () => {
    const a = 2 * Math.PI * random(), r = span * (1 + 2 * random());
    const axis = new THREE.Vector3(random() - 0.5, random() - 0.5, random() - 0.5).normalize();
    const q = new THREE.Quaternion().setFromAxisAngle(axis, Math.PI * random());
    addBody({
      position: [start[0] + r * Math.cos(a), bundle.world.water.level + 1.5 * span, start[2] + r * Math.sin(a)],
      orientation: [q.w, q.x, q.y, q.z],
    });
  };
  $('pause').onclick = () => { paused = !paused; $('pause').textContent = paused ? 'Play' : 'Pause'; };
  $('reset').onclick = reset;

  // Push (click) and pull (drag): a point of the body held in object space.
  const raycaster = new THREE.Raycaster(), pointer = new THREE.Vector2();
  let grab = null;
  const ray = (event) => {
    pointer.set((event.clientX / window.innerWidth) * 2 - 1, -(event.clientY / window.innerHeight) * 2 + 1);
    raycaster.setFromCamera(pointer, camera);
  };
  renderer.domElement.addEventListener('pointerdown', (event) => {
    ray(event);
    const hits = raycaster.intersectObjects(bodies.map((b) => b.visual.group), true);
    if (!hits.length) return;
    const hit = hits[0];
    const entry = bodies.find((b) => { let o = hit.object; while (o && o !== b.visual.group) o = o.parent; return o; });
    selected = bodies.indexOf(entry);
    controls.enabled = false;
    grab = {
      entry, local: entry.visual.group.worldToLocal(hit.point.clone()), plane: new THREE.Plane(new THREE.Vector3(0, 1, 0), -hit.point.y),
      target: hit.point.clone(), down: performance.now(), x: event.clientX, y: event.clientY, direction: raycaster.ray.direction.clone(),
    };
  });
  renderer.domElement.addEventListener('pointermove', (event) => {
    if (!grab) return;
    ray(event);
    raycaster.ray.intersectPlane(grab.plane, grab.target);
    grab.dragged ||= Math.hypot(event.clientX - grab.x, event.clientY - grab.y) > 6;
  });
  window.addEventListener('pointerup', () => {
    if (grab && !grab.dragged) {
      // A push: 1.5 m/s along the view ray at the point clicked.
      const J = grab.direction.clone().multiplyScalar(1.5 * bundle.mass.mass);
      applyImpulse(grab.entry, grab.local, J);
    }
    grab = null;
    controls.enabled = true;
  });
  const meanInertia = (bundle.mass.inertia[0] + bundle.mass.inertia[4] + bundle.mass.inertia[8]) / 3;
  function applyImpulse(entry, local, J) {
    const st = entry.body.state;
    const q = quaternion(st.orientation);
    const com = vec(bundle.mass.centerOfMass).applyQuaternion(q).add(vec(st.position));
    const point = local.clone().applyQuaternion(q).add(vec(st.position));
    const dw = point.sub(com).cross(J).divideScalar(meanInertia);
    st.velocity = st.velocity.map((v, i) => v + J.getComponent(i) / bundle.mass.mass);
    st.angularVelocity = st.angularVelocity.map((w, i) => w + dw.getComponent(i));
    entry.body.wake();
  }
  function pull(entry) {
    const st = entry.body.state;
    const q = quaternion(st.orientation);
    const point = grab.local.clone().applyQuaternion(q).add(vec(st.position));
    // A critically damped spring of the body's own frequency (about 1 Hz).
    const k = bundle.mass.mass * 40, c = bundle.mass.mass * 2 * Math.sqrt(40);
    const F = grab.target.clone().sub(point).multiplyScalar(k).sub(vec(st.velocity).multiplyScalar(c));
    applyImpulse(entry, grab.local, F.multiplyScalar(dt));
  }

  // What the page's test (web/viewer/test/browser-run.mjs --interactive) reads each frame.
  const probe = window.plimsollViewer = {
    frames: 0, time: 0, bodies: [],
    screen(i) {
      const v = bodies[i].visual.group.position.clone().project(camera);
      return { x: ((v.x + 1) / 2) * window.innerWidth, y: ((1 - v.y) / 2) * window.innerHeight };
    },
  };

  let last = performance.now(), carried = 0;
  function frame(now) {
    const elapsed = Math.min(0.1, (now - last) / 1000);
    last = now;
    let physicsMs = 0;
    if (!paused) {
      carried += elapsed;
      const physicsStart = performance.now();
      while (carried >= dt) {
        for (const entry of bodies) {
          if (grab?.dragged && grab.entry === entry) pull(entry);
          entry.body.step(dt, { time });
        }
        time += dt;
        carried -= dt;
      }
      physicsMs = performance.now() - physicsStart;
    }
    for (const [index, { body, visual }] of bodies.entries()) {
      const st = body.state;
      visual.group.position.set(...st.position);
      visual.group.quaternion.copy(quaternion(st.orientation));
      const load = body.waterLoad(dt, { time });
      const f = load.forces;
      const com = vec(bundle.mass.centerOfMass).applyQuaternion(visual.group.quaternion).add(visual.group.position);
      setArrow(visual.arrows.buoyancy, vec(f.centerOfBuoyancy), bundle.world.water.kind === 'flat' ? f.force : f.pressureForce);
      setArrow(visual.arrows.weight, com, [0, -(bundle.mass.mass + load.waterMass) * g, 0]);
      setArrow(visual.arrows.drag, vec(f.centerOfBuoyancy), f.dragForce);
      showFlooding(visual, body.nodeWater(), index === selected);
    }
    updateWater(time);
    $('hash').textContent = bodies[selected].body.stateHash();
    $('simTime').textContent = `${time.toFixed(2)} s`;
    $('bodyCount').textContent = String(bodies.length);
    const physicsAverage = average(physicsTimes, physicsMs);
    $('physicsTime').textContent = `${physicsAverage.toFixed(2)} ms / frame`;
    const renderStart = performance.now();
    controls.update();
    renderer.render(scene, camera);
    const frameMs = average(frameTimes, performance.now() - renderStart + physicsMs);
    $('frameTime').textContent = `${frameMs.toFixed(2)} ms (load ${loadMs.toFixed(0)} ms)`;
    probe.frames += 1;
    probe.time = time;
    probe.frameMs = frameMs;
    probe.physicsMs = physicsAverage;
    probe.bodies = bodies.map(({ body }) => ({
      position: body.state.position, velocity: body.state.velocity,
      water: body.nodeWater().reduce((sum, v) => sum + v, 0),
    }));
    requestAnimationFrame(frame);
  }
  requestAnimationFrame(frame);
}

main().catch(fail);
