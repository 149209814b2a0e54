// Reads a grip recording (JSON Lines, docs/scenes.md) once into typed arrays, so that drawing
// a frame is a few array reads and never a JSON walk. Works on text chunks as they arrive
// (a one-minute run at 240 Hz is about 100 MB), line by line.

export const SUPPORTED_VERSIONS = [1, 2];
const STATES = { touch: 0, stick: 1, slip: 2 };
export const STATE_NAMES = ['touch', 'stick', 'slip'];

// A recording that cannot be read. `message` is meant for the page as is.
export class RecordingError extends Error {}

// A Float32Array / Uint32Array that grows by doubling.
class Grow {
  constructor(Type, capacity = 1024) {
    this.Type = Type;
    this.a = new Type(capacity);
    this.n = 0;
  }
  reserve(extra) {
    if (this.n + extra <= this.a.length) return;
    let cap = this.a.length * 2;
    while (cap < this.n + extra) cap *= 2;
    const b = new this.Type(cap);
    b.set(this.a.subarray(0, this.n));
    this.a = b;
  }
  push(x) {
    this.reserve(1);
    this.a[this.n++] = x;
  }
  done() {
    return this.a.slice(0, this.n);
  }
}

function isNum(x) {
  return typeof x === 'number' && Number.isFinite(x);
}

export class RecordingParser {
  constructor() {
    this.lineNo = 0;
    this.header = null;
    this.end = null;
    this.pendingError = null; // an unreadable line: an error unless it turns out to be the last
    this.rest = '';
    this.t = new Grow(Float64Array);
    this.frameNo = new Grow(Int32Array);
    this.bodyPose = new Grow(Float32Array, 8192);
    this.bonePose = new Grow(Float32Array, 8192);
    this.visualPose = new Grow(Float32Array, 8192);
    this.tracked = new Grow(Uint8Array);
    this.contactStart = new Grow(Uint32Array);
    this.cHand = new Grow(Uint16Array);
    this.cBone = new Grow(Uint16Array);
    this.cBody = new Grow(Uint16Array);
    this.cState = new Grow(Uint8Array);
    this.cKey = new Grow(Uint16Array);
    this.cVec = new Grow(Float32Array); // point, normal, force: 9 per contact
    this.keys = new Map(); // "hand/bone/body" -> index
    this.contactStart.push(0);
  }

  fail(msg) {
    throw new RecordingError(`line ${this.lineNo}: ${msg}`);
  }

  // Feeds a chunk of text (any split, also inside a line).
  push(text) {
    const s = this.rest + text;
    let from = 0;
    for (;;) {
      const nl = s.indexOf('\n', from);
      if (nl < 0) break;
      this.line(s.slice(from, nl));
      from = nl + 1;
    }
    this.rest = s.slice(from);
  }

  line(text) {
    ++this.lineNo;
    if (text.trim() === '') return;
    if (this.pendingError) throw this.pendingError; // more lines follow a broken one
    if (this.end) this.fail('text after the end line');
    let j;
    try {
      j = JSON.parse(text);
    } catch (e) {
      // Kept until we know whether more lines follow: a cut-off last line means truncation.
      this.pendingError = new RecordingError(`line ${this.lineNo}: invalid JSON (${e.message})`);
      this.pendingLine = this.lineNo;
      if (!this.header) throw this.pendingError;
      return;
    }
    if (j === null || typeof j !== 'object' || Array.isArray(j)) this.fail('not a JSON object');
    if (!this.header) return this.readHeader(j);
    if (j.end === true) {
      this.end = j;
      return;
    }
    this.readFrame(j);
  }

