// The page's 2D panels: the input table and the step-time strip chart.
// Status bits: hal::JointStatus (docs/frame-formats.md, CAN joint frames).
const CLAMPED = 1, STALE = 2, REJECTED = 4, YIELDED = 8;

export function inputHealth(status, held) {
  // Worst first: a rejected sample this tick, then no valid sample within the
  // timeout (stale, holding the last good value), then a value unchanged
  // since the tick before (held between samples), else fresh.
  if (status & REJECTED) return 'rejected';
  if (status & STALE) return 'stale';
  if (held) return 'held';
  return 'fresh';
}

export function inputReason(status, held) {
  const why = [];
  if (status & REJECTED) why.push('sample rejected this tick (CRC, counter or range)');
  if (status & STALE) why.push('no valid sample within its timeout: last good value held');
  if (!(status & (REJECTED | STALE)) && held) why.push('same value as the tick before');
  if (status & CLAMPED) why.push('joint limit reached: clamped');
  if (status & YIELDED) why.push('SPH joint yielded');
  return why.join('; ');
}

export function updateInputTable(tbody, rig, inputs) {
  if (tbody.rows.length !== inputs.length) {
    tbody.textContent = '';
    for (let i = 0; i < inputs.length; ++i) {
      const row = tbody.insertRow();
      for (let c = 0; c < 4; ++c) row.insertCell();
      row.cells[0].textContent = rig && rig.inputs[i] ? rig.inputs[i].name : 'input' + i;
    }
  }
  inputs.forEach((input, i) => {
    const row = tbody.rows[i];
    const unit = rig && rig.inputs[i] ? rig.inputs[i].unit : '';
    const v = input.value === undefined ? input.raw : input.value;
    row.cells[1].textContent = (unit === 'm' ? v.toFixed(4) : v.toFixed(2)) + ' ' + unit;
    const health = inputHealth(input.status, input.held);
    row.cells[2].textContent = health;
    row.cells[2].className = health;
    row.cells[3].textContent = inputReason(input.status, input.held);
  });
}

const STAGE_COLOURS = ['#4363d8', '#e6194b', '#3cb44b', '#f58231', '#911eb4'];

// Stacked step time per stage for the latest steps, with the tick budget as
// a line; a step whose total passes the budget is a deadline miss (red tick).
export function drawStepChart(canvas, summary, stages, history, budgetNs) {
  const g = canvas.getContext('2d');
  const w = canvas.width, h = canvas.height;
  g.clearRect(0, 0, w, h);
  if (!history || history.length === 0) {
    summary.textContent = 'no steps yet';
    return 0;
  }
  let peak = budgetNs;
  for (const step of history) {
    let total = 0;
    for (let s = 1; s < step.length; ++s) total += step[s];
    peak = Math.max(peak, total);
  }
  const yOf = (ns) => h - 4 - (ns / (peak * 1.1)) * (h - 8);
  const barW = w / Math.max(history.length, 60);
  let misses = 0;
  const sums = new Array(stages.length).fill(0);
  history.forEach((step, k) => {
    let base = 0;
    for (let s = 1; s < step.length; ++s) {
      const ns = step[s];
      sums[s - 1] += ns;
      if (ns <= 0) continue;
      g.fillStyle = STAGE_COLOURS[(s - 1) % STAGE_COLOURS.length];
      g.fillRect(k * barW, yOf(base + ns), Math.max(barW - 0.5, 1), yOf(base) - yOf(base + ns));
      base += ns;
    }
    if (base > budgetNs) {
      ++misses;
      g.fillStyle = '#d00';
      g.fillRect(k * barW, 0, Math.max(barW - 0.5, 1), 4);
    }
  });
  g.strokeStyle = '#000';
  g.setLineDash([4, 3]);
  g.beginPath();
  g.moveTo(0, yOf(budgetNs));
  g.lineTo(w, yOf(budgetNs));
  g.stroke();
  g.setLineDash([]);
  const parts = stages.map((name, s) => ({name, mean: sums[s] / history.length})).filter((p) => p.mean > 0)
      .map((p, i) => `${p.name} ${(p.mean / 1000).toFixed(1)} µs`);
  summary.textContent = `${history.length} steps: mean ${parts.join(', ')}; budget ${(budgetNs / 1000).toFixed(0)} µs;` +
      ` deadline misses ${misses}`;
  summary.innerHTML += '<br>' + stages.map((name, s) =>
      `<span style="color:${STAGE_COLOURS[s]}">■</span> ${name}`).join(' ');
  return history.length;
}
