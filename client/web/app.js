// app.js - the preview page's logic: controls -> flat GET /v1/render query, debounced renders that supersede
// each other (AbortController), timing and modelled headers, mesh uploads, and the error against the truths
// ("reference": the diffusion model summed exactly; "path": random walks in the medium).
'use strict';

const DEBOUNCE_MS = 250;
const KEPT_TRUTHS = 8;
// Methods whose images the others are scored against.
const TRUTHS = ['reference', 'path'];
// Method path stops starting passes after this long, so that a page's render returns within the daemon's
// render deadline (60 s by default) at any size; the walks done are reported (Lucent-Modelled samples).
const PATH_TIME_S = 20;

const $ = (id) => document.getElementById(id);

// Three significant digits: what a slider shows is exactly what is sent.
const round3 = (v) => (v === 0 ? 0 : Number(v.toPrecision(3)));

// Slider scales: the range input's min, max and step, and position <-> value. Linear sliders move in their
// own units (an arrow key is one step); logarithmic ones over positions 0..1000, where zeroAtStart makes
// position 0 the value 0.
function linearScale(min, max, step) {
  return {
    min, max, step,
    toValue: (p) => +(Math.round(p / step) * step).toFixed(6),
    toPosition: (v) => v,
  };
}
function logScale(min, max, zeroAtStart) {
  const lo = Math.log10(min), hi = Math.log10(max);
  return {
    min: 0, max: 1000, step: 1,
    toValue: (p) => (zeroAtStart && p === 0 ? 0 : round3(10 ** (lo + ((hi - lo) * p) / 1000))),
    toPosition: (v) => {
      if (v <= 0) return 0;
      const p = Math.round(((Math.log10(v) - lo) / (hi - lo)) * 1000);
      return Math.min(1000, Math.max(zeroAtStart ? 1 : 0, p));
    },
  };
}

const CHANNELS = ['red', 'green', 'blue'];
const SLIDERS = [
  ...CHANNELS.map((c, i) => ({ key: 'sigma_a', index: i, parent: 'coefficients', material: true,
    label: `sigma_a ${c} (absorption)`, scale: logScale(1e-4, 10, true) })),
  ...CHANNELS.map((c, i) => ({ key: 'sigma_s_prime', index: i, parent: 'coefficients', material: true,
    label: `sigma_s' ${c} (reduced scattering)`, scale: logScale(1e-2, 100, false) })),
  { key: 'eta', parent: 'coefficients', material: true, label: 'eta (index of refraction)', scale: linearScale(1, 3, 0.01) },
  { key: 'scale_mm', parent: 'scale-slider', label: 'scale_mm (millimetres per scene unit)', scale: logScale(0.1, 1000, false) },
  { key: 'azimuth', parent: 'light-sliders', label: 'azimuth (degrees)', scale: linearScale(-180, 180, 1) },
  { key: 'elevation', parent: 'light-sliders', label: 'elevation (degrees)', scale: linearScale(-90, 90, 1) },
  { key: 'intensity', parent: 'light-sliders', label: 'intensity', scale: logScale(0.01, 100, false) },
  { key: 'view_azimuth', parent: 'view-sliders', label: 'azimuth (degrees)', scale: linearScale(-180, 180, 1) },
  { key: 'view_elevation', parent: 'view-sliders', label: 'elevation (degrees)', scale: linearScale(-85, 85, 1) },
];
// The daemon's automatic camera: from the front left and above (renderer/core/scene_parse.c).
const DEFAULT_VIEW = { view_azimuth: -35, view_elevation: 25 };
const DRAG_DEGREES_PER_PIXEL = 0.5;

const state = {
  preset: 'skin1',
  sigma_a: [0.032, 0.17, 0.48],
  sigma_s_prime: [0.74, 0.88, 1.01],
  eta: 1.3,
  scale_mm: 20,
  azimuth: 90,
  elevation: 0,
  intensity: 4,
  ...DEFAULT_VIEW,
};
const materials = new Map(); // preset name -> {sigma_a, sigma_s_prime, eta}
const truths = new Map(); // scene key -> Map(truth method -> pixels of its render)
const errors = new Map(); // source ("five", "upload", ...) -> {error, control}
let debounceTimer = 0;

