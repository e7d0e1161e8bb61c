// The page test (ctest viewer_page): builds pages with `mocap view` (and mocap-eval's report.html
// when the shared data is there), opens them in headless Chromium and looks at them as a person
// would: skeletons drawn in each clip's colour where expected, playing advances the frame counter,
// scrubbing moves it, and malformed BVH shows a readable error. Skips (exit 77) without Chromium.
//   node view_page_test.mjs --mocap PATH [--mocap-eval PATH] --out DIR [--testdata DIR]
//        [--data-cache DIR] [--shared-data DIR]
import { execFileSync, spawnSync } from 'node:child_process';
import { existsSync, mkdirSync, readdirSync, writeFileSync } from 'node:fs';
import { homedir } from 'node:os';
import { join } from 'node:path';
import { parseArgs } from 'node:util';
import { pathToFileURL } from 'node:url';
import { CLIP_COLOURS } from '../src/palette.js';
import { colourRegions, errorText, openPage, shownFrame, viewerState, BROWSER_ARGS } from './page_checks.mjs';
import { humanoidBvh, reconstructionJson } from './synthetic_bvh.mjs';

const { values: args } = parseArgs({ options: {
  mocap: { type: 'string' }, 'mocap-eval': { type: 'string' }, out: { type: 'string' }, testdata: { type: 'string' },
  'data-cache': { type: 'string' }, 'shared-data': { type: 'string' } } });
const chromiumPath = process.env.MOCAP_CHROMIUM || '/usr/bin/chromium';
if (!existsSync(chromiumPath)) {
  console.log(`SKIP: no Chromium at ${chromiumPath} (scripts/setup.sh installs Debian's chromium package)`);
  process.exit(77);
}
let chromium;
try {
  ({ chromium } = await import('playwright-core'));
} catch {
  console.log('SKIP: playwright-core is not installed (npm ci in viewer/ installs it)');
  process.exit(77);
}
const out = args.out;
mkdirSync(out, { recursive: true });
const [ORANGE, BLUE] = CLIP_COLOURS;

// Runs `mocap view`; returns the page's file URL, exit status and stderr.
function view(name, files, extra = []) {
  const page = join(out, `${name}.html`);
  const run = spawnSync(args.mocap, ['view', ...files, '-o', page, ...extra], { encoding: 'utf8' });
  if (run.error) throw run.error;
  if (!existsSync(page)) throw new Error(`mocap view wrote no page: ${run.stderr}`);
  return { url: pathToFileURL(page).href, status: run.status, stderr: run.stderr };
}

function expect(condition, message) {
  if (!condition) throw new Error(message);
}

function write(name, text) {
  const path = join(out, name);
  writeFileSync(path, text);
  return path;
}

// Synthetic clips: the reconstruction in metres with its JSON beside it, the capture in cm.
const reconstruction = write('reconstruction.bvh', humanoidBvh({ unit: 0.01, phase: 0.4 }));
write('reconstruction.json', reconstructionJson());
const captured = write('captured.bvh', humanoidBvh({ unit: 1 }));
const broken = write('broken.bvh', humanoidBvh({ frames: 3 }).replace('OFFSET 0 10 0', 'OFFSET 0 ten 0'));
const hostile = write('hostile.bvh', humanoidBvh({ frames: 3 }).replace('JOINT Spine', 'JOINT </script><script>window.pwned=1</script>'));

const checks = [];
const check = (name, run) => checks.push({ name, run });

check('two clips overlaid: both drawn, the same size (cm and m), in the middle of the view', async (browser) => {
  const built = view('overlay', [reconstruction, captured]);
  expect(built.status === 0, `mocap view exited ${built.status}: ${built.stderr}`);
  expect(!/not read as a humanoid/.test(built.stderr), `the body analysis failed: ${built.stderr}`);
  const page = await openPage(browser, built.url);
  expect(await viewerState(page) === 'ready', `page state ${await viewerState(page)}: ${await errorText(page)}`);
  const [a, b] = await colourRegions(page, [ORANGE, BLUE], join(out, 'overlay.png'));
  for (const [name, r] of [['reconstruction', a], ['captured', b]]) {
    expect(r.count > 300, `${name}: ${r.count} pixels of its colour`);
    expect(r.centreX > 0.3 && r.centreX < 0.7, `${name}: drawn at x = ${r.centreX.toFixed(2)} of the view, not in its middle`);
    expect(r.height > 0.3, `${name}: only ${(r.height * 100).toFixed(0)}% of the view's height`);
  }
  expect(Math.abs(a.height / b.height - 1) < 0.2, `heights differ: ${a.height.toFixed(2)} vs ${b.height.toFixed(2)} (units?)`);
  expect(a.height > a.width * 0.9, `the body lies sideways (${a.width.toFixed(2)} wide, ${a.height.toFixed(2)} high)`);
  expect(page.problems.length === 0, `page errors: ${page.problems.join('; ')}`);
  await page.close();
});

