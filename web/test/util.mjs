// Shared by the browser tests: the grip binary, a scratch directory, reading a recording in
// node (the expected values), and pixel statistics of a screenshot.
import { spawn, spawnSync } from 'node:child_process';
import { mkdirSync, readFileSync, rmSync } from 'node:fs';
import { join } from 'node:path';
import { tmpdir } from 'node:os';

export const GRIP = process.env.GRIP || join(process.cwd(), 'build/apps/grip');

export function workDir(name) {
  const d = join(process.env.GRIP_WEB_WORK || join(tmpdir(), 'grip-web-test'), name);
  rmSync(d, { recursive: true, force: true });
  mkdirSync(d, { recursive: true });
  return d;
}

// Runs grip; throws with its stderr unless the exit code is `expect`.
export function grip(args, expect = 0) {
  const r = spawnSync(GRIP, args, { encoding: 'utf8' });
  if (r.status !== expect) throw new Error(`grip ${args.join(' ')}: exit ${r.status}\n${r.stderr}`);
  return r;
}

// The lines of a recording file as JSON.
export function readRecording(path) {
  const lines = readFileSync(path, 'utf8').split('\n').filter((l) => l.trim()).map((l) => JSON.parse(l));
  return { header: lines[0], frames: lines.slice(1, -1), end: lines[lines.length - 1] };
}

// `grip view FILE --port 0`: resolves with the process and the printed address.
export function startView(file) {
  const p = spawn(GRIP, ['view', file, '--port', '0'], { stdio: ['ignore', 'pipe', 'pipe'] });
  return new Promise((resolve, reject) => {
    let out = '', err = '';
    const timer = setTimeout(() => reject(new Error(`grip view printed no address: ${out} ${err}`)), 10000);
    p.stderr.on('data', (d) => (err += d));
    p.stdout.on('data', (d) => {
      out += d;
      const m = out.match(/http:\/\/127\.0\.0\.1:(\d+)\/\S*/);
      if (m) {
        clearTimeout(timer);
        resolve({ proc: p, url: m[0], base: `http://127.0.0.1:${m[1]}` });
      }
    });
    p.on('exit', (code) => reject(new Error(`grip view exited ${code}: ${err}`)));
  });
}

// Colour statistics of a PNG, decoded by the page itself (no image library needed).
export async function pixelStats(page, png, palette) {
  return page.evaluate(
    async ({ b64, palette }) => {
      const img = new Image();
      img.src = `data:image/png;base64,${b64}`;
      await img.decode();
      const c = document.createElement('canvas');
      c.width = img.width;
      c.height = img.height;
      const g = c.getContext('2d');
      g.drawImage(img, 0, 0);
      const d = g.getImageData(0, 0, c.width, c.height).data;
      const bg = [d[0], d[1], d[2]];
      const colours = new Set();
      let differing = 0;
      const hits = new Array(palette.length).fill(0);
      for (let i = 0; i < d.length; i += 4) {
        const r = d[i], gg = d[i + 1], b = d[i + 2];
        colours.add((r << 16) | (gg << 8) | b);
        if (Math.abs(r - bg[0]) + Math.abs(gg - bg[1]) + Math.abs(b - bg[2]) > 30) differing++;
        for (let k = 0; k < palette.length; ++k) {
          const p = palette[k];
          if (Math.abs(r - ((p >> 16) & 255)) < 8 && Math.abs(gg - ((p >> 8) & 255)) < 8 && Math.abs(b - (p & 255)) < 8) hits[k]++;
        }
      }
      return { pixels: d.length / 4, colours: colours.size, differing, hits };
    },
    { b64: png.toString('base64'), palette },
  );
}
