// ARKit's 52 blendshape names in Apple's order, and the one parser of the
// spellings found in the wild (the same rules as the core's
// `Blendshape::parse` in rust-core/src/arkit/blendshape.rs).

export const ARKIT_NAMES = Object.freeze([
  'eyeBlinkLeft', 'eyeLookDownLeft', 'eyeLookInLeft', 'eyeLookOutLeft', 'eyeLookUpLeft',
  'eyeSquintLeft', 'eyeWideLeft', 'eyeBlinkRight', 'eyeLookDownRight', 'eyeLookInRight',
  'eyeLookOutRight', 'eyeLookUpRight', 'eyeSquintRight', 'eyeWideRight', 'jawForward',
  'jawLeft', 'jawRight', 'jawOpen', 'mouthClose', 'mouthFunnel', 'mouthPucker', 'mouthLeft',
  'mouthRight', 'mouthSmileLeft', 'mouthSmileRight', 'mouthFrownLeft', 'mouthFrownRight',
  'mouthDimpleLeft', 'mouthDimpleRight', 'mouthStretchLeft', 'mouthStretchRight',
  'mouthRollLower', 'mouthRollUpper', 'mouthShrugLower', 'mouthShrugUpper', 'mouthPressLeft',
  'mouthPressRight', 'mouthLowerDownLeft', 'mouthLowerDownRight', 'mouthUpperUpLeft',
  'mouthUpperUpRight', 'browDownLeft', 'browDownRight', 'browInnerUp', 'browOuterUpLeft',
  'browOuterUpRight', 'cheekPuff', 'cheekSquintLeft', 'cheekSquintRight', 'noseSneerLeft',
  'noseSneerRight', 'tongueOut',
]);

export const ARKIT_COUNT = ARKIT_NAMES.length;

/** Index of each name, by its lower-case form. */
const INDEX_BY_KEY = new Map(ARKIT_NAMES.map((name, i) => [name.toLowerCase(), i]));

/** The groups the sliders are shown in: [title, first index, end index). */
export const GROUPS = Object.freeze([
  ['Eyes', 0, 14],
  ['Jaw', 14, 18],
  ['Mouth', 18, 41],
  ['Brows', 41, 46],
  ['Cheeks and nose', 46, 51],
  ['Tongue', 51, 52],
]);

/** The lower-case key of a spelling: `blendShape1.eyeBlink_L` → `eyeblinkleft`. */
function key(text) {
  const trimmed = text.trim();
  const last = trimmed.slice(trimmed.lastIndexOf('.') + 1);
  let k = last.replace(/[_\- ]/g, '').toLowerCase();
  // ICT-FaceKit / ARKit raw values: a trailing `_L` / `_R`.
  const lower = last.toLowerCase();
  if (lower.endsWith('_l')) k = k.slice(0, -1) + 'left';
  else if (lower.endsWith('_r')) k = k.slice(0, -1) + 'right';
  return k;
}

/**
 * Index (0–51) of an ARKit name in any spelling the core accepts
 * (`eyeBlinkLeft`, `EyeBlinkLeft`, `eyeBlink_L`, `eye_blink_left`, after a
 * dotted prefix), or -1.
 */
export function parseName(text) {
  const i = INDEX_BY_KEY.get(key(text));
  return i === undefined ? -1 : i;
}

/**
 * The ARKit shape a morph target of this name follows, or -1: its own name,
 * or for one half of a split shape (`browInnerUp_L`, `cheekPuffRight`) the
 * whole shape, which drives both halves with the same weight.
 */
export function targetShape(text) {
  const whole = parseName(text);
  if (whole >= 0) return whole;
  const k = key(text);
  const half = k.match(/^(.*?)(left|right)$/);
  if (!half) return -1;
  const i = INDEX_BY_KEY.get(half[1]);
  return i === undefined ? -1 : i;
}
