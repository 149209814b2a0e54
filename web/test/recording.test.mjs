// The recording reader alone (no browser): typed arrays, derived measures, every kind of
// broken input named.
import test from 'node:test';
import assert from 'node:assert/strict';
import { parseText, RecordingError, RecordingParser, shapeRadius } from '../src/recording.js';

const header = {
  format: 'grip-recording', version: 2, scene: 't', dt: 0.5, steps: 2, recordEvery: 1, seed: 1, method: 'coulomb',
  bodies: [
    { name: 'floor', type: 'static', shape: { type: 'plane', normal: [0, 1, 0], offset: 0 } },
    { name: 'lego', type: 'dynamic', shape: { type: 'compound', children: [
      { position: [0, 0, 0], orientation: [1, 0, 0, 0], shape: { type: 'box', halfExtents: [0.1, 0.1, 0.1] } },
      { position: [0.3, 0, 0], orientation: [1, 0, 0, 0], shape: { type: 'box', halfExtents: [0.1, 0.1, 0.1] } }] } },
  ],
  hands: [{ name: 'right', side: 'right', bones: [{ name: 'palm', shape: { type: 'box', halfExtents: [0.04, 0.01, 0.05] } }] }],
};
const I = [1, 0, 0, 0];
function frame(n, x, contacts = []) {
  return { frame: n, t: n * 0.5, bodies: [[0, 0, 0, ...I], [x, 0.1, 0, ...I]],
    hands: [{ tracked: true, bones: [[x, 0.3, 0, ...I]], visual: [[x, 0.25, 0, ...I]] }], contacts };
}
const contact = { hand: 0, bone: 0, body: 1, point: [0, 0.2, 0], normal: [0, 1, 0], force: [3, -4, 0], state: 'slip' };
const good = [header, frame(1, 0, [contact]), frame(2, 1), { end: true, frames: 2, stateHash: '0' }].map((j) => JSON.stringify(j)).join('\n') + '\n';

test('reads frames into typed arrays and derives speeds, forces and hand motion', () => {
  const r = parseText(good);
  assert.equal(r.frames, 2);
  assert.equal(r.truncated, null);
  assert.deepEqual(Array.from(r.t), [0.5, 1]);
  assert.equal(r.bodyPose[(1 * 2 + 1) * 7], 1); // frame 2, body 1, x
  assert.equal(r.pressing[0], 1);
  assert.equal(r.slips[0], 1);
  assert.equal(r.pressing[1], 0);
  assert.equal(r.maxForce, 5);
  assert.equal(r.keyFrame, 0); // the frame with the contact
  assert.equal(r.contactKeys[0].label, 'right palm / lego');
  assert.ok(Math.abs(r.bodySpeed[1 * 2 + 1] - 2) < 1e-6); // 1 m in 0.5 s
  assert.ok(Math.abs(r.handVel[3] - 2) < 1e-6); // the palm moves 1 m in 0.5 s along x
  assert.equal(r.frameAt(0.9), 0);
  assert.equal(r.frameAt(1.0), 1);
  // The compound's radius covers its far child: 0.3 + |(0.1, 0.1, 0.1)|.
  assert.ok(Math.abs(shapeRadius(header.bodies[1].shape) - (0.3 + Math.sqrt(0.03))) < 1e-12);
});

test('joints are optional in the header and read when given', () => {
  assert.deepEqual(parseText(good).header.joints, []);
  const joint = { type: 'distance', a: 0, b: 1, anchorA: [0, 1, 0], anchorB: [0, 0.1, 0] };
  const withJoint = good.replace('"hands":', `"joints":[${JSON.stringify(joint)}],"hands":`);
  assert.deepEqual(parseText(withJoint).header.joints, [joint]);
});

test('any split of the text into chunks reads the same', () => {
  for (const size of [1, 7, 100]) {
    const p = new RecordingParser();
    for (let i = 0; i < good.length; i += size) p.push(good.slice(i, i + size));
    const r = p.finish();
    assert.equal(r.frames, 2);
    assert.deepEqual(Array.from(r.bodyPose), Array.from(parseText(good).bodyPose));
  }
});

test('broken recordings are refused with the line and the reason', () => {
  const lines = good.trim().split('\n');
  const cases = [
    ['', /the recording is empty/],
    ['{"format": "other"}\n', /line 1: not a grip recording/],
    [lines[0].replace('"version":2', '"version":3') + '\n', /unsupported recording version 3/],
    [[lines[0], '{oops', lines[2], lines[3]].join('\n'), /line 2: invalid JSON/],
    [[lines[0], lines[1].replace('"t":0.5', '"t":"x"'), lines[3]].join('\n'), /line 2: frame 1: "t" must be a number/],
    [[lines[0], lines[1].replace('"body":1', '"body":5')].join('\n'), /line 2: contacts\[0\]: no body 5/],
    [[lines[0], lines[1].replace('"slip"', '"skid"')].join('\n'), /unknown state "skid"/],
    [[lines[0], lines[2], lines[1]].join('\n'), /line 3: frame 2: time goes backwards/],
    [[lines[0], lines[1], lines[2], '{"end":true,"frames":5}'].join('\n'), /the end line says 5 frames but the file has 2/],
    [[lines[0], lines[1].replace('[1,0.1,0,1,0,0,0]', '[1,0.1,null,1,0,0,0]').replace('[0,0.1,0,1,0,0,0]', '[0,0.1,null,1,0,0,0]')].join('\n'), /bodies\[1\]: not a finite number \(null\)/],
    [[lines[0], lines[3], lines[1]].join('\n'), /line 3: text after the end line/],
    [[lines[0].replace('"hands":', '"joints":[{"a":0,"b":2,"anchorA":[0,0,0],"anchorB":[0,0,0]}],"hands":'), lines[1]].join('\n'), /header: joints\[0\]\.b: no body 2/],
    [[lines[0].replace('"hands":', '"joints":[{"a":0,"b":1,"anchorA":[0,0],"anchorB":[0,0,0]}],"hands":'), lines[1]].join('\n'), /header: joints\[0\]\.anchorA must be 3 numbers/],
    [[lines[0].replace('"hands":', '"joints":{},"hands":'), lines[1]].join('\n'), /header: "joints" must be an array/],
  ];
  for (const [text, message] of cases) {
    assert.throws(() => parseText(text), (e) => e instanceof RecordingError && message.test(e.message), String(message));
  }
});

test('a recording cut off is read up to its last complete frame and says so', () => {
  const cut = good.slice(0, good.indexOf('\n', good.indexOf('\n') + 1) + 30); // into frame 2
  const r = parseText(cut);
  assert.equal(r.frames, 1);
  assert.equal(r.truncated, 'the last line (3) is cut off');
  const noEnd = good.trim().split('\n').slice(0, 3).join('\n') + '\n';
  assert.equal(parseText(noEnd).truncated, 'there is no end line');
  assert.throws(() => parseText(good.split('\n')[0] + '\n{"fr'), /truncated recording with no frames/);
});
