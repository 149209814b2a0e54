// The viewer in Debian's chromium, served by `grip view`: loads a recording, plays, seeks and
// shows the frame asked for; a screenshot is not blank and shows every body; broken and
// truncated recordings give a clear message in the page.
import test, { after } from 'node:test';
import assert from 'node:assert/strict';
import { readFileSync, writeFileSync } from 'node:fs';
import { join } from 'node:path';
import { launch, newPage, waitLoaded } from './browser.mjs';
import { grip, pixelStats, readRecording, startView, workDir } from './util.mjs';

const dir = workDir('viewer');
grip(['run', 'grasp_lift', '--out', join(dir, 'gl'), '--quiet']);
const recPath = join(dir, 'gl', 'recording.jsonl');
const rec = readRecording(recPath);

// Five separated bodies, one of each shape a scene file can make (the plane is the floor).
const shapes = {
  grip_scene: 1,
  name: 'shapes',
  duration: 0.2,
  bodies: [
    { name: 'floor', type: 'static', shape: { type: 'plane', normal: [0, 1, 0], offset: 0 } },
    { name: 'box', shape: { type: 'box', halfExtents: [0.05, 0.05, 0.05] }, position: [-0.25, 0.05, 0] },
    { name: 'ball', shape: { type: 'sphere', radius: 0.05 }, position: [-0.08, 0.05, 0] },
    { name: 'pen', shape: { type: 'capsule', radius: 0.03, halfHeight: 0.05 }, position: [0.08, 0.08, 0] },
    { name: 'wedge', shape: { type: 'hull', points: [[0, 0, 0], [0.1, 0, 0], [0, 0.1, 0], [0, 0, 0.1], [0.1, 0, 0.1], [0, 0.1, 0.1]] }, position: [0.2, 0, -0.05] },
  ],
};
// A ball on a 0.3 m rope and a door on a hinge: the viewer draws each joint's line.
shapes.bodies.push(
  { name: 'hook', type: 'static', shape: { type: 'box', halfExtents: [0.04, 0.04, 0.04] }, position: [0, 0.6, 0.3] },
  { name: 'bob', shape: { type: 'sphere', radius: 0.05 }, position: [0, 0.3, 0.3] });
shapes.joints = [{ type: 'distance', a: 'hook', b: 'bob', anchor: [0, 0.6, 0.3], anchorB: [0, 0.3, 0.3], limit: [-0.3, 0] }];
writeFileSync(join(dir, 'shapes.json'), JSON.stringify(shapes));
grip(['run', join(dir, 'shapes.json'), '--out', join(dir, 'shapes'), '--quiet']);

const view = await startView(recPath);
const browser = await launch();
after(async () => {
  await browser.close();
  view.proc.kill('SIGTERM');
});

test('grip view serves the page and the recording, GET only', async () => {
  assert.match(view.url, /\?url=recording\.jsonl$/);
  const page = await fetch(`${view.base}/`);
  assert.equal(page.status, 200);
  assert.match(page.headers.get('content-type'), /text\/html/);
  assert.match(await page.text(), /gripViewer/);
  const file = await fetch(`${view.base}/recording.jsonl`);
  assert.equal(file.status, 200);
  assert.equal(await file.text(), readFileSync(recPath, 'utf8'));
  assert.equal((await fetch(`${view.base}/nope`)).status, 404);
  assert.equal((await fetch(`${view.base}/`, { method: 'POST', body: 'x' })).status, 405);
  // The run's directory stands for its recording.
  const byDir = await startView(join(dir, 'gl'));
  assert.equal(await (await fetch(`${byDir.base}/recording.jsonl`)).text(), readFileSync(recPath, 'utf8'));
  byDir.proc.kill('SIGTERM');
});

test('grip view refuses a file that is not a complete recording', () => {
  const bad = join(dir, 'cut.jsonl');
  writeFileSync(bad, readFileSync(recPath, 'utf8').slice(0, 5000));
  for (const [file, message] of [
    [join(dir, 'missing.jsonl'), /cannot open: No such file/],
    [join(dir, 'gl', 'metrics.json'), /not a grip recording/],
    [bad, /truncated recording/],
  ]) {
    const r = grip(['view', file, '--port', '0'], 1);
    assert.match(r.stderr, /^grip: /);
    assert.match(r.stderr, message);
    assert.equal(r.stderr.trim().split('\n').length, 1);
  }
  const html = grip(['run', 'grasp_lift', '--html'], 1);
  assert.equal(html.stderr, 'grip: --html: needs --out DIR (the report goes beside the recording)\n');
});

