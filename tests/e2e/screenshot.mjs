// Opens the display page in headless chromium for a while and saves a
// screenshot: for looking at a running system by hand, e.g.
//   node tests/e2e/screenshot.mjs --url http://127.0.0.1:8080/ --seconds 20 --out display.png
import { mkdtempSync, rmSync } from 'node:fs';
import { tmpdir } from 'node:os';
import path from 'node:path';
import { parseArgs } from 'node:util';
import { chromium } from 'playwright-core';

const { values: opt } = parseArgs({
  options: {
    url: { type: 'string', default: 'http://127.0.0.1:8080/' },
    seconds: { type: 'string', default: '10' },
    out: { type: 'string', default: 'display.png' },
    truth: { type: 'boolean', default: false },
  },
});
const userDir = mkdtempSync(path.join(tmpdir(), 'ephor-shot-'));
const ctx = await chromium.launchPersistentContext(userDir, {
  executablePath: '/usr/bin/chromium',
  headless: true,
  viewport: { width: 1280, height: 1000 },
  args: ['--headless', '--no-sandbox', '--disable-gpu', '--disable-quic', '--no-first-run',
    '--disable-background-networking', '--disable-component-update', '--disable-sync'],
});
try {
  const page = ctx.pages()[0] || await ctx.newPage();
  await page.goto(opt.url);
  if (opt.truth) await page.check('#layer-truth');
  await page.waitForTimeout(Number(opt.seconds) * 1000);
  const d = await page.evaluate(() => ({ u: window.ephorDisplay.updatesPerS, i: window.ephorDisplay.imagesPerS,
    n: window.ephorDisplay.updates }));
  console.log(`updates/s ${d.u}, images/s ${d.i}, updates ${d.n}`);
  await page.screenshot({ path: opt.out, fullPage: true });
  console.log('saved ' + opt.out);
} finally {
  await ctx.close();
  rmSync(userDir, { recursive: true, force: true });
}
