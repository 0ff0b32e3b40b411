// Weight streams: a Live Link Face CSV (`Timecode,BlendShapeCount,
// EyeBlinkLeft,…` with `HH:MM:SS:FF.fff` timecodes and head and eye rotation
// columns) or the `frames.csv` that `likeness export` writes
// (`timestamp,<52 names>`, seconds). The rules follow the core's reader
// (rust-core/src/session/interchange/weights_csv.rs and frame_stream.rs):
// any spelling of the 52 names, each exactly once; spaces around fields,
// a byte-order mark, CRLF and blank lines accepted; bad input is an error
// naming the line and column. No DOM here, so Node's test runner can load it.

import { ARKIT_COUNT, ARKIT_NAMES, parseName } from './arkit.js';

/** Live Link Face columns that are not weights (ignored beside a Timecode). */
const LIVE_LINK_EXTRA = new Set([
  'blendshapecount', 'headyaw', 'headpitch', 'headroll', 'lefteyeyaw', 'lefteyepitch',
  'lefteyeroll', 'righteyeyaw', 'righteyepitch', 'righteyeroll',
]);

/** Frame rates a Live Link timecode's frame number is counted in. */
const TIMECODE_RATES = [24, 25, 30, 48, 50, 60, 120];

/** How far outside [0, 1] a weight may lie (kept as it is, as the core does). */
const WEIGHT_TOLERANCE = 1e-3;

export class StreamError extends Error {
  constructor(source, line, column, message) {
    super(`${source}, line ${line}${column ? `, column ${column}` : ''}: ${message}`);
    this.name = 'StreamError';
  }
}

/**
 * Parses a weight stream.
 * @param {string} text the CSV text
 * @param {string} source a name for errors (the file's)
 * @returns {{format: 'live-link'|'timestamp', source: string, count: number,
 *   times: Float64Array, weights: Float32Array}} times in seconds from the
 *   first frame; weights row-major, 52 per frame in ARKit's order
 */
export function parseWeightStream(text, source = 'take') {
  const lines = splitLines(text);
  if (lines.length === 0) throw new StreamError(source, 1, 0, 'empty file: no header');
  const header = parseHeader(lines[0], source);
  const count = lines.length - 1;
  const weights = new Float32Array(count * ARKIT_COUNT);
  const keys = [];
  for (let r = 0; r < count; r++) {
    const { line, fields } = lines[r + 1];
    if (fields.length !== header.columns.length) {
      throw new StreamError(source, line, 0,
        `${fields.length} fields where the header has ${header.columns.length}`);
    }
    keys.push({ line, text: fields[header.keyColumn] });
    header.columns.forEach((shape, c) => {
      if (shape < 0) return;
      const value = Number(fields[c]);
      if (fields[c] === '' || !Number.isFinite(value)) {
        throw new StreamError(source, line, c + 1,
          `${ARKIT_NAMES[shape]} weight ${JSON.stringify(fields[c])} is not a number`);
      }
      if (value < -WEIGHT_TOLERANCE || value > 1 + WEIGHT_TOLERANCE) {
        throw new StreamError(source, line, c + 1,
          `${ARKIT_NAMES[shape]} weight ${value} is outside [0, 1]`);
      }
      weights[r * ARKIT_COUNT + shape] = value;
    });
  }
  const format = header.liveLink ? 'live-link' : 'timestamp';
  const times = header.liveLink
    ? timecodeSeconds(keys, source, header.keyColumn)
    : timestampSeconds(keys, source, header.keyColumn);
  for (let r = 1; r < count; r++) {
    if (times[r] < times[r - 1]) {
      throw new StreamError(source, keys[r].line, header.keyColumn + 1,
        `time ${times[r]} s is earlier than the row before`);
    }
  }
  return { format, source, count, times, weights };
}

/** Non-blank lines as {line (1-based), fields (trimmed)}. */
function splitLines(text) {
  const body = text.startsWith('\ufeff') ? text.slice(1) : text;
  const out = [];
  body.split('\n').forEach((raw, i) => {
    const line = raw.endsWith('\r') ? raw.slice(0, -1) : raw;
    if (line.trim() !== '') out.push({ line: i + 1, fields: line.split(',').map((f) => f.trim()) });
  });
  return out;
}

