// sinew-view's page: the deformed skin and the physics overlays (three.js),
// the inputs and the step-time chart, fed over a WebSocket by sinew-view
// (host_tools/view/frame_message.hpp documents the messages).
import * as THREE from './three.module.js';
import {drawStepChart, updateInputTable} from './panels.js';

const $ = (id) => document.getElementById(id);
const params = new URLSearchParams(location.search);
const fixedTime = params.has('t') ? Number(params.get('t')) : null;
// ?show=a,b: overlays switched on at load (mesh, displacement, skeleton,
// sph, metaballs, muscles, barnet), e.g. for a screenshot of every layer.
for (const name of (params.get('show') || '').split(',').filter(Boolean)) {
  const box = document.getElementById('show-' + name);
  if (box) box.checked = true;
}
const state = {rig: null, framesDrawn: 0, lastFrame: null, fitted: false, scrubbing: false};
window.sinewView = state;  // for the tests: frames drawn, the last frame's time

const canvas = $('scene');
const renderer = new THREE.WebGLRenderer({canvas, antialias: true, preserveDrawingBuffer: true});
renderer.setClearColor(0x1e2228);
const scene = new THREE.Scene();
const camera = new THREE.PerspectiveCamera(40, canvas.width / canvas.height, 0.001, 100);
scene.add(new THREE.HemisphereLight(0xffffff, 0x505060, 2.2));
const sun = new THREE.DirectionalLight(0xffffff, 1.8);
sun.position.set(1, 2, 3);
scene.add(sun);

const skinGeometry = new THREE.BufferGeometry();
const skinMaterial = new THREE.MeshStandardMaterial({color: 0xd9a27e, roughness: 0.7, side: THREE.DoubleSide});
const skin = new THREE.Mesh(skinGeometry, skinMaterial);
scene.add(skin);

function pointsLayer(size) {
  const geometry = new THREE.BufferGeometry();
  const material = new THREE.PointsMaterial({size, vertexColors: true, sizeAttenuation: false, depthTest: false});
  const points = new THREE.Points(geometry, material);
  points.renderOrder = 2;
  scene.add(points);
  return points;
}
const bones = new THREE.LineSegments(new THREE.BufferGeometry(),
    new THREE.LineBasicMaterial({color: 0xffffff, depthTest: false}));
bones.renderOrder = 3;
scene.add(bones);
const joints = pointsLayer(9);
const sph = pointsLayer(4);
const muscles = pointsLayer(2);
const barnet = pointsLayer(5);
const ballGeometry = new THREE.SphereGeometry(1, 12, 8);
let balls = null;

function setPoints(points, xyz, colour) {
  const n = xyz.length / 3;
  const colours = new Float32Array(3 * n);
  for (let k = 0; k < n; ++k) colour(k, colours, 3 * k);
  points.geometry.setAttribute('position', new THREE.BufferAttribute(xyz, 3));
  points.geometry.setAttribute('color', new THREE.BufferAttribute(colours, 3));
  points.geometry.computeBoundingSphere();
}

// Blue (rest density) to red (most compressed); yielded particles magenta.
function pressureColour(p, maxP, out, at) {
  const x = maxP > 0 ? Math.min(Math.max(p / maxP, 0), 1) : 0;
  out[at] = 0.2 + 0.8 * x; out[at + 1] = 0.4 * (1 - x); out[at + 2] = 1 - x;
}

function decode(buffer) {
  const view = new DataView(buffer);
  const jsonBytes = view.getUint32(0, true);
  const msg = JSON.parse(new TextDecoder().decode(new Uint8Array(buffer, 4, jsonBytes)));
  let at = (4 + jsonBytes + 3) & ~3;
  msg.data = {};
  for (const [name, count] of msg.arrays) {
    msg.data[name] = new Float32Array(buffer, at, count);
    at += 4 * count;
  }
  return msg;
}

function showError(text) {
  $('error').hidden = !text;
  $('error').textContent = text || '';
}

function setRig(rig) {
  state.rig = rig;
  skinGeometry.setIndex(rig.triangles);
  const lines = [];
  rig.joint_parent.forEach((parent, k) => { if (parent >= 0) lines.push(parent, k); });
  bones.geometry.setIndex(lines);
  $('source').textContent = `rig ${rig.name}: ${rig.vertex_count} vertices, ${rig.inputs.length} inputs` +
      (rig.layers ? `, layers ${rig.layers}` : '');
}

