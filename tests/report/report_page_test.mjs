// The report page in headless Chromium (driven by playwright-core from tools/report/node_modules):
// no console errors, every figure image loads, the WebGL canvas is not blank, moving the slider changes the
// drawn pose, and player.js's FK matches the numpy FK (which check_fk.py checked against syn-retarget).
//
//   node report_page_test.mjs REPORT_DIR/index.html EXPECTED_FK.json SCREENSHOT_DIR
import { createRequire } from 'node:module';
import fs from 'node:fs';
import os from 'node:os';
import path from 'node:path';
import { pathToFileURL, fileURLToPath } from 'node:url';

const here = path.dirname(fileURLToPath(import.meta.url));
const require = createRequire(path.join(here, '..', '..', 'tools', 'report', 'package.json'));
const { chromium } = require('playwright-core');

const [page_path, expected_path, shots] = process.argv.slice(2);
const expected = JSON.parse(fs.readFileSync(expected_path, 'utf8'));
fs.mkdirSync(shots, { recursive: true });
const failures = [];
const started = Date.now();
const check = (ok, what) => {
  console.log(`${ok ? 'ok  ' : 'FAIL'} ${what} [${((Date.now() - started) / 1000).toFixed(1)} s]`);
  if (!ok) failures.push(what);
};

