// What the browser tests of the report, the watch page and the studio share: headless Chromium through
// playwright-core (tools/report/node_modules), a check list that prints as it goes, the page's errors, the
// player canvas's drawn pixels, and player.js's FK against the numpy FK.
import { createRequire } from 'node:module';
import fs from 'node:fs';
import os from 'node:os';
import path from 'node:path';
import { fileURLToPath, pathToFileURL } from 'node:url';

const here = path.dirname(fileURLToPath(import.meta.url));
const require = createRequire(path.join(here, '..', '..', 'tools', 'report', 'package.json'));
const { chromium } = require('playwright-core');

// A fresh profile (playwright passes it as --user-data-dir), removed by close().
export async function openChromium(name, contextOptions = {}) {
  const profile = fs.mkdtempSync(path.join(os.tmpdir(), `synsculpt-${name}-chromium-`));
  const browser = await chromium.launchPersistentContext(profile, {
    executablePath: process.env.CHROMIUM || '/usr/bin/chromium',
    viewport: { width: 1280, height: 900 },
    ...contextOptions,
    args: ['--headless', '--no-sandbox', '--disable-gpu', '--disable-quic', '--no-first-run',
           '--disable-background-networking', '--disable-component-update', '--disable-sync',
           // No GPU here: WebGL through SwiftShader, Chromium's CPU renderer.
           '--use-angle=swiftshader', '--enable-unsafe-swiftshader'],
  });
  return {
    browser,
    close: async () => {
      await browser.close();
      fs.rmSync(profile, { recursive: true, force: true });
    },
  };
}

// A page with the 3-D player (the report's, the watch page) opened from file:// in a new tab, once its
// first motion is shown. Returns the tab and its error list (collectErrors, offline).
export async function openPlayerPage(chromium, pagePath) {
  const page = await chromium.browser.newPage();
  const errors = collectErrors(page, { offline: true });
  await page.goto(pathToFileURL(path.resolve(pagePath)).href, { waitUntil: 'load' });
  await page.waitForFunction(() => window.SynReport && SynReport.ready() && synPlayer.frameCount() > 0,
                             null, { timeout: 30000 });
  return { page, errors };
}

// check(ok, what) prints each check with the seconds since start; finish() exits 1 if any failed.
export function checkList(testName) {
  const failures = [];
  const started = Date.now();
  return {
    check: (ok, what) => {
      console.log(`${ok ? 'ok  ' : 'FAIL'} ${what} [${((Date.now() - started) / 1000).toFixed(1)} s]`);
      if (!ok) failures.push(what);
    },
    finish: (success) => {
      if (failures.length) {
        console.log(`${testName}: ${failures.length} check(s) failed`);
        process.exit(1);
      }
      console.log(`${testName}: all checks passed; ${success}`);
    },
  };
}

// The page's console errors, uncaught exceptions and failed requests; with `offline`, any request that is
// not file: or data: too (the report and watch pages must work without a network).
export function collectErrors(page, { offline = false } = {}) {
  const errors = [];
  page.on('console', (message) => { if (message.type() === 'error') errors.push(message.text()); });
  page.on('pageerror', (error) => errors.push(String(error)));
  page.on('requestfailed', (request) => errors.push(`request failed: ${request.url()}`));
  if (offline) {
    page.on('request', (request) => {
      if (!request.url().startsWith('file:') && !request.url().startsWith('data:')) errors.push(`network request: ${request.url()}`);
    });
  }
  return errors;
}

// The player canvas's pixels, compared in the page (moving megabytes through the DevTools protocol takes a
// minute): how many differ from the background, and from the previous snapshot.
export function canvasSnapshot(page) {
  return page.evaluate(() => {
    const source = synPlayer.canvas, canvas = document.createElement('canvas');
    canvas.width = source.width; canvas.height = source.height;
    const context = canvas.getContext('2d');
    context.drawImage(source, 0, 0);
    const data = context.getImageData(0, 0, canvas.width, canvas.height).data, previous = window.previousPixels;
    let drawn = 0, changed = 0;
    for (let i = 0; i < data.length; i += 4) {
      if (Math.abs(data[i] - 0xf4) + Math.abs(data[i + 1] - 0xf5) + Math.abs(data[i + 2] - 0xf7) > 30) drawn++;
      if (previous && Math.abs(data[i] - previous[i]) + Math.abs(data[i + 1] - previous[i + 1]) +
          Math.abs(data[i + 2] - previous[i + 2]) > 30) changed++;
    }
    window.previousPixels = data;
    return { pixels: data.length / 4, drawn, changed };
  });
}

// The slider to the middle, as a user drags it (input event). Returns the player's frame then, how far
// (m) a link moved relative to the root link (the pose itself, not just the camera following the pelvis),
// and how many canvas pixels changed.
export async function slideToMiddle(page) {
  await canvasSnapshot(page);
  const poseBefore = await page.evaluate(() => synPlayer.linkPositions());
  const frame = await page.evaluate(() => {
    const slider = document.getElementById('slider');
    slider.value = String(Math.floor(Number(slider.max) / 2));
    slider.dispatchEvent(new Event('input'));
    return Number(slider.value);
  });
  const { changed } = await canvasSnapshot(page);
  const poseAfter = await page.evaluate(() => synPlayer.linkPositions());
  let moved = 0;
  poseAfter.forEach((p, i) => p.forEach((v, c) => {
    moved = Math.max(moved, Math.abs((v - poseAfter[0][c]) - (poseBefore[i][c] - poseBefore[0][c])));
  }));
  return { frame, moved, changed };
}

// Shows a trial through the page's picker, as a user would.
export async function pickTrial(page, trial) {
  await page.evaluate((id) => { document.getElementById('trial').value = id; document.getElementById('trial').onchange(); }, trial);
  await page.waitForFunction((id) => SynReport.current() === id, trial);
}

// The largest difference (m) between player.js's link positions and `expected`: {trial: {player frame:
// [[x, y, z] per link]}}, each trial shown through the picker.
export async function worstFkDifference(page, expected) {
  let worst = 0;
  for (const [trial, frames] of Object.entries(expected)) {
    await pickTrial(page, trial);
    for (const [frame, positions] of Object.entries(frames)) {
      const got = await page.evaluate((k) => { synPlayer.setFrame(k); return synPlayer.linkPositions(); }, Number(frame));
      positions.forEach((p, i) => p.forEach((v, c) => { worst = Math.max(worst, Math.abs(v - got[i][c])); }));
    }
  }
  return worst;
}

// Every <img> on the page decoded: [{src, width}], width 0 for a broken one.
export function imageWidths(page) {
  return page.$$eval('img', (all) => Promise.all(all.map((img) => img.decode().then(
    () => ({ src: img.getAttribute('src'), width: img.naturalWidth }),
    () => ({ src: img.getAttribute('src'), width: 0 })))));
}