function fitCamera(position) {
  const box = new THREE.Box3().setFromBufferAttribute(new THREE.BufferAttribute(position, 3));
  const centre = box.getCenter(new THREE.Vector3());
  const radius = Math.max(box.getSize(new THREE.Vector3()).length() / 2, 1e-3);
  // The whole bounding sphere in view, with a margin for the arm's swing.
  const distance = 1.3 * radius / Math.sin(THREE.MathUtils.degToRad(camera.fov / 2));
  const direction = new THREE.Vector3(0.35, 0.3, 0.9).normalize();
  camera.position.copy(centre).addScaledVector(direction, distance);
  camera.near = distance / 100;
  camera.far = distance * 10;
  camera.lookAt(centre);
  camera.updateProjectionMatrix();
}

function updateScene(msg) {
  const d = msg.data;
  const v = state.rig.vertex_count;
  skinGeometry.setAttribute('position', new THREE.BufferAttribute(d.position, 3));
  if (d.normal) skinGeometry.setAttribute('normal', new THREE.BufferAttribute(d.normal, 3));
  else skinGeometry.computeVertexNormals();
  skinGeometry.computeBoundingSphere();
  const byDisplacement = $('show-displacement').checked && d.displacement;
  if (byDisplacement) {
    let maxD = 0;
    for (let k = 0; k < v; ++k) maxD = Math.max(maxD, d.displacement[k]);
    const colours = new Float32Array(3 * v);
    for (let k = 0; k < v; ++k) {
      const x = maxD > 0 ? d.displacement[k] / maxD : 0;
      colours[3 * k] = 0.3 + 0.7 * x; colours[3 * k + 1] = 0.3 + 0.3 * (1 - x); colours[3 * k + 2] = 0.9 * (1 - x);
    }
    skinGeometry.setAttribute('color', new THREE.BufferAttribute(colours, 3));
    $('legend').textContent = `displacement from plain skinning: 0 (blue) .. ${(maxD * 1000).toFixed(2)} mm (red)`;
  } else {
    $('legend').textContent = 'SPH particles: blue rest density .. red compressed, magenta yielded; ' +
        'joints: red at a limit, magenta yielded';
  }
  if (skinMaterial.vertexColors !== Boolean(byDisplacement)) {
    skinMaterial.vertexColors = Boolean(byDisplacement);
    skinMaterial.color.set(byDisplacement ? 0xffffff : 0xd9a27e);
    skinMaterial.needsUpdate = true;
  }
  skin.visible = $('show-mesh').checked;

  bones.geometry.setAttribute('position', new THREE.BufferAttribute(d.joints, 3));
  bones.visible = joints.visible = $('show-skeleton').checked;
  const yieldedJoint = new Set((msg.sph_joints || []).filter((j) => j.yielded).map((j) => j.joint));
  setPoints(joints, d.joints, (k, out, at) => {
    const c = yieldedJoint.has(k) ? [1, 0, 1] : msg.joint_limit[k] ? [1, 0.1, 0.1] : [1, 1, 0.6];
    out.set(c, at);
  });
  let maxP = 0;
  for (const p of d.sph_pressure) maxP = Math.max(maxP, p);
  setPoints(sph, d.sph_position, (k, out, at) => {
    if (d.sph_yielded[k] > 0) out.set([1, 0, 1], at);
    else pressureColour(d.sph_pressure[k], maxP, out, at);
  });
  sph.visible = $('show-sph').checked;
  setPoints(muscles, d.muscles, (k, out, at) => out.set([0.8, 0.15, 0.15], at));
  muscles.visible = $('show-muscles').checked;
  setPoints(barnet, d.barnet, (k, out, at) => out.set([0.2, 1, 0.4], at));
  barnet.visible = $('show-barnet').checked;
  const ballCount = d.metaballs.length / 4;
  if (!balls || balls.count !== ballCount) {
    if (balls) scene.remove(balls);
    balls = new THREE.InstancedMesh(ballGeometry,
        new THREE.MeshBasicMaterial({color: 0x66ccff, wireframe: true, transparent: true, opacity: 0.15}), ballCount);
    scene.add(balls);
  }
  const m = new THREE.Matrix4();
  for (let b = 0; b < ballCount; ++b) {
    const r = d.metaballs[4 * b + 3];
    m.makeScale(r, r, r).setPosition(d.metaballs[4 * b], d.metaballs[4 * b + 1], d.metaballs[4 * b + 2]);
    balls.setMatrixAt(b, m);
  }
  balls.instanceMatrix.needsUpdate = true;
  balls.visible = $('show-metaballs').checked && ballCount > 0;
  if (!state.fitted) {
    fitCamera(d.position);
    state.fitted = true;
  }
}