test('loads, plays, seeks and shows the frame asked for', async () => {
  const errors = [];
  const page = await newPage(browser, errors);
  await page.goto(view.url);
  let s = await waitLoaded(page);
  assert.equal(s.error, null);
  assert.equal(s.frames, rec.frames.length);
  assert.equal(s.scene, 'grasp_lift');
  assert.equal(s.index, 0);

  // Seek: the bodies stand where the recording's line says.
  for (const k of [0, 37, 100, rec.frames.length - 1]) {
    await page.evaluate((f) => window.gripViewer.seek(f), k);
    s = await page.evaluate(() => window.gripViewer.state());
    const line = rec.frames[k];
    assert.equal(s.index, k);
    assert.equal(s.frame, line.frame);
    assert.equal(s.t, line.t);
    assert.ok(s.panel.frame.startsWith(`${line.frame} (`), s.panel.frame);
    line.bodies.forEach((p, i) => {
      for (let c = 0; c < 3; ++c) assert.ok(Math.abs(s.bodyPositions[i][c] - p[c]) < 1e-6, `body ${i} at frame ${k}`);
    });
    const pressing = line.contacts.filter((c) => c.state !== 'touch').length;
    assert.equal(s.contacts, pressing);
    assert.equal(s.panel.contacts, String(pressing));
    assert.equal(s.shown.contactDots, line.contacts.length);
    // The visual hand is drawn (opaque) only while the hand presses on the cube.
    assert.equal(s.shown.visualBones > 0, pressing > 0, `visual hand at frame ${k}: ${JSON.stringify(s.shown)} ${pressing}`);
  }
  // The scrub bar seeks too.
  await page.locator('#scrub').fill('60');
  s = await page.evaluate(() => window.gripViewer.state());
  assert.equal(s.index, 60);

  // Play from the start at a quarter speed (10 s for the 2.5 s run): time moves on; pause
  // stops it.
  await page.evaluate(() => window.gripViewer.seek(0));
  await page.selectOption('#speed', '0.25');
  await page.click('#play');
  await page.waitForFunction(() => window.gripViewer.state().index >= 10, null, { timeout: 20000 });
  await page.click('#play');
  const paused = await page.evaluate(() => window.gripViewer.state());
  assert.equal(paused.playing, false);
  assert.equal(paused.speed, 0.25);
  assert.ok(paused.index >= 10 && paused.index < rec.frames.length - 1, `paused at ${paused.index}`);
  await page.waitForTimeout(300);
  assert.equal((await page.evaluate(() => window.gripViewer.state())).index, paused.index);

  // The layer switches hide and show the overlays.
  await page.evaluate(() => window.gripViewer.seek(60));
  const before = (await page.evaluate(() => window.gripViewer.state())).shown;
  assert.ok(before.forceArrows === 2 && before.contactDots === 2 && before.visualBones > 0, JSON.stringify(before));
  for (const layer of ['forces', 'contacts', 'visual']) await page.uncheck(`[data-layer=${layer}]`);
  const hidden = (await page.evaluate(() => window.gripViewer.state())).shown;
  assert.deepEqual([hidden.forceArrows, hidden.contactDots, hidden.visualBones], [0, 0, 0]);
  assert.equal(hidden.trackedBones, before.trackedBones);
  for (const layer of ['forces', 'contacts', 'visual']) await page.check(`[data-layer=${layer}]`);
  assert.deepEqual((await page.evaluate(() => window.gripViewer.state())).shown, before);

  // A screenshot mid-grasp (frame 61), of the canvas alone (panel and legend hidden): not blank.
  const hide = await page.addStyleTag({ content: '#panel, #legend { visibility: hidden; }' });
  const shot = await page.locator('#view').screenshot();
  await hide.evaluate((e) => e.remove());
  const stats = await pixelStats(page, shot, []);
  if (process.env.GRIP_WEB_VERBOSE) console.log(stats);
  assert.ok(stats.colours > 100, `only ${stats.colours} colours`); // 688 here; a blank canvas has 1
  assert.ok(stats.differing > stats.pixels * 0.05, `only ${stats.differing} of ${stats.pixels} pixels differ from the background`);
  assert.deepEqual(errors, []);
  await page.close();
});

