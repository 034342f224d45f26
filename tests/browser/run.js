#!/usr/bin/env node
// Drives tests/browser/index.html in Debian's headless Chromium with playwright-core.
//   node run.js URL SCREENSHOT.png   -> prints the page's result JSON on stdout
// Exit codes: 0 the page reported a result, 2 the browser or page failed.
'use strict';
const { chromium } = require('playwright-core');

(async () => {
  const [url, shot] = process.argv.slice(2);
  if (!url || !shot) { console.error('usage: run.js URL SCREENSHOT.png'); process.exit(2); }
  const browser = await chromium.launch({
    executablePath: process.env.CHROMIUM || '/usr/bin/chromium',
    args: ['--headless', '--no-sandbox', '--disable-gpu', '--use-angle=swiftshader', '--enable-unsafe-swiftshader',
           '--disable-background-networking', '--disable-component-update', '--disable-sync', '--no-first-run'],
  });
  let page;
  try {
    page = await browser.newPage({ viewport: { width: 512, height: 512 } });
    const logs = [];
    page.on('console', (m) => logs.push(m.type() + ': ' + m.text()));
    page.on('pageerror', (e) => logs.push('pageerror: ' + e.message));
    await page.goto(url);
    await page.waitForFunction(() => window.lodbakeResult !== undefined, null, { timeout: 240000 });
    const result = await page.evaluate(() => window.lodbakeResult);
    await page.screenshot({ path: shot });
    result.console = logs.slice(0, 30);
    console.log(JSON.stringify(result));
  } catch (e) {
    const where = page ? await page.evaluate(() => window.lodbakeStage).catch(() => undefined) : undefined;
    console.error(String(e && e.stack || e) + (where ? ' (page stage: ' + where + ')' : ''));
    process.exitCode = 2;
  } finally {
    await browser.close();
  }
})();