const sliderId = (s) => (s.index === undefined ? s.key : `${s.key}-${s.index}`);
const sliderValue = (s) => (s.index === undefined ? state[s.key] : state[s.key][s.index]);

function buildSliders() {
  for (const s of SLIDERS) {
    const row = document.createElement('div');
    row.className = 'slider';
    const label = document.createElement('label');
    label.htmlFor = sliderId(s);
    label.textContent = s.label;
    const input = document.createElement('input');
    Object.assign(input, { type: 'range', id: sliderId(s), min: s.scale.min, max: s.scale.max, step: s.scale.step });
    const out = document.createElement('output');
    out.htmlFor = input.id;
    out.id = `${input.id}-value`;
    row.append(label, input, out);
    $(s.parent).append(row);
    input.addEventListener('input', () => {
      const v = s.scale.toValue(Number(input.value));
      if (s.index === undefined) state[s.key] = v;
      else state[s.key][s.index] = v;
      if (s.material && state.preset) {
        state.preset = '';
        $('preset').value = '';
      }
      showSliderValue(s, false);
      schedule();
    });
  }
}

// moveSlider false: the user is moving it; only the value shown follows.
function showSliderValue(s, moveSlider = true) {
  const v = sliderValue(s);
  const input = $(sliderId(s));
  if (moveSlider) input.value = s.scale.toPosition(v);
  input.setAttribute('aria-valuetext', String(v));
  $(`${input.id}-value`).textContent = String(v);
}

function showAllSliders() {
  for (const s of SLIDERS) showSliderValue(s);
  for (const s of SLIDERS) if (s.key === 'scale_mm') $(sliderId(s)).disabled = $('scale-auto').checked;
}

const unit = (azimuthDeg, elevationDeg) => {
  const az = (azimuthDeg * Math.PI) / 180, el = (elevationDeg * Math.PI) / 180;
  return [Math.cos(el) * Math.sin(az), Math.sin(el), Math.cos(el) * Math.cos(az)];
};
const cross = (a, b) => [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]];
const normalized = (v) => v.map((x) => x / Math.hypot(...v));
const rounded = (v) => v.map((x) => +x.toFixed(4) || 0);

// The camera's basis in the world: back (from the object to the eye), right and up (+Y stays up).
function viewBasis() {
  const back = unit(state.view_azimuth, state.view_elevation);
  const right = normalized(cross([0, 1, 0], back));
  return { back, right, up: cross(back, right) };
}

// The way the camera looks: the daemon frames the object along it (camera_dir).
const cameraDirection = () => rounded(viewBasis().back.map((x) => -x));

// The direction the light travels: opposite to where it comes from, given relative to the camera
// (azimuth 0 = the camera, 90 its right), so the light turns with the view.
function lightDirection() {
  const from = unit(state.azimuth, state.elevation);
  const { back, right, up } = viewBasis();
  return rounded([0, 1, 2].map((i) => -(from[0] * right[i] + from[1] * up[i] + from[2] * back[i])));
}

// Flat query fields of GET /v1/render, in README order; "method" and "samples" last.
function sceneFields(method) {
  const f = [['mesh', $('mesh').value]];
  if (!$('scale-auto').checked) f.push(['scale_mm', state.scale_mm]);
  if (state.preset) f.push(['preset', state.preset]);
  else f.push(['sigma_a', state.sigma_a.join(',')], ['sigma_s_prime', state.sigma_s_prime.join(',')], ['eta', state.eta]);
  f.push(['light_dir', lightDirection().join(',')], ['light_intensity', state.intensity]);
  f.push(['camera_dir', cameraDirection().join(',')]);
  if ($('profile').value) f.push(['profile', $('profile').value]);
  const size = $('size').value.trim();
  f.push(['w', size], ['h', size]);
  const exposure = $('exposure').value.trim();
  if (exposure !== '' && Number(exposure) !== 0) f.push(['exposure', exposure]);
  if (method !== undefined) f.push(['method', method], ['samples', $('samples').value.trim()]);
  if (method === 'path') f.push(['path_time_s', PATH_TIME_S]);
  return f;
}
const toQuery = (fields) =>
  fields.map(([k, v]) => `${k}=${encodeURIComponent(String(v)).replace(/%2C/g, ',')}`).join('&');
