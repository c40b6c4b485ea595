// The page: connects to the server that served it, shows a surface coloured by a field, and
// keeps the controls, the mesh and (with ?session=NAME) a shared session in step.
//
// URL parameters: session=NAME (join or create that session), key=K (the session's key, on
// servers that have session keys), token=T (when the server needs one), surface=ID (instead of
// the first listed: the built-in sample on a fresh server), coarse=N (triangles of the coarsest
// preview level, 2000 by default).
import './style.css';
import { drawLegend, formatValue, viridis } from './colormap.js';
import { ServerConnection } from './connection.js';
import { FileOpener } from './file_open.js';
import { decoderReady, IncomingLevel, MeshError, MeshState } from './mesh.js';
import { enumValues } from './protocol.js';
import { Viewer } from './viewer.js';

const Encoding = enumValues('Encoding');
const Strategy = enumValues('Strategy');
const Placement = enumValues('Placement');
const ErrorCode = enumValues('Error.Code');
const MAX_PREVIEW_LEVELS = 4;

const params = new URLSearchParams(location.search);
const sessionName = params.get('session') ?? '';
const sessionKey = params.get('key') ?? '';
const coarseTriangles = Math.max(1, Number(params.get('coarse')) || 2000);

const $ = (id) => document.getElementById(id);
const ui = {
  status: $('status'), notice: $('notice'), surface: $('surface'), field: $('field'),
  alpha: $('alpha'), alphaValue: $('alpha-value'), level: $('level'), levelValue: $('level-value'),
  strategy: $('strategy'), placement: $('placement'), triangles: $('triangles'),
  trianglesOf: $('triangles-of'), levelError: $('level-error'), exactness: $('exactness'),
  reduction: $('reduction'), time: $('time'), levels: $('levels'), session: $('session'),
  progress: $('progress'), progressText: $('progress-text'), legend: $('legend'),
};

const state = {
  surfaces: [],
  // Placement: the library's default (least error); the protocol's unspecified is the midpoint.
  view: { surface: params.get('surface') ?? '', alpha: 0.5, keep: 0.5, field: '',
    strategy: Strategy.EDGE_COLLAPSE, placement: Placement.LEAST_ERROR }, // until Welcome.defaults
  defaultsLearned: false,
  mesh: new MeshState(),
  meshSurface: '', // the surface the mesh shown belongs to
  meshBegin: null, // the MeshBegin of the last level applied
  meshPending: false, // applied, but its surface is not listed yet
  incoming: null, // { begin, level: IncomingLevel | null (ignored) }
  request: null, // this page's own request (without a session)
  nextRequestId: 1,
  changeStarted: performance.now(), // when the view last changed, for "the time it took"
  waiting: false,
  session: null, // the last SessionState
  joined: false, // JoinSession sent on this connection
  relisted: '', // the session surface the list was last read again for
  clientId: 0,
};

const viewer = new Viewer($('view'));
viewer.offerVR(document.body);

const wsUrl = `${location.protocol === 'https:' ? 'wss' : 'ws'}://${location.host}/ws`;
const connection = new ServerConnection(wsUrl, {
  token: params.get('token') ?? '',
  handlers: {
    onStatus: showStatus,
    onReady: (welcome) => {
      state.clientId = welcome.client_id;
      learnDefaults(welcome.defaults);
      state.joined = false; // a new connection is in no session yet
      connection.send('ListSurfaces', {});
    },
    onMessage: handle,
  },
});
decoderReady.then(() => connection.connect());

// A file opened in the page goes into the session (or to this page alone), and is then shown.
const opener = new FileOpener({
  connection, progress: setProgress, notice,
  session: () => (sessionName && state.joined ? sessionName : ''),
  onUploaded: (result) => {
    notice('');
    // In a session the server switches the session's view to it; alone, this page does.
    if (!sessionName) state.view.surface = result.surface;
    connection.send('ListSurfaces', {});
  },
});
opener.attach($('upload'), document.body);

// The options the server fills in for what a request leaves unset (the library's defaults): the
// controls start from them, once, before this page asks for anything.
function learnDefaults(d) {
  if (!d || state.defaultsLearned) return;
  state.defaultsLearned = true;
  state.view.alpha = d.alpha;
  if (d.strategy) state.view.strategy = d.strategy;
  if (d.placement) state.view.placement = d.placement;
  showControls();
}

// ----- status and progress -----

function showStatus(kind, text) {
  ui.status.textContent = text;
  ui.status.dataset.state = kind;
  if (kind !== 'connected') setProgress(null);
}

function notice(text) {
  ui.notice.textContent = text;
  ui.notice.hidden = !text;
}