check('side by side: the first clip in the left panel, the second in the right', async (browser) => {
  const page = await openPage(browser, `${view('side', [reconstruction, captured]).url}#layout=side-by-side`);
  const [a, b] = await colourRegions(page, [ORANGE, BLUE], join(out, 'side-by-side.png'));
  expect(a.count > 300 && b.count > 300, `pixels: ${a.count} and ${b.count}`);
  expect(a.right < 0.5, `the first clip reaches x = ${a.right.toFixed(2)} (past the left panel)`);
  expect(b.left > 0.5, `the second clip starts at x = ${b.left.toFixed(2)} (before the right panel)`);
  await page.close();
});

check('play advances the frame counter, pause stops it, the slider scrubs', async (browser) => {
  const page = await openPage(browser, view('play', [reconstruction, captured]).url);
  const start = await shownFrame(page);
  await page.click('.mv-play');
  await page.waitForFunction((f) => Number(document.querySelector('.mv-frame-counter').dataset.frame) >= f + 5, start,
    { timeout: 10000 });
  await page.click('.mv-play');
  const paused = await shownFrame(page);
  await page.waitForTimeout(600);
  expect(await shownFrame(page) === paused, 'the counter moved while paused');
  await page.fill('.mv-slider', '42');
  await page.waitForTimeout(200);
  expect(await shownFrame(page) === 42, `scrubbed to 42, counter at ${await shownFrame(page)}`);
  expect(/frame 43 \/ 90/.test(await page.textContent('.mv-frame-counter')), 'counter text');
  await page.close();
});

check('the reconstruct JSON beside a BVH adds wrist and ankle traces and expected-error halos', async (browser) => {
  const page = await openPage(browser, view('traces', [reconstruction]).url);
  const legend = await page.textContent('.mv-legend');
  expect(page.problems.length === 0, `page errors: ${page.problems.join('; ')}`);
  for (const label of ['traces: wrist inputs, estimated ankles', 'halos: expected error']) {
    expect(legend.includes(label), `legend lacks "${label}": ${legend}`);
  }
  await page.screenshot({ path: join(out, 'traces.png') });
  await page.close();
});

check('a malformed BVH shows a readable error naming the file and line', async (browser) => {
  const built = view('malformed', [broken]);
  expect(built.status === 1, `mocap view exited ${built.status} for a malformed file`);
  const page = await openPage(browser, built.url);
  expect(await viewerState(page) === 'error', `page state ${await viewerState(page)}`);
  const text = await errorText(page);
  expect(/broken\.bvh could not be read: broken\.bvh:\d+:/.test(text), `error text: ${text}`);
  expect(await page.isVisible('.mv-errors'), 'the error is not visible');
  await page.screenshot({ path: join(out, 'malformed.png') });
  await page.close();
});

check('a malformed clip beside a good one: the good one plays, the error is shown', async (browser) => {
  const page = await openPage(browser, view('mixed', [captured, broken]).url);
  expect(await viewerState(page) === 'ready', `page state ${await viewerState(page)}`);
  expect((await errorText(page)).includes('broken.bvh could not be read'), 'no error shown');
  const [a] = await colourRegions(page, [ORANGE], join(out, 'mixed.png'));
  expect(a.count > 300, `the good clip: ${a.count} pixels`);
  await page.close();
});

check('BVH text cannot break out of the page (a joint named </script><script>...)', async (browser) => {
  const page = await openPage(browser, view('hostile', [hostile]).url);
  expect(await page.evaluate(() => window.pwned) === undefined, 'the injected script ran');
  expect(['ready', 'error'].includes(await viewerState(page)), 'no state');
  await page.close();
});