const renderUrl = (method) => new URL(`/v1/render?${toQuery(sceneFields(method))}`, location.href).href;
// Renders of one scene by different methods share this key.
const sceneKey = () => toQuery(sceneFields());

function authHeaders() {
  const token = $('token').value.trim();
  return token ? { Authorization: `Bearer ${token}` } : {};
}

// A failed request: the server's problem+json when there is one.
class ProblemError extends Error {
  constructor(status, problem) {
    super(problem.detail || problem.title || `HTTP ${status}`);
    this.status = status;
    this.title = problem.title || '';
    this.field = problem.field || '';
  }
}
async function problemFrom(resp) {
  const text = await resp.text();
  try {
    return new ProblemError(resp.status, JSON.parse(text));
  } catch (e) {
    return new ProblemError(resp.status, { detail: text.slice(0, 300) || resp.statusText });
  }
}

// Query fields the server may name, and the control that sets them.
const FIELD_CONTROLS = { w: 'size', h: 'size', samples: 'samples', method: 'method', mesh: 'mesh', preset: 'preset',
  profile: 'profile', exposure: 'exposure', Authorization: 'token' };

function setError(source, error) {
  const old = errors.get(source);
  if (old && old.control) $(old.control).removeAttribute('aria-invalid');
  if (error) {
    const control = FIELD_CONTROLS[error.field];
    if (control) $(control).setAttribute('aria-invalid', 'true');
    errors.set(source, { error, control });
    if (error.status === 401) $('token-box').open = true;
  } else {
    errors.delete(source);
  }
  const box = $('error');
  box.replaceChildren();
  for (const [src, { error: e }] of errors) {
    const p = document.createElement('p');
    const head = document.createElement('strong');
    head.textContent = `${src} failed`;
    p.append(head, e.status ? ` (${e.status} ${e.title}): ${e.message}` : `: ${e.message}`);
    if (e.field) {
      const field = document.createElement('code');
      field.className = 'field';
      field.textContent = e.field;
      p.append(' (field ', field, ')');
    }
    box.append(p);
  }
  box.hidden = errors.size === 0;
}

// Server-Timing -> {name: {dur, desc}}.
function parseTiming(header) {
  const out = {};
  for (const part of (header || '').split(',')) {
    const [name, ...params] = part.trim().split(';');
    if (!name) continue;
    const entry = {};
    for (const p of params) {
      const [k, v] = p.split('=');
      entry[k.trim()] = k.trim() === 'dur' ? Number(v) : v;
    }
    out[name] = entry;
  }
  return out;
}

function describeTiming(t, roundTripMs) {
  const ms = (x) => `${x.toFixed(1)} ms`;
  const trip = `round trip ${ms(roundTripMs)}`;
  if (t.cache) return `from the server's image cache (${ms(t.cache.dur)}; ${trip})`;
  if (!t.render) return `cached by the browser (${trip})`;
  return `rendered in ${ms(t.render.dur)} (queue ${ms(t.queue ? t.queue.dur : 0)}, encode ${ms(t.encode ? t.encode.dur : 0)}; ${trip})`;
}

function describeModelled(m) {
  const parts = [];
  if (m.views !== undefined) parts.push(`${m.views} view${m.views === 1 ? '' : 's'}`);
  if (m.sampling) parts.push(`${m.samples_per_channel} samples, ${m.sampling}`);
  if (m.points) parts.push(`${m.points} points, ${m.sum} sum, est. error ${m.estimated_rel_error}`);
  if (m.rel_std_error !== undefined) parts.push(`${m.samples} walks a pixel, noise ${m.rel_std_error}`);
  if (m.profile) parts.push(`profile ${m.profile}`);
  if (m.scale_mm) parts.push(`${round3(m.scale_mm)} mm per unit`);
  return parts.join('; ');
}

const slots = {
  a: { img: $('image-a'), figure: $('figure-a'), status: $('status-a'), modelled: $('modelled-a'), renders: 0 },
  b: { img: $('image-b'), figure: $('figure-b'), status: $('status-b'), modelled: $('modelled-b'), renders: 0 },
};