// fraction null hides the bar; NaN shows it busy without a value.
function setProgress(fraction, text = '') {
  if (fraction === null) {
    ui.progress.hidden = true;
    ui.progressText.textContent = '';
    return;
  }
  ui.progress.hidden = false;
  if (Number.isNaN(fraction)) ui.progress.removeAttribute('value');
  else ui.progress.value = fraction;
  ui.progressText.textContent = text;
}

// ----- messages -----

function handle(name, m) {
  switch (name) {
    case 'SurfaceList': return onSurfaceList(m);
    case 'SessionState': return onSessionState(m);
    case 'MeshBegin': return onMeshBegin(m);
    case 'MeshChunk': return onMeshChunk(m);
    case 'MeshEnd': return onMeshEnd(m);
    case 'RequestDone': return onRequestDone(m);
    case 'Error': return opener.onError(m) || onError(m);
    case 'UploadResult': return opener.onUploadResult(m);
    default: return undefined; // not asked for by this page
  }
}

function onSurfaceList(m) {
  state.surfaces = m.surfaces;
  ui.surface.replaceChildren(...m.surfaces.map((s) =>
    new Option(`${s.name || s.surface.slice(0, 12)} (${s.triangles.toLocaleString('en')} triangles)`,
      s.surface)));
  if (m.surfaces.length === 0) {
    notice('The server has no surfaces yet: open a file here, or upload one with ' +
      '`ddsimp remote upload FILE`.');
    return;
  }
  if (!surfaceInfo(state.view.surface)) state.view.surface = m.surfaces[0].surface;
  ui.surface.value = state.view.surface;
  fillFields();
  if (sessionName && state.joined) {
    if (state.session) onSessionState(state.session); // the list it waited for
    if (state.meshPending && surfaceInfo(state.meshSurface)) showMesh();
  } else if (sessionName) {
    if (sessionKey && !connection.welcome.capabilities.includes('session-keys')) {
      // Joining without the key would put this page in the public session of that name.
      notice('This server has no session keys (?key=): the page does not join the session.');
      return;
    }
    connection.send('JoinSession', sessionKey ? { name: sessionName, key: sessionKey } :
      { name: sessionName });
    state.joined = true;
  } else {
    requestMesh();
  }
}

function surfaceInfo(id) {
  return state.surfaces.find((s) => s.surface === id);
}

function fillFields() {
  const info = surfaceInfo(state.view.surface);
  const fields = info ? info.fields : [];
  ui.field.replaceChildren(...fields.map((f) =>
    new Option(f.components === 1 ? f.name : `${f.name} (|vector|)`, f.name)));
  if (!fields.some((f) => f.name === state.view.field)) {
    // The first scalar that varies, else whatever there is.
    const varying = fields.find((f) => f.components === 1 && f.max > f.min);
    state.view.field = (varying ?? fields[0])?.name ?? '';
  }
  ui.field.value = state.view.field;
}

function onSessionState(m) {
  if (m.name !== sessionName) return;
  state.session = m;
  const members = m.members.length;
  const leader = m.leader === state.clientId ? 'you lead' :
    `led by ${m.members.find((x) => x.client_id === m.leader)?.name || `client ${m.leader}`}`;
  ui.session.textContent =
    `${m.name}: ${members} member${members === 1 ? '' : 's'}, ${leader} (version ${m.version})`;
  const v = m.view;
  if (!v.surface) {
    // A new session: it shows what this page would show.
    connection.send('SetSessionState', {
      name: sessionName, set_alpha: true,
      view: { surface: state.view.surface, alpha: state.view.alpha,
        alpha_exact: state.view.alpha, keep: state.view.keep,
        field: state.view.field, strategy: state.view.strategy,
        placement: state.view.placement },
    });
    return;
  }
  if (!surfaceInfo(v.surface)) {
    // Uploaded since the list was read: read it again, then take this state (once).
    if (state.relisted === v.surface) {
      notice(`The session shows surface ${v.surface}, which this server does not list.`);
      return;
    }
    state.relisted = v.surface;
    if (!state.waiting) startWaiting();
    connection.send('ListSurfaces', {});
    return;
  }
  const before = { ...state.view };
  state.view.surface = v.surface;
  state.view.alpha = v.alpha_exact ?? fromFloat32(v.alpha);
  if (v.keep > 0) state.view.keep = fromFloat32(v.keep);
  if (v.strategy) state.view.strategy = v.strategy;
  if (v.placement) state.view.placement = v.placement;
  if (before.surface !== v.surface) fillFields();
  if (v.field && surfaceInfo(v.surface).fields.some((f) => f.name === v.field))
    state.view.field = v.field;
  showControls();
  const meshChanged = before.surface !== state.view.surface || before.alpha !== state.view.alpha ||
    before.keep !== state.view.keep || before.strategy !== state.view.strategy ||
    before.placement !== state.view.placement;
  if (meshChanged && !state.waiting) startWaiting();
  if (before.field !== state.view.field) recolour();
}

