// One avatar: a GLB loaded with three.js, its morph targets bound to ARKit's
// 52 names (every mesh's target of a name moves with that name's weight, as
// engines drive them), and placed so that its face is at the origin, one
// unit tall, looking down +z (glTF's front), whatever its units.

import * as THREE from 'three';
import { GLTFLoader } from 'three/addons/loaders/GLTFLoader.js';
import { ARKIT_COUNT, ARKIT_NAMES, targetShape } from './arkit.js';

/** A displacement smaller than this (in the file's units) moves nothing. */
const STILL = 1e-7;

export class Avatar {
  /**
   * @param {THREE.Object3D} root the loaded scene
   * @param {string} label what the page calls it
   */
  constructor(root, label) {
    this.label = label;
    /** The object placed in a pane's scene: the face normalized. */
    this.object = new THREE.Group();
    this.object.add(root);
    /** For each ARKit shape, the [mesh, influence index] pairs it drives. */
    this.bindings = Array.from({ length: ARKIT_COUNT }, () => []);
    /** Morph target names that are none of the 52 (left at zero). */
    this.unmatched = [];
    this.meshCount = 0;
    root.updateMatrixWorld(true);
    root.traverse((node) => {
      if (!node.isMesh || !node.morphTargetInfluences) return;
      this.meshCount += 1;
      for (const [name, index] of Object.entries(node.morphTargetDictionary ?? {})) {
        const shape = targetShape(name);
        if (shape >= 0) this.bindings[shape].push([node, index]);
        else if (!this.unmatched.includes(name)) this.unmatched.push(name);
      }
    });
    this.placeFace(root);
  }

  /** Loads a GLB from a URL (relative to the page). */
  static async load(url, label) {
    const gltf = await new GLTFLoader().loadAsync(url);
    return new Avatar(gltf.scene, label);
  }

  /** Loads a GLB from bytes (a file the person picked). */
  static async fromBytes(buffer, label) {
    const gltf = await new GLTFLoader().parseAsync(buffer, '');
    return new Avatar(gltf.scene, label);
  }

  /** Sets every bound morph target from 52 weights in ARKit's order. */
  setWeights(weights) {
    this.bindings.forEach((pairs, shape) => {
      for (const [mesh, index] of pairs) mesh.morphTargetInfluences[index] = weights[shape];
    });
  }

  /** The face's width, height and depth in the file's units. */
  faceSize() {
    return this.faceBox.getSize(new THREE.Vector3()).toArray();
  }

  /** Number of morph targets bound to each ARKit name that has any. */
  targetCounts() {
    const counts = {};
    this.bindings.forEach((pairs, shape) => {
      if (pairs.length > 0) counts[ARKIT_NAMES[shape]] = pairs.length;
    });
    return counts;
  }

  /**
   * Centres and scales the avatar on its face: the box of every vertex that
   * some bound morph target moves by at least a tenth of that target's
   * largest displacement (eyes, lids, lips, jaw, teeth; a faint fade-out
   * around an implanted face does not count), or the whole model if no
   * target moves anything.
   */
  placeFace(root) {
    const box = new THREE.Box3();
    const point = new THREE.Vector3();
    this.bindings.flat().forEach(([mesh, index]) => {
      const base = mesh.geometry.attributes.position;
      const delta = mesh.geometry.morphAttributes.position?.[index];
      if (!base || !delta) return;
      const length = (v) => Math.hypot(delta.getX(v), delta.getY(v), delta.getZ(v));
      let largest = 0;
      for (let v = 0; v < delta.count; v++) largest = Math.max(largest, length(v));
      if (largest <= STILL) return;
      for (let v = 0; v < base.count; v++) {
        if (length(v) >= 0.1 * largest) {
          box.expandByPoint(point.fromBufferAttribute(base, v).applyMatrix4(mesh.matrixWorld));
        }
      }
    });
    /** The model at rest (no morph target applied), in the file's units. */
    this.restBox = restBox(root);
    this.place(box.isEmpty() ? this.restBox : box);
  }

  /** Puts `box` at the origin, its larger side of width and height one unit long. */
  place(box) {
    /** The face's box in the file's units. */
    this.faceBox = box.clone();
    const size = box.getSize(new THREE.Vector3());
    const scale = 1 / Math.max(size.x, size.y, 1e-12);
    this.object.scale.setScalar(scale);
    this.object.position.copy(box.getCenter(new THREE.Vector3())).multiplyScalar(-scale);
    /** The face's width, height and depth once placed (the larger of the first two is 1). */
    this.faceExtent = size.multiplyScalar(scale);
  }

  /**
   * Takes `reference`'s face box when both are the same model at rest (an
   * avatar and the same avatar with shapes implanted), so the two are
   * framed alike even where the implanted shapes move other vertices.
   */
  alignTo(reference) {
    const tolerance = 1e-4 * reference.restBox.getSize(new THREE.Vector3()).length();
    const same = ['min', 'max'].every((corner) =>
      this.restBox[corner].distanceTo(reference.restBox[corner]) <= tolerance);
    if (same) this.place(reference.faceBox);
  }
}

/** The box of every mesh vertex at rest, in world space. */
function restBox(root) {
  const box = new THREE.Box3();
  const point = new THREE.Vector3();
  root.traverse((node) => {
    const position = node.isMesh ? node.geometry.attributes.position : null;
    if (!position) return;
    for (let v = 0; v < position.count; v++) {
      box.expandByPoint(point.fromBufferAttribute(position, v).applyMatrix4(node.matrixWorld));
    }
  });
  return box;
}