function pixelsOf(img) {
  const canvas = document.createElement('canvas');
  canvas.width = img.naturalWidth;
  canvas.height = img.naturalHeight;
  const ctx = canvas.getContext('2d', { willReadFrequently: true });
  ctx.drawImage(img, 0, 0);
  return ctx.getImageData(0, 0, canvas.width, canvas.height);
}

async function render(slot, method) {
  if (slot.controller) slot.controller.abort();
  const controller = new AbortController();
  slot.controller = controller;
  const url = renderUrl(method);
  const key = sceneKey();
  slot.figure.dataset.state = 'rendering';
  slot.figure.setAttribute('aria-busy', 'true');
  slot.status.textContent = `${method}: rendering…`;
  const t0 = performance.now();
  try {
    const resp = await fetch(url, { signal: controller.signal, headers: authHeaders() });
    if (!resp.ok) throw await problemFrom(resp);
    const blob = await resp.blob();
    const objectUrl = URL.createObjectURL(blob);
    const img = new Image();
    img.src = objectUrl;
    await img.decode();
    if (controller.signal.aborted) {
      URL.revokeObjectURL(objectUrl);
      return;
    }
    if (slot.img.src.startsWith('blob:')) URL.revokeObjectURL(slot.img.src);
    slot.img.src = objectUrl;
    slot.img.alt = `${method} render of ${$('mesh').selectedOptions[0].text}, ${img.naturalWidth}x${img.naturalHeight}`;
    slot.pixels = { key, method, data: pixelsOf(img) };
    if (TRUTHS.includes(method)) {
      const kept = truths.get(key) || new Map();
      truths.delete(key);
      truths.set(key, kept.set(method, slot.pixels.data));
      if (truths.size > KEPT_TRUTHS) truths.delete(truths.keys().next().value);
    }
    const modelledText = resp.headers.get('Lucent-Modelled');
    const modelled = modelledText ? JSON.parse(modelledText) : {};
    slot.status.textContent = `${method}, ${img.naturalWidth}x${img.naturalHeight}: ` +
      `${describeTiming(parseTiming(resp.headers.get('Server-Timing')), performance.now() - t0)}. ${describeModelled(modelled)}`;
    slot.modelled.textContent = JSON.stringify(modelled, null, 2);
    slot.renders += 1;
    slot.figure.dataset.renders = String(slot.renders);
    slot.figure.dataset.state = 'done';
    setError(slot === slots.a ? 'render' : 'second render', null);
  } catch (e) {
    if (e.name === 'AbortError' || controller.signal.aborted) return;
    const error = e instanceof ProblemError ? e : new Error(`could not reach lucentd (${e.message})`);
    slot.figure.dataset.state = 'failed';
    slot.status.textContent = `${method}: failed (the error is above); the image is the last good one`;
    setError(slot === slots.a ? 'render' : 'second render', error);
  } finally {
    if (slot.controller === controller) {
      slot.controller = null;
      slot.figure.removeAttribute('aria-busy');
    }
    showAccuracy();
  }
}

// rel L2 = sqrt(sum (x - ref)^2 / sum ref^2) over R, G, B of the 8-bit sRGB pixels composited over black.
function relL2(image, ref) {
  let num = 0, den = 0;
  for (let i = 0; i < ref.data.length; i += 4) {
    const ai = image.data[i + 3] / 255, ar = ref.data[i + 3] / 255;
    for (let c = 0; c < 3; c++) {
      const x = image.data[i + c] * ai, r = ref.data[i + c] * ar;
      num += (x - r) ** 2;
      den += r * r;
    }
  }
  return den > 0 ? Math.sqrt(num / den) : NaN;
}