// α and keep travel as float32: 0.3 comes back as 0.30000001192, which is still the 0.3 the
// slider was set to.
function fromFloat32(x) {
  return Number(x.toPrecision(7));
}

function acceptsMesh(begin) {
  if (sessionName) return begin.request_id === 0 && begin.session === sessionName;
  return state.request !== null && begin.request_id === state.request.id;
}

function onMeshBegin(m) {
  if (!acceptsMesh(m)) {
    state.incoming = { begin: m, level: null };
    return;
  }
  try {
    state.incoming = { begin: m, level: new IncomingLevel(m) };
  } catch (e) {
    state.incoming = { begin: m, level: null };
    notice(`A level the page cannot take: ${e.message}`);
    return;
  }
  showTransfer();
}

function sameItem(m) {
  const b = state.incoming?.begin;
  return b && b.request_id === m.request_id && b.level === m.level;
}

function onMeshChunk(m) {
  if (!sameItem(m) || !state.incoming.level) return;
  try {
    state.incoming.level.add(m);
  } catch (e) {
    notice(`A bad level from the server: ${e.message}`);
    state.incoming.level = null;
    return;
  }
  showTransfer();
}

function showTransfer() {
  const { begin, level } = state.incoming;
  const count = sessionName ? 1 : state.request.levels;
  const index = sessionName ? 0 : state.request.applied;
  const percent = Math.round(100 * level.fraction);
  setProgress((index + level.fraction) / count,
    `level ${index + 1} of ${count} (${begin.total_triangles.toLocaleString('en')} triangles): ` +
    `${percent}% of ${formatBytes(begin.total_bytes)}`);
}

function formatBytes(n) {
  return n < 1024 ? `${n} B` : n < 1 << 20 ? `${(n / 1024).toFixed(1)} KiB` :
    `${(n / (1 << 20)).toFixed(1)} MiB`;
}

function onMeshEnd(m) {
  if (!sameItem(m) || !state.incoming.level) return;
  const { begin, level } = state.incoming;
  state.incoming = null;
  if (!level.complete) {
    notice(`A level ended after ${level.received} of ${level.total} bytes`);
    return;
  }
  const refinement = begin.kind === enumValues('MeshBegin.Kind').REFINEMENT;
  if (refinement && (state.request?.applied ?? 0) === 0) return; // its base never arrived
  if (begin.preview && state.request?.applied) return; // an exact level is shown already
  try {
    const live = state.mesh.apply(begin, level.bytes);
    if (live !== begin.total_triangles)
      throw new MeshError(`${live} triangles after the level, but the server says ` +
        `${begin.total_triangles}`);
  } catch (e) {
    if (!(e instanceof MeshError)) throw e;
    notice(`The level could not be shown: ${e.message}`);
    return;
  }
  if (state.request && !begin.preview) ++state.request.applied;
  // The server says which surface this is; a server older than MeshBegin.surface does not, and
  // then it is the one asked for, or the session's.
  state.meshSurface = begin.surface ||
    (sessionName ? state.session?.view.surface ?? state.view.surface : state.request.surface);
  state.meshBegin = begin;
  // A surface uploaded a moment ago is shown once the list that names it has come.
  state.meshPending = !surfaceInfo(state.meshSurface);
  if (!state.meshPending) showMesh();
}

function showMesh() {
  const begin = state.meshBegin;
  state.meshPending = false;
  display(state.meshSurface, begin);
  showExactness(begin);
  if (begin.preview) return; // the exact level follows
  const lastLevel = sessionName || state.request.applied === state.request.levels;
  if (lastLevel) finishWaiting(begin);
  else showTransfer0();
}

// A preview (the nearest level the server had ready) is labelled until the exact level replaces it.
function showExactness(begin) {
  ui.exactness.dataset.preview = String(Boolean(begin.preview));
  ui.exactness.textContent = begin.preview ?
    `a preview (${begin.total_triangles.toLocaleString('en')} triangles, the nearest level ` +
      'the server had ready); the exact level follows' : 'the exact level';
}

function showTransfer0() {
  setProgress(state.request.applied / state.request.levels,
    `level ${state.request.applied} of ${state.request.levels} shown, refining…`);
}

