// The watch page (tools/report/watch.py) in headless Chromium: no console errors or network requests, both
// motions in the picker, their height figures load, the WebGL canvas is drawn, the slider changes the pose,
// player.js's FK matches the numpy FK at the first, middle and last sample of each motion, and the fall is
// seen: the fall record's root link ends far lower than it began.
//
//   node watch_page_test.mjs PAGE/index.html EXPECTED_FK.json SCREENSHOT_DIR
import fs from 'node:fs';
import path from 'node:path';
import { canvasSnapshot, checkList, imageWidths, openChromium, openPlayerPage, pickTrial, slideToMiddle,
         worstFkDifference } from './browser_checks.mjs';

const [page_path, expected_path, shots] = process.argv.slice(2);
const expected = JSON.parse(fs.readFileSync(expected_path, 'utf8'));
const motions = Object.keys(expected.frames);
const fall = motions.find((id) => id.endsWith('_fall'));
fs.mkdirSync(shots, { recursive: true });
const { check, finish } = checkList('watch_page_test');
const chromium = await openChromium('watch');
try {
  const { page, errors } = await openPlayerPage(chromium, page_path);

  const listed = await page.$$eval('#trial option', (options) => options.map((option) => option.value));
  check(JSON.stringify(listed) === JSON.stringify(motions), `the picker lists the motions (${listed.join(', ')})`);
  const images = await imageWidths(page);
  const broken = images.filter((image) => image.width === 0).map((image) => image.src);
  check(images.length === motions.length && broken.length === 0,
        `${images.length} height figures load${broken.length ? ': broken ' + broken.join(', ') : ''}`);

  await pickTrial(page, fall);
  const first = await canvasSnapshot(page);
  check(first.drawn / first.pixels > 0.01, `the WebGL canvas is not blank (${(100 * first.drawn / first.pixels).toFixed(1)} % drawn)`);
  const { frame: middle, moved, changed } = await slideToMiddle(page);
  check(middle > 0 && moved > 0.02 && changed > 200,
        `the slider moves ${fall} to frame ${middle}, its pose (a link moved ${(100 * moved).toFixed(1)} cm against the root) and the drawing (${changed} pixels)`);

  // The fall as the player draws it: the root link at the last sample against the first.
  const rootHeight = (k) => page.evaluate((frame) => { synPlayer.setFrame(frame); return synPlayer.linkPositions()[0][2]; }, k);
  const last = await page.evaluate(() => synPlayer.frameCount() - 1);
  const [start, end] = [await rootHeight(0), await rootHeight(last)];
  check(end < 0.8 * start, `the player shows ${fall} falling: root ${start.toFixed(3)} m -> ${end.toFixed(3)} m`);
  await page.locator('#player').screenshot({ path: path.join(shots, 'watch_fall_end.png') });

  const worst = await worstFkDifference(page, expected.frames);
  // q travels as float32 to the page: about 1e-7 rad per joint, amplified by ~1 m of lever arms.
  check(worst < 1e-4, `player.js FK matches the numpy FK on ${motions.length} motions (worst ${worst.toExponential(2)} m)`);
  await page.screenshot({ path: path.join(shots, 'watch_page.png') });
  check(errors.length === 0, `no console errors or network requests${errors.length ? ': ' + errors.join(' | ') : ''}`);
} finally {
  await chromium.close();
}
finish(`screenshots in ${shots}`);
