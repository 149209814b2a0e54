// Charts over time (uPlot): normal and tangential force of each hand contact, and the speed of
// each dynamic body. A vertical line marks the frame shown; clicking a chart seeks there.
import uPlot from 'uplot';

const PALETTE = ['#4e79a7', '#f28e2b', '#e15759', '#76b7b2', '#59a14f', '#edc948', '#b07aa1', '#ff9da7', '#9c755f', '#bab0ac'];
const MAX_SERIES = 10; // the contacts with the largest forces; more lines are unreadable

// Per contact key and frame: normal and tangential force (null where the contact is absent).
function contactSeries(rec) {
  const nk = rec.contactKeys.length;
  const normal = Array.from({ length: nk }, () => new Array(rec.frames).fill(null));
  const tangential = Array.from({ length: nk }, () => new Array(rec.frames).fill(null));
  const peak = new Float64Array(nk);
  for (let f = 0; f < rec.frames; ++f) {
    for (let c = rec.contactStart[f]; c < rec.contactStart[f + 1]; ++c) {
      const v = rec.cVec.subarray(9 * c, 9 * c + 9);
      const fn = v[3] * v[6] + v[4] * v[7] + v[5] * v[8];
      const tx = v[6] - fn * v[3], ty = v[7] - fn * v[4], tz = v[8] - fn * v[5];
      const k = rec.cKey[c];
      // The force on the body points into it: the normal component is -F.n.
      normal[k][f] = -fn;
      tangential[k][f] = Math.hypot(tx, ty, tz);
      peak[k] = Math.max(peak[k], Math.hypot(v[6], v[7], v[8]));
    }
  }
  const keep = [...peak.keys()].sort((a, b) => peak[b] - peak[a]).slice(0, MAX_SERIES).sort((a, b) => a - b);
  return { keep, normal, tangential };
}

export class Charts {
  constructor(container, onSeek) {
    this.container = container;
    this.onSeek = onSeek;
    this.plots = [];
  }

  load(rec) {
    for (const p of this.plots) p.plot.destroy();
    this.container.innerHTML = '';
    this.plots = [];
    this.rec = rec;
    const t = Array.from(rec.t);
    const { keep, normal, tangential } = contactSeries(rec);
    const labels = keep.map((k) => rec.contactKeys[k].label);
    const speeds = [];
    const speedLabels = [];
    rec.header.bodies.forEach((b, i) => {
      if (b.type !== 'dynamic') return;
      const s = new Array(rec.frames);
      for (let f = 0; f < rec.frames; ++f) s[f] = rec.bodySpeed[f * rec.nb + i];
      speeds.push(s);
      speedLabels.push(b.name || `body ${i}`);
    });
    this.add('normal force (N)', t, keep.map((k) => normal[k]), labels, 'no hand contacts');
    this.add('tangential force (N)', t, keep.map((k) => tangential[k]), labels, 'no hand contacts');
    this.add('body speed (m/s)', t, speeds.slice(0, MAX_SERIES), speedLabels, 'no dynamic bodies');
    this.resize();
  }

  add(title, t, ys, labels, empty) {
    const box = document.createElement('div');
    box.className = 'chart';
    this.container.appendChild(box);
    const heading = document.createElement('div');
    heading.className = 'chart-title';
    heading.textContent = title;
    box.appendChild(heading);
    if (!ys.length) {
      const e = document.createElement('div');
      e.className = 'chart-empty';
      e.textContent = empty;
      box.appendChild(e);
      return;
    }
    const opts = {
      width: 320,
      height: 130,
      legend: { show: true, live: true }, // hovering a chart shows its values
      cursor: { drag: { x: false, y: false }, points: { show: false } },
      scales: { x: { time: false } },
      axes: [{ size: 28 }, { size: 44 }],
      series: [{ label: 't (s)' }, ...labels.map((l, i) => ({ label: l, stroke: PALETTE[i % PALETTE.length], width: 1.25, spanGaps: false }))],
    };
    const plot = new uPlot(opts, [t, ...ys], box);
    const marker = document.createElement('div');
    marker.className = 'chart-marker';
    plot.over.appendChild(marker);
    plot.over.addEventListener('click', (ev) => {
      const x = plot.posToVal(ev.offsetX, 'x');
      this.onSeek(this.rec.frameAt(x));
    });
    this.plots.push({ plot, marker, box });
  }

  resize() {
    for (const p of this.plots) {
      const w = Math.max(200, p.box.clientWidth);
      p.plot.setSize({ width: w, height: 130 });
    }
    if (this.rec) this.mark(this.frame || 0);
  }

  // Moves the frame marker (a positioned div: cheaper than redrawing the plots every frame).
  mark(f) {
    this.frame = f;
    if (!this.rec) return;
    const t = this.rec.t[f];
    for (const p of this.plots) {
      const x = p.plot.valToPos(t, 'x');
      p.marker.style.transform = `translateX(${x}px)`;
    }
  }
}