function onRequestDone(m) {
  if (state.request && m.request_id === state.request.id) state.request.done = true;
}

function onError(m) {
  if (m.request_id !== 0 && (!state.request || m.request_id !== state.request.id)) return;
  if (m.code === ErrorCode.CANCELLED) return;
  notice(`The server says: ${m.message}`);
  if (state.waiting) {
    state.waiting = false;
    setProgress(null);
  }
}

// ----- what the page asks for -----

// The keep fractions of one request: the level asked for and up to MAX_PREVIEW_LEVELS coarser
// ones, each a quarter of the next, down to about coarseTriangles (the server sends the coarsest
// first, whole, and each finer one as a refinement of it).
function keepLadder(keep, triangles) {
  const keeps = [keep];
  let k = keep;
  while (keeps.length <= MAX_PREVIEW_LEVELS && k * triangles > coarseTriangles) {
    k /= 4;
    keeps.unshift(k);
  }
  return keeps;
}

function requestMesh() {
  const info = surfaceInfo(state.view.surface);
  if (!info) return;
  const keep = keepLadder(state.view.keep, info.triangles);
  state.request = { id: state.nextRequestId++, surface: info.surface, levels: keep.length,
    applied: 0, done: false };
  state.incoming = null;
  connection.send('Request', {
    request_id: state.request.id, surface: info.surface, alpha: state.view.alpha,
    alpha_exact: state.view.alpha, supersede: true, keep,
    strategy: state.view.strategy, placement: state.view.placement, progressive: true,
    encoding: Encoding.MESHOPT,
  });
  startWaiting();
}

function startWaiting() {
  state.waiting = true;
  state.changeStarted = performance.now();
  setProgress(NaN, 'simplifying on the server…');
}

function finishWaiting(begin) {
  state.waiting = false;
  setProgress(null);
  const ms = performance.now() - state.changeStarted;
  const server = begin.cached || begin.seconds === 0 ? 'reduction cached on the server' :
    `simplified in ${begin.seconds.toFixed(3)} s on the server`;
  ui.time.textContent = `${server}; shown ${Math.round(ms)} ms after the change`;
  ui.levels.textContent = sessionName ? 'the session\'s level, whole' :
    state.request.levels === 1 ? '1 (the level asked for, whole)' :
      `${state.request.levels} (coarsest first, then refinements)`;
}

// ----- the picture -----

function toLinear(c) {
  return c <= 0.04045 ? c / 12.92 : ((c + 0.055) / 1.055) ** 2.4;
}

// Per-vertex colours (linear, as three.js expects) of the field chosen, and the legend.
function colours() {
  const mesh = state.mesh;
  const out = new Float32Array(3 * mesh.vertexCount).fill(0.2);
  const info = surfaceInfo(state.meshSurface)?.fields.find((f) => f.name === state.view.field);
  const data = info && mesh.scalars(info.name);
  if (!data) {
    ui.legend.hidden = true;
    return out;
  }
  let min = info.min;
  let max = info.max;
  let note = 'range over the whole surface';
  if (data.components > 1) {
    // The server's range is over the components, not the length: use the level's own.
    min = Infinity;
    max = -Infinity;
    for (const v of data.values) {
      min = Math.min(min, v);
      max = Math.max(max, v);
    }
    note = 'range over the vertices shown';
  }
  const span = max > min ? max - min : 1;
  for (let v = 0; v < mesh.vertexCount; ++v) {
    const rgb = viridis(max > min ? (data.values[v] - min) / span : 0.5);
    out[3 * v] = toLinear(rgb[0]);
    out[3 * v + 1] = toLinear(rgb[1]);
    out[3 * v + 2] = toLinear(rgb[2]);
  }
  drawLegend(ui.legend, {
    title: data.components > 1 ? `|${info.name}| (length of ${data.components} components)` :
      info.name,
    min, max, note: `${note}; units are not known to the server`,
  });
  return out;
}

function display(surface, begin) {
  const mesh = state.mesh;
  viewer.show({ surfaceKey: surface, positions: mesh.positions, vertexCount: mesh.vertexCount,
    slots: mesh.slots, slotCount: mesh.slotCount, colours: colours() });
  const info = surfaceInfo(surface);
  ui.triangles.textContent = String(mesh.liveTriangles);
  ui.trianglesOf.textContent = info ? info.triangles.toLocaleString('en') : '?';
  const percent = info ? (100 * mesh.liveTriangles) / info.triangles : NaN;
  ui.reduction.textContent = `${formatValue(percent)}% of the triangles kept` +
    (begin.target_reached ? '' : ' (the target was not reached: nothing more is removable ' +
      'without changing the topology)');
  showLevelError(begin.error, begin.preview);
  notice('');
}