/**
 * The header: the key column (`Timecode` or `timestamp`), the shape of
 * every column (-1 for the key and ignored columns), each of the 52 once.
 */
function parseHeader({ line, fields }, source) {
  const liveLink = fields.some((f) => f.toLowerCase() === 'timecode');
  const keyName = liveLink ? 'timecode' : 'timestamp';
  let keyColumn = -1;
  const seen = new Array(ARKIT_COUNT).fill(-1);
  const columns = fields.map((name, c) => {
    const lower = name.toLowerCase();
    if (lower === keyName) {
      if (keyColumn >= 0) {
        throw new StreamError(source, line, c + 1, `${name} appears twice (first in column ${keyColumn + 1})`);
      }
      keyColumn = c;
      return -1;
    }
    if (liveLink && LIVE_LINK_EXTRA.has(lower)) return -1;
    const shape = parseName(name);
    if (shape < 0) {
      throw new StreamError(source, line, c + 1, `unknown column ${JSON.stringify(name)}: not one of ARKit's 52 names`);
    }
    if (seen[shape] >= 0) {
      throw new StreamError(source, line, c + 1, `${ARKIT_NAMES[shape]} appears twice (first in column ${seen[shape] + 1})`);
    }
    seen[shape] = c;
    return shape;
  });
  if (keyColumn < 0) {
    throw new StreamError(source, line, 0, 'no Timecode or timestamp column');
  }
  const missing = ARKIT_NAMES.filter((_, i) => seen[i] < 0);
  if (missing.length > 0) {
    throw new StreamError(source, line, 0, `missing column${missing.length > 1 ? 's' : ''} ${missing.join(', ')}`);
  }
  return { liveLink, keyColumn, columns };
}

/** `timestamp` cells: seconds, as written. */
function timestampSeconds(keys, source, keyColumn) {
  return Float64Array.from(keys, ({ line, text }) => {
    const t = Number(text);
    if (text === '' || !Number.isFinite(t)) {
      throw new StreamError(source, line, keyColumn + 1, `timestamp ${JSON.stringify(text)} is not a finite number`);
    }
    return t;
  });
}

/**
 * `HH:MM:SS:FF[.fff]` cells: the frame number is counted at the smallest
 * usual rate above every frame number seen (60 for a 60 fps take), and
 * times start at 0.
 */
function timecodeSeconds(keys, source, keyColumn) {
  const parsed = keys.map(({ line, text }) => {
    const t = parseTimecode(text);
    if (!t) {
      throw new StreamError(source, line, keyColumn + 1, `${JSON.stringify(text)} is not a timecode HH:MM:SS:FF[.fff]`);
    }
    return t;
  });
  const maxFrame = parsed.reduce((m, t) => Math.max(m, t.frames), 0);
  const rate = TIMECODE_RATES.find((r) => maxFrame < r) ?? Math.floor(maxFrame) + 1;
  const start = parsed.length > 0 ? parsed[0].seconds + parsed[0].frames / rate : 0;
  return Float64Array.from(parsed, (t) => t.seconds + t.frames / rate - start);
}

/** `HH:MM:SS:FF[.fff]` → {seconds (whole), frames (with the fraction)}, or null. */
export function parseTimecode(text) {
  const m = /^(\d+):(\d+):(\d+):(\d+)(?:\.(\d+))?$/.exec(text);
  if (!m) return null;
  const [h, min, s, f] = [m[1], m[2], m[3], m[4]].map(Number);
  if (min >= 60 || s >= 61) return null;
  const fraction = m[5] ? Number(m[5]) / 10 ** m[5].length : 0;
  return { seconds: h * 3600 + min * 60 + s, frames: f + fraction };
}

/** Index of the last frame at or before time `t` (0 before the first). */
export function frameAt(times, t) {
  let lo = 0;
  let hi = times.length - 1;
  if (hi < 0 || t <= times[0]) return 0;
  while (lo < hi) {
    const mid = (lo + hi + 1) >> 1;
    if (times[mid] <= t) lo = mid;
    else hi = mid - 1;
  }
  return lo;
}
