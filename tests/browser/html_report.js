#!/usr/bin/env node
// Opens an HTML report of `lodbake --html` / `compare --html` from its file (file://, no server)
// in Debian's headless Chromium with playwright-core and prints what the page shows as JSON:
// per level section its view and page images (decoded by the browser: natural sizes), every
// figure cell (JSON pointer, exact value, shown text) and the warnings; takes a full-page screenshot.
//   node html_report.js REPORT.html SCREENSHOT.png
// Exit codes: 0 the page was read, 2 the browser or page failed.
'use strict';
const path = require('path');
const { chromium } = require('playwright-core');

(async () => {
  const [file, shot] = process.argv.slice(2);
  if (!file || !shot) { console.error('usage: html_report.js REPORT.html SCREENSHOT.png'); process.exit(2); }
  const browser = await chromium.launch({
    executablePath: process.env.CHROMIUM || '/usr/bin/chromium',
    args: ['--headless', '--no-sandbox', '--disable-gpu', '--disable-background-networking',
           '--disable-component-update', '--disable-sync', '--no-first-run'],
  });
  try {
    const page = await browser.newPage({ viewport: { width: 1280, height: 900 } });
    const errors = [];
    page.on('pageerror', (e) => errors.push(e.message));
    // Any request that is not the file itself or a data: URI would mean the page is not self-contained.
    const requests = [];
    page.on('request', (r) => { if (!r.url().startsWith('data:')) requests.push(r.url()); });
    await page.goto('file://' + path.resolve(file), { waitUntil: 'load' });
    const result = await page.evaluate(() => {
      const images = (root, cls) => Array.from(root.querySelectorAll('img.' + cls)).map((i) => ({
        alt: i.alt, complete: i.complete, width: i.naturalWidth, height: i.naturalHeight }));
      return {
        title: document.title,
        levels: Array.from(document.querySelectorAll('section.level')).map((s) => ({
          id: s.id, title: s.querySelector('h2').textContent, views: images(s, 'view'), pages: images(s, 'page') })),
        images: document.querySelectorAll('img').length,
        figures: Array.from(document.querySelectorAll('[data-pointer]')).map((e) => ({
          pointer: e.dataset.pointer, value: e.dataset.value === undefined ? null : JSON.parse(e.dataset.value),
          text: e.textContent })),
        warnings: Array.from(document.querySelectorAll('#warnings li')).map((e) => e.textContent),
        scripts: document.querySelectorAll('script').length,
      };
    });
    await page.screenshot({ path: shot, fullPage: true });
    result.pageErrors = errors;
    result.requests = requests;
    console.log(JSON.stringify(result));
  } catch (e) {
    console.error(String(e && e.stack || e));
    process.exitCode = 2;
  } finally {
    await browser.close();
  }
})();
