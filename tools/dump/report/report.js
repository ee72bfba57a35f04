// SPDX-License-Identifier: Apache-2.0
// codrive-dump --report: builds the tables and the uPlot charts from the embedded JSON, then
// writes a summary (data points per chart, script errors) into #codrive-check for tests.
(function () {
  "use strict";
  const D = JSON.parse(document.getElementById("codrive-data").textContent);
  const check = { charts: {}, tables: {}, errors: window.codriveErrors };
  const palette = ["#1f77b4", "#d62728", "#2ca02c", "#ff7f0e", "#9467bd", "#8c564b",
                   "#e377c2", "#7f7f7f", "#bcbd22", "#17becf"];
  const colour = (i) => palette[i % palette.length];
  const fmt = (v, digits) => (v === null || v === undefined) ? "-" : Number(v).toFixed(digits);
  const hex = (v, w) => (v === null) ? "-" : "0x" + v.toString(16).toUpperCase().padStart(w, "0");

  function cell(tr, text, cls) {
    const td = document.createElement("td");
    td.textContent = text;
    if (cls) td.className = cls;
    tr.appendChild(td);
  }
  function table(id, head, rows) {
    const t = document.getElementById(id);
    const hr = document.createElement("tr");
    for (const h of head) {
      const th = document.createElement("th");
      th.textContent = h;
      hr.appendChild(th);
    }
    t.appendChild(hr);
    for (const r of rows) t.appendChild(r);
    check.tables[id] = rows.length;
  }
  // Counts the points uPlot gets that carry data (y above 0 in any series), then draws.
  function chart(id, title, xLabel, yLabel, xs, series, opts) {
    let points = 0;
    for (const s of series) for (const v of s.data) if (v !== null && v > 0) points++;
    check.charts[id] = points;
    const el = document.getElementById(id);
    if (points === 0) {
      el.textContent = "No data for this chart in the trace.";
      return;
    }
    const o = Object.assign({
      title: title, width: 920, height: 260,
      scales: { x: { time: false } },
      axes: [{ label: xLabel }, { label: yLabel }],
      series: [{ label: xLabel }].concat(series.map((s, i) => Object.assign({
        label: s.label, stroke: colour(i), width: 1.5, spanGaps: false,
      }, s.opts || {}))),
    }, opts || {});
    new uPlot(o, [xs].concat(series.map((s) => s.data)), el);
  }

  // Heading.
  const sum = document.getElementById("summary");
  sum.textContent = D.frames + " frames (" + D.error_frames + " error frames) from " + D.source +
    (D.timed ? ", " + fmt(D.duration_s, 3) + " s from " +
      new Date(D.start_s * 1000).toISOString() + "; bus load at " + (D.bitrate / 1000) +
      " kbit/s " + fmt(D.load_mean, 1) + " % mean, " + fmt(D.load_peak_1s, 1) +
      " % peak over 1 s windows (exact bit stuffing)" : ", without timestamps") +
    ". Time buckets of " + fmt(D.bucket_s * 1000, 1) + " ms. " + D.generator + ".";

  // Node table.
  const nodeRows = D.nodes.map((n) => {
    const tr = document.createElement("tr");
    cell(tr, n.id);
    cell(tr, n.name || "", "text");
    cell(tr, hex(n.identity[0], 8));
    cell(tr, hex(n.identity[1], 8));
    cell(tr, hex(n.identity[2], 8));
    cell(tr, n.identity[3] === null ? "-" : String(n.identity[3]));
    cell(tr, n.state || "-", "text");
    cell(tr, n.hb.n ? fmt(n.hb.mean, 1) : "-");
    cell(tr, n.hb.n > 1 ? fmt(n.hb.jitter, 2) : "-");
    cell(tr, n.hb.n ? fmt(n.hb.min, 1) + " / " + fmt(n.hb.max, 1) : "-");
    cell(tr, n.guard[0] || n.guard[1] ? n.guard.join(" / ") : "-");
    cell(tr, n.emcy);
    cell(tr, n.last_emcy || "", "text");
    cell(tr, n.sdo.done + " / " + n.sdo.aborts + " / " + n.sdo.timeouts);
    cell(tr, fmt(n.sdo.mean_ms, 2) + " / " + fmt(n.sdo.max_ms, 2));
    cell(tr, fmt(n.tpdo_rate, 1));
    cell(tr, fmt(n.rpdo_rate, 1));
    cell(tr, n.latency.n ? fmt(n.latency.mean, 0) + " / " + fmt(n.latency.max, 0) : "-");
    if (n.last_emcy && !n.last_emcy.endsWith("(reset)")) tr.className = "error";
    return tr;
  });
  table("nodes", ["node", "device name (1008h)", "vendor", "product", "revision", "serial",
                  "NMT state", "HB period ms", "HB jitter ms", "HB min / max ms",
                  "guarding req / rep / unanswered / toggle err", "EMCY", "last EMCY",
                  "SDO done / aborts / timeouts", "SDO mean / max ms", "TPDO/s", "RPDO/s",
                  "SYNC→TPDO mean / max µs"], nodeRows);

  const t = D.t || [];
  // Bus load.
  chart("chart-load", "Bus load per " + fmt(D.bucket_s * 1000, 1) + " ms bucket", "s", "%", t,
        [{ label: "bus load %", data: D.load || [] }]);
  // Heartbeats.
  chart("chart-hb", "Heartbeat interval (mean per bucket)", "s", "ms", t,
        D.nodes.filter((n) => n.hb_series).map((n) => ({
          label: "node " + n.id, data: n.hb_series,
          opts: { spanGaps: true, points: { show: true, size: 5 } } })));
  // SYNC period histogram.
  const sh = D.sync_hist || { counts: [], bin_us: 0 };
  chart("chart-sync", "SYNC period (" + D.sync.n + " intervals, mean " + fmt(D.sync.mean, 1) +
        " µs, jitter " + fmt(D.sync.jitter, 1) + " µs, beyond the chart " + (sh.above || 0) + ")",
        "µs", "intervals", sh.counts.map((_, i) => (i + 0.5) * sh.bin_us),
        [{ label: "intervals", data: D.sync.n ? sh.counts : [],
           opts: { paths: uPlot.paths.bars({ size: [0.9, 40] }), fill: colour(0) + "88" } }]);
  // Histograms on logarithmic bins: SDO round trips and SYNC→TPDO latency.
  const logOpts = { scales: { x: { time: false, distr: 3 } } };
  const histSeries = (key) => D.nodes.filter((n) => n[key] && n[key].counts.some((c) => c > 0))
    .map((n) => ({ label: "node " + n.id, data: n[key].counts,
                   opts: { points: { show: true, size: 4 } } }));
  // Only the bins from the first to the last filled one (and two either side) are drawn.
  function trimmed(series) {
    const xs = D.log_bins_us || [];
    let lo = xs.length, hi = -1;
    for (const s of series) {
      s.data.forEach((c, i) => { if (c > 0) { lo = Math.min(lo, i); hi = Math.max(hi, i); } });
    }
    if (hi < 0) return { xs: xs, series: series };
    lo = Math.max(0, lo - 2);
    hi = Math.min(xs.length - 1, hi + 2);
    return { xs: xs.slice(lo, hi + 1),
             series: series.map((s) => Object.assign({}, s, { data: s.data.slice(lo, hi + 1) })) };
  }
  const sdo = trimmed(histSeries("sdo_hist"));
  chart("chart-sdo", "SDO round-trip time (request to the response that completes it)", "µs",
        "transfers", sdo.xs, sdo.series, logOpts);
  const lat = trimmed(histSeries("latency_hist"));
  chart("chart-latency", "SYNC → TPDO latency", "µs", "TPDOs", lat.xs, lat.series, logOpts);
  // PDO rates.
  const pdo = [];
  for (const n of D.nodes) {
    if (!n.tpdo_series) continue;
    if (n.tpdo) pdo.push({ label: "node " + n.id + " TPDO/s", data: n.tpdo_series });
    if (n.rpdo) pdo.push({ label: "node " + n.id + " RPDO/s", data: n.rpdo_series });
  }
  chart("chart-pdo", "PDO rate per node", "s", "PDOs/s", t, pdo);
  // EMCY and anomalies over time.
  chart("chart-events", "EMCY and anomalies (warnings, errors) per bucket", "s", "count", t,
        [{ label: "EMCY", data: D.emcy || [],
           opts: { paths: uPlot.paths.bars({ size: [0.9, 12] }), fill: colour(1) + "aa" } },
         { label: "anomalies", data: D.anomalies || [],
           opts: { paths: uPlot.paths.bars({ size: [0.9, 12] }), fill: colour(3) + "aa" } }]);
  const eventRows = (D.events || []).map((e) => {
    const tr = document.createElement("tr");
    tr.className = e.severity;
    cell(tr, fmt(e.t, 6));
    cell(tr, e.node || "-");
    cell(tr, e.emcy ? "EMCY" : e.severity, "text");
    cell(tr, e.service, "text");
    cell(tr, e.text, "text");
    return tr;
  });
  table("events", ["s", "node", "kind", "service", "decoded text"], eventRows);
  if ((D.events_total || 0) > eventRows.length) {
    document.getElementById("events-more").textContent = "The first " + eventRows.length +
      " of " + D.events_total + " events are listed; the chart counts all of them.";
  }
  document.getElementById("codrive-check").textContent = JSON.stringify(check);
})();