test('a screenshot shows every body of the recording', async () => {
  const errors = [];
  const page = await newPage(browser, errors);
  await page.goto(view.url.replace(/\?.*/, ''));
  await waitLoaded(page, 0);
  // Open the shapes recording through the file picker.
  await page.setInputFiles('#file', join(dir, 'shapes', 'recording.jsonl'));
  const s = await waitLoaded(page, 1);
  assert.equal(s.error, null);
  assert.equal(s.scene, 'shapes');
  assert.equal(s.shown.bodies, shapes.bodies.length);
  // The rope hangs taut: its line is the rope's length.
  assert.equal(s.shown.jointLengths.length, 1);
  assert.ok(Math.abs(s.shown.jointLengths[0] - 0.3) < 2e-3, `rope drawn ${s.shown.jointLengths[0]} m long`);
  // Flat colours per body: count the colours seen in a screenshot.
  await page.evaluate(() => window.gripViewer.setIdMode(true));
  const palette = await page.evaluate(() => window.gripViewer.idColors);
  const stats = await pixelStats(page, await page.locator('#view').screenshot(), palette);
  const seen = stats.hits.filter((n) => n > 200).length;
  assert.equal(seen, shapes.bodies.length, `pixels per body colour: ${stats.hits.slice(0, 8)}`);

  // A voxel-style compound of boxes (an L of three), added to the same recording.
  const lego = {
    name: 'lego', type: 'dynamic',
    shape: { type: 'compound', children: [[0, 0, 0], [0.06, 0, 0], [0, 0.06, 0]].map((p) => ({
      position: p, orientation: [1, 0, 0, 0], shape: { type: 'box', halfExtents: [0.03, 0.03, 0.03], rounding: 0 } })) },
  };
  const lines = readFileSync(join(dir, 'shapes', 'recording.jsonl'), 'utf8').trim().split('\n').map((l) => JSON.parse(l));
  lines[0].bodies.push(lego);
  for (const f of lines.slice(1, -1)) f.bodies.push([0.4, 0.03, 0, 1, 0, 0, 0]);
  writeFileSync(join(dir, 'compound.jsonl'), lines.map((l) => JSON.stringify(l)).join('\n') + '\n');
  await page.evaluate(() => window.gripViewer.setIdMode(false));
  await page.setInputFiles('#file', join(dir, 'compound.jsonl'));
  const c = await waitLoaded(page, 2);
  assert.equal(c.error, null);
  assert.equal(c.shown.bodies, shapes.bodies.length + 1);
  await page.evaluate(() => window.gripViewer.setIdMode(true));
  const withLego = await pixelStats(page, await page.locator('#view').screenshot(), palette);
  assert.equal(withLego.hits.filter((n) => n > 200).length, shapes.bodies.length + 1, `${withLego.hits.slice(0, 8)}`);
  assert.deepEqual(errors, []);
  await page.close();
});

test('broken and truncated recordings give a clear message', async () => {
  const errors = [];
  const page = await newPage(browser, errors);
  await page.goto(view.url.replace(/\?.*/, ''));
  await waitLoaded(page, 0);
  const text = readFileSync(recPath, 'utf8');
  const lines = text.split('\n');
  const cases = [
    ['broken.jsonl', [lines[0], lines[1], '{"frame": 2, "t": oops', lines[3], ''].join('\n'), /broken\.jsonl: line 3: invalid JSON/, 'error'],
    ['notes.txt', 'hello\n', /notes\.txt: line 1: invalid JSON/, 'error'],
    ['metrics.json', readFileSync(join(dir, 'gl', 'metrics.json'), 'utf8').replace(/\n/g, ' ') + '\n', /not a grip recording/, 'error'],
    ['empty.jsonl', '', /the recording is empty/, 'error'],
    ['future.jsonl', lines[0].replace('"version":2', '"version":99') + '\n', /unsupported recording version 99/, 'error'],
    ['short.jsonl', [lines[0], lines[1], lines[2].replace(/"bodies":\[\[[^\]]*\],/, '"bodies":[')].join('\n') + '\n', /line 3: bodies: expected 2 poses, got 1/, 'error'],
  ];
  let loads = 0;
  for (const [name, content, message, kind] of cases) {
    writeFileSync(join(dir, name), content);
    await page.setInputFiles('#file', join(dir, name));
    const s = await waitLoaded(page, ++loads);
    assert.match(s.error || '', message, name);
    assert.equal(s.ready, false);
    const box = page.locator('#message');
    assert.ok(await box.isVisible(), name);
    assert.match(await box.textContent(), /^Cannot show this recording\. /, name);
    assert.match(await box.textContent(), message, name);
    assert.equal(await box.getAttribute('class'), kind);
    await page.setInputFiles('#file', []);
  }
  // Cut in the middle of a frame: the complete frames are shown, with a warning.
  const cut = text.slice(0, text.indexOf('\n', text.length / 2) - 40);
  const complete = cut.split('\n').length - 2; // header and the cut line are not frames
  // Dropped onto the page rather than picked.
  await page.evaluate(async (content) => {
    const dt = new DataTransfer();
    dt.items.add(new File([content], 'cut.jsonl'));
    document.body.dispatchEvent(new DragEvent('drop', { dataTransfer: dt, bubbles: true, cancelable: true }));
  }, cut);
  const s = await waitLoaded(page, ++loads);
  assert.equal(s.error, null);
  assert.match(s.warning, /cut\.jsonl: truncated recording \(the last line \(\d+\) is cut off\); showing the \d+ complete frames/);
  assert.equal(s.frames, complete);
  assert.match(await page.locator('#message').textContent(), /truncated recording/);
  // A URL that does not exist.
  await page.evaluate(() => window.gripViewer.openUrl('/missing.jsonl'));
  const m = await waitLoaded(page, ++loads);
  assert.match(m.error, /HTTP 404/);
  assert.deepEqual(errors.filter((e) => !/404/.test(e)), []);
  await page.close();
});