// A fraction as a percentage with two significant digits (0.00123 -> "0.12%").
function asPercent(x) {
  const p = 100 * x;
  return p === 0 ? '0%' : p >= 10 ? `${p.toFixed(1)}%` : `${Number(p.toPrecision(2))}%`;
}

// MeshBegin.error: geometric in bounding-box diagonals, data in field ranges; the raw numbers
// are kept as data attributes for tests and tools.
function showLevelError(error, preview) {
  const el = ui.levelError;
  if (!error) {
    el.textContent = preview ? '– (not measured for a preview)' : '– (this server does not say)';
    delete el.dataset.geometric;
    delete el.dataset.data;
    return;
  }
  el.dataset.geometric = String(error.geometric);
  const parts = [`${asPercent(error.geometric)} of diagonal (geometry)`];
  if (error.data_components > 0) {
    el.dataset.data = String(error.data);
    parts.push(`${asPercent(error.data)} of range (data)`);
  } else {
    delete el.dataset.data;
    parts.push('no data measured');
  }
  el.textContent = parts.join(', ');
}

function recolour() {
  if (state.mesh.vertexCount > 0) viewer.recolour(colours());
}

// ----- the controls -----

function showControls() {
  for (const input of [ui.alpha, ui.level, ui.field, ui.surface, ui.strategy, ui.placement])
    if (input.dataset.dragging) return; // the user's hand wins until released
  ui.surface.value = state.view.surface;
  ui.alpha.value = String(state.view.alpha);
  ui.level.value = String(state.view.keep);
  ui.field.value = state.view.field;
  ui.strategy.value = String(state.view.strategy || Strategy.EDGE_COLLAPSE);
  ui.placement.value = String(state.view.placement || Placement.LEAST_ERROR);
  ui.placement.disabled = Number(ui.strategy.value) === Strategy.VERTEX_REMOVAL;
  showControlValues();
}

function showControlValues() {
  ui.alphaValue.textContent = Number(ui.alpha.value).toFixed(2);
  ui.levelValue.textContent = `${Math.round(Number(ui.level.value) * 100)}%`;
}

// A change made on this page: solo, it asks for the mesh; in a session, it steers the session
// and every member (this page too) gets the new state and mesh from the server.
function change(part) {
  Object.assign(state.view, part);
  if (sessionName) {
    const view = 'alpha' in part ? { ...part, alpha_exact: part.alpha } : part;
    connection.send('SetSessionState', { name: sessionName, view, set_alpha: 'alpha' in part });
    if (!('field' in part)) startWaiting();
  }
  if ('field' in part) recolour();
  if ('surface' in part) fillFields();
  if (!sessionName && !('field' in part)) requestMesh();
}

function debounced(fn, ms) {
  let timer;
  return () => {
    clearTimeout(timer);
    timer = setTimeout(fn, ms);
  };
}

function slider(input, key) {
  const commit = () => {
    const value = Number(input.value);
    if (value !== state.view[key]) change({ [key]: value });
  };
  const later = debounced(commit, 250);
  input.addEventListener('input', () => {
    showControlValues();
    later();
  });
  input.addEventListener('change', commit);
  input.addEventListener('pointerdown', () => { input.dataset.dragging = '1'; });
  const release = () => delete input.dataset.dragging;
  input.addEventListener('pointerup', release);
  input.addEventListener('pointercancel', release);
}

slider(ui.alpha, 'alpha');
slider(ui.level, 'keep');
ui.field.addEventListener('change', () => change({ field: ui.field.value }));
ui.surface.addEventListener('change', () => change({ surface: ui.surface.value }));
ui.strategy.addEventListener('change', () => {
  ui.placement.disabled = Number(ui.strategy.value) === Strategy.VERTEX_REMOVAL;
  change({ strategy: Number(ui.strategy.value) });
});
ui.placement.addEventListener('change', () => change({ placement: Number(ui.placement.value) }));
$('edges').addEventListener('change', (e) => viewer.showEdges(e.target.checked));
ui.strategy.replaceChildren(new Option('edge collapse', String(Strategy.EDGE_COLLAPSE)),
  new Option('vertex removal', String(Strategy.VERTEX_REMOVAL)));
ui.placement.replaceChildren(new Option('least error', String(Placement.LEAST_ERROR)),
  new Option('midpoint', String(Placement.MIDPOINT)),
  new Option('volume-preserving', String(Placement.VOLUME)));
showControls();
if (sessionName) ui.session.textContent = `${sessionName}: joining…`;