  readHeader(h) {
    if (h.format !== 'grip-recording')
      this.fail('not a grip recording (the first line has no "format": "grip-recording")');
    if (!SUPPORTED_VERSIONS.includes(h.version))
      this.fail(`unsupported recording version ${JSON.stringify(h.version)} (this viewer reads ${SUPPORTED_VERSIONS.join(', ')})`);
    if (!Array.isArray(h.bodies)) this.fail('header: "bodies" must be an array');
    if (!Array.isArray(h.hands)) this.fail('header: "hands" must be an array');
    if (!isNum(h.dt) || h.dt <= 0) this.fail('header: "dt" must be a positive number');
    h.bodies.forEach((b, i) => {
      if (!b || typeof b.shape !== 'object' || typeof b.shape.type !== 'string')
        this.fail(`header: bodies[${i}] has no shape`);
    });
    h.hands.forEach((hand, i) => {
      if (!hand || !Array.isArray(hand.bones)) this.fail(`header: hands[${i}] has no bones`);
    });
    // Joints (optional; recordings before them have none): two bodies and an anchor in each.
    if (h.joints === undefined) h.joints = [];
    if (!Array.isArray(h.joints)) this.fail('header: "joints" must be an array');
    const isVec = (v) => Array.isArray(v) && v.length === 3 && v.every(isNum);
    h.joints.forEach((j, i) => {
      for (const k of ['a', 'b']) {
        if (!j || !Number.isInteger(j[k]) || j[k] < 0 || j[k] >= h.bodies.length)
          this.fail(`header: joints[${i}].${k}: no body ${JSON.stringify(j && j[k])}`);
      }
      for (const k of ['anchorA', 'anchorB'])
        if (!isVec(j[k])) this.fail(`header: joints[${i}].${k} must be 3 numbers`);
    });
    this.header = h;
    this.nb = h.bodies.length;
    this.nh = h.hands.length;
    this.bones = h.hands.map((hand) => hand.bones.length);
    this.boneOffset = [];
    let o = 0;
    for (const n of this.bones) {
      this.boneOffset.push(o);
      o += n;
    }
    this.totalBones = o;
  }

  poses(arr, count, into, what) {
    if (!Array.isArray(arr) || arr.length !== count)
      this.fail(`${what}: expected ${count} poses, got ${Array.isArray(arr) ? arr.length : typeof arr}`);
    into.reserve(count * 7);
    for (let i = 0; i < count; ++i) {
      const p = arr[i];
      if (!Array.isArray(p) || p.length !== 7) this.fail(`${what}[${i}]: a pose is 7 numbers`);
      for (let k = 0; k < 7; ++k) {
        if (!isNum(p[k])) this.fail(`${what}[${i}]: not a finite number (${JSON.stringify(p[k])})`);
        into.a[into.n++] = p[k];
      }
    }
  }

  readFrame(f) {
    const frame = this.t.n + 1;
    if (!isNum(f.t)) this.fail(`frame ${frame}: "t" must be a number`);
    if (this.t.n && f.t < this.t.a[this.t.n - 1]) this.fail(`frame ${frame}: time goes backwards`);
    this.t.push(f.t);
    this.frameNo.push(Number.isInteger(f.frame) ? f.frame : frame);
    this.poses(f.bodies, this.nb, this.bodyPose, 'bodies');
    if (!Array.isArray(f.hands) || f.hands.length !== this.nh)
      this.fail(`hands: expected ${this.nh} hands`);
    for (let h = 0; h < this.nh; ++h) {
      const hand = f.hands[h] || {};
      this.tracked.push(hand.tracked === false ? 0 : 1);
      this.poses(hand.bones, this.bones[h], this.bonePose, `hands[${h}].bones`);
      this.poses(hand.visual, this.bones[h], this.visualPose, `hands[${h}].visual`);
    }
    const cs = f.contacts || [];
    if (!Array.isArray(cs)) this.fail('"contacts" must be an array');
    for (let i = 0; i < cs.length; ++i) {
      const c = cs[i];
      const what = `contacts[${i}]`;
      if (!(c.hand >= 0 && c.hand < this.nh)) this.fail(`${what}: no hand ${c.hand}`);
      if (!(c.bone >= 0 && c.bone < this.bones[c.hand])) this.fail(`${what}: no bone ${c.bone}`);
      if (!(c.body >= 0 && c.body < this.nb)) this.fail(`${what}: no body ${c.body}`);
      if (!(c.state in STATES)) this.fail(`${what}: unknown state ${JSON.stringify(c.state)}`);
      this.cHand.push(c.hand);
      this.cBone.push(c.bone);
      this.cBody.push(c.body);
      this.cState.push(STATES[c.state]);
      const key = `${c.hand}/${c.bone}/${c.body}`;
      if (!this.keys.has(key)) this.keys.set(key, this.keys.size);
      this.cKey.push(this.keys.get(key));
      this.cVec.reserve(9);
      for (const v of [c.point, c.normal, c.force]) {
        if (!Array.isArray(v) || v.length !== 3 || !v.every(isNum))
          this.fail(`${what}: point, normal and force are 3 finite numbers each`);
        for (const x of v) this.cVec.a[this.cVec.n++] = x;
      }
    }
    this.contactStart.push(this.cHand.n);
  }

