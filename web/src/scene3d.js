// The 3D view: meshes built once from the recording's header, then moved per frame from the
// typed arrays (no geometry is made after loading). Lambert shading: cheap in software GL too.
import * as THREE from 'three';
import { OrbitControls } from 'three/examples/jsm/controls/OrbitControls.js';

// Body colours keep clear of the contact states (green, orange, grey) and the arrows (red, yellow).
const BODY_COLORS = [0x4e79a7, 0x8e6bb8, 0x3f9e9a, 0x9c755f, 0x5a6d8c, 0xc267a3, 0x6b8e23, 0x7a5c99];
// Flat, far-apart colours of the "ids" mode: a test counts bodies in a screenshot by them.
export const ID_COLORS = [
  0xff0000, 0x00ff00, 0x0000ff, 0xffff00, 0xff00ff, 0x00ffff, 0x800000, 0x008000, 0x000080, 0x808000,
  0x800080, 0x008080, 0xff8000, 0x80ff00, 0x0080ff, 0xff0080,
];
const STATE_COLORS = [0x9e9e9e, 0x2ca02c, 0xff7f0e]; // touch, stick, slip
const FORCE_COLOR = 0xe02020;
const MOTION_COLOR = 0xffd400;
const JOINT_COLOR = 0x334455;
const SKIN = 0xe0ac8a;

// A mesh (or group) for one recorded shape; compounds of boxes become one instanced mesh.
function shapeObject(s, material, extent) {
  switch (s.type) {
    case 'box': {
      const [x, y, z] = s.halfExtents;
      return new THREE.Mesh(new THREE.BoxGeometry(2 * x, 2 * y, 2 * z), material);
    }
    case 'sphere':
      return new THREE.Mesh(new THREE.SphereGeometry(s.radius, 32, 16), material);
    case 'capsule':
      return new THREE.Mesh(new THREE.CapsuleGeometry(s.radius, 2 * s.halfHeight, 6, 16), material);
    case 'plane': {
      // The half space n.x <= offset: a large square on its boundary, facing +n.
      const m = new THREE.Mesh(new THREE.PlaneGeometry(extent, extent), material);
      const n = new THREE.Vector3(...s.normal).normalize();
      m.quaternion.setFromUnitVectors(new THREE.Vector3(0, 0, 1), n);
      m.position.copy(n.multiplyScalar(s.offset));
      const g = new THREE.Group();
      g.add(m);
      // Grid squares of a power of ten: 10 cm for a hand-sized scene.
      const step = Math.pow(10, Math.ceil(Math.log10(extent / 40)));
      const grid = new THREE.GridHelper(extent, Math.round(extent / step), 0x8a949e, 0xaab3bc);
      grid.quaternion.setFromUnitVectors(new THREE.Vector3(0, 1, 0), new THREE.Vector3(...s.normal).normalize());
      grid.position.copy(m.position).addScaledVector(new THREE.Vector3(...s.normal).normalize(), 1e-4);
      grid.userData.decoration = true;
      g.add(grid);
      return g;
    }
    case 'hull': {
      if (!Array.isArray(s.points) || !Array.isArray(s.faces)) break;
      const pos = [];
      for (const f of s.faces)
        for (let k = 1; k + 1 < f.length; ++k) for (const i of [f[0], f[k], f[k + 1]]) pos.push(...s.points[i]);
      const g = new THREE.BufferGeometry();
      g.setAttribute('position', new THREE.Float32BufferAttribute(pos, 3));
      g.computeVertexNormals();
      return new THREE.Mesh(g, material);
    }
    case 'compound': {
      const group = new THREE.Group();
      const boxes = (s.children || []).filter((c) => c.shape.type === 'box');
      if (boxes.length) {
        const inst = new THREE.InstancedMesh(new THREE.BoxGeometry(1, 1, 1), material, boxes.length);
        const m = new THREE.Matrix4();
        boxes.forEach((c, i) => {
          const [x, y, z] = c.shape.halfExtents;
          const [w, qx, qy, qz] = c.orientation;
          m.compose(new THREE.Vector3(...c.position), new THREE.Quaternion(qx, qy, qz, w), new THREE.Vector3(2 * x, 2 * y, 2 * z));
          inst.setMatrixAt(i, m);
        });
        group.add(inst);
      }
      for (const c of s.children || []) {
        if (c.shape.type === 'box') continue;
        const o = shapeObject(c.shape, material, extent);
        const [w, qx, qy, qz] = c.orientation;
        o.position.set(...c.position);
        o.quaternion.set(qx, qy, qz, w);
        group.add(o);
      }
      return group;
    }
  }
  // A shape this viewer cannot draw (a version 1 hull has no points): a small marker.
  const m = new THREE.Mesh(new THREE.IcosahedronGeometry(0.02, 0), material);
  m.userData.unknownShape = true;
  return m;
}

