// PNG screenshots of built-in scenes in Debian's chromium (scripts/screenshots.sh runs this):
// each scene is run with `grip run --html`, its report opened from disk and the 3D view shot at
// the frame with the largest contact force.
//   node tools/screenshots.mjs GRIP OUT_DIR WORK_DIR SCENE...
import { join, resolve } from 'node:path';
import { mkdirSync } from 'node:fs';
import { spawnSync } from 'node:child_process';
import { launch, newPage, waitLoaded } from '../test/browser.mjs';

const [grip, outDir, work, ...scenes] = process.argv.slice(2);
mkdirSync(outDir, { recursive: true });
const browser = await launch();
try {
  for (const [i, name] of scenes.entries()) {
    const dir = resolve(work, name);
    const r = spawnSync(grip, ['run', name, '--out', dir, '--html', '--quiet'], { encoding: 'utf8' });
    if (r.status !== 0 && r.status !== 3) throw new Error(`grip run ${name}: ${r.stderr}`);
    const errors = [];
    const page = await newPage(browser, errors);
    await page.setViewportSize({ width: 960, height: 600 });
    await page.goto(`file://${join(dir, 'report.html')}`);
    const s = await waitLoaded(page);
    if (s.error) throw new Error(`${name}: ${s.error}`);
    await page.evaluate((f) => window.gripViewer.seek(f), s.keyFrame);
    const whole = i === 0;
    const file = join(outDir, whole ? 'viewer.png' : `${name}.png`);
    await (whole ? page : page.locator('#stage')).screenshot({ path: file });
    if (errors.length) throw new Error(`${name}: ${errors.join('; ')}`);
    console.log(`screenshots: ${file} (${name}, frame ${s.keyFrame + 1} of ${s.frames})`);
    await page.close();
  }
} finally {
  await browser.close();
}