  // The recording read so far. Throws RecordingError when it is broken; a recording cut off
  // before its end line is returned with `truncated` set (its complete frames are usable).
  finish() {
    if (this.rest.trim() !== '') {
      // The last line had no newline: complete JSON is fine, a cut-off line is truncation.
      const last = this.rest;
      this.rest = '';
      this.line(last);
    }
    const frames = this.t.n;
    let truncated = null;
    if (this.pendingError) {
      truncated = `the last line (${this.pendingLine}) is cut off`;
    }
    if (!this.header) throw new RecordingError('the recording is empty');
    if (!this.end && !truncated) truncated = 'there is no end line';
    if (this.end && Number.isInteger(this.end.frames) && this.end.frames !== frames)
      throw new RecordingError(`the end line says ${this.end.frames} frames but the file has ${frames}`);
    if (frames === 0) throw new RecordingError(truncated ? `truncated recording with no frames: ${truncated}` : 'the recording has no frames');
    return new Recording(this, truncated);
  }
}

// Everything the viewer draws, indexed by frame.
export class Recording {
  constructor(p, truncated) {
    this.header = p.header;
    this.truncated = truncated; // null, or why the recording is incomplete
    this.end = p.end;
    this.frames = p.t.n;
    this.nb = p.nb;
    this.nh = p.nh;
    this.bones = p.bones;
    this.boneOffset = p.boneOffset;
    this.totalBones = p.totalBones;
    this.t = p.t.done();
    this.frameNo = p.frameNo.done();
    this.bodyPose = p.bodyPose.done();
    this.bonePose = p.bonePose.done();
    this.visualPose = p.visualPose.done();
    this.tracked = p.tracked.done();
    this.contactStart = p.contactStart.done();
    this.cHand = p.cHand.done();
    this.cBone = p.cBone.done();
    this.cBody = p.cBody.done();
    this.cState = p.cState.done();
    this.cKey = p.cKey.done();
    this.cVec = p.cVec.done();
    this.contactKeys = [...p.keys.keys()].map((k) => {
      const [hand, bone, body] = k.split('/').map(Number);
      const h = this.header.hands[hand];
      const boneName = h.bones[bone].name || `bone ${bone}`;
      const bodyName = this.header.bodies[body].name || `body ${body}`;
      return { hand, bone, body, label: `${h.name || 'hand ' + hand} ${boneName} / ${bodyName}` };
    });
    this.derive();
  }

  // Per-frame measures: pressing contacts and slips, the largest contact count, body speeds,
  // each hand's centre and velocity (of the bones near the scene; parked bones are far away).
  derive() {
    const n = this.frames;
    this.pressing = new Uint16Array(n);
    this.slips = new Uint16Array(n);
    this.maxContacts = 0;
    this.maxForce = 0;
    // The key frame: the largest total force of pressing contacts (as the report's still).
    this.keyFrame = n - 1;
    let keyForce = 0;
    for (let f = 0; f < n; ++f) {
      const a = this.contactStart[f], b = this.contactStart[f + 1];
      this.maxContacts = Math.max(this.maxContacts, b - a);
      let total = 0;
      for (let c = a; c < b; ++c) {
        if (this.cState[c] !== 0) this.pressing[f]++;
        if (this.cState[c] === 2) this.slips[f]++;
        const F = this.cVec.subarray(9 * c + 6, 9 * c + 9);
        const mag = Math.hypot(F[0], F[1], F[2]);
        this.maxForce = Math.max(this.maxForce, mag);
        if (this.cState[c] !== 0) total += mag;
      }
      if (total > keyForce) (keyForce = total), (this.keyFrame = f);
    }
    this.bodySpeed = new Float32Array(n * this.nb);
    for (let f = 0; f < n; ++f) {
      const g = f === 0 ? Math.min(1, n - 1) : f - 1;
      const dt = Math.abs(this.t[f] - this.t[g]);
      for (let i = 0; i < this.nb; ++i) {
        const p = this.bodyPose.subarray((f * this.nb + i) * 7), q = this.bodyPose.subarray((g * this.nb + i) * 7);
        this.bodySpeed[f * this.nb + i] = dt > 0 ? Math.hypot(p[0] - q[0], p[1] - q[1], p[2] - q[2]) / dt : 0;
      }
    }
    this.bounds = this.sceneBounds();
    const { center, radius } = this.bounds;
    const near = radius + 1.0;
    this.handCenter = new Float32Array(n * this.nh * 3);
    this.handVel = new Float32Array(n * this.nh * 3);
    this.handHasCenter = new Uint8Array(n * this.nh);
    for (let f = 0; f < n; ++f) {
      for (let h = 0; h < this.nh; ++h) {
        let sx = 0, sy = 0, sz = 0, k = 0;
        for (let b = 0; b < this.bones[h]; ++b) {
          const p = this.bonePose.subarray(this.boneIndex(f, h, b) * 7);
          if (Math.hypot(p[0] - center[0], p[1] - center[1], p[2] - center[2]) > near) continue;
          sx += p[0], sy += p[1], sz += p[2], ++k;
        }
        const o = (f * this.nh + h) * 3;
        if (k) {
          this.handCenter.set([sx / k, sy / k, sz / k], o);
          this.handHasCenter[f * this.nh + h] = 1;
        }
      }
    }
    for (let f = 1; f < n; ++f) {
      for (let h = 0; h < this.nh; ++h) {
        const i = f * this.nh + h, j = (f - 1) * this.nh + h;
        const dt = this.t[f] - this.t[f - 1];
        if (!this.handHasCenter[i] || !this.handHasCenter[j] || !(dt > 0)) continue;
        for (let k = 0; k < 3; ++k) this.handVel[3 * i + k] = (this.handCenter[3 * i + k] - this.handCenter[3 * j + k]) / dt;
      }
    }
  }

