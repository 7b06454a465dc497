// The report page in headless Chromium (driven by playwright-core from tools/report/node_modules):
// no console errors, every figure image loads, the WebGL canvas is not blank, moving the slider changes the
// drawn pose, and player.js's FK matches the numpy FK (which check_fk.py checked against syn-retarget).
//
//   node report_page_test.mjs REPORT_DIR/index.html EXPECTED_FK.json SCREENSHOT_DIR
import fs from 'node:fs';
import path from 'node:path';
import { canvasSnapshot, checkList, imageWidths, openChromium, openPlayerPage, slideToMiddle, worstFkDifference } from './browser_checks.mjs';

const [page_path, expected_path, shots] = process.argv.slice(2);
const expected = JSON.parse(fs.readFileSync(expected_path, 'utf8'));
fs.mkdirSync(shots, { recursive: true });
const { check, finish } = checkList('report_page_test');
const chromium = await openChromium('report');
try {
  const { page, errors } = await openPlayerPage(chromium, page_path);

  const images = await imageWidths(page);
  const broken = images.filter((image) => image.width === 0).map((image) => image.src);
  check(images.length > 0 && broken.length === 0, `${images.length} figure images load${broken.length ? ': broken ' + broken.join(', ') : ''}`);

  const webgl = await page.evaluate(() => !!synPlayer.canvas.getContext('webgl2') || !!synPlayer.canvas.getContext('webgl'));
  check(webgl, 'the player has a WebGL context');
  const first = await canvasSnapshot(page);
  const share = first.drawn / first.pixels;
  check(share > 0.01, `the WebGL canvas is not blank (${(100 * share).toFixed(1)} % of its pixels drawn)`);

  await page.locator('#player').screenshot({ path: path.join(shots, 'player_frame_a.png') });
  await page.screenshot({ path: path.join(shots, 'report_page.png') });
  await page.locator('#figures').scrollIntoViewIfNeeded();
  await page.screenshot({ path: path.join(shots, 'report_figures.png') });

  const { frame: middle, moved, changed } = await slideToMiddle(page);
  check(middle > 0 && (await page.evaluate(() => synPlayer.frame())) === middle, `the slider moves the player to frame ${middle}`);
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
  const worst = await worstFkDifference(page, expected.frames);
  // q travels as float32 to the page: about 1e-7 rad per joint, amplified by ~1 m of lever arms.
  check(worst < 1e-4, `player.js FK matches the numpy FK on ${Object.keys(expected.frames).length} trials (worst ${worst.toExponential(2)} m)`);

  check(errors.length === 0, `no console errors or network requests${errors.length ? ': ' + errors.join(' | ') : ''}`);
} finally {
  await chromium.close();
}
finish(`screenshots in ${shots}`);
