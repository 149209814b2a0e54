// The report page that `grip demo` and `grip run --html` write: opened from disk (file://) in
// Debian's chromium, it shows the checks, the still and plays the embedded recording.
import test, { after } from 'node:test';
import assert from 'node:assert/strict';
import { readFileSync } from 'node:fs';
import { join } from 'node:path';
import { launch, newPage, waitLoaded } from './browser.mjs';
import { grip, readRecording, workDir } from './util.mjs';

const dir = workDir('report');
const browser = await launch();
after(() => browser.close());

async function openReport(file) {
  const errors = [];
  const page = await newPage(browser, errors);
  await page.goto(`file://${file}`);
  const s = await waitLoaded(page);
  return { page, s, errors };
}

test('the demo writes report.html, which opens from disk and plays', async () => {
  const out = join(dir, 'demo');
  const r = grip(['demo', '--out', out]);
  assert.match(r.stdout, /see it: open .*report\.html in a browser/);
  const rec = readRecording(join(out, 'recording.jsonl'));
  const { page, s, errors } = await openReport(join(out, 'report.html'));
  assert.equal(s.error, null);
  assert.equal(s.scene, 'grasp_lift');
  assert.equal(s.frames, rec.frames.length); // 60 Hz: nothing thinned
  // The checks, as the metrics give them.
  const metrics = JSON.parse(readFileSync(join(out, 'metrics.json'), 'utf8'));
  const rows = await page.locator('#checks tr').allTextContents();
  assert.equal(rows.length, metrics.checks.length + 1);
  metrics.checks.forEach((c, i) => {
    assert.ok(rows[i + 1].startsWith(c.passed ? 'PASS' : 'FAIL'), rows[i + 1]);
    assert.ok(rows[i + 1].includes(c.label), rows[i + 1]);
  });
  assert.ok((await page.locator('#metrics').textContent()).includes(metrics.stateHash));
  // The still: an SVG with the cube's faces and the two fingertip contacts.
  assert.ok((await page.locator('#still svg polygon').count()) >= 3);
  assert.ok((await page.locator('#still svg circle').count()) >= 2);
  // It plays.
  await page.click('#play');
  await page.waitForFunction(() => window.gripViewer.state().index >= 10, null, { timeout: 20000 });
  const p = await page.evaluate(() => window.gripViewer.state());
  assert.ok(p.playing || p.index === p.frames - 1);
  assert.deepEqual(errors, []);
  await page.close();
});

test('a 240 Hz run is embedded at 60 frames per second, ending on the last frame', async () => {
  const out = join(dir, 'fast');
  const r = grip(['run', 'grasp_lift', '--out', out, '--html', '--set', 'world.hz=240']);
  const rec = readRecording(join(out, 'recording.jsonl'));
  assert.equal(rec.frames.length, 600);
  assert.match(r.stdout, /151 of 600 frames embedded/);
  const { page, s, errors } = await openReport(join(out, 'report.html'));
  assert.equal(s.frames, 151); // every 4th frame and the last
  await page.evaluate(() => window.gripViewer.seek(1e9));
  const last = await page.evaluate(() => window.gripViewer.state());
  assert.equal(last.frame, 600);
  const cube = rec.frames[599].bodies[1];
  for (let c = 0; c < 3; ++c) assert.ok(Math.abs(last.bodyPositions[1][c] - cube[c]) < 2e-6);
  await page.evaluate(() => window.gripViewer.seek(10));
  assert.equal((await page.evaluate(() => window.gripViewer.state())).frame, 41);
  assert.deepEqual(errors, []);
  await page.close();
});