// A solid arrow (shaft and head) of unit geometry, placed and stretched per frame.
class Arrow extends THREE.Group {
  constructor(color, thickness, onTop = false) {
    super();
    // onTop: drawn over everything (the hand motion starts inside the hand).
    const mat = new THREE.MeshBasicMaterial({ color, depthTest: !onTop });
    this.renderOrder = onTop ? 10 : 0;
    this.shaft = new THREE.Mesh(new THREE.CylinderGeometry(1, 1, 1, 10), mat);
    this.head = new THREE.Mesh(new THREE.ConeGeometry(1, 1, 14), mat);
    this.add(this.shaft, this.head);
    this.thickness = thickness;
    this.visible = false;
  }
  // From `from` along unit `dir`, `len` long.
  place(from, dir, len) {
    const r = Math.min(this.thickness, len * 0.12);
    const head = Math.min(len * 0.4, r * 8);
    this.position.copy(from);
    this.quaternion.setFromUnitVectors(UP, dir);
    this.shaft.scale.set(r, len - head, r);
    this.shaft.position.set(0, (len - head) / 2, 0);
    this.head.scale.set(2.5 * r, head, 2.5 * r);
    this.head.position.set(0, len - head / 2, 0);
  }
}
const UP = new THREE.Vector3(0, 1, 0);
const ANCHOR = new THREE.Vector3();

function setPose(obj, a, o) {
  obj.position.set(a[o], a[o + 1], a[o + 2]);
  obj.quaternion.set(a[o + 4], a[o + 5], a[o + 6], a[o + 3]);
}

export class SceneView {
  constructor(container) {
    this.container = container;
    this.renderer = new THREE.WebGLRenderer({ antialias: true, preserveDrawingBuffer: true });
    this.renderer.setPixelRatio(Math.min(2, window.devicePixelRatio || 1));
    container.appendChild(this.renderer.domElement);
    this.camera = new THREE.PerspectiveCamera(45, 1, 0.005, 200);
    this.controls = new OrbitControls(this.camera, this.renderer.domElement);
    this.controls.enableDamping = false;
    this.controls.addEventListener('change', () => this.render());
    this.scene = null;
    this.idMode = false;
    this.layers = { tracked: true, visual: true, contacts: true, forces: true, motion: true };
    new ResizeObserver(() => this.resize()).observe(container);
    this.resize();
  }

  resize() {
    const w = Math.max(1, this.container.clientWidth), h = Math.max(1, this.container.clientHeight);
    this.renderer.setSize(w, h, false);
    this.renderer.domElement.style.width = '100%';
    this.renderer.domElement.style.height = '100%';
    this.camera.aspect = w / h;
    this.camera.updateProjectionMatrix();
    this.render();
  }