if (args.testdata) {
  check('every valid test BVH plays; every malformed one shows its error', async (browser) => {
    const failures = [];
    for (const kind of ['valid', 'malformed']) {
      for (const file of readdirSync(join(args.testdata, kind)).sort()) {
        const page = await openPage(browser, view(`testdata-${kind}-${file}`, [join(args.testdata, kind, file)]).url);
        const state = await viewerState(page);
        const text = await errorText(page);
        if (kind === 'valid' && state !== 'ready') failures.push(`${file}: ${state} ${text}`);
        if (kind === 'malformed' && (state !== 'error' || !text.includes(`${file} could not be read: `))) failures.push(`${file}: ${state} ${text}`);
        await page.close();
      }
    }
    expect(failures.length === 0, failures.join('\n'));
  });
}

// Real clips, when the shared data can be had.
function sharedData() {
  const cache = args['data-cache'] || join(homedir(), '.cache/mocap/data');
  const unpack = args['shared-data'] && join(args['shared-data'], 'unpack.sh');
  if (!existsSync(join(cache, 'cmu-cc')) && unpack && existsSync(unpack)) {
    spawnSync(unpack, [cache, 'bandai-namco-2', 'cmu-cc'], { stdio: 'ignore' });
  }
  return existsSync(join(cache, 'bandai-namco-2')) && existsSync(join(cache, 'cmu-cc')) ? cache : null;
}
const data = sharedData();
if (data) {
  for (const [name, file] of [['bandai', 'bandai-namco-2/dataset-2_walk_normal_003.bvh'], ['cmu', 'cmu-cc/002_01.bvh']]) {
    check(`a real clip (${file}) stands upright in view`, async (browser) => {
      const built = view(`real-${name}`, [join(data, file)]);
      expect(built.status === 0, `mocap view exited ${built.status}: ${built.stderr}`);
      const page = await openPage(browser, `${built.url}#frame=30`);
      const [a] = await colourRegions(page, [ORANGE], join(out, `real-${name}.png`));
      expect(a.count > 150, `${a.count} pixels of the clip's colour`);
      expect(a.height > a.width, `not upright: ${a.width.toFixed(2)} wide, ${a.height.toFixed(2)} high`);
      await page.close();
      const following = await openPage(browser, `${built.url}#frame=30&follow=1`);
      const [b] = await colourRegions(following, [ORANGE], join(out, `real-${name}-follow.png`));
      expect(b.height > 0.3, `following: the body fills ${(b.height * 100).toFixed(0)}% of the view's height`);
      await following.close();
    });
  }
  if (args['mocap-eval']) {
    check('mocap-eval report.html: tables, plots and the player of reconstruction over truth', async (browser) => {
      const folder = join(out, 'eval-report');
      execFileSync(args['mocap-eval'], ['--quick', '--max-clips', '3', '--out', folder], { stdio: 'ignore' });
      const page = await openPage(browser, pathToFileURL(join(folder, 'report.html')).href, { height: 900 });
      expect(await viewerState(page) === 'ready', `page state ${await viewerState(page)}: ${await errorText(page)}`);
      expect(await page.locator('table').count() >= 2, 'summary tables missing');
      expect(await page.locator('figure svg').count() >= 1, 'plots missing');
      expect(await page.locator('.mv-scene option').count() >= 2, 'fewer than two clips to choose');
      await page.locator('#mocap-viewer').scrollIntoViewIfNeeded();
      const [a, b] = await colourRegions(page, [ORANGE, BLUE], join(out, 'eval-report.png'));
      expect(a.count > 150 && b.count > 150, `reconstruction ${a.count} and truth ${b.count} pixels`);
      await page.close();
    });
  }
} else {
  console.log('note: shared data absent: real-clip and report checks skipped');
}

const browser = await chromium.launch({ executablePath: chromiumPath, args: BROWSER_ARGS });
let failed = 0;
for (const { name, run } of checks) {
  try {
    await run(browser);
    console.log(`ok   ${name}`);
  } catch (error) {
    failed++;
    console.log(`FAIL ${name}\n     ${String(error.message).split('\n').join('\n     ')}`);
  }
}
await browser.close();
console.log(`screenshots and pages in ${out}`);
console.log(`${checks.length - failed} passed, ${failed} failed`);
process.exit(failed ? 1 : 0);
