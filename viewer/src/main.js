// The Likeness avatar viewer. Query parameters (all optional; `likeness view`
// writes them):
//   a=URL      the left avatar (GLB); with b, the generic one
//   b=URL      the right avatar (GLB); with a, the personalized one
//   take=URL   a weight stream: Live Link Face CSV or `likeness export`'s frames.csv
// The same can be opened from disk with the pickers in the header. Both
// avatars always show the same 52 weights: the stream's current frame, as
// changed by the sliders.

import { ARKIT_COUNT, ARKIT_NAMES } from './arkit.js';
import { Avatar } from './avatar.js';
import { Player } from './player.js';
import { Sliders } from './sliders.js';
import { Stage } from './stage.js';
import { exposeStatus } from './status.js';
import { parseWeightStream } from './weight-stream.js';

const $ = (id) => document.getElementById(id);

/** What the page holds. */
const state = {
  /** Left to right; an entry is null while empty. */
  avatars: [null, null],
  weights: new Float32Array(ARKIT_COUNT),
  /** Every requested file loaded or failed. */
  ready: false,
  error: null,
};

const stage = new Stage($('canvas'));
const player = new Player(showFrame, showTransport);
const sliders = new Sliders($('sliders'), (shape, value) => {
  // A hand on a slider stops the take, so the frame does not overwrite it.
  player.pause();
  state.weights[shape] = value;
  applyWeights();
});

/** Puts the current weights on every avatar, the sliders and the screen. */
function applyWeights() {
  for (const avatar of shownAvatars()) avatar.setWeights(state.weights);
  sliders.show(state.weights);
  stage.requestRender();
}

function shownAvatars() {
  return state.avatars.filter(Boolean);
}

/** A new frame of the take: its weights replace the current ones. */
function showFrame(weights, frame) {
  state.weights.set(weights);
  applyWeights();
  $('scrub').value = String(frame);
  showTransport();
}

/** The play button, the frame counter and the clock. */
function showTransport() {
  const stream = player.stream;
  $('play').textContent = player.playing ? 'Pause' : 'Play';
  $('play').disabled = !stream;
  $('scrub').disabled = !stream;
  $('clock').textContent = stream
    ? `frame ${player.frame + 1} / ${stream.count} · ${player.time.toFixed(2)} / ${player.duration.toFixed(2)} s`
    : 'no take';
}

/** Shows the avatars that are loaded, side by side, with their labels. */
function showAvatars() {
  const avatars = shownAvatars();
  stage.setAvatars(avatars);
  $('labels').replaceChildren(...avatars.map((avatar) => {
    const label = document.createElement('div');
    label.textContent = avatar.label;
    return label;
  }));
  const present = ARKIT_NAMES.map((_, shape) => avatars.some((a) => a.bindings[shape].length > 0));
  sliders.enable(present);
  applyWeights();
  say(avatars.map(describe).join(' · ') || 'Open a GLB to start (or run likeness view).');
}

function describe(avatar) {
  const names = Object.keys(avatar.targetCounts()).length;
  const targets = avatar.bindings.reduce((n, pairs) => n + pairs.length, 0);
  const other = avatar.unmatched.length ? `, ${avatar.unmatched.length} other targets at 0` : '';
  return `${avatar.label}: ${names}/52 ARKit names, ${targets} morph targets in ${avatar.meshCount} meshes${other}`;
}

function setStream(stream) {
  player.setStream(stream);
  $('scrub').max = String(Math.max(stream.count - 1, 0));
  showTransport();
}

/** A line in the header; errors stay until the next message. */
function say(text, isError = false) {
  $('message').textContent = text;
  $('message').title = text;
  $('message').classList.toggle('error', isError);
}

function fail(what, error) {
  state.error = `${what}: ${error.message ?? error}`;
  say(state.error, true);
  console.error(error);
}

/** The last part of a URL or path, for labels. */
function fileName(url) {
  return decodeURIComponent(url.split('?')[0].split('/').pop() || url);
}

async function fetchText(url) {
  const response = await fetch(url);
  if (!response.ok) throw new Error(`${response.status} ${response.statusText}`);
  return response.text();
}

/** Loads what the query names. */
async function start() {
  const params = new URLSearchParams(location.search);
  const both = params.has('a') && params.has('b');
  const slots = [['a', 'generic'], ['b', 'personalized']];
  await Promise.all(slots.map(async ([param, role], slot) => {
    const url = params.get(param);
    if (!url) return;
    const label = both ? `${role}: ${fileName(url)}` : fileName(url);
    try {
      state.avatars[slot] = await Avatar.load(url, label);
    } catch (error) {
      fail(fileName(url), error);
    }
  }));
  showAvatars();
  const take = params.get('take');
  if (take) {
    try {
      setStream(parseWeightStream(await fetchText(take), fileName(take)));
    } catch (error) {
      fail(fileName(take), error);
    }
  }
  if (state.error) say(state.error, true);
  state.ready = true;
}

/** The header's file pickers: avatars into their slot, a take into the player. */
function wirePickers() {
  [['open-a', 0], ['open-b', 1]].forEach(([id, slot]) => {
    $(id).addEventListener('change', async (event) => {
      const file = event.target.files[0];
      if (!file) return;
      try {
        state.avatars[slot] = await Avatar.fromBytes(await file.arrayBuffer(), file.name);
        state.error = null;
        showAvatars();
      } catch (error) {
        fail(file.name, error);
      }
    });
  });
  $('open-take').addEventListener('change', async (event) => {
    const file = event.target.files[0];
    if (!file) return;
    try {
      setStream(parseWeightStream(await file.text(), file.name));
      state.error = null;
    } catch (error) {
      fail(file.name, error);
    }
  });
}

function wireTransport() {
  $('play').addEventListener('click', () => (player.playing ? player.pause() : player.play()));
  $('scrub').addEventListener('input', () => player.seekFrame(Number($('scrub').value)));
  $('loop').addEventListener('change', () => { player.loop = $('loop').checked; });
  $('zero').addEventListener('click', () => {
    player.pause();
    state.weights.fill(0);
    applyWeights();
  });
  $('front').addEventListener('click', () => stage.resetView());
  document.addEventListener('keydown', (event) => {
    if (event.code !== 'Space' || event.target.closest?.('input, button')) return;
    event.preventDefault();
    $('play').click();
  });
}

exposeStatus(() => ({
  ready: state.ready,
  error: state.error,
  avatars: shownAvatars().map((avatar) => ({
    label: avatar.label,
    meshes: avatar.meshCount,
    targets: avatar.targetCounts(),
    unmatched: [...avatar.unmatched],
    faceSize: avatar.faceSize(),
  })),
  stream: player.stream && {
    source: player.stream.source,
    format: player.stream.format,
    frames: player.stream.count,
    duration: player.duration,
  },
  frame: player.frame,
  time: player.time,
  playing: player.playing,
  weights: Object.fromEntries(ARKIT_NAMES.map((name, i) => [name, state.weights[i]])),
  renders: stage.renders,
}));

wirePickers();
wireTransport();
showTransport();
start();