  boneIndex(f, h, b) {
    return f * this.totalBones + this.boneOffset[h] + b;
  }

  // Centre and radius of the non-plane bodies over the first frame (what the camera frames).
  sceneBounds() {
    const lo = [Infinity, Infinity, Infinity], hi = [-Infinity, -Infinity, -Infinity];
    for (let i = 0; i < this.nb; ++i) {
      const s = this.header.bodies[i].shape;
      if (s.type === 'plane') continue;
      const r = shapeRadius(s);
      for (const f of [0, this.frames - 1]) {
        const p = this.bodyPose.subarray((f * this.nb + i) * 7);
        for (let k = 0; k < 3; ++k) {
          lo[k] = Math.min(lo[k], p[k] - r);
          hi[k] = Math.max(hi[k], p[k] + r);
        }
      }
    }
    if (!Number.isFinite(lo[0])) return { center: [0, 0, 0], radius: 0.5 };
    const center = lo.map((x, k) => (x + hi[k]) / 2);
    const radius = Math.max(0.05, Math.hypot(hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]) / 2);
    return { center, radius };
  }

  // The index of the last frame at or before time t.
  frameAt(t) {
    let lo = 0, hi = this.frames - 1;
    if (t <= this.t[0]) return 0;
    while (lo < hi) {
      const mid = (lo + hi + 1) >> 1;
      if (this.t[mid] <= t) lo = mid;
      else hi = mid - 1;
    }
    return lo;
  }
}

// A bounding radius of a shape about its origin (m).
export function shapeRadius(s) {
  switch (s.type) {
    case 'box':
      return Math.hypot(...s.halfExtents) + (s.rounding || 0);
    case 'sphere':
      return s.radius;
    case 'capsule':
      return s.radius + s.halfHeight;
    case 'hull':
      return (s.points || [[0, 0, 0]]).reduce((m, p) => Math.max(m, Math.hypot(...p)), 0) + (s.rounding || 0);
    case 'compound':
      return (s.children || []).reduce((m, c) => Math.max(m, Math.hypot(...c.position) + shapeRadius(c.shape)), 0);
    default:
      return 0.05;
  }
}

// Parses a whole text (an embedded recording, a test).
export function parseText(text) {
  const p = new RecordingParser();
  p.push(text);
  return p.finish();
}

// Parses a stream of bytes (a fetch body, a File) as it arrives.
export async function parseStream(stream, onProgress) {
  const p = new RecordingParser();
  const reader = stream.getReader();
  const decoder = new TextDecoder();
  let bytes = 0;
  for (;;) {
    const { done, value } = await reader.read();
    if (done) break;
    bytes += value.length;
    p.push(decoder.decode(value, { stream: true }));
    if (onProgress) onProgress(bytes);
  }
  p.push(decoder.decode());
  return p.finish();
}