function updatePanels(msg) {
  const playback = msg.source === 'log'
      ? `replay ${msg.time_s.toFixed(3)} s of ${msg.end_s.toFixed(3)} s, ${msg.playing ? 'playing' : 'paused'} x${msg.speed}`
      : 'live UDP stream';
  $('status').textContent = msg.type === 'frame'
      ? `${playback}; tick ${msg.tick}; frames ${msg.frames}, lost ${msg.frames_lost}, drawn ${state.framesDrawn}`
      : `${msg.source === 'log' ? 'replay' : 'live UDP stream'}: waiting for frames`;
  $('replay').hidden = msg.source !== 'log';
  if (msg.source === 'log') {
    $('play').textContent = msg.playing ? 'pause' : 'play';
    $('scrub').max = String(msg.end_s);
    if (!state.scrubbing) $('scrub').value = String(msg.time_s);
    $('time').textContent = `${msg.time_s.toFixed(3)} s`;
  }
  if (msg.inputs) updateInputTable($('inputs').tBodies[0], state.rig, msg.inputs);
  if (msg.history) {
    $('budget').textContent = `(tick budget ${(msg.budget_ns / 1000).toFixed(0)} µs)`;
    drawStepChart($('chart'), $('chart-summary'), msg.stages, msg.history, msg.budget_ns);
  }
}

function onFrame(msg) {
  const mismatch = msg.error || '';
  showError(mismatch);
  // With ?t=, frames sent before the server applied this page's pause and
  // seek are not drawn (the position is clamped to the log's range).
  const wanted = fixedTime === null ? 0 : Math.min(Math.max(fixedTime, msg.start_s), msg.end_s);
  const settled = fixedTime === null || msg.source !== 'log' || (!msg.playing && Math.abs(msg.time_s - wanted) < 1e-6);
  if (msg.type === 'frame' && msg.data.position && state.rig && settled) {
    updateScene(msg);
    renderer.render(scene, camera);
    state.lastMessage = msg;
    ++state.framesDrawn;
    state.lastFrame = {tick: msg.tick, time_s: msg.frame_time_s};
    document.body.dataset.framesDrawn = String(state.framesDrawn);
    document.body.dataset.timeS = String(msg.frame_time_s);
  }
  updatePanels(msg);
}

function connect() {
  const socket = new WebSocket(`ws://${location.host}/stream`);
  socket.binaryType = 'arraybuffer';
  const send = (text) => { if (socket.readyState === WebSocket.OPEN) socket.send(text); };
  socket.onopen = () => {
    if (fixedTime !== null) { send('pause'); send(`seek ${fixedTime}`); }
  };
  socket.onmessage = (event) => {
    if (typeof event.data === 'string') {
      const msg = JSON.parse(event.data);
      if (msg.type === 'rig') setRig(msg);
      return;
    }
    onFrame(decode(event.data));
  };
  socket.onclose = () => {
    showError('connection to sinew-view closed; retrying');
    setTimeout(connect, 1000);
  };
  $('play').onclick = () => send($('play').textContent === 'pause' ? 'pause' : 'play');
  $('speed').onchange = () => send(`speed ${$('speed').value}`);
  $('scrub').oninput = () => { state.scrubbing = true; send(`seek ${$('scrub').value}`); };
  $('scrub').onchange = () => { state.scrubbing = false; };
}

// A toggle applies at once, also to a paused replay's frame.
for (const box of document.querySelectorAll('#overlays input')) {
  box.onchange = () => {
    if (!state.lastMessage) return;
    updateScene(state.lastMessage);
    renderer.render(scene, camera);
  };
}
connect();
