// The page's weight-stream reader and ARKit name parser, under Node's own
// test runner (`node --test tests/`): the committed Live Link Face take,
// the `likeness export` form, the spellings the core accepts, and errors
// that name line and column.

import { test } from 'node:test';
import assert from 'node:assert/strict';
import { readFileSync } from 'node:fs';
import { ARKIT_NAMES, parseName, targetShape } from '../src/arkit.js';
import { frameAt, parseTimecode, parseWeightStream } from '../src/weight-stream.js';

const TAKE = new URL('./fixtures/subject-1-take.csv', import.meta.url);
const JAW_OPEN = ARKIT_NAMES.indexOf('jawOpen');

test('the committed Live Link Face take: 300 frames at 60 fps, weights by column name', () => {
  const text = readFileSync(TAKE, 'utf8');
  const stream = parseWeightStream(text, 'subject-1-take.csv');
  assert.equal(stream.format, 'live-link');
  assert.equal(stream.count, 300);
  assert.equal(stream.times[0], 0);
  assert.ok(Math.abs(stream.times[299] - 299 / 60) < 1e-9);
  // Live Link's column order is not Apple's (JawRight before JawLeft):
  // check a cell against the file by header name.
  const rows = text.trim().split('\n').map((l) => l.split(','));
  const jaw = rows[0].indexOf('JawOpen');
  for (const r of [0, 96, 299]) {
    assert.equal(stream.weights[r * 52 + JAW_OPEN], Math.fround(Number(rows[r + 1][jaw])));
  }
  // The take holds the jawOpen prompt: the jaw opens wide somewhere in it.
  let peak = 0;
  for (let r = 0; r < stream.count; r++) peak = Math.max(peak, stream.weights[r * 52 + JAW_OPEN]);
  assert.ok(peak > 0.8, `jawOpen peaks at ${peak}`);
});

test('the frames.csv that likeness export writes: timestamp and ARKit spellings', () => {
  const header = ['timestamp', ...ARKIT_NAMES].join(',');
  const row = (t, jaw) => [t, ...ARKIT_NAMES.map((n) => (n === 'jawOpen' ? jaw : 0))].join(',');
  const stream = parseWeightStream(`\ufeff${header}\r\n${row(0.5, 0.25)}\r\n\r\n${row(0.5166666666666667, 1)}\r\n`);
  assert.equal(stream.format, 'timestamp');
  assert.deepEqual(Array.from(stream.times), [0.5, 0.5166666666666667]);
  assert.equal(stream.weights[52 + JAW_OPEN], 1);
});

test('names in every spelling the core accepts; split halves follow the whole shape', () => {
  for (const spelling of ['eyeBlinkLeft', 'EyeBlinkLeft', 'eyeBlink_L', 'eye_blink_left', 'blendShape1.eyeBlink_L', ' EYEBLINKLEFT ']) {
    assert.equal(parseName(spelling), 0, spelling);
  }
  assert.equal(parseName('tongueOut'), 51);
  assert.equal(parseName('smile'), -1);
  assert.equal(targetShape('browInnerUp_L'), ARKIT_NAMES.indexOf('browInnerUp'));
  assert.equal(targetShape('cheekPuffRight'), ARKIT_NAMES.indexOf('cheekPuff'));
  assert.equal(targetShape('mouthLeft'), ARKIT_NAMES.indexOf('mouthLeft'));
  assert.equal(targetShape('head_turn'), -1);
});

test('timecodes and frame lookup', () => {
  assert.deepEqual(parseTimecode('10:42:31:59.500'), { seconds: 38551, frames: 59.5 });
  assert.equal(parseTimecode('10:42:31'), null);
  assert.equal(parseTimecode('10:60:00:00'), null);
  const times = Float64Array.from([0, 0.1, 0.2, 0.3]);
  assert.equal(frameAt(times, -1), 0);
  assert.equal(frameAt(times, 0.15), 1);
  assert.equal(frameAt(times, 0.2), 2);
  assert.equal(frameAt(times, 9), 3);
});

test('bad streams are errors naming line and column', () => {
  const header = ['timestamp', ...ARKIT_NAMES].join(',');
  const zeros = ARKIT_NAMES.map(() => 0).join(',');
  const cases = [
    ['', /line 1: empty file/],
    ['Timecode,BlendShapeCount,EyeBlinkLeft\n', /line 1: missing columns eyeLookDownLeft, /],
    [`${header},smile\n`, /line 1, column 54: unknown column "smile"/],
    [`${header},eyeBlink_L\n`, /line 1, column 54: eyeBlinkLeft appears twice \(first in column 2\)/],
    [`${ARKIT_NAMES.join(',')}\n`, /line 1: no Timecode or timestamp column/],
    [`${header}\n0,${zeros}\nx,${zeros}\n`, /line 3, column 1: timestamp "x" is not a finite number/],
    [`${header}\n0,${zeros}\n0.1,1.5,${zeros.slice(2)}\n`, /line 3, column 2: eyeBlinkLeft weight 1.5 is outside \[0, 1\]/],
    [`${header}\n0,${zeros}\n0.1,0\n`, /line 3: 2 fields where the header has 53/],
    [`${header}\n1,${zeros}\n0.5,${zeros}\n`, /line 3, column 1: time 0.5 s is earlier/],
  ];
  for (const [text, message] of cases) {
    assert.throws(() => parseWeightStream(text, 'take.csv'), message, JSON.stringify(text.slice(0, 40)));
    assert.throws(() => parseWeightStream(text, 'take.csv'), /^StreamError: take\.csv, line/);
  }
});