const profile = fs.mkdtempSync(path.join(os.tmpdir(), 'synsculpt-chromium-'));
// A fresh profile (playwright passes it as --user-data-dir).
const browser = await chromium.launchPersistentContext(profile, {
  executablePath: process.env.CHROMIUM || '/usr/bin/chromium',
  viewport: { width: 1280, height: 900 },
  args: ['--headless', '--no-sandbox', '--disable-gpu', '--disable-quic', '--no-first-run',
         '--disable-background-networking', '--disable-component-update', '--disable-sync',
         // No GPU here: WebGL through SwiftShader, Chromium's CPU renderer.
         '--use-angle=swiftshader', '--enable-unsafe-swiftshader'],
});
try {
  const page = await browser.newPage();
  const errors = [];
  page.on('console', (message) => { if (message.type() === 'error') errors.push(message.text()); });
  page.on('pageerror', (error) => errors.push(String(error)));
  page.on('requestfailed', (request) => errors.push(`request failed: ${request.url()}`));
  page.on('request', (request) => {
    if (!request.url().startsWith('file:') && !request.url().startsWith('data:')) errors.push(`network request: ${request.url()}`);
  });
  await page.goto(pathToFileURL(path.resolve(page_path)).href, { waitUntil: 'load' });
  await page.waitForFunction(() => window.SynReport && SynReport.ready() && synPlayer.frameCount() > 0,
                             null, { timeout: 30000 });

  const images = await page.$$eval('img', (all) => Promise.all(all.map((img) => img.decode().then(
    () => ({ src: img.getAttribute('src'), width: img.naturalWidth }),
    () => ({ src: img.getAttribute('src'), width: 0 })))));
  const broken = images.filter((image) => image.width === 0).map((image) => image.src);
  check(images.length > 0 && broken.length === 0, `${images.length} figure images load${broken.length ? ': broken ' + broken.join(', ') : ''}`);

  // The canvas's pixels, compared in the page (moving megabytes through the DevTools protocol takes a minute):
  // how many differ from the background, and from the previous snapshot.
  const snapshot = () => page.evaluate(() => {
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
  const webgl = await page.evaluate(() => !!synPlayer.canvas.getContext('webgl2') || !!synPlayer.canvas.getContext('webgl'));
  check(webgl, 'the player has a WebGL context');
  const first = await snapshot();
  const share = first.drawn / first.pixels;
  check(share > 0.01, `the WebGL canvas is not blank (${(100 * share).toFixed(1)} % of its pixels drawn)`);

  await page.locator('#player').screenshot({ path: path.join(shots, 'player_frame_a.png') });
  await page.screenshot({ path: path.join(shots, 'report_page.png') });
  await page.locator('#figures').scrollIntoViewIfNeeded();
  await page.screenshot({ path: path.join(shots, 'report_figures.png') });

  const poseBefore = await page.evaluate(() => synPlayer.linkPositions());
  // The slider to the middle, as a user drags it (input event).
  const middle = await page.evaluate(() => {
    const slider = document.getElementById('slider');
    slider.value = String(Math.floor(Number(slider.max) / 2));
    slider.dispatchEvent(new Event('input'));
    return Number(slider.value);
  });
  check(middle > 0 && (await page.evaluate(() => synPlayer.frame())) === middle, `the slider moves the player to frame ${middle}`);
  const { changed } = await snapshot();
  // The pose itself, not just the camera following the pelvis: links relative to the root moved.
  const poseAfter = await page.evaluate(() => synPlayer.linkPositions());
  let moved = 0;
  poseAfter.forEach((p, i) => p.forEach((v, c) => {
    moved = Math.max(moved, Math.abs((v - poseAfter[0][c]) - (poseBefore[i][c] - poseBefore[0][c])));
  }));
  check(moved > 0.05, `the slider changes the pose relative to the pelvis (a link moved ${(100 * moved).toFixed(1)} cm)`);
  check(changed > 200, `moving the slider changes the drawn pose (${changed} pixels differ)`);
  await page.locator('#player').screenshot({ path: path.join(shots, 'player_frame_b.png') });
  const shotA = fs.readFileSync(path.join(shots, 'player_frame_a.png'));
  const shotB = fs.readFileSync(path.join(shots, 'player_frame_b.png'));
  check(!shotA.equals(shotB), 'the two player screenshots differ');

  // Play advances time; a worst-frame button shows its trial at its moment.
  const playedFrom = await page.evaluate(() => synPlayer.frame());
  await page.click('#play');
  await page.waitForTimeout(700);
  await page.click('#play');
  const playedTo = await page.evaluate(() => synPlayer.frame());
  check(playedTo !== playedFrom, `play advances the motion (frame ${playedFrom} -> ${playedTo})`);
  const button = page.locator('article button.play[data-time]:not([data-time="0"])').last();
  const wanted = { trial: await button.getAttribute('data-trial'), time: Number(await button.getAttribute('data-time')) };
  await button.click();
  await page.waitForFunction((id) => SynReport.current() === id, wanted.trial);
  const shown = await page.evaluate(() => Number(document.getElementById('clock').textContent.split(' ')[0]));
  check(Math.abs(shown - wanted.time) < 0.05, `a worst-frame button shows ${wanted.trial} at ${wanted.time} s (clock ${shown} s)`);

  // player.js FK against the numpy FK at two frames of every trial.
  let worst = 0;
  for (const [trial, frames] of Object.entries(expected.frames)) {
    await page.evaluate((id) => { document.getElementById('trial').value = id; document.getElementById('trial').onchange(); }, trial);
    await page.waitForFunction((id) => SynReport.current() === id, trial);
    for (const [frame, positions] of Object.entries(frames)) {
      const got = await page.evaluate((k) => { synPlayer.setFrame(k); return synPlayer.linkPositions(); }, Number(frame));
      positions.forEach((p, i) => p.forEach((v, c) => { worst = Math.max(worst, Math.abs(v - got[i][c])); }));
    }
  }
  // q travels as float32 to the page: about 1e-7 rad per joint, amplified by ~1 m of lever arms.
  check(worst < 1e-4, `player.js FK matches the numpy FK on ${Object.keys(expected.frames).length} trials (worst ${worst.toExponential(2)} m)`);

  check(errors.length === 0, `no console errors or network requests${errors.length ? ': ' + errors.join(' | ') : ''}`);
} finally {
  await browser.close();
  fs.rmSync(profile, { recursive: true, force: true });
}
if (failures.length) {
  console.log(`report_page_test: ${failures.length} check(s) failed`);
  process.exit(1);
}
console.log(`report_page_test: all checks passed; screenshots in ${shots}`);