// Each image shown against each truth of the same scene other than itself: "five against reference",
// "reference against path" (the diffusion model against the walks).
function showAccuracy() {
  const key = sceneKey();
  const known = truths.get(key) || new Map();
  const lines = [];
  let againstPath = false;
  for (const slot of [slots.a, slots.b]) {
    if (slot.figure.hidden || !slot.pixels || slot.pixels.key !== key) continue;
    const img = slot.pixels.data;
    for (const [truth, ref] of known) {
      if (truth === slot.pixels.method || img.width !== ref.width || img.height !== ref.height) continue;
      const e = relL2(img, ref);
      againstPath = againstPath || truth === 'path';
      lines.push(`${slot.pixels.method} against ${truth}: relative L2 error ` +
        `${Number.isNaN(e) ? `undefined (the ${truth} image is black)` : e.toFixed(4)}`);
    }
  }
  const out = $('accuracy');
  if (lines.length) {
    out.textContent = `${lines.join('; ')}. Computed in this page on the 8-bit sRGB pixels (composited over black), ` +
      `not on linear radiance as the server's benchmarks do${againstPath ? '; path\'s own noise is part of any error against it' : ''}.`;
  } else {
    out.textContent = known.size ? '' :
      'No truth of this scene rendered yet: compare with "reference" (the model) or "path" (the walks) to see the error.';
  }
}

function updateLink() {
  $('link').value = renderUrl($('method').value);
  $('copy-status').textContent = '';
}

function schedule() {
  updateLink();
  clearTimeout(debounceTimer);
  debounceTimer = setTimeout(renderAll, DEBOUNCE_MS);
}

function renderAll() {
  render(slots.a, $('method').value);
  const compare = $('compare').checked;
  slots.b.figure.hidden = !compare;
  $('images').classList.toggle('two', compare);
  if (compare) {
    render(slots.b, $('method2').value);
  } else {
    if (slots.b.controller) slots.b.controller.abort();
    setError('second render', null);
  }
}

async function loadMaterials() {
  try {
    const resp = await fetch('/v1/materials', { headers: authHeaders() });
    if (!resp.ok) throw await problemFrom(resp);
    const doc = await resp.json();
    const select = $('preset');
    select.replaceChildren(select.options[0]);
    for (const m of doc.materials) {
      materials.set(m.name, { sigma_a: m.sigma_a.map(round3), sigma_s_prime: m.sigma_s_prime.map(round3), eta: m.eta });
      select.append(new Option(m.name, m.name));
    }
    select.value = state.preset;
    setError('materials', null);
  } catch (e) {
    setError('materials', e instanceof ProblemError ? e : new Error(`could not load the presets (${e.message})`));
  }
}

function choosePreset(name) {
  state.preset = name;
  const m = materials.get(name);
  if (m) {
    state.sigma_a = [...m.sigma_a];
    state.sigma_s_prime = [...m.sigma_s_prime];
    state.eta = m.eta;
  }
  showAllSliders();
}

const MESH_FILE = /\.(obj|ply|stl|gltf|glb)$/i;

// One mesh file goes as the body (the server sniffs its format); a glTF chosen or dropped together with
// the buffers and images it names goes as multipart/form-data, which the server resolves against them.
async function upload(fileList) {
  const files = [...fileList];
  const main = files.find((f) => MESH_FILE.test(f.name)) || files[0];
  const label = files.length > 1 ? `${main.name} and ${files.length - 1} more file(s)` : main.name;
  const status = $('mesh-status');
  const bytes = files.reduce((sum, f) => sum + f.size, 0);
  status.textContent = `uploading ${label} (${Math.ceil(bytes / 1024)} KiB)…`;
  let body = main;
  let headers = { ...authHeaders(), 'Content-Type': 'application/octet-stream' };
  if (files.length > 1) {
    body = new FormData();
    for (const f of files) body.append('file', f, f.name);
    headers = authHeaders(); // the browser writes the multipart Content-Type with its boundary
  }
  try {
    const resp = await fetch('/v1/meshes', { method: 'POST', body, headers });
    if (!resp.ok) throw await problemFrom(resp);
    const info = await resp.json();
    const select = $('mesh');
    let option = [...select.options].find((o) => o.value === info.id);
    if (!option) {
      option = new Option(`${main.name} (${info.triangles} triangles)`, info.id);
      select.append(option);
    }
    select.value = info.id;
    status.textContent = `${label}: ${info.triangles} triangles, ${info.vertices} vertices, id ${info.id.slice(0, 12)}…`;
    setError('upload', null);
    schedule();
  } catch (e) {
    status.textContent = `${label}: upload failed`;
    setError('upload', e instanceof ProblemError ? e : new Error(`could not upload ${label} (${e.message})`));
  }
}

