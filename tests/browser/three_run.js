#!/usr/bin/env node
// Drives tests/browser/three.html in Debian's headless Chromium with playwright-core (never
// downloads a browser). Used by scripts/render_three.py, which serves the page, three.js and
// the models on 127.0.0.1.
//   node three_run.js PAGE_URL JOB.json
// JOB.json: {"size": S, "views": V, "elevation": DEG,
//            "items": [{"url": URL, "node": K or -1, "out": FILE.rgba, "frame": URL (optional),
//                       "seams": FILE.rgba (optional), "variant": NAME (optional: a
//                       KHR_materials_variants variant selected)}, ...]}
// Renders the items in order; an item with "frame" first frames the cameras on that file (the
// first item must have one). Writes each item's V views to "out" as raw RGBA (V images of
// S x S pixels, rows top-down, RGB premultiplied by alpha), and with "seams" the V seam masks
// there (three_view.js). Prints one JSON line per item:
// {"index", "ok", "errors", "console"}; a failed framing fails that item.
// Exit codes: 0 every item was attempted, 2 the browser or the page failed.
'use strict';
const fs = require('fs');
const { chromium } = require('playwright-core');

(async () => {
  const [url, jobFile] = process.argv.slice(2);
  if (!url || !jobFile) { console.error('usage: three_run.js PAGE_URL JOB.json'); process.exit(2); }
  const job = JSON.parse(fs.readFileSync(jobFile, 'utf8'));
  const browser = await chromium.launch({
    executablePath: process.env.CHROMIUM || '/usr/bin/chromium',
    args: ['--headless', '--no-sandbox', '--disable-gpu', '--use-angle=swiftshader', '--enable-unsafe-swiftshader',
           '--disable-quic', '--no-first-run', '--disable-background-networking', '--disable-component-update',
           '--disable-sync'],
  });
  try {
    const page = await browser.newPage({ viewport: { width: job.size, height: job.size } });
    let logs = [];
    page.on('console', (m) => { if (m.type() === 'error' || m.type() === 'warning') logs.push(m.type() + ': ' + m.text()); });
    page.on('pageerror', (e) => logs.push('pageerror: ' + e.message));
    await page.goto(url);
    await page.waitForFunction(() => window.lodbakeThreeReady === true, null, { timeout: 60000 });
    const setup = await page.evaluate((size) => window.lodbakeSetup({ size }), job.size);
    if (!setup.ok) throw new Error('setup failed: ' + JSON.stringify(setup.errors) + ' ' + JSON.stringify(logs));
    let framed = { ok: false, errors: ['no framing item'] };
    for (let i = 0; i < job.items.length; ++i) {
      const item = job.items[i];
      logs = [];
      if (item.frame) framed = await page.evaluate((u) => window.lodbakeFrame(u), item.frame);
      const r = framed.ok ? await page.evaluate(([u, n, v, e, s, m]) => window.lodbakeRender(u, n, v, e, s, m),
                                                [item.url, item.node, job.views, job.elevation, !!item.seams,
                                                 item.variant === undefined ? null : item.variant])
                          : { ok: false, errors: ['framing failed: '].concat(framed.errors) };
      if (r.ok) {
        const bytes = Buffer.concat(r.views.map((b) => Buffer.from(b, 'base64')));
        fs.writeFileSync(item.out, bytes);
        if (item.seams) fs.writeFileSync(item.seams, Buffer.concat(r.seams.map((b) => Buffer.from(b, 'base64'))));
      }
      console.log(JSON.stringify({ index: i, ok: r.ok, errors: r.errors, console: logs.slice(0, 20), revision: setup.revision }));
    }
  } catch (e) {
    console.error(String(e && e.stack || e));
    process.exitCode = 2;
  } finally {
    await browser.close();
  }
})();
