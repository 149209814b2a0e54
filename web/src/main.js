// grip's recording viewer: opens a recording (embedded in a report, ?url=, file picker, drag and
// drop), plays it with a timeline, and shows charts and a small panel. State for tests and
// scripts: window.gripViewer.
import { parseStream, parseText, RecordingError } from './recording.js';
import { SceneView, ID_COLORS } from './scene3d.js';
import { Charts } from './charts.js';

const $ = (id) => document.getElementById(id);
const SPEEDS = [0.1, 0.25, 0.5, 1, 2, 4];

class Viewer {
  constructor() {
    this.rec = null;
    this.index = 0; // frame index into the recording
    this.playing = false;
    this.speed = 1;
    this.simTime = 0;
    this.error = null;
    this.warning = null;
    this.ready = false;
    this.loads = 0; // completed loads, so that a test can wait for the next one
    this.view = new SceneView($('view'));
    this.charts = new Charts($('charts'), (f) => this.seek(f));
    this.wire();
    requestAnimationFrame((ts) => this.tick(ts));
  }

  wire() {
    $('play').addEventListener('click', () => (this.playing ? this.pause() : this.play()));
    const speed = $('speed');
    for (const s of SPEEDS) {
      const o = document.createElement('option');
      o.value = String(s);
      o.textContent = `${s}×`;
      if (s === 1) o.selected = true;
      speed.appendChild(o);
    }
    speed.addEventListener('change', () => this.setSpeed(Number(speed.value)));
    $('scrub').addEventListener('input', (e) => {
      this.pause();
      this.seek(Number(e.target.value));
    });
    for (const box of document.querySelectorAll('#layers input')) {
      box.addEventListener('change', () => this.view.setLayer(box.dataset.layer, box.checked));
    }
    $('home').addEventListener('click', () => this.view.home());
    $('file').addEventListener('change', (e) => {
      const f = e.target.files && e.target.files[0];
      if (f) this.openFile(f);
    });
    const drop = document.body;
    drop.addEventListener('dragover', (e) => {
      e.preventDefault();
      document.body.classList.add('dragging');
    });
    drop.addEventListener('dragleave', () => document.body.classList.remove('dragging'));
    drop.addEventListener('drop', (e) => {
      e.preventDefault();
      document.body.classList.remove('dragging');
      const f = e.dataTransfer.files && e.dataTransfer.files[0];
      if (f) this.openFile(f);
    });
    window.addEventListener('keydown', (e) => {
      if (!this.rec || e.target.tagName === 'INPUT' || e.target.tagName === 'SELECT') return;
      if (e.key === ' ') (this.playing ? this.pause() : this.play()), e.preventDefault();
      if (e.key === 'ArrowRight') this.pause(), this.seek(Math.min(this.rec.frames - 1, this.index + 1));
      if (e.key === 'ArrowLeft') this.pause(), this.seek(Math.max(0, this.index - 1));
    });
    window.addEventListener('resize', () => this.charts.resize());
  }

  status(text, kind) {
    const m = $('message');
    m.textContent = text || '';
    m.className = kind || '';
    m.hidden = !text;
  }

  async open(what, name) {
    this.pause();
    this.ready = false;
    this.error = null;
    this.warning = null;
    this.status(`reading ${name}…`, 'info');
    try {
      const rec = await what();
      this.show(rec, name);
    } catch (e) {
      const msg = e instanceof RecordingError ? e.message : String(e.message || e);
      this.error = `${name}: ${msg}`;
      this.status(`Cannot show this recording. ${this.error}`, 'error');
      this.rec = null;
      document.body.classList.remove('loaded');
    }
    this.loads++;
  }

  openFile(file) {
    return this.open(() => parseStream(file.stream(), (n) => this.progress(n, file.size)), file.name);
  }

  openUrl(url) {
    return this.open(async () => {
      const r = await fetch(url);
      if (!r.ok) throw new RecordingError(`HTTP ${r.status} ${r.statusText}`);
      const size = Number(r.headers.get('content-length')) || 0;
      return parseStream(r.body, (n) => this.progress(n, size));
    }, url);
  }

  openText(text, name) {
    return this.open(async () => parseText(text), name);
  }

  progress(bytes, size) {
    const mb = (bytes / 1e6).toFixed(1);
    this.status(size ? `reading… ${mb} of ${(size / 1e6).toFixed(1)} MB` : `reading… ${mb} MB`, 'info');
  }