  // Builds every object for a recording (once).
  load(rec) {
    this.dispose();
    this.rec = rec;
    const scene = new THREE.Scene();
    this.scene = scene;
    scene.background = new THREE.Color(0xf4f6f9);
    scene.add(new THREE.HemisphereLight(0xffffff, 0x667788, 1.6));
    const sun = new THREE.DirectionalLight(0xffffff, 1.6);
    sun.position.set(2, 4, 3);
    scene.add(sun);
    const { center, radius } = rec.bounds;
    const extent = Math.max(2, radius * 12);
    this.scale = radius;

    this.bodies = rec.header.bodies.map((b, i) => {
      const color = b.type === 'static' ? 0xe4e8ec : BODY_COLORS[i % BODY_COLORS.length];
      // Planes unlit: a large shaded square is most of a frame's cost in software GL.
      const plane = b.shape.type === 'plane';
      const Material = plane ? THREE.MeshBasicMaterial : THREE.MeshLambertMaterial;
      const normal = new Material({ color: plane ? 0xd3d8de : color, side: THREE.DoubleSide });
      const id = new THREE.MeshBasicMaterial({ color: ID_COLORS[i % ID_COLORS.length], side: THREE.DoubleSide });
      const obj = shapeObject(b.shape, normal, extent);
      obj.userData = { normal, id, plane: b.shape.type === 'plane' };
      scene.add(obj);
      return obj;
    });

    // Joints: a line from each joint's anchor on a to its anchor on b (a rope, a rod; a point
    // where the joint holds them together).
    const nj = rec.header.joints.length;
    this.jointLines = new THREE.LineSegments(
      new THREE.BufferGeometry().setAttribute('position', new THREE.BufferAttribute(new Float32Array(Math.max(1, nj) * 6), 3)),
      new THREE.LineBasicMaterial({ color: JOINT_COLOR }));
    this.jointLines.frustumCulled = false;
    this.jointLines.geometry.setDrawRange(0, 2 * nj);
    scene.add(this.jointLines);

    const skinTracked = new THREE.MeshLambertMaterial({ color: SKIN, transparent: true, opacity: 0.3, depthWrite: false });
    const skinVisual = new THREE.MeshLambertMaterial({ color: SKIN });
    this.hands = rec.header.hands.map((h) => {
      const make = (mat) => h.bones.map((bone) => {
        const o = shapeObject(bone.shape, mat, extent);
        scene.add(o);
        return o;
      });
      return { tracked: make(skinTracked), visual: make(skinVisual) };
    });

    // Contact points and force arrows: pools as large as the busiest frame.
    const nc = Math.max(1, rec.maxContacts);
    // Drawn over everything: a contact sits under the fingertip that makes it.
    const dotR = Math.max(0.002, radius * 0.04);
    this.dots = new THREE.InstancedMesh(new THREE.SphereGeometry(dotR, 12, 8), new THREE.MeshBasicMaterial({ depthTest: false }), nc);
    this.dots.frustumCulled = false;
    this.dots.renderOrder = 11;
    for (let i = 0; i < nc; ++i) this.dots.setColorAt(i, new THREE.Color(STATE_COLORS[1]));
    scene.add(this.dots);
    this.forceArrows = [];
    for (let i = 0; i < nc; ++i) {
      const a = new Arrow(FORCE_COLOR, radius * 0.015);
      scene.add(a);
      this.forceArrows.push(a);
    }
    // The longest force arrow: 60 % of the scene's radius.
    this.forceScale = rec.maxForce > 0 ? (0.6 * radius) / rec.maxForce : 1;
    this.motionArrows = rec.header.hands.map(() => {
      const a = new Arrow(MOTION_COLOR, radius * 0.02, true);
      scene.add(a);
      return a;
    });

    this.home();
    this.setIdMode(this.idMode);
  }

  // The starting camera: from the front right, above, the bodies in view.
  home() {
    if (!this.rec) return;
    const { center, radius } = this.rec.bounds;
    this.controls.target.set(...center);
    const d = Math.max(0.3, radius * 3.2);
    this.camera.position.set(center[0] + 0.55 * d, center[1] + 0.45 * d, center[2] + 0.7 * d);
    this.camera.near = d / 200;
    this.camera.far = d * 200;
    this.camera.updateProjectionMatrix();
    this.controls.update();
    this.render();
  }

  // Shows or hides one kind of overlay: tracked, visual, contacts, forces, motion.
  setLayer(name, on) {
    this.layers[name] = on;
    this.showFrame(this.frame || 0);
  }

  dispose() {
    if (!this.scene) return;
    this.scene.traverse((o) => {
      if (o.geometry) o.geometry.dispose();
    });
    this.scene = null;
  }

  // Flat unlit colours, one per body; hands, contacts, arrows and grids hidden.
  setIdMode(on) {
    this.idMode = on;
    if (!this.scene) return;
    this.scene.background = new THREE.Color(on ? 0x000000 : 0xf4f6f9);
    for (const b of this.bodies) {
      b.traverse((o) => {
        if (o.userData.decoration) o.visible = !on;
        else if (o.material) o.material = on ? b.userData.id : b.userData.normal;
      });
    }
    this.showFrame(this.frame || 0);
  }

