// The 3D view: one canvas split into side-by-side panes, one per avatar,
// each with its own scene and lights but one camera, so turning the view
// turns every avatar alike. Renders only when something changed.

import * as THREE from 'three';
import { OrbitControls } from 'three/addons/controls/OrbitControls.js';

/** Vertical field of view, degrees. */
const FOV = 30;
/** Share of a pane's height the face fills when the view is reset. */
const FILL = 0.6;

export class Stage {
  /** @param {HTMLCanvasElement} canvas */
  constructor(canvas) {
    this.canvas = canvas;
    this.renderer = new THREE.WebGLRenderer({ canvas, antialias: true });
    this.renderer.setPixelRatio(Math.min(window.devicePixelRatio, 2));
    this.renderer.setScissorTest(true);
    this.camera = new THREE.PerspectiveCamera(FOV, 1, 0.01, 100);
    this.controls = new OrbitControls(this.camera, canvas);
    this.controls.addEventListener('change', () => this.requestRender());
    /** @type {{scene: THREE.Scene, avatar: import('./avatar.js').Avatar}[]} */
    this.panes = [];
    /** Frames drawn so far (the status reports it, so tests can wait for one). */
    this.renders = 0;
    this.pending = false;
    new ResizeObserver(() => this.resize()).observe(canvas);
  }

  /**
   * Shows the avatars side by side, left to right, and resets the view.
   * The same model twice (before and after implanting) is framed alike.
   */
  setAvatars(avatars) {
    avatars.slice(1).forEach((avatar) => avatar.alignTo(avatars[0]));
    this.panes = avatars.map((avatar) => ({ scene: makeScene(avatar), avatar }));
    this.resize();
    this.resetView();
  }

  /** Looks at the faces from the front, filling the panes. */
  resetView() {
    const aspect = this.paneAspect();
    const half = Math.tan(THREE.MathUtils.degToRad(FOV / 2));
    // Faces are placed at the origin, their larger side one unit long.
    const extents = this.panes.map(({ avatar }) => avatar.faceExtent);
    const largest = (axis) => Math.max(0, ...extents.map((e) => e[axis]));
    const [width, height, depth] = extents.length ? ['x', 'y', 'z'].map(largest) : [1, 1, 0];
    const fit = Math.max(height / half, width / (half * aspect)) / (2 * FILL);
    this.camera.position.set(0, 0, fit + depth / 2);
    this.controls.target.set(0, 0, 0);
    this.controls.update();
    this.requestRender();
  }

  paneAspect() {
    const { clientWidth: w, clientHeight: h } = this.canvas;
    return w > 0 && h > 0 ? w / Math.max(this.panes.length, 1) / h : 1;
  }

  resize() {
    const { clientWidth: w, clientHeight: h } = this.canvas;
    if (w === 0 || h === 0) return;
    this.renderer.setSize(w, h, false);
    this.camera.aspect = this.paneAspect();
    this.camera.updateProjectionMatrix();
    this.requestRender();
  }

  /** Draws at the next animation frame (once, however often asked). */
  requestRender() {
    if (this.pending) return;
    this.pending = true;
    requestAnimationFrame(() => {
      this.pending = false;
      this.render();
    });
  }

  render() {
    const { clientWidth: w, clientHeight: h } = this.canvas;
    const width = Math.floor(w / Math.max(this.panes.length, 1));
    this.renderer.setScissor(0, 0, w, h);
    this.renderer.setClearColor(0x1d2026);
    this.renderer.clear();
    this.panes.forEach(({ scene }, i) => {
      this.renderer.setViewport(i * width, 0, width, h);
      this.renderer.setScissor(i * width, 0, width, h);
      this.renderer.render(scene, this.camera);
    });
    this.renders += 1;
  }
}

/** A pane's scene: the avatar, a soft sky and ground light, a key and a rim light. */
function makeScene(avatar) {
  const scene = new THREE.Scene();
  scene.background = new THREE.Color(0x2a2e36);
  scene.add(new THREE.HemisphereLight(0xf4f1ee, 0x40362f, 1.6));
  const key = new THREE.DirectionalLight(0xffffff, 2.2);
  key.position.set(0.6, 0.8, 1.5);
  const rim = new THREE.DirectionalLight(0xcfe0ff, 0.8);
  rim.position.set(-1.2, 0.4, -0.8);
  scene.add(key, rim, avatar.object);
  return scene;
}
