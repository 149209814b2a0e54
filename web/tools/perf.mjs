// Measures the viewer on a long recording (docs/viewer.md): load time, the time to show one
// frame (a seek), and the frames drawn per second while playing. Prints, asserts nothing.
//   GRIP=build/apps/grip GRIP_WEB_MODULES=build/apps/web/npm/node_modules \
//     node web/tools/perf.mjs RECORDING
import { launch, newPage, waitLoaded } from '../test/browser.mjs';
import { startView } from '../test/util.mjs';
import { statSync } from 'node:fs';

const [file] = process.argv.slice(2);
const view = await startView(file);
const browser = await launch();
const page = await newPage(browser, []);
const t0 = Date.now();
await page.goto(view.url);
const s = await waitLoaded(page);
const loadSeconds = (Date.now() - t0) / 1000;
const seek = await page.evaluate((n) => {
  const times = [];
  for (let i = 0; i < 200; ++i) {
    const f = Math.floor(Math.random() * n);
    const a = performance.now();
    window.gripViewer.seek(f);
    times.push(performance.now() - a);
  }
  times.sort((x, y) => x - y);
  return { median: times[100], p95: times[190] };
}, s.frames);
// Counted while playing at 1x: 5 s, or 90 % of a shorter recording.
const fps = await page.evaluate(async (seconds) => {
  window.gripViewer.seek(0);
  window.gripViewer.play();
  let frames = 0, ticks = 0, last = -1;
  const start = performance.now();
  await new Promise((done) => {
    const tick = () => {
      ticks++;
      const i = window.gripViewer.state().index;
      if (i !== last) frames++, (last = i);
      if (performance.now() - start < 1000 * seconds) requestAnimationFrame(tick);
      else done();
    };
    requestAnimationFrame(tick);
  });
  window.gripViewer.pause();
  return { shown: frames / seconds, animationFrames: ticks / seconds };
}, Math.min(5, 0.9 * s.duration));
console.log(JSON.stringify({ file, megabytes: statSync(file).size / 1e6, frames: s.frames, loadSeconds, seekMs: seek, playFps: fps }));
await browser.close();
view.proc.kill('SIGTERM');
