// Plays a weight stream in real time: play, pause, scrub to a frame, loop.
// Each time the frame changes it hands that frame's 52 weights on.

import { ARKIT_COUNT } from './arkit.js';
import { frameAt } from './weight-stream.js';

export class Player {
  /**
   * @param {(weights: Float32Array, frame: number) => void} onFrame a new frame is shown
   * @param {() => void} onState playing started or stopped
   */
  constructor(onFrame, onState) {
    this.onFrame = onFrame;
    this.onState = onState;
    this.stream = null;
    this.frame = 0;
    this.time = 0;
    this.playing = false;
    this.loop = true;
    /** performance.now() at the last tick while playing. */
    this.lastTick = 0;
  }

  /** Takes a parsed stream (see weight-stream.js) and shows its first frame. */
  setStream(stream) {
    this.pause();
    this.stream = stream;
    this.seekFrame(0);
  }

  get duration() {
    return this.stream && this.stream.count > 0 ? this.stream.times[this.stream.count - 1] : 0;
  }

  play() {
    if (!this.stream || this.stream.count === 0 || this.playing) return;
    // From the end, start again.
    if (this.frame >= this.stream.count - 1) this.seekFrame(0);
    this.playing = true;
    this.onState();
    this.lastTick = performance.now();
    requestAnimationFrame((now) => this.tick(now));
  }

  pause() {
    if (!this.playing) return;
    this.playing = false;
    this.onState();
  }

  /** Shows frame `k` (clamped) and sets the clock to its time. */
  seekFrame(k) {
    if (!this.stream || this.stream.count === 0) return;
    const frame = Math.min(Math.max(Math.round(k), 0), this.stream.count - 1);
    this.time = this.stream.times[frame];
    this.show(frame);
  }

  tick(now) {
    if (!this.playing) return;
    this.time += Math.max(now - this.lastTick, 0) / 1000;
    this.lastTick = now;
    if (this.time > this.duration) {
      if (this.loop && this.duration > 0) {
        this.time %= this.duration;
      } else {
        this.time = this.duration;
        this.playing = false;
        this.onState();
      }
    }
    const frame = frameAt(this.stream.times, this.time);
    if (frame !== this.frame) this.show(frame);
    if (this.playing) requestAnimationFrame((t) => this.tick(t));
  }

  show(frame) {
    this.frame = frame;
    const start = frame * ARKIT_COUNT;
    this.onFrame(this.stream.weights.subarray(start, start + ARKIT_COUNT), frame);
  }
}
