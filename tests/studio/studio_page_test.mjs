// syn-studio's page in headless Chromium (playwright-core from tools/report/node_modules): it loads with no
// console error, composes, moving one coefficient slider recomposes and changes both the drawn pose (the
// player's link positions across the slider's step) and the momentum plot, and "save script" downloads the script
// that was composed. Writes the page's q and the saved script for studio_page_test.sh to compose in batch.
//
//   node studio_page_test.mjs URL OUT_DIR
import fs from 'node:fs';
import path from 'node:path';
import { checkList, collectErrors, openChromium } from '../report/browser_checks.mjs';

const [url, out] = process.argv.slice(2);
fs.mkdirSync(out, { recursive: true });
const { check, finish } = checkList('studio_page_test');
const chromium = await openChromium('studio', { viewport: { width: 1400, height: 900 }, acceptDownloads: true });
try {
  const page = await chromium.browser.newPage();
  const errors = collectErrors(page);
  await page.goto(url, { waitUntil: 'load' });
  await page.waitForFunction(() => window.studio && studio.composeCount > 0, null, { timeout: 30000 });
  check(await page.evaluate(() => studio.lastResult !== null), 'the page composed its first script');

  // The drawn poses at fixed instants, the momentum plot's pixels and the composed q, before and after a slider
  // move. The instants span the first step, the one whose slider moves: later steps start from wherever it
  // ends, so how far a gain on it carries into them depends on the library, not on the page; and at any one
  // instant the coefficient it scales may be passing through zero.
  const snapshot = () => page.evaluate(() => {
    studio.player.pause();
    const first = studio.lastResult.steps[0], poses = [];
    for (let k = 0; k <= 10; ++k) {
      studio.player.setTime(first.start_s + (first.end_s - first.start_s) * k / 10);
      poses.push(studio.player.linkPositions());
    }
    return { poses, plot: document.getElementById('plot-momentum').toDataURL(),
             count: studio.composeCount, frames: studio.lastResult.time.length };
  });
  const before = await snapshot();
  await page.screenshot({ path: path.join(out, 'before.png') });
  const slider = page.locator('input[data-test="gain-0-0-0"]');
  check(await slider.count() === 1, 'the first step has a slider for its first coefficient');
  await slider.evaluate((input) => { input.value = '1.8'; input.dispatchEvent(new Event('input')); });
  await page.waitForFunction((count) => studio.composeCount > count && document.getElementById('status')
    .textContent.startsWith('composed'), before.count, { timeout: 30000 });
  const after = await snapshot();
  await page.screenshot({ path: path.join(out, 'after.png') });
  let moved = 0;
  before.poses.forEach((links, k) => links.forEach((p, i) => {
    const q = after.poses[k][i];
    moved = Math.max(moved, Math.hypot(p[0] - q[0], p[1] - q[1], p[2] - q[2]));
  }));
  check(moved > 0.01, `moving a1/σ1 to 1.8 moves the drawn robot during its step (largest link move ${moved.toFixed(3)} m)`);
  check(before.plot !== after.plot, 'the momentum plot changed');
  check(await page.evaluate(() => studio.state.steps[0].keyframes[0].gain[0] === 1.8), 'the script holds gain 1.8');

  // Joint-limit warnings on the step that causes them (the dance phrase's steps hit G1's limits).
  const placed = await page.evaluate(() => studio.lastResult.warnings.map((w) => {
    const item = document.querySelector(`#steps li[data-step="${w.step}"]`);
    return item !== null && item.classList.contains('warned') && item.querySelector('.warning').textContent.includes(w.message);
  }));
  check(placed.length > 0 && placed.every((ok) => ok), `each of the ${placed.length} joint-limit warnings is shown on its step`);

  // Reorder (step 1 down) and delete (the last step): each recomposes.
  const recomposed = async (action) => {
    const count = await page.evaluate(() => studio.composeCount);
    await action();
    await page.waitForFunction((c) => studio.composeCount > c && document.getElementById('status').textContent
      .startsWith('composed'), count, { timeout: 30000 });
  };
  const order = await page.evaluate(() => studio.state.steps.map((s) => s.synergy));
  await recomposed(() => page.click('#steps li[data-step="0"] button[title="move down"]'));
  const reordered = await page.evaluate(() => studio.lastResult.steps.map((s) => s.synergy));
  check(reordered[0] === order[1] && reordered[1] === order[0], `moving step 1 down swaps it with step 2 (${reordered.join(', ')})`);
  await recomposed(() => page.click(`#steps li[data-step="${order.length - 1}"] button[title="delete"]`));
  check(await page.evaluate(() => studio.lastResult.steps.length) === order.length - 1, 'deleting the last step composes one step fewer');

  const [download] = await Promise.all([page.waitForEvent('download'), page.click('#save')]);
  const saved = path.join(out, 'saved.toml');
  await download.saveAs(saved);
  const text = fs.readFileSync(saved, 'utf8');
  check(text === await page.evaluate(() => studio.lastText), 'the saved script is the text last composed');
  // Loading the saved file gives the same script and the same motion.
  const savedQ = await page.evaluate(() => JSON.stringify(studio.lastResult.q));
  await recomposed(() => page.setInputFiles('#load', saved));
  check(await page.evaluate(() => studio.scriptText()) === text, 'loading the saved script gives back the same script');
  check(await page.evaluate(() => JSON.stringify(studio.lastResult.q)) === savedQ, 'and the same motion');
  fs.writeFileSync(path.join(out, 'page_motion.json'),
                   JSON.stringify(await page.evaluate(() => ({ time: studio.lastResult.time, q: studio.lastResult.q }))));
  check(errors.length === 0, `no console errors${errors.length ? ': ' + errors.join(' | ') : ''}`);
} finally {
  await chromium.close();
}
finish(`files in ${out}`);