  // Moves everything to frame f of the recording and renders.
  showFrame(f) {
    const rec = this.rec;
    if (!rec) return;
    this.frame = f;
    for (let i = 0; i < rec.nb; ++i) setPose(this.bodies[i], rec.bodyPose, (f * rec.nb + i) * 7);
    const line = this.jointLines.geometry.attributes.position;
    rec.header.joints.forEach((j, k) => {
      const a = ANCHOR.fromArray(j.anchorA).applyQuaternion(this.bodies[j.a].quaternion).add(this.bodies[j.a].position);
      line.setXYZ(2 * k, a.x, a.y, a.z);
      const b = ANCHOR.fromArray(j.anchorB).applyQuaternion(this.bodies[j.b].quaternion).add(this.bodies[j.b].position);
      line.setXYZ(2 * k + 1, b.x, b.y, b.z);
    });
    line.needsUpdate = true;
    this.jointLines.visible = !this.idMode;
    const a = rec.contactStart[f], b = rec.contactStart[f + 1];
    const inContact = new Array(rec.nh).fill(false);
    for (let c = a; c < b; ++c) if (rec.cState[c] !== 0) inContact[rec.cHand[c]] = true;
    const { center, radius } = rec.bounds;
    const near = radius + 1.0;
    for (let h = 0; h < rec.nh; ++h) {
      const hand = this.hands[h];
      const tracked = rec.tracked[f * rec.nh + h] === 1;
      for (let k = 0; k < rec.bones[h]; ++k) {
        const o = rec.boneIndex(f, h, k) * 7;
        setPose(hand.tracked[k], rec.bonePose, o);
        setPose(hand.visual[k], rec.visualPose, o);
        // Bones parked far from the scene (pinch/press scripts) are not drawn.
        const p = hand.tracked[k].position;
        const parked = Math.hypot(p.x - center[0], p.y - center[1], p.z - center[2]) > near;
        hand.tracked[k].visible = !this.idMode && this.layers.tracked && !parked;
        hand.visual[k].visible = !this.idMode && this.layers.visual && !parked && tracked && inContact[h];
      }
    }
    const m = new THREE.Matrix4();
    const color = new THREE.Color();
    this.dots.count = this.idMode || !this.layers.contacts ? 0 : b - a;
    for (let c = a; c < b; ++c) {
      const v = rec.cVec.subarray(9 * c, 9 * c + 9);
      m.makeTranslation(v[0], v[1], v[2]);
      this.dots.setMatrixAt(c - a, m);
      this.dots.setColorAt(c - a, color.setHex(STATE_COLORS[rec.cState[c]]));
      const arrow = this.forceArrows[c - a];
      const len = Math.hypot(v[6], v[7], v[8]) * this.forceScale;
      arrow.visible = !this.idMode && this.layers.forces && len > 1e-5;
      if (arrow.visible) {
        // The force on the body, drawn from outside with its tip at the contact point.
        const dir = new THREE.Vector3(v[6], v[7], v[8]).normalize();
        arrow.place(new THREE.Vector3(v[0], v[1], v[2]).addScaledVector(dir, -len), dir, len);
      }
    }
    for (let i = b - a; i < this.forceArrows.length; ++i) this.forceArrows[i].visible = false;
    this.dots.instanceMatrix.needsUpdate = true;
    if (this.dots.instanceColor) this.dots.instanceColor.needsUpdate = true;
    for (let h = 0; h < rec.nh; ++h) {
      const arrow = this.motionArrows[h];
      const i = f * rec.nh + h;
      const v = rec.handVel.subarray(3 * i, 3 * i + 3);
      const speed = Math.hypot(v[0], v[1], v[2]);
      // The arrow shows 0.5 s of the current hand motion.
      const len = speed * 0.5;
      arrow.visible = !this.idMode && this.layers.motion && rec.handHasCenter[i] === 1 && len > radius * 0.02;
      if (arrow.visible) {
        const from = new THREE.Vector3(...rec.handCenter.subarray(3 * i, 3 * i + 3));
        arrow.place(from, new THREE.Vector3(v[0], v[1], v[2]).normalize(), len);
      }
    }
    this.render();
  }

  render() {
    if (this.scene) this.renderer.render(this.scene, this.camera);
  }

  // What a test reads back: how many bodies and visible hand bones are in the scene.
  counts() {
    if (!this.scene) return null;
    let trackedBones = 0, visualBones = 0;
    for (const h of this.hands || []) {
      trackedBones += h.tracked.filter((o) => o.visible).length;
      visualBones += h.visual.filter((o) => o.visible).length;
    }
    const line = this.jointLines.geometry.attributes.position;
    const jointLengths = this.jointLines.visible
      ? this.rec.header.joints.map((j, k) => Math.hypot(line.getX(2 * k + 1) - line.getX(2 * k),
        line.getY(2 * k + 1) - line.getY(2 * k), line.getZ(2 * k + 1) - line.getZ(2 * k)))
      : [];
    return {
      bodies: this.bodies.length,
      jointLengths,
      trackedBones,
      visualBones,
      contactDots: this.dots.count,
      forceArrows: this.forceArrows.filter((a) => a.visible).length,
      motionArrows: this.motionArrows.filter((a) => a.visible).length,
    };
  }
}