  show(rec, name) {
    this.rec = rec;
    const h = rec.header;
    $('title').textContent = `${h.scene || 'recording'} — ${h.method || ''}`;
    document.title = `grip · ${h.scene || name}`;
    $('scrub').max = String(rec.frames - 1);
    this.view.load(rec);
    this.charts.load(rec);
    document.body.classList.add('loaded');
    if (rec.truncated) {
      this.warning = `${name}: truncated recording (${rec.truncated}); showing the ${rec.frames} complete frames`;
      this.status(this.warning, 'warning');
    } else {
      this.status('');
    }
    this.seek(0);
    this.ready = true;
  }

  play() {
    if (!this.rec) return;
    if (this.index >= this.rec.frames - 1) this.seek(0);
    this.playing = true;
    this.last = null;
    $('play').textContent = '❚❚ pause';
  }

  pause() {
    this.playing = false;
    $('play').textContent = '▶ play';
  }

  setSpeed(s) {
    this.speed = s;
    $('speed').value = String(s);
  }

  seek(f) {
    if (!this.rec) return;
    this.index = Math.max(0, Math.min(this.rec.frames - 1, Math.round(f)));
    this.simTime = this.rec.t[this.index];
    this.draw();
  }

  draw() {
    const rec = this.rec, f = this.index;
    this.view.showFrame(f);
    this.charts.mark(f);
    $('scrub').value = String(f);
    const h = rec.header;
    const dtRec = (h.dt || 0) * (h.recordEvery || 1);
    $('p-time').textContent = `${rec.t[f].toFixed(3)} s / ${rec.t[rec.frames - 1].toFixed(2)} s`;
    $('p-frame').textContent = `${rec.frameNo[f]} (${f + 1} of ${rec.frames})`;
    $('p-contacts').textContent = String(rec.pressing[f]);
    $('p-slips').textContent = String(rec.slips[f]);
    $('p-rate').textContent = dtRec > 0 ? `${(1 / dtRec).toFixed(0)} frames/s` : '';
  }

  tick(ts) {
    if (this.playing && this.rec) {
      if (this.last != null) this.simTime += ((ts - this.last) / 1000) * this.speed;
      this.last = ts;
      const end = this.rec.t[this.rec.frames - 1];
      if (this.simTime >= end) {
        this.simTime = end;
        this.pause();
      }
      const f = this.rec.frameAt(this.simTime);
      if (f !== this.index) {
        this.index = f;
        this.draw();
      }
    }
    requestAnimationFrame((t) => this.tick(t));
  }

  // A snapshot for tests: what is on screen now.
  state() {
    const rec = this.rec;
    const s = { ready: this.ready, error: this.error, warning: this.warning, loads: this.loads, playing: this.playing, speed: this.speed };
    if (!rec) return s;
    const f = this.index;
    const bodies = [];
    for (let i = 0; i < rec.nb; ++i) {
      const o = this.view.bodies[i];
      bodies.push([o.position.x, o.position.y, o.position.z]);
    }
    return {
      ...s,
      scene: rec.header.scene,
      frames: rec.frames,
      keyFrame: rec.keyFrame,
      duration: rec.t[rec.frames - 1] - rec.t[0],
      index: f,
      frame: rec.frameNo[f],
      t: rec.t[f],
      contacts: rec.pressing[f],
      slips: rec.slips[f],
      bodyPositions: bodies,
      shown: this.view.counts(),
      panel: {
        time: $('p-time').textContent,
        frame: $('p-frame').textContent,
        contacts: $('p-contacts').textContent,
        slips: $('p-slips').textContent,
      },
    };
  }
}

const viewer = new Viewer();
window.gripViewer = {
  state: () => viewer.state(),
  play: () => viewer.play(),
  pause: () => viewer.pause(),
  seek: (f) => viewer.seek(f),
  setSpeed: (s) => viewer.setSpeed(s),
  setIdMode: (on) => viewer.view.setIdMode(on),
  idColors: ID_COLORS,
  openUrl: (u) => viewer.openUrl(u),
  openText: (t, n) => viewer.openText(t, n || 'text'),
};

// Where the recording comes from: embedded (a report), ?url=, or the user.
const embedded = document.getElementById('grip-recording');
const url = new URLSearchParams(location.search).get('url');
if (embedded) {
  viewer.openText(embedded.textContent, 'the embedded recording');
} else if (url) {
  viewer.openUrl(url);
} else {
  viewer.status('Open a grip recording (recording.jsonl): choose a file or drop it here.', 'info');
}