async function copyLink() {
  const link = $('link');
  const note = $('token').value.trim() ? ' This daemon needs a token, which <img src> cannot send.' : '';
  try {
    await navigator.clipboard.writeText(link.value);
    $('copy-status').textContent = `Copied.${note}`;
  } catch (e) {
    link.focus();
    link.select();
    $('copy-status').textContent = `Selected: press Ctrl+C (or Cmd+C) to copy.${note}`;
  }
}

// The page's own query presets controls, e.g. /?mesh=torus&preset=marble&size=128&profile=burley&compare=path.
function applyPageQuery() {
  const q = new URLSearchParams(location.search);
  for (const id of ['mesh', 'method', 'size', 'samples', 'profile', 'exposure']) if (q.has(id)) $(id).value = q.get(id);
  if (q.has('preset')) state.preset = q.get('preset');
  if (q.has('compare')) {
    $('compare').checked = true;
    $('method2').value = q.get('compare');
  }
}

// Dragging an image orbits the camera around the object (left-right: azimuth, up-down: elevation);
// arrow keys on a focused image turn it by 5 degrees.
function orbit(dAzimuth, dElevation) {
  state.view_azimuth = ((((state.view_azimuth + dAzimuth + 180) % 360) + 360) % 360) - 180;
  state.view_elevation = Math.max(-85, Math.min(85, state.view_elevation + dElevation));
  for (const s of SLIDERS) if (s.key.startsWith('view_')) showSliderValue(s);
  schedule();
}

function wireOrbit(img) {
  let last = null;
  img.draggable = false;
  img.tabIndex = 0;
  img.title = 'Drag to orbit the camera (arrow keys when the image has focus)';
  img.addEventListener('pointerdown', (e) => {
    last = [e.clientX, e.clientY];
    img.setPointerCapture(e.pointerId);
  });
  img.addEventListener('pointermove', (e) => {
    if (!last) return;
    const [dx, dy] = [e.clientX - last[0], e.clientY - last[1]];
    last = [e.clientX, e.clientY];
    orbit(-dx * DRAG_DEGREES_PER_PIXEL, dy * DRAG_DEGREES_PER_PIXEL);
  });
  for (const end of ['pointerup', 'pointercancel']) img.addEventListener(end, () => { last = null; });
  img.addEventListener('keydown', (e) => {
    const turn = { ArrowLeft: [5, 0], ArrowRight: [-5, 0], ArrowUp: [0, -5], ArrowDown: [0, 5] }[e.key];
    if (!turn) return;
    e.preventDefault();
    orbit(...turn);
  });
}

function wire() {
  for (const id of ['mesh', 'method', 'method2', 'samples', 'size', 'profile', 'exposure']) {
    $(id).addEventListener('change', schedule);
    $(id).addEventListener('input', schedule);
  }
  $('preset').addEventListener('change', () => {
    choosePreset($('preset').value);
    schedule();
  });
  $('scale-auto').addEventListener('change', () => {
    showAllSliders();
    schedule();
  });
  $('compare').addEventListener('change', () => {
    $('method2').disabled = !$('compare').checked;
    schedule();
  });
  $('mesh-file').addEventListener('change', () => {
    const files = $('mesh-file').files;
    if (files.length) upload(files);
  });
  const drop = $('mesh-box');
  drop.addEventListener('dragover', (e) => {
    e.preventDefault();
    drop.classList.add('dragging');
  });
  drop.addEventListener('dragleave', () => drop.classList.remove('dragging'));
  drop.addEventListener('drop', (e) => {
    e.preventDefault();
    drop.classList.remove('dragging');
    const files = e.dataTransfer.files;
    if (files.length) upload(files);
  });
  for (const id of ['image-a', 'image-b']) wireOrbit($(id));
  $('copy-link').addEventListener('click', copyLink);
  $('token').value = sessionStorage.getItem('lucent-token') || '';
  $('token').addEventListener('change', async () => {
    sessionStorage.setItem('lucent-token', $('token').value.trim());
    await loadMaterials();
    schedule();
  });
}

async function main() {
  buildSliders();
  applyPageQuery();
  wire();
  $('method2').disabled = !$('compare').checked;
  await loadMaterials();
  choosePreset(materials.has(state.preset) ? state.preset : '');
  $('preset').value = state.preset;
  schedule();
}

main();
